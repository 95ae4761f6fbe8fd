//! The joint-space quantities of a run, time by time ([`JointSpaceHistory`]), and the scratch
//! that computes them ([`JointSpaceWork`]); the theory is the parent module's.

use cardan_mechanism::BodyId;
use nalgebra::Vector3;

/// A point whose Jacobian is recorded: its name (`body.point`), body and place in the body's
/// frame.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpacePoint {
    /// `body.point`, for the tables.
    pub name: String,
    /// The body (the ground's points have zero Jacobians).
    pub body: BodyId,
    /// s'_P, in the body's frame (m).
    pub local: Vector3<f64>,
}

/// The joint-space quantities at each recorded time ([`crate::DynamicResults::joint_space`]),
/// stored flat: time k's mass matrix is `mass[k n² .. (k+1) n²]` (row-major), its bias forces
/// `bias[k n .. (k+1) n]`, the Jacobian of point p `jacobians[(k P + p) 6n ..][..6n]` (rows
/// ẋ ẏ ż ω_x ω_y ω_z in global axes, row-major). Empty unless requested.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointSpaceHistory {
    /// The coordinates: the drivers' names, in model order (n).
    pub coordinates: Vec<String>,
    /// The points whose Jacobians are recorded.
    pub points: Vec<JointSpacePoint>,
    /// M(θ), n × n per time, row-major.
    pub mass: Vec<f64>,
    /// h(θ, θ̇), n per time.
    pub bias: Vec<f64>,
    /// The points' Jacobians, 6 × n each per time, row-major.
    pub jacobians: Vec<f64>,
}

impl JointSpaceHistory {
    /// n, the number of coordinates.
    pub fn n(&self) -> usize {
        self.coordinates.len()
    }

    /// Whether the history is recorded (a run that requested it).
    pub fn is_requested(&self) -> bool {
        !self.coordinates.is_empty()
    }

    /// M(θ) at time k: entry (i, j) is `mass_at(k)[i * n + j]`.
    pub fn mass_at(&self, k: usize) -> &[f64] {
        let n2 = self.n() * self.n();
        &self.mass[k * n2..(k + 1) * n2]
    }

    /// h(θ, θ̇) at time k.
    pub fn bias_at(&self, k: usize) -> &[f64] {
        let n = self.n();
        &self.bias[k * n..(k + 1) * n]
    }

    /// The Jacobian of point p at time k: entry (row, i) is `jacobian_at(k, p)[row * n + i]`.
    pub fn jacobian_at(&self, k: usize, p: usize) -> &[f64] {
        let size = 6 * self.n();
        let at = (k * self.points.len() + p) * size;
        &self.jacobians[at..at + size]
    }

    /// The same coordinates and points, no time, room for `capacity` times.
    pub(crate) fn empty_like(&self, capacity: usize) -> Self {
        let n = self.n();
        Self {
            coordinates: self.coordinates.clone(),
            points: self.points.clone(),
            mass: Vec::with_capacity(capacity * n * n),
            bias: Vec::with_capacity(capacity * n),
            jacobians: Vec::with_capacity(capacity * self.points.len() * 6 * n),
        }
    }

    /// Removes every time, keeping the storage.
    pub(crate) fn clear(&mut self) {
        self.mass.clear();
        self.bias.clear();
        self.jacobians.clear();
    }

    /// Appends the times of `o` (same coordinates and points).
    pub(crate) fn extend_from(&mut self, o: &Self) {
        self.mass.extend_from_slice(&o.mass);
        self.bias.extend_from_slice(&o.bias);
        self.jacobians.extend_from_slice(&o.jacobians);
    }
}

/// What [`crate::Dynamics::request_joint_space`] prepared: the history's names and the
/// scratch of one time.
#[derive(Debug, Clone)]
pub(crate) struct JointSpaceWork {
    /// The names and points (no times).
    pub names: JointSpaceHistory,
    /// V, column i = `v_cols[i * 6nb ..][..6nb]`.
    pub v_cols: Vec<f64>,
    /// θ̈ of each coordinate at the time being recorded.
    pub theta_ddot: Vec<f64>,
}

impl JointSpaceWork {
    /// For `coordinates` and `points`, V of `size` entries (n · 6nb).
    pub fn new(coordinates: Vec<String>, points: Vec<JointSpacePoint>, size: usize) -> Self {
        Self {
            theta_ddot: vec![0.0; coordinates.len()],
            names: JointSpaceHistory {
                coordinates,
                points,
                ..JointSpaceHistory::default()
            },
            v_cols: vec![0.0; size],
        }
    }
}
