//! A bicubic Bézier patch: S'(u, v) = Σᵢ Σⱼ Bᵢ(u) Bⱼ(v) Pᵢⱼ over its 4 × 4 control points, with
//! the Bernstein polynomials B₀ = (1 − t)³, B₁ = 3t(1 − t)², B₂ = 3t²(1 − t), B₃ = t³
//! (Farin, *Curves and Surfaces for CAGD*, §14). It interpolates its four corners and is
//! tangent there to the edges of its control net; u, v ∈ [0, 1] (the polynomial continues
//! beyond, which keeps the equations smooth; analyses stop at the edge).
//!
//! The derivatives are those of the Bernstein polynomials: B' and B'' below.

use super::SurfaceJet;
use crate::error::ConstraintError;
use nalgebra::Vector3;

/// A bicubic Bézier patch.
#[derive(Debug, Clone, PartialEq)]
pub struct BicubicPatch {
    /// Pᵢⱼ: `points[i][j]`, i along u, j along v (boxed: the other surfaces are small).
    points: Box<[[Vector3<f64>; 4]; 4]>,
}

/// (B, B', B'') of degree 3 at t.
fn bernstein(t: f64) -> [[f64; 4]; 3] {
    let s = 1.0 - t;
    [
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
        [6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t],
    ]
}

impl BicubicPatch {
    /// The patch of the control points `points` (`points[i][j]`, i along u, j along v; finite).
    /// Refused: a non-finite point, or a degenerate patch whose corners coincide.
    pub fn new(points: [[Vector3<f64>; 4]; 4]) -> Result<Self, ConstraintError> {
        if points
            .iter()
            .flatten()
            .any(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(ConstraintError::Curve(
                "a bicubic patch's control points must be finite".into(),
            ));
        }
        let patch = Self {
            points: Box::new(points),
        };
        if patch.size() == 0.0 {
            return Err(ConstraintError::Curve(
                "a bicubic patch's control points all coincide".into(),
            ));
        }
        Ok(patch)
    }

    /// The largest distance of a control point from P₀₀.
    pub fn size(&self) -> f64 {
        let p0 = self.points[0][0];
        (self.points.iter().flatten()).fold(0.0, |a, p| a.max((p - p0).norm()))
    }

    /// The control points.
    pub fn points(&self) -> &[[Vector3<f64>; 4]; 4] {
        &self.points
    }

    /// S' and its derivatives.
    pub fn jet(&self, u: f64, v: f64) -> SurfaceJet {
        let (bu, bv) = (bernstein(u), bernstein(v));
        let sum = |a: &[f64; 4], b: &[f64; 4]| {
            let mut s = Vector3::zeros();
            for (i, row) in self.points.iter().enumerate() {
                for (j, p) in row.iter().enumerate() {
                    s += p * (a[i] * b[j]);
                }
            }
            s
        };
        SurfaceJet {
            s: sum(&bu[0], &bv[0]),
            s_u: sum(&bu[1], &bv[0]),
            s_v: sum(&bu[0], &bv[1]),
            s_uu: sum(&bu[2], &bv[0]),
            s_uv: sum(&bu[1], &bv[1]),
            s_vv: sum(&bu[0], &bv[2]),
        }
    }

    /// The nearest of a 17 × 17 grid of patch points to `p` (the start of
    /// [`super::Surface::closest`]).
    pub(super) fn sample_nearest(&self, p: &Vector3<f64>) -> [f64; 2] {
        const N: usize = 16;
        let mut best = (f64::INFINITY, [0.0, 0.0]);
        for a in 0..=N {
            for b in 0..=N {
                let (u, v) = (a as f64 / N as f64, b as f64 / N as f64);
                let d = (self.jet(u, v).s - p).norm_squared();
                if d < best.0 {
                    best = (d, [u, v]);
                }
            }
        }
        best.1
    }
}
