//! `[[force]] type = ...`: the force elements and the keys each takes. Signs and formulas:
//! `cardan_dynamics::forces`.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const FRAME: Key = Key::new(
    "frame",
    Value::Choice(&["global", "body", "local"]),
    Default::Is("\"global\""),
    "\"global\": the vector keeps its global direction; \"body\" (or \"local\"): it is given in body components and turns with the body",
);

/// The force element types.
pub const FORCES: Vocabulary = Vocabulary {
    what: "force type",
    table: "[[force]]",
    selector: "type",
    common: &[
        Key::new("name", Value::Name, Default::Required, "unique among joints, couplers, drivers and forces"),
        Key::new("type", Value::Name, Default::Required, "the force type"),
    ],
    entries: &[
        Entry {
            name: "point_force",
            aliases: &[],
            summary: "a force at a point of a moving body",
            keys: &[
                Key::new("body", Value::Name, Default::Required, "the moving body"),
                Key::new("point", Value::Name, Default::Required, "the point of application"),
                Key::new("value", Value::Vector(Quantity::Force), Default::Is("components"), "a constant force (N)"),
                Key::new("components", Value::Functions(Quantity::Force), Default::Is("value"), "three time functions x, y, z (N), instead of value"),
                FRAME,
            ],
        },
        Entry {
            name: "torque",
            aliases: &[],
            summary: "a pure torque on a moving body",
            keys: &[
                Key::new("body", Value::Name, Default::Required, "the moving body"),
                Key::new("value", Value::Vector(Quantity::Torque), Default::Is("components"), "a constant torque (N m)"),
                Key::new("components", Value::Functions(Quantity::Torque), Default::Is("value"), "three time functions x, y, z (N m), instead of value"),
                FRAME,
            ],
        },
        Entry {
            name: "spring_damper",
            aliases: &[],
            summary: "tension f = k (ℓ − ℓ0) + c ℓ̇ + f_a(t) along the line between two points (positive pulls them together); potential ½ k (ℓ − ℓ0)²",
            keys: &[
                Key::new("body_i", Value::Name, Default::Required, "body i"),
                Key::new("point_i", Value::Name, Default::Required, "the point on body i"),
                Key::new("body_j", Value::Name, Default::Required, "body j"),
                Key::new("point_j", Value::Name, Default::Required, "the point on body j"),
                Key::new("stiffness", Value::Number(Quantity::Stiffness), Default::Is("0"), "k ≥ 0 (N/m)"),
                Key::new("damping", Value::Number(Quantity::Damping), Default::Is("0"), "c ≥ 0 (N s/m)"),
                Key::new("free_length", Value::Number(Quantity::Length), Default::Is("the initial distance"), "ℓ0 ≥ 0 (m)"),
                Key::new("actuator", Value::Function(Quantity::Force), Default::Is("none"), "f_a(t), a tension added to the spring's (N)"),
            ],
        },
        Entry {
            name: "rotational_spring_damper",
            aliases: &[],
            summary: "torque −(k (θ − θ0) + c θ̇) about a revolute or cylindrical joint's axis on body j, the opposite on body i (θ continued over turns)",
            keys: &[
                Key::new("joint", Value::Name, Default::Required, "the revolute or cylindrical joint"),
                Key::new("stiffness", Value::Number(Quantity::RotationalStiffness), Default::Is("0"), "k ≥ 0 (N m/rad)"),
                Key::new("damping", Value::Number(Quantity::RotationalDamping), Default::Is("0"), "c ≥ 0 (N m s/rad)"),
                Key::new("rest_angle", Value::Number(Quantity::Angle), Default::Is("0"), "θ0 (rad)"),
            ],
        },
        Entry {
            name: "translational_spring_damper",
            aliases: &[],
            summary: "force −(k (s − s0) + c ṡ) along a prismatic or cylindrical joint's axis, on body j at its marker, the opposite on body i (s the joint's slide)",
            keys: &[
                Key::new("joint", Value::Name, Default::Required, "the prismatic or cylindrical joint"),
                Key::new("stiffness", Value::Number(Quantity::Stiffness), Default::Is("0"), "k ≥ 0 (N/m)"),
                Key::new("damping", Value::Number(Quantity::Damping), Default::Is("0"), "c ≥ 0 (N s/m)"),
                Key::new("rest_position", Value::Number(Quantity::Length), Default::Is("0"), "s0 (m)"),
            ],
        },
    ],
};
