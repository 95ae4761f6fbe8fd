//! [`DynamicsError`]: everything a dynamic analysis can report. Variants name the element
//! (body, joint, force) and carry the numbers.

use crate::results::DynamicResults;
use cardan_mechanism::{AnalysisError, EquationName, OpenElement};
use thiserror::Error;

/// An error of the dynamics layer.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// A moving body has no mass or no inertia tensor.
    #[error("body \"{body}\": dynamic analysis needs a mass and an inertia tensor")]
    MissingInertia {
        /// The body.
        body: String,
    },
    /// The model has curve elements (points on curves, cam pairs), which the linearization
    /// about a motion and the sparse linearization do not take yet.
    #[error("{what} \"{element}\": the linearization about a motion and the sparse linearization do not take curve elements yet (kinematic, dynamic, inverse dynamic, static and modal analyses do)")]
    CurveElement {
        /// What the first such element is ("point-on-curve", "cam").
        what: &'static str,
        /// The first such element.
        element: String,
    },
    /// A curve element's parameter ran off the end of its open curve (a slot's end, a
    /// profile's end) during a dynamic run: beyond it the curve is only the straight continuation
    /// that keeps the equations smooth, so the run stops there.
    #[error("{what} \"{element}\": at t = {time} the {contact} has run off the end of its {curve} ({parameter} = {u:.9}; the {curve} runs from {parameter} = {start} to {end}); the motion carries it past the {curve}'s end: extend the {curve}, stop the motion with a limit, or shorten the run", curve = cardan_mechanism::runs_on(what))]
    CurveEnd {
        /// What the element is ("point-on-curve", "cam").
        what: &'static str,
        /// The element.
        element: String,
        /// "point", or "contact point" of a cam pair.
        contact: &'static str,
        /// The parameter's name ("u", "w", "v").
        parameter: &'static str,
        /// The time of the evaluation past the end.
        time: f64,
        /// The curve parameter there.
        u: f64,
        /// The curve's first parameter.
        start: f64,
        /// The curve's last parameter.
        end: f64,
    },
    /// A curve element's parameters could not be found at the bodies' poses (the closest-point
    /// iteration did not converge, or the curve's tangent vanished).
    #[error("{what} \"{element}\": at t = {time} its curve parameters could not be followed (the closest point on the curve did not converge; the point is {residual:.3e} from the curve): the bodies have left the curve, or the curve has a cusp there")]
    CurveLost {
        /// What the element is ("point-on-curve", "cam").
        what: &'static str,
        /// The element.
        element: String,
        /// The time.
        time: f64,
        /// |Φ| at the last iterate.
        residual: f64,
    },
    /// The model has a path driver (a curve parameter prescribed in time), which the
    /// equations of motion, whose curve parameters follow the bodies, do not take.
    #[error("path driver \"{driver}\": dynamic, inverse dynamic, static and modal analyses do not take path drivers yet (a kinematic analysis does); drive the mechanism's joints instead, or run kind = \"kinematic\"")]
    PathDriver {
        /// The first path driver.
        driver: String,
    },
    /// A collision shape the geometry library refuses (a convex hull that cannot be built, a
    /// triangle mesh that is not valid).
    #[error("shape \"{shape}\": {reason}")]
    BadShape {
        /// The shape.
        shape: String,
        /// What is wrong.
        reason: String,
    },
    /// Two collision shapes overlap deeply at the start of a run (more than
    /// [`crate::collision::DEEP_PENETRATION`] of the thinner one's thickness).
    #[error("shapes \"{shape_1}\" and \"{shape_2}\" overlap by {depth:e} m at the start (t = {time} s), {percent:.0} % of the thinner one: the contact would throw them apart; draw them apart or touching (a resting contact's static penetration is allowed)")]
    ShapesOverlap {
        /// One shape.
        shape_1: String,
        /// The other.
        shape_2: String,
        /// The penetration (m).
        depth: f64,
        /// The time.
        time: f64,
        /// The penetration in percent of the thinner shape's thickness.
        percent: f64,
    },
    /// A force element refers to a body, point or joint that does not exist, or is invalid.
    #[error("force \"{force}\": {reason}")]
    BadForce {
        /// The force element.
        force: String,
        /// The key of the element the reason is about (`stiffness`, `body_j`...), when one is;
        /// a front end places the error there.
        key: Option<&'static str>,
        /// What is wrong.
        reason: String,
    },
    /// A limit the dynamics cannot treat (a compliant law, not yet supported) or a state
    /// beyond a limit at the start of a run.
    #[error("limit \"{limit}\": {reason}")]
    Limit {
        /// The limit.
        limit: String,
        /// What is wrong.
        reason: String,
    },
    /// The joint-space outputs cannot be computed for this model or at this time
    /// ([`crate::joint_space`]).
    #[error("joint space: {reason}")]
    JointSpace {
        /// Why.
        reason: String,
    },
    /// Invalid options (times, tolerances, step sizes).
    #[error("invalid options: {0}")]
    Options(String),
    /// The initial positions cannot be assembled (the joints and drivers that stay open).
    #[error("initial conditions: positions cannot be made consistent; open: {}", fmt_open(.open))]
    InconsistentPositions {
        /// The elements that stay open, largest residual first.
        open: Vec<OpenElement>,
    },
    /// The initial velocities cannot be made consistent (Φ_v v = ν has no solution: the
    /// velocity equations named are dependent on others with incompatible right-hand sides).
    #[error("initial conditions: velocities cannot be made consistent (residual {residual:.3e}); equations: {}", fmt_names(.equations))]
    InconsistentVelocities {
        /// Residual max |Φ_v v − ν| after the projection.
        residual: f64,
        /// The equations that stay violated.
        equations: Vec<EquationName>,
    },
    /// The augmented (KKT) matrix is singular: the constraints are dependent at this
    /// configuration (a singular position), beyond the redundancy removed at the start.
    #[error("t = {time}: the equations of motion are singular (dependent constraints: {})", fmt_names(.dependent))]
    Singular {
        /// Time.
        time: f64,
        /// The constraint equations found dependent.
        dependent: Vec<EquationName>,
    },
    /// The step size fell below the minimum (adaptive integration) or Newton did not converge
    /// at the minimum step (implicit integration).
    #[error("t = {time}: step size {step:.3e} below the minimum ({reason})")]
    StepTooSmall {
        /// Time.
        time: f64,
        /// The step size.
        step: f64,
        /// Why the step was reduced.
        reason: String,
    },
    /// The position projection or the implicit Newton iteration did not converge.
    #[error(
        "t = {time}: {what} did not converge in {iterations} iterations (residual {residual:.3e})"
    )]
    NotConverged {
        /// Time.
        time: f64,
        /// Which iteration.
        what: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Last scaled residual.
        residual: f64,
    },
    /// NaN or infinity in the state or the forces.
    #[error("t = {time}: non-finite values in {what}")]
    NonFinite {
        /// Time.
        time: f64,
        /// Where.
        what: &'static str,
    },
    /// A force element's force or torque exceeded the magnitude limit of a constant one, or
    /// was not finite ([`crate::Dynamics`] checks every force evaluation of a run).
    #[error("t = {time}: force \"{force}\" reaches {value:e} {unit}, beyond the limit of {limit:e} {unit} that any force element must stay within (a runaway expression, a spring stretched without bound, or a value in the wrong unit?)")]
    ForceLimit {
        /// Time.
        time: f64,
        /// The force element.
        force: String,
        /// Its force's or torque's magnitude.
        value: f64,
        /// The limit.
        limit: f64,
        /// N or N m.
        unit: &'static str,
    },
    /// Inverse dynamics needs a fully driven mechanism (DOF = number of drivers, DOF > 0 or
    /// drivers present).
    #[error("inverse dynamics needs a kinematically driven mechanism: {dof} degrees of freedom, {drivers} drivers")]
    NotFullyDriven {
        /// Degrees of freedom of the joints.
        dof: usize,
        /// Drivers.
        drivers: usize,
    },
    /// The step limit was reached.
    #[error("t = {time}: maximum number of steps ({max_steps}) reached")]
    TooManySteps {
        /// Time.
        time: f64,
        /// The limit.
        max_steps: usize,
    },
    /// The caller's progress callback asked to stop (e.g. Ctrl-C): not a failure of the
    /// analysis; the results so far are kept ([`DynamicsError::MidRun`]).
    #[error("t = {time}: stopped on request")]
    Stopped {
        /// The time reached.
        time: f64,
    },
    /// A failure after some outputs were stored: the cause and the results up to the last
    /// stored time.
    #[error("{source} (results kept up to t = {last_time})")]
    MidRun {
        /// The cause.
        source: Box<DynamicsError>,
        /// The last stored time.
        last_time: f64,
        /// The results so far.
        partial: Box<DynamicResults>,
    },
    /// A static analysis found no equilibrium: Newton did not converge even with the load
    /// steps halved `max_halvings` times (or, quasi-statically, the time interval).
    #[error("t = {time}: no static equilibrium found; the load factor reached {load_factor} of 1 (scaled residual {residual:.3e})")]
    NoEquilibrium {
        /// Time (drivers held there).
        time: f64,
        /// The last load factor at which an equilibrium was found (0: none).
        load_factor: f64,
        /// The scaled residual of the last failed solve.
        residual: f64,
    },
    /// A static analysis found a degree of freedom without stiffness along which the loads do
    /// work: there is no equilibrium (a slider under gravity along its slide, with no spring).
    #[error("t = {time}: no static equilibrium: the mechanism is free to move along {direction} (no stiffness along it) and the loads push it that way; add a spring, a driver or a stop")]
    FreeDirection {
        /// Time.
        time: f64,
        /// The direction, named by the joint coordinate that moves most along it.
        direction: String,
    },
    /// An error of the mechanism layer (assembly, kinematics).
    #[error(transparent)]
    Mechanism(#[from] AnalysisError),
}

impl DynamicsError {
    /// The results stored before a mid-run failure ([`DynamicsError::MidRun`]).
    pub fn partial_results(&self) -> Option<&DynamicResults> {
        match self {
            DynamicsError::MidRun { partial, .. } => Some(partial),
            _ => None,
        }
    }

    /// The underlying error (unwraps [`DynamicsError::MidRun`]).
    pub fn cause(&self) -> &DynamicsError {
        match self {
            DynamicsError::MidRun { source, .. } => source.cause(),
            e => e,
        }
    }
}

fn fmt_open(open: &[OpenElement]) -> String {
    open.iter()
        .map(|e| format!("{} ({:.3e})", e.element, e.residual))
        .collect::<Vec<_>>()
        .join(", ")
}

fn fmt_names(names: &[EquationName]) -> String {
    names
        .iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
