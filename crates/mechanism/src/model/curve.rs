//! Resolution of a [`CurveSpec`]: its bodies and point by name, its curve parameter's index
//! among the extra coordinates and its value at the drawn pose (given, or the nearest curve
//! point to the drawn point; an open curve's parameter must lie on the curve); of a
//! [`PathSpec`]: its curve element by name and its function checked.

use super::elements::{CurveInfo, PathInfo, ScatterMap};
use super::resolve::{pose, Names};
use super::validate::check_number;
use super::BodyInfo;
use crate::curve_spec::{CurveSpec, PathSpec};
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::{PathDriver, PointOnCurve};

/// The model form of `spec`, whose curve parameter is extra coordinate `extra`.
pub(super) fn curve(
    spec: &CurveSpec,
    extra: usize,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<CurveInfo, ModelError> {
    let el = format!("point-on-curve \"{}\"", spec.name);
    let (bi, bj) = names.pair(&el, &spec.body_i, &spec.body_j)?;
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

/// The model form of path driver `spec` on one of `curves`.
pub(super) fn path(spec: &PathSpec, curves: &[CurveInfo]) -> Result<PathInfo, ModelError> {
    let curve = curves
        .iter()
        .position(|c| c.name == spec.curve)
        .ok_or_else(|| ModelError::UnknownJoint {
            element: format!("path driver \"{}\"", spec.name),
            name: spec.curve.clone(),
            suggestion: crate::model::nearest(&spec.curve, curves.iter().map(|c| c.name.as_str()))
                .map(str::to_string),
            known: curves.iter().map(|c| c.name.clone()).collect(),
        })?;
    spec.function
        .validate()
        .map_err(|e| ModelError::BadTimeFunction {
            driver: spec.name.clone(),
            reason: e.to_string(),
        })?;
    Ok(PathInfo {
        name: spec.name.clone(),
        curve,
        driver: PathDriver::new(spec.function.clone()),
        rows: 0..0,
        slot: 0,
    })
}
