//! Collision shapes and contact materials as the builder collects them ([`ShapeSpec`],
//! [`MaterialSpec`]); the equations of the contact law they feed are in
//! `cardan_dynamics::collision`.
//!
//! A shape is fixed in a body (or in the ground) by its **centre** s' (body frame, relative to
//! the body's reference point, which is its centre of mass) and its **axes** (a rotation A_s
//! from the shape frame to the body frame: the columns are the shape's x, y, z axes in body
//! components). In the shape frame:
//!
//! | geometry | extent |
//! |---|---|
//! | sphere | radius r about the centre |
//! | capsule | the points within r of the segment from −ℓ/2 to +ℓ/2 on z |
//! | cylinder | radius r about z, from −ℓ/2 to +ℓ/2 |
//! | box | edges a, b, c along x, y, z, centred |
//! | plane | the half-space z ≤ 0 (its outward normal is +z) |
//! | convex mesh | the convex hull of its points |
//! | triangle mesh | its triangles (a static shape: ground only) |

use nalgebra::{Matrix3, Vector3};

/// The geometry of a collision shape, in the shape frame (module docs). Lengths in m.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A ball of radius r.
    Sphere {
        /// r > 0.
        radius: f64,
    },
    /// A segment of length ℓ on z swept by a ball of radius r.
    Capsule {
        /// r > 0.
        radius: f64,
        /// ℓ > 0, between the centres of the end caps.
        length: f64,
    },
    /// A circular cylinder about z.
    Cylinder {
        /// r > 0.
        radius: f64,
        /// ℓ > 0.
        length: f64,
    },
    /// A rectangular box.
    Box {
        /// Edge lengths along x, y, z, all > 0.
        size: Vector3<f64>,
    },
    /// The half-space z ≤ 0 (outward normal +z).
    Plane,
    /// The convex hull of a point cloud.
    ConvexMesh {
        /// At least four points not in a plane.
        points: Vec<Vector3<f64>>,
    },
    /// A triangle mesh (ground only).
    TriangleMesh {
        /// The vertices.
        vertices: Vec<Vector3<f64>>,
        /// Vertex indices of each triangle, counter-clockwise seen from outside.
        triangles: Vec<[u32; 3]>,
    },
}

impl Geometry {
    /// The geometry's name in the model file.
    pub fn kind(&self) -> &'static str {
        match self {
            Geometry::Sphere { .. } => "sphere",
            Geometry::Capsule { .. } => "capsule",
            Geometry::Cylinder { .. } => "cylinder",
            Geometry::Box { .. } => "box",
            Geometry::Plane => "plane",
            Geometry::ConvexMesh { .. } => "convex_mesh",
            Geometry::TriangleMesh { .. } => "mesh",
        }
    }

    /// The thickness a penetration is measured against: a sphere's or capsule's radius, a
    /// cylinder's radius or half length, a box's smallest half edge, a hull's smallest half
    /// extent; ∞ for a plane or a triangle mesh (the other shape decides).
    pub fn thickness(&self) -> f64 {
        match self {
            Geometry::Sphere { radius } | Geometry::Capsule { radius, .. } => *radius,
            Geometry::Cylinder { radius, length } => radius.min(0.5 * length),
            Geometry::Box { size } => 0.5 * size.min(),
            Geometry::ConvexMesh { points } => {
                let Some(&first) = points.first() else {
                    return f64::INFINITY;
                };
                let (mut lo, mut hi) = (first, first);
                for p in points {
                    lo = lo.inf(p);
                    hi = hi.sup(p);
                }
                0.5 * (hi - lo).min()
            }
            Geometry::Plane | Geometry::TriangleMesh { .. } => f64::INFINITY,
        }
    }

    /// The radius of curvature a Hertz contact sees on this shape: r for a sphere or a
    /// capsule (its caps and, across, its side), ∞ for the flat or edged shapes.
    pub fn curvature_radius(&self) -> f64 {
        match self {
            Geometry::Sphere { radius } | Geometry::Capsule { radius, .. } => *radius,
            _ => f64::INFINITY,
        }
    }
}

/// A collision shape fixed in a body (see the module docs for the frames).
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeSpec {
    /// Name (unique among the shapes).
    pub name: String,
    /// The body (`"ground"` allowed).
    pub body: String,
    /// The geometry.
    pub geometry: Geometry,
    /// The centre s' in the body frame (m; global for ground).
    pub center: Vector3<f64>,
    /// The shape's axes in body components (columns x, y, z; a rotation).
    pub axes: Matrix3<f64>,
    /// The material's name.
    pub material: String,
    /// The collision groups the shape belongs to (bits; default 1).
    pub groups: u32,
    /// The groups it collides with (bits; default all). Two shapes touch when each one's
    /// `collides_with` meets the other's `groups`.
    pub collides_with: u32,
}

impl ShapeSpec {
    /// A shape of `material` at the origin of `body`'s frame with the body's axes.
    pub fn new(name: impl Into<String>, body: &str, geometry: Geometry, material: &str) -> Self {
        Self {
            name: name.into(),
            body: body.into(),
            geometry,
            center: Vector3::zeros(),
            axes: Matrix3::identity(),
            material: material.into(),
            groups: 1,
            collides_with: u32::MAX,
        }
    }

    /// The centre s' (body frame).
    pub fn center(mut self, s: Vector3<f64>) -> Self {
        self.center = s;
        self
    }

    /// The shape's z axis along `z` and its x axis along the part of `x` normal to it (body
    /// frame; checked when the model is built).
    pub fn axes(mut self, z: Vector3<f64>, x: Vector3<f64>) -> Self {
        let zn = z.normalize();
        let xn = (x - zn * zn.dot(&x)).normalize();
        self.axes = Matrix3::from_columns(&[xn, zn.cross(&xn), zn]);
        self
    }

    /// The collision groups (`groups`) and the groups it collides with (`collides_with`).
    pub fn filter(mut self, groups: u32, collides_with: u32) -> Self {
        self.groups = groups;
        self.collides_with = collides_with;
        self
    }
}

/// How a material's contact stiffness is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stiffness {
    /// K (N/m^n) of F = K δⁿ directly, with its exponent n ≥ 1. Two such materials in
    /// contact add their compliances, as Hertz's 1/E do: K = K₁K₂/(K₁ + K₂) (two equal
    /// materials of K give K/2).
    Direct {
        /// K > 0.
        k: f64,
        /// n ≥ 1 (1.5 for a Hertz contact, 1 for a linear spring).
        exponent: f64,
    },
    /// Young's modulus E (Pa) and Poisson's ratio ν: Hertz's K = 4/3 E* √R* with
    /// 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ and 1/R* = 1/R₁ + 1/R₂ (the shapes' radii of
    /// curvature, [`Geometry::curvature_radius`]); n = 3/2 (Johnson 1985, §4.2).
    Elastic {
        /// E > 0.
        youngs_modulus: f64,
        /// ν ∈ [0, 0.5).
        poisson_ratio: f64,
    },
}

/// A contact material. Two materials in contact combine: the stiffness as in [`Stiffness`],
/// the restitution and the friction coefficients as the smaller of the two.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialSpec {
    /// Name (unique among the materials).
    pub name: String,
    /// The stiffness.
    pub stiffness: Stiffness,
    /// Newton's coefficient of restitution e ∈ (0, 1] of a normal impact.
    pub restitution: f64,
    /// μ_s ≥ μ_d: the friction coefficient at rest.
    pub friction_static: f64,
    /// μ_d ≥ 0: the friction coefficient in sliding.
    pub friction_dynamic: f64,
    /// v_s > 0 (m/s): the slip speed below which friction is a steep viscous law
    /// (regularized Coulomb friction).
    pub slip_velocity: f64,
    /// A pair law: the contact between shapes of these two materials (either order; the same
    /// name twice for a material against itself) takes this law instead of the two materials'
    /// combination. No shape may name it. Its stiffness must be direct (the pair's measured K).
    pub between: Option<[String; 2]>,
}

impl MaterialSpec {
    /// A frictionless material of stiffness `stiffness` and restitution e.
    pub fn new(name: impl Into<String>, stiffness: Stiffness, restitution: f64) -> Self {
        Self {
            name: name.into(),
            stiffness,
            restitution,
            friction_static: 0.0,
            friction_dynamic: 0.0,
            slip_velocity: 1e-3,
            between: None,
        }
    }

    /// Makes it the law of the contacts between materials `a` and `b` ([`Self::between`]).
    pub fn between(mut self, a: impl Into<String>, b: impl Into<String>) -> Self {
        self.between = Some([a.into(), b.into()]);
        self
    }

    /// Coulomb friction μ (static and dynamic alike).
    pub fn friction(mut self, mu: f64) -> Self {
        self.friction_static = mu;
        self.friction_dynamic = mu;
        self
    }

    /// Static and dynamic friction coefficients μ_s ≥ μ_d.
    pub fn friction_static_dynamic(mut self, mu_s: f64, mu_d: f64) -> Self {
        self.friction_static = mu_s;
        self.friction_dynamic = mu_d;
        self
    }

    /// The slip speed v_s of the regularization.
    pub fn slip_velocity(mut self, vs: f64) -> Self {
        self.slip_velocity = vs;
        self
    }
}
