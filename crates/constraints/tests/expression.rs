//! Expression time functions: parsing (precedence, associativity, errors with their columns),
//! exact derivatives against closed forms and the other time-function kinds, domain errors.

use cardan_constraints::expression::{Expression, ParseError};
use cardan_constraints::TimeFunction;
use proptest::prelude::*;
use std::f64::consts::{E, PI};

fn value(text: &str) -> f64 {
    Expression::parse(text).unwrap().eval(0.0).0
}

fn err(text: &str) -> ParseError {
    Expression::parse(text).expect_err(text)
}

fn close(a: (f64, f64, f64), b: (f64, f64, f64), tol: f64) -> bool {
    let ok = |x: f64, y: f64| (x - y).abs() <= tol * (1.0 + x.abs().max(y.abs()));
    ok(a.0, b.0) && ok(a.1, b.1) && ok(a.2, b.2)
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(value("1 + 2*3"), 7.0);
    assert_eq!(value("(1 + 2)*3"), 9.0);
    assert_eq!(value("-2^2"), -4.0, "unary minus binds looser than ^");
    assert_eq!(value("(-2)^2"), 4.0);
    assert_eq!(value("2^3^2"), 512.0, "^ is right-associative");
    assert_eq!(value("2^-1"), 0.5);
    assert_eq!(value("8/2/2"), 2.0, "/ is left-associative");
    assert_eq!(value("8 - 2 - 2"), 4.0);
    assert_eq!(value("2*-3"), -6.0);
    assert_eq!(value("--3"), 3.0);
    assert_eq!(value("+3"), 3.0);
    assert_eq!(value("1.5e-3"), 1.5e-3);
    assert_eq!(value("2E+2"), 200.0);
    assert_eq!(value(".5 + 1."), 1.5);
    assert_eq!(value("pi"), PI);
    assert_eq!(value("e"), E);
    assert_eq!(value("2*e"), 2.0 * E);
    let f = Expression::parse("time + t").unwrap();
    assert_eq!(f.eval(1.5), (3.0, 2.0, 0.0));
}

#[test]
fn errors_have_columns() {
    let e = err("1 + * 2");
    assert_eq!((e.span.start, e.column("1 + * 2")), (4, 5), "{e}");
    let e = err("sin(t");
    assert!(e.message.contains("never closed"), "{e}");
    assert_eq!(e.span, 3..4);
    let e = err("t t");
    assert_eq!(e.span, 2..3);
    assert!(e.message.contains("expected an operator"), "{e}");
    let e = err("2 $ 3");
    assert_eq!(e.span, 2..3);
    let e = err("1 + sinn(t)");
    assert_eq!((e.span.clone(), e.unknown.as_deref()), (4..8, Some("sinn")));
    let e = err("2*tt");
    assert_eq!(e.unknown.as_deref(), Some("tt"));
    let e = err("atan2(t)");
    assert!(
        e.message.contains("atan2") && e.message.contains("2 arguments"),
        "{e}"
    );
    assert!(e.message.contains("given 1"), "{e}");
    let e = err("piecewise(t, 0, 1)");
    assert!(e.message.contains("piecewise"), "{e}");
    assert!(err("").message.contains("empty"));
    assert!(err("   ").message.contains("empty"));
    let e = err("1 + sqrt(-1)");
    assert_eq!(e.span, 4..12, "{e}");
    let e = err("t/0 + 1/0");
    assert_eq!(e.span, 6..9, "{e}");
    let e = err("step(t, 1, 0, 0, 1)");
    assert!(e.message.contains("x1 > x0"), "{e}");
    let e = err("step(t, t, 0, 1, 1)");
    assert!(e.message.contains("constant"), "{e}");
    let e = err("piecewise(t, 0, 2, 1, 1, 2)");
    assert!(e.message.contains("increase"), "{e}");
    let e = err("spline(t, [0, 1], [0])");
    assert!(e.message.contains("spline"), "{e}");
    let e = err("spline(t, 0, 1)");
    assert!(e.message.contains("list"), "{e}");
    let e = err("[1, 2]");
    assert!(e.message.contains("list"), "{e}");
    let e = err("sin t");
    assert!(e.message.contains("parentheses"), "{e}");
    let e = err("2t");
    assert_eq!(e.span, 1..2, "{e}");
    let e = err("1e999");
    assert!(e.message.contains("range"), "{e}");
    let e = err("(t))");
    assert_eq!(e.span, 3..4, "{e}");
    let deep = format!("{}t{}", "(".repeat(200), ")".repeat(200));
    assert!(err(&deep).message.contains("nests"));
}

/// (f, ḟ, f̈) of t written out by hand.
type ClosedForm = dyn Fn(f64) -> (f64, f64, f64);

#[test]
fn derivatives_match_closed_forms() {
    let cases: Vec<(&str, Box<ClosedForm>)> = vec![
        (
            "sin(2*t)",
            Box::new(|t: f64| {
                (
                    (2.0 * t).sin(),
                    2.0 * (2.0 * t).cos(),
                    -4.0 * (2.0 * t).sin(),
                )
            }),
        ),
        ("t^3", Box::new(|t: f64| (t.powi(3), 3.0 * t * t, 6.0 * t))),
        (
            "exp(-t)*t",
            Box::new(|t: f64| {
                let e = (-t).exp();
                (t * e, e - t * e, -2.0 * e + t * e)
            }),
        ),
        (
            "1/t",
            Box::new(|t: f64| (1.0 / t, -1.0 / (t * t), 2.0 / (t * t * t))),
        ),
        (
            "log(t)",
            Box::new(|t: f64| (t.ln(), 1.0 / t, -1.0 / (t * t))),
        ),
        (
            "sqrt(t)",
            Box::new(|t: f64| (t.sqrt(), 0.5 / t.sqrt(), -0.25 / (t * t.sqrt()))),
        ),
        (
            "t^t",
            Box::new(|t: f64| {
                let f = t.powf(t);
                let l = t.ln() + 1.0;
                (f, f * l, f * (l * l + 1.0 / t))
            }),
        ),
        (
            "atan(t)",
            Box::new(|t: f64| {
                let w = 1.0 + t * t;
                (t.atan(), 1.0 / w, -2.0 * t / (w * w))
            }),
        ),
        (
            "asin(t/2)",
            Box::new(|t: f64| {
                let u = t / 2.0;
                let w = 1.0 - u * u;
                ((u).asin(), 0.5 / w.sqrt(), 0.25 * u / w.powf(1.5))
            }),
        ),
        ("atan2(sin(t), cos(t))", Box::new(|t: f64| (t, 1.0, 0.0))),
        (
            "abs(t - 1)",
            Box::new(|t: f64| ((t - 1.0).abs(), (t - 1.0).signum(), 0.0)),
        ),
        ("min(t, 1)*max(t, 1)", Box::new(|t: f64| (t, 1.0, 0.0))),
        (
            "sign(t - 1)*t^2",
            Box::new(|t: f64| {
                let s = (t - 1.0).signum();
                (s * t * t, 2.0 * s * t, 2.0 * s)
            }),
        ),
        ("cosh(t)^2 - sinh(t)^2", Box::new(|_| (1.0, 0.0, 0.0))),
        ("tan(t) - sin(t)/cos(t)", Box::new(|_| (0.0, 0.0, 0.0))),
        ("tanh(t) - sinh(t)/cosh(t)", Box::new(|_| (0.0, 0.0, 0.0))),
        ("acos(t/2) + asin(t/2)", Box::new(|_| (PI / 2.0, 0.0, 0.0))),
    ];
    for (text, exact) in &cases {
        let f = Expression::parse(text).unwrap();
        for t in [0.3, 0.7, 1.3, 1.9] {
            let got = f.eval(t);
            assert!(
                close(got, exact(t), 1e-13),
                "{text} at t = {t}: {got:?} vs {:?}",
                exact(t)
            );
        }
    }
}

#[test]
fn step_piecewise_and_spline_match_their_time_functions() {
    let ramp = TimeFunction::Ramp {
        t0: 0.5,
        t1: 1.5,
        f0: -1.0,
        f1: 2.0,
    };
    let step = Expression::parse("step(t, 0.5, -1, 1.5, 2)").unwrap();
    let spline = TimeFunction::spline(vec![0.0, 0.4, 1.0, 2.0], vec![0.0, 1.0, -0.5, 0.3]).unwrap();
    let sp = Expression::parse("spline(t, [0, 0.4, 1, 2], [0, 1, -0.5, 0.3])").unwrap();
    for k in 0..=60 {
        let t = -0.5 + 0.05 * k as f64;
        assert!(close(step.eval(t), ramp.eval(t), 1e-15), "step at {t}");
        assert!(close(sp.eval(t), spline.eval(t), 1e-15), "spline at {t}");
    }
    // step's argument is any expression: the chain rule applies.
    let s2 = Expression::parse("step(2*t, 0.5, -1, 1.5, 2)").unwrap();
    let (v, d1, d2) = ramp.eval(0.9);
    assert!(close(s2.eval(0.45), (v, 2.0 * d1, 4.0 * d2), 1e-14));
    let pw = Expression::parse("piecewise(t, 0, 1, t^2, 2, sqrt(t))").unwrap();
    assert_eq!(pw.eval(0.5), (0.0, 0.0, 0.0));
    assert_eq!(
        pw.eval(1.0),
        (1.0, 2.0, 2.0),
        "a breakpoint belongs to the branch after it"
    );
    assert_eq!(pw.eval(1.5), (2.25, 3.0, 2.0));
    assert!(close(pw.eval(4.0), (2.0, 0.25, -1.0 / 32.0), 1e-15));
    // Inactive branches are not evaluated: sqrt(t - 1) is NaN before 1 but unused.
    let guarded = Expression::parse("piecewise(t, 0, 1, sqrt(t - 1))").unwrap();
    assert_eq!(guarded.eval(0.5), (0.0, 0.0, 0.0));
    assert!(guarded.diagnose(0.5).is_none());
}

#[test]
fn domain_errors_name_the_failing_part() {
    let f = Expression::parse("0.5 + sqrt(1 - t)").unwrap();
    assert!(f.eval(2.0).0.is_nan());
    let d = f.diagnose(2.0).unwrap();
    assert_eq!(&f.text()[d.span.clone()], "sqrt(1 - t)");
    assert!(d.message.contains("sqrt of -1"), "{}", d.message);
    let m = f.domain_message(2.0).unwrap();
    assert!(m.contains("column 7"), "{m}");
    // Finite value, infinite rate.
    let d = f.diagnose(1.0).unwrap();
    assert!(d.message.contains("derivatives"), "{}", d.message);
    assert!(f.diagnose(0.5).is_none());
    for (text, t, what) in [
        ("log(t)", 0.0, "log of 0"),
        ("asin(t)", 2.0, "asin of 2"),
        ("acos(t)", -2.0, "acos of -2"),
        ("1/(t - 1)", 1.0, "division of 1 by 0"),
        ("exp(t)", 1000.0, "exp of 1000"),
    ] {
        let d = Expression::parse(text).unwrap().diagnose(t);
        let m = d.map(|d| d.message).unwrap_or_default();
        assert!(m.contains(what), "{text} at {t}: {m}");
    }
}

#[test]
fn the_time_function_kind() {
    let f = TimeFunction::expression("0.5 + 0.3*sin(2*pi*t - pi/2)").unwrap();
    assert_eq!(f.kind(), "expression");
    assert!(TimeFunction::KINDS.contains(&"expression"));
    let h = TimeFunction::Harmonic {
        amplitude: 0.3,
        frequency: 2.0 * PI,
        phase: -PI / 2.0,
        offset: 0.5,
    };
    for t in [0.0, 0.1, 0.37, 1.0] {
        assert!(close(f.eval(t), h.eval(t), 1e-14));
    }
    let e = TimeFunction::expression("sin(").unwrap_err().to_string();
    assert!(e.contains("column 5"), "{e}");
}

proptest! {
    /// A polynomial written as text has the derivatives of the polynomial kind.
    #[test]
    fn polynomials(c in prop::collection::vec(-10.0..10.0f64, 1..6), t in -3.0..3.0f64) {
        let text: Vec<String> = c.iter().enumerate().map(|(k, ck)| format!("({ck:e})*t^{k}")).collect();
        let f = Expression::parse(&text.join(" + ")).unwrap();
        let p = TimeFunction::Polynomial(c.clone());
        prop_assert!(close(f.eval(t), p.eval(t), 1e-12), "{:?} vs {:?}", f.eval(t), p.eval(t));
    }

    /// Harmonics: offset + amplitude*sin(frequency*t + phase).
    #[test]
    fn harmonics(a in -5.0..5.0f64, w in -20.0..20.0f64, p in -4.0..4.0f64, b in -3.0..3.0f64, t in -2.0..2.0f64) {
        let f = Expression::parse(&format!("{b:e} + {a:e}*sin({w:e}*t + {p:e})")).unwrap();
        let h = TimeFunction::Harmonic { amplitude: a, frequency: w, phase: p, offset: b };
        prop_assert!(close(f.eval(t), h.eval(t), 1e-12));
    }

    /// Arbitrary text never panics the parser.
    #[test]
    fn any_text_is_parsed_or_refused(s in "[-+*/^()\\[\\], .0-9a-z]{0,40}") {
        if let Ok(f) = Expression::parse(&s) {
            let _ = f.eval(0.5);
            let _ = f.diagnose(0.5);
        }
    }
}

/// The per-thread memo of the last value of each expression ([`Expression::eval`]) gives the
/// program's own values: expressions evaluated in turn at one time, at alternating times, a
/// clone, one parsed where another was dropped (same text, then another text), and more
/// expressions than the memo has slots.
#[test]
fn the_evaluation_memo_gives_each_expression_its_own_values() {
    let a = Expression::parse("sin(3*t) + t^2").unwrap();
    let b = Expression::parse("cos(2*t)").unwrap();
    for t in [0.1, 0.2, 0.1, 0.1, 0.3] {
        for _ in 0..3 {
            let (fa, fb) = (a.eval(t), b.eval(t));
            assert_eq!(fa.0, (3.0 * t).sin() + t * t);
            assert_eq!(fa.1, 3.0 * (3.0 * t).cos() + 2.0 * t);
            assert_eq!(fb.0, (2.0 * t).cos());
            assert_eq!(a.clone().eval(t), fa);
        }
    }
    // Dropped and parsed again at the same place and time: its own values.
    let v = a.eval(0.5);
    drop(a);
    let c = Expression::parse("t").unwrap();
    assert_eq!(c.eval(0.5), (0.5, 1.0, 0.0));
    assert_ne!(c.eval(0.5), v);
    // More expressions than slots, each evaluated twice.
    let many: Vec<Expression> = (0..200)
        .map(|k| Expression::parse(&format!("{k} * t")).unwrap())
        .collect();
    for round in 0..2 {
        for (k, e) in many.iter().enumerate() {
            assert_eq!(
                e.eval(2.0),
                (2.0 * k as f64, k as f64, 0.0),
                "round {round}"
            );
        }
    }
}
