//! Linearization about a static equilibrium and modal analysis: [`Dynamics::linearize`],
//! [`Dynamics::modes`], [`Dynamics::modal`].
//!
//! ## Theory
//! About an equilibrium (q₀, λ₀) (see [`crate::statics`]) let q = q₀ ⊕ δ, λ = λ₀ + δλ. The
//! equations of motion M v̇ + Φ_vᵀλ = h(q, v) and Φ(q) = 0, to first order, are
//!
//! ```text
//! M δv̇ + C_t δv + K_t δ + Φ_vᵀ δλ = 0,      Φ_v δ = 0
//! ```
//!
//! with K_t = ∂(Φ_vᵀλ₀ − h)/∂δ (the force elements' stiffness and the geometric stiffness of the
//! constraint forces, the λ-dependent term) and C_t = −∂h/∂v (dampers). With N a basis of the
//! null space of Φ_v, δ = N z, and premultiplying by Nᵀ (which removes Φ_vᵀδλ):
//!
//! ```text
//! M_r z̈ + C_r ż + K_r z = 0,      M_r = NᵀMN,  C_r = NᵀC_tN,  K_r = NᵀK_tN
//! ```
//!
//! (Géradin & Cardona 2001 §6.7; Exudyn's ComputeODE2Eigenvalues with constraints uses the same
//! null-space projection). Mode i of the undamped system solves K_r x = ω² M_r x; the natural
//! frequency is f = ω / 2π (Hz). Zero eigenvalues are rigid-body modes (free directions),
//! negative ones unstable (divergence) modes; both are reported, not errors.
//!
//! With damping (C_r ≠ 0) the first-order form ẏ = A y, y = [z; ż],
//! A = [0, I; −M_r⁻¹K_r, −M_r⁻¹C_r], gives eigenvalues s = −ζω_n ± iω_d: ω_n = |s| (natural
//! frequency), ζ = −Re s / |s| (damping ratio), ω_d = Im s (damped frequency). A real negative
//! s is an overdamped (non-oscillating) mode, reported with ζ = 1 and f = |s| / 2π; the rigid
//! modes are those of the undamped problem (zero stiffness) and their real roots are not
//! repeated. The shape of a damped mode is the position part of its complex eigenvector (by
//! inverse iteration), rotated in phase so that its largest component is real, real part.
//!
//! Shapes are given per body as a translation δr and a rotation δθ = A δπ' (both global),
//! scaled so that the largest of |δr| and L |δθ| over the bodies is 1, its sign chosen so
//! that its largest component is positive.

use crate::state::State;
use crate::statics::{
    generalized_symmetric, soft_threshold, Equilibrium, StaticOptions, StaticResults,
};
use crate::system::Dynamics;
use crate::tangent::Load;
use crate::DynamicsError;
use nalgebra::{Cholesky, Complex, DMatrix, DVector, Dyn, Vector3};

/// The linearized equations M_r z̈ + C_r ż + K_r z = 0 about an equilibrium (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Linearization {
    /// N: a basis of the null space of Φ_v, n × d (n = 6 nb increments δ = [δr; δπ'] per
    /// body, d the degrees of freedom); δ = N z.
    pub basis: DMatrix<f64>,
    /// M_r = NᵀMN (d × d).
    pub mass: DMatrix<f64>,
    /// C_r = NᵀC_tN (d × d).
    pub damping: DMatrix<f64>,
    /// K_r = NᵀK_tN (d × d).
    pub stiffness: DMatrix<f64>,
    /// K_t (n × n): ∂(Φ_vᵀλ − h)/∂δ, the geometric stiffness included.
    pub full_stiffness: DMatrix<f64>,
    /// C_t = −∂h/∂v (n × n).
    pub full_damping: DMatrix<f64>,
    /// G = P W N (d × d): the rates of the rotation increments relative to a moving reference,
    /// ż = w − G z with w = P δv ([`crate::moving`]); zero about an equilibrium.
    pub transport: DMatrix<f64>,
}

impl Linearization {
    /// Degrees of freedom d.
    pub fn dof(&self) -> usize {
        self.basis.ncols()
    }

    /// The Cholesky factor of the reduced mass matrix M_r (symmetric positive definite for a
    /// mechanism whose every free direction carries mass); an error at time `t` otherwise.
    pub(crate) fn mass_cholesky(&self, t: f64) -> Result<Cholesky<f64, Dyn>, DynamicsError> {
        self.mass
            .clone()
            .cholesky()
            .ok_or(DynamicsError::NonFinite {
                time: t,
                what: "the reduced mass matrix",
            })
    }

    /// Whether the force elements damp: max |C_r| > 1e-12 max(|K_r|, |M_r|).
    pub fn is_damped(&self) -> bool {
        let big = self.stiffness.amax().max(self.mass.amax());
        self.damping.amax() > 1e-12 * big
    }

    /// Whether K_r is not symmetric (max |K_r − K_rᵀ| > 1e-9 max |K_r|): a linearization about
    /// a moving state, whose modes come from the first-order form only.
    pub fn is_general(&self) -> bool {
        let k = &self.stiffness;
        (k - k.transpose()).amax() > 1e-9 * k.amax() || self.transport.amax() > 0.0
    }
}

/// What kind of mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeKind {
    /// An oscillating (or, damped, decaying oscillating) mode.
    Elastic,
    /// A zero-frequency mode: a free direction without stiffness.
    Rigid,
    /// A negative stiffness: the equilibrium is unstable along it.
    Unstable,
    /// A real negative eigenvalue of the damped system: decays without oscillating.
    Overdamped,
}

impl ModeKind {
    /// `elastic`, `rigid`, `unstable` or `overdamped`.
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::Elastic => "elastic",
            ModeKind::Rigid => "rigid",
            ModeKind::Unstable => "unstable",
            ModeKind::Overdamped => "overdamped",
        }
    }
}

/// One body's motion in a mode shape (global components).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyShape {
    /// δr of the centre of mass.
    pub translation: Vector3<f64>,
    /// δθ = A δπ' (rad).
    pub rotation: Vector3<f64>,
}

/// One mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// Kind.
    pub kind: ModeKind,
    /// Natural frequency ω_n / 2π (Hz); 0 for a rigid mode; for an unstable mode √(−ω²)/2π,
    /// the divergence rate over 2π.
    pub frequency: f64,
    /// Damped frequency ω_d / 2π (Hz); equal to `frequency` without damping.
    pub damped_frequency: f64,
    /// Damping ratio ζ (0 without damping; 1 for an overdamped mode).
    pub damping_ratio: f64,
    /// The eigenvalue s = [re, im] (1/s) of the first-order form ẏ = A y: −ζω_n + iω_d for an
    /// elastic mode (iω without damping), 0 for a rigid mode, √(−ω²) (real, positive) for an
    /// unstable one, the real negative root for an overdamped one.
    pub eigenvalue: [f64; 2],
    /// The shape, one entry per moving body (module docs for the scaling).
    pub shape: Vec<BodyShape>,
    /// The joint coordinate that moves most in the shape (`joint "pin" angle`).
    pub direction: String,
}

/// Options of a modal analysis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalOptions {
    /// The static analysis that finds the equilibrium first.
    pub statics: StaticOptions,
}

/// The results of a modal analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalResults {
    /// The equilibrium (one output time).
    pub equilibrium: StaticResults,
    /// The linearized equations about it.
    pub linearization: Linearization,
    /// The modes, by increasing frequency (rigid first, unstable before them).
    pub modes: Vec<Mode>,
}

impl Dynamics<'_> {
    /// Modal analysis: the static equilibrium ([`Dynamics::statics`]), the linearization about
    /// it and its modes.
    ///
    /// # Errors
    /// As [`Dynamics::statics`].
    pub fn modal(&mut self, options: &ModalOptions) -> Result<ModalResults, DynamicsError> {
        let equilibrium = self.statics(&options.statics)?;
        let eq = &equilibrium.equilibria[0];
        let linearization = self.linearize(eq)?;
        let modes = self.modes(&eq.state, &linearization)?;
        Ok(ModalResults {
            equilibrium,
            linearization,
            modes,
        })
    }

    /// The linearized equations about the equilibrium `eq` (found by this [`Dynamics`], whose
    /// independent rows it uses).
    ///
    /// # Errors
    /// [`DynamicsError::NonFinite`] for non-finite tangents.
    pub fn linearize(&mut self, eq: &Equilibrium) -> Result<Linearization, DynamicsError> {
        self.linearize_released(eq, &[])
    }

    /// As [`Dynamics::linearize`] with the equations of the drivers `released` left out: their
    /// coordinates become free (d grows by one per driver), held by the efforts at the
    /// equilibrium, whose changes are then inputs ([`crate::Input::Driver`]). K_t keeps the
    /// geometric stiffness of the released rows (the effort stays applied along the coordinate).
    ///
    /// # Errors
    /// As [`Dynamics::linearize`]; [`DynamicsError::BadForce`] naming an unknown driver, one
    /// of more than one equation (a pose driver) or one whose equation was dropped as
    /// redundant.
    pub fn linearize_released(
        &mut self,
        eq: &Equilibrium,
        released: &[String],
    ) -> Result<Linearization, DynamicsError> {
        let state = &eq.state;
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        let mut active = self
            .kkt
            .as_ref()
            .map(|k| k.active.clone())
            .unwrap_or_default();
        for name in released {
            let row = self.driver_row(name)?;
            let Some(i) = active.iter().position(|&r| r == row) else {
                return Err(DynamicsError::BadForce {
                    key: None,
                    force: name.clone(),
                    reason: format!("the equation of driver \"{name}\" was dropped as redundant"),
                });
            };
            active.remove(i);
        }
        let full_stiffness = self.static_tangent(state, &eq.lambda, 1.0);
        let full_damping = self.damping_tangent(state, Load::Static(1.0));
        let basis = self.constraint_null_space(state, &active);
        if full_stiffness
            .iter()
            .chain(full_damping.iter())
            .any(|v| !v.is_finite())
        {
            return Err(DynamicsError::NonFinite {
                time: state.t,
                what: "the tangent stiffness or damping",
            });
        }
        let m = self.mass_matrix();
        let bt = basis.transpose();
        let d = basis.ncols();
        Ok(Linearization {
            transport: DMatrix::zeros(d, d),
            mass: &bt * m * &basis,
            damping: &bt * &full_damping * &basis,
            stiffness: &bt * &full_stiffness * &basis,
            basis,
            full_stiffness,
            full_damping,
        })
    }

    /// The model row of the one-equation driver `name`.
    pub(crate) fn driver_row(&self, name: &str) -> Result<usize, DynamicsError> {
        let bad = |reason: String| DynamicsError::BadForce {
            key: None,
            force: name.to_string(),
            reason,
        };
        let dr = self
            .model
            .drivers()
            .iter()
            .find(|d| d.name == name)
            .ok_or_else(|| bad(format!("unknown driver \"{name}\"")))?;
        if dr.rows.len() != 1 {
            return Err(bad(format!(
                "driver \"{name}\" has {} equations; only one-coordinate drivers can be inputs",
                dr.rows.len()
            )));
        }
        Ok(dr.rows.start)
    }

    /// The modes of the linearization `lin` about the equilibrium pose `state` (module docs).
    ///
    /// # Errors
    /// [`DynamicsError::NonFinite`] when the reduced mass matrix is not positive definite.
    pub fn modes(
        &mut self,
        state: &State,
        lin: &Linearization,
    ) -> Result<Vec<Mode>, DynamicsError> {
        let bad = DynamicsError::NonFinite {
            time: state.t,
            what: "the reduced mass matrix",
        };
        if lin.is_general() {
            return self.general_modes(state, lin);
        }
        let (values, x) = generalized_symmetric(&lin.stiffness, &lin.mass).ok_or(bad)?;
        let thr = soft_threshold(&values);
        let two_pi = 2.0 * std::f64::consts::PI;
        let mut modes = Vec::new();
        let damped = lin.is_damped();
        for (i, &w2) in values.iter().enumerate() {
            let kind = if w2 < -thr {
                ModeKind::Unstable
            } else if w2 <= thr {
                ModeKind::Rigid
            } else {
                ModeKind::Elastic
            };
            if damped && kind == ModeKind::Elastic {
                continue;
            }
            let f = if kind == ModeKind::Rigid {
                0.0
            } else {
                w2.abs().sqrt() / two_pi
            };
            let delta = &lin.basis * x.column(i);
            let s = match kind {
                ModeKind::Elastic => [0.0, w2.sqrt()],
                ModeKind::Unstable => [(-w2).sqrt(), 0.0],
                _ => [0.0, 0.0],
            };
            modes.push(self.mode(state, kind, f, f, 0.0, s, delta.as_slice()));
        }
        if damped {
            modes.extend(self.damped_modes(state, lin, thr)?);
        }
        sort_modes(&mut modes);
        Ok(modes)
    }

    /// The modes of a linearization about a moving state (K_r not symmetric, gyroscopic C_r):
    /// all from the first-order form; the zero roots (two per free direction without
    /// stiffness) are reported as rigid modes, their shapes the right singular vectors of K_r
    /// with the smallest singular values.
    fn general_modes(
        &mut self,
        state: &State,
        lin: &Linearization,
    ) -> Result<Vec<Mode>, DynamicsError> {
        let chol = lin.mass_cholesky(state.t)?;
        let mk = chol.solve(&lin.stiffness);
        let mags: Vec<f64> = mk.complex_eigenvalues().iter().map(|s| s.norm()).collect();
        let thr = soft_threshold(&mags);
        let mut modes = self.damped_modes(state, lin, thr)?;
        let found: usize = modes
            .iter()
            .map(|m| if m.kind == ModeKind::Elastic { 2 } else { 1 })
            .sum();
        let rigid = (2 * lin.dof()).saturating_sub(found).div_ceil(2);
        if rigid > 0 {
            let svd = lin.stiffness.clone().svd(false, true);
            let v_t = svd.v_t.expect("requested");
            let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
            order.sort_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]));
            for &i in order.iter().take(rigid) {
                let z = v_t.row(i).transpose();
                let delta = &lin.basis * z;
                modes.push(self.mode(
                    state,
                    ModeKind::Rigid,
                    0.0,
                    0.0,
                    0.0,
                    [0.0, 0.0],
                    delta.as_slice(),
                ));
            }
        }
        sort_modes(&mut modes);
        Ok(modes)
    }

    /// The oscillating and overdamped modes of the damped first-order form.
    fn damped_modes(
        &mut self,
        state: &State,
        lin: &Linearization,
        thr: f64,
    ) -> Result<Vec<Mode>, DynamicsError> {
        let d = lin.dof();
        let two_pi = 2.0 * std::f64::consts::PI;
        let chol = lin.mass_cholesky(state.t)?;
        let mk = chol.solve(&lin.stiffness);
        let mc = chol.solve(&lin.damping);
        let mut a = DMatrix::zeros(2 * d, 2 * d);
        for i in 0..d {
            a[(i, d + i)] = 1.0;
        }
        a.view_mut((d, 0), (d, d)).copy_from(&(-mk));
        a.view_mut((d, d), (d, d)).copy_from(&(-mc));
        let eig = a.clone().complex_eigenvalues();
        let zero = thr.sqrt();
        let mut modes = Vec::new();
        for s in eig.iter() {
            let mag = s.norm();
            if mag <= zero || s.im < -1e-12 * mag {
                continue;
            }
            let oscillating = s.im > 1e-12 * mag;
            let (kind, f, fd, zeta) = if oscillating {
                (ModeKind::Elastic, mag / two_pi, s.im / two_pi, -s.re / mag)
            } else if s.re > 0.0 {
                (ModeKind::Unstable, mag / two_pi, 0.0, -1.0)
            } else {
                (ModeKind::Overdamped, mag / two_pi, 0.0, 1.0)
            };
            let y = inverse_iteration(&a, *s);
            let z = y.rows(0, d).into_owned();
            let delta = real_shape(&lin.basis, &z);
            modes.push(self.mode(state, kind, f, fd, zeta, [s.re, s.im], delta.as_slice()));
        }
        Ok(modes)
    }

    /// A [`Mode`] from its numbers and its direction δ (n).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn mode(
        &mut self,
        state: &State,
        kind: ModeKind,
        frequency: f64,
        damped_frequency: f64,
        damping_ratio: f64,
        eigenvalue: [f64; 2],
        delta: &[f64],
    ) -> Mode {
        let l = self.model.characteristic_length();
        let nb = delta.len() / 6;
        let mut shape: Vec<BodyShape> = (0..nb)
            .map(|k| {
                let a = state.body_state(k).a;
                BodyShape {
                    translation: Vector3::from_column_slice(&delta[6 * k..6 * k + 3]),
                    rotation: a * Vector3::from_column_slice(&delta[6 * k + 3..6 * k + 6]),
                }
            })
            .collect();
        // Largest component (rotations weighted by L) scaled to +1.
        let mut big = 0.0f64;
        let mut signed = 1.0;
        for b in &shape {
            for (v, w) in b
                .translation
                .iter()
                .map(|v| (*v, 1.0))
                .chain(b.rotation.iter().map(|v| (*v, l)))
            {
                if (v * w).abs() > big.abs() {
                    big = v * w;
                    signed = big.signum();
                }
            }
        }
        if big != 0.0 {
            let s = signed / big.abs();
            for b in &mut shape {
                b.translation *= s;
                b.rotation *= s;
            }
        }
        let direction = self.direction_name(state, delta);
        Mode {
            kind,
            frequency,
            damped_frequency,
            damping_ratio,
            eigenvalue,
            shape,
            direction,
        }
    }
}

/// Sorts modes: unstable first, then rigid, then by increasing frequency.
fn sort_modes(modes: &mut [Mode]) {
    modes.sort_by(|a, b| {
        let key = |m: &Mode| match m.kind {
            ModeKind::Unstable => (0, m.frequency),
            ModeKind::Rigid => (1, 0.0),
            _ => (2, m.frequency),
        };
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
    });
}

/// An eigenvector of `a` for the eigenvalue `s` by inverse iteration with a slightly shifted
/// complex LU (three iterations from a vector of ones).
fn inverse_iteration(a: &DMatrix<f64>, s: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let shift = s + Complex::new(1e-10, 1e-10) * (1.0 + s.norm());
    let mut b: DMatrix<Complex<f64>> = a.map(|v| Complex::new(v, 0.0));
    for i in 0..n {
        b[(i, i)] -= shift;
    }
    let lu = b.lu();
    let mut x: DVector<Complex<f64>> =
        DVector::from_fn(n, |i, _| Complex::new(1.0 + 0.1 * i as f64, 0.0));
    for _ in 0..3 {
        if let Some(y) = lu.solve(&x) {
            let norm = y.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
            if norm > 0.0 && norm.is_finite() {
                x = y / Complex::new(norm, 0.0);
            }
        }
    }
    x
}

/// δ = N z for a complex z, rotated in phase so that its largest component is real; the real
/// part.
fn real_shape(basis: &DMatrix<f64>, z: &DVector<Complex<f64>>) -> DVector<f64> {
    let bc: DMatrix<Complex<f64>> = basis.map(|v| Complex::new(v, 0.0));
    let delta = bc * z;
    let big = delta
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap_or(Complex::new(1.0, 0.0));
    let rot = if big.norm() > 0.0 {
        big.conj() / big.norm()
    } else {
        Complex::new(1.0, 0.0)
    };
    delta.map(|c| (c * rot).re)
}
