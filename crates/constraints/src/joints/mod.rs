//! Joints: compositions of primitives (Haug 1989 §9.3, Nikravesh 1988 §7.3–7.4).
//!
//! A joint connects body i and body j through a [`Marker`] on each (a point and a frame). Its
//! equations are a fixed list of primitives; the marker axes supply the primitive vectors:
//!
//! | joint | rows, in order | count | relative DOF |
//! |---|---|---|---|
//! | spherical | s(P_i, P_j) | 3 | 3 |
//! | universal | s(P_i, P_j); n1(z_i, z_j) | 4 | 2 |
//! | revolute | s(P_i, P_j); n1(x_i, z_j); n1(y_i, z_j) | 5 | 1 |
//! | cylindrical | n1(x_i, z_j); n1(y_i, z_j); n2(x_i; P_i, P_j); n2(y_i; P_i, P_j) | 4 | 2 |
//! | prismatic | cylindrical rows; n1(x_i, y_j) | 5 | 1 |
//! | fixed | s(P_i, P_j); n1(x_i, z_j); n1(y_i, z_j); n1(x_i, y_j) | 6 | 0 |
//! | spherical-spherical | distance(P_i, P_j, ℓ) | 1 | 5 |
//! | planar | n1(x_i, z_j); n1(y_i, z_j); n2(z_i; P_i, P_j) | 3 | 3 |
//!
//! The parallel conditions use the always-rank-2 form (two n1 or n2 rows with the marker's x and
//! y, see [`crate::P1Perp`]), so a joint never loses rank through its own equations. For the
//! universal joint z_i and z_j are the two arms of the cross (perpendicular); for the planar joint
//! z is the plane normal; for the prismatic joint the extra n1(x_i, y_j) stops rotation about z.
//!
//! [`JointCoordinates`] gives the relative joint coordinates for output.

mod coordinates;

pub use coordinates::{unwrap_angle, JointCoordinates};

use crate::constraint::Constraint;
use crate::error::{finite, ConstraintError};
use crate::jet::Form;
use crate::marker::Marker;
use crate::primitive::Primitive;
use crate::state::{BodyPair, Footprint};
use crate::{Distance, P1Perp, P2Perp, Spherical, N1, N2};

/// The kind of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointKind {
    /// Coincident points (3 rows).
    Spherical,
    /// Coincident points, perpendicular cross arms z_i ⟂ z_j (4 rows).
    Universal,
    /// Coincident points, common axis z (5 rows).
    Revolute,
    /// Common axis z, rotation and sliding along it (4 rows).
    Cylindrical,
    /// Common axis z, sliding only (5 rows).
    Prismatic,
    /// No relative motion (6 rows).
    Fixed,
    /// Two points at a constant distance (1 row).
    SphericalSpherical,
    /// Plane normals z_i ∥ z_j and P_j in the plane of i (3 rows).
    Planar,
}

impl JointKind {
    /// The name used in model files and oracle data.
    pub fn name(self) -> &'static str {
        match self {
            JointKind::Spherical => "spherical",
            JointKind::Universal => "universal",
            JointKind::Revolute => "revolute",
            JointKind::Cylindrical => "cylindrical",
            JointKind::Prismatic => "prismatic",
            JointKind::Fixed => "fixed",
            JointKind::SphericalSpherical => "spherical_spherical",
            JointKind::Planar => "planar",
        }
    }

    /// Number of equations.
    pub fn rows(self) -> usize {
        match self {
            JointKind::Spherical | JointKind::Planar => 3,
            JointKind::Universal | JointKind::Cylindrical => 4,
            JointKind::Revolute | JointKind::Prismatic => 5,
            JointKind::Fixed => 6,
            JointKind::SphericalSpherical => 1,
        }
    }

    /// All kinds, for iteration in tests and documentation.
    pub const ALL: [JointKind; 8] = [
        JointKind::Spherical,
        JointKind::Universal,
        JointKind::Revolute,
        JointKind::Cylindrical,
        JointKind::Prismatic,
        JointKind::Fixed,
        JointKind::SphericalSpherical,
        JointKind::Planar,
    ];
}

/// A joint between body i and body j: its kind, markers and the primitives it is made of.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    kind: JointKind,
    marker_i: Marker,
    marker_j: Marker,
    length: f64,
    primitives: Vec<Primitive>,
    rows: usize,
    footprint: Footprint,
}

impl Joint {
    /// A joint of `kind` between markers on body i and body j.
    ///
    /// [`JointKind::SphericalSpherical`] needs a length, which markers do not carry: build it
    /// with [`Joint::spherical_spherical`]; here it is an error.
    pub fn new(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
    ) -> Result<Self, ConstraintError> {
        if kind == JointKind::SphericalSpherical {
            return Err(ConstraintError::Invalid(
                "a spherical-spherical joint needs a length: use Joint::spherical_spherical".into(),
            ));
        }
        let (pi, pj) = (marker_i.point, marker_j.point);
        let (xi, yi, zi) = (marker_i.x(), marker_i.y(), marker_i.z());
        let (yj, zj) = (marker_j.y(), marker_j.z());
        let s = Primitive::from(Spherical::new(pi, pj));
        let p1 = Primitive::from(P1Perp::new(xi, yi, zj));
        let p2 = Primitive::from(P2Perp::new(xi, yi, pi, pj));
        let twist = Primitive::from(N1::new(xi, yj));
        let primitives = match kind {
            JointKind::Spherical => vec![s],
            JointKind::Universal => vec![s, N1::new(zi, zj).into()],
            JointKind::Revolute => vec![s, p1],
            JointKind::Cylindrical => vec![p1, p2],
            JointKind::Prismatic => vec![p1, p2, twist],
            JointKind::Fixed => vec![s, p1, twist],
            JointKind::Planar => vec![p1, N2::new(zi, pi, pj).into()],
            JointKind::SphericalSpherical => unreachable!("handled above"),
        };
        Ok(Self::assemble(kind, marker_i, marker_j, 0.0, primitives))
    }

    /// Two points kept at distance `length` > 0 (a massless rod with ball joints at both ends).
    pub fn spherical_spherical(
        point_i: nalgebra::Vector3<f64>,
        point_j: nalgebra::Vector3<f64>,
        length: f64,
    ) -> Result<Self, ConstraintError> {
        finite("spherical-spherical point", point_i.as_slice())?;
        finite("spherical-spherical point", point_j.as_slice())?;
        finite("spherical-spherical length", &[length])?;
        if length <= 0.0 {
            return Err(ConstraintError::NotPositive {
                what: "spherical-spherical length".into(),
                value: length,
            });
        }
        let m = |p| Marker {
            point: p,
            frame: nalgebra::Matrix3::identity(),
        };
        let prim = Distance::new(point_i, point_j, length).into();
        Ok(Self::assemble(
            JointKind::SphericalSpherical,
            m(point_i),
            m(point_j),
            length,
            vec![prim],
        ))
    }

    fn assemble(
        kind: JointKind,
        marker_i: Marker,
        marker_j: Marker,
        length: f64,
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
            length,
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

    /// ℓ of a spherical-spherical joint (0 for the others).
    pub fn length(&self) -> f64 {
        self.length
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
