//! [`Marker`]: a point and an orthonormal frame fixed in a body, the data joints are built from.

use crate::error::{finite, ConstraintError};
use cardan_eulerparam::{frame_from_axis, frame_from_two_axes, EulerParamError};
use nalgebra::{Matrix3, Vector3};

/// A body-fixed point with a right-handed orthonormal frame [x y z] (body components).
///
/// Joints read their axes from markers: z is the joint axis (revolute, cylindrical, prismatic),
/// the cross arm (universal) or the plane normal (planar); x and y span the perpendicular plane
/// and give the zero of joint angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    /// s'^P, the point in body coordinates.
    pub point: Vector3<f64>,
    /// The frame, columns x', y', z' in body coordinates.
    pub frame: Matrix3<f64>,
}

fn from_ep(what: &str, e: EulerParamError) -> ConstraintError {
    match e {
        EulerParamError::ZeroAxis { .. } => ConstraintError::ZeroAxis {
            what: what.to_string(),
        },
        EulerParamError::ParallelAxes { .. } => ConstraintError::ParallelAxes {
            what: what.to_string(),
        },
        EulerParamError::NotFinite { value, .. } => ConstraintError::NotFinite {
            what: what.to_string(),
            value: value
                .into_iter()
                .find(|v| !v.is_finite())
                .unwrap_or(f64::NAN),
        },
        other => ConstraintError::Invalid(format!("{what}: {other}")),
    }
}

impl Marker {
    /// A marker from a point and a full frame (validated: orthonormal to 1e-9, det = +1).
    pub fn new(point: Vector3<f64>, frame: Matrix3<f64>) -> Result<Self, ConstraintError> {
        finite("marker point", point.as_slice())?;
        finite("marker frame", frame.as_slice())?;
        let error = (frame.transpose() * frame - Matrix3::identity()).norm();
        let det = frame.determinant();
        if error > 1e-9 || det <= 0.0 {
            return Err(ConstraintError::NotOrthonormal {
                what: "marker frame".into(),
                error,
                det,
            });
        }
        Ok(Self { point, frame })
    }

    /// A marker at `point` whose z is along `z`; x, y are a fixed perpendicular pair
    /// ([`cardan_eulerparam::frame_from_axis`]).
    pub fn from_axis(point: Vector3<f64>, z: Vector3<f64>) -> Result<Self, ConstraintError> {
        finite("marker point", point.as_slice())?;
        let frame = frame_from_axis(&z).map_err(|e| from_ep("marker z axis", e))?;
        Ok(Self { point, frame })
    }

    /// A marker at `point` with z along `z` and x along the part of `x` perpendicular to z.
    pub fn from_axes(
        point: Vector3<f64>,
        z: Vector3<f64>,
        x: Vector3<f64>,
    ) -> Result<Self, ConstraintError> {
        finite("marker point", point.as_slice())?;
        let frame = frame_from_two_axes(&z, &x).map_err(|e| from_ep("marker axes", e))?;
        Ok(Self { point, frame })
    }

    /// x' (body components).
    pub fn x(&self) -> Vector3<f64> {
        self.frame.column(0).into_owned()
    }

    /// y' (body components).
    pub fn y(&self) -> Vector3<f64> {
        self.frame.column(1).into_owned()
    }

    /// z' (body components).
    pub fn z(&self) -> Vector3<f64> {
        self.frame.column(2).into_owned()
    }
}
