//! Errors of the mechanism layer: [`ModelError`] (building), [`AnalysisError`] (running).
//!
//! Each variant names the element concerned and carries the numbers that explain the problem.

pub use crate::equation::EquationName;
use crate::results::{DroppedRowResidual, Results};
use cardan_solver::SolverError;
use thiserror::Error;

/// "a, b, c": plain notation between 1e-4 and 1e9, scientific beyond.
fn fmt_numbers(v: &[f64]) -> String {
    v.iter()
        .map(|&x| {
            if x == 0.0 || (1e-4..1e9).contains(&x.abs()) {
                format!("{x}")
            } else {
                format!("{x:e}")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn fmt_suggestion(s: &Option<String>) -> String {
    match s {
        Some(s) => format!("; did you mean \"{s}\"?"),
        None => String::new(),
    }
}

/// "\"a\", \"b\"" (quoted), or "(none)".
fn fmt_known(names: &[String]) -> String {
    if names.is_empty() {
        return "(none)".into();
    }
    let v: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
    v.join(", ")
}

/// A mechanism definition that cannot be built.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ModelError {
    /// A body name is used twice (or a body is called "ground").
    #[error("duplicate body name \"{name}\"")]
    DuplicateBody {
        /// The name.
        name: String,
    },
    /// A point or vector name is used twice on the same body.
    #[error("duplicate {what} \"{name}\" on body \"{body}\"")]
    DuplicateFeature {
        /// "point" or "vector".
        what: &'static str,
        /// The body.
        body: String,
        /// The name.
        name: String,
    },
    /// A joint or driver name is used twice (joints and drivers share one namespace).
    #[error("duplicate joint/driver name \"{name}\"")]
    DuplicateElement {
        /// The name.
        name: String,
    },
    /// A name is empty.
    #[error("{what} has an empty name")]
    EmptyName {
        /// What kind of element.
        what: String,
    },
    /// A referenced body does not exist.
    #[error("{element}: unknown body \"{name}\"{} (bodies: {})", fmt_suggestion(.suggestion), fmt_known(.known))]
    UnknownBody {
        /// The element that refers to it (e.g. `joint "j2"`, `point "B"`).
        element: String,
        /// The missing name.
        name: String,
        /// The closest existing name, if any is close.
        suggestion: Option<String>,
        /// The bodies there are (ground first, then in definition order).
        known: Vec<String>,
    },
    /// A referenced point does not exist on its body.
    #[error("{element}: body \"{body}\" has no point \"{name}\"{} (points of \"{body}\": {})", fmt_suggestion(.suggestion), fmt_known(.known))]
    UnknownPoint {
        /// The element that refers to it.
        element: String,
        /// The body.
        body: String,
        /// The missing name.
        name: String,
        /// The closest point name on that body.
        suggestion: Option<String>,
        /// The points of that body, sorted.
        known: Vec<String>,
    },
    /// A referenced vector does not exist on its body.
    #[error("{element}: body \"{body}\" has no vector \"{name}\"{} (vectors of \"{body}\": {})", fmt_suggestion(.suggestion), fmt_known(.known))]
    UnknownVector {
        /// The element that refers to it.
        element: String,
        /// The body.
        body: String,
        /// The missing name.
        name: String,
        /// The closest vector name on that body.
        suggestion: Option<String>,
        /// The vectors of that body, sorted.
        known: Vec<String>,
    },
    /// A driver refers to a joint that does not exist.
    #[error("{element}: unknown joint \"{name}\"{} (joints: {})", fmt_suggestion(.suggestion), fmt_known(.known))]
    UnknownJoint {
        /// The driver.
        element: String,
        /// The missing name.
        name: String,
        /// The closest joint name.
        suggestion: Option<String>,
        /// The joints, in definition order.
        known: Vec<String>,
    },
    /// A number is NaN or infinite.
    #[error("{element}: {what} is not finite ({value})")]
    NotFinite {
        /// The element.
        element: String,
        /// Which quantity.
        what: String,
        /// The value.
        value: f64,
    },
    /// A number is finite but absurdly large for its quantity (|x| > limit,
    /// [`crate::sanity::Quantity::limit`]).
    #[error("{element}: {what} = {value:e} {unit} is beyond the limit of {limit:e} {unit} (in SI units); check the exponent and the unit")]
    Absurd {
        /// The element.
        element: String,
        /// Which quantity.
        what: String,
        /// The value.
        value: f64,
        /// The limit.
        limit: f64,
        /// The SI unit of value and limit.
        unit: &'static str,
    },
    /// A direction vector has zero length.
    #[error("vector \"{name}\" on body \"{body}\" has zero length")]
    ZeroVector {
        /// The body.
        body: String,
        /// The vector.
        name: String,
    },
    /// An orientation cannot be built (zero axis, zero Euler parameters, parallel axes).
    #[error("body \"{body}\": invalid orientation: {reason}")]
    BadOrientation {
        /// The body.
        body: String,
        /// Why.
        reason: String,
    },
    /// Mass zero or negative.
    #[error("body \"{body}\": mass must be positive, got {mass} kg")]
    NonPositiveMass {
        /// The body.
        body: String,
        /// The mass.
        mass: f64,
    },
    /// Inertia tensor not symmetric.
    #[error(
        "body \"{body}\": inertia tensor is not symmetric (relative asymmetry {asymmetry:.3e})"
    )]
    InertiaNotSymmetric {
        /// The body.
        body: String,
        /// max |I − Iᵀ| / max |I|.
        asymmetry: f64,
    },
    /// Inertia tensor not positive definite.
    #[error("body \"{body}\": inertia tensor is not positive definite (smallest principal moment {min_eigenvalue:.3e} kg m²); every principal moment must be > 0")]
    InertiaNotPositiveDefinite {
        /// The body.
        body: String,
        /// Its smallest eigenvalue.
        min_eigenvalue: f64,
    },
    /// The principal moments violate the triangle inequality I₁ + I₂ ≥ I₃: no rigid body
    /// has them ([`crate::sanity`]).
    #[error(
        "body \"{body}\": inertia tensor is not a rigid body's: its principal moments {} kg m² violate the triangle inequality (the two smaller must add up to at least the largest; a thin disk has equality)",
        fmt_numbers(.moments)
    )]
    InertiaTriangle {
        /// The body.
        body: String,
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
    /// A joint or driver connects a body to itself.
    #[error("{element} connects body \"{body}\" to itself; it needs two different bodies")]
    SelfConnection {
        /// The element.
        element: String,
        /// The body.
        body: String,
    },
    /// A joint or driver acts between ground and ground (constrains nothing).
    #[error("{element}: both ends are on ground")]
    GroundToGround {
        /// The element.
        element: String,
    },
    /// A force element acts on ground (it needs a moving body).
    #[error("{element}: acts on the ground, which cannot move; it needs a moving body")]
    OnGround {
        /// The element.
        element: String,
    },
    /// A joint kind needs an axis that was not given.
    #[error("joint \"{joint}\" ({kind}): {which} is required")]
    MissingAxis {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
        /// "axis_i" or "axis_j".
        which: &'static str,
    },
    /// A rotation driver (or another element that uses the joint angle's zero) acts on a joint
    /// without x axes.
    #[error(
        "{element}: joint \"{joint}\" has no x axes, so its angle has no defined zero; the angle \
         is measured from x_axis_i to x_axis_j about axis_i: add x_axis_i and x_axis_j to the \
         joint (vectors perpendicular to its axes; pointing them the same way at the drawn pose \
         makes the drawn angle 0)"
    )]
    AngleWithoutXAxes {
        /// The element that needs the angle, e.g. `driver "motor"`.
        element: String,
        /// The joint.
        joint: String,
    },
    /// The axes of a joint on one body do not define a frame (x axis parallel to the axis),
    /// or the joint cannot be formed from them. `reason` uses the builder's keys.
    #[error("joint \"{joint}\", on body \"{body}\": {reason}")]
    BadMarker {
        /// The joint.
        joint: String,
        /// The body.
        body: String,
        /// Why.
        reason: String,
    },
    /// The arms of a universal joint's cross are drawn (nearly) parallel
    /// ([`crate::sanity::check_universal_arms`]).
    #[error("joint \"{joint}\" (universal): its arms axis_i and axis_j are {angle_deg:.1}° apart at the drawn pose; the two arms of the cross must be perpendicular (at least 45° apart as drawn, so the assembly can close them): check the vectors and the bodies' orientations")]
    UniversalArms {
        /// The joint.
        joint: String,
        /// The angle between the arms at the drawn pose, in degrees (0 to 90).
        angle_deg: f64,
    },
    /// A cone joint's half-angle α is within [`cardan_constraints::joints::CONE_MARGIN`] of 0 or
    /// π (or outside [0, π]): its row z_iᵀz_j − cos α loses rank there.
    #[error("{element} (cone): angle {value} rad {} must lie from 0.001 to π − 0.001 rad; near 0 or π the row z_i·z_j − cos α loses rank (its gradient vanishes where the axes are parallel): for parallel axes use a parallel_axes joint (or revolute / cylindrical, which hold them parallel with full-rank rows)", if *given { "(as given)" } else { "(as drawn, no angle given)" })]
    ConeAngle {
        /// The joint.
        element: String,
        /// α, rad.
        value: f64,
        /// Whether the model gave it (else it is the drawn angle).
        given: bool,
    },
    /// A number that must be positive is not.
    #[error("{element}: {what} must be positive, got {value}")]
    NonPositive {
        /// The element.
        element: String,
        /// Which quantity.
        what: String,
        /// The value.
        value: f64,
    },
    /// A point-on-curve element's initial parameter lies off its open curve.
    #[error("{element}: the initial curve parameter u = {u} lies off the open curve, which runs from u = {start} to {end}; move the point onto the curve or extend the curve")]
    CurveParameterOff {
        /// The element.
        element: String,
        /// The initial parameter.
        u: f64,
        /// The curve's first parameter.
        start: f64,
        /// The curve's last parameter.
        end: f64,
    },
    /// A curve element drawn apart: its point (a cam's follower curve) is off its curve at the
    /// drawn pose by more than 1e-3 of the element's size, or a cam's curves cross instead of
    /// touching tangentially. The assembly would pull the bodies together, silently and maybe
    /// onto another branch (the roller on the far side of the cam).
    #[error("{element}: {what} at the drawn pose ({gap:.3e}{unit}, more than {tolerance:.1e}{unit} allowed); {advice}")]
    CurveApart {
        /// The element.
        element: String,
        /// What is apart ("the point is this far from its curve"...).
        what: String,
        /// The distance (m) or the tangents' misalignment (the sine of their angle).
        gap: f64,
        /// What is allowed.
        tolerance: f64,
        /// The unit of both (" m", or "" for a sine).
        unit: &'static str,
        /// What to do.
        advice: &'static str,
    },
    /// A number that must not be zero is (its sign is meaningful: a gear ratio's sense of
    /// rotation, a screw's hand).
    #[error("{element}: {what} must be non-zero (its sign gives the sense), got 0")]
    Zero {
        /// The element.
        element: String,
        /// Which quantity.
        what: String,
    },
    /// A driver refers to a joint of a kind it cannot drive.
    #[error(
        "driver \"{driver}\": joint \"{joint}\" is {kind}; a {driver_kind} driver needs {expected}"
    )]
    WrongJointKind {
        /// The driver.
        driver: String,
        /// The joint.
        joint: String,
        /// The joint's kind.
        kind: &'static str,
        /// "rotation" or "translation".
        driver_kind: &'static str,
        /// What kinds are accepted ("a revolute or cylindrical joint").
        expected: String,
    },
    /// A time function is malformed.
    #[error("driver \"{driver}\": {reason}")]
    BadTimeFunction {
        /// The driver.
        driver: String,
        /// Why.
        reason: String,
    },
    /// A coupler names a joint of a kind it cannot couple.
    #[error(
        "coupler \"{coupler}\" ({coupler_kind}): {role} \"{joint}\" is {kind}; it needs {expected}"
    )]
    WrongCouplerJoint {
        /// The coupler.
        coupler: String,
        /// Its kind ("gear", ...).
        coupler_kind: &'static str,
        /// The key naming the joint ("joint_i", "slide_joint", ...).
        role: &'static str,
        /// The joint.
        joint: String,
        /// The joint's kind.
        kind: &'static str,
        /// What kinds are accepted.
        expected: String,
    },
    /// A coupler's joints do not share exactly one body.
    #[error("coupler \"{coupler}\": {reason}")]
    CouplerBodies {
        /// The coupler.
        coupler: String,
        /// Why.
        reason: String,
    },
    /// A coupler's joint axes are not arranged as it needs (collinear gear axes, a rack not
    /// across its pinion's axis, a screw's slide not along its axis).
    #[error("coupler \"{coupler}\": {reason}")]
    CouplerGeometry {
        /// The coupler.
        coupler: String,
        /// Why.
        reason: String,
    },
    /// A cam pair cannot be formed from its curves (a helix, a zero plane normal).
    #[error("cam \"{cam}\": {reason}")]
    CamGeometry {
        /// The cam pair.
        cam: String,
        /// Why.
        reason: String,
    },
    /// The mechanism has no moving body.
    #[error("the mechanism has no moving body")]
    NoBodies,
    /// A limit's numbers or coordinate are wrong (lo > hi, e outside [0, 1], a coordinate the
    /// joint kind does not have, a compliant law with a negative coefficient).
    #[error("limit \"{limit}\", {key}: {reason}")]
    BadLimit {
        /// The limit.
        limit: String,
        /// Its joint (as given).
        joint: String,
        /// The key whose value is wrong.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A joint friction's numbers or joint are wrong (μ < 0, a kind without friction, a
    /// missing pin radius).
    #[error("friction \"{friction}\", {key}: {reason}")]
    BadFriction {
        /// The friction element.
        friction: String,
        /// Its joint (as given).
        joint: String,
        /// The key whose value is wrong.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A collision shape's geometry, placement, material or filter is wrong.
    #[error("shape \"{shape}\", {key}: {reason}")]
    BadShape {
        /// The shape.
        shape: String,
        /// The key whose value is wrong.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A contact material's numbers are wrong.
    #[error("material \"{material}\", {key}: {reason}")]
    BadMaterial {
        /// The material.
        material: String,
        /// The key whose value is wrong.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// The drawn pose lies beyond a limit of its own model.
    #[error("limit \"{limit}\": the drawn pose violates its {key} bound: joint \"{joint}\" has {coordinate} = {value} there, beyond {key} = {bound}; draw the bodies inside the range or move the bound")]
    LimitViolated {
        /// The limit.
        limit: String,
        /// "lower" or "upper".
        key: &'static str,
        /// The joint.
        joint: String,
        /// The coordinate's name.
        coordinate: &'static str,
        /// Its value at the drawn pose.
        value: f64,
        /// The bound.
        bound: f64,
    },
    /// A joint is given a key its kind does not use (axes of a spherical-spherical joint, x axes
    /// of a perpendicular joint, a length of a revolute joint).
    #[error("joint \"{joint}\" ({kind}): a {kind} joint takes no {key}; its equations and coordinates do not use them: remove them")]
    UnusedKey {
        /// The joint.
        joint: String,
        /// Its kind.
        kind: &'static str,
        /// The keys.
        key: &'static str,
    },
}

/// What kind of model element an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// A moving body (its points and vectors included).
    Body,
    /// A joint.
    Joint,
    /// A driver.
    Driver,
    /// A coupler.
    Coupler,
    /// A force element.
    Force,
}

/// Where in a model an error is, for a front end to point at the source: the element (kind and
/// name), and the field (the builder's and the model file's key) or the offending value (a name
/// the element refers to) when known.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Site {
    /// The element's kind.
    pub kind: ElementKind,
    /// The element's name (a body's name for its points and vectors).
    pub name: String,
    /// The key whose value is wrong (`mass`, `inertia`, `length`, `joint`, ...).
    pub field: Option<String>,
    /// A name the element refers to that is wrong (an unknown body, point or joint).
    pub value: Option<String>,
}

impl Site {
    fn new(kind: ElementKind, name: &str, field: Option<&str>, value: Option<&str>) -> Self {
        Self {
            kind,
            name: name.into(),
            field: field.map(Into::into),
            value: value.map(Into::into),
        }
    }

    /// From an element description as the builder writes it (`joint "j"`, `driver "d"`,
    /// `force "f"`, `body "b"`, `point "p" on body "b"`, `vector "v" on body "b"`).
    fn parse(element: &str, field: Option<&str>, value: Option<&str>) -> Option<Self> {
        let quoted: Vec<&str> = element.split('"').skip(1).step_by(2).collect();
        let kind = match element.split_whitespace().next()? {
            "body" | "point" | "vector" => ElementKind::Body,
            "joint" | "point-on-curve" | "point-on-surface" | "cam" => ElementKind::Joint,
            "driver" | "path" => ElementKind::Driver,
            "coupler" => ElementKind::Coupler,
            "force" => ElementKind::Force,
            _ => return None,
        };
        // A point or vector: the body's, at the feature's name.
        let (name, value) = match (element.split_whitespace().next()?, quoted.as_slice()) {
            ("point" | "vector", [feature, body, ..]) => (*body, value.or(Some(*feature))),
            (_, [name, ..]) => (*name, value),
            _ => return None,
        };
        Some(Self::new(kind, name, field, value))
    }
}

/// The model file key of a builder field description ("free length (≥ 0 required)" →
/// "free_length").
fn key_of(what: &str) -> String {
    what.split(" (")
        .next()
        .unwrap_or(what)
        .trim()
        .replace(' ', "_")
}

impl ModelError {
    /// The table (`"shape"` or `"material"`), the element and the key of a collision shape's
    /// or a material's error ([`ModelError::BadShape`], [`ModelError::BadMaterial`], or an
    /// unknown body named by a shape).
    pub fn contact_site(&self) -> Option<(&'static str, &str, &str)> {
        match self {
            ModelError::BadShape { shape, key, .. } => Some(("shape", shape, key)),
            ModelError::BadMaterial { material, key, .. } => Some(("material", material, key)),
            ModelError::UnknownBody { element, .. } => element
                .strip_prefix("shape \"")
                .and_then(|r| r.strip_suffix('"'))
                .map(|s| ("shape", s, "body")),
            _ => None,
        }
    }

    /// The element and the key of a limit's or a friction's error ([`ModelError::BadLimit`],
    /// [`ModelError::LimitViolated`], [`ModelError::BadFriction`], or an unknown joint named by
    /// one), for a front end that declares them as elements of their own.
    pub fn limit_site(&self) -> Option<(&str, &str)> {
        match self {
            ModelError::BadLimit { limit, key, .. } => Some((limit, key)),
            ModelError::LimitViolated { limit, key, .. } => Some((limit, key)),
            ModelError::BadFriction { friction, key, .. } => Some((friction, key)),
            ModelError::UnknownJoint { element, .. } => element
                .strip_prefix("limit \"")
                .or_else(|| element.strip_prefix("friction \""))
                .and_then(|r| r.strip_suffix('"'))
                .map(|l| (l, "joint")),
            _ => None,
        }
    }

    /// Where in the model the error is (see [`Site`]); `None` for errors about the model as a
    /// whole.
    pub fn site(&self) -> Option<Site> {
        use ElementKind::{Body, Driver, Joint};
        use ModelError as E;
        match self {
            E::DuplicateBody { name } => Some(Site::new(Body, name, None, None)),
            E::DuplicateFeature { body, name, .. } | E::ZeroVector { body, name } => {
                Some(Site::new(Body, body, None, Some(name)))
            }
            E::UnknownBody { element, name, .. }
            | E::UnknownPoint { element, name, .. }
            | E::UnknownVector { element, name, .. }
            | E::UnknownJoint { element, name, .. } => Site::parse(element, None, Some(name)),
            E::NotFinite { element, what, .. }
            | E::Absurd { element, what, .. }
            | E::NonPositive { element, what, .. }
            | E::Zero { element, what } => Site::parse(element, Some(&key_of(what)), None),
            E::CurveParameterOff { element, .. } => Site::parse(element, Some("initial_u"), None),
            E::CurveApart { element, .. } => Site::parse(element, None, None),
            E::BadOrientation { body, .. } => {
                Some(Site::new(Body, body, Some("orientation"), None))
            }
            E::NonPositiveMass { body, .. } => Some(Site::new(Body, body, Some("mass"), None)),
            E::InertiaNotSymmetric { body, .. }
            | E::InertiaNotPositiveDefinite { body, .. }
            | E::InertiaTriangle { body, .. } => Some(Site::new(Body, body, Some("inertia"), None)),
            E::SelfConnection { element, .. } | E::GroundToGround { element } => {
                Site::parse(element, Some("body_j"), None)
            }
            E::OnGround { element } => Site::parse(element, Some("body"), None),
            E::MissingAxis { joint, .. } | E::BadMarker { joint, .. } => {
                Some(Site::new(Joint, joint, None, None))
            }
            E::UniversalArms { joint, .. } => Some(Site::new(Joint, joint, Some("axis_j"), None)),
            E::ConeAngle { element, given, .. } => {
                Site::parse(element, Some(if *given { "angle" } else { "axis_j" }), None)
            }
            E::AngleWithoutXAxes { element, .. } => Site::parse(element, Some("joint"), None),
            E::WrongJointKind { driver, .. } => {
                Some(Site::new(Driver, driver, Some("joint"), None))
            }
            E::BadTimeFunction { driver, .. } => {
                Some(Site::new(Driver, driver, Some("function"), None))
            }
            E::UnusedKey { joint, key, .. } => {
                Some(Site::new(Joint, joint, key.split_whitespace().next(), None))
            }
            E::WrongCouplerJoint { coupler, role, .. } => {
                Some(Site::new(ElementKind::Coupler, coupler, Some(role), None))
            }
            E::CouplerBodies { coupler, .. } | E::CouplerGeometry { coupler, .. } => {
                Some(Site::new(ElementKind::Coupler, coupler, None, None))
            }
            E::CamGeometry { cam, .. } => Some(Site::new(Joint, cam, None, None)),
            // A limit is about its joint's coordinate: the joint, at the limit's key (the limit
            // itself is named by [`ModelError::limit_site`]).
            E::BadLimit { joint, key, .. } => Some(Site::new(Joint, joint, Some(key), None)),
            E::LimitViolated { joint, key, .. } => Some(Site::new(Joint, joint, Some(key), None)),
            E::BadFriction { joint, key, .. } => Some(Site::new(Joint, joint, Some(key), None)),
            // Shapes and materials are named by [`ModelError::contact_site`].
            E::BadShape { .. } | E::BadMaterial { .. } => None,
            E::DuplicateElement { .. } | E::EmptyName { .. } | E::NoBodies => None,
        }
    }
}

fn fmt_names(v: &[EquationName]) -> String {
    if v.is_empty() {
        return "none identified".into();
    }
    v.iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A joint or driver whose equations are not satisfied, with its residual.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenElement {
    /// Joint or driver name.
    pub element: String,
    /// Euclidean norm of its residual (units of its equations).
    pub residual: f64,
}

fn fmt_open(v: &[OpenElement]) -> String {
    v.iter()
        .map(|e| format!("\"{}\" (|Φ| = {:.3e})", e.element, e.residual))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An analysis that could not be carried out.
#[derive(Debug, Clone, Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// The drivers do not use up exactly the degrees of freedom.
    #[error(
        "the mechanism has {dof} degrees of freedom but {drivers} drivers: {} {}",
        (*.dof as i64 - *.drivers as i64).unsigned_abs(),
        if .dof > .drivers { "missing" } else { "superfluous" }
    )]
    DriverCount {
        /// Degrees of freedom (joints only).
        dof: usize,
        /// Number of drivers.
        drivers: usize,
    },
    /// As many drivers as degrees of freedom, but some drivers depend on the joints or on each
    /// other (they do not control the free motion).
    #[error("the drivers do not control the mechanism: {} depend on the other equations", fmt_names(.dependent))]
    DependentDrivers {
        /// The dependent equations (drivers).
        dependent: Vec<EquationName>,
    },
    /// Assembly did not close the loops.
    #[error("assembly failed after {iterations} iterations: open {}", fmt_open(.open))]
    AssemblyFailed {
        /// Elements whose residual stays above tolerance, largest first.
        open: Vec<OpenElement>,
        /// Newton iterations made.
        iterations: usize,
    },
    /// A redundant model whose joints disagree grossly: with the kept equations satisfied, the
    /// equations dropped as redundant stay off by more than `limit` of the model's size
    /// (`analysis::dropped`).
    #[error(
        "at t = {time}: the model is over-constrained and inconsistent (its redundant joints \
         disagree): at its best fit, with the other equations satisfied, {} (more than \
         {limit:.0e} of the model's size is not rounding). The joints of \
         the loop through {} do not fit together: check that their axes are parallel (or \
         perpendicular) and their points agree as drawn, or replace one of them by a joint with \
         fewer equations (a revolute by a cylindrical, a spherical by a point_in_plane) so the \
         loop is no longer over-constrained",
        fmt_dropped(.dropped),
        fmt_elements(.dropped)
    )]
    InconsistentJoints {
        /// The time.
        time: f64,
        /// The scaled residual above which a dropped row is a gross disagreement.
        limit: f64,
        /// The dropped rows that stay off, one per element (its worst row).
        dropped: Vec<DroppedRowResidual>,
    },
    /// A rotation driver could only be assembled on the spurious branch φ = θ(t) ± π of its
    /// equation sin(φ − θ(t)) = 0, even by continuation from the drawn pose.
    #[error(
        "at t = {time}: rotation driver \"{driver}\" prescribes the angle {prescribed} rad, but \
         the mechanism assembles only at {reached} rad (the opposite branch, θ ± π), even when \
         turned there step by step from the drawn pose; check that the drawn pose can reach the \
         prescribed angle (a limit of the motion?) and that the x axes of the driven joint point \
         where you mean the angle 0"
    )]
    DriverBranch {
        /// The time.
        time: f64,
        /// The driver.
        driver: String,
        /// The assembled angle φ (principal value).
        reached: f64,
        /// The prescribed θ(t).
        prescribed: f64,
    },
    /// The Jacobian became singular during a run.
    #[error("singular configuration at t = {time}: dependent equations {}", fmt_names(.dependent))]
    Singular {
        /// The time.
        time: f64,
        /// The dependent equations.
        dependent: Vec<EquationName>,
        /// Results up to (not including) `time`, when the failure happened in a time-grid run.
        partial: Option<Box<Results>>,
    },
    /// Position Newton-Raphson did not converge during a run.
    #[error("position analysis did not converge at t = {time} after {iterations} iterations: worst equations {}", fmt_worst(.worst))]
    NotConverged {
        /// The time.
        time: f64,
        /// Iterations.
        iterations: usize,
        /// Worst equations and their scaled residuals.
        worst: Vec<(EquationName, f64)>,
        /// Results up to (not including) `time`.
        partial: Option<Box<Results>>,
    },
    /// A step's solution left solved equations open once the couplers' angles were continued
    /// over turns, even in the finest substep ([`crate::PositionReport::open`]).
    #[error("the motion could not be followed continuously at t = {time}: once the couplers' angles are continued over turns, {} stay open (the pose solved is a turn or a branch away from the last one); use more output steps", fmt_worst(.worst))]
    Discontinuous {
        /// The time.
        time: f64,
        /// The open equations and their scaled residuals.
        worst: Vec<(EquationName, f64)>,
        /// Results up to (not including) `time`.
        partial: Option<Box<Results>>,
    },
    /// A curve element's parameter left its open curve: the point (or the contact point of a
    /// cam pair) ran off the end of the curve's data (a slot's end, a path's last point, a
    /// profile's end); the run stops there.
    #[error("{what} \"{element}\": at t = {time} the {contact} has run off the end of its {curve} ({parameter} = {u:.9}; the {curve} runs from {parameter} = {start} to {end}); the prescribed motion drives it past the {curve}'s end: extend the {curve} or shorten the run", curve = runs_on(what))]
    CurveEnd {
        /// What the element is ("point-on-curve", "cam").
        what: &'static str,
        /// The element.
        element: String,
        /// "point", or "contact point" of a cam pair.
        contact: &'static str,
        /// The parameter's name ("u", "w", "v").
        parameter: &'static str,
        /// The first output time past the end.
        time: f64,
        /// The curve parameter there.
        u: f64,
        /// The curve's first parameter.
        start: f64,
        /// The curve's last parameter.
        end: f64,
        /// Results up to (not including) `time`.
        partial: Option<Box<Results>>,
    },
    /// A prescribed motion drives a joint coordinate past a limit: the run stops at the
    /// crossing, located inside the grid step ([`crate::Model::kinematics`]).
    #[error("limit \"{limit}\" reached at t = {time}: joint \"{joint}\" has {coordinate} = {value} at its {bound_name} bound {bound}; the prescribed motion drives it past the stop")]
    LimitReached {
        /// The limit.
        limit: String,
        /// The joint.
        joint: String,
        /// The coordinate's name.
        coordinate: &'static str,
        /// "lower" or "upper".
        bound_name: &'static str,
        /// The bound (rad or m).
        bound: f64,
        /// The crossing time.
        time: f64,
        /// The coordinate there (the bound, to the location's tolerance).
        value: f64,
        /// Results up to (not including) the grid time past the crossing.
        partial: Option<Box<Results>>,
    },
    /// Bad analysis options (time grid, ...).
    #[error("invalid analysis options: {0}")]
    Options(String),
    /// Any other solver failure.
    #[error("at t = {time}: {source}")]
    Solver {
        /// The time.
        time: f64,
        /// The solver error.
        source: SolverError,
        /// Results up to (not including) `time`.
        partial: Option<Box<Results>>,
    },
}

fn fmt_dropped(v: &[DroppedRowResidual]) -> String {
    v.iter()
        .map(|d| {
            let unit = match d.dimension {
                cardan_constraints::Dimension::Length => " m",
                cardan_constraints::Dimension::Area => " m²",
                cardan_constraints::Dimension::Dimensionless => "",
            };
            format!(
                "{} (dropped as redundant) stays off by {:.3e}{unit} ({:.3e} of the model's size)",
                d.equation,
                d.value.abs(),
                d.residual
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn fmt_elements(v: &[DroppedRowResidual]) -> String {
    let mut names: Vec<&str> = v.iter().map(|d| d.equation.element.as_str()).collect();
    names.dedup();
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

fn fmt_worst(v: &[(EquationName, f64)]) -> String {
    v.iter()
        .map(|(e, r)| format!("{e}: {r:.3e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl AnalysisError {
    /// The results computed before the failure, if the failure happened during a time-grid run.
    pub fn partial_results(&self) -> Option<&Results> {
        match self {
            AnalysisError::Singular { partial, .. }
            | AnalysisError::NotConverged { partial, .. }
            | AnalysisError::Discontinuous { partial, .. }
            | AnalysisError::LimitReached { partial, .. }
            | AnalysisError::CurveEnd { partial, .. }
            | AnalysisError::Solver { partial, .. } => partial.as_deref(),
            _ => None,
        }
    }

    /// Takes the partial results out of the error.
    pub fn into_partial_results(self) -> Option<Results> {
        match self {
            AnalysisError::Singular { partial, .. }
            | AnalysisError::NotConverged { partial, .. }
            | AnalysisError::Discontinuous { partial, .. }
            | AnalysisError::LimitReached { partial, .. }
            | AnalysisError::CurveEnd { partial, .. }
            | AnalysisError::Solver { partial, .. } => partial.map(|b| *b),
            _ => None,
        }
    }

    /// The error with `results` as its partial results (e.g. a front end's copy of a streamed run).
    pub fn with_partial(mut self, results: Results) -> Self {
        match &mut self {
            AnalysisError::Singular { partial, .. }
            | AnalysisError::NotConverged { partial, .. }
            | AnalysisError::Discontinuous { partial, .. }
            | AnalysisError::LimitReached { partial, .. }
            | AnalysisError::CurveEnd { partial, .. }
            | AnalysisError::Solver { partial, .. } => *partial = Some(Box::new(results)),
            _ => {}
        }
        self
    }
}

/// Either kind of error, for callers that build and run in one go.
#[derive(Debug, Clone, Error)]
pub enum Error {
    /// Building failed.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Running failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
}

/// What a curve element's parameter runs on, for messages: a point on a surface's "patch",
/// else an "open curve" (`what` is the element's [`crate::CurveElement::what`]).
pub fn runs_on(what: &str) -> &'static str {
    if what == "point-on-surface" {
        "patch"
    } else {
        "open curve"
    }
}
