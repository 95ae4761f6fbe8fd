//! A model file's dynamics problem, shared by every analysis that runs the dynamics: the
//! [`Dynamics`] with the file's forces ([`dynamics`]), the initial state from the bodies'
//! poses and the file's velocities ([`initial_state`]), and the integrator settings of a
//! `kind = "dynamic"` analysis ([`options`]). Errors are located in the file
//! ([`super::located`]).

use super::located::located_as;
use crate::diag::Error;
use crate::prepare::Prepared;
use cardan_dynamics::{Dynamics, Integrator, SimulationOptions, State};

/// The [`Dynamics`] of a prepared model with the file's forces (gravity first).
///
/// # Errors
/// A body without mass or inertia, an invalid force element.
pub fn dynamics(p: &Prepared) -> Result<Dynamics<'_>, Error> {
    dynamics_as(p, "dynamic analysis")
}

/// As [`dynamics`], errors starting with `what`.
pub(super) fn dynamics_as<'p>(p: &'p Prepared, what: &str) -> Result<Dynamics<'p>, Error> {
    let mut d = Dynamics::new(&p.model).map_err(|e| located_as(p, &e, what))?;
    for f in &p.loaded.forces {
        d.add_force(f.clone())
            .map_err(|e| located_as(p, &e, what))?;
    }
    Ok(d)
}

/// The initial guess: the bodies' initial poses (assembled later) and the file's velocities, at
/// `t_start`.
pub fn initial_state(p: &Prepared) -> State {
    let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let mut s = State::initial(&p.model, t0);
    for v in &p.loaded.velocities {
        if let Some(k) = p.model.bodies().iter().position(|b| b.name == v.body) {
            if v.omega_local {
                s.set_velocity(k, v.velocity, v.omega);
            } else {
                s.set_velocity_global(k, v.velocity, v.omega);
            }
        }
    }
    s
}

/// The file's simulation options; `integrator` overrides the file's integrator settings.
///
/// # Errors
/// The file has no `kind = "dynamic"` analysis.
pub fn options(p: &Prepared, integrator: Option<Integrator>) -> Result<SimulationOptions, Error> {
    let a = p
        .loaded
        .analysis
        .as_ref()
        .filter(|a| a.integrator().is_some())
        .ok_or_else(|| {
            p.source
                .error("the model file has no [analysis] with kind = \"dynamic\"")
        })?;
    let integrator = integrator.or(a.integrator()).unwrap_or_default();
    Ok(SimulationOptions::new(a.t_end, a.steps).integrator(integrator))
}
