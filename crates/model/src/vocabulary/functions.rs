//! `function = { kind = ..., ... }`: the time functions and their keys. A value key's quantity
//! is the one of what the function drives (an angle, a length, a force...): `Unbounded` here,
//! the loader converts it by the owner's quantity.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const VALUE: Value = Value::Number(Quantity::Unbounded);

/// The time function kinds.
pub const FUNCTIONS: Vocabulary = Vocabulary {
    what: "function kind",
    table: "function = { ... }",
    selector: "kind",
    common: &[Key::new(
        "kind",
        Value::Name,
        Default::Required,
        "the function kind",
    )],
    entries: &[
        Entry {
            name: "constant",
            aliases: &[],
            summary: "f = value",
            keys: &[Key::new("value", VALUE, Default::Required, "the value")],
        },
        Entry {
            name: "polynomial",
            aliases: &[],
            summary: "f = Σ c_k t^k",
            keys: &[Key::new(
                "coefficients",
                Value::Numbers,
                Default::Required,
                "c0, c1, … (at least one; c_k in the value's unit per s^k)",
            )],
        },
        Entry {
            name: "harmonic",
            aliases: &[],
            summary: "offset + amplitude · sin(frequency · t + phase)",
            keys: &[
                Key::new("amplitude", VALUE, Default::Required, "the amplitude"),
                Key::new(
                    "frequency",
                    Value::Number(Quantity::Frequency),
                    Default::Required,
                    "the angular frequency (rad/s)",
                ),
                Key::new(
                    "phase",
                    Value::Number(Quantity::Angle),
                    Default::Is("0"),
                    "the phase (rad)",
                ),
                Key::new("offset", VALUE, Default::Is("0"), "the offset"),
            ],
        },
        Entry {
            name: "ramp",
            aliases: &[],
            summary: "a C² quintic step from f0 (t ≤ t0) to f1 (t ≥ t1)",
            keys: &[
                Key::new(
                    "t0",
                    Value::Number(Quantity::Time),
                    Default::Required,
                    "start of the blend",
                ),
                Key::new(
                    "t1",
                    Value::Number(Quantity::Time),
                    Default::Required,
                    "end of the blend",
                ),
                Key::new("f0", VALUE, Default::Required, "the value before t0"),
                Key::new("f1", VALUE, Default::Required, "the value after t1"),
            ],
        },
        Entry {
            name: "spline",
            aliases: &[],
            summary: "the natural cubic spline through the knots; linear beyond them",
            keys: &[
                Key::new(
                    "times",
                    Value::Numbers,
                    Default::Required,
                    "knot times, increasing (s)",
                ),
                Key::new("values", Value::Numbers, Default::Required, "knot values"),
            ],
        },
        Entry {
            name: "expression",
            aliases: &[],
            summary: "a formula of t (docs: expressions)",
            keys: &[Key::new(
                "text",
                Value::Text,
                Default::Required,
                "the formula, e.g. \"2*pi*t + 0.3*sin(2*pi*t)\"",
            )],
        },
    ],
};
