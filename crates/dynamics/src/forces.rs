//! Applied forces: gravity, point forces and torques, translational spring-damper-actuators,
//! rotational spring-dampers on revolute joints, translational ones on prismatic joints, and a
//! user callback.
//!
//! ## Generalized forces in the 6-coordinate form
//! With v_k = [ṙ_k; ω'_k] the generalized force of body k is h_k = [f_k; n'_k]: f_k the resultant
//! force (global components) and n'_k the resultant torque about the centre of mass in body
//! components. A force F (global) at body point s'^P contributes
//!
//! ```text
//! f_k += F,      n'_k += s̃'^P (A_kᵀ F)
//! ```
//!
//! and a torque T (global) contributes n'_k += A_kᵀ T. The gyroscopic term −ω̃' J' ω' is added by
//! the equations of motion, not here.
//!
//! ## Elements
//! - [`Force::Gravity`]: f_k += m_k g at every centre of mass; potential −m_k gᵀ r_k.
//! - [`Force::PointForce`], [`Force::PointTorque`]: a vector [`VectorFunction`] of time in the
//!   global or the body frame ([`Frame`]).
//! - [`Force::SpringDamperActuator`]: between P_i and P_j, d = P_j − P_i, ℓ = |d|, u = d/ℓ; tension
//!   f = k (ℓ − ℓ0) + c ℓ̇ + f_a(t) (positive pulls the points together): body i gets +f u at P_i,
//!   body j gets −f u at P_j. Potential ½ k (ℓ − ℓ0)².
//! - [`Force::RotationalSpringDamper`]: on a revolute (or cylindrical) joint with angle θ (the
//!   joint's marker angle, x_j from x_i about z_i) and rate θ̇ = z_iᵀ(ω_j − ω_i): torque
//!   T = −(k (θ − θ0) + c θ̇) z_i on body j and −T on body i. θ − θ0 is taken in (−π, π].
//!   Potential ½ k (θ − θ0)².
//! - [`Force::TranslationalSpringDamper`]: on a prismatic (or cylindrical) joint with slide s
//!   (z_iᵀ(P_j − P_i)) and rate ṡ = z_iᵀ(v_Pj − v_Q), Q the point of body i at P_j: force
//!   F = −(k (s − s0) + c ṡ) z_i on body j at P_j and −F on body i at Q (no moment, and the
//!   pair's power is F ṡ). Potential ½ k (s − s0)².
//! - A user callback ([`UserForces`]) adds anything else through [`AppliedForces`].

use crate::DynamicsError;
use cardan_constraints::joints::unwrap_angle;
use cardan_constraints::{BodyPair, BodyState, TimeFunction};
use cardan_mechanism::Quantity;
use cardan_mechanism::{BodyId, ForceInfo, Model};
use nalgebra::Vector3;
use std::fmt;
use std::sync::Arc;

/// The frame in which a force or torque vector is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Frame {
    /// Global components.
    #[default]
    Global,
    /// Components in the body frame (the vector turns with the body).
    Body,
}

/// A vector-valued function of time.
#[derive(Clone)]
pub enum VectorFunction {
    /// A constant vector.
    Constant(Vector3<f64>),
    /// Three scalar time functions (x, y, z).
    Components(Box<[TimeFunction; 3]>),
    /// Any function of time.
    Function(Arc<dyn Fn(f64) -> Vector3<f64> + Send + Sync>),
}

impl VectorFunction {
    /// The value at time `t`.
    pub fn eval(&self, t: f64) -> Vector3<f64> {
        match self {
            VectorFunction::Constant(v) => *v,
            VectorFunction::Components(c) => {
                Vector3::new(c[0].eval(t).0, c[1].eval(t).0, c[2].eval(t).0)
            }
            VectorFunction::Function(f) => f(t),
        }
    }

    /// A function of time.
    pub fn function(f: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Self {
        VectorFunction::Function(Arc::new(f))
    }
}

impl From<Vector3<f64>> for VectorFunction {
    fn from(v: Vector3<f64>) -> Self {
        VectorFunction::Constant(v)
    }
}

impl fmt::Debug for VectorFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VectorFunction::Constant(v) => write!(f, "Constant({v:?})"),
            VectorFunction::Components(c) => write!(f, "Components({c:?})"),
            VectorFunction::Function(_) => write!(f, "Function(..)"),
        }
    }
}

/// A point of a body: a named point of the model or body-frame coordinates (relative to the
/// body reference point, which is the centre of mass).
#[derive(Debug, Clone, PartialEq)]
pub enum PointRef {
    /// A point declared on the body in the model.
    Named(String),
    /// Body-frame coordinates (global for ground).
    Local(Vector3<f64>),
}

impl From<&str> for PointRef {
    fn from(s: &str) -> Self {
        PointRef::Named(s.into())
    }
}

impl From<Vector3<f64>> for PointRef {
    fn from(v: Vector3<f64>) -> Self {
        PointRef::Local(v)
    }
}

/// A force element (see the module docs for the formulas and signs). Bodies are named
/// (`"ground"` allowed where a second body is needed).
#[derive(Debug, Clone)]
pub enum Force {
    /// Uniform gravity g (global, m/s²) on every moving body.
    Gravity {
        /// Acceleration of gravity.
        g: Vector3<f64>,
    },
    /// A force at a point of a moving body.
    PointForce {
        /// Name (for error messages).
        name: String,
        /// The body.
        body: String,
        /// The point of application.
        point: PointRef,
        /// The force (N).
        value: VectorFunction,
        /// Frame of `value`.
        frame: Frame,
    },
    /// A pure torque on a moving body.
    PointTorque {
        /// Name.
        name: String,
        /// The body.
        body: String,
        /// The torque (N m).
        value: VectorFunction,
        /// Frame of `value`.
        frame: Frame,
    },
    /// Translational spring-damper-actuator between two points.
    SpringDamperActuator {
        /// Name.
        name: String,
        /// Body i.
        body_i: String,
        /// Point on body i.
        point_i: PointRef,
        /// Body j.
        body_j: String,
        /// Point on body j.
        point_j: PointRef,
        /// k ≥ 0 (N/m).
        stiffness: f64,
        /// c ≥ 0 (N s/m).
        damping: f64,
        /// ℓ0 (m); `None`: the distance at the model's initial poses.
        free_length: Option<f64>,
        /// Actuator tension f_a(t) (N), added to the spring-damper tension.
        actuator: Option<TimeFunction>,
    },
    /// Rotational spring-damper on a revolute or cylindrical joint.
    RotationalSpringDamper {
        /// Name.
        name: String,
        /// The joint.
        joint: String,
        /// k ≥ 0 (N m/rad).
        stiffness: f64,
        /// c ≥ 0 (N m s/rad).
        damping: f64,
        /// θ0 (rad).
        rest_angle: f64,
    },
    /// Translational spring-damper on a prismatic or cylindrical joint.
    TranslationalSpringDamper {
        /// Name.
        name: String,
        /// The joint.
        joint: String,
        /// k ≥ 0 (N/m).
        stiffness: f64,
        /// c ≥ 0 (N s/m).
        damping: f64,
        /// s0 (m).
        rest_position: f64,
    },
}

impl Force {
    /// Gravity.
    pub fn gravity(g: Vector3<f64>) -> Self {
        Force::Gravity { g }
    }

    /// A force `value` (frame `frame`) at `point` of `body`.
    pub fn point_force(
        name: &str,
        body: &str,
        point: impl Into<PointRef>,
        value: impl Into<VectorFunction>,
        frame: Frame,
    ) -> Self {
        Force::PointForce {
            name: name.into(),
            body: body.into(),
            point: point.into(),
            value: value.into(),
            frame,
        }
    }

    /// A torque `value` (frame `frame`) on `body`.
    pub fn torque(name: &str, body: &str, value: impl Into<VectorFunction>, frame: Frame) -> Self {
        Force::PointTorque {
            name: name.into(),
            body: body.into(),
            value: value.into(),
            frame,
        }
    }

    /// A spring-damper (no actuator) between `(body_i, point_i)` and `(body_j, point_j)`.
    pub fn spring_damper(
        name: &str,
        (body_i, point_i): (&str, impl Into<PointRef>),
        (body_j, point_j): (&str, impl Into<PointRef>),
        stiffness: f64,
        damping: f64,
        free_length: Option<f64>,
    ) -> Self {
        Force::SpringDamperActuator {
            name: name.into(),
            body_i: body_i.into(),
            point_i: point_i.into(),
            body_j: body_j.into(),
            point_j: point_j.into(),
            stiffness,
            damping,
            free_length,
            actuator: None,
        }
    }

    /// A rotational spring-damper on joint `joint`.
    pub fn rotational_spring_damper(
        name: &str,
        joint: &str,
        stiffness: f64,
        damping: f64,
        rest_angle: f64,
    ) -> Self {
        Force::RotationalSpringDamper {
            name: name.into(),
            joint: joint.into(),
            stiffness,
            damping,
            rest_angle,
        }
    }

    /// A translational spring-damper on joint `joint` (a prismatic or cylindrical joint's slide).
    pub fn translational_spring_damper(
        name: &str,
        joint: &str,
        stiffness: f64,
        damping: f64,
        rest_position: f64,
    ) -> Self {
        Force::TranslationalSpringDamper {
            name: name.into(),
            joint: joint.into(),
            stiffness,
            damping,
            rest_position,
        }
    }

    /// Checks the element against `model` as [`crate::Dynamics::add_force`] does (its bodies,
    /// points and joint exist; coefficients ≥ 0; a spring between two bodies that does
    /// something; a rotational spring on a joint with an angle and x axes), without building
    /// the dynamics (which needs every body's mass): the one validation of a force element,
    /// for front ends to run when a model is read.
    ///
    /// # Errors
    /// [`DynamicsError::BadForce`] naming the element and, where it is one key's, the key.
    pub fn validate(&self, model: &Model) -> Result<(), DynamicsError> {
        Resolved::resolve(model, self).map(drop)
    }

    /// The element's name ("gravity" for gravity).
    pub fn name(&self) -> &str {
        match self {
            Force::Gravity { .. } => "gravity",
            Force::PointForce { name, .. }
            | Force::PointTorque { name, .. }
            | Force::SpringDamperActuator { name, .. }
            | Force::RotationalSpringDamper { name, .. }
            | Force::TranslationalSpringDamper { name, .. } => name,
        }
    }

    /// The force elements stored in a model ([`Model::forces`]).
    pub fn from_model(model: &Model) -> Vec<Force> {
        model
            .forces()
            .iter()
            .map(|f| match f {
                ForceInfo::Gravity { g } => Force::Gravity { g: *g },
                ForceInfo::SpringDamper {
                    name,
                    body_i,
                    point_i,
                    body_j,
                    point_j,
                    stiffness,
                    damping,
                    free_length,
                } => Force::SpringDamperActuator {
                    name: name.clone(),
                    body_i: model.body_name(*body_i).into(),
                    point_i: PointRef::Local(*point_i),
                    body_j: model.body_name(*body_j).into(),
                    point_j: PointRef::Local(*point_j),
                    stiffness: *stiffness,
                    damping: *damping,
                    free_length: Some(*free_length),
                    actuator: None,
                },
                ForceInfo::PointForce {
                    name,
                    body,
                    point,
                    force,
                } => Force::PointForce {
                    name: name.clone(),
                    body: model.body_name(*body).into(),
                    point: PointRef::Local(*point),
                    value: VectorFunction::Constant(*force),
                    frame: Frame::Global,
                },
                ForceInfo::Torque { name, body, torque } => Force::PointTorque {
                    name: name.clone(),
                    body: model.body_name(*body).into(),
                    value: VectorFunction::Constant(*torque),
                    frame: Frame::Global,
                },
            })
            .collect()
    }
}

/// Accumulates generalized forces h_k = [f_k; n'_k] (see the module docs). Handed to the user
/// callback; ground contributions are ignored.
pub struct AppliedForces<'a> {
    pub(crate) h: &'a mut [f64],
    pub(crate) bodies: &'a [BodyState],
}

impl AppliedForces<'_> {
    /// Adds force `f` (global) at body point `s_local` (body frame) of `body`.
    pub fn add_force_at(&mut self, body: BodyId, s_local: &Vector3<f64>, f: &Vector3<f64>) {
        if let BodyId::Moving(k) = body {
            let fl = self.bodies[k].a.tr_mul(f);
            let n = s_local.cross(&fl);
            for c in 0..3 {
                self.h[6 * k + c] += f[c];
                self.h[6 * k + 3 + c] += n[c];
            }
        }
    }

    /// Adds force `f` (global) at the centre of mass of `body`.
    pub fn add_force(&mut self, body: BodyId, f: &Vector3<f64>) {
        if let BodyId::Moving(k) = body {
            for c in 0..3 {
                self.h[6 * k + c] += f[c];
            }
        }
    }

    /// Adds torque `n` (global components) to `body`.
    pub fn add_torque(&mut self, body: BodyId, n: &Vector3<f64>) {
        if let BodyId::Moving(k) = body {
            let nl = self.bodies[k].a.tr_mul(n);
            self.add_torque_local(body, &nl);
        }
    }

    /// Adds torque `n_local` (body components) to `body`.
    pub fn add_torque_local(&mut self, body: BodyId, n_local: &Vector3<f64>) {
        if let BodyId::Moving(k) = body {
            for c in 0..3 {
                self.h[6 * k + 3 + c] += n_local[c];
            }
        }
    }

    /// The body states (pose r, p, A and velocity ṙ, ω') of the moving bodies.
    pub fn bodies(&self) -> &[BodyState] {
        self.bodies
    }
}

/// A user force callback: `f(t, forces)` adds forces through [`AppliedForces`] (whose
/// [`bodies`](AppliedForces::bodies) give the current poses and velocities). It may be called
/// several times per step and at trial states; it must not keep state that depends on being
/// called once per step.
pub type UserForces = Box<dyn FnMut(f64, &mut AppliedForces<'_>) + Send>;

/// A force element with names resolved to body indices and body-frame points.
#[derive(Debug, Clone)]
pub(crate) enum Resolved {
    Gravity(Vector3<f64>),
    PointForce {
        body: BodyId,
        point: Vector3<f64>,
        value: VectorFunction,
        frame: Frame,
    },
    Torque {
        body: BodyId,
        value: VectorFunction,
        frame: Frame,
    },
    Spring {
        bi: BodyId,
        pi: Vector3<f64>,
        bj: BodyId,
        pj: Vector3<f64>,
        k: f64,
        c: f64,
        l0: f64,
        actuator: Option<TimeFunction>,
    },
    Rotational {
        joint: usize,
        k: f64,
        c: f64,
        theta0: f64,
        /// The joint angle continued over turns at the last accepted pose
        /// ([`Resolved::accept_angle`]); NaN before the first.
        reference: f64,
        /// [`Resolved::follow_angle`]: the spring's angle minus the caller's (a multiple of 2π).
        offset: f64,
    },
    Translational {
        joint: usize,
        /// The index of the joint's slide among its coordinates.
        slide: usize,
        k: f64,
        c: f64,
        s0: f64,
    },
}

fn state_of<'a>(bodies: &'a [BodyState], ground: &'a BodyState, id: BodyId) -> &'a BodyState {
    match id {
        BodyId::Ground => ground,
        BodyId::Moving(k) => &bodies[k],
    }
}

fn point_velocity(b: &BodyState, s: &Vector3<f64>) -> Vector3<f64> {
    b.r_dot + b.a * b.omega_local.cross(s)
}

/// The angle of a rotational spring's joint continued over turns: the value congruent to the
/// principal angle `theta` nearest to the last accepted one (`reference`), or, before the first
/// accepted pose, nearest to the rest angle θ0 (so the initial deflection is within ±π, and
/// the deflection θ − θ0 then follows the joint over any number of turns).
fn continued(theta: f64, reference: f64, theta0: f64) -> f64 {
    let from = if reference.is_nan() {
        theta0
    } else {
        reference
    };
    unwrap_angle(from, theta)
}

/// A prismatic or cylindrical joint's slide s along z_i (its coordinate `slide`), its rate
/// ṡ = z_iᵀ(v_Pj − v_Pi), the axis z_i (global) and the marker point P_j in body i's
/// coordinates (where the reaction of a force on j at P_j acts on i, so the pair has no moment).
struct JointSlide {
    s: f64,
    rate: f64,
    z: Vector3<f64>,
    on_i: Vector3<f64>,
}

impl JointSlide {
    fn at(j: &cardan_mechanism::JointInfo, slide: usize, bodies: &[BodyState]) -> Self {
        let ground = BodyState::ground();
        let (si, sj) = (
            state_of(bodies, &ground, j.body_i),
            state_of(bodies, &ground, j.body_j),
        );
        let s = j.joint.coordinates(&BodyPair::new(si, sj)).values[slide];
        let z = si.a * j.joint.marker_i().z();
        let pj = &j.joint.marker_j().point;
        let on_i = si.a.tr_mul(&(sj.point(pj) - si.r));
        let rate = z.dot(&(point_velocity(sj, pj) - point_velocity(si, &on_i)));
        Self { s, rate, z, on_i }
    }
}

/// The checks of one force element against the model while it is resolved: each failure a
/// [`DynamicsError::BadForce`] naming the element.
struct Checks<'a> {
    model: &'a Model,
    force: &'a str,
}

impl Checks<'_> {
    /// A failure of the element as a whole.
    fn bad(&self, reason: String) -> DynamicsError {
        DynamicsError::BadForce {
            force: self.force.into(),
            key: None,
            reason,
        }
    }

    /// A failure of the element's entry `key` (so a model file can point at its line).
    fn at(&self, key: &'static str, reason: String) -> DynamicsError {
        DynamicsError::BadForce {
            force: self.force.into(),
            key: Some(key),
            reason,
        }
    }

    /// The body `name` (entry `key`), which must be a moving body when `moving`.
    fn body(&self, key: &'static str, name: &str, moving: bool) -> Result<BodyId, DynamicsError> {
        match self.model.body_id(name) {
            Some(BodyId::Ground) if moving => Err(self.at(
                key,
                "a force on the ground does nothing; name a moving body".into(),
            )),
            Some(id) => Ok(id),
            None => Err(self.at(key, format!("unknown body \"{name}\""))),
        }
    }

    /// The local coordinates of the point `p` on body `b` (finite, or a named point of `b`).
    fn point(
        &self,
        key: &'static str,
        b: &str,
        p: &PointRef,
    ) -> Result<Vector3<f64>, DynamicsError> {
        let model = self.model;
        match p {
            PointRef::Local(v) if v.iter().all(|x| x.is_finite()) => Ok(*v),
            PointRef::Local(_) => Err(self.at(key, "point is not finite".into())),
            PointRef::Named(n) => model
                .point_index(b, n)
                .map(|i| model.points()[i].local)
                .ok_or_else(|| self.at(key, format!("unknown point \"{n}\" on body \"{b}\""))),
        }
    }

    /// A coefficient (entry `key`) that must be finite and not negative.
    fn nonneg(&self, key: &'static str, v: f64) -> Result<(), DynamicsError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.at(key, format!("{key} must be finite and ≥ 0, got {v}")))
        }
    }

    /// The free length of a spring between point `pi` of `bi` and `pj` of `bj`: the file's
    /// (checked), or the distance between the points at the model's initial poses.
    fn free_length(
        &self,
        given: Option<f64>,
        (bi, pi): (BodyId, &Vector3<f64>),
        (bj, pj): (BodyId, &Vector3<f64>),
    ) -> Result<f64, DynamicsError> {
        if let Some(l) = given {
            self.nonneg("free_length", l)?;
            return Ok(l);
        }
        let at = |id: BodyId, s: &Vector3<f64>| match id {
            BodyId::Ground => *s,
            BodyId::Moving(k) => {
                let b = &self.model.bodies()[k];
                BodyState::at(b.initial_r, b.initial_p).point(s)
            }
        };
        Ok((at(bj, pj) - at(bi, pi)).norm())
    }

    /// The index of the joint of a translational spring and of its slide among the joint's
    /// coordinates: a joint with a translation along its axis.
    fn translational_joint(&self, joint: &str) -> Result<(usize, usize), DynamicsError> {
        let model = self.model;
        let j = model
            .joint_index(joint)
            .ok_or_else(|| self.at("joint", format!("unknown joint \"{joint}\"")))?;
        let info = model.joints()[j].joint.kind().info();
        let slide = info
            .translation
            .and_then(|name| info.coordinates.iter().position(|c| c.name == name));
        slide.map(|s| (j, s)).ok_or_else(|| {
            self.at(
                "joint",
                format!(
                    "joint \"{joint}\" is a {} joint; a translational spring acts on the slide \
                     of {}",
                    info.name,
                    cardan_mechanism::kinds_with(|k| k.translation.is_some())
                ),
            )
        })
    }

    /// The index of the joint of a rotational spring: a joint with a rotation angle.
    fn rotational_joint(&self, joint: &str) -> Result<usize, DynamicsError> {
        let model = self.model;
        let j = model
            .joint_index(joint)
            .ok_or_else(|| self.at("joint", format!("unknown joint \"{joint}\"")))?;
        let info = model.joints()[j].joint.kind().info();
        if info.rotation.is_none() {
            return Err(self.at(
                "joint",
                format!(
                    "joint \"{joint}\" is a {} joint; a rotational spring acts on the angle of {}",
                    info.name,
                    cardan_mechanism::kinds_with(|k| k.rotation.is_some())
                ),
            ));
        }
        Ok(j)
    }
}

impl Resolved {
    /// The element `f` checked against the model, its bodies, points and joint resolved to
    /// indices and local coordinates ([`Checks`]).
    pub(crate) fn resolve(model: &Model, f: &Force) -> Result<Self, DynamicsError> {
        let checks = Checks {
            model,
            force: f.name(),
        };
        Ok(match f {
            Force::Gravity { g } => {
                if !g.iter().all(|x| x.is_finite()) {
                    return Err(checks.bad("gravity is not finite".into()));
                }
                Resolved::Gravity(*g)
            }
            Force::PointForce {
                body: b,
                point: p,
                value,
                frame,
                ..
            } => Resolved::PointForce {
                body: checks.body("body", b, true)?,
                point: checks.point("point", b, p)?,
                value: value.clone(),
                frame: *frame,
            },
            Force::PointTorque {
                body: b,
                value,
                frame,
                ..
            } => Resolved::Torque {
                body: checks.body("body", b, true)?,
                value: value.clone(),
                frame: *frame,
            },
            Force::SpringDamperActuator {
                body_i,
                point_i,
                body_j,
                point_j,
                stiffness,
                damping,
                free_length,
                actuator,
                ..
            } => {
                let bi = checks.body("body_i", body_i, false)?;
                let bj = checks.body("body_j", body_j, false)?;
                if bi == bj {
                    return Err(checks.at(
                        "body_j",
                        format!("both points are on body \"{body_i}\"; the spring cannot stretch"),
                    ));
                }
                let pi = checks.point("point_i", body_i, point_i)?;
                let pj = checks.point("point_j", body_j, point_j)?;
                checks.nonneg("stiffness", *stiffness)?;
                checks.nonneg("damping", *damping)?;
                if *stiffness == 0.0 && *damping == 0.0 && actuator.is_none() {
                    return Err(checks.bad(
                        "stiffness, damping and actuator are all absent or zero, so the element \
                         does nothing"
                            .into(),
                    ));
                }
                let l0 = checks.free_length(*free_length, (bi, &pi), (bj, &pj))?;
                if let Some(a) = actuator {
                    a.validate()
                        .map_err(|e| checks.at("actuator", format!("actuator: {e}")))?;
                }
                Resolved::Spring {
                    bi,
                    pi,
                    bj,
                    pj,
                    k: *stiffness,
                    c: *damping,
                    l0,
                    actuator: actuator.clone(),
                }
            }
            Force::RotationalSpringDamper {
                joint,
                stiffness,
                damping,
                rest_angle,
                ..
            } => {
                let j = checks.rotational_joint(joint)?;
                checks.nonneg("stiffness", *stiffness)?;
                checks.nonneg("damping", *damping)?;
                if *stiffness != 0.0 && !model.joints()[j].has_x_axes {
                    return Err(checks.at(
                        "joint",
                        format!(
                        "joint \"{joint}\" has no x axes, so the spring's angle has no defined \
                         zero; the angle is measured from x_axis_i to x_axis_j about axis_i: add \
                         x_axis_i and x_axis_j to the joint (pointing them the same way at the \
                         drawn pose makes the drawn angle 0)"
                    ),
                    ));
                }
                if !rest_angle.is_finite() {
                    return Err(checks.at("rest_angle", "rest_angle is not finite".into()));
                }
                Resolved::Rotational {
                    joint: j,
                    k: *stiffness,
                    c: *damping,
                    theta0: *rest_angle,
                    reference: f64::NAN,
                    offset: f64::NAN,
                }
            }
            Force::TranslationalSpringDamper {
                joint,
                stiffness,
                damping,
                rest_position,
                ..
            } => {
                let (j, slide) = checks.translational_joint(joint)?;
                checks.nonneg("stiffness", *stiffness)?;
                checks.nonneg("damping", *damping)?;
                if *stiffness == 0.0 && *damping == 0.0 {
                    return Err(checks.bad(
                        "a translational spring-damper with no stiffness and no damping does \
                         nothing"
                            .into(),
                    ));
                }
                if !rest_position.is_finite() {
                    return Err(checks.at("rest_position", "rest_position is not finite".into()));
                }
                Resolved::Translational {
                    joint: j,
                    slide,
                    k: *stiffness,
                    c: *damping,
                    s0: *rest_position,
                }
            }
        })
    }

    /// The quantity whose magnitude limit ([`Quantity::limit`]) bounds this element's force:
    /// a torque for torques and rotational springs, a force otherwise.
    pub(crate) fn quantity(&self) -> Quantity {
        match self {
            Resolved::Torque { .. } | Resolved::Rotational { .. } => Quantity::Torque,
            _ => Quantity::Force,
        }
    }

    /// Adds this element's generalized forces and returns the magnitude of its force (N) or
    /// torque (N m), for the limit of [`Resolved::quantity`] (0 for gravity, bounded by the
    /// masses and g). No allocation.
    pub(crate) fn apply(
        &self,
        model: &Model,
        masses: &[f64],
        t: f64,
        out: &mut AppliedForces,
    ) -> f64 {
        let ground = BodyState::ground();
        match self {
            Resolved::Gravity(g) => {
                for (k, m) in masses.iter().enumerate() {
                    out.add_force(BodyId::Moving(k), &(g * *m));
                }
                0.0
            }
            Resolved::PointForce {
                body,
                point,
                value,
                frame,
            } => {
                let mut f = value.eval(t);
                if *frame == Frame::Body {
                    f = state_of(out.bodies, &ground, *body).a * f;
                }
                out.add_force_at(*body, point, &f);
                f.norm()
            }
            Resolved::Torque { body, value, frame } => {
                let n = value.eval(t);
                match frame {
                    Frame::Global => out.add_torque(*body, &n),
                    Frame::Body => out.add_torque_local(*body, &n),
                }
                n.norm()
            }
            Resolved::Spring {
                bi,
                pi,
                bj,
                pj,
                k,
                c,
                l0,
                actuator,
            } => {
                let (si, sj) = (
                    state_of(out.bodies, &ground, *bi),
                    state_of(out.bodies, &ground, *bj),
                );
                let d = sj.point(pj) - si.point(pi);
                let l = d.norm();
                if l == 0.0 {
                    return 0.0;
                }
                let u = d / l;
                let ldot = u.dot(&(point_velocity(sj, pj) - point_velocity(si, pi)));
                let mut f = k * (l - l0) + c * ldot;
                if let Some(a) = actuator {
                    f += a.eval(t).0;
                }
                let fu = u * f;
                out.add_force_at(*bi, pi, &fu);
                out.add_force_at(*bj, pj, &(-fu));
                f.abs()
            }
            Resolved::Rotational {
                joint,
                k,
                c,
                theta0,
                reference,
                ..
            } => {
                let j = &model.joints()[*joint];
                let (si, sj) = (
                    state_of(out.bodies, &ground, j.body_i),
                    state_of(out.bodies, &ground, j.body_j),
                );
                let theta = j.joint.coordinates(&BodyPair::new(si, sj)).values[0];
                let z = si.a * j.joint.marker_i().z();
                let rate = z.dot(&(sj.a * sj.omega_local - si.a * si.omega_local));
                let deflection = continued(theta, *reference, *theta0) - theta0;
                let tq = z * (-(k * deflection + c * rate));
                out.add_torque(j.body_j, &tq);
                out.add_torque(j.body_i, &(-tq));
                tq.norm()
            }
            Resolved::Translational {
                joint,
                slide,
                k,
                c,
                s0,
            } => {
                let j = &model.joints()[*joint];
                let m = JointSlide::at(j, *slide, out.bodies);
                let f = -(k * (m.s - s0) + c * m.rate);
                let fz = m.z * f;
                out.add_force_at(j.body_j, &j.joint.marker_j().point, &fz);
                out.add_force_at(j.body_i, &m.on_i, &(-fz));
                f.abs()
            }
        }
    }

    /// Whether this is a rotational spring (whose joint angle is continued over turns).
    pub(crate) fn is_rotational(&self) -> bool {
        matches!(self, Resolved::Rotational { .. })
    }

    /// Accepts the bodies' poses for a rotational spring's continued angle (at each accepted
    /// step, with the couplers' turns: the joint must turn by less than π between two calls).
    /// No allocation.
    pub(crate) fn accept_angle(&mut self, model: &Model, bodies: &[BodyState]) {
        if let Resolved::Rotational {
            joint,
            theta0,
            reference,
            ..
        } = self
        {
            let ground = BodyState::ground();
            let j = &model.joints()[*joint];
            let pair = BodyPair::new(
                state_of(bodies, &ground, j.body_i),
                state_of(bodies, &ground, j.body_j),
            );
            let theta = j.joint.coordinates(&pair).values[0];
            *reference = continued(theta, *reference, *theta0);
        }
    }

    /// A rotational spring's joint angle continued by the caller (an inverse dynamics run's
    /// kinematic frames, whose output times may be turns apart): `value` is the angle continued
    /// from its principal value at the first frame; the spring keeps its own turn count (its
    /// first angle within ±π of θ0). `joint_value(j)` gives joint j's continued angle.
    pub(crate) fn follow_angle(&mut self, joint_value: impl Fn(usize) -> f64) {
        if let Resolved::Rotational {
            joint,
            theta0,
            reference,
            offset,
            ..
        } = self
        {
            let value = joint_value(*joint);
            if offset.is_nan() {
                *offset = unwrap_angle(*theta0, value) - value;
            }
            *reference = value + *offset;
        }
    }

    /// Whether the element does work that its potential energy does not account for: a damper
    /// (c > 0), an actuator, a point force or torque. Gravity and springs are conservative:
    /// their work is the decrease of the potential in [`crate::Energy`].
    pub(crate) fn is_non_conservative(&self) -> bool {
        match self {
            Resolved::Gravity(_) => false,
            Resolved::PointForce { .. } | Resolved::Torque { .. } => true,
            Resolved::Spring { c, actuator, .. } => *c != 0.0 || actuator.is_some(),
            Resolved::Rotational { c, .. } | Resolved::Translational { c, .. } => *c != 0.0,
        }
    }

    /// The power of the element's non-conservative part at the bodies `bodies` and time `t`
    /// (W; see [`crate::work`]): F · v_P for a point force, T · ω for a torque,
    /// −(c ℓ̇ + f_a) ℓ̇ for a spring-damper-actuator (its spring part k (ℓ − ℓ0) is in the
    /// potential), −c θ̇² for a rotational spring-damper; 0 for conservative elements. The same
    /// forces as [`apply`](Self::apply) puts into h, so their sum is the power vᵀh of the
    /// non-conservative forces. No allocation.
    pub(crate) fn non_conservative_power(
        &self,
        model: &Model,
        t: f64,
        bodies: &[BodyState],
    ) -> f64 {
        let ground = BodyState::ground();
        match self {
            Resolved::Gravity(_) => 0.0,
            Resolved::PointForce {
                body,
                point,
                value,
                frame,
            } => {
                let b = state_of(bodies, &ground, *body);
                let mut f = value.eval(t);
                if *frame == Frame::Body {
                    f = b.a * f;
                }
                f.dot(&point_velocity(b, point))
            }
            Resolved::Torque { body, value, frame } => {
                let b = state_of(bodies, &ground, *body);
                let n = value.eval(t);
                match frame {
                    Frame::Global => n.dot(&(b.a * b.omega_local)),
                    Frame::Body => n.dot(&b.omega_local),
                }
            }
            Resolved::Spring {
                bi,
                pi,
                bj,
                pj,
                c,
                actuator,
                ..
            } => {
                let (si, sj) = (
                    state_of(bodies, &ground, *bi),
                    state_of(bodies, &ground, *bj),
                );
                let d = sj.point(pj) - si.point(pi);
                let l = d.norm();
                if l == 0.0 {
                    // `apply` puts no force there either.
                    return 0.0;
                }
                let ldot = (d / l).dot(&(point_velocity(sj, pj) - point_velocity(si, pi)));
                let fa = actuator.as_ref().map_or(0.0, |a| a.eval(t).0);
                -(c * ldot + fa) * ldot
            }
            Resolved::Rotational { joint, c, .. } => {
                let j = &model.joints()[*joint];
                let (si, sj) = (
                    state_of(bodies, &ground, j.body_i),
                    state_of(bodies, &ground, j.body_j),
                );
                let z = si.a * j.joint.marker_i().z();
                let rate = z.dot(&(sj.a * sj.omega_local - si.a * si.omega_local));
                -c * rate * rate
            }
            Resolved::Translational {
                joint, slide, c, ..
            } => {
                let m = JointSlide::at(&model.joints()[*joint], *slide, bodies);
                -c * m.rate * m.rate
            }
        }
    }

    /// Potential energy of the element: (gravity, spring).
    pub(crate) fn potential(
        &self,
        model: &Model,
        masses: &[f64],
        bodies: &[BodyState],
    ) -> (f64, f64) {
        let ground = BodyState::ground();
        match self {
            Resolved::Gravity(g) => (
                -masses
                    .iter()
                    .zip(bodies)
                    .map(|(m, b)| m * g.dot(&b.r))
                    .sum::<f64>(),
                0.0,
            ),
            Resolved::Spring {
                bi,
                pi,
                bj,
                pj,
                k,
                l0,
                ..
            } => {
                let d = state_of(bodies, &ground, *bj).point(pj)
                    - state_of(bodies, &ground, *bi).point(pi);
                (0.0, 0.5 * k * (d.norm() - l0).powi(2))
            }
            Resolved::Rotational {
                joint,
                k,
                theta0,
                reference,
                ..
            } => {
                let j = &model.joints()[*joint];
                let pair = BodyPair::new(
                    state_of(bodies, &ground, j.body_i),
                    state_of(bodies, &ground, j.body_j),
                );
                let theta = j.joint.coordinates(&pair).values[0];
                let th = continued(theta, *reference, *theta0) - theta0;
                (0.0, 0.5 * k * th * th)
            }
            Resolved::Translational {
                joint,
                slide,
                k,
                s0,
                ..
            } => {
                let m = JointSlide::at(&model.joints()[*joint], *slide, bodies);
                (0.0, 0.5 * k * (m.s - s0).powi(2))
            }
            _ => (0.0, 0.0),
        }
    }

    /// Bodies whose generalized forces this element couples (for the iteration-matrix pattern).
    pub(crate) fn coupled(&self, model: &Model) -> Option<(BodyId, BodyId)> {
        match self {
            Resolved::Spring { bi, bj, .. } => Some((*bi, *bj)),
            Resolved::Rotational { joint, .. } | Resolved::Translational { joint, .. } => {
                let j = &model.joints()[*joint];
                Some((j.body_i, j.body_j))
            }
            _ => None,
        }
    }
}
