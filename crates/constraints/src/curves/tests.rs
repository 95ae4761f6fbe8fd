//! Curve geometry: derivatives against central differences, unit speed and the Frenet closed
//! forms, interpolation, continuity, periodicity, and the refusals of bad data.

use super::*;
use crate::error::ConstraintError;
use crate::marker::Marker;
use approx::assert_relative_eq;
use nalgebra::Vector3;

fn marker() -> Marker {
    Marker::from_axes(
        Vector3::new(0.3, -0.2, 0.5),
        Vector3::new(0.2, 0.4, 1.0),
        Vector3::new(1.0, -0.3, 0.1),
    )
    .unwrap()
}

/// c_u, c_uu, c_uuu against central differences of the next lower derivative.
fn check_derivatives(curve: &Curve, u: f64, h: f64, tol: f64) {
    let (a, b) = (curve.jet(u - h), curve.jet(u + h));
    let j = curve.jet(u);
    let pairs = [
        ((b.c - a.c) / (2.0 * h), j.c_u, "c_u"),
        ((b.c_u - a.c_u) / (2.0 * h), j.c_uu, "c_uu"),
        ((b.c_uu - a.c_uu) / (2.0 * h), j.c_uuu, "c_uuu"),
    ];
    for (fd, exact, what) in pairs {
        let scale = exact.norm().max(1.0);
        assert!(
            (fd - exact).norm() <= tol * scale,
            "{} {what} at u = {u}: exact {exact:?}, differences {fd:?}",
            curve.kind()
        );
    }
}

fn spline_points() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.5, 0.1),
        Vector3::new(1.6, 1.4, -0.2),
        Vector3::new(1.0, 2.2, 0.3),
        Vector3::new(0.1, 1.8, 0.0),
    ]
}

/// n points of the unit circle about z, the first repeated at the end.
fn circle_points(n: usize) -> Vec<Vector3<f64>> {
    let mut pts: Vec<_> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            Vector3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    pts.push(pts[0]);
    pts
}

fn closed_points() -> Vec<Vector3<f64>> {
    let mut p = spline_points();
    p.push(p[0]);
    p
}

#[test]
fn derivatives_agree_with_differences() {
    let m = marker();
    let curves: Vec<Curve> = vec![
        Line::new(&m).into(),
        Circle::new(&m, 0.7).unwrap().into(),
        Helix::new(&m, 0.7, 0.4).unwrap().into(),
        Helix::new(&m, 1.3, -2.0).unwrap().into(),
        CubicCurve::new(spline_points(), false).unwrap().into(),
        CubicCurve::new(closed_points(), true).unwrap().into(),
    ];
    for c in &curves {
        for u in [-7.3, -0.4, 0.05, 0.9, 1.77, 3.1, 11.2] {
            // Away from the knots (the spline's c'_uuu jumps there).
            let near_knot = match c {
                Curve::Cubic(s) => {
                    let l = s.knot_range().1;
                    let w = if s.is_closed() {
                        u - l * (u / l).floor()
                    } else {
                        u
                    };
                    s.knots().iter().any(|k| (k - w).abs() < 1e-3)
                }
                _ => false,
            };
            if !near_knot {
                check_derivatives(c, u, 1e-5, 1e-7);
            }
        }
    }
}

#[test]
fn line_circle_and_helix_have_unit_speed() {
    let m = marker();
    let curves: Vec<Curve> = vec![
        Line::new(&m).into(),
        Circle::new(&m, 0.7).unwrap().into(),
        Helix::new(&m, 0.7, 0.4).unwrap().into(),
    ];
    for c in &curves {
        for u in [-3.0, 0.0, 0.4, 5.0] {
            assert_relative_eq!(c.jet(u).c_u.norm(), 1.0, epsilon = 1e-14);
        }
    }
    let circle = Circle::new(&m, 0.7).unwrap();
    assert_relative_eq!(circle.jet(0.0).c, m.point + m.x() * 0.7, epsilon = 1e-15);
    assert_relative_eq!(
        circle.jet(circle.period()).c,
        circle.jet(0.0).c,
        epsilon = 1e-14
    );
}

/// κ = |c_u × c_uu| / |c_u|³, τ = (c_u × c_uu)·c_uuu / |c_u × c_uu|² against R / k², (h/2π) / k².
#[test]
fn helix_curvature_and_torsion_are_the_frenet_closed_forms() {
    let m = marker();
    for (r, pitch) in [(0.7, 0.4), (1.3, -2.0), (0.05, 3.0)] {
        let h = Helix::new(&m, r, pitch).unwrap();
        let rise = pitch / std::f64::consts::TAU;
        let k2 = r * r + rise * rise;
        assert_relative_eq!(h.curvature(), r / k2, max_relative = 1e-15);
        assert_relative_eq!(h.torsion(), rise / k2, max_relative = 1e-15);
        for u in [0.0, 0.8, -2.5] {
            let j = h.jet(u);
            let b = j.c_u.cross(&j.c_uu);
            assert_relative_eq!(
                b.norm() / j.c_u.norm().powi(3),
                r / k2,
                max_relative = 1e-13
            );
            assert_relative_eq!(
                b.dot(&j.c_uuu) / b.norm_squared(),
                rise / k2,
                max_relative = 1e-12
            );
        }
        // One turn rises by the pitch.
        let turn = std::f64::consts::TAU * k2.sqrt();
        assert_relative_eq!(
            (h.jet(turn).c - h.jet(0.0).c),
            m.z() * pitch,
            epsilon = 1e-14
        );
    }
}

#[test]
fn a_spline_interpolates_its_points_and_is_c2_at_its_knots() {
    for (points, closed) in [(spline_points(), false), (closed_points(), true)] {
        let s = CubicCurve::new(points.clone(), closed).unwrap();
        for (k, p) in points.iter().enumerate() {
            assert_relative_eq!(s.jet(s.knots()[k]).c, *p, epsilon = 1e-14);
        }
        let n = s.knots().len() - 1;
        let knots: Vec<f64> = s.knots().to_vec();
        for &u in &knots[1..n] {
            let (a, b) = (s.jet(u - 1e-9), s.jet(u + 1e-9));
            assert_relative_eq!(a.c_u, b.c_u, epsilon = 1e-7);
            assert_relative_eq!(a.c_uu, b.c_uu, epsilon = 1e-7);
        }
        if closed {
            // Periodic: value, tangent and curvature vector meet across the seam.
            let l = s.knot_range().1;
            let (a, b) = (s.jet(l - 1e-9), s.jet(1e-9));
            assert_relative_eq!(a.c, b.c, epsilon = 1e-8);
            assert_relative_eq!(a.c_u, b.c_u, epsilon = 1e-7);
            assert_relative_eq!(a.c_uu, b.c_uu, epsilon = 1e-7);
            assert_relative_eq!(s.jet(0.37 + 3.0 * l).c, s.jet(0.37).c, epsilon = 1e-12);
            assert_relative_eq!(s.jet(0.37 - 2.0 * l).c, s.jet(0.37).c, epsilon = 1e-12);
        } else {
            // Natural ends, and the straight continuation beyond them.
            assert_relative_eq!(s.jet(0.0).c_uu, Vector3::zeros(), epsilon = 1e-14);
            let (end, j) = (s.knot_range().1, s.jet(s.knot_range().1));
            assert_relative_eq!(j.c_uu, Vector3::zeros(), epsilon = 1e-12);
            assert_relative_eq!(s.jet(end + 0.5).c, j.c + j.c_u * 0.5, epsilon = 1e-14);
            assert_eq!(s.jet(-0.5).c_uu, Vector3::zeros());
        }
    }
}

/// Points on a straight line make the straight line, parametrized by arc length.
#[test]
fn collinear_points_make_the_straight_line() {
    let d = Vector3::new(1.0, 2.0, -2.0) / 3.0;
    let pts: Vec<_> = [0.0, 0.5, 1.7, 2.0, 3.1]
        .iter()
        .map(|&a| Vector3::new(1.0, 1.0, 1.0) + d * a)
        .collect();
    let s = CubicCurve::new(pts, false).unwrap();
    for u in [0.1, 1.0, 2.9] {
        let j = s.jet(u);
        assert_relative_eq!(j.c, Vector3::new(1.0, 1.0, 1.0) + d * u, epsilon = 1e-14);
        assert_relative_eq!(j.c_u, d, epsilon = 1e-14);
        assert_relative_eq!(j.c_uu.norm(), 0.0, epsilon = 1e-13);
    }
}

/// The periodic spline through n points of a unit circle (a cam profile given as a table)
/// converges to the circle at the cubic's orders: the radial deviation as h⁴, the curvature as
/// h² (each halving of the spacing divides them by about 16 and 4), and at 36 points (10°) they
/// are below 1e-5 and 3e-3.
#[test]
fn a_closed_spline_through_points_of_a_circle_converges_to_the_circle() {
    let errors = |n: usize| {
        let s = CubicCurve::new(circle_points(n), true).unwrap();
        let l = s.knot_range().1;
        let (mut radial, mut curvature) = (0.0f64, 0.0f64);
        for k in 0..2000 {
            let j = s.jet(l * k as f64 / 2000.0);
            radial = radial.max((j.c.norm() - 1.0).abs());
            let kappa = j.c_u.cross(&j.c_uu).norm() / j.c_u.norm().powi(3);
            curvature = curvature.max((kappa - 1.0).abs());
        }
        (radial, curvature)
    };
    let (r36, k36) = errors(36);
    let (r72, k72) = errors(72);
    let (r144, k144) = errors(144);
    eprintln!("radial {r36:.2e} {r72:.2e} {r144:.2e}, curvature {k36:.2e} {k72:.2e} {k144:.2e}");
    assert!(r36 < 1e-5 && k36 < 3e-3, "{r36} {k36}");
    for (coarse, fine, order) in [
        (r36, r72, 16.0),
        (r72, r144, 16.0),
        (k36, k72, 4.0),
        (k72, k144, 4.0),
    ] {
        let ratio = coarse / fine;
        assert!(
            (0.75 * order..1.25 * order).contains(&ratio),
            "ratio {ratio} for order {order}"
        );
    }
}

fn curve_error(e: ConstraintError) -> String {
    match e {
        ConstraintError::Curve(m) => m,
        other => panic!("not a curve error: {other}"),
    }
}

#[test]
fn bad_curve_data_is_refused_with_what_to_do() {
    let p = spline_points();
    let one = CubicCurve::new(p[..1].to_vec(), false).unwrap_err();
    assert!(curve_error(one).contains("at least 2 points, got 1"));
    let mut repeated = p.clone();
    repeated.insert(2, p[1]);
    let m = curve_error(CubicCurve::new(repeated, false).unwrap_err());
    assert!(m.contains("points[1] and points[2] coincide"), "{m}");
    assert!(m.contains("remove the repeated point"), "{m}");
    let open_ends = curve_error(CubicCurve::new(p.clone(), true).unwrap_err());
    assert!(
        open_ends.contains("must end where it starts"),
        "{open_ends}"
    );
    assert!(open_ends.contains("repeat the first point"), "{open_ends}");
    let few = curve_error(CubicCurve::new(vec![p[0], p[1], p[0]], true).unwrap_err());
    assert!(few.contains("at least 4 points"), "{few}");
    let mut nan = p.clone();
    nan[3].y = f64::NAN;
    assert!(matches!(
        CubicCurve::new(nan, false),
        Err(ConstraintError::NotFinite { .. })
    ));
    let m = marker();
    assert!(Circle::new(&m, 0.0).is_err());
    assert!(Helix::new(&m, 1.0, 0.0).is_err());
    assert!(Helix::new(&m, -1.0, 1.0).is_err());
}

/// The nearest curve point of a point placed off the curve along the normal plane.
#[test]
fn closest_finds_the_nearest_parameter() {
    let m = marker();
    let curves: Vec<Curve> = vec![
        Line::new(&m).into(),
        Circle::new(&m, 0.7).unwrap().into(),
        Helix::new(&m, 0.7, 0.4).unwrap().into(),
        CubicCurve::new(spline_points(), false).unwrap().into(),
        CubicCurve::new(closed_points(), true).unwrap().into(),
    ];
    for c in &curves {
        for u in [0.3, 1.1, 2.05] {
            let j = c.jet(u);
            // A small offset perpendicular to the tangent, toward the concave side or not.
            let n = j.c_u.cross(&Vector3::new(0.3, -0.7, 0.2)).normalize() * 0.01;
            let found = c.closest(&(j.c + n));
            let p = c.period().unwrap_or(f64::INFINITY);
            let diff = (found - u).abs().min((found - u).abs() % p);
            assert!(diff < 1e-6, "{} at {u}: found {found}", c.kind());
        }
    }
}

/// ∫ₐᵇ |c'_u| by composite Simpson with `n` (even) intervals: an independent reference.
fn simpson_length(c: &CubicCurve, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let f = |u: f64| c.jet(u).c_u.norm();
    let inner: f64 = (1..n)
        .map(|k| f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    (f(a) + f(b) + inner) * h / 3.0
}

/// The arc length table against Simpson's rule on 2·10⁵ intervals per knot span (whose error,
/// h⁴ |f''''|, is below 1e-13 here), across knots, beyond an open spline's ends (straight at
/// the end speed) and over the turns of a closed one; S_u = |c'_u| and S_uu against differences.
#[test]
fn arc_length_agrees_with_simpson_and_its_derivatives_with_differences() {
    let cases = [(spline_points(), false), (closed_points(), true)];
    for ((points, closed), quintic) in cases
        .iter()
        .cloned()
        .flat_map(|c| [(c.clone(), false), (c, true)])
    {
        let c = match quintic {
            true => CubicCurve::quintic(points, closed).unwrap(),
            false => CubicCurve::new(points, closed).unwrap(),
        };
        let arc = ArcLength::new(&c);
        let k = c.knots().to_vec();
        let n = k.len() - 1;
        let mut reference = 0.0;
        for s in 0..n {
            let mid = 0.5 * (k[s] + k[s + 1]);
            let at_mid = reference + simpson_length(&c, k[s], mid, 200_000);
            assert!(
                (arc.eval(mid).0 - at_mid).abs() < 1e-12,
                "{} {at_mid}",
                arc.eval(mid).0
            );
            reference += simpson_length(&c, k[s], k[s + 1], 200_000);
            assert!((arc.eval(k[s + 1]).0 - reference).abs() < 1e-12);
        }
        assert!((arc.total() - reference).abs() < 1e-12);
        let end = k[n];
        if closed {
            let (s, _, _) = arc.eval(2.0 * end + 0.3 * k[1]);
            assert!((s - 2.0 * reference - arc.eval(0.3 * k[1]).0).abs() < 1e-12);
            let (s, _, _) = arc.eval(-end + 0.3 * k[1]);
            assert!((s + reference - arc.eval(0.3 * k[1]).0).abs() < 1e-12);
        } else {
            let beyond = simpson_length(&c, end, end + 0.5, 200_000);
            let d = arc.eval(end + 0.5).0 - reference - beyond;
            assert!(d.abs() < 1e-11, "beyond the end: {d:e} (quintic {quintic})");
            let before = simpson_length(&c, -0.3, 0.0, 200_000);
            assert!((arc.eval(-0.3).0 + before).abs() < 1e-11);
        }
        for u in [0.1 * end, 0.37 * end, 0.81 * end] {
            let h = 1e-5;
            let (s, s_u, s_uu) = arc.eval(u);
            assert!((s_u - c.jet(u).c_u.norm()).abs() < 1e-15);
            let fd = (arc.eval(u + h).0 - arc.eval(u - h).0) / (2.0 * h);
            assert!((fd - s_u).abs() < 1e-8, "{fd} {s_u} {s}");
            let fd2 = (arc.eval(u + h).1 - arc.eval(u - h).1) / (2.0 * h);
            assert!((fd2 - s_uu).abs() < 1e-7, "{fd2} {s_uu}");
        }
    }
}

/// The quintic spline interpolates its points, is C⁴ at its knots (c' to c'''' from the left and
/// the right agree; c'''' by differences of c'''), has the natural quintic's ends c''' = 0, and
/// its jet agrees with differences, open and closed (across the seam too).
#[test]
fn a_quintic_spline_interpolates_and_is_c4_at_its_knots() {
    for closed in [false, true] {
        let pts = if closed {
            closed_points()
        } else {
            spline_points()
        };
        let s = CubicCurve::quintic(pts.clone(), closed).unwrap();
        assert_eq!(s.degree(), 5);
        let curve: Curve = s.clone().into();
        assert_eq!(
            curve.kind(),
            if closed { "quintic_closed" } else { "quintic" }
        );
        let k = s.knots().to_vec();
        for (i, p) in pts.iter().enumerate() {
            assert!((s.jet(k[i]).c - p).norm() < 1e-13, "point {i}");
        }
        let e = 1e-7;
        let inner: Vec<usize> = if closed {
            (0..k.len()).collect()
        } else {
            (1..k.len() - 1).collect()
        };
        for i in inner {
            let (l, r) = (s.jet(k[i] - e), s.jet(k[i] + e));
            assert!((l.c_u - r.c_u).norm() < 1e-5, "c' at knot {i}");
            assert!((l.c_uu - r.c_uu).norm() < 1e-5, "c'' at knot {i}");
            assert!((l.c_uuu - r.c_uuu).norm() < 1e-5, "c''' at knot {i}");
            // c'''' from each side by one-sided differences of c'''.
            let h = 1e-4;
            let left = (s.jet(k[i] - e).c_uuu - s.jet(k[i] - h).c_uuu) / (h - e);
            let right = (s.jet(k[i] + h).c_uuu - s.jet(k[i] + e).c_uuu) / (h - e);
            assert!(
                (left - right).norm() < 1e-2 * left.norm().max(1.0),
                "c'''' at knot {i}"
            );
        }
        if !closed {
            let end = k[k.len() - 1];
            assert!(s.jet(0.0).c_uuu.norm() < 1e-10 && s.jet(end).c_uuu.norm() < 1e-10);
            // Beyond the ends: the quadratic Taylor polynomial, C² with the inside.
            let (a, b) = (s.jet(end - 1e-9), s.jet(end + 1e-9));
            assert!((a.c_uu - b.c_uu).norm() < 1e-6);
        }
        for u in [0.13, 0.77, 1.9, 2.6, -0.4, 4.2] {
            check_derivatives(&curve, u * k[k.len() - 1] / 3.0, 1e-5, 1e-6);
        }
    }
}

/// Through points of a circle the quintic closed spline converges as h⁶ (radial error), far
/// faster than the cubic's h⁴, and points on a line give the line.
#[test]
fn a_quintic_through_circle_points_converges_as_h6_and_collinear_points_give_the_line() {
    let radial = |n: usize| {
        let s = CubicCurve::quintic(circle_points(n), true).unwrap();
        let l = s.knot_range().1;
        (0..2000)
            .map(|k| (s.jet(l * k as f64 / 2000.0).c.norm() - 1.0).abs())
            .fold(0.0f64, f64::max)
    };
    let (r12, r24) = (radial(12), radial(24));
    eprintln!("quintic circle radial error: 12 points {r12:.2e}, 24 points {r24:.2e}");
    let ratio = r12 / r24;
    assert!((0.75 * 64.0..1.25 * 64.0).contains(&ratio), "ratio {ratio}");
    let pts: Vec<_> = (0..5)
        .map(|k| Vector3::new(0.3 * k as f64, 0.1 * k as f64, -0.2 * k as f64))
        .collect();
    let s = CubicCurve::quintic(pts, false).unwrap();
    let dir = Vector3::new(0.3, 0.1, -0.2).normalize();
    for u in [0.05, 0.3, 0.61, 0.9] {
        let j = s.jet(u);
        assert!((j.c - dir * u).norm() < 1e-14 && (j.c_u - dir).norm() < 1e-13);
    }
}
