//! `[analysis.outputs]`: the output groups a run writes, and which analysis kinds take each.

use super::{Default, Entry, Key, Value, Vocabulary};

const POINTS: Key = Key::new(
    "points",
    Value::Names,
    Default::Is("every named point of a moving body when none of points, joints, bodies is given; else none"),
    "\"body.point\": positions, velocities and accelerations (points.csv, point_velocities.csv, point_accelerations.csv)",
);
const JOINTS: Key = Key::new(
    "joints",
    Value::Names,
    Default::Is("every joint when none of points, joints, bodies is given; else none"),
    "joint coordinates and their rates (joints.csv, joint_velocities.csv, joint_accelerations.csv); a [[curve]]'s, a [[surface]]'s or a [[cam]]'s name adds its curve or surface parameters, a cam's also its contact point and pressure angle (cams.csv)",
);
const BODIES: Key = Key::new(
    "bodies",
    Value::Names,
    Default::Is("every moving body when none of points, joints, bodies is given; else none"),
    "positions and Euler parameters (bodies.csv), velocities and accelerations",
);
const REACTIONS: Key = Key::new(
    "reactions",
    Value::Names,
    Default::Is("every joint and coupler"),
    "joints and couplers whose reactions are written (reactions.csv, reactions_local.csv)",
)
.elsewhere("a kinematic run has no forces");
const ENERGY: Key = Key::new(
    "energy",
    Value::Flag,
    Default::Is("true"),
    "write energy.csv (energies, the power and work of drivers and non-conservative forces, the balance)",
)
.elsewhere("a kinematic run has no forces, a static one no motion to conserve energy along");

const JOINT_SPACE: Key = Key::new(
    "joint_space",
    Value::Flag,
    Default::Is("false"),
    "write mass_matrix.csv and bias_forces.csv: the mass matrix M(θ) and the bias forces h(θ, θ̇) in the coordinates the drivers prescribe (efforts = M θ̈ + h)",
)
.elsewhere("the joint space is an inverse dynamics run's: its coordinates are the drivers'");
const JACOBIANS: Key = Key::new(
    "jacobians",
    Value::Names,
    Default::Is("none"),
    "\"body.point\": the point's velocity and its body's angular velocity per unit rate of each driven coordinate, global axes (jacobians.csv)",
)
.elsewhere("the joint space is an inverse dynamics run's: its coordinates are the drivers'");

const MOTION: &[Key] = &[POINTS, JOINTS, BODIES, REACTIONS, ENERGY];
const INVERSE: &[Key] = &[
    POINTS,
    JOINTS,
    BODIES,
    REACTIONS,
    ENERGY,
    JOINT_SPACE,
    JACOBIANS,
];
const STATIC: &[Key] = &[POINTS, JOINTS, BODIES, REACTIONS];

/// The output groups, by analysis kind.
pub const OUTPUTS: Vocabulary = Vocabulary {
    what: "analysis kind",
    table: "[analysis.outputs]",
    selector: "kind",
    common: &[],
    entries: &[
        Entry {
            name: "kinematic",
            aliases: &[],
            summary: "positions, velocities and accelerations",
            keys: &[POINTS, JOINTS, BODIES],
        },
        Entry {
            name: "dynamic",
            aliases: &[],
            summary: "the kinematic groups, driver efforts, reactions, energy, constraint drift",
            keys: MOTION,
        },
        Entry {
            name: "inverse_dynamics",
            aliases: &[],
            summary: "the kinematic groups, driver efforts, reactions, energy, the joint space",
            keys: INVERSE,
        },
        Entry {
            name: "static",
            aliases: &[],
            summary: "poses, holding efforts, reactions, stability",
            keys: STATIC,
        },
        Entry {
            name: "quasi_static",
            aliases: &[],
            summary: "poses, holding efforts, reactions, stability at each time",
            keys: STATIC,
        },
        Entry {
            name: "modal",
            aliases: &[],
            summary: "the static groups, modes and mode shapes",
            keys: STATIC,
        },
    ],
};
