//! [`Results`]: the time histories a run produces, stored in memory reserved before the run.
//!
//! Only what the run asked for is filled: with `outputs.velocity == false` every velocity
//! vector stays empty, and so on. All vectors that are filled have one entry per time in
//! [`Results::times`].
//!
//! The same type carries one frame at a time to a [`FrameSink`] (a streamed run,
//! [`Model::kinematics_into`](crate::Model::kinematics_into)): a `Results` holding exactly the
//! time just solved, whose storage is reused from frame to frame. A run that returns all its
//! frames is such a sink that appends each frame ([`Results::extend_from`]).

use crate::equation::EquationName;
use cardan_constraints::joints::MAX_COORDINATES;
use cardan_constraints::{Dimension, JointKind};
use nalgebra::{Vector3, Vector4};
use std::ops::ControlFlow;

/// The consumer of a streamed run's frames: called once per stored time, in order, with the
/// grid index k and a [`Results`] holding that one time (the counters
/// [`Results::subdivided_steps`] and [`Results::row_reselections`] are the run's totals so far).
/// [`ControlFlow::Break`] stops the run after this frame (e.g. Ctrl-C in the command line).
///
/// Closures `FnMut(usize, &Results) -> ControlFlow<()>` are sinks.
pub trait FrameSink {
    /// Takes frame `k`.
    fn frame(&mut self, k: usize, frame: &Results) -> ControlFlow<()>;
}

impl<F: FnMut(usize, &Results) -> ControlFlow<()>> FrameSink for F {
    fn frame(&mut self, k: usize, frame: &Results) -> ControlFlow<()> {
        self(k, frame)
    }
}

/// What a streamed run tells at its end beside its frames.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunTotals {
    /// Frames handed to the sink.
    pub frames: usize,
    /// As [`Results::subdivided_steps`].
    pub subdivided_steps: usize,
    /// As [`Results::row_reselections`].
    pub row_reselections: usize,
    /// As [`Results::dropped_rows`].
    pub dropped_rows: Vec<DroppedRowResidual>,
    /// As [`Results::held_dof`].
    pub held_dof: usize,
    /// As [`Results::held_from_assembly`].
    pub held_from_assembly: bool,
}

/// The worst residual of a row dropped as redundant, over a run (how it is found:
/// [`crate::analysis::dropped`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DroppedRowResidual {
    /// The equation (element, kind, primitive, row).
    pub equation: EquationName,
    /// Its scaled residual |Φ_r| / e_r (relative to the model's size for a length).
    pub residual: f64,
    /// Its residual Φ_r in SI units (m, m², or dimensionless, as `dimension` says).
    pub value: f64,
    /// What Φ_r measures.
    pub dimension: Dimension,
    /// When it was largest (s).
    pub time: f64,
}

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

/// The history of one curve parameter (an extra coordinate) of a curve element: a
/// point-on-curve element's u, a cam pair's u (on the cam) or w (on the follower's curve).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CurveResults {
    /// Element name.
    pub name: String,
    /// The parameter's name: "u", or "w" for a cam pair's second.
    pub parameter: &'static str,
    /// u (the curve's parameter: arc length for lines, circles and helices, chord length along
    /// a spline; continued over the turns of a closed curve).
    pub u: Vec<f64>,
    /// u̇, when velocities were computed (else empty).
    pub u_dot: Vec<f64>,
    /// ü, when accelerations were computed (else empty).
    pub u_ddot: Vec<f64>,
    /// Whether this is a cam pair's first entry, which records the contact and the pressure
    /// angle.
    pub cam: bool,
    /// A cam pair's first entry only (else empty): the contact point, global.
    pub contact: Vec<Vector3<f64>>,
    /// A cam pair's first entry only, when velocities were computed (else empty): the pressure
    /// angle, between the contact's common normal and the direction the follower's point at
    /// the contact moves (rad, 0 to π/2; [`crate::model::CurveElement::pressure_angle`]).
    pub pressure_angle: Vec<f64>,
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
    /// One entry per point-on-curve element, in model order (always recorded).
    pub curves: Vec<CurveResults>,
    /// Max |Φ_i| over all equations after each position solve (unscaled).
    pub residual: Vec<f64>,
    /// Newton iterations per step.
    pub iterations: Vec<usize>,
    /// Grid steps of a kinematic run that were solved in substeps because the full step's
    /// solution left the assembly branch (see the time-grid docs, `analysis::grid`); 0 for a
    /// run whose every step followed its prediction.
    pub subdivided_steps: usize,
    /// Degrees of freedom no driver prescribed, held still by least change from frame to frame
    /// ([`crate::analysis::least_change`]; `free_dof = "hold"`); 0 for a fully driven run.
    pub held_dof: usize,
    /// A held run whose start is the minimum-norm assembly's pose, not the least change from
    /// the drawn pose: the least-change iteration did not converge there (a distance joint
    /// drawn far from its place), so the free parts start from another valid pose.
    pub held_from_assembly: bool,
    /// Times the independent equations of a mechanism with redundant equations were chosen
    /// again during the run because the kept ones lost rank where the full set has not
    /// (see `Workspace::row_reselections`); 0 without redundant equations.
    pub row_reselections: usize,
    /// The rows dropped as redundant that were not satisfied at the solution (scaled residual
    /// above the position tolerance at some step): one per element, its worst row, value and
    /// time ([`Model::dropped_row_residuals`](crate::Model::dropped_row_residuals)). Empty for a
    /// consistent model; otherwise its joints disagree slightly and a front end should say so.
    pub dropped_rows: Vec<DroppedRowResidual>,
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

    /// The history of the first curve parameter (u) of curve element `name`.
    pub fn curve(&self, name: &str) -> Option<&CurveResults> {
        self.curves.iter().find(|c| c.name == name)
    }

    /// The history of curve parameter `parameter` ("u", "w") of curve element `name`.
    pub fn curve_parameter(&self, name: &str, parameter: &str) -> Option<&CurveResults> {
        (self.curves.iter()).find(|c| c.name == name && c.parameter == parameter)
    }

    /// The coordinate history of joint `name`.
    pub fn joint(&self, name: &str) -> Option<&JointResults> {
        self.joints.iter().find(|j| j.name == name)
    }

    /// The same names, outputs and counters without any frame, with room for `capacity` frames
    /// in every history this one fills (a copy of a run's layout, e.g. for a decimated copy of
    /// a streamed run).
    pub fn empty_like(&self, capacity: usize) -> Results {
        fn room<T>(v: &[T], capacity: usize) -> Vec<T> {
            Vec::with_capacity(if v.is_empty() { 0 } else { capacity })
        }
        let n = capacity;
        Results {
            outputs: self.outputs,
            times: Vec::with_capacity(n),
            bodies: (self.bodies.iter())
                .map(|b| BodyResults {
                    name: b.name.clone(),
                    r: room(&b.r, n),
                    p: room(&b.p, n),
                    r_dot: room(&b.r_dot, n),
                    p_dot: room(&b.p_dot, n),
                    omega: room(&b.omega, n),
                    omega_local: room(&b.omega_local, n),
                    r_ddot: room(&b.r_ddot, n),
                    p_ddot: room(&b.p_ddot, n),
                    omega_dot: room(&b.omega_dot, n),
                    omega_dot_local: room(&b.omega_dot_local, n),
                })
                .collect(),
            points: (self.points.iter())
                .map(|p| PointResults {
                    body: p.body.clone(),
                    name: p.name.clone(),
                    position: room(&p.position, n),
                    velocity: room(&p.velocity, n),
                    acceleration: room(&p.acceleration, n),
                })
                .collect(),
            joints: (self.joints.iter())
                .map(|j| JointResults {
                    name: j.name.clone(),
                    kind: j.kind,
                    coordinates: j.coordinates,
                    values: room(&j.values, n),
                    rates: room(&j.rates, n),
                    accelerations: room(&j.accelerations, n),
                })
                .collect(),
            curves: (self.curves.iter())
                .map(|c| CurveResults {
                    name: c.name.clone(),
                    parameter: c.parameter,
                    cam: c.cam,
                    u: room(&c.u, n),
                    u_dot: room(&c.u_dot, n),
                    u_ddot: room(&c.u_ddot, n),
                    contact: room(&c.contact, n),
                    pressure_angle: room(&c.pressure_angle, n),
                })
                .collect(),
            residual: room(&self.residual, n),
            iterations: room(&self.iterations, n),
            subdivided_steps: self.subdivided_steps,
            row_reselections: self.row_reselections,
            dropped_rows: self.dropped_rows.clone(),
            held_dof: self.held_dof,
            held_from_assembly: self.held_from_assembly,
        }
    }

    /// Removes every frame, keeping the storage (no allocation when filled again) and the
    /// counters.
    pub fn clear_frames(&mut self) {
        self.times.clear();
        self.residual.clear();
        self.iterations.clear();
        for b in &mut self.bodies {
            for v in [&mut b.r, &mut b.r_dot, &mut b.omega, &mut b.omega_local] {
                v.clear();
            }
            for v in [&mut b.r_ddot, &mut b.omega_dot, &mut b.omega_dot_local] {
                v.clear();
            }
            for v in [&mut b.p, &mut b.p_dot, &mut b.p_ddot] {
                v.clear();
            }
        }
        for p in &mut self.points {
            for v in [&mut p.position, &mut p.velocity, &mut p.acceleration] {
                v.clear();
            }
        }
        for j in &mut self.joints {
            for v in [&mut j.values, &mut j.rates, &mut j.accelerations] {
                v.clear();
            }
        }
        for c in &mut self.curves {
            for v in [&mut c.u, &mut c.u_dot, &mut c.u_ddot, &mut c.pressure_angle] {
                v.clear();
            }
            c.contact.clear();
        }
    }

    /// Appends the frames of `other`, which has the same layout (e.g. made by
    /// [`Results::empty_like`] or by the same run); no allocation within the reserved room.
    pub fn extend_from(&mut self, other: &Results) {
        self.times.extend_from_slice(&other.times);
        self.residual.extend_from_slice(&other.residual);
        self.iterations.extend_from_slice(&other.iterations);
        for (a, b) in self.bodies.iter_mut().zip(&other.bodies) {
            a.r.extend_from_slice(&b.r);
            a.p.extend_from_slice(&b.p);
            a.r_dot.extend_from_slice(&b.r_dot);
            a.p_dot.extend_from_slice(&b.p_dot);
            a.omega.extend_from_slice(&b.omega);
            a.omega_local.extend_from_slice(&b.omega_local);
            a.r_ddot.extend_from_slice(&b.r_ddot);
            a.p_ddot.extend_from_slice(&b.p_ddot);
            a.omega_dot.extend_from_slice(&b.omega_dot);
            a.omega_dot_local.extend_from_slice(&b.omega_dot_local);
        }
        for (a, b) in self.points.iter_mut().zip(&other.points) {
            a.position.extend_from_slice(&b.position);
            a.velocity.extend_from_slice(&b.velocity);
            a.acceleration.extend_from_slice(&b.acceleration);
        }
        for (a, b) in self.joints.iter_mut().zip(&other.joints) {
            a.values.extend_from_slice(&b.values);
            a.rates.extend_from_slice(&b.rates);
            a.accelerations.extend_from_slice(&b.accelerations);
        }
        for (a, b) in self.curves.iter_mut().zip(&other.curves) {
            a.u.extend_from_slice(&b.u);
            a.u_dot.extend_from_slice(&b.u_dot);
            a.u_ddot.extend_from_slice(&b.u_ddot);
            a.contact.extend_from_slice(&b.contact);
            a.pressure_angle.extend_from_slice(&b.pressure_angle);
        }
    }

    /// Takes the counters and dropped rows of a streamed run.
    pub fn set_totals(&mut self, totals: RunTotals) {
        self.subdivided_steps = totals.subdivided_steps;
        self.row_reselections = totals.row_reselections;
        self.dropped_rows = totals.dropped_rows;
        self.held_dof = totals.held_dof;
        self.held_from_assembly = totals.held_from_assembly;
    }

    /// The counters and dropped rows (and the number of frames).
    pub fn totals(&self) -> RunTotals {
        RunTotals {
            frames: self.len(),
            subdivided_steps: self.subdivided_steps,
            row_reselections: self.row_reselections,
            dropped_rows: self.dropped_rows.clone(),
            held_dof: self.held_dof,
            held_from_assembly: self.held_from_assembly,
        }
    }
}
