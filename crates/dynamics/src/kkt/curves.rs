//! Curve elements (a point on a curve, a cam pair) in the equations of motion, their curve
//! parameters eliminated.
//!
//! A curve element's r rows Φ(q, u) = 0 hold k curve parameters u (k = 1 for a point on a curve,
//! 2 for a cam pair) that carry neither mass nor applied force. The parameters' own rows of the
//! equations of motion (Haug, *Computer-Aided Kinematics and Dynamics*, §11.1, with the extra
//! coordinates of §3.6 massless) are
//!
//! ```text
//! Φ_uᵀ λ = 0,
//! ```
//!
//! so the element's multipliers lie in the null space of Φ_uᵀ: the contact force of a
//! frictionless higher pair does no work along the curve. With W = diag(1/s_r) the rows' scales
//! and N (r × (r − k), orthonormal columns) a basis of the complement of W Φ_u, λ = s W N μ
//! satisfies it for every μ, and the element enters the augmented system as r − k rows
//!
//! ```text
//! Φ̃ = s Nᵀ W Φ(q, u*),   Φ̃_v = s Nᵀ W Φ_v,   γ̃# = s Nᵀ W γ#(q, v, u*, u̇*),
//! ```
//!
//! (s: the scale of the element's first row, a length, so Φ̃ is a length) — the term Φ_u ü
//! of Φ's second derivative drops out since Nᵀ W Φ_u = 0: the parameters' accelerations are never
//! needed. The parameters themselves follow the bodies: u* minimizes |W Φ(q, u)| (Gauss–Newton
//! from the value at the last synced state: on the constraint manifold the exact solution, off
//! it the closest point, where W Φ ⊥ W Φ_u so that |Φ̃| = |W Φ| s), and
//! u̇* = −(Φ_uᵀ W² Φ_u)⁻¹ Φ_uᵀ W² (Φ_v v − ν). The element's last k rows are zero and never
//! active. At the solution ∂Φ̃/∂q = s Nᵀ W (Φ_q + Φ_u ∂u*/∂q) = s Nᵀ W Φ_q exactly, so Newton
//! projections and the Jacobian of the reduced rows agree with the full system's.
//!
//! The state of the parameters ([`CurveTrack`]) is refreshed by every sync of the bodies
//! ([`crate::Dynamics`]), without allocation.

use cardan_constraints::{BodyPair, BodyState, Constraint, MAX_EXTRA};
use cardan_mechanism::{BodyId, CurveInfo, Model};

/// Rows of the largest curve element (a cam pair).
pub(crate) const MAX_ROWS: usize = 4;

/// Gauss–Newton iterations of a parameter update at most (it converges quadratically on the
/// manifold from the last state's value: two or three).
const MAX_ITERATIONS: usize = 30;

/// One curve element's parameters and reduced rows at the synced bodies.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tracked {
    /// u*, then w* of a cam.
    pub u: [f64; MAX_EXTRA],
    /// u̇*, ẇ*.
    pub u_dot: [f64; MAX_EXTRA],
    /// The basis N as rows: `basis[a][r]` is entry r of column a, pre-multiplied by s W_r.
    basis: [[f64; MAX_ROWS]; MAX_ROWS],
    /// The coordinate axes N is built from, in order (see [`complement`]); `None` until the
    /// first update.
    axes: Option<[usize; MAX_ROWS]>,
    /// The reduced Φ̃_v blocks of body i and j (rows r − k..r zero).
    pub bi: [[f64; 6]; 6],
    pub bj: [[f64; 6]; 6],
}

/// The curve elements' parameters at the synced bodies (module docs).
#[derive(Debug, Clone)]
pub(crate) struct CurveTrack {
    pub elements: Vec<Tracked>,
    /// The first element whose parameters did not converge or whose Φ_u lost rank at the last
    /// sync (an element index), with its residual |W Φ| s.
    pub failed: Option<(usize, f64)>,
}

impl CurveTrack {
    /// The parameters of `model`'s curve elements at the drawn pose.
    pub fn new(model: &Model) -> Self {
        let elements = model
            .curves()
            .iter()
            .map(|c| Tracked {
                u: c.initial,
                u_dot: [0.0; MAX_EXTRA],
                basis: [[0.0; MAX_ROWS]; MAX_ROWS],
                axes: None,
                bi: [[0.0; 6]; 6],
                bj: [[0.0; 6]; 6],
            })
            .collect();
        Self {
            elements,
            failed: None,
        }
    }

    /// Starts the parameters from `extras` (the model's extra coordinates, e.g. of an
    /// assembly).
    pub fn start_from(&mut self, model: &Model, extras: &[f64]) {
        for (c, tr) in model.curves().iter().zip(&mut self.elements) {
            for (k, e) in c.extras().enumerate() {
                tr.u[k] = extras[e];
            }
        }
    }

    /// The parameters and reduced rows at `bodies` (module docs). No allocation.
    pub fn track(&mut self, model: &Model, bodies: &[BodyState]) {
        self.failed = None;
        let scales = model.equation_scales();
        let g = BodyState::ground();
        for (k, (c, tr)) in model.curves().iter().zip(&mut self.elements).enumerate() {
            let si = st(bodies, &g, c.body_i);
            let sj = st(bodies, &g, c.body_j);
            let w = weights(c, scales);
            if let Err(res) = tr.update(c, si, sj, &w) {
                self.failed.get_or_insert((k, res));
            }
        }
    }
}

impl CurveTrack {
    /// The parameters' accelerations ü of curve element `k` at the synced bodies `bodies` with
    /// body accelerations `vdot` (6 per body): ü = −(Φ_uᵀW²Φ_u)⁻¹Φ_uᵀW²(Φ_v v̇ − γ#), the
    /// least-squares solution of the element's rows at the acceleration level (exact on the
    /// constraint manifold). No allocation.
    pub fn accelerations(
        &self,
        model: &Model,
        k: usize,
        bodies: &[BodyState],
        vdot: &[f64],
    ) -> [f64; MAX_EXTRA] {
        let c = &model.curves()[k];
        let tr = &self.elements[k];
        let el = &c.element;
        let (r, n) = (el.rows(), el.extra());
        let g = BodyState::ground();
        let (si, sj) = (st(bodies, &g, c.body_i), st(bodies, &g, c.body_j));
        let pair = BodyPair::with_extra(si, sj, &tr.u[..n], &tr.u_dot[..n]);
        let (mut bi, mut bj) = ([[0.0; 6]; 6], [[0.0; 6]; 6]);
        el.phi_v(&pair, 0.0, &mut bi[..r], &mut bj[..r]);
        let mut gamma = [0.0; MAX_ROWS];
        el.gamma_sharp_v(&pair, 0.0, &mut gamma[..r]);
        let mut ju = [[0.0; MAX_EXTRA]; MAX_ROWS];
        el.jacobian_extra(&pair, 0.0, &mut ju[..r]);
        let acc = |id: BodyId, row: &[f64; 6]| match id {
            BodyId::Ground => 0.0,
            BodyId::Moving(b) => (0..6).map(|c| row[c] * vdot[6 * b + c]).sum::<f64>(),
        };
        let mut res = [0.0; MAX_ROWS];
        for q in 0..r {
            res[q] = acc(c.body_i, &bi[q]) + acc(c.body_j, &bj[q]) - gamma[q];
        }
        let w = weights(c, model.equation_scales());
        let step = normal_step(&ju, &res, &w, r, n).unwrap_or([f64::NAN; MAX_EXTRA]);
        [-step[0], -step[1]]
    }
}

/// The state of body `id` (`g` for the ground).
pub(super) fn st<'a>(bodies: &'a [BodyState], g: &'a BodyState, id: BodyId) -> &'a BodyState {
    match id {
        BodyId::Ground => g,
        BodyId::Moving(k) => &bodies[k],
    }
}

/// W_r of each row (1/s_r), zero past the element's rows.
fn weights(c: &CurveInfo, scales: &[f64]) -> [f64; MAX_ROWS] {
    let mut w = [0.0; MAX_ROWS];
    for (lr, r) in c.rows.clone().enumerate() {
        w[lr] = 1.0 / scales[r];
    }
    w
}

impl Tracked {
    /// Gauss–Newton on |W Φ(u)|², then N, the reduced blocks and u̇. `Err(residual)` when the
    /// parameters do not converge or Φ_u loses rank (a curve with c' = 0).
    fn update(
        &mut self,
        c: &CurveInfo,
        si: &BodyState,
        sj: &BodyState,
        w: &[f64; MAX_ROWS],
    ) -> Result<(), f64> {
        let el = &c.element;
        let (r, k) = (el.rows(), el.extra());
        let zero = [0.0; MAX_EXTRA];
        let mut phi = [0.0; MAX_ROWS];
        let mut ju = [[0.0; MAX_EXTRA]; MAX_ROWS];
        // Each pass evaluates Φ and Φ_u at the current u; a step below 1e-14 (relative) is not
        // taken, so the last evaluation is the converged one the basis and rows are built from.
        let mut converged = false;
        for _ in 0..MAX_ITERATIONS {
            let pair = BodyPair::with_extra(si, sj, &self.u[..k], &zero[..k]);
            el.phi(&pair, 0.0, &mut phi[..r]);
            el.jacobian_extra(&pair, 0.0, &mut ju[..r]);
            let Some(du) = normal_step(&ju, &phi, w, r, k) else {
                return Err(f64::INFINITY);
            };
            let big = (0..k)
                .map(|e| du[e].abs() / (1.0 + self.u[e].abs()))
                .fold(0.0f64, f64::max);
            if !big.is_finite() {
                return Err(f64::INFINITY);
            }
            if big <= 1e-14 {
                converged = true;
                break;
            }
            for e in 0..k {
                self.u[e] -= du[e];
            }
        }
        let pair = BodyPair::with_extra(si, sj, &self.u[..k], &zero[..k]);
        let s = 1.0 / w[0];
        let residual = (0..r).map(|q| (w[q] * phi[q]).powi(2)).sum::<f64>().sqrt() * s;
        let (basis, axes) = complement(&ju, w, r, k, self.axes).ok_or(residual)?;
        (self.basis, self.axes) = (basis, Some(axes));
        for a in 0..r - k {
            for q in 0..r {
                self.basis[a][q] *= s * w[q];
            }
        }
        let (mut bi, mut bj) = ([[0.0; 6]; 6], [[0.0; 6]; 6]);
        el.phi_v(&pair, 0.0, &mut bi[..r], &mut bj[..r]);
        let mut nu = [0.0; MAX_ROWS];
        el.nu(&pair, 0.0, &mut nu[..r]);
        // Φ_v v − ν, then u̇ = −(Φ_uᵀW²Φ_u)⁻¹Φ_uᵀW²(Φ_v v − ν).
        let mut rate = [0.0; MAX_ROWS];
        for q in 0..r {
            rate[q] = dot6(&bi[q], si) + dot6(&bj[q], sj) - nu[q];
        }
        let du = normal_step(&ju, &rate, w, r, k).ok_or(residual)?;
        for e in 0..k {
            self.u_dot[e] = -du[e];
        }
        self.bi = self.reduce_block(&bi, r, k);
        self.bj = self.reduce_block(&bj, r, k);
        if converged {
            Ok(())
        } else {
            Err(residual)
        }
    }

    /// s Nᵀ W B of an r × 6 block (rows r − k..r zero).
    fn reduce_block(&self, b: &[[f64; 6]; 6], r: usize, k: usize) -> [[f64; 6]; 6] {
        let mut out = [[0.0; 6]; 6];
        for (a, row) in out.iter_mut().enumerate().take(r - k) {
            for (col, v) in row.iter_mut().enumerate() {
                *v = (0..r).map(|q| self.basis[a][q] * b[q][col]).sum();
            }
        }
        out
    }

    /// s Nᵀ W v of an r-vector into `out` (r entries; the last k zero).
    pub fn reduce(&self, v: &[f64], r: usize, k: usize, out: &mut [f64]) {
        for (a, o) in out.iter_mut().enumerate().take(r) {
            *o = if a < r - k {
                (0..r).map(|q| self.basis[a][q] * v[q]).sum()
            } else {
                0.0
            };
        }
    }
}

/// Body velocities [ṙ; ω'] dotted with one row of a Φ_v block.
fn dot6(row: &[f64; 6], s: &BodyState) -> f64 {
    (0..3)
        .map(|c| row[c] * s.r_dot[c] + row[3 + c] * s.omega_local[c])
        .sum()
}

/// The least-squares step (Φ_uᵀW²Φ_u)⁻¹ Φ_uᵀ W² b (k ≤ 2 unknowns); `None` when Φ_u has lost
/// rank.
fn normal_step(
    ju: &[[f64; MAX_EXTRA]; MAX_ROWS],
    b: &[f64; MAX_ROWS],
    w: &[f64; MAX_ROWS],
    r: usize,
    k: usize,
) -> Option<[f64; MAX_EXTRA]> {
    let mut a = [[0.0; MAX_EXTRA]; MAX_EXTRA];
    let mut rhs = [0.0; MAX_EXTRA];
    for q in 0..r {
        let w2 = w[q] * w[q];
        for e in 0..k {
            rhs[e] += ju[q][e] * w2 * b[q];
            for f in 0..k {
                a[e][f] += ju[q][e] * w2 * ju[q][f];
            }
        }
    }
    let tiny = 1e-24 * (a[0][0] + a[k - 1][k - 1]).max(f64::MIN_POSITIVE);
    if k == 1 {
        (a[0][0] > tiny).then(|| [rhs[0] / a[0][0], 0.0])
    } else {
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        (det.abs() > 1e-12 * a[0][0] * a[1][1] && det.abs() > tiny).then(|| {
            [
                (a[1][1] * rhs[0] - a[0][1] * rhs[1]) / det,
                (a[0][0] * rhs[1] - a[1][0] * rhs[0]) / det,
            ]
        })
    }
}

/// An orthonormal basis of the complement of the columns of W Φ_u (r − k vectors, as rows),
/// by Gram–Schmidt: the columns first, then r − k coordinate axes projected on their complement,
/// and the axes used. The axes are those of the last call (`axes`) while each keeps at least
/// half its length through the projection, so that N varies smoothly with the poses (the
/// multipliers of the reduced rows keep their meaning from one evaluation to the next, and
/// finite differences of Φ̃_vᵀλ at fixed λ are the geometric stiffness); otherwise, and at the
/// first call, the axes that keep the most, one by one. `None` when the columns are dependent.
fn complement(
    ju: &[[f64; MAX_EXTRA]; MAX_ROWS],
    w: &[f64; MAX_ROWS],
    r: usize,
    k: usize,
    axes: Option<[usize; MAX_ROWS]>,
) -> Option<([[f64; MAX_ROWS]; MAX_ROWS], [usize; MAX_ROWS])> {
    let mut q = [[0.0; MAX_ROWS]; MAX_ROWS];
    for e in 0..k {
        let mut v = [0.0; MAX_ROWS];
        for c in 0..r {
            v[c] = w[c] * ju[c][e];
        }
        let size = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let res = orthogonalize(v, &q[..e], r);
        let norm = res.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm.is_nan() || norm <= 1e-8 * size {
            return None;
        }
        for c in 0..r {
            q[e][c] = res[c] / norm;
        }
    }
    let axis = |c: usize| {
        let mut e = [0.0; MAX_ROWS];
        e[c] = 1.0;
        e
    };
    let norm = |v: &[f64; MAX_ROWS]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    // The last call's axes, while each keeps half its length.
    let kept = axes.and_then(|a| {
        let mut q = q;
        for n in k..r {
            let res = orthogonalize(axis(a[n - k]), &q[..n], r);
            let len = norm(&res);
            if len.is_nan() || len < 0.5 {
                return None;
            }
            q[n] = res.map(|x| x / len);
        }
        Some((q, a))
    });
    if let Some(found) = kept {
        return Some(shift(found, r, k));
    }
    let mut chosen = [0; MAX_ROWS];
    for n in k..r {
        // The axis that keeps the most through the projection.
        let (best, res) = (0..r)
            .map(|c| (c, orthogonalize(axis(c), &q[..n], r)))
            .fold((0, [0.0; MAX_ROWS]), |b, x| {
                if norm(&x.1) > norm(&b.1) {
                    x
                } else {
                    b
                }
            });
        let len = norm(&res);
        q[n] = res.map(|x| x / len);
        chosen[n - k] = best;
    }
    Some(shift((q, chosen), r, k))
}

/// The complement's vectors (rows k..r of `q`) moved to the front.
fn shift(
    (q, axes): ([[f64; MAX_ROWS]; MAX_ROWS], [usize; MAX_ROWS]),
    r: usize,
    k: usize,
) -> ([[f64; MAX_ROWS]; MAX_ROWS], [usize; MAX_ROWS]) {
    let mut out = [[0.0; MAX_ROWS]; MAX_ROWS];
    out[..r - k].copy_from_slice(&q[k..r]);
    (out, axes)
}

/// v minus its projections on the orthonormal rows `q` (twice, for round-off).
fn orthogonalize(mut v: [f64; MAX_ROWS], q: &[[f64; MAX_ROWS]], r: usize) -> [f64; MAX_ROWS] {
    for _ in 0..2 {
        for b in q {
            let d: f64 = (0..r).map(|c| b[c] * v[c]).sum();
            for c in 0..r {
                v[c] -= d * b[c];
            }
        }
    }
    v
}
