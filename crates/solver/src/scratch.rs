//! faer's scratch memory for the factorizations and solves, sized once at `analyze` so that
//! `factor` and `solve` do not allocate.

use crate::error::SolverError;

/// faer scratch memory, sized at analysis ([`faer::dyn_stack::MemBuffer`] with a `Debug` impl).
pub(crate) struct Scratch(pub(crate) faer::dyn_stack::MemBuffer);

impl Scratch {
    pub(crate) fn empty() -> Self {
        Self(faer::dyn_stack::MemBuffer::new(
            faer::dyn_stack::StackReq::EMPTY,
        ))
    }

    pub(crate) fn try_new(req: faer::dyn_stack::StackReq) -> Result<Self, SolverError> {
        faer::dyn_stack::MemBuffer::try_new(req)
            .map(Self)
            .map_err(|e| SolverError::Backend(format!("scratch allocation: {e:?}")))
    }

    pub(crate) fn stack(&mut self) -> &mut faer::dyn_stack::MemStack {
        faer::dyn_stack::MemStack::new(&mut self.0)
    }
}

impl core::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Scratch")
    }
}
