//! Generalized-α.

use crate::options::{GeneralizedAlphaOptions, SimulationOptions};
use crate::results::DynamicResults;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

pub(crate) fn run(
    _d: &mut Dynamics,
    _state: State,
    _times: &[f64],
    _o: &GeneralizedAlphaOptions,
    _options: &SimulationOptions,
) -> Result<DynamicResults, DynamicsError> {
    todo!()
}
