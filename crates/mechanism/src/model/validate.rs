//! The builder's checks of numbers and shapes, in one place: magnitudes per quantity in SI
//! ([`crate::sanity`]), orientations, two-body elements, and the wording of accepted joint kinds
//! and of suggestions for unknown names.

use super::elements::BodyId;
use crate::builder::Orientation;
use crate::error::ModelError;
use crate::sanity::Quantity;
use nalgebra::Vector4;

/// The candidate nearest to `word` (Jaro-Winkler similarity and Levenshtein distance, ignoring
/// case), if any is close enough to be a plausible typo. The one did-you-mean of cardan: the
/// builder's errors and the model file's use it.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lw = word.to_lowercase();
    candidates
        .into_iter()
        .map(|c| {
            let lc = c.to_lowercase();
            let lev = strsim::levenshtein(&lw, &lc);
            let jw = strsim::jaro_winkler(&lw, &lc);
            (c, lev, jw)
        })
        .filter(|&(c, lev, jw)| jw >= 0.7 || lev <= 2.max(c.len() / 3))
        .min_by(|a, b| a.1.cmp(&b.1).then(b.2.total_cmp(&a.2)))
        .map(|(c, _, _)| c)
}

/// [`nearest`] as an owned suggestion for an error.
pub(super) fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    nearest(name, candidates).map(str::to_string)
}

/// A finite number within the SI magnitude limit of its quantity ([`crate::sanity`]).
pub(super) fn check_number(
    element: impl std::fmt::Display,
    what: &str,
    q: Quantity,
    v: f64,
) -> Result<(), ModelError> {
    if !v.is_finite() {
        return Err(ModelError::NotFinite {
            element: element.to_string(),
            what: what.into(),
            value: v,
        });
    }
    if v.abs() > q.limit() {
        return Err(ModelError::Absurd {
            element: element.to_string(),
            what: what.into(),
            value: v,
            limit: q.limit(),
            unit: q.unit(),
        });
    }
    Ok(())
}

pub(super) fn check_numbers(
    element: impl std::fmt::Display,
    what: &str,
    q: Quantity,
    v: &[f64],
) -> Result<(), ModelError> {
    v.iter()
        .try_for_each(|&x| check_number(&element, what, q, x))
}

pub(super) fn orientation_p(body: &str, o: &Orientation) -> Result<Vector4<f64>, ModelError> {
    let el = format!("body \"{body}\"");
    match o {
        Orientation::Identity => {}
        Orientation::EulerParams(e) => {
            check_numbers(&el, "Euler parameters", Quantity::Direction, e)?
        }
        Orientation::AxisAngle { axis, angle } => {
            check_numbers(
                &el,
                "orientation axis",
                Quantity::Direction,
                axis.as_slice(),
            )?;
            check_number(&el, "orientation angle", Quantity::Angle, *angle)?;
        }
        Orientation::Euler313(a) | Orientation::Euler123(a) => {
            check_numbers(&el, "Euler angles", Quantity::Angle, a)?
        }
        Orientation::Axes { z, x } => {
            check_numbers(&el, "orientation z axis", Quantity::Direction, z.as_slice())?;
            if let Some(x) = x {
                check_numbers(&el, "orientation x axis", Quantity::Direction, x.as_slice())?;
            }
        }
    }
    let p = o.euler_params().map_err(|e| ModelError::BadOrientation {
        body: body.into(),
        reason: e.to_string(),
    })?;
    Ok(*p.as_vector())
}

/// Body i and body j of a two-body element differ (and are not both ground).
pub(super) fn pair_check(
    element: &str,
    bi: BodyId,
    bj: BodyId,
    name_i: &str,
) -> Result<(), ModelError> {
    if bi == bj {
        return Err(match bi {
            BodyId::Ground => ModelError::GroundToGround {
                element: element.into(),
            },
            BodyId::Moving(_) => ModelError::SelfConnection {
                element: element.into(),
                body: name_i.into(),
            },
        });
    }
    Ok(())
}

/// "a revolute or cylindrical joint": the kinds whose description passes `pick`, for messages.
pub fn kinds_with(pick: impl Fn(&cardan_constraints::KindInfo) -> bool) -> String {
    let names: Vec<&str> = cardan_constraints::KINDS
        .iter()
        .filter(|k| pick(k))
        .map(|k| k.name)
        .collect();
    match names.as_slice() {
        [] => "no joint".into(),
        [one] => format!("a {one} joint"),
        [init @ .., last] => format!("a {} or {last} joint", init.join(", ")),
    }
}
