//! `[[coupler]] type = ...`: the couplers and the keys each takes.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const SLIDE_JOINT: Key = Key::new(
    "slide_joint",
    Value::Name,
    Default::Required,
    "the joint whose slide moves (prismatic or cylindrical)",
);
const ANGLE_JOINT: Key = Key::new(
    "angle_joint",
    Value::Name,
    Default::Required,
    "the joint whose angle turns (revolute or cylindrical)",
);
const CONSTANT_ANGLE: Key = Key::new(
    "constant",
    Value::Number(Quantity::Angle),
    Default::Is("its value at the initial poses"),
    "c (rad); needs the joints' x axes",
);
const CONSTANT_LENGTH: Key = Key::new(
    "constant",
    Value::Number(Quantity::Length),
    Default::Is("its value at the initial poses"),
    "c (m); needs the joints' x axes",
);

/// The coupler types.
pub const COUPLERS: Vocabulary = Vocabulary {
    what: "coupler type",
    table: "[[coupler]]",
    selector: "type",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, couplers, drivers and forces",
        ),
        Key::new("type", Value::Name, Default::Required, "the coupler type"),
    ],
    entries: &[
        Entry {
            name: "gear",
            aliases: &[],
            summary: "θ_j = −(r_i/r_j) θ_i + c, or θ_j = ratio · θ_i + c",
            keys: &[
                Key::new(
                    "joint_i",
                    Value::Name,
                    Default::Required,
                    "the joint of gear i (revolute or cylindrical)",
                ),
                Key::new(
                    "joint_j",
                    Value::Name,
                    Default::Required,
                    "the joint of gear j",
                ),
                Key::new(
                    "radius_i",
                    Value::Number(Quantity::Length),
                    Default::Is("ratio"),
                    "pitch radius of gear i (m; not zero; negative: an internal gear)",
                ),
                Key::new(
                    "radius_j",
                    Value::Number(Quantity::Length),
                    Default::Is("ratio"),
                    "pitch radius of gear j (m; not zero)",
                ),
                Key::new(
                    "ratio",
                    Value::Number(Quantity::Ratio),
                    Default::Is("the radii"),
                    "the signed speed ratio dθ_j/dθ_i, instead of the radii (not zero)",
                ),
                CONSTANT_ANGLE,
            ],
        },
        Entry {
            name: "rack_pinion",
            aliases: &[],
            summary: "s = −r θ + c",
            keys: &[
                SLIDE_JOINT,
                ANGLE_JOINT,
                Key::new(
                    "radius",
                    Value::Number(Quantity::Length),
                    Default::Required,
                    "the pinion's pitch radius (m, > 0)",
                ),
                CONSTANT_LENGTH,
            ],
        },
        Entry {
            name: "screw",
            aliases: &[],
            summary: "s = (pitch / 2π) θ + c",
            keys: &[
                SLIDE_JOINT.default_is("joint"),
                ANGLE_JOINT.default_is("joint"),
                Key::new(
                    "joint",
                    Value::Name,
                    Default::Is("slide_joint and angle_joint"),
                    "one cylindrical joint (slide and angle)",
                ),
                Key::new(
                    "pitch",
                    Value::Number(Quantity::Length),
                    Default::Required,
                    "advance per revolution (m; negative: a left-hand thread; not zero)",
                ),
                CONSTANT_LENGTH,
            ],
        },
    ],
};
