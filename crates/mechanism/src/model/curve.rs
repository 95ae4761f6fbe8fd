//! Resolution of a [`CurveSpec`]: its bodies and point by name, its curve parameter's index
//! among the extra coordinates and its value at the drawn pose (given, or the nearest curve
//! point to the drawn point; an open curve's parameter must lie on the curve).

use super::elements::{CurveInfo, ScatterMap};
use super::resolve::{pose, Names};
use super::validate::{check_number, pair_check};
use super::BodyInfo;
use crate::curve_spec::CurveSpec;
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::PointOnCurve;

/// The model form of `spec`, whose curve parameter is extra coordinate `extra`.
pub(super) fn curve(
    spec: &CurveSpec,
    extra: usize,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<CurveInfo, ModelError> {
    let el = format!("point-on-curve \"{}\"", spec.name);
    let bi = names.body(&el, &spec.body_i)?;
    let bj = names.body(&el, &spec.body_j)?;
    pair_check(&el, bi, bj, &spec.body_i)?;
    let sp_j = names.feature(&el, &spec.body_j, &spec.point_j, false)?;
    let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
    let initial_u = match spec.initial_u {
        Some(u) => {
            check_number(&el, "initial curve parameter", Quantity::Length, u)?;
            u
        }
        // The drawn point in the curve body's frame.
        None => spec
            .curve
            .closest(&(si.a.transpose() * (sj.point(&sp_j) - si.r))),
    };
    if let Some((a, b)) = spec.curve.domain() {
        if !(a..=b).contains(&initial_u) {
            return Err(ModelError::CurveParameterOff {
                element: el,
                u: initial_u,
                start: a,
                end: b,
            });
        }
    }
    Ok(CurveInfo {
        name: spec.name.clone(),
        body_i: bi,
        body_j: bj,
        element: PointOnCurve::new(spec.curve.clone(), sp_j),
        extra,
        initial_u,
        rows: 0..0,
        map: ScatterMap { slots: Vec::new() },
        extra_slots: Vec::new(),
    })
}
