//! `[[limit]] law = ...` and `[[friction]] law = ...`: the end stops on joint coordinates and
//! the joint friction, with the keys each law takes (`cardan_mechanism::LimitSpec`,
//! `cardan_mechanism::FrictionSpec`).

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

/// The limit laws: impacts with restitution, or a compliant contact force.
pub const LIMITS: Vocabulary = Vocabulary {
    what: "limit law",
    table: "[[limit]]",
    selector: "law",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, couplers, drivers, forces, limits and frictions",
        ),
        Key::new(
            "law",
            Value::Name,
            Default::Is("\"impact\""),
            "how the stop acts",
        ),
        Key::new(
            "joint",
            Value::Name,
            Default::Required,
            "the joint whose coordinate is limited",
        ),
        Key::new(
            "coordinate",
            Value::Name,
            Default::Is("the kind's only coordinate, else its angle, else its slide"),
            "the limited coordinate (`angle`, `slide`, `distance`...: the joint kind's \
             coordinates, as `cardan check` lists them)",
        ),
        Key::new(
            "lower",
            Value::Number(Quantity::Unbounded),
            Default::Is("no lower stop"),
            "lo, in the coordinate's unit (rad or m); give lower, upper or both",
        ),
        Key::new(
            "upper",
            Value::Number(Quantity::Unbounded),
            Default::Is("no upper stop"),
            "hi, in the coordinate's unit (rad or m), ≥ lower",
        ),
    ],
    entries: &[
        Entry {
            name: "impact",
            aliases: &[],
            summary: "a rigid stop: impacts with Newton's restitution, held closed at e = 0 \
                      until pulled away",
            keys: &[Key::new(
                "restitution",
                Value::Number(Quantity::Ratio),
                Default::Is("0"),
                "Newton's coefficient of restitution e ∈ [0, 1] (rebound rate = −e × impact rate)",
            )],
        },
        Entry {
            name: "compliant",
            aliases: &[],
            summary: "Hunt–Crossley's force F = k δⁿ + c δⁿ δ̇ ≥ 0 along the coordinate past \
                      the bound (penetration δ)",
            keys: &[
                Key::new(
                    "stiffness",
                    Value::Number(Quantity::Unbounded),
                    Default::Required,
                    "k > 0 (N/mⁿ for a length, N m/radⁿ for an angle)",
                ),
                Key::new(
                    "damping",
                    Value::Number(Quantity::Unbounded),
                    Default::Is("0"),
                    "c ≥ 0 (N s/mⁿ⁺¹ for a length, N m s/radⁿ⁺¹ for an angle)",
                ),
                Key::new(
                    "exponent",
                    Value::Number(Quantity::Ratio),
                    Default::Is("1"),
                    "n ≥ 1 (1.5: Hertzian contact)",
                ),
            ],
        },
    ],
};

/// The joint friction laws.
pub const FRICTIONS: Vocabulary = Vocabulary {
    what: "friction law",
    table: "[[friction]]",
    selector: "law",
    common: &[
        Key::new(
            "name",
            Value::Name,
            Default::Required,
            "unique among joints, couplers, drivers, forces, limits and frictions",
        ),
        Key::new(
            "law",
            Value::Name,
            Default::Is("\"coulomb\""),
            "the friction law",
        ),
        Key::new(
            "joint",
            Value::Name,
            Default::Required,
            "the joint (revolute, prismatic, cylindrical or spherical)",
        ),
    ],
    entries: &[
        Entry {
            name: "coulomb",
            aliases: &[],
            summary: "Coulomb friction from the joint's reaction N: a slide's force μ N, a pin's \
                  torque μ r N (the friction circle), a ball's μ r ‖F‖, against the motion, \
                  with the sign regularized below the stiction velocity",
            keys: &[
                Key::new(
                    "coefficient",
                    Value::Number(Quantity::Ratio),
                    Default::Required,
                    "μ ≥ 0",
                ),
                Key::new(
                    "radius",
                    Value::Number(Quantity::Length),
                    Default::Is("required for a rotating joint"),
                    "the pin, journal or ball radius r (m, > 0)",
                ),
                Key::new(
                    "preload",
                    Value::Number(Quantity::Force),
                    Default::Is("0"),
                    "N₀ ≥ 0 added to the reaction (N): a preload, or a constant friction μ N₀",
                ),
                STICTION_VELOCITY,
            ],
        },
        Entry {
            name: "constant",
            aliases: &[],
            summary: "a friction independent of the load: a slide's force F_c, a pin's or ball's \
                  torque T_c, against the motion, with the sign regularized below the stiction \
                  velocity (URDF's <dynamics friction>, MuJoCo's frictionloss)",
            keys: &[
                Key::new(
                    "force",
                    Value::Number(Quantity::Force),
                    Default::Is("0"),
                    "F_c ≥ 0 of a slide (prismatic, cylindrical), N",
                ),
                Key::new(
                    "torque",
                    Value::Number(Quantity::Torque),
                    Default::Is("0"),
                    "T_c ≥ 0 of a pin or ball (revolute, cylindrical, spherical), N m",
                ),
                STICTION_VELOCITY,
            ],
        },
    ],
};

const STICTION_VELOCITY: Key = Key::new(
    "stiction_velocity",
    Value::Number(Quantity::Unbounded),
    Default::Is("1e-4"),
    "v_s > 0 of s(v) = v/√(v² + v_s²) (m/s for a slide, rad/s for a rotation): below it the \
     friction acts as a steep viscous law",
);
