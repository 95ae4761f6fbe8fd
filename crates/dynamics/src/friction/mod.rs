//! Coulomb friction in joints, from the joints' reactions ([`cardan_mechanism::FrictionInfo`]).
//!
//! ## Theory
//! For a joint with reaction force F on body j (global, from its multipliers: F = −Φ_rᵀλ)
//! and marker axis z_i, the normal load is N = |F − (zᵀF) z| + N₀ (the force across the
//! axis, plus the preload; |F| + N₀ for a ball joint). The friction is
//!
//! ```text
//! slide (prismatic, cylindrical):  f = −(μ N + F_c) s(ṡ)           along z_i, on j at P_j (−f on i)
//! pin (revolute, cylindrical):     τ = −(μ r N + T_c) s(θ̇)         about z_i, on j (−τ on i)
//! ball (spherical):                τ = −(μ r N + T_c) ω_rel / √(|ω_rel|² + v_s²)   on j (−τ on i)
//! s(v) = v / √(v² + v_s²)
//! ```
//!
//! with ṡ, θ̇ the joint's slide and angle rates and ω_rel = ω_j − ω_i: the friction circle of
//! radius μ r for a pin (Shigley; Haug 1989 §11.4 for joint friction from reactions). F_c and
//! T_c are a friction independent of the load (the `constant` law: URDF's `<dynamics
//! friction>`, MuJoCo's `frictionloss`, whose inverse dynamics gives exactly F_c sign(ṡ) while
//! the joint slides). s regularizes sign(v) near zero velocity (the stiction model: a steep viscous law of slope
//! μN/v_s below v_s, so a joint held by friction creeps at about v_s times the ratio of the
//! driving force to μN; the run's steps resolve that slope).
//!
//! The friction depends on the reactions, which depend on the friction: the augmented system
//! is solved again with the friction forces added to h, with the factorization kept, until
//! the friction forces change by less than 1e-12 of the forces' scale (a fixed point; the
//! run stops with an error when it does not converge in [`MAX_ITERATIONS`], as for a
//! self-locking joint). The friction's power vᵀh_f (≤ 0) is a work channel of the energy
//! balance ([`crate::work`]).
//!
//! Generalized-α solves the step's equations for v̇ and λ together, so there the friction is
//! a force of the iterate: evaluated from the iterate's λ at every Newton iteration (the
//! converged step satisfies friction and reactions together, nothing lagged), its velocity
//! tangent in the iteration matrix through the force tangents' differences.

use crate::forces::AppliedForces;
use crate::kkt::SchurRefinement;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_constraints::joints::{BodyAcceleration, Measure};
use cardan_constraints::{BodyPair, BodyState, JointKind};
use cardan_mechanism::BodyId;
use nalgebra::Vector3;

pub mod state;

/// The most re-solves of the friction–reaction fixed point at one evaluation.
pub const MAX_ITERATIONS: usize = 50;

fn reg(v: f64, vs: f64) -> f64 {
    v / (v * v + vs * vs).sqrt()
}

impl Dynamics<'_> {
    /// The reaction force on body j of joint `joint` (global) from the last solution, or from
    /// the multipliers `frozen` (over the kept rows).
    fn joint_force(&self, joint: usize, t: f64, frozen: bool) -> Vector3<f64> {
        let e = &self.elements[joint];
        let (mut bi, mut bj) = ([[0.0; 6]; 6], [[0.0; 6]; 6]);
        self.element_blocks(e, t, &mut bi, &mut bj);
        let kkt = self.kkt.as_ref().expect("prepared");
        let (mut fi, mut fj) = (Vector3::zeros(), Vector3::zeros());
        for (lr, r) in e.rows.clone().enumerate() {
            let a = kkt.active_of[r];
            if a == usize::MAX {
                continue;
            }
            let l = if frozen {
                self.friction.frozen.get(a).copied().unwrap_or(0.0)
            } else {
                kkt.sol[kkt.n + a]
            };
            for c in 0..3 {
                fi[c] -= bi[lr][c] * l;
                fj[c] -= bj[lr][c] * l;
            }
        }
        match e.bj {
            BodyId::Moving(_) => fj,
            BodyId::Ground => -fi,
        }
    }

    /// h_f at the synced bodies from the reactions of the last solution (or of the multipliers
    /// `friction.frozen`), each element's friction and power.
    fn eval_friction(&mut self, t: f64, frozen: bool) {
        let model = self.model;
        let g = BodyState::ground();
        let mut hf = std::mem::take(&mut self.friction.hf);
        hf.fill(0.0);
        for (k, f) in model.frictions().iter().enumerate() {
            let info = &model.joints()[f.joint];
            let joint = &info.joint;
            let st = |id: BodyId| match id {
                BodyId::Ground => g,
                BodyId::Moving(b) => self.bodies[b],
            };
            let (si, sj) = (st(info.body_i), st(info.body_j));
            let pair = BodyPair::new(&si, &sj);
            let z = si.a * joint.marker_i().z();
            let force = self.joint_force(f.joint, t, frozen);
            let radial = (force - z * z.dot(&force)).norm();
            let zero = BodyAcceleration::default();
            let rates = joint.coordinate_rates(&pair, &zero, &zero);
            let rate_of = |m: Measure| {
                let c = joint.kind().info().coordinates;
                c.iter()
                    .position(|c| c.measure == m)
                    .map(|i| rates.rates[i])
            };
            let mut acc = AppliedForces {
                h: &mut hf,
                bodies: &self.bodies,
            };
            let (mut value, mut power) = (0.0, 0.0);
            if let Some(v) = rate_of(Measure::Slide) {
                let load = f.coefficient * (radial + f.preload) + f.force;
                let fr = -load * reg(v, f.stiction_velocity);
                let pj = sj.point(&joint.marker_j().point);
                let on_i = si.a.tr_mul(&(pj - si.r));
                acc.add_force_at(info.body_j, &joint.marker_j().point, &(z * fr));
                acc.add_force_at(info.body_i, &on_i, &(-z * fr));
                value = fr;
                power += fr * v;
            }
            if let Some(w) = rate_of(Measure::Angle) {
                let load = f.coefficient * f.radius * (radial + f.preload) + f.torque;
                let tq = -load * reg(w, f.stiction_velocity);
                acc.add_torque(info.body_j, &(z * tq));
                acc.add_torque(info.body_i, &(-z * tq));
                value = if joint.kind() == JointKind::Cylindrical {
                    value
                } else {
                    tq
                };
                power += tq * w;
            }
            if joint.kind() == JointKind::Spherical {
                let w = sj.a * sj.omega_local - si.a * si.omega_local;
                let n = w.norm();
                let scale = (f.coefficient * f.radius * (force.norm() + f.preload) + f.torque)
                    / (n * n + f.stiction_velocity * f.stiction_velocity).sqrt();
                acc.add_torque(info.body_j, &(-w * scale));
                acc.add_torque(info.body_i, &(w * scale));
                value = scale * n;
                power -= scale * n * n;
            }
            self.friction.value[k] = value;
            self.friction.power[k] = power;
        }
        self.friction.hf = hf;
    }

    /// Appends each element's friction and power at the output time `t` (after the equations
    /// of motion were solved there) to the run's history. Nothing without friction.
    pub(crate) fn record_friction(&mut self, t: f64) {
        let f = &mut self.friction;
        if f.hf.is_empty() {
            return;
        }
        f.history.times.push(t);
        f.history.value.push(f.value.clone());
        f.history.power.push(f.power.clone());
    }

    /// The joints' friction at each output time of the last run (force or torque, power).
    pub fn friction_history(&self) -> &state::FrictionHistory {
        &self.friction.history
    }

    /// Forgets the history of an earlier run.
    pub(crate) fn reset_friction_history(&mut self) {
        self.friction.history = state::FrictionHistory::default();
    }

    /// Takes the multipliers `lambda` (over the kept rows) of an implicit step's iterate for the
    /// friction ([`Self::add_friction_frozen`]); nothing without friction. Allocates only when
    /// the kept rows change.
    pub(crate) fn freeze_friction(&mut self, lambda: &[f64]) {
        if self.friction.hf.is_empty() {
            return;
        }
        let frozen = &mut self.friction.frozen;
        if frozen.len() != lambda.len() {
            frozen.resize(lambda.len(), 0.0);
        }
        frozen.copy_from_slice(lambda);
    }

    /// The friction from the multipliers in `friction.frozen` (an implicit step's iterate)
    /// added to h at the synced bodies: the step's Newton iteration solves the friction with
    /// the reactions, and its finite-difference tangents take ∂h_f/∂v (the regularized sign's
    /// slope μN/v_s, which the iteration matrix needs while a joint sticks).
    pub(crate) fn add_friction_frozen(&mut self, t: f64) {
        self.eval_friction(t, true);
        for (h, f) in self.h.iter_mut().zip(&self.friction.hf) {
            *h += f;
        }
    }

    /// After the solve without friction: the fixed point of friction and reactions (module
    /// docs). No allocation after the first call.
    ///
    /// # Errors
    /// [`DynamicsError::NotConverged`] when the friction forces do not settle; the solves'
    /// failures.
    pub(crate) fn solve_friction(
        &mut self,
        t: f64,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        let n = self.friction.hf.len();
        self.friction.hf_prev.fill(0.0);
        let scale = self.h.iter().fold(1e-300f64, |a, v| a.max(v.abs()));
        let mut change = 0.0;
        for _ in 0..MAX_ITERATIONS {
            self.eval_friction(t, false);
            change = self
                .friction
                .hf
                .iter()
                .zip(&self.friction.hf_prev)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            let size = self.friction.hf.iter().fold(scale, |a, v| a.max(v.abs()));
            if change <= 1e-12 * size {
                return Ok(());
            }
            self.friction.hf_prev.copy_from_slice(&self.friction.hf);
            let kkt = self.kkt.as_mut().expect("prepared");
            kkt.rhs.copy_from_slice(&self.friction.rhs0);
            for (r, f) in kkt.rhs[..n].iter_mut().zip(&self.friction.hf) {
                *r += f;
            }
            if let Err(e) = kkt.solve(refine) {
                return Err(self.solver_error(t, e));
            }
            if self.contacts.any_held() {
                self.add_held_stops(t, refine)?;
            }
        }
        Err(DynamicsError::NotConverged {
            time: t,
            what: "joint friction (the friction–reaction fixed point)",
            iterations: MAX_ITERATIONS,
            residual: change,
        })
    }
}
