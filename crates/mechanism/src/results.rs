//! [`Results`]: the time histories a run produces, stored in memory reserved before the run.
//!
//! Only what the run asked for is filled: with `outputs.velocity == false` every velocity
//! vector stays empty, and so on. All vectors that are filled have one entry per time in
//! [`Results::times`].

use cardan_constraints::joints::MAX_COORDINATES;
use cardan_constraints::JointKind;
use nalgebra::{Vector3, Vector4};

/// Which quantities a run computes and stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outputs {
    /// Velocity analysis (ṙ, ṗ, ω, ω', point velocities).
    pub velocity: bool,
    /// Acceleration analysis (r̈, p̈, ω̇, ω̇', point accelerations); implies `velocity`.
    pub acceleration: bool,
    /// Histories of every named point of the moving bodies.
    pub points: bool,
    /// Joint coordinates (angles unwrapped over turns).
    pub joints: bool,
}

impl Default for Outputs {
    /// Everything.
    fn default() -> Self {
        Self {
            velocity: true,
            acceleration: true,
            points: true,
            joints: true,
        }
    }
}

impl Outputs {
    /// Positions only (never evaluates ν or γ#).
    pub fn position_only() -> Self {
        Self {
            velocity: false,
            acceleration: false,
            points: true,
            joints: true,
        }
    }

    /// Positions and velocities.
    pub fn with_velocity() -> Self {
        Self {
            acceleration: false,
            ..Self::default()
        }
    }

    /// Velocity analysis is needed (asked for directly or by the acceleration analysis).
    pub fn needs_velocity(&self) -> bool {
        self.velocity || self.acceleration
    }
}

/// The history of one moving body.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BodyResults {
    /// Body name.
    pub name: String,
    /// Position r (global).
    pub r: Vec<Vector3<f64>>,
    /// Euler parameters p.
    pub p: Vec<Vector4<f64>>,
    /// ṙ.
    pub r_dot: Vec<Vector3<f64>>,
    /// ṗ = ½ Lᵀ ω'.
    pub p_dot: Vec<Vector4<f64>>,
    /// ω (global).
    pub omega: Vec<Vector3<f64>>,
    /// ω' (body frame).
    pub omega_local: Vec<Vector3<f64>>,
    /// r̈.
    pub r_ddot: Vec<Vector3<f64>>,
    /// p̈.
    pub p_ddot: Vec<Vector4<f64>>,
    /// ω̇ (global).
    pub omega_dot: Vec<Vector3<f64>>,
    /// ω̇' (body frame).
    pub omega_dot_local: Vec<Vector3<f64>>,
}

/// The history of one named point of a moving body (global components).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PointResults {
    /// Body name.
    pub body: String,
    /// Point name.
    pub name: String,
    /// Position.
    pub position: Vec<Vector3<f64>>,
    /// Velocity.
    pub velocity: Vec<Vector3<f64>>,
    /// Acceleration.
    pub acceleration: Vec<Vector3<f64>>,
}

/// The history of one joint's relative coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct JointResults {
    /// Joint name.
    pub name: String,
    /// Joint kind.
    pub kind: JointKind,
    /// The coordinates (names and measures; see [`cardan_constraints::Joint::coordinates`]).
    pub coordinates: &'static [cardan_constraints::joints::Coordinate],
    /// Values per time (first `coordinates.len()` entries meaningful); angles unwrapped.
    pub values: Vec<[f64; MAX_COORDINATES]>,
    /// Rates per time (rad/s, m/s), when velocities were computed (else empty).
    pub rates: Vec<[f64; MAX_COORDINATES]>,
    /// Accelerations per time (rad/s², m/s²), when accelerations were computed (else empty).
    pub accelerations: Vec<[f64; MAX_COORDINATES]>,
}

/// Everything a kinematic run produced.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Results {
    /// What was computed.
    pub outputs: Option<Outputs>,
    /// Output times.
    pub times: Vec<f64>,
    /// One entry per moving body, in model order.
    pub bodies: Vec<BodyResults>,
    /// One entry per named point of a moving body, in declaration order (empty without
    /// `outputs.points`).
    pub points: Vec<PointResults>,
    /// One entry per joint, in model order (empty without `outputs.joints`).
    pub joints: Vec<JointResults>,
    /// Max |Φ_i| over all equations after each position solve (unscaled).
    pub residual: Vec<f64>,
    /// Newton iterations per step.
    pub iterations: Vec<usize>,
    /// Grid steps of a kinematic run that were solved in substeps because the full step's
    /// solution left the assembly branch (see the time-grid docs, `analysis::grid`); 0 for a
    /// run whose every step followed its prediction.
    pub subdivided_steps: usize,
    /// Times the independent equations of a mechanism with redundant equations were chosen
    /// again during the run because the kept ones lost rank where the full set has not
    /// (see `Workspace::row_reselections`); 0 without redundant equations.
    pub row_reselections: usize,
    /// The rows dropped as redundant that were not satisfied at the solution (scaled residual
    /// above the position tolerance at some step): one per element, its worst row, value and
    /// time ([`Model::dropped_row_residuals`](crate::Model::dropped_row_residuals)). Empty for a
    /// consistent model; otherwise its joints disagree slightly and a front end should say so.
    pub dropped_rows: Vec<crate::analysis::dropped::DroppedRowResidual>,
}

impl Results {
    /// Number of stored time steps.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True if no step was stored.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The body history named `name`.
    pub fn body(&self, name: &str) -> Option<&BodyResults> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// The history of point `name` on `body`.
    pub fn point(&self, body: &str, name: &str) -> Option<&PointResults> {
        self.points
            .iter()
            .find(|p| p.body == body && p.name == name)
    }

    /// The coordinate history of joint `name`.
    pub fn joint(&self, name: &str) -> Option<&JointResults> {
        self.joints.iter().find(|j| j.name == name)
    }
}
