//! The joint-space view of a fully driven mechanism: the mass matrix M(θ), the bias forces
//! h(θ, θ̇) and the Jacobians of body points, in the coordinates θ the drivers prescribe (for a
//! robot read from URDF and driven joint by joint: its joint angles and slides in the drivers'
//! order). Robot codes compute them by recursive algorithms over a tree in joint coordinates
//! (Featherstone 2008 §6.2 composite rigid bodies for M, §5.3 recursive Newton–Euler for h);
//! here they come from the absolute-coordinate model, which also holds for closed loops.
//!
//! # Theory
//!
//! With v = [ṙ_k; ω'_k] (6 per body) and the constraints Φ_v v = ν, a fully driven mechanism's
//! rows are the joints' (ν = 0) and one per driver, whose Φ_v row times v is s_i ċ_i (s_i =
//! ∂Φ/∂c, [`cardan_constraints::Driver::coordinate_slope`]: 1 for a rotation or translation
//! driver). The velocity of every body per unit rate of coordinate i is the column
//!
//! ```text
//! V_i = Φ_v⁻¹ (s_i e_i)            so that  v = Σ_i V_i ċ_i   (Haug 1989 §11.2, the velocity
//!                                            transformation; Nikravesh 1988 §13.2)
//! ```
//!
//! solved with the factorization of the augmented matrix [M Φ_vᵀ; Φ_v 0] the dynamics already
//! holds (right-hand side [0; s_i e_i]: its first block is V_i). The virtual work of the joint
//! reactions vanishes along every V_i (Φ_v^joints V_i = 0), so projecting the Newton–Euler
//! equations M v̇ − h_e = −Φ_vᵀλ onto the V_i gives the equations in θ:
//!
//! ```text
//! M(θ) = Vᵀ M V = Σ_k m_k V_r,kᵀ V_r,k + V_ω,kᵀ J'_k V_ω,k       (M = diag(m_k I, J'_k))
//! h(θ, θ̇) = τ − M(θ) θ̈
//! ```
//!
//! with τ the drivers' efforts at this time (−s_i λ_i, the inverse dynamics') and θ̈ the
//! coordinates' accelerations: f̈_i(t) for a driver written c_i − f_i(t) (or ℓ² − ℓ(t)²). So
//! τ = M(θ) θ̈ + h(θ, θ̇): h holds the Coriolis, centrifugal and gyroscopic terms, gravity and
//! every applied force element with the sign of an effort that balances them (Pinocchio's
//! `rnea` = `crba` · q̈ + `nonLinearEffects`).
//!
//! **A floating base** is driven by a general motion from the ground (a pose driver, rows
//! x_Iᵀ d − f_k(t) and the fixed joint's x_Eᵀ z_J, y_Eᵀ z_J, x_Eᵀ y_J to the prescribed frame
//! E = A_I R(t)). Its six rows are quasi-coordinates: at the solution (E = A_J) their rates are
//! the point's velocity along the ground axes, then ω·y_J, −ω·x_J and −ω·z_J (the body's angular
//! velocity along its marker's axes: u = T v for Pinocchio's free-flyer velocity
//! v = [A_Jᵀ ṙ_P; A_Jᵀ ω], T = diag(A_J, P), P = [0 1 0; −1 0 0; 0 0 −1] row by row, so
//! M_pin = Tᵀ M T and h_pin = Tᵀ (h + M Ṫ v), docs/urdf.md). Their
//! accelerations are f̈_k and α·y_J, −α·x_J, −α·z_J (ω·ẏ_J = ω·(ω × y_J) = 0), α from v̇. A
//! pose driver from a moving body is refused (its rows' rates are not these).
//!
//! A point P at s'_P on body k moves with ṙ_P = ṙ_k + A_k (ω'_k × s'_P) and turns with
//! ω_k = A_k ω'_k, so its Jacobian (6 × n, global axes; Pinocchio's `LOCAL_WORLD_ALIGNED`) has
//! the columns [V_r,k,i + A_k (V_ω,k,i × s'_P); A_k V_ω,k,i].
//!
//! Cost per time: n solves with the factored matrix and O(n² · bodies) products; nothing is
//! allocated after [`Dynamics::request_joint_space`].

use crate::kkt::SchurRefinement;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_constraints::Driver;
use cardan_mechanism::BodyId;
use nalgebra::Vector3;

pub(crate) mod history;
pub(crate) use history::JointSpaceWork;
pub use history::{JointSpaceHistory, JointSpacePoint};

impl Dynamics<'_> {
    /// Asks the next inverse dynamics run to record M(θ), h(θ, θ̇) and the Jacobians of
    /// `points` at every output time ([`crate::DynamicResults::joint_space`]; module docs of
    /// [`crate::joint_space`]). The coordinates are the drivers', in model order.
    ///
    /// # Errors
    /// [`DynamicsError::JointSpace`] without drivers, or with a pose driver from a moving body.
    pub fn request_joint_space(
        &mut self,
        points: Vec<JointSpacePoint>,
    ) -> Result<&mut Self, DynamicsError> {
        let drivers = self.model.drivers();
        if drivers.is_empty() {
            return Err(DynamicsError::JointSpace {
                reason: "the model has no drivers: the joint space is the coordinates the \
                         drivers prescribe (drive each joint)"
                    .into(),
            });
        }
        let from_moving = |d: &&cardan_mechanism::DriverInfo| {
            matches!(d.driver, Driver::Pose(_)) && d.body_i != BodyId::Ground
        };
        if let Some(d) = drivers.iter().find(from_moving) {
            return Err(DynamicsError::JointSpace {
                reason: format!(
                    "driver \"{}\" prescribes a pose relative to a moving body: the joint space \
                     takes a general motion from the ground only (a floating base)",
                    d.name
                ),
            });
        }
        let n = drivers.len();
        self.joint_space = Some(JointSpaceWork::new(
            drivers.iter().map(|d| d.name.clone()).collect(),
            points,
            n * 6 * self.model.num_bodies(),
        ));
        Ok(self)
    }

    /// Appends M(θ), h(θ, θ̇) and the points' Jacobians at the synced bodies and time `t` to
    /// `out` (module docs), with the multipliers `lambda` (one per model row) and accelerations
    /// `vdot` the equations of motion gave there (the KKT layout prepared). No allocation when
    /// `out` has room.
    ///
    /// # Errors
    /// [`DynamicsError::JointSpace`] when a driver's row was dropped as redundant (its
    /// coordinate is not independent); a singular matrix.
    pub(crate) fn record_joint_space(
        &mut self,
        t: f64,
        (lambda, vdot): (&[f64], &[f64]),
        out: &mut JointSpaceHistory,
    ) -> Result<(), DynamicsError> {
        let Some(mut work) = self.joint_space.take() else {
            return Ok(());
        };
        let r = self.joint_space_into(t, (lambda, vdot), &mut work, out);
        self.joint_space = Some(work);
        r
    }

    fn joint_space_into(
        &mut self,
        t: f64,
        (lambda, vdot): (&[f64], &[f64]),
        work: &mut JointSpaceWork,
        out: &mut JointSpaceHistory,
    ) -> Result<(), DynamicsError> {
        let model = self.model;
        let kkt = self
            .kkt
            .as_mut()
            .expect("prepared by the equations of motion");
        let n6 = kkt.n;
        // The plain augmented matrix at these bodies: the efforts' solve may have held stops or
        // joint friction on top of it. Its factors are reused when nothing changed.
        kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, t);
        kkt.set_mass(&self.mass, &self.inertia);
        if let Err(e) = kkt.factor() {
            return Err(self.solver_error(t, e));
        }
        let kkt = self.kkt.as_mut().expect("prepared");
        // V_i = Φ_v⁻¹ (s_i e_i), the first block of [M Φ_vᵀ; Φ_v 0]⁻¹ [0; s_i e_i].
        for (i, d) in model.drivers().iter().enumerate() {
            let a = kkt.active_of[d.rows.start];
            if a == usize::MAX {
                return Err(DynamicsError::JointSpace {
                    reason: format!(
                        "driver \"{}\" was dropped as redundant at t = {t}: its coordinate is \
                         not independent of the others, so the joint space is not defined",
                        d.name
                    ),
                });
            }
            kkt.rhs.fill(0.0);
            kkt.rhs[n6 + a] = d.driver.coordinate_slope(t);
            kkt.solve(SchurRefinement::ONE_SHOT)
                .map_err(|e| DynamicsError::JointSpace {
                    reason: format!("t = {t}: the velocity transformation: {e}"),
                })?;
            work.v_cols[i * n6..(i + 1) * n6].copy_from_slice(&kkt.sol[..n6]);
        }
        let at = out.mass.len();
        self.push_mass(&work.v_cols, out);
        // h = τ − M θ̈, θ̈ evaluated once per coordinate.
        for (acc, d) in work.theta_ddot.iter_mut().zip(model.drivers()) {
            *acc = self.coordinate_acceleration(d, vdot, t);
        }
        let n = work.theta_ddot.len();
        for (i, d) in model.drivers().iter().enumerate() {
            let tau = -lambda[d.rows.start] * d.driver.coordinate_slope(t);
            let row = &out.mass[at + i * n..at + (i + 1) * n];
            let m_theta: f64 = row.iter().zip(&work.theta_ddot).map(|(m, a)| m * a).sum();
            out.bias.push(tau - m_theta);
        }
        self.push_jacobians(&work.v_cols, &work.names.points, out);
        Ok(())
    }

    /// θ̈ of driver `d`'s coordinate (module docs): f̈(t), or a floating base's angular rows
    /// from the body's angular acceleration in `vdot`.
    fn coordinate_acceleration(
        &self,
        d: &cardan_mechanism::DriverInfo,
        vdot: &[f64],
        t: f64,
    ) -> f64 {
        let Driver::Pose(p) = &d.driver else {
            return d.driver.function().eval(t).2;
        };
        let BodyId::Moving(k) = d.body_j else {
            return 0.0;
        };
        if p.row < 3 {
            return d.driver.function().eval(t).2;
        }
        let a = &self.bodies[k].a;
        let alpha = a * Vector3::new(vdot[6 * k + 3], vdot[6 * k + 4], vdot[6 * k + 5]);
        let m = &p.marker_j;
        match p.row {
            3 => alpha.dot(&(a * m.y())),
            4 => -alpha.dot(&(a * m.x())),
            _ => -alpha.dot(&(a * m.z())),
        }
    }

    /// M(θ) = Vᵀ diag(m_k I, J'_k) V, appended row-major (the upper triangle computed, the
    /// lower one its mirror).
    fn push_mass(&self, v: &[f64], out: &mut JointSpaceHistory) {
        let n6 = 6 * self.bodies.len();
        let n = v.len() / n6.max(1);
        let at = out.mass.len();
        out.mass.resize(at + n * n, 0.0);
        for i in 0..n {
            let vi = &v[i * n6..(i + 1) * n6];
            for j in i..n {
                let vj = &v[j * n6..(j + 1) * n6];
                let mut s = 0.0;
                for (k, (m, inertia)) in self.mass.iter().zip(&self.inertia).enumerate() {
                    let (bi, bj) = (&vi[6 * k..6 * k + 6], &vj[6 * k..6 * k + 6]);
                    s += m * (bi[0] * bj[0] + bi[1] * bj[1] + bi[2] * bj[2]);
                    let wj = inertia * Vector3::new(bj[3], bj[4], bj[5]);
                    s += bi[3] * wj[0] + bi[4] * wj[1] + bi[5] * wj[2];
                }
                out.mass[at + i * n + j] = s;
                out.mass[at + j * n + i] = s;
            }
        }
    }

    /// Each requested point's Jacobian [V_r + A (V_ω × s'); A V_ω], appended row-major.
    fn push_jacobians(&self, v: &[f64], points: &[JointSpacePoint], out: &mut JointSpaceHistory) {
        let n6 = 6 * self.bodies.len();
        let n = v.len() / n6.max(1);
        for p in points {
            let at = out.jacobians.len();
            out.jacobians.resize(at + 6 * n, 0.0);
            let BodyId::Moving(k) = p.body else { continue };
            let a = &self.bodies[k].a;
            for i in 0..n {
                let b = &v[i * n6 + 6 * k..i * n6 + 6 * k + 6];
                let w = Vector3::new(b[3], b[4], b[5]);
                let lin = Vector3::new(b[0], b[1], b[2]) + a * w.cross(&p.local);
                let ang = a * w;
                for c in 0..3 {
                    out.jacobians[at + c * n + i] = lin[c];
                    out.jacobians[at + (3 + c) * n + i] = ang[c];
                }
            }
        }
    }
}
