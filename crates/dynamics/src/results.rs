//! [`DynamicResults`]: the kinematic histories (the mechanism's [`Results`]) extended with
//! multipliers, joint reactions, driver efforts, energy and constraint drift.

use cardan_mechanism::{BodyResults, EquationName, PointResults, Results};
use nalgebra::Vector3;

/// A reaction on one body at a joint point: force and torque about the joint point, in global
/// and body components.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reaction {
    /// Force F = −(Φ_r,k)ᵀ λ (global).
    pub force: Vector3<f64>,
    /// Torque about the joint point (global).
    pub torque: Vector3<f64>,
    /// Force in the body frame, Aᵀ F.
    pub force_local: Vector3<f64>,
    /// Torque about the joint point in the body frame, n' − s̃'^P F'.
    pub torque_local: Vector3<f64>,
}

/// Reaction histories of one joint (or driver): on body i at marker point P_i and on body j at
/// P_j. For ground, "local" components are global.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointReactions {
    /// Joint name.
    pub name: String,
    /// Body i.
    pub body_i: String,
    /// Body j.
    pub body_j: String,
    /// The point of body i the torques on it are taken about: the name of the body's point
    /// there (P_i of the joint), or `origin` (the body frame origin, the centre of mass).
    pub point_i: String,
    /// The same for body j (P_j).
    pub point_j: String,
    /// On body i, per output time.
    pub on_i: Vec<Reaction>,
    /// On body j, per output time.
    pub on_j: Vec<Reaction>,
}

/// Effort histories of one driver.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DriverEfforts {
    /// Driver name.
    pub name: String,
    /// Its multiplier λ.
    pub lambda: Vec<f64>,
    /// The generalized force the driver applies along its driven coordinate c, −λ ∂Φ/∂c
    /// ([`cardan_constraints::Driver::coordinate_slope`]: 2ℓ for the distance driver, 1 for the
    /// others), so that effort × ċ is the driver's power: the torque
    /// (N m) about the joint axis on body j for a rotation driver, the force (N) for translation,
    /// distance and coordinate drivers (positive in the sense of increasing coordinate).
    pub effort: Vec<f64>,
    /// Power −λ ν (ν = −Φ_t) = effort · (rate of the driven coordinate), W.
    pub power: Vec<f64>,
    /// Reactions of the driver row on its bodies (as for a joint).
    pub reactions: JointReactions,
}

/// Effort histories of one coupler (gear, rack and pinion, screw; see
/// [`cardan_mechanism::CouplerInfo`]: its equation is the law a₀ q₀ + a₁ q₁ − c = 0 between two
/// joint coordinates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CouplerEfforts {
    /// Coupler name.
    pub name: String,
    /// Its multiplier λ.
    pub lambda: Vec<f64>,
    /// The generalized forces the coupler applies along the two coupled joint coordinates,
    /// Q_k = −λ a_k: a torque (N m) on an angle, a force (N) on a slide, positive in the sense of
    /// the increasing coordinate (as a driver's effort). An ideal coupler does no work:
    /// Q₀ q̇₀ + Q₁ q̇₁ = 0.
    pub efforts: Vec<[f64; 2]>,
    /// The tooth or thread force (N): for a gear given by radii, Q₁ / r_j, the tangential force
    /// on gear j at its pitch circle (none for a gear given by a ratio); for a rack and pinion,
    /// Q₀, the force along the rack on its slide; for a screw, Q₀, the axial force on the slide.
    pub force: Option<Vec<f64>>,
    /// The wrench −Φ_vᵀλ of the coupler's equation on its two bodies (body i and j of
    /// [`cardan_mechanism::CouplerInfo`]), about its marker points. For a gear the equation
    /// (orbit angles) puts a force at the centres that differs from the tooth force; only the
    /// torques about the axes (hence `efforts`) are physical, and the gears' joint reactions
    /// carry the difference.
    pub reactions: JointReactions,
}

/// Power and work of one element that is not conservative: a driver, a damper, an actuator, a
/// point force or torque, the user callback (see [`crate::work`] for the signs and the
/// quadratures).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ElementWork {
    /// The driver's or force element's name (`user` for the user callback).
    pub name: String,
    /// What it is: `driver`, `force` or `user`.
    pub kind: &'static str,
    /// Power P(t) the element puts into the mechanism (W; negative: it takes energy out).
    pub power: Vec<f64>,
    /// Work W(t) = ∫ P dt since the first stored time (J).
    pub work: Vec<f64>,
}

/// Energy histories, and the power and work of everything the energy does not hold.
///
/// The work-energy theorem (see [`crate::work`]): E(t) − E(t₀) = W_nc(t), the work of the
/// drivers and of the non-conservative forces. `drift` = E − E(t₀) is therefore physics for a
/// driven or damped model; `balance` = E − E(t₀) − W_nc is the integration error.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnergyHistory {
    /// Kinetic ½ m ṙᵀṙ + ½ ω'ᵀ J' ω'.
    pub kinetic: Vec<f64>,
    /// Gravity potential −Σ m gᵀ r.
    pub gravity: Vec<f64>,
    /// Spring potential ½ k (ℓ − ℓ0)² and ½ k (θ − θ0)².
    pub spring: Vec<f64>,
    /// Sum of the three.
    pub total: Vec<f64>,
    /// Power and work of each driver (model order), then of each non-conservative force element
    /// (the order they were added), then of the user callback.
    pub elements: Vec<ElementWork>,
    /// W_nc: the sum of the elements' work (J).
    pub work: Vec<f64>,
    /// A diagnostic: the power of the joints' and couplers' reactions, −λᵀ Φ_v v over their
    /// rows (W). Ideal constraints do no work, so this is 0 up to the velocity drift.
    pub constraint_power: Vec<f64>,
}

impl EnergyHistory {
    /// total − total\[0\] per time: the integration error for a conservative model, the work
    /// of drivers and non-conservative forces plus that error otherwise ([`balance`](Self::balance)).
    pub fn drift(&self) -> Vec<f64> {
        let e0 = self.total.first().copied().unwrap_or(0.0);
        self.total.iter().map(|e| e - e0).collect()
    }

    /// max |total − total\[0\]|.
    pub fn max_drift(&self) -> f64 {
        self.drift().iter().fold(0.0, |a, d| a.max(d.abs()))
    }

    /// E(t) − E(t₀) − W_nc(t) per time: what the work-energy theorem leaves unexplained, the
    /// integration error (0 for the exact motion).
    pub fn balance(&self) -> Vec<f64> {
        let e0 = self.total.first().copied().unwrap_or(0.0);
        self.total
            .iter()
            .zip(&self.work)
            .map(|(e, w)| e - e0 - w)
            .collect()
    }

    /// max |E(t) − E(t₀) − W_nc(t)|.
    pub fn max_balance(&self) -> f64 {
        self.balance().iter().fold(0.0, |a, d| a.max(d.abs()))
    }

    /// The power and work of element `name`.
    pub fn element(&self, name: &str) -> Option<&ElementWork> {
        self.elements.iter().find(|e| e.name == name)
    }
}

/// Counters of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IntegrationStats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (error test or Newton failure).
    pub rejected: usize,
    /// Evaluations of the equations of motion (KKT solves).
    pub evaluations: usize,
    /// Newton iterations (implicit method and projections).
    pub newton_iterations: usize,
    /// Numeric factorizations of the KKT matrix.
    pub factorizations: usize,
    /// Times the independent equations of a mechanism with redundant equations were chosen
    /// again because the kept ones lost rank where the full set has not
    /// ([`Dynamics::row_reselections`](crate::Dynamics::row_reselections)).
    pub row_reselections: usize,
    /// Wall time of the integration loop (s).
    pub wall_time: f64,
}

/// Everything a dynamic run (forward or inverse) produced.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DynamicResults {
    /// Times, body poses / velocities / accelerations, points and joint coordinates (the
    /// mechanism's results; `residual` holds max |Φ| per time, `iterations` the Newton
    /// iterations of the step that reached the time).
    pub kinematics: Results,
    /// λ per time, one per equation of the model (joints then drivers); rows dropped as
    /// redundant have λ = 0.
    pub lambda: Vec<Vec<f64>>,
    /// Reactions of every joint, in model order.
    pub reactions: Vec<JointReactions>,
    /// Efforts of every driver, in model order.
    pub drivers: Vec<DriverEfforts>,
    /// Efforts of every coupler, in model order.
    pub couplers: Vec<CouplerEfforts>,
    /// Energy.
    pub energy: EnergyHistory,
    /// max |Φ_i| (unscaled) per time.
    pub position_drift: Vec<f64>,
    /// max |Φ_v v − ν| per time.
    pub velocity_drift: Vec<f64>,
    /// Equations dropped as redundant (their share of the reactions is carried by the others,
    /// so the split of reactions between redundant joints is one of many).
    pub redundant: Vec<EquationName>,
    /// Counters.
    pub stats: IntegrationStats,
}

impl DynamicResults {
    /// Output times.
    pub fn times(&self) -> &[f64] {
        &self.kinematics.times
    }

    /// Number of output times.
    pub fn len(&self) -> usize {
        self.kinematics.times.len()
    }

    /// True if nothing was stored.
    pub fn is_empty(&self) -> bool {
        self.kinematics.times.is_empty()
    }

    /// The history of body `name`.
    pub fn body(&self, name: &str) -> Option<&BodyResults> {
        self.kinematics.body(name)
    }

    /// The history of point `name` on `body`.
    pub fn point(&self, body: &str, name: &str) -> Option<&PointResults> {
        self.kinematics.point(body, name)
    }

    /// The reactions of joint `name`.
    pub fn joint_reactions(&self, name: &str) -> Option<&JointReactions> {
        self.reactions.iter().find(|r| r.name == name)
    }

    /// The efforts of driver `name`.
    pub fn coupler(&self, name: &str) -> Option<&CouplerEfforts> {
        self.couplers.iter().find(|c| c.name == name)
    }

    /// The efforts of driver `name`.
    pub fn driver(&self, name: &str) -> Option<&DriverEfforts> {
        self.drivers.iter().find(|d| d.name == name)
    }
}
