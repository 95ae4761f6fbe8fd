//! The conformance suite: one set of finite-difference checks that every primitive, joint and
//! driver must pass. A new element is checked by one call of [`run`] (one line in
//! `tests/conformance.rs`).
//!
//! For each case (a configuration of bodies i and j, either possibly ground, with velocities and
//! a time) it compares the analytic quantities with independent numerical ones:
//!
//! | quantity | reference |
//! |---|---|
//! | Φ_q | 4th-order central differences of Φ in each of the 14 coordinates |
//! | Φ_v | 4th-order central differences of Φ(r, p ⊗ exp(ε e_k/2)) (body-frame rotation) |
//! | ν | −∂Φ/∂t by 4th-order central differences |
//! | γ# (7-coordinate) | −d²/dτ² Φ(q + q̇τ, t + τ), 5-point stencil (constant q̇: q̈ = 0) |
//! | γ# (6-coordinate) | −d²/dτ² Φ(r + ṙτ, p ⊗ exp(ω'τ/2), t + τ) (constant ṙ and ω') |
//! | footprint | every column with a nonzero finite-difference derivative lies inside it, and the analytic Jacobian is exactly zero outside it |
//!
//! The γ# references use only Φ, never Φ_q, so an error in the Jacobian cannot hide one in γ#.
//! Cases: curated ones (identity, e0 = 0, 90° turns about coordinate axes, axis-aligned vectors,
//! ground on either side, sizes 1e-3 and 1e3, unnormalized p for the 7-coordinate form) plus
//! seeded random ones. Each mismatch names element, case, quantity, row, column, got and want.

use crate::constraint::{Constraint, MAX_EXTRA};
use crate::joints::{Joint, JointKind, JointParams};
use crate::marker::Marker;
use crate::state::{BodyPair, BodyState, Footprint};
use crate::time_function::TimeFunction;
use cardan_eulerparam::{p_from_euler_123, EulerParams};
use nalgebra::{Matrix3, Vector3, Vector4};
use std::fmt;

/// A small deterministic generator (SplitMix64), so the suite needs no `rand` dependency and a
/// failing case is reproduced from its seed.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    /// Uniform integer in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Draws the parameters of an element (vectors, markers, lengths, time functions) for one case.
///
/// In axis-aligned mode every vector lies along a coordinate axis and every marker frame is a
/// signed permutation of the identity: the degenerate inputs where row selections and
/// perpendicular constructions are most likely to fail.
#[derive(Debug, Clone)]
pub struct Sampler {
    /// The random source.
    pub rng: Rng,
    /// Characteristic size of points and lengths (1e-3, 1 or 1e3 in the curated cases).
    pub scale: f64,
    /// Draw axis-aligned vectors and frames.
    pub axis_aligned: bool,
    function_kind: usize,
    /// The case's time: breakpoints of drawn time functions (ramp ends, spline knots, where f'''
    /// jumps) are kept ≥ 0.05 s away from it, so the finite-difference stencils never straddle
    /// one. (The oracle covers evaluation exactly at breakpoints.)
    pub avoid_t: f64,
    /// The extra coordinates u an element's `make` chose (a curve parameter kept away from a
    /// spline's knots, where c'_uuu jumps); [`run`] draws them when `None`.
    pub extra: Option<[f64; MAX_EXTRA]>,
    /// The scale of each extra coordinate, for its rate (a bicubic patch's parameters are
    /// dimensionless); `None`: the sampler's scale.
    pub extra_scale: Option<[f64; MAX_EXTRA]>,
}

impl Sampler {
    /// A sampler with the given seed, size and mode.
    pub fn new(seed: u64, scale: f64, axis_aligned: bool) -> Self {
        let mut rng = Rng::new(seed);
        let function_kind = rng.below(5);
        Self {
            rng,
            scale,
            axis_aligned,
            function_kind,
            avoid_t: f64::NAN,
            extra: None,
            extra_scale: None,
        }
    }

    fn axis(&mut self) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        v[self.rng.below(3)] = if self.rng.below(2) == 0 { 1.0 } else { -1.0 };
        v
    }

    /// A direction (unit length) — random, or along a coordinate axis.
    pub fn direction(&mut self) -> Vector3<f64> {
        if self.axis_aligned {
            return self.axis();
        }
        loop {
            let v = Vector3::new(
                self.rng.uniform(-1.0, 1.0),
                self.rng.uniform(-1.0, 1.0),
                self.rng.uniform(-1.0, 1.0),
            );
            let n = v.norm();
            if (0.2..=1.0).contains(&n) {
                return v / n;
            }
        }
    }

    /// A point vector of size ~`scale`.
    pub fn point(&mut self) -> Vector3<f64> {
        if self.axis_aligned {
            return self.axis() * self.scale;
        }
        Vector3::new(
            self.rng.uniform(-1.0, 1.0),
            self.rng.uniform(-1.0, 1.0),
            self.rng.uniform(-1.0, 1.0),
        ) * self.scale
    }

    /// A positive length ~`scale`.
    pub fn length(&mut self) -> f64 {
        self.scale * self.rng.uniform(0.5, 2.0)
    }

    /// A marker: a point and a right-handed orthonormal frame.
    pub fn marker(&mut self) -> Marker {
        let point = self.point();
        let frame = if self.axis_aligned {
            let z = self.axis();
            let mut x = self.axis();
            while x.dot(&z).abs() > 0.5 {
                x = self.axis();
            }
            Matrix3::from_columns(&[x, z.cross(&x), z])
        } else {
            self.rotation()
        };
        Marker { point, frame }
    }

    /// A joint of `kind` on sampled markers, with a sampled length, offset and angle when the
    /// kind takes them.
    pub fn joint(&mut self, kind: JointKind) -> Joint {
        let info = kind.info();
        let (mi, mj) = (self.marker(), self.marker());
        let mut params = JointParams::default();
        if info.length {
            params.length = self.length();
        }
        if info.offset {
            params.offset = self.scale * self.rng.uniform(-1.0, 1.0);
        }
        if info.angle {
            params.angle = self.rng.uniform(-3.2, 3.2);
        }
        Joint::with_params(kind, mi, mj, params).expect("sampled markers and numbers are valid")
    }

    /// A random rotation matrix.
    pub fn rotation(&mut self) -> Matrix3<f64> {
        random_unit_p(&mut self.rng).a()
    }

    /// A time function of size ~`scale` (a length); successive calls cycle through all five
    /// kinds.
    pub fn function(&mut self) -> TimeFunction {
        self.function_of_size(self.scale)
    }

    /// A time function of size ~1 (an angle in rad).
    pub fn angle_function(&mut self) -> TimeFunction {
        self.function_of_size(1.0)
    }

    fn function_of_size(&mut self, s: f64) -> TimeFunction {
        self.function_kind = (self.function_kind + 1) % 5;
        let avoid = self.avoid_t;
        let away = |x: f64| match x - avoid {
            d if d.abs() >= 0.05 => x,
            d if d >= 0.0 => avoid + 0.05,
            _ => avoid - 0.05,
        };
        let r = &mut self.rng;
        match self.function_kind {
            0 => TimeFunction::Constant(r.uniform(-1.0, 1.0) * s),
            1 => TimeFunction::Polynomial(vec![
                r.uniform(-1.0, 1.0) * s,
                r.uniform(-1.0, 1.0) * s,
                r.uniform(-1.0, 1.0) * s,
                r.uniform(-0.5, 0.5) * s,
            ]),
            2 => TimeFunction::Harmonic {
                amplitude: r.uniform(0.1, 1.0) * s,
                frequency: r.uniform(0.5, 7.0),
                phase: r.uniform(-3.0, 3.0),
                offset: r.uniform(-1.0, 1.0) * s,
            },
            3 => TimeFunction::Ramp {
                t0: away(r.uniform(0.0, 0.5)),
                t1: away(r.uniform(0.8, 1.5)),
                f0: r.uniform(-1.0, 1.0) * s,
                f1: r.uniform(-1.0, 1.0) * s,
            },
            _ => {
                // Knots 0.3 apart, shifted so that none is within 0.05 of the case time.
                let mut off = 0.0;
                while (0..6).any(|k| (k as f64 * 0.3 + off - avoid).abs() < 0.05) {
                    off += 0.06;
                }
                let t: Vec<f64> = (0..6).map(|k| k as f64 * 0.3 + off).collect();
                let f = t.iter().map(|_| r.uniform(-1.0, 1.0) * s).collect();
                TimeFunction::spline(t, f).expect("valid knots")
            }
        }
    }
}

fn random_unit_p(rng: &mut Rng) -> EulerParams {
    loop {
        let v = Vector4::new(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        );
        let n = v.norm();
        if (0.2..=1.0).contains(&n) {
            return EulerParams::from_vector(v / n);
        }
    }
}

/// Which body of a case is ground.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ground {
    /// Both bodies move.
    None,
    /// Body i is ground.
    I,
    /// Body j is ground.
    J,
}

/// One configuration at which an element is checked.
#[derive(Debug, Clone)]
pub struct Case {
    /// A name that identifies the case in messages ("curated identity", "random seed 17", ...).
    pub label: String,
    /// Body i.
    pub i: BodyState,
    /// Body j.
    pub j: BodyState,
    /// Which body is ground (its columns are not checked, its state is [`BodyState::ground`]).
    pub ground: Ground,
    /// Time.
    pub t: f64,
    /// Both p have unit length and ṗ = ½ Lᵀ ω' (6-coordinate checks run only then).
    pub normalized: bool,
    /// The element's extra coordinates u (the first [`Constraint::extra`] are used; drawn by
    /// [`run`] for an element that has any).
    pub u: [f64; MAX_EXTRA],
    /// Their rates u̇.
    pub u_dot: [f64; MAX_EXTRA],
}

impl Case {
    /// The pair at this case, with `c`'s extra coordinates.
    pub fn pair<C: Constraint>(&self, c: &C) -> BodyPair<'_> {
        let n = c.extra();
        BodyPair::with_extra(&self.i, &self.j, &self.u[..n], &self.u_dot[..n])
    }
}

fn random_body(rng: &mut Rng, scale: f64, p: Option<Vector4<f64>>) -> BodyState {
    let p = p.unwrap_or_else(|| *random_unit_p(rng).as_vector());
    let r = Vector3::new(
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
    ) * scale;
    let rd = Vector3::new(
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
    ) * scale;
    let w = Vector3::new(
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
    );
    BodyState::at(r, p).with_v(rd, w)
}

/// The curated cases plus `n_random` seeded random ones, for an element whose allowed ground
/// sides are `grounds` (e.g. `&[Ground::J]` for single-body elements).
///
/// Returns (case, sampler) pairs: the sampler draws the element's parameters for that case.
pub fn cases(n_random: usize, grounds: &[Ground]) -> Vec<(Case, Sampler)> {
    let mut out = Vec::new();
    let pick_ground = |k: usize| grounds[k % grounds.len()];
    let half = std::f64::consts::FRAC_PI_2;
    let curated_p: [(&str, Vector4<f64>); 6] = [
        ("identity", Vector4::new(1.0, 0.0, 0.0, 0.0)),
        ("e0 = 0 (180° about x)", Vector4::new(0.0, 1.0, 0.0, 0.0)),
        (
            "e0 = 0 (180° about [0,1,1])",
            Vector4::new(0.0, 0.0, 0.5f64.sqrt(), 0.5f64.sqrt()),
        ),
        (
            "90° about z",
            *p_from_euler_123(0.0, 0.0, half).unwrap().as_vector(),
        ),
        (
            "90° about y",
            *p_from_euler_123(0.0, half, 0.0).unwrap().as_vector(),
        ),
        (
            "−p of 120° about [1,1,1]",
            Vector4::new(-0.5, -0.5, -0.5, -0.5),
        ),
    ];
    let mut k = 0usize;
    for (scale, scale_name) in [(1.0, "size 1"), (1e-3, "size 1e-3"), (1e3, "size 1e3")] {
        for (axis_aligned, mode) in [(true, "axis-aligned"), (false, "general")] {
            for (pn, p) in &curated_p {
                let seed = 1000 + k as u64;
                let mut rng = Rng::new(seed);
                let i = random_body(&mut rng, scale, Some(*p));
                let j = random_body(
                    &mut rng,
                    scale,
                    Some(curated_p[(k + 1) % curated_p.len()].1),
                );
                let ground = pick_ground(k);
                out.push(make_case(
                    format!("curated {pn}, {mode}, {scale_name}, ground {ground:?}"),
                    i,
                    j,
                    ground,
                    rng.uniform(0.0, 2.0),
                    true,
                    Sampler::new(seed, scale, axis_aligned),
                ));
                k += 1;
            }
        }
    }
    for n in 0..4 {
        let seed = 5000 + n;
        let mut rng = Rng::new(seed);
        let mut i = random_body(&mut rng, 1.0, None);
        let mut j = random_body(&mut rng, 1.0, None);
        i = BodyState::at(i.r, i.p * 1.3).with_q_dot(i.r_dot, i.p_dot + Vector4::repeat(0.1));
        j = BodyState::at(j.r, j.p * 0.8).with_q_dot(j.r_dot, j.p_dot - Vector4::repeat(0.2));
        out.push(make_case(
            format!("curated unnormalized p (seed {seed})"),
            i,
            j,
            pick_ground(n as usize),
            rng.uniform(0.0, 2.0),
            false,
            Sampler::new(seed, 1.0, false),
        ));
    }
    for n in 0..n_random {
        let seed = 9000 + n as u64;
        out.push(random_case(seed, grounds));
    }
    out
}

/// One random case from a seed (for proptest and reproduction).
pub fn random_case(seed: u64, grounds: &[Ground]) -> (Case, Sampler) {
    let mut rng = Rng::new(seed);
    let scale = [1.0, 1e-3, 1e3, 0.1][rng.below(4)];
    let i = random_body(&mut rng, scale, None);
    let j = random_body(&mut rng, scale, None);
    let ground = grounds[rng.below(grounds.len())];
    let t = rng.uniform(0.0, 2.0);
    make_case(
        format!("random seed {seed}, ground {ground:?}"),
        i,
        j,
        ground,
        t,
        true,
        Sampler::new(seed ^ 0xABCD, scale, false),
    )
}

fn make_case(
    label: String,
    mut i: BodyState,
    mut j: BodyState,
    ground: Ground,
    t: f64,
    normalized: bool,
    s: Sampler,
) -> (Case, Sampler) {
    let mut s = s;
    s.avoid_t = t;
    match ground {
        Ground::I => i = BodyState::ground(),
        Ground::J => j = BodyState::ground(),
        Ground::None => {}
    }
    (
        Case {
            label,
            i,
            j,
            ground,
            t,
            normalized,
            u: [0.0; MAX_EXTRA],
            u_dot: [0.0; MAX_EXTRA],
        },
        s,
    )
}

/// One disagreement between an analytic quantity and its numerical reference.
#[derive(Debug, Clone)]
pub struct Mismatch {
    /// Element name.
    pub element: &'static str,
    /// Case label.
    pub case: String,
    /// "phi_q", "phi_v", "nu", "gamma_q", "gamma_v" or "footprint".
    pub quantity: &'static str,
    /// Row.
    pub row: usize,
    /// Column (for Jacobians; columns 0..N body i, N..2N body j).
    pub col: Option<usize>,
    /// Analytic value.
    pub got: f64,
    /// Numerical reference.
    pub want: f64,
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} [{}] {} row {}",
            self.element, self.case, self.quantity, self.row
        )?;
        if let Some(c) = self.col {
            write!(f, " col {c}")?;
        }
        write!(f, ": got {:.12e}, want {:.12e}", self.got, self.want)
    }
}

const MAX_ROWS: usize = 8;

struct Eval<'c, C: Constraint> {
    c: &'c C,
    case: &'c Case,
    out: Vec<Mismatch>,
    /// The case's natural magnitude of rates: max over rows of Σ |Φ_q| |q̇| and |Φ|; the
    /// absolute floor of the ν and γ# comparisons (which can be legitimately zero).
    rate_scale: f64,
    /// Magnitude of the terms that make up Φ: max over rows of |Φ| and Σ |Φ_q| |q|. Finite
    /// differences lose about ε·T/h (first) and ε·T/h² (second derivative) to round-off.
    term_scale: f64,
}

const EPS: f64 = f64::EPSILON;

/// Φ at modified bodies and extra coordinates `u`.
fn phi_at<C: Constraint>(
    c: &C,
    i: &BodyState,
    j: &BodyState,
    u: &[f64],
    t: f64,
) -> [f64; MAX_ROWS] {
    let mut v = [0.0; MAX_ROWS];
    c.phi(
        &BodyPair::with_extra(i, j, u, &[0.0; MAX_EXTRA][..u.len()]),
        t,
        &mut v[..c.rows()],
    );
    v
}

/// u + u̇ τ.
fn u_along(case: &Case, n: usize, tau: f64) -> [f64; MAX_EXTRA] {
    std::array::from_fn(|k| {
        if k < n {
            case.u[k] + case.u_dot[k] * tau
        } else {
            0.0
        }
    })
}

/// 4th-order central first derivative of a vector function of one scalar.
fn d1(f: impl Fn(f64) -> [f64; MAX_ROWS], h: f64) -> [f64; MAX_ROWS] {
    let (a, b, c, d) = (f(-2.0 * h), f(-h), f(h), f(2.0 * h));
    std::array::from_fn(|k| (a[k] - 8.0 * b[k] + 8.0 * c[k] - d[k]) / (12.0 * h))
}

/// 4th-order central second derivative.
fn d2(f: impl Fn(f64) -> [f64; MAX_ROWS], h: f64) -> [f64; MAX_ROWS] {
    let (a, b, z, c, d) = (f(-2.0 * h), f(-h), f(0.0), f(h), f(2.0 * h));
    std::array::from_fn(|k| {
        (-a[k] + 16.0 * b[k] - 30.0 * z[k] + 16.0 * c[k] - d[k]) / (12.0 * h * h)
    })
}

fn rotated(b: &BodyState, axis: usize, angle: f64) -> BodyState {
    let mut e = Vector3::zeros();
    e[axis] = 1.0;
    let dp = EulerParams::from_axis_angle(&e, angle).expect("unit axis");
    let p = EulerParams::from_vector(b.p).compose(&dp);
    BodyState {
        a: p.a(),
        p: *p.as_vector(),
        ..*b
    }
}

fn along_v(b: &BodyState, tau: f64) -> BodyState {
    let w = b.omega_local;
    let n = w.norm();
    let p = if n == 0.0 {
        EulerParams::from_vector(b.p)
    } else {
        EulerParams::from_vector(b.p)
            .compose(&EulerParams::from_axis_angle(&w, n * tau).expect("nonzero"))
    };
    BodyState {
        r: b.r + b.r_dot * tau,
        a: p.a(),
        p: *p.as_vector(),
        ..*b
    }
}

fn along_q(b: &BodyState, tau: f64) -> BodyState {
    let p = b.p + b.p_dot * tau;
    BodyState {
        r: b.r + b.r_dot * tau,
        p,
        a: cardan_eulerparam::a(&p),
        ..*b
    }
}

impl<C: Constraint> Eval<'_, C> {
    fn compare(
        &mut self,
        quantity: &'static str,
        got: &[f64],
        want: &[f64],
        floor: f64,
        rtol: f64,
        cols: Option<usize>,
    ) {
        // Relative to the largest entry of this quantity in this case, with an absolute floor.
        let scale = got
            .iter()
            .chain(want)
            .fold(floor, |m, v| m.max(v.abs()))
            .max(1e-300);
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            let close = (g - w).abs() <= rtol * scale;
            if !close {
                let (row, col) = match cols {
                    Some(n) => (k / n, Some(k % n)),
                    None => (k, None),
                };
                self.out.push(Mismatch {
                    element: self.c.name(),
                    case: self.case.label.clone(),
                    quantity,
                    row,
                    col,
                    got: *g,
                    want: *w,
                });
            }
        }
    }

    fn moving(&self, side: usize) -> bool {
        !matches!((self.case.ground, side), (Ground::I, 0) | (Ground::J, 1))
    }

    /// The case's size: the larger body position (the step of r in the finite differences is
    /// 1e-3 of it, so bodies 1e-3 apart get 1e-6: an element that is not polynomial in r, like
    /// a coupler's angle, needs a step below its size).
    fn length(&self) -> f64 {
        let l = self.case.i.r.amax().max(self.case.j.r.amax());
        if l > 0.0 {
            l
        } else {
            1.0
        }
    }

    fn check_q(&mut self) {
        let (c, case) = (self.c, self.case);
        let m = c.rows();
        let x = case.pair(c);
        let u = x.u;
        let mut ji = vec![[0.0; 7]; m];
        let mut jj = vec![[0.0; 7]; m];
        c.phi_q(&x, case.t, &mut ji, &mut jj);
        let fp = c.footprint();
        // Row-major m × 14 (columns of ground bodies stay zero in both).
        let mut got = vec![0.0; m * 14];
        let mut want = vec![0.0; m * 14];
        for side in 0..2 {
            if !self.moving(side) {
                continue;
            }
            for col in 0..7 {
                let base = if side == 0 { &case.i } else { &case.j };
                let mag = if col < 3 { self.length() } else { 1.0 };
                let h = 1e-3 * mag;
                let fd = d1(
                    |e| {
                        let mut b = *base;
                        if col < 3 {
                            b.r[col] += e;
                        } else {
                            b.p[col - 3] += e;
                            b.a = cardan_eulerparam::a(&b.p);
                        }
                        if side == 0 {
                            phi_at(c, &b, &case.j, u, case.t)
                        } else {
                            phi_at(c, &case.i, &b, u, case.t)
                        }
                    },
                    h,
                );
                for row in 0..m {
                    let g = if side == 0 {
                        ji[row][col]
                    } else {
                        jj[row][col]
                    };
                    got[row * 14 + side * 7 + col] = g;
                    want[row * 14 + side * 7 + col] = fd[row];
                }
                self.footprint_check(fp, side, col < 3, col, &fd[..m], |row| {
                    if side == 0 {
                        ji[row][col]
                    } else {
                        jj[row][col]
                    }
                });
            }
        }
        let noise = 10.0 * EPS * self.term_scale / (1e-3 * self.length()).min(1e-3);
        self.compare("phi_q", &got, &want, noise / 1e-7, 1e-7, Some(14));
        // γ# (7): −Φ̈ along q + q̇ τ, t + τ.
        let mut gq = [0.0; MAX_ROWS];
        c.gamma_sharp_q(&x, case.t, &mut gq[..m]);
        let h = 1e-3 / (case.i.p_dot.amax().max(case.j.p_dot.amax()).max(1.0));
        let fd = d2(
            |tau| {
                phi_at(
                    c,
                    &along_q(&case.i, tau),
                    &along_q(&case.j, tau),
                    &u_along(case, u.len(), tau)[..u.len()],
                    case.t + tau,
                )
            },
            h,
        );
        let want: Vec<f64> = fd[..m].iter().map(|v| -v).collect();
        let floor = self
            .rate_scale
            .max(100.0 * EPS * self.term_scale / (h * h) / 1e-6);
        self.compare("gamma_q", &gq[..m], &want, floor, 1e-6, None);
    }

    fn footprint_check(
        &mut self,
        fp: Footprint,
        side: usize,
        is_r: bool,
        col: usize,
        fd: &[f64],
        analytic: impl Fn(usize) -> f64,
    ) {
        let use_ = if side == 0 { fp.i } else { fp.j };
        let declared = if is_r { use_.r } else { use_.p };
        if declared {
            return;
        }
        for (row, v) in fd.iter().enumerate() {
            let a = analytic(row);
            if *v != 0.0 && v.abs() > 1e-9 || a != 0.0 {
                self.out.push(Mismatch {
                    element: self.c.name(),
                    case: self.case.label.clone(),
                    quantity: "footprint",
                    row,
                    col: Some(col + side * 7),
                    got: a,
                    want: *v,
                });
            }
        }
    }

    fn check_v(&mut self) {
        let (c, case) = (self.c, self.case);
        let m = c.rows();
        let x = case.pair(c);
        let u = x.u;
        let mut ji = vec![[0.0; 6]; m];
        let mut jj = vec![[0.0; 6]; m];
        c.phi_v(&x, case.t, &mut ji, &mut jj);
        let mut got = vec![0.0; m * 12];
        let mut want = vec![0.0; m * 12];
        for side in 0..2 {
            if !self.moving(side) {
                continue;
            }
            let base = if side == 0 { &case.i } else { &case.j };
            for col in 0..6 {
                let h = if col < 3 { 1e-3 * self.length() } else { 1e-3 };
                let fd = d1(
                    |e| {
                        let b = if col < 3 {
                            let mut b = *base;
                            b.r[col] += e;
                            b
                        } else {
                            rotated(base, col - 3, e)
                        };
                        if side == 0 {
                            phi_at(c, &b, &case.j, u, case.t)
                        } else {
                            phi_at(c, &case.i, &b, u, case.t)
                        }
                    },
                    h,
                );
                for row in 0..m {
                    got[row * 12 + side * 6 + col] = if side == 0 {
                        ji[row][col]
                    } else {
                        jj[row][col]
                    };
                    want[row * 12 + side * 6 + col] = fd[row];
                }
            }
        }
        let noise = 10.0 * EPS * self.term_scale / (1e-3 * self.length()).min(1e-3);
        self.compare("phi_v", &got, &want, noise / 1e-7, 1e-7, Some(12));
        let mut gv = [0.0; MAX_ROWS];
        c.gamma_sharp_v(&x, case.t, &mut gv[..m]);
        let rate = case
            .i
            .omega_local
            .amax()
            .max(case.j.omega_local.amax())
            .max(1.0);
        let h = 1e-3 / rate;
        let fd = d2(
            |tau| {
                phi_at(
                    c,
                    &along_v(&case.i, tau),
                    &along_v(&case.j, tau),
                    &u_along(case, u.len(), tau)[..u.len()],
                    case.t + tau,
                )
            },
            h,
        );
        let want: Vec<f64> = fd[..m].iter().map(|v| -v).collect();
        let floor = self
            .rate_scale
            .max(100.0 * EPS * self.term_scale / (h * h) / 1e-6);
        self.compare("gamma_v", &gv[..m], &want, floor, 1e-6, None);
    }

    /// ∂Φ/∂u against central differences in each extra coordinate.
    fn check_extra(&mut self) {
        let (c, case) = (self.c, self.case);
        let (m, n) = (c.rows(), c.extra());
        let x = case.pair(c);
        let mut ju = [[0.0; MAX_EXTRA]; MAX_ROWS];
        c.jacobian_extra(&x, case.t, &mut ju[..m]);
        let mut got = vec![0.0; m * n];
        let mut want = vec![0.0; m * n];
        let h = 1e-3 * self.length();
        for k in 0..n {
            let fd = d1(
                |e| {
                    let mut u = case.u;
                    u[k] += e;
                    phi_at(c, &case.i, &case.j, &u[..n], case.t)
                },
                h,
            );
            for row in 0..m {
                got[row * n + k] = ju[row][k];
                want[row * n + k] = fd[row];
            }
        }
        let noise = 10.0 * EPS * self.term_scale / h;
        self.compare("phi_u", &got, &want, noise / 1e-7, 1e-7, Some(n));
    }

    fn check_nu(&mut self) {
        let (c, case) = (self.c, self.case);
        let m = c.rows();
        let x = case.pair(c);
        let u = x.u;
        let mut nu = [0.0; MAX_ROWS];
        c.nu(&x, case.t, &mut nu[..m]);
        let fd = d1(|e| phi_at(c, &case.i, &case.j, u, case.t + e), 1e-3);
        let want: Vec<f64> = fd[..m].iter().map(|v| -v).collect();
        let floor = self
            .rate_scale
            .max(10.0 * EPS * self.term_scale / 1e-3 / 1e-7);
        self.compare("nu", &nu[..m], &want, floor, 1e-7, None);
    }
}

/// Runs every check of the suite on `element` at `case`; returns the mismatches (empty = pass).
pub fn check<C: Constraint>(element: &C, case: &Case) -> Vec<Mismatch> {
    assert!(
        element.rows() <= MAX_ROWS,
        "conformance suite supports up to {MAX_ROWS} rows"
    );
    let m = element.rows();
    let x = case.pair(element);
    let mut ji = vec![[0.0; 7]; m];
    let mut jj = vec![[0.0; 7]; m];
    element.phi_q(&x, case.t, &mut ji, &mut jj);
    let mut ju = [[0.0; MAX_EXTRA]; MAX_ROWS];
    element.jacobian_extra(&x, case.t, &mut ju[..m]);
    let extra_rate = |r: usize| {
        (0..element.extra())
            .map(|k| (ju[r][k] * case.u_dot[k]).abs())
            .sum::<f64>()
    };
    let mut phi = [0.0; MAX_ROWS];
    element.phi(&x, case.t, &mut phi[..m]);
    let qd = |b: &BodyState, c: usize| if c < 3 { b.r_dot[c] } else { b.p_dot[c - 3] };
    let rate_scale = (0..m)
        .map(|r| {
            (0..7)
                .map(|c| (ji[r][c] * qd(&case.i, c)).abs() + (jj[r][c] * qd(&case.j, c)).abs())
                .sum::<f64>()
                .max(phi[r].abs())
                .max(extra_rate(r))
        })
        .fold(0.0, f64::max);
    let qv = |b: &BodyState, c: usize| if c < 3 { b.r[c] } else { b.p[c - 3] };
    let term_scale = (0..m)
        .map(|r| {
            (0..7)
                .map(|c| (ji[r][c] * qv(&case.i, c)).abs() + (jj[r][c] * qv(&case.j, c)).abs())
                .sum::<f64>()
                .max(phi[r].abs())
        })
        .fold(0.0, f64::max);
    let mut e = Eval {
        c: element,
        case,
        out: Vec::new(),
        rate_scale,
        term_scale,
    };
    e.check_q();
    e.check_nu();
    if element.extra() > 0 {
        e.check_extra();
    }
    if case.normalized {
        e.check_v();
    }
    e.out
}

/// Builds the element for each case with `make` (which draws its parameters from the case's
/// sampler) and checks it. Returns (number of cases run, all mismatches).
pub fn run<C: Constraint>(
    n_random: usize,
    grounds: &[Ground],
    make: impl Fn(&mut Sampler) -> C,
) -> (usize, Vec<Mismatch>) {
    let cases = cases(n_random, grounds);
    let n = cases.len();
    let mut all = Vec::new();
    for (mut case, mut sampler) in cases {
        let element = make(&mut sampler);
        for k in 0..element.extra() {
            case.u[k] = match sampler.extra {
                Some(u) => u[k],
                None => sampler.rng.uniform(-3.0, 3.0) * sampler.scale,
            };
            let scale = sampler.extra_scale.map_or(sampler.scale, |s| s[k]);
            case.u_dot[k] = sampler.rng.uniform(-2.0, 2.0) * scale;
        }
        all.extend(check(&element, &case));
    }
    (n, all)
}

/// Formats up to `max` mismatches, one per line, for a test failure message.
pub fn report(mismatches: &[Mismatch], max: usize) -> String {
    let mut s = String::new();
    for m in mismatches.iter().take(max) {
        s.push_str(&m.to_string());
        s.push('\n');
    }
    if mismatches.len() > max {
        s.push_str(&format!("... and {} more\n", mismatches.len() - max));
    }
    s
}
