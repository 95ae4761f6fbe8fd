//! Inverse dynamics of a kinematically driven mechanism: [`Dynamics::inverse_dynamics`].

use crate::results::DynamicResults;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::KinematicOptions;

impl Dynamics<'_> {
    /// Inverse dynamics: runs the kinematics (mechanism crate) over the grid of `options`, then
    /// at each time solves the augmented system at the kinematic state for λ (for a fully
    /// driven mechanism v̇ is fixed by the constraints, so this is Φ_vᵀλ = h − M v̇, solved with
    /// the redundant rows dropped). Driver efforts and joint reactions follow from λ.
    ///
    /// # Errors
    /// [`DynamicsError::NotFullyDriven`] unless DOF = drivers; kinematic errors.
    pub fn inverse_dynamics(
        &mut self,
        options: &KinematicOptions,
    ) -> Result<DynamicResults, DynamicsError> {
        let _ = options;
        todo!()
    }
}
