//! What every section reader shares: [`Ctx`] (the source, the file's units, the vocabulary keys;
//! numbers and vectors read in SI with their limits), [`Resolver`] (body, point and vector names
//! against what the bodies defined, with suggestions), and the common checks and messages.

use super::loaded::Spans;
use crate::diag::{did_you_mean, list, Error, Source};
use crate::file::{Name, Num, Vec3};
use crate::units::UnitSystem;
use cardan_mechanism::Quantity;
use nalgebra::Vector3;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Display;
use std::ops::Range;

/// Points and vectors of one body, with the span of each name.
#[derive(Default)]
pub(super) struct Features {
    pub(super) points: BTreeMap<String, (Range<usize>, Vector3<f64>)>,
    pub(super) vectors: BTreeMap<String, (Range<usize>, Vector3<f64>)>,
}

pub(super) struct Ctx<'a> {
    pub(super) src: &'a Source,
    /// The file's `[model] units`: every number is converted to SI as it is read.
    pub(super) units: UnitSystem,
    /// The keys written in the sections with vocabularies ([`crate::vocabulary`]).
    pub(super) keys: &'a crate::vocabulary::KeySpans,
    /// The file's parameters: constants of its time-function expressions.
    pub(super) parameters: &'a crate::parameters::Parameters,
}

impl Ctx<'_> {
    /// Checks the table whose span starts at `table` against `vocab` (its entry `selected`
    /// exists, it takes every key given, every key it needs is given; [`crate::vocabulary`]).
    pub(super) fn check(
        &self,
        vocab: &crate::vocabulary::Vocabulary,
        owner: &str,
        selected: &Name,
        table: usize,
        element: Range<usize>,
    ) -> Result<&'static crate::vocabulary::Entry, Error> {
        crate::vocabulary::check(
            self.src,
            vocab,
            owner,
            selected,
            (self.keys, table),
            |_| true,
            element,
        )
    }

    pub(super) fn err(&self, span: Range<usize>, m: impl Into<String>) -> Error {
        self.src.error_at(span, m)
    }

    /// A finite, not subnormal number within the SI magnitude limit of its quantity
    /// (`cardan_mechanism::sanity::Quantity`, the builder's limits), converted to SI from the
    /// file's units (the limit applies to the SI value).
    pub(super) fn num(&self, n: &Num, what: impl Display, q: Quantity) -> Result<f64, Error> {
        let v = *n.get_ref();
        if v != 0.0 && v.abs() < f64::MIN_POSITIVE {
            return Err(self.err(
                n.span(),
                format!(
                    "{what} = {v:e} is subnormal (0 < |value| < {:e}): it has no meaning in SI units \
                     and loses precision in any arithmetic; write 0 or a meaningful value",
                    f64::MIN_POSITIVE
                ),
            ));
        }
        let factor = self.units.to_si(q);
        if factor == 1.0 {
            q.check(&what, v).map_err(|m| self.err(n.span(), m))?;
            return Ok(v);
        }
        let si = v * factor;
        if q.check(&what, si).is_err() {
            let (unit, _) = self.units.unit(q.unit());
            let what = format!(
                "{what} ({} {unit})",
                cardan_mechanism::sanity::scientific(v)
            );
            q.check(&what, si).map_err(|m| self.err(n.span(), m))?;
        }
        Ok(si)
    }

    /// The three components of `v`; `what` names the vector in a message (formatted only then).
    pub(super) fn vec3(
        &self,
        v: &Vec3,
        what: impl Display,
        q: Quantity,
    ) -> Result<Vector3<f64>, Error> {
        let a = v.get_ref();
        Ok(Vector3::new(
            self.num(&a[0], format_args!("{what} x"), q)?,
            self.num(&a[1], format_args!("{what} y"), q)?,
            self.num(&a[2], format_args!("{what} z"), q)?,
        ))
    }

    pub(super) fn direction(&self, v: &Vec3, what: impl Display) -> Result<Vector3<f64>, Error> {
        let d = self.vec3(v, &what, Quantity::Direction)?;
        if d.norm() < 1e-12 {
            return Err(self.err(
                v.span(),
                format!(
                    "{what} has zero length ({}); a direction needs a nonzero vector",
                    fmt_vec(&d)
                ),
            ));
        }
        Ok(d)
    }

    pub(super) fn raw_num(
        &self,
        span: Range<usize>,
        v: f64,
        what: impl Display,
        q: Quantity,
    ) -> Result<f64, Error> {
        self.num(&crate::file::Num::new(span, v), what, q)
    }
}

pub(super) struct Resolver<'a> {
    pub(super) cx: &'a Ctx<'a>,
    pub(super) features: &'a HashMap<String, Features>,
    pub(super) order: &'a [String],
}

impl Resolver<'_> {
    pub(super) fn body<'n>(&self, n: &'n Name, owner: &str) -> Result<&'n str, Error> {
        let b = n.get_ref();
        if self.features.contains_key(b) {
            return Ok(b);
        }
        let hint = did_you_mean(b, self.order.iter().map(String::as_str));
        Err(self.cx.err(
            n.span(),
            format!(
                "{owner}: unknown body \"{b}\"{hint} (bodies: {})",
                list(self.order.iter().map(String::as_str))
            ),
        ))
    }

    pub(super) fn feature(
        &self,
        body: &str,
        n: &Name,
        owner: &str,
        points: bool,
    ) -> Result<(), Error> {
        let f = &self.features[body];
        let map = if points { &f.points } else { &f.vectors };
        let what = if points { "point" } else { "vector" };
        if map.contains_key(n.get_ref()) {
            return Ok(());
        }
        let hint = did_you_mean(n.get_ref(), map.keys().map(String::as_str));
        let hint = if hint.is_empty() && !points {
            // A vector name that is a point's name, or a common slip.
            did_you_mean(n.get_ref(), map.keys().map(String::as_str))
        } else {
            hint
        };
        Err(self.cx.err(
            n.span(),
            format!(
                "{owner}: body \"{body}\" has no {what} \"{}\"{hint} ({what}s of \"{body}\": {})",
                n.get_ref(),
                list(map.keys().map(String::as_str))
            ),
        ))
    }

    pub(super) fn point_value(&self, body: &str, n: &str) -> Vector3<f64> {
        self.features[body].points[n].1
    }

    pub(super) fn vector_value(&self, body: &str, n: &str) -> Vector3<f64> {
        self.features[body].vectors[n].1
    }
}

pub(super) fn check_unique_element(
    cx: &Ctx,
    spans: &Spans,
    name: &Name,
    what: &str,
) -> Result<(), Error> {
    let n = name.get_ref();
    if n.trim().is_empty() {
        return Err(cx.err(name.span(), format!("{what} name must not be empty")));
    }
    let prev = spans
        .joints
        .get(n)
        .map(|s| ("joint", s))
        .or_else(|| spans.curves.get(n).map(|s| ("curve", s)))
        .or_else(|| spans.drivers.get(n).map(|s| ("driver", s)))
        .or_else(|| spans.couplers.get(n).map(|s| ("coupler", s)))
        .or_else(|| spans.forces.get(n).map(|s| ("force", s)))
        .or_else(|| spans.limits.get(n).map(|s| ("limit", s)))
        .or_else(|| spans.frictions.get(n).map(|s| ("friction", s)));
    if let Some((kind, s)) = prev {
        let l = cx.src.location(s.start);
        return Err(cx.err(
            name.span(),
            format!(
                "duplicate name \"{n}\": a {kind} of that name is defined at line {} \
                 (joints, curves, couplers, drivers, forces, limits and frictions share one namespace)",
                l.line
            ),
        ));
    }
    Ok(())
}

pub(super) fn missing(cx: &Ctx, span: Range<usize>, owner: &str, key: &str, why: &str) -> Error {
    cx.err(span, format!("{owner}: missing key \"{key}\" ({why})"))
}

/// Formats a vector as "(x, y, z)".
pub fn fmt_vec(v: &Vector3<f64>) -> String {
    let f = |x: f64| {
        if x == 0.0 || (1e-4..1e9).contains(&x.abs()) {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    };
    format!("({}, {}, {})", f(v.x), f(v.y), f(v.z))
}
