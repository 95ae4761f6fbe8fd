//! `[analysis] kind = ...`: the analysis kinds and the keys each takes.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const T_START: Key = Key::new(
    "t_start",
    Value::Number(Quantity::Time),
    Default::Is("0"),
    "start time",
);
const T_END: Key = Key::new(
    "t_end",
    Value::Number(Quantity::Time),
    Default::Required,
    "end time",
);
const STEPS: Key = Key::new(
    "steps",
    Value::Count {
        min: 1,
        max: 10_000_000,
    },
    Default::Is("100 (or from dt)"),
    "output steps: the grid has steps + 1 times",
);
const DT: Key = Key::new(
    "dt",
    Value::Number(Quantity::Time),
    Default::Is("(t_end − t_start) / steps"),
    "the output step, instead of steps (it must divide the span into whole steps)",
)
.elsewhere("a dynamic analysis's dt is the integration step (its output step is output_dt or steps); a static or modal analysis has one time");
const POSITION_TOLERANCE: Key = Key::new(
    "position_tolerance",
    Value::Tolerance {
        min: 1e-14,
        max: 1e-6,
    },
    Default::Is("1e-10"),
    "the position solves' tolerance on the scaled residual max |Φ_i| / e_i",
)
.aliases(&["tolerance"])
.elsewhere("a dynamic run's accuracy is set by rtol and atol, or newton_tolerance; a static one's by equilibrium_tolerance");
const EQUILIBRIUM_TOLERANCE: Key = Key::new(
    "equilibrium_tolerance",
    Value::Tolerance {
        min: 1e-14,
        max: 1e-6,
    },
    Default::Is("1e-10"),
    "the equilibrium's tolerance: unbalanced forces over the size of the force terms, torques over L times it, constraint equations over their scale",
)
.aliases(&["tolerance"]);
const TIME: Key = Key::new(
    "time",
    Value::Number(Quantity::Time),
    Default::Is("0"),
    "the time at which the drivers are held",
)
.elsewhere("the other kinds have a time grid (t_start, t_end, steps or dt)");
const LOAD_STEPS: Key = Key::new(
    "load_steps",
    Value::Count { min: 1, max: 1000 },
    Default::Is("1"),
    "equal load increments tried first",
);
const MODES: Key = Key::new(
    "modes",
    Value::Count {
        min: 1,
        max: 10_000,
    },
    Default::Is("all (10 on the sparse path of large models)"),
    "how many of the lowest modes",
);
const INPUTS: Key = Key::new(
    "inputs",
    Value::Names,
    Default::Is("none"),
    "the force elements (point_force, torque) and, for modal, one-coordinate drivers that are the inputs of the state-space model",
);
const LINEARIZE_AT: Key = Key::new(
    "linearize_at",
    Value::Number(Quantity::Time),
    Default::Is("none"),
    "the time of the state about which the run is linearized (modes and state-space matrices)",
)
.elsewhere("kind = \"modal\" linearizes about an equilibrium");
const OUTPUT_DT: Key = Key::new(
    "output_dt",
    Value::Number(Quantity::Time),
    Default::Is("(t_end − t_start) / steps"),
    "the output step, instead of steps",
)
.elsewhere(
    "the output step of a kinematic, inverse dynamics or quasi-static analysis is dt or steps",
);
const INTEGRATOR: Key = Key::new(
    "integrator",
    Value::Choice(&["dopri5", "generalized_alpha"]),
    Default::Is("\"dopri5\""),
    "the integrator; its keys are in the integrator table",
)
.elsewhere("only a dynamic analysis integrates");

/// The integrator keys of a dynamic analysis (the integrator table, `super::INTEGRATORS`,
/// says which integrator takes which).
const INTEGRATOR_KEYS: [Key; 6] = super::integrators::KEYS;

const FREE_DOF: Key = Key::new(
    "free_dof",
    Value::Choice(&["refuse", "hold"]),
    Default::Is("\"refuse\""),
    "degrees of freedom no driver prescribes: \"refuse\" the run, or \"hold\" them still by the least change from the last output time, weighted as OndselSolver weights it (the default of an ASMT file)",
)
.elsewhere("inverse dynamics needs a fully driven mechanism; a dynamic run moves the free degrees of freedom by the forces");
const INCONSISTENT_JOINTS: Key = Key::new(
    "inconsistent_joints",
    Value::Choice(&["refuse", "drop"]),
    Default::Is("\"refuse\""),
    "an over-constrained model whose redundant joints disagree: \"refuse\" it, naming the rows that stay open at the best fit, or \"drop\" those rows and run with them open, as OndselSolver does (a warning at every run)",
)
.elsewhere("a dynamic run assembles only consistent models");
const KINEMATIC: &[Key] = &[
    T_START,
    T_END,
    STEPS,
    DT,
    POSITION_TOLERANCE,
    FREE_DOF,
    INCONSISTENT_JOINTS,
];
const INVERSE_DYNAMICS: &[Key] = &[
    T_START,
    T_END,
    STEPS,
    DT,
    POSITION_TOLERANCE,
    INCONSISTENT_JOINTS,
];
const DYNAMIC: &[Key] = &[
    T_START,
    T_END,
    STEPS,
    OUTPUT_DT,
    INTEGRATOR,
    INTEGRATOR_KEYS[0],
    INTEGRATOR_KEYS[1],
    INTEGRATOR_KEYS[2],
    INTEGRATOR_KEYS[3],
    INTEGRATOR_KEYS[4],
    INTEGRATOR_KEYS[5],
    LINEARIZE_AT,
    INPUTS,
];
const STATIC: &[Key] = &[TIME, EQUILIBRIUM_TOLERANCE, LOAD_STEPS];
const QUASI_STATIC: &[Key] = &[T_START, T_END, STEPS, DT, EQUILIBRIUM_TOLERANCE, LOAD_STEPS];
const MODAL: &[Key] = &[TIME, EQUILIBRIUM_TOLERANCE, LOAD_STEPS, MODES, INPUTS];

/// The analysis kinds.
pub const ANALYSES: Vocabulary = Vocabulary {
    what: "analysis kind",
    table: "[analysis]",
    selector: "kind",
    common: &[
        Key::new(
            "kind",
            Value::Choice(&[
                "kinematic",
                "dynamic",
                "inverse_dynamics",
                "static",
                "quasi_static",
                "modal",
            ]),
            Default::Required,
            "the analysis",
        ),
        Key::new(
            "outputs",
            Value::Table,
            Default::Is("every body, point and joint"),
            "[analysis.outputs]: what to write",
        ),
        Key::new(
            "plots",
            Value::Choice(&["svg", "none"]),
            Default::Is("\"svg\""),
            "the plot format",
        ),
    ],
    entries: &[
        Entry {
            name: "kinematic",
            aliases: &[],
            summary: "positions, velocities and accelerations of a driven mechanism over the time grid (free degrees of freedom refused or held)",
            keys: KINEMATIC,
        },
        Entry {
            name: "dynamic",
            aliases: &[],
            summary: "the motion the forces produce, from the drawn pose and velocities",
            keys: DYNAMIC,
        },
        Entry {
            name: "inverse_dynamics",
            aliases: &[],
            summary: "driver efforts and joint reactions of a fully driven mechanism along its kinematics",
            keys: INVERSE_DYNAMICS,
        },
        Entry {
            name: "static",
            aliases: &[],
            summary: "the equilibrium under the file's forces with the drivers held, its stability and holding efforts",
            keys: STATIC,
        },
        Entry {
            name: "quasi_static",
            aliases: &[],
            summary: "the equilibria along the time grid as the drivers move",
            keys: QUASI_STATIC,
        },
        Entry {
            name: "modal",
            aliases: &[],
            summary: "natural frequencies, damping ratios and mode shapes about an equilibrium, and a state-space model",
            keys: MODAL,
        },
    ],
};
