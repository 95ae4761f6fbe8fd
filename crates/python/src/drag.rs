//! `drag`: one drag step of a model (FreeCAD's interaction, [`cardan_mechanism::Drag`]), for
//! `cardan.Model.drag`. The model text is prepared, the bodies put at the given pose (or
//! assembled at `time` from the drawn one), the point of the body pulled toward the target, and
//! the new pose returned with how far the step got. Lengths in the model's units.

use crate::convert::{error_dict, ErrorData};
use cardan_mechanism::nalgebra::{Vector3, Vector4};
use cardan_mechanism::{AnalysisError, AssemblyOptions, Drag, DragStop};
use cardan_model::prepare::{analysis_error, Prepared};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;

/// A body's pose as Python gives it: position (model units) and Euler parameters.
type Pose = HashMap<String, ([f64; 3], [f64; 4])>;

/// One drag step (module docs): a dict with `pose` (body → (r, p)), `reached`, `stop` (the
/// limit's name, `"not converged"` or None), `distance` (model units), or `error`.
#[pyfunction]
#[pyo3(signature = (text, path, body, target, point=None, pose=None, time=0.0, model=None))]
#[allow(clippy::too_many_arguments)]
pub fn drag<'py>(
    py: Python<'py>,
    text: String,
    path: String,
    body: String,
    target: [f64; 3],
    point: Option<String>,
    pose: Option<Pose>,
    time: f64,
    model: Option<&Bound<'py, crate::prepared::Prepared>>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let handle = model.map(Bound::get);
    let Some(p) = crate::prepared::model_or_error(py, &out, text, path, handle)? else {
        return Ok(out);
    };
    match step(&p, &body, target, point.as_deref(), pose.as_ref(), time) {
        Ok((new_pose, report)) => {
            let (_, f) = p.units.unit("m");
            let poses = PyDict::new(py);
            for (name, (r, q)) in new_pose {
                poses.set_item(name, ((r * f).as_slice().to_vec(), q.as_slice().to_vec()))?;
            }
            out.set_item("pose", poses)?;
            out.set_item("reached", report.reached)?;
            let stop = match report.stop {
                DragStop::None => None,
                DragStop::Limit(name) => Some(name),
                DragStop::NotConverged => Some("not converged".to_string()),
            };
            out.set_item("stop", stop)?;
            out.set_item("distance", report.distance * f)?;
            out.set_item("error", py.None())?;
        }
        Err(e) => {
            let err = analysis_error(&p, &e);
            out.set_item("error", error_dict(py, &ErrorData::from(&err))?)?;
        }
    }
    Ok(out)
}

/// The new poses (SI) by body name, and the step's report.
type Stepped = (
    Vec<(String, (Vector3<f64>, Vector4<f64>))>,
    cardan_mechanism::DragReport,
);

fn step(
    p: &Prepared,
    body: &str,
    target: [f64; 3],
    point: Option<&str>,
    pose: Option<&Pose>,
    time: f64,
) -> Result<Stepped, AnalysisError> {
    let model = &p.model;
    let bad = |m: String| AnalysisError::Options(format!("drag: {m}"));
    let (_, f) = p.units.unit("m");
    let local = match point {
        None => Vector3::zeros(),
        Some(name) => {
            let k = model
                .point_index(body, name)
                .ok_or_else(|| bad(format!("body \"{body}\" has no point \"{name}\"")))?;
            model.points()[k].local
        }
    };
    let mut ws = model.workspace();
    match pose {
        Some(pose) => {
            for (b, info) in model.bodies().iter().enumerate() {
                let (r, q) = pose
                    .get(&info.name)
                    .ok_or_else(|| bad(format!("the pose has no body \"{}\"", info.name)))?;
                let r = Vector3::from(*r) / f;
                let q = Vector4::from(*q);
                if !(r.iter().chain(q.iter()).all(|x| x.is_finite()) && q.norm() > 0.0) {
                    return Err(bad(format!("the pose of \"{}\" is not finite", info.name)));
                }
                ws.set_pose(b, r, q.normalize());
            }
            ws.set_time(time);
        }
        None => {
            model.assemble(&mut ws, &AssemblyOptions::at(time))?;
        }
    }
    let mut drag = Drag::new(model, body, local, 1.0 / f)?;
    let report = drag.step(model, &mut ws, time, Vector3::from(target) / f)?;
    let poses = (model.bodies().iter().enumerate())
        .map(|(b, info)| (info.name.clone(), (ws.r(b), ws.p(b))))
        .collect();
    Ok((poses, report))
}
