//! Jets of body-fixed vectors: the shared machinery every primitive is written with.
//!
//! Every primitive is a small algebraic expression (dot products, cross products, differences)
//! of vectors fixed in body i or j. For each such vector we need, depending on the analysis:
//!
//! - its value (for Φ);
//! - its gradient with respect to the coordinates of bodies i and j ([`Grad`]): for a direction
//!   s = A s' the 7-coordinate block is ∂(A s')/∂p = 2 (G s̄' + s' pᵀ) (the seed's C) and the
//!   6-coordinate block is ∂(A s')/∂π' = −A s̃'; a point r^P = r + A s'^P adds I on r (the seed's
//!   B is the same matrix for a point vector);
//! - its rate and its velocity-quadratic acceleration ([`Motion`]): the first time derivative and
//!   the second time derivative *with zero coordinate acceleration*. Then for any constraint
//!   Φ̈ = Φ_q q̈ + (velocity-quadratic part), and γ# = −(velocity-quadratic part) − Φ_tt terms.
//!
//! The two coordinate forms differ only in those per-vector formulas ([`Form`]):
//!
//! | | rate ṡ | quadratic part of s̈ |
//! |---|---|---|
//! | 7-coordinate ([`Q7`]), constant q̇ | C(p) ṗ | C(ṗ) ṗ (A is quadratic in p, so this is exact for any p) |
//! | 6-coordinate ([`V6`]), constant v | A (ω' × s') | A (ω' × (ω' × s')) |
//!
//! The expression rules ([`Grad::dot`], [`Motion::dot`], [`Grad::cross`], ...) are the product
//! rule, written once. A primitive is then two short generic functions, correct in both forms.

use crate::state::BodyState;
use cardan_eulerparam::{da_dp, skew};
use nalgebra::{SMatrix, Vector3};

/// One body's coordinate form: 7 (q = [r; p]) or 6 (v = [ṙ; ω']) columns per body.
pub trait Form<const N: usize> {
    /// Name for messages: "7-coordinate" or "6-coordinate".
    const NAME: &'static str;
    /// ∂(A s')/∂(body coordinates), 3×N (r columns zero).
    fn dir_grad(b: &BodyState, s_local: &Vector3<f64>) -> SMatrix<f64, 3, N>;
    /// ṡ for s = A s'.
    fn dir_rate(b: &BodyState, s_local: &Vector3<f64>) -> Vector3<f64>;
    /// The velocity-quadratic part of s̈ for s = A s'.
    fn dir_quad(b: &BodyState, s_local: &Vector3<f64>) -> Vector3<f64>;
}

/// The 7-coordinate form: columns [r (3), p (4)], velocity q̇ = [ṙ; ṗ].
#[derive(Debug, Clone, Copy)]
pub struct Q7;

/// The 6-coordinate form: columns [ṙ (3), ω' (3)], velocity v = [ṙ; ω'].
#[derive(Debug, Clone, Copy)]
pub struct V6;

impl Form<7> for Q7 {
    const NAME: &'static str = "7-coordinate";
    #[inline]
    fn dir_grad(b: &BodyState, s: &Vector3<f64>) -> SMatrix<f64, 3, 7> {
        let mut m = SMatrix::<f64, 3, 7>::zeros();
        m.fixed_view_mut::<3, 4>(0, 3).copy_from(&da_dp(&b.p, s));
        m
    }
    #[inline]
    fn dir_rate(b: &BodyState, s: &Vector3<f64>) -> Vector3<f64> {
        da_dp(&b.p, s) * b.p_dot
    }
    #[inline]
    fn dir_quad(b: &BodyState, s: &Vector3<f64>) -> Vector3<f64> {
        da_dp(&b.p_dot, s) * b.p_dot
    }
}

impl Form<6> for V6 {
    const NAME: &'static str = "6-coordinate";
    #[inline]
    fn dir_grad(b: &BodyState, s: &Vector3<f64>) -> SMatrix<f64, 3, 6> {
        let mut m = SMatrix::<f64, 3, 6>::zeros();
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-b.a * skew(s)));
        m
    }
    #[inline]
    fn dir_rate(b: &BodyState, s: &Vector3<f64>) -> Vector3<f64> {
        b.a * b.omega_local.cross(s)
    }
    #[inline]
    fn dir_quad(b: &BodyState, s: &Vector3<f64>) -> Vector3<f64> {
        let w = &b.omega_local;
        b.a * w.cross(&w.cross(s))
    }
}

/// Which body a vector is fixed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Body i.
    I,
    /// Body j.
    J,
}

fn pick<'a>(i: &'a BodyState, j: &'a BodyState, side: Side) -> &'a BodyState {
    match side {
        Side::I => i,
        Side::J => j,
    }
}

/// A 3-vector expression with its gradient blocks with respect to bodies i and j.
#[derive(Debug, Clone, Copy)]
pub struct Grad<const N: usize> {
    /// Value.
    pub v: Vector3<f64>,
    /// ∂/∂(coordinates of body i), 3×N.
    pub di: SMatrix<f64, 3, N>,
    /// ∂/∂(coordinates of body j), 3×N.
    pub dj: SMatrix<f64, 3, N>,
}

/// A scalar expression with its gradient rows with respect to bodies i and j.
#[derive(Debug, Clone, Copy)]
pub struct ScalarGrad<const N: usize> {
    /// Value.
    pub v: f64,
    /// ∂/∂(coordinates of body i), 1×N.
    pub di: SMatrix<f64, 1, N>,
    /// ∂/∂(coordinates of body j), 1×N.
    pub dj: SMatrix<f64, 1, N>,
}

impl<const N: usize> Grad<N> {
    /// s = A_k s' for a direction fixed in body `side`.
    #[inline]
    pub fn dir<F: Form<N>>(i: &BodyState, j: &BodyState, side: Side, s: &Vector3<f64>) -> Self {
        let b = pick(i, j, side);
        let g = F::dir_grad(b, s);
        let z = SMatrix::<f64, 3, N>::zeros();
        let (di, dj) = match side {
            Side::I => (g, z),
            Side::J => (z, g),
        };
        Self { v: b.a * s, di, dj }
    }

    /// r^P = r_k + A_k s'^P for a point fixed in body `side`.
    #[inline]
    pub fn point<F: Form<N>>(i: &BodyState, j: &BodyState, side: Side, s: &Vector3<f64>) -> Self {
        let mut g = Self::dir::<F>(i, j, side, s);
        g.v += pick(i, j, side).r;
        let d = match side {
            Side::I => &mut g.di,
            Side::J => &mut g.dj,
        };
        for k in 0..3 {
            d[(k, k)] += 1.0;
        }
        g
    }

    /// d = r^P_j − r^P_i.
    #[inline]
    pub fn between<F: Form<N>>(
        i: &BodyState,
        j: &BodyState,
        sp_i: &Vector3<f64>,
        sp_j: &Vector3<f64>,
    ) -> Self {
        Self::point::<F>(i, j, Side::J, sp_j).sub(&Self::point::<F>(i, j, Side::I, sp_i))
    }

    /// self − o.
    #[inline]
    pub fn sub(&self, o: &Self) -> Self {
        Self {
            v: self.v - o.v,
            di: self.di - o.di,
            dj: self.dj - o.dj,
        }
    }

    /// selfᵀ o, by the product rule.
    #[inline]
    pub fn dot(&self, o: &Self) -> ScalarGrad<N> {
        ScalarGrad {
            v: self.v.dot(&o.v),
            di: self.v.transpose() * o.di + o.v.transpose() * self.di,
            dj: self.v.transpose() * o.dj + o.v.transpose() * self.dj,
        }
    }

    /// self × o = s̃ o, by the product rule: ∂(a × b) = ã ∂b − b̃ ∂a.
    #[inline]
    pub fn cross(&self, o: &Self) -> Self {
        let (ta, tb) = (skew(&self.v), skew(&o.v));
        Self {
            v: self.v.cross(&o.v),
            di: ta * o.di - tb * self.di,
            dj: ta * o.dj - tb * self.dj,
        }
    }

    /// |self|, by the chain rule: ∂|a| = aᵀ∂a / |a| (undefined at a = 0).
    #[inline]
    pub fn norm(&self) -> ScalarGrad<N> {
        let n = self.v.norm();
        ScalarGrad {
            v: n,
            di: self.v.transpose() * self.di / n,
            dj: self.v.transpose() * self.dj / n,
        }
    }
}

impl<const N: usize> ScalarGrad<N> {
    /// Scales value and gradient.
    #[inline]
    pub fn scale(&self, c: f64) -> Self {
        Self {
            v: self.v * c,
            di: self.di * c,
            dj: self.dj * c,
        }
    }

    /// self + o.
    #[inline]
    pub fn add(&self, o: &Self) -> Self {
        Self {
            v: self.v + o.v,
            di: self.di + o.di,
            dj: self.dj + o.dj,
        }
    }

    /// self − o.
    #[inline]
    pub fn sub(&self, o: &Self) -> Self {
        self.add(&o.scale(-1.0))
    }

    /// self², by the chain rule: ∂(u²) = 2 u ∂u.
    #[inline]
    pub fn square(&self) -> Self {
        Self {
            v: self.v * self.v,
            di: self.di * (2.0 * self.v),
            dj: self.dj * (2.0 * self.v),
        }
    }

    /// Writes the gradient rows into one Jacobian row of each body.
    #[inline]
    pub fn write(&self, out_i: &mut [f64; N], out_j: &mut [f64; N]) {
        for c in 0..N {
            out_i[c] = self.di[c];
            out_j[c] = self.dj[c];
        }
    }
}

/// Writes the three rows of a vector gradient into three Jacobian rows of each body.
pub fn write_rows<const N: usize>(g: &Grad<N>, out_i: &mut [[f64; N]], out_j: &mut [[f64; N]]) {
    for r in 0..3 {
        for c in 0..N {
            out_i[r][c] = g.di[(r, c)];
            out_j[r][c] = g.dj[(r, c)];
        }
    }
}

/// A 3-vector expression with its rate and the velocity-quadratic part of its acceleration.
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    /// Value.
    pub v: Vector3<f64>,
    /// First time derivative.
    pub rate: Vector3<f64>,
    /// Second time derivative at zero coordinate acceleration.
    pub quad: Vector3<f64>,
}

/// A scalar expression with its rate and the velocity-quadratic part of its acceleration.
#[derive(Debug, Clone, Copy)]
pub struct ScalarMotion {
    /// Value.
    pub v: f64,
    /// First time derivative.
    pub rate: f64,
    /// Second time derivative at zero coordinate acceleration.
    pub quad: f64,
}

impl Motion {
    /// s = A_k s' for a direction fixed in body `side`.
    pub fn dir<const N: usize, F: Form<N>>(
        i: &BodyState,
        j: &BodyState,
        side: Side,
        s: &Vector3<f64>,
    ) -> Self {
        let b = pick(i, j, side);
        Self {
            v: b.a * s,
            rate: F::dir_rate(b, s),
            quad: F::dir_quad(b, s),
        }
    }

    /// r^P = r_k + A_k s'^P for a point fixed in body `side`.
    pub fn point<const N: usize, F: Form<N>>(
        i: &BodyState,
        j: &BodyState,
        side: Side,
        s: &Vector3<f64>,
    ) -> Self {
        let b = pick(i, j, side);
        let mut m = Self::dir::<N, F>(i, j, side, s);
        m.v += b.r;
        m.rate += b.r_dot;
        m
    }

    /// d = r^P_j − r^P_i.
    pub fn between<const N: usize, F: Form<N>>(
        i: &BodyState,
        j: &BodyState,
        sp_i: &Vector3<f64>,
        sp_j: &Vector3<f64>,
    ) -> Self {
        Self::point::<N, F>(i, j, Side::J, sp_j).sub(&Self::point::<N, F>(i, j, Side::I, sp_i))
    }

    /// self − o.
    pub fn sub(&self, o: &Self) -> Self {
        Self {
            v: self.v - o.v,
            rate: self.rate - o.rate,
            quad: self.quad - o.quad,
        }
    }

    /// selfᵀ o: (aᵀb)¨ = äᵀb + 2 ȧᵀḃ + aᵀb̈.
    pub fn dot(&self, o: &Self) -> ScalarMotion {
        ScalarMotion {
            v: self.v.dot(&o.v),
            rate: self.rate.dot(&o.v) + self.v.dot(&o.rate),
            quad: self.quad.dot(&o.v) + 2.0 * self.rate.dot(&o.rate) + self.v.dot(&o.quad),
        }
    }

    /// self × o: (a × b)¨ = ä × b + 2 ȧ × ḃ + a × b̈.
    pub fn cross(&self, o: &Self) -> Self {
        Self {
            v: self.v.cross(&o.v),
            rate: self.rate.cross(&o.v) + self.v.cross(&o.rate),
            quad: self.quad.cross(&o.v) + 2.0 * self.rate.cross(&o.rate) + self.v.cross(&o.quad),
        }
    }

    /// |self|: (|a|)˙ = aᵀȧ/|a|, (|a|)¨ = (ȧᵀȧ + aᵀä)/|a| − (|a|)˙²/|a| (undefined at a = 0).
    pub fn norm(&self) -> ScalarMotion {
        let n = self.v.norm();
        let rate = self.v.dot(&self.rate) / n;
        ScalarMotion {
            v: n,
            rate,
            quad: (self.rate.dot(&self.rate) + self.v.dot(&self.quad)) / n - rate * rate / n,
        }
    }
}

impl ScalarMotion {
    /// self + o.
    pub fn add(&self, o: &Self) -> Self {
        Self {
            v: self.v + o.v,
            rate: self.rate + o.rate,
            quad: self.quad + o.quad,
        }
    }

    /// self − o.
    pub fn sub(&self, o: &Self) -> Self {
        Self {
            v: self.v - o.v,
            rate: self.rate - o.rate,
            quad: self.quad - o.quad,
        }
    }

    /// self²: (u²)¨ = 2 u̇² + 2 u ü.
    pub fn square(&self) -> Self {
        Self {
            v: self.v * self.v,
            rate: 2.0 * self.v * self.rate,
            quad: 2.0 * self.rate * self.rate + 2.0 * self.v * self.quad,
        }
    }
}
