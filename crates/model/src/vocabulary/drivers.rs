//! `[[driver]] type = ...`: the drivers and the keys each takes.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const JOINT: Key = Key::new("joint", Value::Name, Default::Required, "the driven joint");
const FUNCTION_ANGLE: Key = Key::new(
    "function",
    Value::Function(Quantity::Angle),
    Default::Required,
    "the law θ(t) of the joint angle (rad)",
)
.elsewhere("a general_motion driver's laws are translation = [three functions] and rotation = [three functions]");
const FUNCTION_LENGTH: Key = Key::new(
    "function",
    Value::Function(Quantity::Length),
    Default::Required,
    "the law of the driven length (m)",
);
const BODY_I: Key = Key::new("body_i", Value::Name, Default::Required, "body i");
const POINT_I: Key = Key::new(
    "point_i",
    Value::Name,
    Default::Required,
    "the point on body i",
);
const BODY_J: Key = Key::new("body_j", Value::Name, Default::Required, "body j");
const POINT_J: Key = Key::new(
    "point_j",
    Value::Name,
    Default::Required,
    "the point on body j",
);
const GM_POINT_I: Key = Key::new(
    "point_i",
    Value::Name,
    Default::Required,
    "the origin of frame i on body i",
);
const GM_POINT_J: Key = Key::new(
    "point_j",
    Value::Name,
    Default::Required,
    "the origin of frame j on body j",
);
const NAMED_FRAME: [Key; 4] = [
    Key::new(
        "axis_i",
        Value::Name,
        Default::Is("the body frame's z"),
        "z of frame i (a vector of body i)",
    ),
    Key::new(
        "x_axis_i",
        Value::Name,
        Default::Is("the body frame's x"),
        "x of frame i",
    ),
    Key::new(
        "axis_j",
        Value::Name,
        Default::Is("the body frame's z"),
        "z of frame j",
    ),
    Key::new(
        "x_axis_j",
        Value::Name,
        Default::Is("the body frame's x"),
        "x of frame j",
    ),
];

/// The driver types.
pub const DRIVERS: Vocabulary = Vocabulary {
    what: "driver type",
    table: "[[driver]]",
    selector: "type",
    common: &[
        Key::new("name", Value::Name, Default::Required, "unique among joints, couplers, drivers and forces"),
        Key::new("type", Value::Name, Default::Required, "the driver type"),
    ],
    entries: &[
        Entry {
            name: "rotation",
            aliases: &[],
            summary: "the angle of a revolute or cylindrical joint follows θ(t) (any number of turns)",
            keys: &[JOINT, FUNCTION_ANGLE],
        },
        Entry {
            name: "translation",
            aliases: &[],
            summary: "the slide of a prismatic or cylindrical joint follows s(t)",
            keys: &[JOINT, FUNCTION_LENGTH],
        },
        Entry {
            name: "distance",
            aliases: &[],
            summary: "the distance between two body points follows ℓ(t) > 0",
            keys: &[BODY_I, POINT_I, BODY_J, POINT_J, FUNCTION_LENGTH],
        },
        Entry {
            name: "coordinate",
            aliases: &[],
            summary: "one global coordinate of a body point follows x(t)",
            keys: &[
                Key::new("body", Value::Name, Default::Required, "the moving body"),
                Key::new("point", Value::Name, Default::Required, "its point"),
                Key::new("coordinate", Value::Choice(&["x", "y", "z"]), Default::Required, "the global coordinate"),
                FUNCTION_LENGTH,
            ],
        },
        Entry {
            name: "path",
            aliases: &[],
            summary: "the parameter u of a [[curve]] follows u(t): its point moves along the curve (arc length for a line, a circle and a helix: u = v t moves it at speed v)",
            keys: &[
                Key::new("curve", Value::Name, Default::Required, "the driven [[curve]]"),
                Key::new(
                    "function",
                    Value::Function(Quantity::Length),
                    Default::Required,
                    "the law u(t) of the curve parameter (m)",
                ),
                Key::new(
                    "arc_length",
                    Value::Flag,
                    Default::Is("false"),
                    "the function is the arc length travelled S(u(t)) (m) rather than u: a spline's u is its chord length, so f = v t moves the point at speed v only with this set (lines, circles and helices: the same)",
                ),
            ],
        },
        Entry {
            name: "general_motion",
            aliases: &[],
            summary: "the full pose of frame j relative to frame i: three translations and three angles of a rotation sequence",
            keys: &[
                BODY_I,
                GM_POINT_I,
                BODY_J,
                GM_POINT_J,
                NAMED_FRAME[0],
                NAMED_FRAME[1],
                NAMED_FRAME[2],
                NAMED_FRAME[3],
                Key::new("order", Value::Name, Default::Is("\"xyz\""), "the rotation sequence (the 6 Bryant and 6 Euler sequences, e.g. \"zxz\")"),
                Key::new("translation", Value::Functions(Quantity::Length), Default::Required, "three functions: the translations along x_i, y_i, z_i (m)"),
                Key::new("rotation", Value::Functions(Quantity::Angle), Default::Required, "three functions: the angles of the sequence (rad)"),
            ],
        },
    ],
};
