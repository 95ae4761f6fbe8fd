//! Linearization about a moving state (a state of a dynamic run at a chosen time):
//! [`Dynamics::linearize_moving`].
//!
//! ## Theory
//! About a state (q₀, v₀) at t₀ that is not an equilibrium (v₀ ≠ 0, v̇₀ ≠ 0), compare a
//! neighbouring consistent state (q₀ ⊕ δ, v₀ + δv) at the same time. The equations of motion
//! M v̇ + Φ_vᵀλ = h(q, v, t), to first order, are
//!
//! ```text
//! M δv̇ + Φ_vᵀ δλ + K_t δ + C_t δv = 0,    K_t = ∂(Φ_vᵀλ₀ − h)/∂δ,    C_t = −∂h/∂v
//! ```
//!
//! with λ₀ the multipliers of the dynamics at that instant (they carry the inertial loads: the
//! geometric stiffness of the constraint forces of a moving mechanism), h with the quadratic
//! velocity term −ω̃'J'ω' (its derivative in C_t is the gyroscopic matrix) and K_t at fixed v
//! (velocity-dependent forces change with the pose too). Position and velocity constraints,
//! to first order (ν may depend on q), restrict the perturbation to
//!
//! ```text
//! Φ_v δ = 0,      Φ_v δv + Ψ δ = 0,      Ψ = ∂(Φ_v v₀ − ν)/∂δ
//! ```
//!
//! With N a basis of the null space of Φ_v and P = M_r⁻¹NᵀM its M-orthogonal left inverse
//! (M_r = NᵀMN, P N = I), independent coordinates z = P δ and independent velocities
//! w = P δv give δ = N z and δv = N w − X z, X = M⁻¹Φ_vᵀ(Φ_vM⁻¹Φ_vᵀ)⁻¹ΨN (the M-orthogonal
//! velocity correction, P X = 0). Premultiplying by Nᵀ removes δλ, and NᵀM δv̇ = M_r P δv̇
//! (the part of δv̇ outside the null space is M-orthogonal to it; that is where the
//! perturbation of γ# goes, so it does not appear):
//!
//! ```text
//! M_r ẇ + Ĉ w + K̂ z = 0,      Ĉ = NᵀC_tN,      K̂ = NᵀK_tN − NᵀC_t X
//! ```
//!
//! (all in global translation components: the 6-coordinate form of the crate).
//!
//! **The body-frame chart.** The perturbation is measured in the frames of the moving
//! reference bodies, as joint coordinates would measure it: per body δ' = [A₀ᵀ(r − r₀);
//! δπ'] and δv' = v' − v'₀ with v' = [Aᵀṙ; ω'] (T = diag(A₀, I) per body maps body to global
//! components; M commutes with T, so z = P δ = (P T) δ' is the same coordinate). Then, per body,
//!
//! ```text
//! δv' = Tᵀ(δv + V̂ δ),                       V̂ = [0, A₀ṽ'_r; 0, 0]
//! δv̇' = Tᵀ(δv̇ + Ê δ + F̂ δv + F̂ V̂ δ),       Ê = [0, A₀ã'_r; 0, 0],  F̂ = [−ω̃, A₀ṽ'_r; 0, 0]
//! δ̇'  = δv' − W' δ',  W' = [ω̃'₀, ṽ'_r; 0, ω̃'₀]:  ż = w' − G z,  G = P T W' Tᵀ N
//! ```
//!
//! (v'_r = A₀ᵀṙ₀, a'_r = A₀ᵀr̈₀, ω = A₀ω'₀; from v̇'_r = Aᵀr̈ − ω' × v'_r and
//! δṙ' = d/dt A₀ᵀ(r − r₀)). With w' = P T δv' = w + H z, H = P V̂ N:
//!
//! ```text
//! M_r ẇ' + C' w' + K' z = 0,    C' = Ĉ − NᵀM F̂ N,
//!                               K' = K̂ − Ĉ H − NᵀM (Ê N − F̂ N H − F̂ X + F̂ V̂ N)
//! ```
//!
//! This chart makes a pendulum swinging at θ̇ linearize to J_O z̈ = −m g l_c sin θ z, as its
//! joint angle does; measured in global components the translation increments would add a
//! frame term m l_c² θ̇² (the centripetal acceleration seen along a fixed direction). Freezing
//! the matrices at t₀ (the linearization of an operating point, as Adams/Linear or Exudyn's
//! ComputeLinearizedSystem give it; the rates of N, P and G along the motion are not included)
//! and writing w' = ż + G z gives the second-order form that [`Linearization`] holds:
//!
//! ```text
//! M_r z̈ + C_r ż + K_r z = 0,      C_r = C' + M_r G,      K_r = K' + C' G
//! ```
//!
//! About an equilibrium (v₀ = 0, v̇₀ = 0) every frame term vanishes and these are the matrices
//! of [`Dynamics::linearize`]. C' = C_r − M_r G and K' = K_r − C' G are recovered from
//! [`Linearization::transport`] (G); they are what central differences of the body-frame
//! accelerations of the nonlinear model check (tests/linearization.rs). Frozen-time modes about
//! a moving state depend on the frame the perturbation is measured in (a spinning rotor's
//! whirl: body-frame here, not the stationary frame of a Campbell diagram).

use crate::kkt::{eval_rows, Rhs};
use crate::modal::Linearization;
use crate::state::State;
use crate::system::Dynamics;
use crate::tangent::{null_space, Load};
use crate::DynamicsError;
use cardan_mechanism::apply_rotation_step;
use nalgebra::{DMatrix, DVector, Vector3};

/// Relative finite-difference step of Ψ (times L for translations; rad).
const FD_STEP: f64 = 1e-6;

impl Dynamics<'_> {
    /// The linearized equations about the consistent state `state` (positions and velocities
    /// satisfying the constraints; a state of a dynamic run), module docs. About a state at
    /// rest in equilibrium it equals [`Dynamics::linearize`].
    ///
    /// # Errors
    /// [`DynamicsError::Singular`] at a singular configuration, [`DynamicsError::NonFinite`]
    /// for non-finite tangents or a singular reduced mass matrix.
    pub fn linearize_moving(&mut self, state: &State) -> Result<Linearization, DynamicsError> {
        self.refuse_curves()?;
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        let n = state.v.len();
        let mut vdot = vec![0.0; n];
        let mut lambda = vec![0.0; self.model.num_equations()];
        self.accelerations(state, &mut vdot, &mut lambda)?;
        let active = self
            .kkt
            .as_ref()
            .map(|k| k.active.clone())
            .unwrap_or_default();
        let full_stiffness = self.stiffness_tangent(state, &lambda, Load::Dynamic);
        let full_damping = self.damping_tangent(state, Load::Dynamic);
        let psi = self.velocity_constraint_tangent(state, &active);
        self.sync(state);
        let j = self.phi_v_dense(state.t, &active);
        let model = self.model;
        let (basis, _) = null_space(
            &j,
            model.equation_scales(),
            &active,
            model.characteristic_length(),
        );
        let non_finite = |what| DynamicsError::NonFinite {
            time: state.t,
            what,
        };
        if full_stiffness
            .iter()
            .chain(full_damping.iter())
            .chain(psi.iter())
            .any(|v| !v.is_finite())
        {
            return Err(non_finite("the tangent stiffness or damping"));
        }
        let m = self.mass_matrix();
        let m_inv = m
            .clone()
            .cholesky()
            .ok_or(non_finite("the mass matrix"))?
            .inverse();
        let s = &j * &m_inv * j.transpose();
        let y = s
            .lu()
            .solve(&(&psi * &basis))
            .ok_or(non_finite("the constraint Jacobian"))?;
        let x = &m_inv * j.transpose() * y;
        let nt = basis.transpose();
        let mass = &nt * &m * &basis;
        let c_hat = &nt * &full_damping * &basis;
        let k_hat = &nt * &full_stiffness * &basis - &nt * &full_damping * &x;
        let p = mass
            .clone()
            .cholesky()
            .ok_or(non_finite("the reduced mass matrix"))?
            .solve(&(&nt * &m));
        let f = frame_terms(state, &vdot);
        let h = &p * &f.v * &basis;
        let ntm = &nt * &m;
        let c_body = &c_hat - &ntm * &f.f * &basis;
        let k_body = &k_hat
            - &c_hat * &h
            - &ntm * (&f.e * &basis - &f.f * &basis * &h - &f.f * &x + &f.f * &f.v * &basis);
        let g = &p * &f.w * &basis;
        Ok(Linearization {
            damping: &c_body + &mass * &g,
            stiffness: &k_body + &c_body * &g,
            mass,
            transport: g,
            basis,
            full_stiffness,
            full_damping,
        })
    }

    /// Ψ = ∂(Φ_v v − ν)/∂δ on the rows `active` at fixed v, by central differences
    /// (m_a × n).
    fn velocity_constraint_tangent(&mut self, state: &State, active: &[usize]) -> DMatrix<f64> {
        let n = state.v.len();
        let l = self.model.characteristic_length();
        let v = DVector::from_column_slice(&state.v);
        let mut psi = DMatrix::zeros(active.len(), n);
        let mut p = state.clone();
        let mut dq = vec![0.0; n];
        let mut nu = vec![0.0; self.model.num_equations()];
        for c in 0..n {
            let e = if c % 6 < 3 { FD_STEP * l } else { FD_STEP };
            let mut col = [DVector::zeros(0), DVector::zeros(0)];
            for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                p.q.copy_from_slice(&state.q);
                dq.fill(0.0);
                dq[c] = sign * e;
                apply_rotation_step(&mut p.q, &dq);
                self.sync(&p);
                eval_rows(
                    self.model,
                    &self.elements,
                    &self.bodies,
                    &self.turns,
                    &self.curves,
                    state.t,
                    Rhs::Nu,
                    &mut nu,
                );
                let mut r = self.phi_v_dense(state.t, active) * &v;
                for (a, &row) in active.iter().enumerate() {
                    r[a] -= nu[row];
                }
                col[i] = r;
            }
            psi.set_column(c, &((&col[0] - &col[1]) / (2.0 * e)));
        }
        self.sync(state);
        psi
    }
}

/// The frame terms of the body-frame chart at a state (module docs), n × n each, acting on the
/// global-translation increments δ.
struct FrameTerms {
    /// V̂: δv' = Tᵀ(δv + V̂ δ), the velocity a rotation increment adds in body components.
    v: DMatrix<f64>,
    /// Ê: the change of the body-frame acceleration components with the rotation increment.
    e: DMatrix<f64>,
    /// F̂: the change of −ω'×v'_r with the velocities.
    f: DMatrix<f64>,
    /// Ŵ: δ̇' = Tᵀ(δv' … − Ŵ δ), the rates of the increments relative to the moving frames.
    w: DMatrix<f64>,
}

/// [`FrameTerms`] at `state` with the accelerations `vdot` (per body blocks, T = diag(A, I)).
fn frame_terms(state: &State, vdot: &[f64]) -> FrameTerms {
    let n = state.v.len();
    let z = || DMatrix::<f64>::zeros(n, n);
    let (mut v, mut e, mut f, mut w) = (z(), z(), z(), z());
    for k in 0..n / 6 {
        let bs = state.body_state(k);
        let a = bs.a;
        let om = state.omega_local(k);
        let vr = a.transpose() * state.r_dot(k);
        let ar = a.transpose() * Vector3::from_column_slice(&vdot[6 * k..6 * k + 3]);
        let (r, pi) = (6 * k, 6 * k + 3);
        let av = a * vr.cross_matrix();
        v.view_mut((r, pi), (3, 3)).copy_from(&av);
        e.view_mut((r, pi), (3, 3))
            .copy_from(&(a * ar.cross_matrix()));
        f.view_mut((r, r), (3, 3))
            .copy_from(&(-(a * om.cross_matrix() * a.transpose())));
        f.view_mut((r, pi), (3, 3)).copy_from(&av);
        w.view_mut((r, r), (3, 3))
            .copy_from(&(a * om.cross_matrix() * a.transpose()));
        w.view_mut((r, pi), (3, 3)).copy_from(&av);
        w.view_mut((pi, pi), (3, 3)).copy_from(&om.cross_matrix());
    }
    FrameTerms { v, e, f, w }
}
