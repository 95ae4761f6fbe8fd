//! [`State`]: time, poses q = [r_k; p_k] (7 per moving body) and velocities v = [ṙ_k; ω'_k]
//! (6 per moving body, ω' in the body frame).

use cardan_constraints::BodyState;
use cardan_mechanism::{BodyId, Model};
use nalgebra::{Vector3, Vector4};

/// The state of a mechanism in the 6-coordinate velocity form.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time.
    pub t: f64,
    /// Poses `[r_k; p_k]`, 7 per moving body (p unit).
    pub q: Vec<f64>,
    /// Velocities `[ṙ_k; ω'_k]`, 6 per moving body.
    pub v: Vec<f64>,
}

impl State {
    /// The model's initial poses (as given to the builder, not assembled), at rest, at `t`.
    pub fn initial(model: &Model, t: f64) -> Self {
        let nb = model.num_bodies();
        let mut q = vec![0.0; 7 * nb];
        for (k, b) in model.bodies().iter().enumerate() {
            q[7 * k..7 * k + 3].copy_from_slice(b.initial_r.as_slice());
            q[7 * k + 3..7 * k + 7].copy_from_slice(b.initial_p.as_slice());
        }
        Self {
            t,
            q,
            v: vec![0.0; 6 * nb],
        }
    }

    /// Number of moving bodies.
    pub fn num_bodies(&self) -> usize {
        self.v.len() / 6
    }

    /// r of body k.
    pub fn r(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.q[7 * k..7 * k + 3])
    }

    /// p of body k.
    pub fn p(&self, k: usize) -> Vector4<f64> {
        Vector4::from_column_slice(&self.q[7 * k + 3..7 * k + 7])
    }

    /// ṙ of body k.
    pub fn r_dot(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.v[6 * k..6 * k + 3])
    }

    /// ω' of body k (body frame).
    pub fn omega_local(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.v[6 * k + 3..6 * k + 6])
    }

    /// ω = A ω' of body k (global).
    pub fn omega(&self, k: usize) -> Vector3<f64> {
        self.body_state(k).a * self.omega_local(k)
    }

    /// Pose and velocity of body k as the constraints see it (A computed here).
    pub fn body_state(&self, k: usize) -> BodyState {
        BodyState::at(self.r(k), self.p(k)).with_v(self.r_dot(k), self.omega_local(k))
    }

    /// Sets the pose of body k (p normalized).
    pub fn set_pose(&mut self, k: usize, r: Vector3<f64>, p: Vector4<f64>) {
        let p = p / p.norm();
        self.q[7 * k..7 * k + 3].copy_from_slice(r.as_slice());
        self.q[7 * k + 3..7 * k + 7].copy_from_slice(p.as_slice());
    }

    /// Sets the velocity of body k: ṙ and ω' (body frame).
    pub fn set_velocity(&mut self, k: usize, r_dot: Vector3<f64>, omega_local: Vector3<f64>) {
        self.v[6 * k..6 * k + 3].copy_from_slice(r_dot.as_slice());
        self.v[6 * k + 3..6 * k + 6].copy_from_slice(omega_local.as_slice());
    }

    /// Sets the velocity of body k from ṙ and the global ω.
    pub fn set_velocity_global(&mut self, k: usize, r_dot: Vector3<f64>, omega: Vector3<f64>) {
        let a = self.body_state(k).a;
        self.set_velocity(k, r_dot, a.tr_mul(&omega));
    }

    /// Global position of a body point (body frame `s_local`).
    pub fn point_position(&self, body: BodyId, s_local: &Vector3<f64>) -> Vector3<f64> {
        match body {
            BodyId::Ground => *s_local,
            BodyId::Moving(k) => self.body_state(k).point(s_local),
        }
    }

    /// Global velocity of a body point: ṙ + A (ω' × s').
    pub fn point_velocity(&self, body: BodyId, s_local: &Vector3<f64>) -> Vector3<f64> {
        match body {
            BodyId::Ground => Vector3::zeros(),
            BodyId::Moving(k) => {
                self.r_dot(k) + self.body_state(k).a * self.omega_local(k).cross(s_local)
            }
        }
    }

    /// Fills `out` (one per body) with the body states. No allocation.
    pub fn body_states_into(&self, out: &mut [BodyState]) {
        for (k, b) in out.iter_mut().enumerate() {
            *b = self.body_state(k);
        }
    }
}
