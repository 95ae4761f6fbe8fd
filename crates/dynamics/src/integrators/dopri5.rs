//! Dormand-Prince 5(4).

use crate::options::{Dopri5Options, SimulationOptions};
use crate::results::DynamicResults;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

pub(crate) fn run(
    _d: &mut Dynamics,
    _state: State,
    _times: &[f64],
    _o: &Dopri5Options,
    _options: &SimulationOptions,
) -> Result<DynamicResults, DynamicsError> {
    todo!()
}
