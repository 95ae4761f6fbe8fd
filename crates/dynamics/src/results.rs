//! [`DynamicResults`]: the kinematic histories (the mechanism's [`Results`]) extended with
//! multipliers, joint reactions, driver efforts, energy and constraint drift.
//!
//! The same type carries one stored time at a time to a [`DynamicSink`] (a streamed run,
//! [`Dynamics::simulate_into`](crate::Dynamics::simulate_into),
//! [`Dynamics::inverse_dynamics_into`](crate::Dynamics::inverse_dynamics_into)): a
//! `DynamicResults` holding exactly that time, its storage reused from one time to the next, as
//! the mechanism's [`FrameSink`](cardan_mechanism::FrameSink) does for kinematic frames.

use crate::joint_space::history::JointSpaceHistory;
use cardan_mechanism::{BodyResults, EquationName, PointResults, Results};
use nalgebra::Vector3;
use std::ops::ControlFlow;

/// The consumer of a streamed dynamic run's stored times: called once per output time, in
/// order, with its index k and a [`DynamicResults`] holding that one time (its histories, λ,
/// reactions, efforts, energy and drift rows; the counters are filled only in what the run
/// returns at its end). [`ControlFlow::Break`] stops the run after this time
/// ([`crate::DynamicsError::Stopped`]).
///
/// Closures `FnMut(usize, &DynamicResults) -> ControlFlow<()>` are sinks.
pub trait DynamicSink {
    /// Takes the output time k.
    fn frame(&mut self, k: usize, frame: &DynamicResults) -> ControlFlow<()>;
}

impl<F: FnMut(usize, &DynamicResults) -> ControlFlow<()>> DynamicSink for F {
    fn frame(&mut self, k: usize, frame: &DynamicResults) -> ControlFlow<()> {
        self(k, frame)
    }
}

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

    /// The same channels without any time, with room for `capacity` times.
    fn empty_like(&self, capacity: usize) -> Self {
        let e = || Vec::with_capacity(capacity);
        Self {
            kinetic: e(),
            gravity: e(),
            spring: e(),
            total: e(),
            elements: (self.elements.iter())
                .map(|w| ElementWork {
                    name: w.name.clone(),
                    kind: w.kind,
                    power: e(),
                    work: e(),
                })
                .collect(),
            work: e(),
            constraint_power: e(),
        }
    }

    /// Removes every time, keeping the storage.
    fn clear(&mut self) {
        for v in [
            &mut self.kinetic,
            &mut self.gravity,
            &mut self.spring,
            &mut self.total,
            &mut self.work,
            &mut self.constraint_power,
        ] {
            v.clear();
        }
        for w in &mut self.elements {
            w.power.clear();
            w.work.clear();
        }
    }

    /// Appends the times of `o` (same channels).
    fn extend_from(&mut self, o: &Self) {
        self.kinetic.extend_from_slice(&o.kinetic);
        self.gravity.extend_from_slice(&o.gravity);
        self.spring.extend_from_slice(&o.spring);
        self.total.extend_from_slice(&o.total);
        self.work.extend_from_slice(&o.work);
        self.constraint_power.extend_from_slice(&o.constraint_power);
        for (a, b) in self.elements.iter_mut().zip(&o.elements) {
            a.power.extend_from_slice(&b.power);
            a.work.extend_from_slice(&b.work);
        }
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
    /// The largest accepted step over the collision shapes' step cap
    /// (a quarter of each shape's thickness over its speed), with its time: above
    /// 1, a shape moved more than a quarter of its thickness in one step and thin shapes could
    /// have passed through each other unseen (generalized-α's fixed steps; DOPRI5 caps its
    /// own). 0 without shapes.
    pub contact_step_ratio: (f64, f64),
}

/// The contact force of a cam pair on its follower (body j) at each time, from the
/// multipliers of its reduced rows (the parameters' rows Φ_uᵀλ = 0 make it the frictionless
/// contact force: along the common normal).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CamForces {
    /// The cam pair's name.
    pub name: String,
    /// The force on the follower, global (N).
    pub force: Vec<Vector3<f64>>,
    /// Its component along the direction a pressing contact pushes the follower
    /// ([`cardan_mechanism::CurveElement::push_direction`]): positive while the cam pushes,
    /// negative where the bilateral constraint pulls the follower on (it would lift off); NaN
    /// where the curves do not tell the side (a flat face on an open profile).
    pub normal_force: Vec<f64>,
}

impl CamForces {
    /// The first time at which the contact pulls by more than `tolerance` (N), with that force:
    /// where the follower would lift off the cam.
    pub fn first_pull(&self, times: &[f64], tolerance: f64) -> Option<(f64, f64)> {
        (self.normal_force.iter().zip(times))
            .find(|(f, _)| **f < -tolerance)
            .map(|(f, t)| (*t, *f))
    }
}

/// The contacts between collision shapes at the output times ([`crate::collision`]): one row
/// per contact point and time, in time order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContactHistory {
    /// The shapes' names (index = the model's shape index).
    pub shapes: Vec<String>,
    /// The contact points: the output time and the contact there.
    pub points: Vec<(f64, crate::collision::ContactPoint)>,
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
    /// The contact force of every cam pair, in model order.
    pub cams: Vec<CamForces>,
    /// The contacts between collision shapes.
    pub contacts: ContactHistory,
    /// Energy.
    pub energy: EnergyHistory,
    /// The mass matrix, bias forces and point Jacobians in the drivers' coordinates, when
    /// requested ([`crate::Dynamics::request_joint_space`]; inverse dynamics).
    pub joint_space: JointSpaceHistory,
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

    /// The efforts of coupler `name`.
    pub fn coupler(&self, name: &str) -> Option<&CouplerEfforts> {
        self.couplers.iter().find(|c| c.name == name)
    }

    /// The efforts of driver `name`.
    pub fn driver(&self, name: &str) -> Option<&DriverEfforts> {
        self.drivers.iter().find(|d| d.name == name)
    }

    /// The contact forces of cam pair `name`.
    pub fn cam(&self, name: &str) -> Option<&CamForces> {
        self.cams.iter().find(|c| c.name == name)
    }

    /// The same names, outputs and counters without any time, with room for `capacity` times
    /// in every history this one fills (e.g. for a decimated copy of a streamed run).
    pub fn empty_like(&self, capacity: usize) -> Self {
        let n = capacity;
        fn room<T>(n: usize) -> Vec<T> {
            Vec::with_capacity(n)
        }
        let e = || room::<f64>(n);
        let reactions = |r: &JointReactions| JointReactions {
            on_i: room(n),
            on_j: room(n),
            ..r.empty()
        };
        Self {
            kinematics: self.kinematics.empty_like(n),
            lambda: room(n),
            reactions: self.reactions.iter().map(reactions).collect(),
            drivers: (self.drivers.iter())
                .map(|d| DriverEfforts {
                    name: d.name.clone(),
                    lambda: e(),
                    effort: e(),
                    power: e(),
                    reactions: reactions(&d.reactions),
                })
                .collect(),
            couplers: (self.couplers.iter())
                .map(|c| CouplerEfforts {
                    name: c.name.clone(),
                    lambda: e(),
                    efforts: Vec::with_capacity(n),
                    force: c.force.as_ref().map(|_| e()),
                    reactions: reactions(&c.reactions),
                })
                .collect(),
            cams: (self.cams.iter())
                .map(|c| CamForces {
                    name: c.name.clone(),
                    force: room(n),
                    normal_force: e(),
                })
                .collect(),
            contacts: ContactHistory {
                shapes: self.contacts.shapes.clone(),
                points: Vec::new(),
            },
            energy: self.energy.empty_like(n),
            joint_space: self.joint_space.empty_like(n),
            position_drift: e(),
            velocity_drift: e(),
            redundant: self.redundant.clone(),
            stats: self.stats,
        }
    }

    /// Removes every time, keeping the storage (no allocation when filled again, but for the
    /// λ vectors, which are dropped) and the counters.
    pub fn clear_frames(&mut self) {
        self.kinematics.clear_frames();
        self.lambda.clear();
        let clear = |r: &mut JointReactions| {
            r.on_i.clear();
            r.on_j.clear();
        };
        self.reactions.iter_mut().for_each(clear);
        for d in &mut self.drivers {
            d.lambda.clear();
            d.effort.clear();
            d.power.clear();
            clear(&mut d.reactions);
        }
        for c in &mut self.couplers {
            c.lambda.clear();
            c.efforts.clear();
            if let Some(f) = c.force.as_mut() {
                f.clear();
            }
            clear(&mut c.reactions);
        }
        for c in &mut self.cams {
            c.force.clear();
            c.normal_force.clear();
        }
        self.contacts.points.clear();
        self.energy.clear();
        self.joint_space.clear();
        self.position_drift.clear();
        self.velocity_drift.clear();
    }

    /// Appends the times of `other`, which has the same layout (made by
    /// [`DynamicResults::empty_like`] or by the same run); within the reserved room, only the
    /// λ vectors are allocated.
    pub fn extend_from(&mut self, other: &Self) {
        self.kinematics.extend_from(&other.kinematics);
        self.lambda.extend(other.lambda.iter().cloned());
        let extend = |a: &mut JointReactions, b: &JointReactions| {
            a.on_i.extend_from_slice(&b.on_i);
            a.on_j.extend_from_slice(&b.on_j);
        };
        for (a, b) in self.reactions.iter_mut().zip(&other.reactions) {
            extend(a, b);
        }
        for (a, b) in self.drivers.iter_mut().zip(&other.drivers) {
            a.lambda.extend_from_slice(&b.lambda);
            a.effort.extend_from_slice(&b.effort);
            a.power.extend_from_slice(&b.power);
            extend(&mut a.reactions, &b.reactions);
        }
        for (a, b) in self.couplers.iter_mut().zip(&other.couplers) {
            a.lambda.extend_from_slice(&b.lambda);
            a.efforts.extend_from_slice(&b.efforts);
            if let (Some(fa), Some(fb)) = (a.force.as_mut(), b.force.as_ref()) {
                fa.extend_from_slice(fb);
            }
            extend(&mut a.reactions, &b.reactions);
        }
        for (a, b) in self.cams.iter_mut().zip(&other.cams) {
            a.force.extend_from_slice(&b.force);
            a.normal_force.extend_from_slice(&b.normal_force);
        }
        (self.contacts.points).extend_from_slice(&other.contacts.points);
        self.energy.extend_from(&other.energy);
        self.joint_space.extend_from(&other.joint_space);
        self.position_drift.extend_from_slice(&other.position_drift);
        self.velocity_drift.extend_from_slice(&other.velocity_drift);
    }
}

impl JointReactions {
    /// The names without any time.
    fn empty(&self) -> Self {
        Self {
            name: self.name.clone(),
            body_i: self.body_i.clone(),
            body_j: self.body_j.clone(),
            point_i: self.point_i.clone(),
            point_j: self.point_j.clone(),
            on_i: Vec::new(),
            on_j: Vec::new(),
        }
    }
}
