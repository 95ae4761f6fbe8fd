//! Joints: compositions of primitives (Haug 1989 §9.3, Nikravesh 1988 §7.3–7.4).
//!
//! A joint connects body i and body j through a [`Marker`] on each (a point and a frame). Its
//! equations are a fixed list of primitives; the marker axes supply the primitive vectors:
//!
//! Each kind is described once, as data, in [`KINDS`] ([`JointKind::info`]): its rows as a
//! composition of [`Block`]s (each a primitive built from the two markers), which axes it needs,
//! its joint coordinates and what drives them. The joint table of docs/model-format.md is
//! generated from it (`cargo xtask docs`).
//!
//! The parallel conditions use the always-rank-2 form (two n1 or n2 rows with the marker's x and
//! y, see [`crate::P1Perp`]), so a joint never loses rank through its own equations. For the
//! universal joint z_i and z_j are the two arms of the cross (perpendicular); for the planar joint
//! z is the plane normal; for the prismatic joint the extra n1(x_i, y_j) stops rotation about z.
//!
//! [`JointCoordinates`] gives the relative joint coordinates for output, [`JointRates`] their
//! exact rates and accelerations.

mod coordinates;
mod kinds;
mod rates;

pub use coordinates::{continue_angle, unwrap_angle, JointCoordinates};
pub use kinds::{
    markdown_table, Axes, Axis, Block, Coordinate, CoordinateQuantity, JointKind, JointParams,
    KindInfo, Measure, CONE_MARGIN, KINDS, MAX_COORDINATES,
};
pub use rates::{BodyAcceleration, JointRates};

use crate::constraint::{Constraint, Dimension};
use crate::error::{finite, ConstraintError};
use crate::jet::Form;
use crate::marker::Marker;
use crate::primitive::Primitive;
use crate::state::{BodyPair, Footprint};

/// A joint between body i and body j: its kind, markers and the primitives it is made of.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    kind: JointKind,
    marker_i: Marker,
    marker_j: Marker,
    params: JointParams,
    primitives: Vec<Primitive>,
    rows: usize,
    footprint: Footprint,
}

impl Joint {
    /// A joint of `kind` between markers on body i and body j.
    ///
    /// A kind that takes a length or an angle ([`KindInfo::length`], [`KindInfo::angle`]) needs
    /// it: build it with [`Joint::with_params`]; here it is an error.
    pub fn new(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
    ) -> Result<Self, ConstraintError> {
        let info = kind.info();
        if info.length || info.angle {
            return Err(ConstraintError::Invalid(format!(
                "a {} joint needs a {}: use Joint::with_params",
                info.name,
                if info.length { "length" } else { "angle" }
            )));
        }
        Self::with_params(kind, marker_i, marker_j, JointParams::default())
    }

    /// A joint of a `kind` that takes a length ([`KindInfo::length`]; e.g. spherical-spherical)
    /// between markers on body i and body j; `length` > 0.
    pub fn with_length(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
        length: f64,
    ) -> Result<Self, ConstraintError> {
        if !kind.info().length {
            return Err(ConstraintError::Invalid(format!(
                "a {} joint takes no length: use Joint::new",
                kind.name()
            )));
        }
        let params = JointParams {
            length,
            ..JointParams::default()
        };
        Self::with_params(kind, marker_i, marker_j, params)
    }

    /// A joint of `kind` with its numbers: `length` > 0 when the kind takes one, `offset` and
    /// `angle` finite; a number the kind does not take must be 0.
    pub fn with_params(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
        params: JointParams,
    ) -> Result<Self, ConstraintError> {
        let info = kind.info();
        let JointParams {
            length,
            offset,
            angle,
        } = params;
        for (what, value, takes) in [
            ("length", length, info.length),
            ("offset", offset, info.offset),
            ("angle", angle, info.angle),
        ] {
            finite(&format!("{} {what}", info.name), &[value])?;
            if !takes && value != 0.0 {
                return Err(ConstraintError::Invalid(format!(
                    "a {} joint takes no {what}",
                    info.name
                )));
            }
        }
        if info.length && length <= 0.0 {
            return Err(ConstraintError::NotPositive {
                what: format!("{} length", info.name),
                value: length,
            });
        }
        Ok(Self::from_blocks(kind, marker_i, marker_j, params))
    }

    /// Two points kept at distance `length` > 0 (a massless rod with ball joints at both ends).
    pub fn spherical_spherical(
        point_i: nalgebra::Vector3<f64>,
        point_j: nalgebra::Vector3<f64>,
        length: f64,
    ) -> Result<Self, ConstraintError> {
        finite("spherical-spherical point", point_i.as_slice())?;
        finite("spherical-spherical point", point_j.as_slice())?;
        let m = |p| Marker {
            point: p,
            frame: nalgebra::Matrix3::identity(),
        };
        Self::with_length(
            JointKind::SphericalSpherical,
            m(point_i),
            m(point_j),
            length,
        )
    }

    /// The joint's primitives from its kind's blocks ([`KindInfo::blocks`]).
    fn from_blocks(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
        params: JointParams,
    ) -> Self {
        let primitives = kind
            .info()
            .blocks
            .iter()
            .map(|b| b.primitive(&marker_i, &marker_j, &params))
            .collect();
        Self::assemble(kind, marker_i, marker_j, params, primitives)
    }

    fn assemble(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
        params: JointParams,
        primitives: Vec<Primitive>,
    ) -> Self {
        let rows = primitives.iter().map(|p| p.rows()).sum();
        debug_assert_eq!(rows, kind.rows());
        let footprint = primitives
            .iter()
            .map(|p| p.footprint())
            .reduce(Footprint::or)
            .expect("a joint has at least one primitive");
        Self {
            kind,
            marker_i,
            marker_j,
            params,
            primitives,
            rows,
            footprint,
        }
    }

    /// The joint kind.
    pub fn kind(&self) -> JointKind {
        self.kind
    }

    /// The marker on body i.
    pub fn marker_i(&self) -> &Marker {
        &self.marker_i
    }

    /// The marker on body j.
    pub fn marker_j(&self) -> &Marker {
        &self.marker_j
    }

    /// ℓ of a joint that takes a length (0 for the others).
    pub fn length(&self) -> f64 {
        self.params.length
    }

    /// The joint's numbers (length, offset, angle; 0 for those its kind does not take).
    pub fn params(&self) -> &JointParams {
        &self.params
    }

    /// The primitives, in row order.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// Which primitive (and its name) a row of this joint belongs to: for error messages.
    pub fn row_origin(&self, row: usize) -> Option<(usize, &'static str)> {
        let mut start = 0;
        for (k, p) in self.primitives.iter().enumerate() {
            if row < start + p.rows() {
                return Some((k, p.name()));
            }
            start += p.rows();
        }
        None
    }
}

impl Constraint for Joint {
    fn name(&self) -> &'static str {
        self.kind.name()
    }
    fn rows(&self) -> usize {
        self.rows
    }
    fn dimension(&self, row: usize) -> Dimension {
        let mut start = 0;
        for p in &self.primitives {
            if row < start + p.rows() {
                return p.dimension(row - start);
            }
            start += p.rows();
        }
        panic!("row {row} of a {}-row joint", self.rows)
    }
    fn footprint(&self) -> Footprint {
        self.footprint
    }
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let mut r = 0;
        for p in &self.primitives {
            let n = p.rows();
            p.phi(x, t, &mut out[r..r + n]);
            r += n;
        }
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let mut r = 0;
        for p in &self.primitives {
            let n = p.rows();
            p.jacobian::<N, F>(x, t, &mut out_i[r..r + n], &mut out_j[r..r + n]);
            r += n;
        }
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let mut r = 0;
        for p in &self.primitives {
            let n = p.rows();
            p.gamma_sharp::<N, F>(x, t, &mut out[r..r + n]);
            r += n;
        }
    }
}
