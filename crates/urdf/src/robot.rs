//! The URDF model as read: links, joints and their elements, each with its file line. Nothing
//! here is checked beyond the element's own values ([`mod@crate::tree`] checks the topology).

use crate::pose::Pose;
use nalgebra::{Matrix3, Vector3};

/// A `<robot>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    /// `name` attribute.
    pub name: String,
    /// `<link>` elements in file order.
    pub links: Vec<Link>,
    /// `<joint>` elements in file order (URDF joint order: the order of the joint tables).
    pub joints: Vec<Joint>,
}

/// A `<link>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    /// `name`.
    pub name: String,
    /// Line of the `<link>` tag.
    pub line: usize,
    /// `<inertial>`: absent for a massless link (a frame).
    pub inertial: Option<Inertial>,
    /// `<visual>` elements.
    pub visuals: Vec<Visual>,
    /// `<collision>` elements.
    pub collisions: Vec<Visual>,
}

/// A link's `<inertial>`: the centre of mass frame and the inertia tensor in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Inertial {
    /// `<origin>`: the centre of mass and the axes the inertia is expressed in, link frame.
    pub origin: Pose,
    /// `<mass value>` \[kg\], ≥ 0.
    pub mass: f64,
    /// `<inertia ixx ixy ixz iyy iyz izz>` about the centre of mass in the origin's axes
    /// \[kg m²\] (symmetric).
    pub inertia: Matrix3<f64>,
    /// Line of the `<inertial>` tag.
    pub line: usize,
}

/// A `<visual>` or `<collision>`: a geometry placed in the link frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Visual {
    /// `<origin>` in the link frame.
    pub origin: Pose,
    /// The geometry.
    pub geometry: Geometry,
    /// Line of the element.
    pub line: usize,
}

/// A `<geometry>`.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// `<box size>`: full edge lengths.
    Box(Vector3<f64>),
    /// `<cylinder radius length>` about the z axis, centred.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
    },
    /// `<sphere radius>`.
    Sphere(f64),
    /// `<capsule radius length>` (an extension many files use), about z.
    Capsule {
        /// Radius.
        radius: f64,
        /// Length of the cylinder part along z.
        length: f64,
    },
    /// `<mesh filename scale>`.
    Mesh {
        /// The file name as written (`package://…`, `file://…` or a relative path).
        filename: String,
        /// Scale per axis (default 1 1 1).
        scale: Vector3<f64>,
    },
}

/// URDF joint types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointType {
    /// Turns about the axis within limits.
    Revolute,
    /// Turns about the axis without limits.
    Continuous,
    /// Slides along the axis within limits.
    Prismatic,
    /// No motion: the child is part of the parent's rigid body.
    Fixed,
    /// Six degrees of freedom.
    Floating,
    /// Slides and turns in the plane normal to the axis.
    Planar,
}

impl JointType {
    /// The URDF table: type name → kind.
    pub const TABLE: [(&'static str, JointType); 6] = [
        ("revolute", JointType::Revolute),
        ("continuous", JointType::Continuous),
        ("prismatic", JointType::Prismatic),
        ("fixed", JointType::Fixed),
        ("floating", JointType::Floating),
        ("planar", JointType::Planar),
    ];

    /// The kind of a `type` attribute.
    pub fn parse(name: &str) -> Option<Self> {
        Self::TABLE
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, k)| *k)
    }

    /// The URDF name.
    pub fn name(self) -> &'static str {
        Self::TABLE
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(n, _)| n)
    }
}

/// A `<joint>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// `name`.
    pub name: String,
    /// Line of the `<joint>` tag.
    pub line: usize,
    /// `type`.
    pub kind: JointType,
    /// `<parent link>`.
    pub parent: String,
    /// `<child link>`.
    pub child: String,
    /// `<origin>`: the joint frame in the parent link's frame; at q = 0 it is the child link's
    /// frame.
    pub origin: Pose,
    /// `<axis xyz>` in the joint frame, unit length (default x).
    pub axis: Vector3<f64>,
    /// `<limit>`.
    pub limit: Option<Limit>,
    /// `<mimic>`.
    pub mimic: Option<Mimic>,
    /// `<dynamics>`.
    pub dynamics: Option<Dynamics>,
}

/// A `<dynamics>`: the joint's viscous damping and dry friction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dynamics {
    /// `damping` \[N m s/rad or N s/m\] (default 0): the torque or force −c q̇.
    pub damping: f64,
    /// `friction` \[N m or N\] (default 0): a dry friction's largest torque or force.
    pub friction: f64,
    /// Line of the `<dynamics>` tag.
    pub line: usize,
}

/// A `<limit>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// `lower` \[rad or m\] (default 0; −∞ for a bound below −10⁶, which files write for
    /// "none").
    pub lower: f64,
    /// `upper` (default 0; +∞ above 10⁶).
    pub upper: f64,
    /// `effort` \[N m or N\]: the largest joint effort.
    pub effort: Option<f64>,
    /// `velocity` \[rad/s or m/s\]: the largest joint rate.
    pub velocity: Option<f64>,
    /// Line of the `<limit>` tag.
    pub line: usize,
}

/// A `<mimic>`: q = multiplier · q_joint + offset.
#[derive(Debug, Clone, PartialEq)]
pub struct Mimic {
    /// The joint followed.
    pub joint: String,
    /// Multiplier (default 1).
    pub multiplier: f64,
    /// Offset (default 0).
    pub offset: f64,
    /// Line of the `<mimic>` tag.
    pub line: usize,
}
