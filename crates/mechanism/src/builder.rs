//! The builder: bodies, named points and vectors, joints and drivers, validated by
//! [`MechanismBuilder::build`] into an immutable [`Model`](crate::Model) (`model/build.rs`:
//! the builder holds the specifications only and knows nothing of the model).
//!
//! Everything is referred to by name. A body's points and vectors are named per body
//! (`"crank"`, `"B"`), so a model file can say "a revolute joint between ground point `A` about
//! ground vector `x` and crank point `A` about crank vector `x`":
//!
//! ```
//! use cardan_mechanism::{Body, JointSpec, MechanismBuilder, GROUND};
//! use cardan_constraints::JointKind;
//! use nalgebra::Vector3;
//! let mut b = MechanismBuilder::new();
//! b.body(Body::new("crank").position(Vector3::new(0.0, 0.1, 0.16)));
//! b.point(GROUND, "A", Vector3::new(0.0, 0.1, 0.12));
//! b.vector(GROUND, "x", Vector3::x());
//! b.point("crank", "A", Vector3::new(0.0, 0.0, -0.04));
//! b.vector("crank", "x", Vector3::x());
//! b.joint(JointSpec::new("A", JointKind::Revolute, (GROUND, "A"), ("crank", "A")).axes("x", "x"));
//! let model = b.build().unwrap();
//! assert_eq!(model.num_bodies(), 1);
//! ```
//!
//! The ground body [`GROUND`] exists from the start; its points and vectors are global. It has no
//! unknowns: its coordinates are eliminated, not constrained.

use crate::curve_spec::{CamSpec, CurveSpec, PathSpec, SurfaceSpec};
use crate::shape_spec::{MaterialSpec, ShapeSpec};
use cardan_constraints::drivers::POSE_ROWS;
use cardan_constraints::{JointKind, RotationOrder, TimeFunction};
use cardan_eulerparam::{
    frame_from_axis, frame_from_two_axes, p_from_euler_123, p_from_euler_313,
    p_from_rotation_matrix, EulerParamError, EulerParams,
};
use nalgebra::{Matrix3, Vector3};

/// The name of the built-in ground body.
pub const GROUND: &str = "ground";

/// The initial orientation of a body (body frame → global), in any of the usual forms.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Orientation {
    /// Body axes along the global axes.
    #[default]
    Identity,
    /// Euler parameters [e0, e1, e2, e3] (normalized by the builder; must not be zero).
    EulerParams([f64; 4]),
    /// A rotation by `angle` (rad) about `axis` (global, any nonzero length).
    AxisAngle {
        /// Rotation axis.
        axis: Vector3<f64>,
        /// Angle in rad.
        angle: f64,
    },
    /// Euler angles 3-1-3 (φ, θ, ψ) in rad.
    Euler313([f64; 3]),
    /// Bryant angles 1-2-3 (φ, θ, ψ) in rad.
    Euler123([f64; 3]),
    /// The body z axis along `z` (global) and, if given, the body x axis along the part of `x`
    /// perpendicular to z (else a fixed perpendicular is chosen).
    Axes {
        /// Global direction of the body z axis.
        z: Vector3<f64>,
        /// Global direction hint for the body x axis.
        x: Option<Vector3<f64>>,
    },
}

impl Orientation {
    /// The Euler parameters of this orientation (unit length, e0 ≥ 0 for the matrix and axis
    /// forms). Fails on zero or parallel axes, zero-length parameters or non-finite numbers.
    pub fn euler_params(&self) -> Result<EulerParams, EulerParamError> {
        match self {
            Orientation::Identity => Ok(EulerParams::identity()),
            Orientation::EulerParams(e) => EulerParams::try_new_normalized(e[0], e[1], e[2], e[3]),
            Orientation::AxisAngle { axis, angle } => EulerParams::from_axis_angle(axis, *angle),
            Orientation::Euler313(a) => p_from_euler_313(a[0], a[1], a[2]),
            Orientation::Euler123(a) => p_from_euler_123(a[0], a[1], a[2]),
            Orientation::Axes { z, x } => {
                let frame = match x {
                    Some(x) => frame_from_two_axes(z, x)?,
                    None => frame_from_axis(z)?,
                };
                p_from_rotation_matrix(&frame)
            }
        }
    }
}

/// A moving body: name, inertia data and a (rough) initial pose.
///
/// Mass and inertia are optional for kinematics (not used); a dynamic analysis requires them.
/// The inertia tensor is about the centre of mass in body components; the body reference point
/// is the centre of mass.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name (not `"ground"`).
    pub name: String,
    /// Mass in kg (> 0 when given).
    pub mass: Option<f64>,
    /// Inertia tensor about the centre of mass, body frame (symmetric positive definite).
    pub inertia: Option<Matrix3<f64>>,
    /// Initial position of the body reference point, global.
    pub position: Vector3<f64>,
    /// Initial orientation.
    pub orientation: Orientation,
}

impl Body {
    /// A body at the origin with identity orientation and no inertia data.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            mass: None,
            inertia: None,
            position: Vector3::zeros(),
            orientation: Orientation::Identity,
        }
    }

    /// Sets the mass (kg).
    pub fn mass(mut self, mass: f64) -> Self {
        self.mass = Some(mass);
        self
    }

    /// Sets the inertia tensor about the centre of mass (body frame).
    pub fn inertia(mut self, inertia: Matrix3<f64>) -> Self {
        self.inertia = Some(inertia);
        self
    }

    /// Sets a diagonal inertia tensor diag(ixx, iyy, izz).
    pub fn inertia_diagonal(self, ixx: f64, iyy: f64, izz: f64) -> Self {
        self.inertia(Matrix3::from_diagonal(&Vector3::new(ixx, iyy, izz)))
    }

    /// Sets the initial position (global).
    pub fn position(mut self, position: Vector3<f64>) -> Self {
        self.position = position;
        self
    }

    /// Sets the initial orientation.
    pub fn orientation(mut self, orientation: Orientation) -> Self {
        self.orientation = orientation;
        self
    }
}

/// A joint between a named point of body i and a named point of body j.
///
/// Axes are names of vectors on the respective bodies:
///
/// | kind | `axis_i`, `axis_j` (marker z) | `x_axis_i`, `x_axis_j` |
/// |---|---|---|
/// | spherical | unused | unused (optional: frame of the joint angles) |
/// | universal | required: the two arms of the cross (perpendicular) | optional |
/// | revolute, cylindrical, prismatic, fixed | required: the common axis on each body | optional: zero of the angle |
/// | planar | required: the plane normal on each body | optional |
/// | spherical-spherical | unused | unused; `length` optional (default: the initial distance) |
///
/// Without an x axis the marker's x is a fixed perpendicular to z
/// ([`cardan_eulerparam::frame_from_axis`]). A rotation or translation driver on the joint and the
/// joint angle output use the marker x axes, so give them when the angle matters.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// Unique name among joints and drivers.
    pub name: String,
    /// The joint kind.
    pub kind: JointKind,
    /// Body i.
    pub body_i: String,
    /// Point on body i.
    pub point_i: String,
    /// Body j.
    pub body_j: String,
    /// Point on body j.
    pub point_j: String,
    /// Vector on body i: the joint axis (marker z_i).
    pub axis_i: Option<String>,
    /// Vector on body j: the joint axis (marker z_j).
    pub axis_j: Option<String>,
    /// Vector on body i: marker x_i (reference for angles).
    pub x_axis_i: Option<String>,
    /// Vector on body j: marker x_j.
    pub x_axis_j: Option<String>,
    /// Length ℓ of a kind that takes one (spherical_spherical, rev_cyl, cyl_sph, rev_rev;
    /// default: its value at the initial poses).
    pub length: Option<f64>,
    /// Offset h of the plane along z_i of a kind that takes one (point_in_plane, line_in_plane,
    /// planar, rev_rev; default 0).
    pub offset: Option<f64>,
    /// Angle α of an angle or cone joint, rad (default: its value at the initial poses; a cone
    /// refuses α within 0.001 rad of 0 or π).
    pub angle: Option<f64>,
}

impl JointSpec {
    /// A joint `name` of `kind` between `(body_i, point_i)` and `(body_j, point_j)`.
    pub fn new(
        name: impl Into<String>,
        kind: JointKind,
        (body_i, point_i): (&str, &str),
        (body_j, point_j): (&str, &str),
    ) -> Self {
        Self {
            name: name.into(),
            kind,
            body_i: body_i.into(),
            point_i: point_i.into(),
            body_j: body_j.into(),
            point_j: point_j.into(),
            axis_i: None,
            axis_j: None,
            x_axis_i: None,
            x_axis_j: None,
            length: None,
            offset: None,
            angle: None,
        }
    }

    /// Sets the joint axes (vector names on body i and body j).
    pub fn axes(mut self, axis_i: &str, axis_j: &str) -> Self {
        self.axis_i = Some(axis_i.into());
        self.axis_j = Some(axis_j.into());
        self
    }

    /// Sets the joint axis on body i only (kinds that use marker i's frame alone, e.g.
    /// point_in_plane).
    pub fn axis_i(mut self, axis_i: &str) -> Self {
        self.axis_i = Some(axis_i.into());
        self
    }

    /// Sets the marker x axes (vector names on body i and body j).
    pub fn x_axes(mut self, x_axis_i: &str, x_axis_j: &str) -> Self {
        self.x_axis_i = Some(x_axis_i.into());
        self.x_axis_j = Some(x_axis_j.into());
        self
    }

    /// Sets the marker x axis on body i only.
    pub fn x_axis_i(mut self, x_axis_i: &str) -> Self {
        self.x_axis_i = Some(x_axis_i.into());
        self
    }

    /// Sets the length ℓ of a kind that takes one.
    pub fn length(mut self, length: f64) -> Self {
        self.length = Some(length);
        self
    }

    /// Sets the offset h of a kind that takes one.
    pub fn offset(mut self, offset: f64) -> Self {
        self.offset = Some(offset);
        self
    }

    /// Sets the angle α (rad) of an angle joint.
    pub fn angle(mut self, angle: f64) -> Self {
        self.angle = Some(angle);
        self
    }
}

/// A global coordinate direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// "x", "y" or "z".
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// What a driver prescribes.
#[derive(Debug, Clone, PartialEq)]
pub enum DriverTarget {
    /// The angle of a named revolute or cylindrical joint (its markers: angle of x_j from x_i
    /// about z_i), in rad.
    JointRotation {
        /// Name of the joint.
        joint: String,
    },
    /// The slide of a named prismatic or cylindrical joint (z_iᵀ (P_j − P_i)), in m.
    JointTranslation {
        /// Name of the joint.
        joint: String,
    },
    /// The distance between two named points, in m.
    Distance {
        /// Body of the first point.
        body_i: String,
        /// First point.
        point_i: String,
        /// Body of the second point.
        body_j: String,
        /// Second point.
        point_j: String,
    },
    /// One global coordinate of a named point of a moving body, in m.
    Coordinate {
        /// The body (not ground).
        body: String,
        /// The point.
        point: String,
        /// Which coordinate.
        axis: Axis,
    },
    /// The full pose of a marker frame on body j relative to one on body i (general motion):
    /// six rows, named `<driver>.x`, `.y`, `.z`, `.angle_1`, `.angle_2`, `.angle_3`.
    Pose(Box<PoseTarget>),
}

/// The frames and laws of a pose (general motion) driver: marker frame j = marker frame i
/// translated by (f₁, f₂, f₃)(t) along its own axes and turned by R_{o1}(a₁) R_{o2}(a₂) R_{o3}(a₃).
#[derive(Debug, Clone, PartialEq)]
pub struct PoseTarget {
    /// Body i (may be ground).
    pub body_i: String,
    /// The origin of frame i: a point of body i.
    pub point_i: String,
    /// z of frame i (a vector of body i); default: the body frame.
    pub axis_i: Option<String>,
    /// x of frame i.
    pub x_axis_i: Option<String>,
    /// Body j.
    pub body_j: String,
    /// The origin of frame j: a point of body j.
    pub point_j: String,
    /// z of frame j (a vector of body j); default: the body frame.
    pub axis_j: Option<String>,
    /// x of frame j.
    pub x_axis_j: Option<String>,
    /// The rotation sequence.
    pub order: RotationOrder,
    /// f₁, f₂, f₃ (m) and a₁, a₂, a₃ (rad).
    pub functions: [TimeFunction; 6],
}

/// The name of row `k` (0–5) of pose driver `name`: `name.x`, ..., `name.angle_3`.
pub fn pose_row_name(name: &str, k: usize) -> String {
    format!("{name}.{}", POSE_ROWS[k])
}

/// A driver: a named time law f(t) for a [`DriverTarget`].
#[derive(Debug, Clone, PartialEq)]
pub struct DriverSpec {
    /// Unique name among joints and drivers.
    pub name: String,
    /// What is driven.
    pub target: DriverTarget,
    /// The prescribed value f(t).
    pub function: TimeFunction,
}

impl DriverSpec {
    /// The angle of joint `joint` follows `function` (rad).
    pub fn rotation(name: impl Into<String>, joint: &str, function: TimeFunction) -> Self {
        Self {
            name: name.into(),
            target: DriverTarget::JointRotation {
                joint: joint.into(),
            },
            function,
        }
    }

    /// The slide of joint `joint` follows `function` (m).
    pub fn translation(name: impl Into<String>, joint: &str, function: TimeFunction) -> Self {
        Self {
            name: name.into(),
            target: DriverTarget::JointTranslation {
                joint: joint.into(),
            },
            function,
        }
    }

    /// The distance between `(body_i, point_i)` and `(body_j, point_j)` follows `function` (m).
    pub fn distance(
        name: impl Into<String>,
        (body_i, point_i): (&str, &str),
        (body_j, point_j): (&str, &str),
        function: TimeFunction,
    ) -> Self {
        Self {
            name: name.into(),
            target: DriverTarget::Distance {
                body_i: body_i.into(),
                point_i: point_i.into(),
                body_j: body_j.into(),
                point_j: point_j.into(),
            },
            function,
        }
    }

    /// The pose of a frame on body j relative to one on body i follows `target`'s six laws.
    pub fn pose(name: impl Into<String>, target: PoseTarget) -> Self {
        Self {
            name: name.into(),
            target: DriverTarget::Pose(Box::new(target)),
            // Unused: the six laws are in the target.
            function: TimeFunction::Constant(0.0),
        }
    }

    /// Global coordinate `axis` of `(body, point)` follows `function` (m).
    pub fn coordinate(
        name: impl Into<String>,
        (body, point): (&str, &str),
        axis: Axis,
        function: TimeFunction,
    ) -> Self {
        Self {
            name: name.into(),
            target: DriverTarget::Coordinate {
                body: body.into(),
                point: point.into(),
                axis,
            },
            function,
        }
    }
}

/// A force element, for dynamic analysis (kinematic analyses ignore forces). The builder
/// validates it (names, finite numbers, non-negative coefficients) and the model stores it
/// resolved ([`crate::model::ForceInfo`]); evaluating it is the dynamics layer's job.
#[derive(Debug, Clone, PartialEq)]
pub enum ForceSpec {
    /// Uniform gravity acting at the centre of mass of every moving body with a mass.
    Gravity {
        /// Acceleration of gravity, global (m/s²), e.g. (0, 0, −9.81).
        g: Vector3<f64>,
    },
    /// A linear spring-damper between two points: tension f = k (ℓ − ℓ0) + c ℓ̇ along the line.
    SpringDamper {
        /// Unique name among joints, drivers and forces.
        name: String,
        /// Body of the first point.
        body_i: String,
        /// First point.
        point_i: String,
        /// Body of the second point.
        body_j: String,
        /// Second point.
        point_j: String,
        /// k ≥ 0 (N/m).
        stiffness: f64,
        /// c ≥ 0 (N s/m).
        damping: f64,
        /// ℓ0 ≥ 0 (m); default: the distance at the initial poses.
        free_length: Option<f64>,
    },
    /// A constant force (global components, N) at a named point of a moving body.
    PointForce {
        /// Unique name.
        name: String,
        /// The body.
        body: String,
        /// The point of application.
        point: String,
        /// The force, global.
        force: Vector3<f64>,
    },
    /// A constant torque (global components, N m) on a moving body.
    Torque {
        /// Unique name.
        name: String,
        /// The body.
        body: String,
        /// The torque, global.
        torque: Vector3<f64>,
    },
}

impl ForceSpec {
    /// The element name ("gravity" for gravity).
    pub fn name(&self) -> &str {
        match self {
            ForceSpec::Gravity { .. } => "gravity",
            ForceSpec::SpringDamper { name, .. }
            | ForceSpec::PointForce { name, .. }
            | ForceSpec::Torque { name, .. } => name,
        }
    }
}

/// What a coupler relates (see [`CouplerSpec`]).
#[derive(Debug, Clone, PartialEq)]
pub enum CouplerKind {
    /// Two gears on revolute (or cylindrical) joints `joint_i`, `joint_j`:
    /// θ_j = ratio · θ_i + c.
    Gear {
        /// The joint of gear i.
        joint_i: String,
        /// The joint of gear j.
        joint_j: String,
        /// The speed ratio dθ_j/dθ_i.
        ratio: GearRatio,
    },
    /// A rack on a prismatic (or cylindrical) joint and a pinion on a revolute (or cylindrical)
    /// joint: s = −radius · θ + c.
    RackPinion {
        /// The rack's joint (its slide s).
        slide_joint: String,
        /// The pinion's joint (its angle θ).
        angle_joint: String,
        /// The pinion's pitch radius (m, > 0).
        radius: f64,
    },
    /// A screw: s = (pitch / 2π) · θ + c, the slide and the angle of one cylindrical joint, or
    /// of a prismatic and a revolute joint on a common axis.
    Screw {
        /// The joint whose slide s advances.
        slide_joint: String,
        /// The joint whose angle θ turns (the same cylindrical joint, or a revolute joint).
        angle_joint: String,
        /// Advance per revolution (m; negative for a left-hand thread; not zero).
        pitch: f64,
    },
}

/// The ratio of a gear pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GearRatio {
    /// Pitch radii r_i, r_j (m): ratio = −r_i / r_j (external gears; give a negative radius for
    /// an internal gear, which turns the same way as its pinion).
    Radii(f64, f64),
    /// The signed speed ratio dθ_j/dθ_i itself (not zero).
    Ratio(f64),
}

impl GearRatio {
    /// dθ_j/dθ_i.
    pub fn value(self) -> f64 {
        match self {
            GearRatio::Radii(ri, rj) => -ri / rj,
            GearRatio::Ratio(k) => k,
        }
    }
}

/// A coupler: one equation between the coordinates of two joints (or the two coordinates of one
/// cylindrical joint), the constant c from the initial poses unless given.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplerSpec {
    /// Unique name among joints, couplers, drivers and forces.
    pub name: String,
    /// What is coupled.
    pub kind: CouplerKind,
    /// c (rad for a gear, m for the others); default: its value at the initial poses.
    pub constant: Option<f64>,
}

impl CouplerSpec {
    /// Gears on `joint_i` and `joint_j` with pitch radii `radius_i`, `radius_j`.
    pub fn gear(name: impl Into<String>, joint_i: &str, joint_j: &str, ratio: GearRatio) -> Self {
        Self {
            name: name.into(),
            kind: CouplerKind::Gear {
                joint_i: joint_i.into(),
                joint_j: joint_j.into(),
                ratio,
            },
            constant: None,
        }
    }

    /// A rack on `slide_joint` and a pinion of pitch radius `radius` on `angle_joint`.
    pub fn rack_pinion(
        name: impl Into<String>,
        slide_joint: &str,
        angle_joint: &str,
        radius: f64,
    ) -> Self {
        Self {
            name: name.into(),
            kind: CouplerKind::RackPinion {
                slide_joint: slide_joint.into(),
                angle_joint: angle_joint.into(),
                radius,
            },
            constant: None,
        }
    }

    /// A screw of `pitch` between the slide of `slide_joint` and the angle of `angle_joint`
    /// (the same cylindrical joint, or a prismatic and a revolute joint on a common axis).
    pub fn screw(
        name: impl Into<String>,
        slide_joint: &str,
        angle_joint: &str,
        pitch: f64,
    ) -> Self {
        Self {
            name: name.into(),
            kind: CouplerKind::Screw {
                slide_joint: slide_joint.into(),
                angle_joint: angle_joint.into(),
                pitch,
            },
            constant: None,
        }
    }

    /// Sets the constant c.
    pub fn constant(mut self, c: f64) -> Self {
        self.constant = Some(c);
        self
    }

    /// The kind's name: "gear", "rack_pinion" or "screw".
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            CouplerKind::Gear { .. } => "gear",
            CouplerKind::RackPinion { .. } => "rack_pinion",
            CouplerKind::Screw { .. } => "screw",
        }
    }
}

/// A compliant law for a limit instead of impacts: a contact force along the coordinate,
/// Hunt–Crossley's F = k δⁿ + c δⁿ δ̇ ≥ 0 with the penetration δ = −g > 0 past the limit (and
/// its rate δ̇), zero inside the range (K. H. Hunt, F. R. E. Crossley, J. Appl. Mech. 42 (1975)
/// 440–445). n = 1 with the damping multiplied by δ makes the force continuous at contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compliance {
    /// k, N/mⁿ or N m/radⁿ (> 0).
    pub stiffness: f64,
    /// c, N s/mⁿ⁺¹ or N m s/radⁿ⁺¹ (≥ 0).
    pub damping: f64,
    /// n (≥ 1; 1.5 for Hertzian contact).
    pub exponent: f64,
}

/// A limit on one coordinate of a joint: a lower bound, an upper bound or both (end stops),
/// with Newton's coefficient of restitution e for the impacts on them or a compliant law.
///
/// ```
/// use cardan_mechanism::LimitSpec;
/// let stop = LimitSpec::new("door_stop", "hinge").coordinate("angle").range(-1.5, 1.5).restitution(0.3);
/// assert_eq!(stop.upper, Some(1.5));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LimitSpec {
    /// Unique name among the model's elements.
    pub name: String,
    /// The joint whose coordinate is limited.
    pub joint: String,
    /// The coordinate's name among the joint kind's coordinates (`angle`, `slide`, `distance`,
    /// ...; [`cardan_constraints::KindInfo::coordinates`]). Default: the kind's only
    /// coordinate, else its rotation coordinate, else its translation coordinate.
    pub coordinate: Option<String>,
    /// lo (rad or m).
    pub lower: Option<f64>,
    /// hi (rad or m).
    pub upper: Option<f64>,
    /// Newton's coefficient of restitution e ∈ [0, 1] (default 0: the joint stays on the stop
    /// until it is pulled away).
    pub restitution: f64,
    /// A force law instead of impacts.
    pub compliance: Option<Compliance>,
}

impl LimitSpec {
    /// A limit `name` on joint `joint` (no bound yet: give one with [`LimitSpec::lower`],
    /// [`LimitSpec::upper`] or [`LimitSpec::range`]).
    pub fn new(name: impl Into<String>, joint: &str) -> Self {
        Self {
            name: name.into(),
            joint: joint.into(),
            coordinate: None,
            lower: None,
            upper: None,
            restitution: 0.0,
            compliance: None,
        }
    }

    /// The limited coordinate by name.
    pub fn coordinate(mut self, name: &str) -> Self {
        self.coordinate = Some(name.into());
        self
    }

    /// The lower bound lo.
    pub fn lower(mut self, lo: f64) -> Self {
        self.lower = Some(lo);
        self
    }

    /// The upper bound hi.
    pub fn upper(mut self, hi: f64) -> Self {
        self.upper = Some(hi);
        self
    }

    /// Both bounds, lo ≤ hi.
    pub fn range(self, lo: f64, hi: f64) -> Self {
        self.lower(lo).upper(hi)
    }

    /// Newton's coefficient of restitution e ∈ [0, 1].
    pub fn restitution(mut self, e: f64) -> Self {
        self.restitution = e;
        self
    }

    /// A compliant contact law instead of impacts.
    pub fn compliant(mut self, law: Compliance) -> Self {
        self.compliance = Some(law);
        self
    }
}

/// Coulomb friction in a joint (revolute, prismatic, cylindrical or spherical), from the joint's
/// reaction: a slide's friction force −μ N s(v) along the axis, with N the reaction force
/// across the axis plus the preload; a pin's friction torque −μ r N s(ω) about the axis (the
/// friction circle of radius μ r), with N the radial reaction; a ball joint's torque
/// −μ r |F| s(|ω|) against the relative rotation. s(v) = v / √(v² + v_s²) regularizes the
/// sign near zero velocity (the stiction model: below v_s the friction acts as a steep viscous
/// law, so a held joint creeps at about v_s tan α / μ).
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionSpec {
    /// Unique name among the model's elements.
    pub name: String,
    /// The joint.
    pub joint: String,
    /// μ ≥ 0.
    pub coefficient: f64,
    /// The pin (or ball, or journal) radius r > 0 of a rotating joint, m.
    pub radius: Option<f64>,
    /// A load N₀ ≥ 0 added to the reaction (N): a preload, or a constant friction μ N₀.
    pub preload: f64,
    /// v_s > 0 of the regularization (m/s or rad/s; default 1e-4).
    pub stiction_velocity: f64,
    /// F_c ≥ 0: a slide's friction force independent of the load (N): URDF's `<dynamics
    /// friction>`, MuJoCo's `frictionloss`.
    pub force: f64,
    /// T_c ≥ 0: a pin's or ball's friction torque independent of the load (N m).
    pub torque: f64,
}

impl FrictionSpec {
    /// Friction with coefficient μ in joint `joint`.
    pub fn new(name: impl Into<String>, joint: &str, coefficient: f64) -> Self {
        Self {
            name: name.into(),
            joint: joint.into(),
            coefficient,
            radius: None,
            preload: 0.0,
            stiction_velocity: 1e-4,
            force: 0.0,
            torque: 0.0,
        }
    }

    /// A constant friction force F_c of a slide, added to μ N.
    pub fn constant_force(mut self, f: f64) -> Self {
        self.force = f;
        self
    }

    /// A constant friction torque T_c of a pin or ball, added to μ r N.
    pub fn constant_torque(mut self, t: f64) -> Self {
        self.torque = t;
        self
    }

    /// The pin radius r of a rotating joint.
    pub fn radius(mut self, r: f64) -> Self {
        self.radius = Some(r);
        self
    }

    /// A preload N₀ added to the reaction.
    pub fn preload(mut self, n0: f64) -> Self {
        self.preload = n0;
        self
    }

    /// The regularization velocity v_s.
    pub fn stiction_velocity(mut self, v: f64) -> Self {
        self.stiction_velocity = v;
        self
    }
}

/// A named point or vector declared on a body, in declaration order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Feature {
    pub body: String,
    pub name: String,
    pub value: Vector3<f64>,
}

/// Collects the elements of a mechanism; [`build`](Self::build) validates them all.
///
/// Methods take `&mut self` and return `&mut Self`, so calls can be chained or issued one by one
/// (as a model-file reader does). Nothing is checked before `build`; `build` reports the first
/// problem, naming the element.
#[derive(Debug, Clone, Default)]
pub struct MechanismBuilder {
    pub(crate) bodies: Vec<Body>,
    pub(crate) points: Vec<Feature>,
    pub(crate) vectors: Vec<Feature>,
    pub(crate) joints: Vec<JointSpec>,
    pub(crate) drivers: Vec<DriverSpec>,
    pub(crate) couplers: Vec<CouplerSpec>,
    pub(crate) forces: Vec<ForceSpec>,
    pub(crate) limits: Vec<LimitSpec>,
    pub(crate) frictions: Vec<FrictionSpec>,
    pub(crate) curves: Vec<CurveSpec>,
    pub(crate) cams: Vec<CamSpec>,
    pub(crate) surfaces: Vec<SurfaceSpec>,
    pub(crate) paths: Vec<PathSpec>,
    pub(crate) shapes: Vec<ShapeSpec>,
    pub(crate) materials: Vec<MaterialSpec>,
}

impl MechanismBuilder {
    /// An empty mechanism (ground only).
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a moving body.
    pub fn body(&mut self, body: Body) -> &mut Self {
        self.bodies.push(body);
        self
    }

    /// Declares point `name` on `body` at body-frame position `local` (global for ground).
    pub fn point(&mut self, body: &str, name: &str, local: Vector3<f64>) -> &mut Self {
        self.points.push(Feature {
            body: body.into(),
            name: name.into(),
            value: local,
        });
        self
    }

    /// Declares vector `name` on `body` with body-frame components `local` (global for ground).
    /// Only its direction matters; it must not be zero.
    pub fn vector(&mut self, body: &str, name: &str, local: Vector3<f64>) -> &mut Self {
        self.vectors.push(Feature {
            body: body.into(),
            name: name.into(),
            value: local,
        });
        self
    }

    /// Adds a joint.
    pub fn joint(&mut self, joint: JointSpec) -> &mut Self {
        self.joints.push(joint);
        self
    }

    /// Adds a point-on-curve element (its curve parameter becomes an extra coordinate).
    pub fn curve(&mut self, curve: CurveSpec) -> &mut Self {
        self.curves.push(curve);
        self
    }

    /// Adds a cam pair (a follower's curve tangent to a cam's; both curve parameters become
    /// extra coordinates, after those of the point-on-curve elements).
    pub fn cam(&mut self, cam: CamSpec) -> &mut Self {
        self.cams.push(cam);
        self
    }

    /// Adds a point-on-surface element (its two surface parameters become extra coordinates,
    /// after those of the curves and cams).
    pub fn surface(&mut self, surface: SurfaceSpec) -> &mut Self {
        self.surfaces.push(surface);
        self
    }

    /// Adds a path driver (a point-on-curve element's parameter prescribed in time).
    pub fn path(&mut self, path: PathSpec) -> &mut Self {
        self.paths.push(path);
        self
    }

    /// Adds a coupler (gear, rack and pinion, screw).
    pub fn coupler(&mut self, coupler: CouplerSpec) -> &mut Self {
        self.couplers.push(coupler);
        self
    }

    /// Adds a driver.
    pub fn driver(&mut self, driver: DriverSpec) -> &mut Self {
        self.drivers.push(driver);
        self
    }

    /// Adds a limit on a joint coordinate (end stops; see [`LimitSpec`]).
    pub fn limit(&mut self, limit: LimitSpec) -> &mut Self {
        self.limits.push(limit);
        self
    }

    /// Adds Coulomb friction to a joint (dynamic analyses; see [`FrictionSpec`]).
    pub fn friction(&mut self, friction: FrictionSpec) -> &mut Self {
        self.frictions.push(friction);
        self
    }

    /// Adds a collision shape (dynamic analyses; see [`ShapeSpec`]).
    pub fn shape(&mut self, shape: ShapeSpec) -> &mut Self {
        self.shapes.push(shape);
        self
    }

    /// Adds a contact material (see [`MaterialSpec`]).
    pub fn material(&mut self, material: MaterialSpec) -> &mut Self {
        self.materials.push(material);
        self
    }

    /// Adds a force element (used by dynamic analyses only).
    pub fn force(&mut self, force: ForceSpec) -> &mut Self {
        self.forces.push(force);
        self
    }
}
