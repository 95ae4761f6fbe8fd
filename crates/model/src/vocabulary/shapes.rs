//! `[[shape]] type = ...` and `[[material]]`: the collision shapes on bodies and the ground and
//! the contact materials they are made of (`cardan_mechanism::ShapeSpec`,
//! `cardan_mechanism::MaterialSpec`; the contact law in `cardan_dynamics::collision`).

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const RADIUS: Key = Key::new(
    "radius",
    Value::Number(Quantity::Length),
    Default::Required,
    "r > 0 (m)",
);
const LENGTH: Key = Key::new(
    "length",
    Value::Number(Quantity::Length),
    Default::Required,
    "ℓ > 0 (m) along the shape's z axis (a capsule's: between the centres of its end caps)",
);
const FILE: Key = Key::new(
    "file",
    Value::Text,
    Default::Required,
    "an STL or OBJ file, the path relative to the model file",
);
const SCALE: Key = Key::new(
    "scale",
    Value::Number(Quantity::Ratio),
    Default::Is("1"),
    "from the file's coordinates to the model's length unit (0.001 for a file in mm in an SI \
     model)",
);

/// The collision shape kinds.
pub const SHAPES: Vocabulary = Vocabulary {
    what: "shape type",
    table: "[[shape]]",
    selector: "type",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among the shapes; contacts.csv names the shapes in contact",
        ),
        Key::new("type", Value::Name, Default::Required, "the shape kind"),
        Key::new(
            "body",
            Value::Name,
            Default::Required,
            "the body carrying the shape (ground allowed)",
        ),
        Key::new(
            "material",
            Value::Name,
            Default::Required,
            "the [[material]] the shape is made of",
        ),
        Key::new(
            "point",
            Value::Name,
            Default::Is("the body's reference point (its centre of mass)"),
            "a point of the body: the shape's centre (a plane's origin)",
        ),
        Key::new(
            "axis",
            Value::Name,
            Default::Is("the body's z axis"),
            "a vector of the body: the shape's z axis (a cylinder's or capsule's axis, a \
             plane's outward normal)",
        ),
        Key::new(
            "x_axis",
            Value::Name,
            Default::Is("a direction perpendicular to axis chosen by cardan"),
            "a vector of the body: the shape's x axis (its part perpendicular to axis)",
        ),
        Key::new(
            "groups",
            Value::Numbers,
            Default::Is("[1]"),
            "the collision groups (whole numbers 1 – 32) the shape belongs to",
        ),
        Key::new(
            "collides_with",
            Value::Numbers,
            Default::Is("all groups"),
            "the groups it touches: two shapes touch when each one's collides_with holds one \
             of the other's groups (and their bodies are not joined by a joint)",
        ),
    ],
    entries: &[
        Entry {
            name: "sphere",
            aliases: &["ball"],
            summary: "a ball of radius r about the point",
            keys: &[RADIUS],
        },
        Entry {
            name: "capsule",
            aliases: &[],
            summary: "the points within r of a segment of length ℓ along the axis, centred on \
                      the point",
            keys: &[RADIUS, LENGTH],
        },
        Entry {
            name: "cylinder",
            aliases: &[],
            summary: "a circular cylinder of radius r and length ℓ about the axis, centred on \
                      the point",
            keys: &[RADIUS, LENGTH],
        },
        Entry {
            name: "box",
            aliases: &["cuboid"],
            summary: "a rectangular box centred on the point, its edges along x_axis, the \
                      third axis and axis",
            keys: &[Key::new(
                "size",
                Value::Vector(Quantity::Length),
                Default::Required,
                "the edge lengths [a, b, c] (m) along the shape's x, y, z",
            )],
        },
        Entry {
            name: "plane",
            aliases: &["half_space"],
            summary: "the half-space behind the plane through the point normal to axis (the \
                      side axis points out of is free): a floor, a wall",
            keys: &[],
        },
        Entry {
            name: "convex_mesh",
            aliases: &["convex"],
            summary: "the convex hull of a mesh file's vertices or of the given points (a \
                      part's hull; split a concave part into convex shapes)",
            keys: &[
                FILE.default_is("required unless points are given"),
                SCALE,
                Key::new(
                    "points",
                    Value::Points(Quantity::Length),
                    Default::Is("required unless file is given"),
                    "the points (in the shape's frame, m) whose hull is the shape",
                ),
            ],
        },
        Entry {
            name: "mesh",
            aliases: &["trimesh"],
            summary: "a triangle mesh from a file, fixed in the ground (terrain, a bowl, a \
                      fixture): any shape, but not on a moving body",
            keys: &[FILE, SCALE],
        },
    ],
};

/// The contact laws of a material.
pub const MATERIALS: Vocabulary = Vocabulary {
    what: "contact law",
    table: "[[material]]",
    selector: "law",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among the materials; shapes name it",
        ),
        Key::new(
            "law",
            Value::Name,
            Default::Is("\"hunt_crossley\""),
            "the contact law",
        ),
        Key::new(
            "between",
            Value::Names,
            Default::Is("none: a material of shapes"),
            "two materials' names: this is the law of their contacts, used as given instead of \
             the two materials' combination (the same name twice: a material against itself); \
             no shape names it, and it takes a stiffness, not a Young's modulus",
        ),
    ],
    entries: &[Entry {
        name: "hunt_crossley",
        aliases: &[],
        summary: "F_n = K δⁿ (1 + a δ̇/v₀), the hysteresis a set so that a normal impact \
                  rebounds at e times its speed v₀ exactly, with regularized Coulomb friction; \
                  two materials in contact take the smaller e and μ and add their \
                  compliances",
        keys: &[
            Key::new(
                "stiffness",
                Value::Number(Quantity::Unbounded),
                Default::Is("required unless youngs_modulus is given"),
                "K > 0 of F = K δⁿ (N/mⁿ; N/mmⁿ in a mm model)",
            ),
            Key::new(
                "exponent",
                Value::Number(Quantity::Ratio),
                Default::Is("1.5 (Hertz)"),
                "n ∈ [1, 3] of F = K δⁿ (with stiffness)",
            ),
            Key::new(
                "youngs_modulus",
                Value::Number(Quantity::Unbounded),
                Default::Is("required unless stiffness is given"),
                "E > 0 (Pa; N/mm² in a mm model): Hertz's K = 4/3 E* √R* from the shapes' radii \
                 (a sphere's or capsule's; one side of a contact must be curved)",
            ),
            Key::new(
                "poisson_ratio",
                Value::Number(Quantity::Ratio),
                Default::Is("0.3 (with youngs_modulus)"),
                "ν ∈ [0, 0.5)",
            ),
            Key::new(
                "restitution",
                Value::Number(Quantity::Ratio),
                Default::Required,
                "Newton's e ∈ (0, 1] of a normal impact",
            ),
            Key::new(
                "friction",
                Value::Number(Quantity::Ratio),
                Default::Is("0 (frictionless)"),
                "μ_d ≥ 0, the sliding friction coefficient",
            ),
            Key::new(
                "friction_static",
                Value::Number(Quantity::Ratio),
                Default::Is("friction"),
                "μ_s ≥ μ_d, the coefficient at rest (falls to μ_d over a few slip_velocity)",
            ),
            Key::new(
                "slip_velocity",
                Value::Number(Quantity::Velocity),
                Default::Is("1e-3 m/s"),
                "v_s > 0: below it friction is a steep viscous law (a held contact creeps at \
                 about v_s times the ratio of its tangential load to μ N)",
            ),
        ],
    }],
};
