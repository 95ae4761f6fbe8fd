//! Shared test fixtures: mechanism-like sparsity patterns, a small RNG, and a planar four-bar
//! built from four spatial revolute joints (7- and 6-coordinate forms).
#![allow(dead_code, missing_docs)]

use cardan_solver::{NonlinearSystem, SparsityPattern};

/// Deterministic xorshift generator (no dependency).
pub struct Rng(pub u64);

impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [-1, 1).
    pub fn sym(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
}

/// Block rows of 7 equations per body, coupled to the bodies adjacent in a graph.
/// Returns the pattern and slot values that are block diagonally dominant (nonsingular).
pub fn block_graph(
    nb: usize,
    neighbors: &dyn Fn(usize) -> Vec<usize>,
    rng: &mut Rng,
) -> (SparsityPattern, Vec<f64>) {
    const B: usize = 7;
    let mut entries = Vec::new();
    let mut values = Vec::new();
    for i in 0..nb {
        let mut blocks = neighbors(i);
        blocks.push(i);
        blocks.sort_unstable();
        for &j in &blocks {
            for r in 0..B {
                for c in 0..B {
                    entries.push((B * i + r, B * j + c));
                    let diag = if i == j && r == c { 40.0 } else { 0.0 };
                    values.push(diag + rng.sym());
                }
            }
        }
    }
    (
        SparsityPattern::new(B * nb, B * nb, &entries).unwrap(),
        values,
    )
}

/// A chain of bodies: body i is jointed to i − 1 and i + 1.
pub fn chain(nb: usize, rng: &mut Rng) -> (SparsityPattern, Vec<f64>) {
    block_graph(
        nb,
        &move |i| {
            let mut v = Vec::new();
            if i > 0 {
                v.push(i - 1);
            }
            if i + 1 < nb {
                v.push(i + 1);
            }
            v
        },
        rng,
    )
}

/// A ladder of closed loops: two rails (even and odd bodies) with a rung between 2k and 2k + 1.
pub fn ladder(nb: usize, rng: &mut Rng) -> (SparsityPattern, Vec<f64>) {
    block_graph(
        nb,
        &move |i| {
            let mut v = Vec::new();
            if i >= 2 {
                v.push(i - 2);
            }
            if i + 2 < nb {
                v.push(i + 2);
            }
            let partner = i ^ 1;
            if partner < nb {
                v.push(partner);
            }
            v
        },
        rng,
    )
}

// ---------------------------------------------------------------- Euler parameters (test-only)

pub type V3 = [f64; 3];

pub fn a_mat(p: &[f64]) -> [[f64; 3]; 3] {
    let (e0, e) = (p[0], [p[1], p[2], p[3]]);
    let mut a = [[0.0; 3]; 3];
    let skew = [[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            let id = if i == j { 1.0 } else { 0.0 };
            a[i][j] = (2.0 * e0 * e0 - 1.0) * id + 2.0 * (e[i] * e[j] + e0 * skew[i][j]);
        }
    }
    a
}

pub fn rot(p: &[f64], v: V3) -> V3 {
    let a = a_mat(p);
    [0, 1, 2].map(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

/// ∂(A(p) a')/∂p, 3 × 4: columns e0, e1, e2, e3.
pub fn d_rot(p: &[f64], a: V3) -> [[f64; 4]; 3] {
    let (e0, e) = (p[0], [p[1], p[2], p[3]]);
    let ea = e[0] * a[0] + e[1] * a[1] + e[2] * a[2];
    let cross = [
        e[1] * a[2] - e[2] * a[1],
        e[2] * a[0] - e[0] * a[2],
        e[0] * a[1] - e[1] * a[0],
    ];
    // ã'
    let sa = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
    let mut d = [[0.0; 4]; 3];
    for i in 0..3 {
        d[i][0] = 4.0 * e0 * a[i] + 2.0 * cross[i];
        for j in 0..3 {
            let id = if i == j { 1.0 } else { 0.0 };
            d[i][1 + j] = 2.0 * ea * id + 2.0 * e[i] * a[j] - 2.0 * e0 * sa[i][j];
        }
    }
    d
}

pub fn z_rotation(theta: f64) -> [f64; 4] {
    [(theta / 2.0).cos(), 0.0, 0.0, (theta / 2.0).sin()]
}

// ---------------------------------------------------------------- planar four-bar, spatial joints

/// Ground pivots A = (0,0,0), D = (ground, 0, 0); crank (body 0) A→B, coupler (body 1) B→C,
/// rocker (body 2) C→D. Each body frame has its origin at its first joint and x along the link.
/// Four revolute joints (spherical + two n1 rows each, axes z), three normalization rows and a
/// crank-angle driver (A₀ x̂)·(−sin θ, cos θ, 0) = 0: 24 equations in 21 unknowns, rank 21,
/// 3 redundant. Driver: ν = θ̇, and Φ_qt q̇ = Φ_tt = 0 on the solution, so γ# = −(Φ_q q̇)_q q̇.
pub struct FourBar {
    pub scale: f64,
    pub lengths: [f64; 4], // ground, crank, coupler, rocker (before scale)
    pub theta: f64,
}

/// Joint k: (body i or None for ground, point in i, body j or None, point in j).
type Joint = (Option<usize>, V3, Option<usize>, V3);

impl FourBar {
    pub fn new(scale: f64, theta: f64) -> Self {
        Self {
            scale,
            lengths: [4.0, 1.0, 3.5, 3.0],
            theta,
        }
    }

    fn joints(&self) -> [Joint; 4] {
        let [g, l1, l2, l3] = self.lengths.map(|l| l * self.scale);
        [
            (None, [0.0; 3], Some(0), [0.0; 3]),
            (Some(0), [l1, 0.0, 0.0], Some(1), [0.0; 3]),
            (Some(1), [l2, 0.0, 0.0], Some(2), [0.0; 3]),
            (Some(2), [l3, 0.0, 0.0], None, [g, 0.0, 0.0]),
        ]
    }

    pub const M: usize = 24;
    pub const N: usize = 21;

    /// Rows: joint k → rows 5k..5k+5 (3 spherical, 2 parallel); 20..23 normalization; 23 driver.
    pub fn entries() -> Vec<(usize, usize)> {
        let fb = FourBar::new(1.0, 0.0);
        let mut e = Vec::new();
        for (k, (bi, _, bj, _)) in fb.joints().iter().enumerate() {
            for b in [bi, bj].into_iter().flatten() {
                for r in 0..5 {
                    let cols = if r < 3 { 0..7 } else { 3..7 };
                    for c in cols {
                        e.push((5 * k + r, 7 * b + c));
                    }
                }
            }
        }
        for b in 0..3 {
            for c in 3..7 {
                e.push((20 + b, 7 * b + c));
            }
        }
        for c in 3..7 {
            e.push((23, c));
        }
        e
    }

    pub fn pattern() -> SparsityPattern {
        SparsityPattern::new(Self::M, Self::N, &Self::entries()).unwrap()
    }

    /// Assembled configuration for the crank angle (closed-form circle intersection).
    pub fn assembled(&self) -> Vec<f64> {
        let [g, l1, l2, l3] = self.lengths.map(|l| l * self.scale);
        let b = [l1 * self.theta.cos(), l1 * self.theta.sin()];
        let d = [g, 0.0];
        let (dx, dy) = (d[0] - b[0], d[1] - b[1]);
        let dist = (dx * dx + dy * dy).sqrt();
        let a = (l2 * l2 - l3 * l3 + dist * dist) / (2.0 * dist);
        let h = (l2 * l2 - a * a).sqrt();
        let c = [
            b[0] + a * dx / dist - h * dy / dist,
            b[1] + a * dy / dist + h * dx / dist,
        ];
        let t2 = (c[1] - b[1]).atan2(c[0] - b[0]);
        let t3 = (d[1] - c[1]).atan2(d[0] - c[0]);
        let mut q = vec![0.0; 21];
        for (k, (r, t)) in [([0.0, 0.0], self.theta), (b, t2), (c, t3)]
            .iter()
            .enumerate()
        {
            q[7 * k] = r[0];
            q[7 * k + 1] = r[1];
            q[7 * k + 3..7 * k + 7].copy_from_slice(&z_rotation(*t));
        }
        q
    }

    pub fn body(q: &[f64], b: Option<usize>) -> (V3, &[f64]) {
        const IDENTITY: [f64; 4] = [1.0, 0.0, 0.0, 0.0];
        match b {
            Some(b) => (
                [q[7 * b], q[7 * b + 1], q[7 * b + 2]],
                &q[7 * b + 3..7 * b + 7],
            ),
            None => ([0.0; 3], &IDENTITY),
        }
    }
}

impl NonlinearSystem for FourBar {
    fn num_equations(&self) -> usize {
        Self::M
    }
    fn num_unknowns(&self) -> usize {
        Self::N
    }
    fn residual(&mut self, q: &[f64], out: &mut [f64]) {
        for (k, (bi, si, bj, sj)) in self.joints().iter().enumerate() {
            let (ri, pi) = Self::body(q, *bi);
            let (rj, pj) = Self::body(q, *bj);
            let (ai, aj) = (rot(pi, *si), rot(pj, *sj));
            for x in 0..3 {
                out[5 * k + x] = ri[x] + ai[x] - rj[x] - aj[x];
            }
            let zj = rot(pj, [0.0, 0.0, 1.0]);
            let (fi, gi) = (rot(pi, [1.0, 0.0, 0.0]), rot(pi, [0.0, 1.0, 0.0]));
            out[5 * k + 3] = (0..3).map(|x| fi[x] * zj[x]).sum();
            out[5 * k + 4] = (0..3).map(|x| gi[x] * zj[x]).sum();
        }
        for b in 0..3 {
            let p = &q[7 * b + 3..7 * b + 7];
            out[20 + b] = p.iter().map(|v| v * v).sum::<f64>() - 1.0;
        }
        let x0 = rot(&q[3..7], [1.0, 0.0, 0.0]);
        out[23] = -x0[0] * self.theta.sin() + x0[1] * self.theta.cos();
    }
    fn jacobian(&mut self, q: &[f64], slots: &mut [f64]) {
        let mut s = 0;
        let mut push = |v: f64| {
            slots[s] = v;
            s += 1;
        };
        for (bi, si, bj, sj) in self.joints() {
            let (_, pi) = Self::body(q, bi);
            let (_, pj) = Self::body(q, bj);
            let zj = rot(pj, [0.0, 0.0, 1.0]);
            let (fi, gi) = (rot(pi, [1.0, 0.0, 0.0]), rot(pi, [0.0, 1.0, 0.0]));
            for (b, sign, sp, is_i) in [(bi, 1.0, si, true), (bj, -1.0, sj, false)] {
                let Some(_) = b else { continue };
                let p = if is_i { pi } else { pj };
                let d = d_rot(p, sp);
                for r in 0..3 {
                    for c in 0..3 {
                        push(if r == c { sign } else { 0.0 });
                    }
                    for c in 0..4 {
                        push(sign * d[r][c]);
                    }
                }
                // n1 rows: f_i·z_j and g_i·z_j
                for other in [fi, gi] {
                    let local = if is_i {
                        if other == fi {
                            [1.0, 0.0, 0.0]
                        } else {
                            [0.0, 1.0, 0.0]
                        }
                    } else {
                        [0.0, 0.0, 1.0]
                    };
                    let partner = if is_i { zj } else { other };
                    let d = d_rot(p, local);
                    for c in 0..4 {
                        push((0..3).map(|x| partner[x] * d[x][c]).sum());
                    }
                }
            }
        }
        for b in 0..3 {
            for c in 0..4 {
                push(2.0 * q[7 * b + 3 + c]);
            }
        }
        let d = d_rot(&q[3..7], [1.0, 0.0, 0.0]);
        for c in 0..4 {
            push(-d[0][c] * self.theta.sin() + d[1][c] * self.theta.cos());
        }
    }
    fn equation_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
        for k in 0..4 {
            out[5 * k..5 * k + 3].fill(self.scale);
        }
    }
    fn unknown_scales(&self, out: &mut [f64]) {
        for b in 0..3 {
            out[7 * b..7 * b + 3].fill(self.scale);
            out[7 * b + 3..7 * b + 7].fill(1.0);
        }
    }
}

/// The same four-bar in the 6-coordinate form: step [Δr; Δπ'] per body, no normalization rows
/// (21 equations: 20 joint rows + driver, 18 unknowns, rank 18). The state stays [r; p].
pub struct FourBar6 {
    pub inner: FourBar,
    full_slots: Vec<f64>,
    full_res: Vec<f64>,
}

impl FourBar6 {
    pub const M: usize = 21;
    pub const N: usize = 18;

    fn rows_kept(r: usize) -> Option<usize> {
        match r {
            0..20 => Some(r),
            23 => Some(20),
            _ => None,
        }
    }

    pub fn entries() -> Vec<(usize, usize)> {
        let mut e = Vec::new();
        let mut seen = std::collections::BTreeSet::new();
        for (r, c) in FourBar::entries() {
            let Some(r6) = Self::rows_kept(r) else {
                continue;
            };
            let (b, local) = (c / 7, c % 7);
            let cols: Vec<usize> = if local < 3 {
                vec![6 * b + local]
            } else {
                (0..3).map(|k| 6 * b + 3 + k).collect()
            };
            for c6 in cols {
                if seen.insert((r6, c6)) {
                    e.push((r6, c6));
                }
            }
        }
        e
    }

    pub fn pattern() -> SparsityPattern {
        SparsityPattern::new(Self::M, Self::N, &Self::entries()).unwrap()
    }

    pub fn new(inner: FourBar) -> Self {
        Self {
            inner,
            full_slots: vec![0.0; FourBar::entries().len()],
            full_res: vec![0.0; FourBar::M],
        }
    }
}

/// L(p) = [−e, −ẽ + e0 I].
fn l_mat(p: &[f64]) -> [[f64; 4]; 3] {
    let (e0, e) = (p[0], [p[1], p[2], p[3]]);
    [
        [-e[0], e0, e[2], -e[1]],
        [-e[1], -e[2], e0, e[0]],
        [-e[2], e[1], -e[0], e0],
    ]
}

impl NonlinearSystem for FourBar6 {
    fn num_equations(&self) -> usize {
        Self::M
    }
    fn num_unknowns(&self) -> usize {
        Self::N
    }
    fn state_len(&self) -> usize {
        FourBar::N
    }
    fn residual(&mut self, q: &[f64], out: &mut [f64]) {
        self.inner.residual(q, &mut self.full_res);
        out[..20].copy_from_slice(&self.full_res[..20]);
        out[20] = self.full_res[23];
    }
    fn jacobian(&mut self, q: &[f64], slots: &mut [f64]) {
        self.inner.jacobian(q, &mut self.full_slots);
        // Φ_π' = ½ Φ_p Lᵀ: accumulate row by row through dense scratch (test code: allocation ok).
        let e6 = Self::entries();
        let index: std::collections::HashMap<(usize, usize), usize> =
            e6.iter().enumerate().map(|(k, &rc)| (rc, k)).collect();
        slots.fill(0.0);
        for (k, (r, c)) in FourBar::entries().into_iter().enumerate() {
            let Some(r6) = Self::rows_kept(r) else {
                continue;
            };
            let (b, local) = (c / 7, c % 7);
            let v = self.full_slots[k];
            if local < 3 {
                slots[index[&(r6, 6 * b + local)]] += v;
            } else {
                let l = l_mat(&q[7 * b + 3..7 * b + 7]);
                for a in 0..3 {
                    slots[index[&(r6, 6 * b + 3 + a)]] += 0.5 * v * l[a][local - 3];
                }
            }
        }
    }
    fn apply_step(&mut self, q: &mut [f64], dx: &[f64]) {
        for b in 0..3 {
            for k in 0..3 {
                q[7 * b + k] += dx[6 * b + k];
            }
            let phi = [dx[6 * b + 3], dx[6 * b + 4], dx[6 * b + 5]];
            let angle = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
            let (c, s) = (
                (angle / 2.0).cos(),
                if angle > 0.0 {
                    (angle / 2.0).sin() / angle
                } else {
                    0.5
                },
            );
            let d = [c, s * phi[0], s * phi[1], s * phi[2]];
            let p = [q[7 * b + 3], q[7 * b + 4], q[7 * b + 5], q[7 * b + 6]];
            // p ⊗ d (scalar first)
            let mut n = [
                p[0] * d[0] - p[1] * d[1] - p[2] * d[2] - p[3] * d[3],
                p[0] * d[1] + p[1] * d[0] + p[2] * d[3] - p[3] * d[2],
                p[0] * d[2] - p[1] * d[3] + p[2] * d[0] + p[3] * d[1],
                p[0] * d[3] + p[1] * d[2] - p[2] * d[1] + p[3] * d[0],
            ];
            let norm = n.iter().map(|v| v * v).sum::<f64>().sqrt();
            n.iter_mut().for_each(|v| *v /= norm);
            q[7 * b + 3..7 * b + 7].copy_from_slice(&n);
        }
    }
    fn equation_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
        for k in 0..4 {
            out[5 * k..5 * k + 3].fill(self.inner.scale);
        }
    }
    fn unknown_scales(&self, out: &mut [f64]) {
        for b in 0..3 {
            out[6 * b..6 * b + 3].fill(self.inner.scale);
            out[6 * b + 3..6 * b + 6].fill(1.0);
        }
    }
}

/// Central finite-difference check of a system's Jacobian at x (7-coordinate, additive step).
pub fn fd_jacobian_error(
    sys: &mut dyn NonlinearSystem,
    pattern: &SparsityPattern,
    x: &[f64],
) -> f64 {
    let (m, n) = (pattern.nrows(), pattern.ncols());
    let mut slots = vec![0.0; pattern.num_slots()];
    sys.jacobian(x, &mut slots);
    let mut dense = vec![0.0; m * n];
    pattern.to_dense_col_major(&slots, &mut dense).unwrap();
    let h = 1e-6;
    let mut worst = 0.0f64;
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    for j in 0..n {
        let mut xp = x.to_vec();
        let mut xm = x.to_vec();
        let mut e = vec![0.0; n];
        e[j] = h;
        sys.apply_step(&mut xp, &e);
        e[j] = -h;
        sys.apply_step(&mut xm, &e);
        sys.residual(&xp, &mut rp);
        sys.residual(&xm, &mut rm);
        for i in 0..m {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            worst = worst.max((fd - dense[i + m * j]).abs());
        }
    }
    worst
}

// ---------------------------------------------------------------- Bennett linkage

type Frame = ([[f64; 3]; 3], V3);

fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn mat_vec(a: &[[f64; 3]; 3], v: V3) -> V3 {
    [0, 1, 2].map(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

fn compose(f: &Frame, g: &Frame) -> Frame {
    let t = mat_vec(&f.0, g.1);
    (
        mat_mul(&f.0, &g.0),
        [t[0] + f.1[0], t[1] + f.1[1], t[2] + f.1[2]],
    )
}

/// Denavit–Hartenberg step Rz(θ) Tx(a) Rx(α).
fn dh(theta: f64, a: f64, alpha: f64) -> Frame {
    let (ct, st, ca, sa) = (theta.cos(), theta.sin(), alpha.cos(), alpha.sin());
    (
        [
            [ct, -st * ca, st * sa],
            [st, ct * ca, -ct * sa],
            [0.0, sa, ca],
        ],
        [a * ct, a * st, 0.0],
    )
}

/// Euler parameters of a rotation matrix (Shepperd), e0 ≥ 0.
pub fn quat_from_matrix(r: &[[f64; 3]; 3]) -> [f64; 4] {
    let tr = r[0][0] + r[1][1] + r[2][2];
    let cands = [tr, r[0][0], r[1][1], r[2][2]];
    let k = (0..4)
        .max_by(|&a, &b| cands[a].total_cmp(&cands[b]))
        .unwrap();
    let mut q = match k {
        0 => {
            let s = (1.0 + tr).sqrt() * 2.0;
            [
                s / 4.0,
                (r[2][1] - r[1][2]) / s,
                (r[0][2] - r[2][0]) / s,
                (r[1][0] - r[0][1]) / s,
            ]
        }
        1 => {
            let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
            [
                (r[2][1] - r[1][2]) / s,
                s / 4.0,
                (r[0][1] + r[1][0]) / s,
                (r[0][2] + r[2][0]) / s,
            ]
        }
        2 => {
            let s = (1.0 - r[0][0] + r[1][1] - r[2][2]).sqrt() * 2.0;
            [
                (r[0][2] - r[2][0]) / s,
                (r[0][1] + r[1][0]) / s,
                s / 4.0,
                (r[1][2] + r[2][1]) / s,
            ]
        }
        _ => {
            let s = (1.0 - r[0][0] - r[1][1] + r[2][2]).sqrt() * 2.0;
            [
                (r[1][0] - r[0][1]) / s,
                (r[0][2] + r[2][0]) / s,
                (r[1][2] + r[2][1]) / s,
                s / 4.0,
            ]
        }
    };
    if q[0] < 0.0 {
        q.iter_mut().for_each(|v| *v = -*v);
    }
    q
}

/// DH loop closure of a Bennett linkage as a function of (θ2, θ3, θ4) for a given θ1: the 12
/// entries of (R − I, t) of the loop transform. Jacobian by central differences (test helper).
pub struct BennettClosure {
    pub theta1: f64,
    pub params: [(f64, f64); 4], // (a_k, α_k)
}

impl BennettClosure {
    pub fn loop_frame(&self, th: [f64; 4]) -> [Frame; 4] {
        let mut f: Frame = (
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [0.0; 3],
        );
        let mut out = [f; 4];
        for k in 0..4 {
            f = compose(&f, &dh(th[k], self.params[k].0, self.params[k].1));
            out[k] = f;
        }
        out
    }
}

impl NonlinearSystem for BennettClosure {
    fn num_equations(&self) -> usize {
        12
    }
    fn num_unknowns(&self) -> usize {
        3
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        let f = self.loop_frame([self.theta1, x[0], x[1], x[2]])[3];
        for i in 0..3 {
            for j in 0..3 {
                out[3 * i + j] = f.0[i][j] - if i == j { 1.0 } else { 0.0 };
            }
            out[9 + i] = f.1[i];
        }
    }
    fn jacobian(&mut self, x: &[f64], slots: &mut [f64]) {
        let h = 1e-7;
        let (mut rp, mut rm) = ([0.0; 12], [0.0; 12]);
        for j in 0..3 {
            let mut xp = [x[0], x[1], x[2]];
            let mut xm = xp;
            xp[j] += h;
            xm[j] -= h;
            self.residual(&xp, &mut rp);
            self.residual(&xm, &mut rm);
            for i in 0..12 {
                slots[i + 12 * j] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
    }
}

/// The Bennett linkage in absolute coordinates: ground + 3 moving bodies (DH frames), four
/// revolute joints (spherical + two n1 rows each), three normalization rows, **no driver**:
/// 23 equations in 21 unknowns, mobility 1, so rank 20 and 3 redundant equations.
pub struct Bennett {
    /// (body i or ground, point in i, body j or ground, point in j, axis in j); the axis in i is
    /// its local z, with local x and y spanning the normal plane.
    joints: [Joint5; 4],
}

type Joint5 = (Option<usize>, V3, Option<usize>, V3, V3);

impl Bennett {
    pub const M: usize = 23;
    pub const N: usize = 21;

    /// Builds the linkage from DH parameters, and the configuration of the given joint angles
    /// (assembled to the accuracy of the angles).
    pub fn new(params: [(f64, f64); 4], angles: [f64; 4]) -> (Self, Vec<f64>) {
        let closure = BennettClosure {
            theta1: angles[0],
            params,
        };
        let frames = closure.loop_frame(angles);
        // Body k (k = 1..3) has frame F_k; ground is F_0 = I (= F_4 after closure).
        let frame = |k: usize| frames[k - 1];
        let body = |k: usize| if k == 0 || k == 4 { None } else { Some(k - 1) };
        // Joint k joins bodies k−1 and k along the z axis of F_{k−1}. In F_{k−1}: origin, z. In
        // F_k = F_{k−1} Rz(θ) Tx(a) Rx(α): (−a, 0, 0) and Rx(−α) ẑ = (0, sin α, cos α), exactly,
        // whatever θ (so the geometry is an exact Bennett linkage even if the angles are not).
        let joints = [1, 2, 3, 4].map(|k| {
            let (a, alpha) = params[k - 1];
            (
                body(k - 1),
                [0.0; 3],
                body(k),
                [-a, 0.0, 0.0],
                [0.0, alpha.sin(), alpha.cos()],
            )
        });
        let mut q = vec![0.0; Self::N];
        for k in 1..=3 {
            let f = frame(k);
            q[7 * (k - 1)..7 * (k - 1) + 3].copy_from_slice(&f.1);
            q[7 * (k - 1) + 3..7 * k].copy_from_slice(&quat_from_matrix(&f.0));
        }
        (Self { joints }, q)
    }

    pub fn entries() -> Vec<(usize, usize)> {
        let mut e = Vec::new();
        let bodies = [
            (None, Some(0)),
            (Some(0), Some(1)),
            (Some(1), Some(2)),
            (Some(2), None),
        ];
        for (k, (bi, bj)) in bodies.iter().enumerate() {
            for b in [bi, bj].into_iter().flatten() {
                for r in 0..5 {
                    let cols = if r < 3 { 0..7 } else { 3..7 };
                    for c in cols {
                        e.push((5 * k + r, 7 * b + c));
                    }
                }
            }
        }
        for b in 0..3 {
            for c in 3..7 {
                e.push((20 + b, 7 * b + c));
            }
        }
        e
    }

    pub fn pattern() -> SparsityPattern {
        SparsityPattern::new(Self::M, Self::N, &Self::entries()).unwrap()
    }
}

impl NonlinearSystem for Bennett {
    fn num_equations(&self) -> usize {
        Self::M
    }
    fn num_unknowns(&self) -> usize {
        Self::N
    }
    fn residual(&mut self, q: &[f64], out: &mut [f64]) {
        for (k, (bi, si, bj, sj, hj)) in self.joints.iter().enumerate() {
            let (ri, pi) = FourBar::body(q, *bi);
            let (rj, pj) = FourBar::body(q, *bj);
            let (ai, aj) = (rot(pi, *si), rot(pj, *sj));
            for x in 0..3 {
                out[5 * k + x] = ri[x] + ai[x] - rj[x] - aj[x];
            }
            let h = rot(pj, *hj);
            let (fi, gi) = (rot(pi, [1.0, 0.0, 0.0]), rot(pi, [0.0, 1.0, 0.0]));
            out[5 * k + 3] = (0..3).map(|x| fi[x] * h[x]).sum();
            out[5 * k + 4] = (0..3).map(|x| gi[x] * h[x]).sum();
        }
        for b in 0..3 {
            let p = &q[7 * b + 3..7 * b + 7];
            out[20 + b] = p.iter().map(|v| v * v).sum::<f64>() - 1.0;
        }
    }
    fn jacobian(&mut self, q: &[f64], slots: &mut [f64]) {
        let mut s = 0;
        for (bi, si, bj, sj, hj) in self.joints {
            let (_, pi) = FourBar::body(q, bi);
            let (_, pj) = FourBar::body(q, bj);
            let h = rot(pj, hj);
            let (fi, gi) = (rot(pi, [1.0, 0.0, 0.0]), rot(pi, [0.0, 1.0, 0.0]));
            for (b, sign, sp, is_i) in [(bi, 1.0, si, true), (bj, -1.0, sj, false)] {
                if b.is_none() {
                    continue;
                }
                let p = if is_i { pi } else { pj };
                let d = d_rot(p, sp);
                for r in 0..3 {
                    for c in 0..3 {
                        slots[s] = if r == c { sign } else { 0.0 };
                        s += 1;
                    }
                    for c in 0..4 {
                        slots[s] = sign * d[r][c];
                        s += 1;
                    }
                }
                for (row, local_i) in [(fi, [1.0, 0.0, 0.0]), (gi, [0.0, 1.0, 0.0])] {
                    let (local, partner) = if is_i { (local_i, h) } else { (hj, row) };
                    let d = d_rot(p, local);
                    for c in 0..4 {
                        slots[s] = (0..3).map(|x| partner[x] * d[x][c]).sum();
                        s += 1;
                    }
                }
            }
        }
        for b in 0..3 {
            for c in 0..4 {
                slots[s] = 2.0 * q[7 * b + 3 + c];
                s += 1;
            }
        }
    }
}
