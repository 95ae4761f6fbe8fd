//! The joint kinds as data: one [`KindInfo`] per [`JointKind`], the single description every
//! list in cardan is derived from (the builder's validation, the model file's accepted names and
//! keys, the drivers and springs a joint accepts, the units of its output columns, the
//! conformance and oracle registries, the documentation table).
//!
//! A kind's equations are a composition of [`Block`]s, a closed family of primitives built from
//! the two joint markers (each block knows its rows); its relative
//! coordinates are a list of [`Measure`]s. Adding a kind that these families can express is one
//! entry in [`KINDS`] plus one variant of [`JointKind`] (see ARCHITECTURE.md, "Adding a joint
//! kind").

use crate::marker::Marker;
use crate::primitive::Primitive;
use nalgebra::Vector3;

use crate::{Distance, Homokinetic, P1Perp, P2Perp, RadialDistance, Spherical, N1, N2};

/// An axis of a joint marker frame: x, y or the joint axis z.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// The marker's x axis (the zero of the joint angle).
    X,
    /// The marker's y axis, z × x.
    Y,
    /// The joint axis.
    Z,
}

impl Axis {
    fn of(self, m: &Marker) -> Vector3<f64> {
        match self {
            Axis::X => m.x(),
            Axis::Y => m.y(),
            Axis::Z => m.z(),
        }
    }

    fn letter(self) -> char {
        match self {
            Axis::X => 'x',
            Axis::Y => 'y',
            Axis::Z => 'z',
        }
    }
}

/// One block of a joint's equations: a primitive built from marker i (point P_i, axes x_i, y_i,
/// z_i) and marker j. A closed family: each block has a fixed row count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    /// s(P_i, P_j) = P_i − P_j: coincident points (3 rows; [`Spherical`]).
    Coincident,
    /// n1(a_i, b_j) = a_iᵀ b_j: the two axes perpendicular (1 row; [`N1`]).
    Perpendicular(Axis, Axis),
    /// [x_iᵀ z_j; y_iᵀ z_j]: z_j parallel to z_i (2 rows; [`P1Perp`]).
    ParallelAxes,
    /// [x_iᵀ d; y_iᵀ d], d = P_j − P_i: P_j on the line through P_i along z_i (2 rows; [`P2Perp`]).
    OnAxisLine,
    /// a_iᵀ d − h: P_j in the plane through P_i normal to a_i, shifted by the joint's offset h
    /// along a_i (1 row; [`N2`] with its offset).
    InPlane(Axis),
    /// dᵀd − ℓ²: P_j at distance ℓ from P_i (1 row; [`Distance`]).
    Distance,
    /// (x_iᵀ d)² + (y_iᵀ d)² − ℓ²: P_j at distance ℓ from the line through P_i along z_i
    /// (1 row; [`RadialDistance`]).
    RadialDistance,
    /// (cos α y_i + sin α z_i)ᵀ z_j: z_j at the angle α from z_i, measured about x_i
    /// (1 row; [`N1`]).
    AtAngle,
    /// z_iᵀ z_j − cos α: z_j on the cone of half-angle α about z_i (1 row; [`N1`] with the
    /// value cos α). Singular where z_i ∥ z_j, so α near 0 or π is refused at model build.
    Cone,
    /// x_iᵀ y_j − y_iᵀ x_j: no relative twist about the z axes, the constant-velocity condition
    /// (1 row; [`Homokinetic`]).
    Homokinetic,
}

/// The numbers a joint takes besides its markers (zero for those its kind does not take;
/// [`KindInfo::length`], [`KindInfo::offset`], [`KindInfo::angle`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointParams {
    /// ℓ of [`Block::Distance`] and [`Block::RadialDistance`], m (> 0).
    pub length: f64,
    /// h of [`Block::InPlane`], m.
    pub offset: f64,
    /// α of [`Block::AtAngle`] and [`Block::Cone`], rad.
    pub angle: f64,
}

impl Block {
    /// Number of equations.
    pub const fn rows(self) -> usize {
        match self {
            Block::Coincident => 3,
            Block::ParallelAxes | Block::OnAxisLine => 2,
            Block::Perpendicular(..)
            | Block::InPlane(_)
            | Block::Distance
            | Block::RadialDistance
            | Block::AtAngle
            | Block::Cone
            | Block::Homokinetic => 1,
        }
    }

    /// The primitive between markers `mi` and `mj` with the joint's numbers `v`.
    pub fn primitive(self, mi: &Marker, mj: &Marker, v: &JointParams) -> Primitive {
        let (pi, pj) = (mi.point, mj.point);
        match self {
            Block::Coincident => Spherical::new(pi, pj).into(),
            Block::Perpendicular(a, b) => N1::new(a.of(mi), b.of(mj)).into(),
            Block::ParallelAxes => P1Perp::new(mi.x(), mi.y(), mj.z()).into(),
            Block::OnAxisLine => P2Perp::new(mi.x(), mi.y(), pi, pj).into(),
            Block::InPlane(a) => N2::with_offset(a.of(mi), pi, pj, v.offset).into(),
            Block::Distance => Distance::new(pi, pj, v.length).into(),
            Block::RadialDistance => RadialDistance::new(mi.x(), mi.y(), pi, pj, v.length).into(),
            Block::AtAngle => {
                let (s, c) = v.angle.sin_cos();
                N1::new(c * mi.y() + s * mi.z(), mj.z()).into()
            }
            Block::Cone => N1::with_value(mi.z(), mj.z(), v.angle.cos()).into(),
            Block::Homokinetic => Homokinetic::new(mi.x(), mi.y(), mj.x(), mj.y()).into(),
        }
    }

    /// The block in the notation of the joint docs, e.g. `n1(x_i, z_j)`.
    pub fn notation(self) -> String {
        match self {
            Block::Coincident => "s(P_i, P_j)".into(),
            Block::Perpendicular(a, b) => format!("n1({}_i, {}_j)", a.letter(), b.letter()),
            Block::ParallelAxes => "n1(x_i, z_j); n1(y_i, z_j)".into(),
            Block::OnAxisLine => "n2(x_i; P_i, P_j); n2(y_i; P_i, P_j)".into(),
            Block::InPlane(a) => format!("n2({}_i; P_i, P_j) − h", a.letter()),
            Block::Distance => "distance(P_i, P_j, ℓ)".into(),
            Block::RadialDistance => "(x_iᵀd)² + (y_iᵀd)² − ℓ²".into(),
            Block::AtAngle => "n1(cos α y_i + sin α z_i, z_j)".into(),
            Block::Cone => "n1(z_i, z_j) − cos α".into(),
            Block::Homokinetic => "x_iᵀy_j − y_iᵀx_j".into(),
        }
    }
}

/// What a joint coordinate measures (d = P_j − P_i; x_k, y_k, z_k the global marker axes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The angle of x_j from x_i about z_i, atan2(y_iᵀ x_j, x_iᵀ x_j), rad.
    Angle,
    /// The slide z_iᵀ d along the joint axis, m.
    Slide,
    /// The component a_iᵀ d of d in marker frame i, m.
    Offset(Axis),
    /// The current distance |d|, m.
    Distance,
    /// The direction of z_j in the x–y plane of marker i, atan2(y_iᵀ z_j, x_iᵀ z_j) (for the
    /// universal joint: its cross about arm z_i relative to body i).
    CrossAngleI,
    /// Body j about arm z_j relative to the cross, atan2(y_jᵀ z_i, x_jᵀ z_i).
    CrossAngleJ,
    /// Bryant 1-2-3 angle k (0, 1, 2) of marker frame j relative to marker frame i.
    Bryant(usize),
    /// The angle of z_j from z_i about x_i, atan2(−y_iᵀ z_j, z_iᵀ z_j).
    AxisAngle,
    /// The angle between z_i and z_j, atan2(|z_i × z_j|, z_iᵀ z_j), in [0, π].
    Bend,
    /// The direction of d across z_i, atan2(y_iᵀ d, x_iᵀ d).
    Azimuth,
}

/// The physical quantity of a joint coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateQuantity {
    /// An angle, rad (continued over full turns in outputs).
    Angle,
    /// A length, m.
    Length,
}

impl CoordinateQuantity {
    /// The SI unit written in output headers.
    pub fn unit(self) -> &'static str {
        match self {
            CoordinateQuantity::Angle => "rad",
            CoordinateQuantity::Length => "m",
        }
    }
}

impl Measure {
    /// Every measure (the oracle gate requires limit data for each: `limit_<key>`).
    pub const ALL: [Measure; 14] = [
        Measure::Angle,
        Measure::Slide,
        Measure::Offset(Axis::X),
        Measure::Offset(Axis::Y),
        Measure::Offset(Axis::Z),
        Measure::Distance,
        Measure::CrossAngleI,
        Measure::CrossAngleJ,
        Measure::Bryant(0),
        Measure::Bryant(1),
        Measure::Bryant(2),
        Measure::AxisAngle,
        Measure::Bend,
        Measure::Azimuth,
    ];

    /// A short name for the measure (oracle data, messages): `angle`, `slide`, `offset_x`, ...
    pub fn key(self) -> &'static str {
        match self {
            Measure::Angle => "angle",
            Measure::Slide => "slide",
            Measure::Offset(Axis::X) => "offset_x",
            Measure::Offset(Axis::Y) => "offset_y",
            Measure::Offset(Axis::Z) => "offset_z",
            Measure::Distance => "distance",
            Measure::CrossAngleI => "cross_angle_i",
            Measure::CrossAngleJ => "cross_angle_j",
            Measure::Bryant(0) => "bryant_x",
            Measure::Bryant(1) => "bryant_y",
            Measure::Bryant(_) => "bryant_z",
            Measure::AxisAngle => "axis_angle",
            Measure::Bend => "bend",
            Measure::Azimuth => "azimuth",
        }
    }

    /// Whether the measure is an angle continued over turns (an atan2 of two smooth scalars):
    /// every angle but [`Measure::Bend`] (in [0, π]) and the middle Bryant angle (an asin, in
    /// [−π/2, π/2]).
    pub fn turns(self) -> bool {
        self.quantity() == CoordinateQuantity::Angle
            && !matches!(self, Measure::Bend | Measure::Bryant(1))
    }

    /// Angle or length.
    pub fn quantity(self) -> CoordinateQuantity {
        match self {
            Measure::Angle
            | Measure::CrossAngleI
            | Measure::CrossAngleJ
            | Measure::Bryant(_)
            | Measure::AxisAngle
            | Measure::Bend
            | Measure::Azimuth => CoordinateQuantity::Angle,
            Measure::Slide | Measure::Offset(_) | Measure::Distance => CoordinateQuantity::Length,
        }
    }
}

/// How far (rad) a cone joint's α must stay from 0 and π: there z_iᵀz_j − cos α has a zero
/// gradient at the solution (the row loses rank).
pub const CONE_MARGIN: f64 = 1e-3;

/// The most coordinates a kind has.
pub const MAX_COORDINATES: usize = 4;

/// A named joint coordinate, written to `joints.csv` as `joint.name [unit]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coordinate {
    /// Its name.
    pub name: &'static str,
    /// What it measures.
    pub measure: Measure,
}

const fn coord(name: &'static str, measure: Measure) -> Coordinate {
    Coordinate { name, measure }
}

/// Whether a joint kind takes axes (`axis_i`, `axis_j`: the z axes of its markers), and what
/// they mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axes {
    /// Required; their meaning.
    Required(&'static str),
    /// Accepted; their meaning (without them the marker frames are the body frames).
    Optional(&'static str),
    /// `axis_i` (and `x_axis_i`) required on body i, refused on body j: the kind uses marker i's
    /// frame only; its meaning.
    OnlyI(&'static str),
    /// Refused: the kind's equations and coordinates do not use them.
    Unused,
}

impl Axes {
    /// Whether the kind requires `axis_i`.
    pub fn required(self) -> bool {
        matches!(self, Axes::Required(_) | Axes::OnlyI(_))
    }

    /// Whether the kind accepts axes (`axis_i` at least).
    pub fn accepted(self) -> bool {
        !matches!(self, Axes::Unused)
    }

    /// Whether the kind takes `axis_j` and `x_axis_j` (a frame on body j).
    pub fn on_j(self) -> bool {
        matches!(self, Axes::Required(_) | Axes::Optional(_))
    }
}

/// Everything cardan knows about a joint kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KindInfo {
    /// The kind.
    pub kind: JointKind,
    /// The name in model files, oracle data and outputs.
    pub name: &'static str,
    /// Other names model files accept.
    pub aliases: &'static [&'static str],
    /// One line for the documentation.
    pub summary: &'static str,
    /// Whether the kind takes `axis_i` / `axis_j`, and what they mean.
    pub axes: Axes,
    /// Whether the kind accepts x axes (`x_axis_i`, `x_axis_j`: the zero of its angles); a kind
    /// that does not refuses them.
    pub x_axes: bool,
    /// Whether the kind takes a `length` ℓ (default: its drawn value, see
    /// [`KindInfo::drawn_length`]).
    pub length: bool,
    /// Whether the kind takes an `offset` h of its plane along z_i (default 0).
    pub offset: bool,
    /// Whether the kind takes an `angle` α (default: the drawn angle).
    pub angle: bool,
    /// Its equations, in row order.
    pub blocks: &'static [Block],
    /// Its relative coordinates, in output order.
    pub coordinates: &'static [Coordinate],
    /// The coordinate a rotation driver or a rotational spring acts on (an angle measured from
    /// x_axis_i to x_axis_j about z_i: x axes required), if any.
    pub rotation: Option<&'static str>,
    /// The coordinate a translation driver acts on (a slide along z_i), if any.
    pub translation: Option<&'static str>,
}

impl KindInfo {
    /// The coordinate `name`, or without a name the kind's default one (a limit's or a held
    /// stop's): its only coordinate, else its rotation, else its translation. `None` when the
    /// kind has no such coordinate, or several and neither a rotation nor a translation.
    pub fn coordinate(&self, name: Option<&str>) -> Option<&'static Coordinate> {
        let name = match name {
            Some(n) => n,
            None if self.coordinates.len() == 1 => self.coordinates[0].name,
            None => self.rotation.or(self.translation)?,
        };
        self.coordinates.iter().find(|c| c.name == name)
    }

    /// Number of equations (sum of the blocks' rows).
    pub const fn rows(&self) -> usize {
        let mut n = 0;
        let mut k = 0;
        while k < self.blocks.len() {
            n += self.blocks[k].rows();
            k += 1;
        }
        n
    }

    /// Degrees of freedom between the two bodies when the equations are independent.
    pub const fn relative_dof(&self) -> usize {
        6 - self.rows()
    }

    /// Whether `name` (or an alias) names this kind.
    pub fn is_called(&self, name: &str) -> bool {
        self.name == name || self.aliases.contains(&name)
    }

    /// The `length` that makes the kind's length block hold at the drawn pose (its default):
    /// the distance of P_j from the line through P_i along z_i for [`Block::RadialDistance`],
    /// else |P_j − P_i|. `d` = P_j − P_i and `z_i` in any common frame.
    pub fn drawn_length(&self, d: &Vector3<f64>, z_i: &Vector3<f64>) -> f64 {
        if self.blocks.contains(&Block::RadialDistance) {
            let z = z_i.normalize();
            (d - z * z.dot(d)).norm()
        } else {
            d.norm()
        }
    }

    /// The equations in the notation of the joint docs.
    pub fn notation(&self) -> String {
        let b: Vec<String> = self.blocks.iter().map(|b| b.notation()).collect();
        b.join("; ")
    }
}

use Axis::{X, Y, Z};
use Block::{Coincident, InPlane, OnAxisLine, ParallelAxes, Perpendicular};

const ANGLE: Coordinate = coord("angle", Measure::Angle);
const SLIDE: Coordinate = coord("slide", Measure::Slide);

/// Declares [`JointKind`] and [`KINDS`] from one list, so a variant cannot exist without its
/// description (and the description's `kind` is filled in).
macro_rules! joint_kinds {
    ($( $(#[$doc:meta])* $variant:ident => { $($field:ident : $value:expr),* $(,)? } ),* $(,)?) => {
        /// The kind of a joint; [`JointKind::info`] describes it.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum JointKind {
            $( $(#[$doc])* $variant, )*
        }

        /// Every kind's description, in [`JointKind`] order.
        pub const KINDS: &[KindInfo] = &[
            $( KindInfo { kind: JointKind::$variant, $($field: $value),* }, )*
        ];
    };
}

// The parallel conditions use the always-rank-2 form (two rows with the marker's x and y,
// `P1Perp` and `P2Perp`), so a joint never loses rank through its own equations.
joint_kinds! {
    /// Coincident points (3 rows).
    Spherical => {
        name: "spherical",
        aliases: &[],
        summary: "coincident points: a ball joint",
        axes: Axes::Optional("with the x axes, the frames its Bryant angles are measured between"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Coincident],
        coordinates: &[
            coord("angle_x", Measure::Bryant(0)),
            coord("angle_y", Measure::Bryant(1)),
            coord("angle_z", Measure::Bryant(2)),
        ],
        rotation: None,
        translation: None,
    },
    /// Coincident points, perpendicular cross arms z_i ⟂ z_j (4 rows).
    Universal => {
        name: "universal",
        aliases: &[],
        summary: "coincident points, perpendicular cross arms z_i ⟂ z_j",
        axes: Axes::Required(
            "the two arms of the cross (perpendicular; drawn at least 45° apart, else the model \
             is refused)",
        ),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Coincident, Perpendicular(Z, Z)],
        coordinates: &[
            coord("angle_i", Measure::CrossAngleI),
            coord("angle_j", Measure::CrossAngleJ),
        ],
        rotation: None,
        translation: None,
    },
    /// Coincident points, common axis z (5 rows).
    Revolute => {
        name: "revolute",
        aliases: &[],
        summary: "coincident points and a common axis: rotation about it",
        axes: Axes::Required("the common axis"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Coincident, ParallelAxes],
        coordinates: &[ANGLE],
        rotation: Some("angle"),
        translation: None,
    },
    /// Common axis z, rotation and sliding along it (4 rows).
    Cylindrical => {
        name: "cylindrical",
        aliases: &[],
        summary: "a common axis: rotation about it and sliding along it",
        axes: Axes::Required("the common axis"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[ParallelAxes, OnAxisLine],
        coordinates: &[ANGLE, SLIDE],
        rotation: Some("angle"),
        translation: Some("slide"),
    },
    /// Common axis z, sliding only (5 rows).
    Prismatic => {
        name: "prismatic",
        aliases: &["translational"],
        summary: "a common axis and no rotation: sliding along it",
        axes: Axes::Required("the common axis"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[ParallelAxes, OnAxisLine, Perpendicular(X, Y)],
        coordinates: &[SLIDE],
        rotation: None,
        translation: Some("slide"),
    },
    /// No relative motion (6 rows).
    Fixed => {
        name: "fixed",
        aliases: &[],
        summary: "no relative motion",
        axes: Axes::Required("a common axis (and x axes for the twist)"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Coincident, ParallelAxes, Perpendicular(X, Y)],
        coordinates: &[],
        rotation: None,
        translation: None,
    },
    /// Two points at a constant distance (1 row).
    SphericalSpherical => {
        name: "spherical_spherical",
        aliases: &["distance"],
        summary: "two points at a constant distance: a massless rod with ball joints at both ends",
        axes: Axes::Unused,
        x_axes: false,
        length: true,
        offset: false,
        angle: false,
        blocks: &[Block::Distance],
        coordinates: &[coord("distance", Measure::Distance)],
        rotation: None,
        translation: None,
    },
    /// Plane normals z_i ∥ z_j and P_j in the plane of i (3 rows).
    Planar => {
        name: "planar",
        aliases: &[],
        summary: "parallel plane normals and P_j in the plane of i: sliding and turning in a plane",
        axes: Axes::Required("the plane normals"),
        x_axes: true,
        length: false,
        offset: true,
        angle: false,
        blocks: &[ParallelAxes, InPlane(Z)],
        coordinates: &[
            coord("x", Measure::Offset(X)),
            coord("y", Measure::Offset(Y)),
            ANGLE,
        ],
        rotation: None,
        translation: None,
    },
    /// Axes z_i ⟂ z_j, points free (1 row).
    Perpendicular => {
        name: "perpendicular",
        aliases: &[],
        summary: "the two axes held perpendicular, z_i ⟂ z_j; everything else free",
        axes: Axes::Required("the two axes held perpendicular"),
        x_axes: false,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Perpendicular(Z, Z)],
        coordinates: &[],
        rotation: None,
        translation: None,
    },
    /// P_j on the line through P_i along z_i (2 rows).
    PointInLine => {
        name: "point_in_line",
        aliases: &[],
        summary: "P_j on the line through P_i along z_i: sliding along it, turning freely",
        axes: Axes::OnlyI("the line's direction z_i"),
        x_axes: false,
        length: false,
        offset: false,
        angle: false,
        blocks: &[OnAxisLine],
        coordinates: &[SLIDE],
        rotation: None,
        translation: Some("slide"),
    },
    /// P_j in the plane through P_i normal to z_i, shifted by the offset (1 row).
    PointInPlane => {
        name: "point_in_plane",
        aliases: &[],
        summary: "P_j in the plane through P_i normal to z_i (moved by `offset` along z_i)",
        axes: Axes::OnlyI("the plane normal z_i (x_axis_i: the x of the in-plane coordinates)"),
        x_axes: true,
        length: false,
        offset: true,
        angle: false,
        blocks: &[InPlane(Z)],
        coordinates: &[
            coord("x", Measure::Offset(X)),
            coord("y", Measure::Offset(Y)),
        ],
        rotation: None,
        translation: None,
    },
    /// The line through P_j along z_j in the plane of P_i normal to z_i (2 rows).
    LineInPlane => {
        name: "line_in_plane",
        aliases: &[],
        summary: "the line through P_j along z_j lies in the plane through P_i normal to z_i \
                  (moved by `offset` along z_i)",
        axes: Axes::Required("z_i: the plane normal; z_j: the line's direction"),
        x_axes: true,
        length: false,
        offset: true,
        angle: false,
        blocks: &[InPlane(Z), Perpendicular(Z, Z)],
        coordinates: &[
            coord("x", Measure::Offset(X)),
            coord("y", Measure::Offset(Y)),
            coord("angle", Measure::CrossAngleI),
        ],
        rotation: None,
        translation: None,
    },
    /// z_j parallel to z_i, points free (2 rows).
    ParallelAxes => {
        name: "parallel_axes",
        aliases: &[],
        summary: "the two axes held parallel, z_i ∥ z_j; translation free",
        axes: Axes::Required("the two axes held parallel"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[ParallelAxes],
        coordinates: &[
            ANGLE,
            coord("x", Measure::Offset(X)),
            coord("y", Measure::Offset(Y)),
            coord("z", Measure::Slide),
        ],
        rotation: Some("angle"),
        translation: Some("z"),
    },
    /// z_j at a fixed angle α from z_i about x_i (1 row).
    Angle => {
        name: "angle",
        aliases: &[],
        summary: "z_j at the angle α from z_i, measured about x_i (default x_i: the axes' \
                  common perpendicular as drawn); everything else free",
        axes: Axes::Required("the two axes whose angle is held"),
        x_axes: true,
        length: false,
        offset: false,
        angle: true,
        blocks: &[Block::AtAngle],
        coordinates: &[coord("angle", Measure::AxisAngle)],
        rotation: None,
        translation: None,
    },
    /// z_j on the cone of half-angle α about z_i: z_iᵀ z_j = cos α (1 row). OndselSolver's
    /// AngleJoint. The row loses rank where z_i ∥ z_j, so α within [`CONE_MARGIN`] of 0 or π
    /// is refused (use `parallel_axes`, or a `revolute`-style joint, for parallel axes).
    Cone => {
        name: "cone",
        aliases: &[],
        summary: "z_j on the cone of half-angle α about z_i, z_iᵀz_j = cos α (α from 0.001 to \
                  π − 0.001 rad); everything else free",
        axes: Axes::Required("the cone's axis z_i and the axis z_j held on it"),
        x_axes: false,
        length: false,
        offset: false,
        angle: true,
        blocks: &[Block::Cone],
        coordinates: &[coord("bend", Measure::Bend)],
        rotation: None,
        translation: None,
    },
    /// Marker frames held parallel, translation free (3 rows).
    NoRotation => {
        name: "no_rotation",
        aliases: &[],
        summary: "no relative rotation; translation free",
        axes: Axes::Optional("with the x axes, the frames held parallel"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[ParallelAxes, Perpendicular(X, Y)],
        coordinates: &[
            coord("x", Measure::Offset(X)),
            coord("y", Measure::Offset(Y)),
            coord("z", Measure::Slide),
        ],
        rotation: None,
        translation: Some("z"),
    },
    /// Coincident points and no relative twist: a constant-velocity joint (4 rows).
    ConstantVelocity => {
        name: "constant_velocity",
        aliases: &["cv"],
        summary: "coincident points and no relative twist about the shafts: shaft j turns at \
                  exactly the speed of shaft i at every bend",
        axes: Axes::Required("the two shaft axes, in the same sense (z_i = z_j when straight)"),
        x_axes: true,
        length: false,
        offset: false,
        angle: false,
        blocks: &[Coincident, Block::Homokinetic],
        coordinates: &[coord("bend", Measure::Bend)],
        rotation: None,
        translation: None,
    },
    /// Parallel axes at distance ℓ (3 rows).
    RevCyl => {
        name: "rev_cyl",
        aliases: &[],
        summary: "parallel axes at the distance ℓ: a link with a revolute joint on body i's \
                  axis and a cylindrical joint on body j's",
        axes: Axes::Required("the two parallel axes"),
        x_axes: true,
        length: true,
        offset: false,
        angle: false,
        blocks: &[ParallelAxes, Block::RadialDistance],
        coordinates: &[ANGLE, SLIDE, coord("azimuth", Measure::Azimuth)],
        rotation: Some("angle"),
        translation: Some("slide"),
    },
    /// P_j at distance ℓ from the line through P_i along z_i (1 row).
    CylSph => {
        name: "cyl_sph",
        aliases: &[],
        summary: "P_j at the distance ℓ from the line through P_i along z_i: a link with a \
                  cylindrical joint on body i and a spherical joint on body j",
        axes: Axes::OnlyI("the cylinder's axis z_i (x_axis_i: the zero of the azimuth)"),
        x_axes: true,
        length: true,
        offset: false,
        angle: false,
        blocks: &[Block::RadialDistance],
        coordinates: &[SLIDE, coord("azimuth", Measure::Azimuth)],
        rotation: None,
        translation: Some("slide"),
    },
    /// Parallel axes at distance ℓ, P_j in the plane of P_i normal to them (4 rows).
    RevRev => {
        name: "rev_rev",
        aliases: &[],
        summary: "parallel axes at the distance ℓ with P_j in the plane through P_i normal to \
                  them: a link with revolute joints at both ends",
        axes: Axes::Required("the two parallel axes"),
        x_axes: true,
        length: true,
        offset: true,
        angle: false,
        blocks: &[ParallelAxes, InPlane(Z), Block::RadialDistance],
        coordinates: &[ANGLE, coord("azimuth", Measure::Azimuth)],
        rotation: Some("angle"),
        translation: None,
    },
}

impl JointKind {
    /// The kind's description.
    pub fn info(self) -> &'static KindInfo {
        &KINDS[self as usize]
    }

    /// The name used in model files, oracle data and outputs.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Number of equations.
    pub fn rows(self) -> usize {
        self.info().rows()
    }

    /// The kind called `name` (or an alias), if any.
    pub fn from_name(name: &str) -> Option<JointKind> {
        KINDS.iter().find(|k| k.is_called(name)).map(|k| k.kind)
    }

    /// Every kind, in declaration order.
    pub fn all() -> impl Iterator<Item = JointKind> {
        KINDS.iter().map(|k| k.kind)
    }
}

fn axes_column(a: Axes) -> String {
    match a {
        Axes::Required(m) => m.into(),
        Axes::Optional(m) => format!("optional: {m}"),
        Axes::OnlyI(m) => format!("axis_i only: {m}"),
        Axes::Unused => "–".into(),
    }
}

fn numbers_column(k: &KindInfo) -> String {
    let mut n = Vec::new();
    if k.length {
        n.push("`length` ℓ [m] (default: as drawn)");
    }
    if k.offset {
        n.push("`offset` h [m] (default 0)");
    }
    if k.angle {
        n.push("`angle` α [rad] (default: as drawn)");
    }
    n.join(", ")
}

/// The joint table of docs/model-format.md, generated from [`KINDS`] (`cargo xtask docs`
/// writes it; a test fails when the committed table differs).
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| type | equations | rows, in order | axes | numbers | joint coordinates written | driven by |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for k in KINDS {
        let mut name = format!("`{}`", k.name);
        if !k.aliases.is_empty() {
            let a: Vec<String> = k.aliases.iter().map(|a| format!("`{a}`")).collect();
            name.push_str(&format!(" (alias {})", a.join(", ")));
        }
        let coords: Vec<String> = k
            .coordinates
            .iter()
            .map(|c| format!("{} [{}]", c.name, c.measure.quantity().unit()))
            .collect();
        let mut driven = Vec::new();
        if let Some(c) = k.rotation {
            driven.push(format!("rotation ({c}), rotational spring"));
        }
        if let Some(c) = k.translation {
            driven.push(format!("translation ({c})"));
        }
        let or_dash = |s: String| if s.is_empty() { "–".to_string() } else { s };
        out.push_str(&format!(
            "| {name}: {} | {} | {} | {} | {} | {} | {} |\n",
            k.summary,
            k.rows(),
            k.notation(),
            axes_column(k.axes),
            or_dash(numbers_column(k)),
            or_dash(coords.join(", ")),
            or_dash(driven.join("; ")),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_described_once_in_order() {
        for (k, info) in KINDS.iter().enumerate() {
            assert_eq!(info.kind as usize, k);
            assert_eq!(info.kind.info(), info);
            assert_eq!(JointKind::from_name(info.name), Some(info.kind));
            for a in info.aliases {
                assert_eq!(JointKind::from_name(a), Some(info.kind), "{a}");
            }
            assert!(info.rows() >= 1 && info.rows() <= 6, "{}", info.name);
            assert!(info.coordinates.len() <= MAX_COORDINATES, "{}", info.name);
            let rows_need = |b: Block| info.blocks.contains(&b);
            assert_eq!(
                info.length,
                rows_need(Block::Distance) || rows_need(Block::RadialDistance),
                "{}: takes a length exactly when a block uses one",
                info.name
            );
            assert_eq!(
                info.angle,
                rows_need(Block::AtAngle) || rows_need(Block::Cone),
                "{}",
                info.name
            );
            assert_eq!(
                info.offset,
                info.blocks.iter().any(|b| matches!(b, Block::InPlane(_))),
                "{}: takes an offset exactly when a block is a plane",
                info.name
            );
            for c in [info.rotation, info.translation].into_iter().flatten() {
                assert!(
                    info.coordinates.iter().any(|x| x.name == c),
                    "{}",
                    info.name
                );
            }
            if let Some(r) = info.rotation {
                assert!(info.x_axes, "{}: a driven angle needs x axes", info.name);
                // Springs and drivers read the angle as the first coordinate.
                assert_eq!(info.coordinates[0].name, r, "{}", info.name);
                assert_eq!(info.coordinates[0].measure, Measure::Angle, "{}", info.name);
            }
            if let Some(t) = info.translation {
                let c = info.coordinates.iter().find(|c| c.name == t).unwrap();
                assert_eq!(c.measure, Measure::Slide, "{}", info.name);
            }
            for c in info.coordinates {
                assert!(
                    Measure::ALL.contains(&c.measure),
                    "{}: {:?}",
                    info.name,
                    c.measure
                );
            }
        }
        let names: std::collections::BTreeSet<_> = KINDS
            .iter()
            .flat_map(|k| std::iter::once(k.name).chain(k.aliases.iter().copied()))
            .collect();
        let count: usize = KINDS.iter().map(|k| 1 + k.aliases.len()).sum();
        assert_eq!(names.len(), count, "names and aliases are unique");
    }
}
