//! The conformance suite applied to every primitive, joint and driver: one line each.
//!
//! See `cardan_constraints::conformance` for what is checked. Each element runs the curated
//! cases plus `RANDOM` seeded random ones; `proptest_random_cases` adds proptest-drawn seeds.

use cardan_constraints::conformance::{self, Ground, Sampler};
use cardan_constraints::*;
use nalgebra::Vector3;
use proptest::prelude::*;

const RANDOM: usize = 30;
const BOTH: &[Ground] = &[Ground::None, Ground::I, Ground::J];
const ONLY_I_MOVES: &[Ground] = &[Ground::J];

fn assert_conforms<C: Constraint>(
    name: &str,
    grounds: &[Ground],
    make: impl Fn(&mut Sampler) -> C,
) {
    let (n, bad) = conformance::run(RANDOM, grounds, make);
    assert!(n >= 50, "{name}: only {n} cases");
    assert!(
        bad.is_empty(),
        "{name}: {} mismatches in {n} cases:\n{}",
        bad.len(),
        conformance::report(&bad, 20)
    );
}

/// Every joint kind of the table (`KINDS`): a kind added there is checked here with no edit.
#[test]
fn every_joint_kind() {
    for info in KINDS {
        assert_conforms(info.name, BOTH, |s: &mut Sampler| s.joint(info.kind));
    }
}

/// A limit on every joint-coordinate measure, lower and upper, its angle continued from a
/// reference several turns away (`Measure::ALL`: a measure added there is checked here).
/// Cases where the coordinate is ill-defined (`JointLimit::definition` below 0.4: the cross
/// angle with z_j nearly along z_i, a bend near 0 or π) are left out, as the couplers' axes.
#[test]
fn every_joint_limit() {
    use cardan_constraints::joints::Measure;
    let mut report = String::new();
    for m in Measure::ALL {
        for bound in [Bound::Lower, Bound::Upper] {
            let (mut n, mut bad) = (0, Vec::new());
            for (case, mut s) in conformance::cases(RANDOM, BOTH) {
                general(&mut s);
                let value = s.rng.uniform(-2.0, 2.0);
                let limit = JointLimit::new(s.marker(), s.marker(), m, bound, value)
                    .with_reference(turns(&mut s));
                let x = BodyPair::new(&case.i, &case.j);
                let length = matches!(m, Measure::Distance | Measure::Azimuth);
                if limit.definition(&x) < 0.4 * if length { s.length() } else { 1.0 } {
                    continue;
                }
                n += 1;
                bad.extend(conformance::check(&limit, &case));
            }
            assert!(n >= 50, "limit_{}: only {n} cases", m.key());
            if !bad.is_empty() {
                report.push_str(&format!(
                    "limit_{} ({}): {} mismatches in {n} cases:\n{}\n",
                    m.key(),
                    bound.name(),
                    bad.len(),
                    conformance::report(&bad, 6)
                ));
            }
        }
    }
    assert!(report.is_empty(), "{report}");
}

/// A random row of a pose driver with a random rotation sequence (all 12 occur).
fn pose_row(s: &mut Sampler) -> PoseDriver {
    const ORDERS: [&str; 12] = [
        "xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz",
    ];
    let order = RotationOrder::parse(ORDERS[s.rng.below(12)]).unwrap();
    let f = [
        s.function(),
        s.function(),
        s.function(),
        s.angle_function(),
        s.angle_function(),
        s.angle_function(),
    ];
    let row = s.rng.below(6);
    PoseDriver::new(s.marker(), s.marker(), order, f, row)
}

macro_rules! conformance_tests {
    ($($test:ident: $grounds:expr, $make:expr;)*) => {$(
        #[test]
        fn $test() {
            assert_conforms(stringify!($test), $grounds, $make);
        }
    )*};
}

conformance_tests! {
    n1: BOTH, |s: &mut Sampler| N1::new(s.direction(), s.direction());
    n2: BOTH, |s: &mut Sampler| N2::new(s.direction(), s.point(), s.point());
    p1: BOTH, |s: &mut Sampler| P1::new(s.direction(), s.direction());
    p1_select: BOTH, |s: &mut Sampler| P1Select::new(s.direction(), s.direction());
    p1_perp: BOTH, |s: &mut Sampler| P1Perp::new(s.direction(), s.direction(), s.direction());
    p2: BOTH, |s: &mut Sampler| P2::new(s.direction(), s.point(), s.point());
    p2_select: BOTH, |s: &mut Sampler| P2Select::new(s.direction(), s.point(), s.point());
    p2_perp: BOTH, |s: &mut Sampler| P2Perp::new(s.direction(), s.direction(), s.point(), s.point());
    spherical_primitive: BOTH, |s: &mut Sampler| Spherical::new(s.point(), s.point());
    distance: BOTH, |s: &mut Sampler| Distance::new(s.point(), s.point(), s.length());
    radial_distance: BOTH, |s: &mut Sampler| RadialDistance::new(s.direction(), s.direction(), s.point(), s.point(), s.length());
    homokinetic: BOTH, |s: &mut Sampler| Homokinetic::new(s.direction(), s.direction(), s.direction(), s.direction());
    normalization: ONLY_I_MOVES, |_: &mut Sampler| Normalization;
    rotation_driver: BOTH, |s: &mut Sampler| RotationDriver::new(s.marker(), s.marker(), s.angle_function());
    translation_driver: BOTH, |s: &mut Sampler| TranslationDriver::new(s.marker(), s.marker(), s.function());
    distance_driver: BOTH, |s: &mut Sampler| DistanceDriver::new(s.point(), s.point(), s.function());
    pose_driver: BOTH, pose_row;
    coordinate_driver: ONLY_I_MOVES, |s: &mut Sampler| CoordinateDriver::new(s.point(), s.rng.below(3), s.function()).unwrap();
    gear: BOTH, sample_gear;
    rack_pinion: BOTH, |s: &mut Sampler| RackPinion::new(general(s).marker(), s.marker(), coefficient(s), s.length() * coefficient(s), s.length(), turns(s));
    screw: BOTH, |s: &mut Sampler| Screw::new(general(s).marker(), s.marker(), coefficient(s), s.length() * coefficient(s), s.length(), turns(s));
}

/// A coupler coefficient of either sign.
fn coefficient(s: &mut Sampler) -> f64 {
    s.rng.uniform(-2.0, 2.0)
}

/// A reference angle several turns away from the principal range, so that the continuation
/// over turns is exercised.
fn turns(s: &mut Sampler) -> f64 {
    s.rng.uniform(-40.0, 40.0)
}

/// A coupler's angle is undefined where x_j ∥ z_i (rack, screw) or d ∥ z_i (gear), which the
/// joints exclude but axis-aligned frames and points on bodies turned by multiples of 90° hit
/// exactly: couplers draw general frames and points.
fn general(s: &mut Sampler) -> &mut Sampler {
    s.axis_aligned = false;
    s
}

fn sample_gear(s: &mut Sampler) -> Gear {
    general(s);
    Gear {
        marker_i: s.marker(),
        marker_j: s.marker(),
        k_i: coefficient(s),
        k_j: coefficient(s),
        constant: s.rng.uniform(-3.0, 3.0),
        reference: [turns(s), turns(s)],
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Random seeds through every element kind (a failure prints the seed, which reproduces it).
    #[test]
    fn proptest_random_cases(seed in any::<u64>()) {
        let (case, mut s) = conformance::random_case(seed, BOTH);
        let mut bad = Vec::new();
        for info in KINDS {
            bad.extend(conformance::check(&s.joint(info.kind), &case));
        }
        bad.extend(conformance::check(&RotationDriver::new(s.marker(), s.marker(), s.angle_function()), &case));
        bad.extend(conformance::check(&DistanceDriver::new(s.point(), s.point(), s.function()), &case));
        prop_assert!(bad.is_empty(), "{}", conformance::report(&bad, 10));
    }
}

/// A curve of kind `kind` (an entry of `Curve::KINDS`) of the sampler's size, and a curve
/// parameter on it at least 1 % of the size away from a spline's knots (where c'_uuu jumps and
/// the stencils would straddle the jump; the oracle covers evaluation at the knots).
fn curve(s: &mut Sampler, kind: &str) -> (Curve, f64) {
    let size = s.scale;
    let m = s.marker();
    let c: Curve = match kind {
        "line" => Line::new(&m).into(),
        "circle" => Circle::new(&m, s.rng.uniform(0.3, 2.0) * size)
            .unwrap()
            .into(),
        "helix" => {
            let sign = if s.rng.below(2) == 0 { 1.0 } else { -1.0 };
            let pitch = sign * s.rng.uniform(0.2, 2.0) * size;
            Helix::new(&m, s.rng.uniform(0.3, 2.0) * size, pitch)
                .unwrap()
                .into()
        }
        _ => {
            let closed = kind.ends_with("_closed");
            let n = 4 + s.rng.below(5);
            let mut pts = vec![s.point()];
            while pts.len() < n {
                let p = s.point();
                let last = pts.len() + 1 == n;
                let apart = |q: Vector3<f64>| (p - q).norm() > 0.2 * size;
                if apart(pts[pts.len() - 1]) && !(closed && last && !apart(pts[0])) {
                    pts.push(p);
                }
            }
            if closed {
                pts.push(pts[0]);
            }
            match kind.starts_with("quintic") {
                true => CubicCurve::quintic(pts, closed).unwrap().into(),
                false => CubicCurve::new(pts, closed).unwrap().into(),
            }
        }
    };
    let knots: Vec<f64> = match &c {
        Curve::Cubic(k) => k.knots().to_vec(),
        _ => Vec::new(),
    };
    let period = c.period();
    loop {
        let u = s.rng.uniform(-3.0, 3.0) * size;
        let w = match (period, &c) {
            (Some(l), Curve::Cubic(_)) => u - l * (u / l).floor(),
            _ => u,
        };
        if knots.iter().all(|k| (k - w).abs() > 0.01 * size) {
            return (c, u);
        }
    }
}

/// A point on each kind of curve, the curve parameter an extra coordinate (Φ_u and γ# with u̇).
#[test]
fn point_on_every_curve_kind() {
    for kind in Curve::KINDS {
        assert_conforms(kind, BOTH, |s: &mut Sampler| {
            let (c, u) = curve(s, kind);
            let mut extra = [0.0; MAX_EXTRA];
            extra[0] = u;
            s.extra = Some(extra);
            PointOnCurve::new(c, s.point())
        });
    }
}

/// A surface of kind `kind` (an entry of `Surface::KINDS`) of the sampler's size and parameters
/// on it (a sphere's latitude within 1.2 rad of its equator, away from the singular poles; a
/// patch's within [−0.2, 1.2]²).
fn surface(s: &mut Sampler, kind: &str) -> (Surface, [f64; 2]) {
    let size = s.scale;
    let m = s.marker();
    let mut r = |lo: f64, hi: f64| s.rng.uniform(lo, hi) * size;
    let (surf, scale): (Surface, [f64; 2]) = match kind {
        "plane" => (Plane::new(&m).into(), [size, size]),
        "sphere" => {
            let radius = r(0.3, 2.0);
            (Sphere::new(&m, radius).unwrap().into(), [radius, radius])
        }
        "cylinder" => {
            let radius = r(0.3, 2.0);
            (Cylinder::new(&m, radius).unwrap().into(), [radius, size])
        }
        "torus" => {
            let big = r(0.8, 2.0);
            let tube = big * s.rng.uniform(0.15, 0.7);
            (Torus::new(&m, big, tube).unwrap().into(), [big, tube])
        }
        _ => {
            let mut pts = [[Vector3::zeros(); 4]; 4];
            for row in pts.iter_mut() {
                for p in row.iter_mut() {
                    *p = s.point();
                }
            }
            (BicubicPatch::new(pts).unwrap().into(), [1.0, 1.0])
        }
    };
    let uv = match kind {
        "sphere" => [
            scale[0] * s.rng.uniform(-8.0, 8.0),
            scale[1] * s.rng.uniform(-1.2, 1.2),
        ],
        "bicubic" => [s.rng.uniform(-0.2, 1.2), s.rng.uniform(-0.2, 1.2)],
        _ => [
            scale[0] * s.rng.uniform(-3.0, 3.0),
            scale[1] * s.rng.uniform(-3.0, 3.0),
        ],
    };
    (surf, uv)
}

/// A point on each kind of surface, u and v extra coordinates (Φ_u, Φ_v and γ# with u̇, v̇).
#[test]
fn point_on_every_surface_kind() {
    for kind in Surface::KINDS {
        assert_conforms(
            &format!("point_on_surface_{kind}"),
            BOTH,
            |s: &mut Sampler| {
                let (surf, uv) = surface(s, kind);
                s.extra = Some(uv);
                if kind == "bicubic" {
                    s.extra_scale = Some([1.0, 1.0]);
                }
                PointOnSurface::new(surf, s.point())
            },
        );
    }
}

/// The planar curve kinds a cam pair takes (every kind but the helix).
const PLANAR: [&str; 6] = [
    "line",
    "circle",
    "cubic",
    "cubic_closed",
    "quintic",
    "quintic_closed",
];

/// Every pair of planar curves in tangent contact, both curve parameters extra coordinates
/// (Φ_u, Φ_w and γ# with u̇ and ẇ); the plane normal is any direction (the equations do not
/// need the curves to lie in the plane).
#[test]
fn curve_on_every_pair_of_curve_kinds() {
    for kind_i in PLANAR {
        for kind_j in PLANAR {
            let name = format!("curve_on_curve_{kind_i}_{kind_j}");
            assert_conforms(&name, BOTH, |s: &mut Sampler| {
                let (ci, u) = curve(s, kind_i);
                let (cj, w) = curve(s, kind_j);
                s.extra = Some([u, w]);
                CurveOnCurve::new(ci, s.direction(), cj).unwrap()
            });
        }
    }
}

/// The path driver along a spline's arc length, S(u) = f(t) (Φ_u = |c'_u|, γ# with S_uu u̇²).
#[test]
fn path_driver_along_a_spline() {
    for kind in ["cubic", "cubic_closed"] {
        assert_conforms(
            &format!("path_driver_arc_{kind}"),
            BOTH,
            |s: &mut Sampler| {
                let (c, u) = curve(s, kind);
                s.extra = Some([u, 0.0]);
                PathDriver::along_arc(s.function(), &c)
            },
        );
    }
}

/// The path driver u = f(t) of a curve parameter (Φ_u = 1, ν = ḟ, γ# = f̈).
#[test]
fn path_driver() {
    assert_conforms("path_driver", BOTH, |s: &mut Sampler| {
        PathDriver::new(s.function())
    });
}
