//! `[[driver]]` sections to [`DriverSpec`]s (rotation, translation, distance, coordinate, and
//! the six laws of a general motion), and the time functions that drivers and forces share:
//! their keys checked from [`crate::vocabulary::FUNCTIONS`], their numbers read in the file's
//! units, an expression's parse errors placed at the column inside its string.

use super::context::{missing, Ctx, Resolver};
use crate::diag::{did_you_mean, list, Error};
use crate::file::{DriverSection, FunctionSpec, Name, Num};
use crate::vocabulary::{DRIVERS, FUNCTIONS};
use cardan_constraints::expression::{self, Expression};
use cardan_constraints::{RotationOrder, TimeFunction};
use cardan_mechanism::{Axis, DriverSpec, PathSpec, PoseTarget, Quantity};
use std::ops::Range;
use toml::Spanned;

/// A time function whose values are `value_q` (an angle for a rotation driver, a length for the
/// other drivers, a force or torque for force components).
pub(super) fn load_function(
    cx: &Ctx,
    f: &Spanned<FunctionSpec>,
    owner: &str,
    value_q: Quantity,
) -> Result<TimeFunction, Error> {
    let s = f.get_ref();
    // The quantity of each key: times, the frequency and the phase have theirs; a polynomial
    // coefficient c_k has the unit of the value / s^k, so it is only checked to be finite.
    let quantity = |key: &str| match key {
        "t0" | "t1" | "times" => Quantity::Time,
        "frequency" => Quantity::Frequency,
        "phase" => Quantity::Angle,
        "coefficients" => Quantity::Unbounded,
        _ => value_q,
    };
    let kind = s.kind.get_ref().as_str();
    let span = f.span();
    let req = |v: &Option<Num>, key: &str| -> Result<f64, Error> {
        match v {
            Some(n) => cx.num(n, format_args!("{owner}: function {key}"), quantity(key)),
            None => Err(missing(
                cx,
                span.clone(),
                owner,
                key,
                &format!("a {kind} function needs it"),
            )),
        }
    };
    let opt = |v: &Option<Num>, key: &str, d: f64| -> Result<f64, Error> {
        match v {
            Some(n) => cx.num(n, format_args!("{owner}: function {key}"), quantity(key)),
            None => Ok(d),
        }
    };
    let list_of = |v: &Option<Spanned<Vec<Num>>>, key: &str| -> Result<Vec<f64>, Error> {
        match v {
            Some(l) => l
                .get_ref()
                .iter()
                .enumerate()
                .map(|(k, n)| {
                    let v = cx.num(
                        n,
                        format_args!("{owner}: function {key}[{k}]"),
                        quantity(key),
                    )?;
                    // c_k has the unit of the value / s^k: converted as the value.
                    Ok(if key == "coefficients" {
                        v * cx.units.to_si(value_q)
                    } else {
                        v
                    })
                })
                .collect(),
            None => Err(missing(
                cx,
                span.clone(),
                owner,
                key,
                &format!("a {kind} function needs it"),
            )),
        }
    };
    // Keys that belong to another kind are an error, so a typo in kind does not go unnoticed.
    cx.check(
        &FUNCTIONS,
        &format!("{owner}: function"),
        &s.kind,
        span.start,
        span.clone(),
    )?;
    let tf = match kind {
        "constant" => TimeFunction::Constant(req(&s.value, "value")?),
        "polynomial" => {
            let c = list_of(&s.coefficients, "coefficients")?;
            if c.is_empty() {
                return Err(cx.err(
                    span,
                    format!("{owner}: polynomial needs at least one coefficient"),
                ));
            }
            TimeFunction::Polynomial(c)
        }
        "harmonic" => TimeFunction::Harmonic {
            amplitude: req(&s.amplitude, "amplitude")?,
            frequency: req(&s.frequency, "frequency")?,
            phase: opt(&s.phase, "phase", 0.0)?,
            offset: opt(&s.offset, "offset", 0.0)?,
        },
        "ramp" => TimeFunction::Ramp {
            t0: req(&s.t0, "t0")?,
            t1: req(&s.t1, "t1")?,
            f0: req(&s.f0, "f0")?,
            f1: req(&s.f1, "f1")?,
        },
        "expression" => match &s.text {
            Some(text) => in_si(cx, expression(cx, text, owner)?, cx.units.to_si(value_q)),
            None => return Err(missing(cx, span, owner, "text", "an expression needs it")),
        },
        _ => {
            let t = list_of(&s.times, "times")?;
            let v = list_of(&s.values, "values")?;
            TimeFunction::spline(t, v).map_err(|e| cx.err(span.clone(), format!("{owner}: {e}")))?
        }
    };
    tf.validate()
        .map_err(|e| cx.err(span, format!("{owner}: {e}")))?;
    Ok(tf)
}

/// A general_motion driver: frames i and j (bodies, origins, optional axes), the rotation
/// sequence and the six laws (three translations, three angles).
fn load_general_motion(r: &Resolver, d: &DriverSection) -> Result<(DriverSpec, String), Error> {
    let cx = r.cx;
    let name = d.name.get_ref().clone();
    let owner = format!("driver \"{name}\"");
    let span = d.name.span();
    let need = |v: &Option<Name>, key: &str| -> Result<String, Error> {
        v.as_ref().map(|n| n.get_ref().clone()).ok_or_else(|| {
            missing(
                cx,
                span.clone(),
                &owner,
                key,
                "a general motion moves frame j relative to frame i",
            )
        })
    };
    let order = match &d.order {
        None => RotationOrder([0, 1, 2]),
        Some(o) => RotationOrder::parse(o.get_ref()).ok_or_else(|| {
            cx.err(
                o.span(),
                format!(
                    "{owner}: order must be three axis letters with no axis twice in a row (xyz, \
                     xzy, yxz, yzx, zxy, zyx, xyx, xzx, yxy, yzy, zxz, zyz), got \"{}\"",
                    o.get_ref()
                ),
            )
        })?,
    };
    let three = |list: &Option<Spanned<Vec<Spanned<FunctionSpec>>>>, key: &str, q: Quantity| {
        let Some(l) = list else {
            return Err(missing(
                cx,
                span.clone(),
                &owner,
                key,
                "three functions of time",
            ));
        };
        if l.get_ref().len() != 3 {
            return Err(cx.err(
                l.span(),
                format!(
                    "{owner}: {key} needs three functions, got {}",
                    l.get_ref().len()
                ),
            ));
        }
        l.get_ref()
            .iter()
            .map(|f| load_function(cx, f, &owner, q))
            .collect::<Result<Vec<_>, _>>()
    };
    let mut f = three(&d.translation, "translation", Quantity::Length)?;
    f.extend(three(&d.rotation, "rotation", Quantity::Angle)?);
    let functions: [TimeFunction; 6] = f.try_into().expect("three and three");
    let opt = |v: &Option<Name>| v.as_ref().map(|n| n.get_ref().clone());
    let target = PoseTarget {
        body_i: need(&d.body_i, "body_i")?,
        point_i: need(&d.point_i, "point_i")?,
        axis_i: opt(&d.axis_i),
        x_axis_i: opt(&d.x_axis_i),
        body_j: need(&d.body_j, "body_j")?,
        point_j: need(&d.point_j, "point_j")?,
        axis_j: opt(&d.axis_j),
        x_axis_j: opt(&d.x_axis_j),
        order,
        functions,
    };
    let what = format!(
        "pose of {}.{} in {}.{} ({} angles)",
        target.body_j,
        target.point_j,
        target.body_i,
        target.point_i,
        order.name()
    );
    Ok((DriverSpec::pose(name, target), what))
}

/// An expression function; a parse error points at its column inside the TOML string.
fn expression(cx: &Ctx, text: &Name, owner: &str) -> Result<TimeFunction, Error> {
    let t = text.get_ref();
    Expression::parse_with(t, &|n| cx.parameters.constant(n))
        .map(TimeFunction::Expression)
        .map_err(|e| {
            let hint = e
                .unknown
                .as_deref()
                .map(|n| {
                    let mut known: Vec<&str> = expression::names().collect();
                    known.extend(cx.parameters.list.iter().map(|p| p.name.as_str()));
                    did_you_mean(n, known)
                })
                .unwrap_or_default();
            let span = string_inner_span(&cx.src.text, text.span(), t, e.span.clone());
            cx.err(
                span,
                format!(
                    "{owner}: expression \"{}\", column {}: {}{hint}",
                    expression::quoted(t),
                    e.column(t),
                    e.message
                ),
            )
        })
}

/// An expression in the file's units as a function of SI value: `factor·(f)` (`f` itself in
/// SI). The text parsed first, so that errors point into the file's string.
fn in_si(cx: &Ctx, f: TimeFunction, factor: f64) -> TimeFunction {
    match f {
        TimeFunction::Expression(e) if factor != 1.0 => {
            let scaled = format!("{factor:?}*({})", e.text());
            match Expression::parse_with(&scaled, &|n| cx.parameters.constant(n)) {
                Ok(scaled) => TimeFunction::Expression(scaled),
                Err(_) => TimeFunction::Expression(e),
            }
        }
        other => other,
    }
}

/// The file span of `inner` (a byte span of the string's value `value`) when the TOML string at
/// `span` is written without escapes on one line (`"..."` or `'...'`, the value verbatim); else
/// the whole string.
fn string_inner_span(
    file: &str,
    span: Range<usize>,
    value: &str,
    inner: Range<usize>,
) -> Range<usize> {
    let raw = file.get(span.clone()).unwrap_or("");
    let verbatim = raw.len() == value.len() + 2
        && (raw.starts_with('"') || raw.starts_with('\''))
        && &raw[1..raw.len() - 1] == value;
    if !verbatim {
        return span;
    }
    let start = span.start + 1 + inner.start;
    // An empty span (the end of the text) underlines the closing quote.
    start..(span.start + 1 + inner.end).max(start + 1)
}

/// A path driver: the parameter of the `[[curve]]` named by `curve` follows `function` (the
/// curve's existence is checked by the builder, located at this key).
pub(super) fn load_path(cx: &Ctx, d: &DriverSection) -> Result<PathSpec, Error> {
    let owner = format!("driver \"{}\"", d.name.get_ref());
    let need = |key: &str, why: &str| missing(cx, d.name.span(), &owner, key, why);
    let curve = (d.curve.as_ref()).ok_or_else(|| need("curve", "the [[curve]] it drives"))?;
    let f = (d.function.as_ref())
        .ok_or_else(|| need("function", "the law u(t) of the curve parameter"))?;
    let function = load_function(cx, f, &owner, Quantity::Length)?;
    let spec = PathSpec::new(d.name.get_ref().clone(), curve.get_ref(), function);
    Ok(match d.arc_length.as_ref().is_some_and(|f| *f.get_ref()) {
        true => spec.along_arc(),
        false => spec,
    })
}

pub(super) fn load_driver(r: &Resolver, d: &DriverSection) -> Result<(DriverSpec, String), Error> {
    let cx = r.cx;
    let name = d.name.get_ref().clone();
    let owner = format!("driver \"{name}\"");
    let kind = d.kind.get_ref().as_str();
    let value_q = if kind == "rotation" {
        Quantity::Angle
    } else {
        Quantity::Length
    };
    let span = d.name.span();
    if kind == "general_motion" {
        return load_general_motion(r, d);
    }
    let Some(fspec) = &d.function else {
        return Err(missing(
            cx,
            span,
            &owner,
            "function",
            "the law the driven value follows",
        ));
    };
    let function = load_function(cx, fspec, &owner, value_q)?;
    // The joint's existence and kind are checked by the builder (located at this key).
    let joint_ref = || -> Result<String, Error> {
        let Some(j) = &d.joint else {
            return Err(missing(
                cx,
                span.clone(),
                &owner,
                "joint",
                &format!("a {kind} driver drives a joint"),
            ));
        };
        Ok(j.get_ref().clone())
    };
    match kind {
        "rotation" | "translation" => {
            if kind == "rotation" {
                let j = joint_ref()?;
                Ok((
                    DriverSpec::rotation(name, &j, function),
                    format!("rotation of joint {j}"),
                ))
            } else {
                let j = joint_ref()?;
                Ok((
                    DriverSpec::translation(name, &j, function),
                    format!("translation of joint {j}"),
                ))
            }
        }
        "distance" => {
            let need = |v: &Option<Name>, key: &str| -> Result<Name, Error> {
                v.clone().ok_or_else(|| {
                    missing(
                        cx,
                        span.clone(),
                        &owner,
                        key,
                        "a distance driver is between two points",
                    )
                })
            };
            let (bi, pi, bj, pj) = (
                need(&d.body_i, "body_i")?,
                need(&d.point_i, "point_i")?,
                need(&d.body_j, "body_j")?,
                need(&d.point_j, "point_j")?,
            );
            // Bodies and points (and that they differ) are checked by the builder.
            let (bi_s, bj_s) = (bi.get_ref().as_str(), bj.get_ref().as_str());
            Ok((
                DriverSpec::distance(name, (bi_s, pi.get_ref()), (bj_s, pj.get_ref()), function),
                format!("distance {bi_s}.{} – {bj_s}.{}", pi.get_ref(), pj.get_ref()),
            ))
        }
        "coordinate" => {
            let (Some(b), Some(p), Some(c)) = (&d.body, &d.point, &d.coordinate) else {
                return Err(missing(
                    cx,
                    span,
                    &owner,
                    "body, point and coordinate",
                    "a coordinate driver moves one coordinate of a body point",
                ));
            };
            // The body (a moving one) and the point are checked by the builder.
            let bs = b.get_ref().as_str();
            let axis = match c.get_ref().as_str() {
                "x" => Axis::X,
                "y" => Axis::Y,
                "z" => Axis::Z,
                other => {
                    return Err(cx.err(
                        c.span(),
                        format!(
                            "{owner}: coordinate must be \"x\", \"y\" or \"z\", got \"{other}\""
                        ),
                    ))
                }
            };
            Ok((
                DriverSpec::coordinate(name, (bs, p.get_ref()), axis, function),
                format!("{} of {bs}.{}", axis.name(), p.get_ref()),
            ))
        }
        _ => {
            let hint = did_you_mean(kind, DRIVERS.names());
            Err(cx.err(
                d.kind.span(),
                format!(
                    "{owner}: unknown driver type \"{kind}\"{hint} (types: {})",
                    list(DRIVERS.names())
                ),
            ))
        }
    }
}
