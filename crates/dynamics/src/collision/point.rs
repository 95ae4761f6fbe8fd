//! One contact point, as the results keep it (a leaf: the results and the detection both use
//! it).

use nalgebra::Vector3;

/// One contact point at an evaluation (the rows of `contacts.csv`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Shape 1 and shape 2 (indices into [`cardan_mechanism::Model::shapes`]).
    pub shapes: [usize; 2],
    /// The contact point P (global, m).
    pub point: Vector3<f64>,
    /// The unit normal n from shape 1 towards shape 2.
    pub normal: Vector3<f64>,
    /// The penetration δ > 0 (m).
    pub penetration: f64,
    /// The approach rate δ̇ (m/s, positive while approaching).
    pub penetration_rate: f64,
    /// F_n (N), pushing shape 2 along n.
    pub normal_force: f64,
    /// The friction force on shape 2 (global, N).
    pub friction_force: Vector3<f64>,
    /// The slip velocity v_t of shape 2 over shape 1 (global, m/s).
    pub slip_velocity: Vector3<f64>,
}
