//! From a parsed model file to a [`MechanismBuilder`], checking everything that can be pinned to
//! a place in the file: names (with suggestions), duplicates, numbers, axes, mass and inertia,
//! self-joints, function parameters. What only the mechanism can judge (DOF, assembly) is
//! checked later, and mapped back to the element's line through [`Spans`].

mod coupler;

pub use coupler::TYPES as COUPLER_TYPES;

use crate::diag::{did_you_mean, list, Error, Source};
use crate::file::{
    AnalysisSection, BodySection, DriverSection, ForceSection, FunctionSpec, InertiaSpec,
    JointSection, ModelFile, Name, Num, OrientationSpec, Vec3,
};
use crate::units::UnitSystem;
use cardan_constraints::drivers::POSE_ROWS;
use cardan_constraints::expression::{self, Expression};
use cardan_constraints::{JointKind, RotationOrder, TimeFunction, KINDS};
use cardan_dynamics::{
    Dopri5Options, Force, Frame, GeneralizedAlphaOptions, Integrator, PointRef, VectorFunction,
};
use cardan_mechanism::{
    pose_row_name, Axis, Body, DriverSpec, DriverTarget, ElementKind, JointSpec, KinematicOptions,
    MechanismBuilder, Orientation, PoseTarget, Quantity, Site, GROUND,
};
use nalgebra::{Matrix3, Vector3};
use std::collections::{BTreeMap, HashMap};
use std::fmt::Display;
use std::ops::Range;
use toml::Spanned;

/// Most (output times) × (moving bodies + their points) a run may store: 10⁷, at most about
/// 2.6 GB of results.
pub const MAX_STORED_FRAMES: usize = 10_000_000;

/// Where each named element is defined, to place errors found after parsing.
#[derive(Debug, Clone, Default)]
pub struct Spans {
    /// Body name → span of its `[[body]]` name value.
    pub bodies: HashMap<String, Range<usize>>,
    /// Joint name → span.
    pub joints: HashMap<String, Range<usize>>,
    /// Driver name → span.
    pub drivers: HashMap<String, Range<usize>>,
    /// Coupler name → span.
    pub couplers: HashMap<String, Range<usize>>,
    /// Force name → span.
    pub forces: HashMap<String, Range<usize>>,
    /// Span of `[analysis] kind` (or of the file start).
    pub analysis: Range<usize>,
    /// Span of the `[[driver]]` array (first driver name) for driver-count messages.
    pub first_driver: Option<Range<usize>>,
}

impl Spans {
    /// The span in `text` (the model file) of what a builder error is about: the value of the
    /// key `site.field`, or the quoted name `site.value`, inside the element's section; else
    /// the element's name.
    pub fn locate(&self, text: &str, site: &Site) -> Option<Range<usize>> {
        let table = match site.kind {
            ElementKind::Body => &self.bodies,
            ElementKind::Joint => &self.joints,
            ElementKind::Driver => &self.drivers,
            ElementKind::Coupler => &self.couplers,
            ElementKind::Force => &self.forces,
        };
        let name = table.get(&site.name)?.clone();
        // The section: from its header to the next header.
        let start = text[..name.start].rfind("\n[").map_or(0, |k| k + 1);
        let end = text[name.end..]
            .find("\n[")
            .map_or(text.len(), |k| name.end + k);
        let section = &text[start..end];
        let found = site
            .field
            .as_deref()
            .and_then(|f| key_value_span(section, f))
            .or_else(|| {
                let v = format!("\"{}\"", site.value.as_deref()?);
                section.find(&v).map(|k| k..k + v.len())
            });
        Some(found.map_or(name, |r| start + r.start..start + r.end))
    }

    /// The span of a joint or driver or body by name.
    pub fn element(&self, name: &str) -> Option<Range<usize>> {
        self.joints
            .get(name)
            .or_else(|| self.drivers.get(name))
            .or_else(|| self.couplers.get(name))
            .or_else(|| self.bodies.get(name))
            .or_else(|| self.forces.get(name))
            .cloned()
    }
}

/// What to write.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outputs {
    /// (body, point).
    pub points: Vec<(String, String)>,
    /// Joint names.
    pub joints: Vec<String>,
    /// Body names.
    pub bodies: Vec<String>,
    /// Dynamic: joints whose reactions are written (`None`: all joints).
    pub reactions: Option<Vec<String>>,
    /// Dynamic and inverse dynamics: write the energy table (with power, work and balance).
    pub energy: bool,
}

/// What `[analysis] kind` asks for, with what only that kind has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnalysisKind {
    /// Positions (velocities, accelerations) of a fully driven mechanism over the time grid.
    Kinematic,
    /// Driver efforts and joint reactions of a fully driven mechanism along its kinematics.
    InverseDynamics,
    /// The motion the forces produce, by the integrator with its options.
    Dynamic(Integrator),
    /// An equilibrium (static), equilibria along the grid (quasi-static), or the modes about
    /// one (modal).
    Static(StaticKind),
}

impl AnalysisKind {
    /// The kind's name in the model file (`kind = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            AnalysisKind::Kinematic => "kinematic",
            AnalysisKind::InverseDynamics => "inverse_dynamics",
            AnalysisKind::Dynamic(_) => "dynamic",
            AnalysisKind::Static(k) => k.name(),
        }
    }
}

/// The analysis requested.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    /// The kind and its integrator or static kind.
    pub kind: AnalysisKind,
    /// Start time \[s\].
    pub t_start: f64,
    /// End time \[s\].
    pub t_end: f64,
    /// Number of steps. A static or modal analysis has one time: t_start = t_end = the time
    /// the drivers are held, steps = 0.
    pub steps: usize,
    /// What to write.
    pub outputs: Outputs,
    /// Write SVG plots.
    pub plots: bool,
    /// Kinematic and inverse dynamics: the position solves' tolerance on the scaled residual
    /// (`position_tolerance`); static kinds: the equilibrium's (`equilibrium_tolerance`).
    pub tolerance: f64,
    /// Static kinds: equal load increments tried first.
    pub load_steps: usize,
    /// Modal, and dynamic with `linearize_at`: the force elements that are the inputs of the
    /// state-space model.
    pub inputs: Vec<String>,
    /// Dynamic: the time of the state about which the run is linearized (in [t_start, t_end]).
    pub linearize_at: Option<f64>,
    /// Modal: how many of the lowest modes (`None`: all on the dense path,
    /// [`DEFAULT_SPARSE_MODES`] on the sparse path).
    pub modes: Option<usize>,
}

/// Modes of a modal analysis on the sparse path (large models) without `modes = ...`.
pub const DEFAULT_SPARSE_MODES: usize = 10;

/// The static analyses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticKind {
    /// The equilibrium at one time.
    Static,
    /// The equilibrium at each time of the grid, drivers moving.
    QuasiStatic,
    /// The equilibrium at one time and the vibration modes about it.
    Modal,
}

impl StaticKind {
    /// The kind's name in the model file.
    pub fn name(self) -> &'static str {
        match self {
            StaticKind::Static => "static",
            StaticKind::QuasiStatic => "quasi_static",
            StaticKind::Modal => "modal",
        }
    }
}

impl Analysis {
    /// The integrator of a dynamic analysis.
    pub fn integrator(&self) -> Option<Integrator> {
        match self.kind {
            AnalysisKind::Dynamic(i) => Some(i),
            _ => None,
        }
    }

    /// The static kind of a static, quasi-static or modal analysis.
    pub fn statics(&self) -> Option<StaticKind> {
        match self.kind {
            AnalysisKind::Static(k) => Some(k),
            _ => None,
        }
    }

    /// Whether the analysis needs forces and masses (every kind but kinematic).
    pub fn has_forces(&self) -> bool {
        self.kind != AnalysisKind::Kinematic
    }

    /// The time grid t_start + k (t_end − t_start) / steps, k = 0..=steps.
    pub fn times(&self) -> Vec<f64> {
        let h = (self.t_end - self.t_start) / self.steps as f64;
        (0..=self.steps)
            .map(|k| {
                if k == self.steps {
                    self.t_end
                } else {
                    self.t_start + k as f64 * h
                }
            })
            .collect()
    }
}

/// A model file turned into a builder plus everything the commands need.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// `[model] name`.
    pub name: String,
    /// `[model] units`: the inputs were converted from them, the outputs are written in them.
    pub units: UnitSystem,
    /// The mechanism.
    pub builder: MechanismBuilder,
    /// Element locations.
    pub spans: Spans,
    /// `[analysis]`, if present.
    pub analysis: Option<Analysis>,
    /// Joint names and kinds, in file order (for `check`).
    pub joints: Vec<(String, JointKind, String, String)>,
    /// Body names with mass, in file order.
    pub bodies: Vec<(String, Option<f64>)>,
    /// Driver names and what they drive, in file order.
    pub drivers: Vec<(String, String)>,
    /// The drivers' time functions and the quantities of their values (an angle for a rotation
    /// driver, a length for the others), in file order (as `drivers`).
    pub driver_functions: Vec<(TimeFunction, Quantity)>,
    /// Force elements for dynamic analysis: `[model] gravity` first, then `[[force]]` in file
    /// order.
    pub forces: Vec<Force>,
    /// Initial body velocities given in the file (dynamic analysis), in file order.
    pub velocities: Vec<BodyVelocity>,
}

/// The initial velocity of one body as given in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyVelocity {
    /// Body name.
    pub body: String,
    /// Velocity of the body origin (centre of mass), global [m/s].
    pub velocity: Vector3<f64>,
    /// Angular velocity [rad/s].
    pub omega: Vector3<f64>,
    /// `omega` is in body components (`angular_velocity_local`), else global.
    pub omega_local: bool,
}

/// Points and vectors of one body, with the span of each name.
#[derive(Default)]
struct Features {
    points: BTreeMap<String, (Range<usize>, Vector3<f64>)>,
    vectors: BTreeMap<String, (Range<usize>, Vector3<f64>)>,
}

struct Ctx<'a> {
    src: &'a Source,
    /// The file's `[model] units`: every number is converted to SI as it is read.
    units: UnitSystem,
}

impl Ctx<'_> {
    fn err(&self, span: Range<usize>, m: impl Into<String>) -> Error {
        self.src.error_at(span, m)
    }

    /// A finite, not subnormal number within the SI magnitude limit of its quantity
    /// (`cardan_mechanism::sanity::Quantity`, the builder's limits), converted to SI from the
    /// file's units (the limit applies to the SI value).
    fn num(&self, n: &Num, what: impl Display, q: Quantity) -> Result<f64, Error> {
        let v = *n.get_ref();
        if v != 0.0 && v.abs() < f64::MIN_POSITIVE {
            return Err(self.err(
                n.span(),
                format!(
                    "{what} = {v:e} is subnormal (0 < |value| < {:e}): it has no meaning in SI units \
                     and loses precision in any arithmetic; write 0 or a meaningful value",
                    f64::MIN_POSITIVE
                ),
            ));
        }
        let factor = self.units.to_si(q);
        if factor == 1.0 {
            q.check(&what, v).map_err(|m| self.err(n.span(), m))?;
            return Ok(v);
        }
        let si = v * factor;
        if q.check(&what, si).is_err() {
            let (unit, _) = self.units.unit(q.unit());
            let what = format!(
                "{what} ({} {unit})",
                cardan_mechanism::sanity::scientific(v)
            );
            q.check(&what, si).map_err(|m| self.err(n.span(), m))?;
        }
        Ok(si)
    }

    /// The three components of `v`; `what` names the vector in a message (formatted only then).
    fn vec3(&self, v: &Vec3, what: impl Display, q: Quantity) -> Result<Vector3<f64>, Error> {
        let a = v.get_ref();
        Ok(Vector3::new(
            self.num(&a[0], format_args!("{what} x"), q)?,
            self.num(&a[1], format_args!("{what} y"), q)?,
            self.num(&a[2], format_args!("{what} z"), q)?,
        ))
    }

    fn direction(&self, v: &Vec3, what: impl Display) -> Result<Vector3<f64>, Error> {
        let d = self.vec3(v, &what, Quantity::Direction)?;
        if d.norm() < 1e-12 {
            return Err(self.err(
                v.span(),
                format!(
                    "{what} has zero length ({}); a direction needs a nonzero vector",
                    fmt_vec(&d)
                ),
            ));
        }
        Ok(d)
    }

    fn raw_num(
        &self,
        span: Range<usize>,
        v: f64,
        what: impl Display,
        q: Quantity,
    ) -> Result<f64, Error> {
        self.num(&Spanned::new(span, v), what, q)
    }
}

/// The file's `[model] units` (default SI).
///
/// # Errors
/// A unit system cardan does not have, at the key.
pub fn model_units(src: &Source, file: &ModelFile) -> Result<UnitSystem, Error> {
    let Some(u) = &file.model.get_ref().units else {
        return Ok(UnitSystem::Si);
    };
    UnitSystem::parse(u.get_ref()).ok_or_else(|| {
        src.error_at(
            u.span(),
            format!(
                "units = \"{}\" is not a unit system of cardan: write units = \"SI\" (m, kg, s, \
                 N, N m) or units = \"mm\" (mm, kg, s, N, N mm)",
                u.get_ref()
            ),
        )
    })
}

/// The span of the value of `key = value` on a line of `section` (up to a comment or the end of
/// the line), if the key is there.
fn key_value_span(section: &str, key: &str) -> Option<Range<usize>> {
    let mut at = 0;
    for line in section.split_inclusive('\n') {
        let body = line.trim_start();
        let indent = line.len() - body.len();
        if let Some(rest) = body.strip_prefix(key) {
            let after = rest.trim_start();
            if let Some(value) = after.strip_prefix('=') {
                let value_start = at + indent + key.len() + (rest.len() - after.len()) + 1;
                let v = value.trim_start();
                let v_start = value_start + (value.len() - v.len());
                let v = v.split(" #").next().unwrap_or(v).trim_end();
                return Some(v_start..v_start + v.len().max(1));
            }
        }
        at += line.len();
    }
    None
}

/// Formats a vector as "(x, y, z)".
pub fn fmt_vec(v: &Vector3<f64>) -> String {
    let f = |x: f64| {
        if x == 0.0 || (1e-4..1e9).contains(&x.abs()) {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    };
    format!("({}, {}, {})", f(v.x), f(v.y), f(v.z))
}

/// Every joint type name a model file accepts (names and aliases, from the kind table).
fn joint_types() -> impl Iterator<Item = &'static str> + Clone {
    KINDS
        .iter()
        .flat_map(|k| std::iter::once(k.name).chain(k.aliases.iter().copied()))
}

const DRIVER_TYPES: &[&str] = &[
    "rotation",
    "translation",
    "distance",
    "coordinate",
    "general_motion",
];
const FUNCTION_KINDS: &[&str] = &TimeFunction::KINDS;

/// Turns a parsed file into a builder, checking everything that has a place in the file.
pub fn load(src: &Source, file: &ModelFile) -> Result<Loaded, Error> {
    let units = model_units(src, file)?;
    let cx = Ctx { src, units };
    let mut spans = Spans::default();
    let mut builder = MechanismBuilder::new();

    let model = file.model.get_ref();
    let name = model.name.get_ref().trim().to_string();
    if let Some(why) = unusable_directory_name(&name) {
        return Err(cx.err(
            model.name.span(),
            format!("model name {why}; it names the output directory out/<name>/"),
        ));
    }
    let mut forces = Vec::new();
    if let Some(g) = &model.gravity {
        forces.push(Force::gravity(cx.vec3(
            g,
            "gravity",
            Quantity::Acceleration,
        )?));
    }

    // Ground features.
    let mut features: HashMap<String, Features> = HashMap::new();
    let mut ground = Features::default();
    if let Some(g) = &file.ground {
        for (k, v) in &g.get_ref().points {
            let p = cx.vec3(
                v,
                format_args!("ground point \"{}\"", k.get_ref()),
                Quantity::Length,
            )?;
            ground.points.insert(k.get_ref().clone(), (k.span(), p));
            builder.point(GROUND, k.get_ref(), p);
        }
        for (k, v) in &g.get_ref().vectors {
            let d = cx.direction(v, format_args!("ground vector \"{}\"", k.get_ref()))?;
            ground.vectors.insert(k.get_ref().clone(), (k.span(), d));
            builder.vector(GROUND, k.get_ref(), d);
        }
    }
    features.insert(GROUND.to_string(), ground);

    // Bodies.
    let mut bodies = Vec::new();
    let mut velocities = Vec::new();
    let mut body_order: Vec<String> = vec![GROUND.into()];
    for b in &file.body {
        let b = b.get_ref();
        let bname = b.name.get_ref().clone();
        if bname == GROUND {
            return Err(cx.err(
                b.name.span(),
                "\"ground\" is the built-in fixed body; give the moving body another name \
                 (ground points and vectors go in [ground])",
            ));
        }
        if bname.trim().is_empty() {
            return Err(cx.err(b.name.span(), "body name must not be empty"));
        }
        if let Some(first) = spans.bodies.get(&bname) {
            let l = src.location(first.start);
            return Err(cx.err(
                b.name.span(),
                format!(
                    "duplicate body name \"{bname}\" (first defined at line {})",
                    l.line
                ),
            ));
        }
        spans.bodies.insert(bname.clone(), b.name.span());
        let (body, f) = load_body(&cx, b)?;
        if let Some(v) = body_velocity(&cx, b)? {
            velocities.push(v);
        }
        for (n, (_, v)) in &f.points {
            builder.point(&bname, n, *v);
        }
        for (n, (_, v)) in &f.vectors {
            builder.vector(&bname, n, *v);
        }
        bodies.push((bname.clone(), body.mass));
        builder.body(body);
        features.insert(bname.clone(), f);
        body_order.push(bname);
    }

    let resolver = Resolver {
        cx: &cx,
        features: &features,
        order: &body_order,
    };

    // Joints.
    let mut joints = Vec::new();
    let mut joint_kinds: HashMap<String, JointKind> = HashMap::new();
    for j in &file.joint {
        let j = j.get_ref();
        let jname = j.name.get_ref().clone();
        check_unique_element(&cx, &spans, &j.name, "joint")?;
        spans.joints.insert(jname.clone(), j.name.span());
        let spec = load_joint(&resolver, j)?;
        joints.push((
            jname.clone(),
            spec.kind,
            spec.body_i.clone(),
            spec.body_j.clone(),
        ));
        joint_kinds.insert(jname, spec.kind);
        builder.joint(spec);
    }

    // Couplers.
    for c in &file.coupler {
        let c = c.get_ref();
        check_unique_element(&cx, &spans, &c.name, "coupler")?;
        spans
            .couplers
            .insert(c.name.get_ref().clone(), c.name.span());
        builder.coupler(coupler::load_coupler(&cx, c)?);
    }

    // Drivers.
    let mut drivers = Vec::new();
    let mut driver_functions = Vec::new();
    for d in &file.driver {
        let d = d.get_ref();
        check_unique_element(&cx, &spans, &d.name, "driver")?;
        spans
            .drivers
            .insert(d.name.get_ref().clone(), d.name.span());
        if spans.first_driver.is_none() {
            spans.first_driver = Some(d.name.span());
        }
        let (spec, what) = load_driver(&resolver, d)?;
        match &spec.target {
            // A general motion is six driver rows: each is listed, located and checked.
            DriverTarget::Pose(t) => {
                for (k, f) in t.functions.iter().enumerate() {
                    let row = pose_row_name(&spec.name, k);
                    spans.drivers.insert(row.clone(), d.name.span());
                    drivers.push((row, format!("{} of the {what}", POSE_ROWS[k])));
                    let q = if k < 3 {
                        Quantity::Length
                    } else {
                        Quantity::Angle
                    };
                    driver_functions.push((f.clone(), q));
                }
            }
            target => {
                drivers.push((d.name.get_ref().clone(), what));
                let q = match target {
                    DriverTarget::JointRotation { .. } => Quantity::Angle,
                    _ => Quantity::Length,
                };
                driver_functions.push((spec.function.clone(), q));
            }
        }
        builder.driver(spec);
    }

    // Forces.
    for f in &file.force {
        let f = f.get_ref();
        check_unique_element(&cx, &spans, &f.name, "force")?;
        spans.forces.insert(f.name.get_ref().clone(), f.name.span());
        forces.push(load_force(&resolver, f, &joint_kinds, &spans)?);
    }

    // Analysis.
    spans.analysis = 0..0;
    let analysis = match &file.analysis {
        Some(a) => {
            spans.analysis = a.get_ref().kind.span();
            let mut an = load_analysis(&resolver, a.get_ref(), &spans)?;
            an.inputs = load_inputs(&cx, a.get_ref(), &an, &forces, &drivers)?;
            Some(an)
        }
        None => None,
    };

    Ok(Loaded {
        name,
        units,
        builder,
        spans,
        analysis,
        joints,
        bodies,
        drivers,
        driver_functions,
        forces,
        velocities,
    })
}

/// Why `name` cannot name one output directory, if it cannot.
fn unusable_directory_name(name: &str) -> Option<String> {
    if name.is_empty() {
        return Some("must not be empty".into());
    }
    match name {
        "." => return Some("\".\" is the output directory itself (out/./ is out/)".into()),
        ".." => return Some("\"..\" is the parent of the output directory (out/../)".into()),
        _ => {}
    }
    if let Some(c) = name.chars().find(|c| matches!(c, '/' | '\\')) {
        return Some(format!(
            "\"{name}\" contains the path separator '{c}', which would make nested directories"
        ));
    }
    if let Some(c) = name.chars().find(|c| c.is_control()) {
        return Some(format!(
            "{:?} contains a control character (U+{:04X}); write the name on one line, \
             without tabs or other control characters",
            name,
            u32::from(c)
        ));
    }
    None
}

fn check_unique_element(cx: &Ctx, spans: &Spans, name: &Name, what: &str) -> Result<(), Error> {
    let n = name.get_ref();
    if n.trim().is_empty() {
        return Err(cx.err(name.span(), format!("{what} name must not be empty")));
    }
    let prev = spans
        .joints
        .get(n)
        .map(|s| ("joint", s))
        .or_else(|| spans.drivers.get(n).map(|s| ("driver", s)))
        .or_else(|| spans.couplers.get(n).map(|s| ("coupler", s)))
        .or_else(|| spans.forces.get(n).map(|s| ("force", s)));
    if let Some((kind, s)) = prev {
        let l = cx.src.location(s.start);
        return Err(cx.err(
            name.span(),
            format!(
                "duplicate name \"{n}\": a {kind} of that name is defined at line {} \
                 (joints, couplers, drivers and forces share one namespace)",
                l.line
            ),
        ));
    }
    Ok(())
}

/// The rotation matrix of an `orientation = { ... }` table (for the animation's geometry items),
/// with the checks and messages of a body's orientation.
///
/// # Errors
/// An input error located at the table (no or several forms, zero axes, bad numbers).
pub(crate) fn orientation_matrix(
    src: &Source,
    o: &Spanned<OrientationSpec>,
) -> Result<Matrix3<f64>, Error> {
    // Angles and directions only: the same in every unit system.
    let cx = Ctx {
        src,
        units: UnitSystem::Si,
    };
    orientation(&cx, o).map(|(_, a)| a)
}

fn orientation(
    cx: &Ctx,
    o: &Spanned<OrientationSpec>,
) -> Result<(Orientation, Matrix3<f64>), Error> {
    let s = o.get_ref();
    let given: Vec<&str> = [
        ("euler_parameters", s.euler_parameters.is_some()),
        ("axis/angle", s.axis.is_some() || s.angle.is_some()),
        ("euler313", s.euler313.is_some()),
        ("euler123", s.euler123.is_some()),
        ("z/x", s.z.is_some() || s.x.is_some()),
    ]
    .into_iter()
    .filter(|(_, g)| *g)
    .map(|(n, _)| n)
    .collect();
    if given.len() != 1 {
        return Err(cx.err(
            o.span(),
            format!(
                "orientation needs exactly one form: euler_parameters = [e0, e1, e2, e3], \
                 axis = [..] with angle = .., euler313 = [φ, θ, ψ], euler123 = [φ, θ, ψ], or z = [..] \
                 (with optional x = [..]); found {}",
                if given.is_empty() { "none".to_string() } else { given.join(", ") }
            ),
        ));
    }
    let bad = |e: cardan_eulerparam::EulerParamError| cx.err(o.span(), format!("orientation: {e}"));
    let orient = if let Some(ep) = &s.euler_parameters {
        let a = ep.get_ref();
        let mut v = [0.0; 4];
        for k in 0..4 {
            v[k] = cx.num(
                &a[k],
                format_args!("euler_parameters[{k}]"),
                Quantity::Direction,
            )?;
        }
        let n = (v.iter().map(|x| x * x).sum::<f64>()).sqrt();
        if (n - 1.0).abs() > 1e-6 {
            return Err(cx.err(
                ep.span(),
                format!(
                    "euler_parameters must have unit length (e0² + e1² + e2² + e3² = 1); |p| = {n}"
                ),
            ));
        }
        Orientation::EulerParams(v)
    } else if s.axis.is_some() || s.angle.is_some() {
        let (Some(axis), Some(angle)) = (&s.axis, &s.angle) else {
            return Err(cx.err(
                o.span(),
                "axis-angle orientation needs both axis = [x, y, z] and angle = θ [rad]",
            ));
        };
        let axis = cx.direction(axis, "orientation axis")?;
        let angle = cx.num(angle, "orientation angle", Quantity::Angle)?;
        Orientation::AxisAngle { axis, angle }
    } else if let Some(e) = &s.euler313 {
        let v = cx.vec3(e, "euler313", Quantity::Angle)?;
        Orientation::Euler313([v.x, v.y, v.z])
    } else if let Some(e) = &s.euler123 {
        let v = cx.vec3(e, "euler123", Quantity::Angle)?;
        Orientation::Euler123([v.x, v.y, v.z])
    } else {
        let Some(z) = &s.z else {
            return Err(cx.err(
                o.span(),
                "orientation by axes needs z = [..] (x = [..] is optional)",
            ));
        };
        let zv = cx.direction(z, "orientation z")?;
        let x = match &s.x {
            Some(x) => Some(cx.direction(x, "orientation x")?),
            None => None,
        };
        Orientation::Axes { z: zv, x }
    };
    // The conversion is the builder's own (`Orientation::euler_params`); errors located here.
    let p = orient.euler_params().map_err(bad)?;
    Ok((orient, p.a()))
}

fn load_body(cx: &Ctx, b: &BodySection) -> Result<(Body, Features), Error> {
    let name = b.name.get_ref();
    let mut body = Body::new(name.clone());
    if let Some(m) = &b.mass {
        // Positive: checked by the builder (located here through its error's site).
        let m_v = cx.num(m, format_args!("mass of body \"{name}\""), Quantity::Mass)?;
        body = body.mass(m_v);
    }
    if let Some(i) = &b.inertia {
        let mut j = match i.get_ref() {
            InertiaSpec::Matrix(m) => Matrix3::from_fn(|r, c| m[r][c]),
            InertiaSpec::Diag { diag } => Matrix3::from_diagonal(&Vector3::from(*diag)),
        };
        for v in j.iter_mut() {
            // Checked and converted to SI (kg m²).
            *v = cx.raw_num(
                i.span(),
                *v,
                format_args!("inertia of body \"{name}\""),
                Quantity::Inertia,
            )?;
        }
        // Symmetric, positive definite, triangle inequality: checked by the builder.
        body = body.inertia(j);
    }
    let position = match &b.position {
        Some(p) => cx.vec3(
            p,
            format_args!("position of body \"{name}\""),
            Quantity::Length,
        )?,
        None => Vector3::zeros(),
    };
    body = body.position(position);
    let mut a = Matrix3::identity();
    if let Some(o) = &b.orientation {
        let (orient, a_) = orientation(cx, o)?;
        a = a_;
        body = body.orientation(orient);
    }

    let mut f = Features::default();
    // One named feature (point or vector) into its map; a second definition of the name is an
    // error located at the repeat, naming the line of the first.
    let add = |what: &str,
               map: &mut BTreeMap<String, (Range<usize>, Vector3<f64>)>,
               k: &Name,
               v: Vector3<f64>|
     -> Result<(), Error> {
        if let Some((s, _)) = map.get(k.get_ref()) {
            let l = cx.src.location(s.start);
            return Err(cx.err(
                k.span(),
                format!(
                    "duplicate {what} \"{}\" on body \"{name}\" (also defined at line {})",
                    k.get_ref(),
                    l.line
                ),
            ));
        }
        map.insert(k.get_ref().clone(), (k.span(), v));
        Ok(())
    };
    let at = a.transpose();
    for (k, v) in &b.points {
        let p = cx.vec3(
            v,
            format_args!("point \"{}\" of body \"{name}\"", k.get_ref()),
            Quantity::Length,
        )?;
        add("point", &mut f.points, k, p)?;
    }
    for (k, v) in &b.global_points {
        let g = cx.vec3(
            v,
            format_args!("point \"{}\" of body \"{name}\"", k.get_ref()),
            Quantity::Length,
        )?;
        add("point", &mut f.points, k, at * (g - position))?;
    }
    for (k, v) in &b.vectors {
        let d = cx.direction(
            v,
            format_args!("vector \"{}\" of body \"{name}\"", k.get_ref()),
        )?;
        add("vector", &mut f.vectors, k, d)?;
    }
    for (k, v) in &b.global_vectors {
        let d = cx.direction(
            v,
            format_args!("vector \"{}\" of body \"{name}\"", k.get_ref()),
        )?;
        add("vector", &mut f.vectors, k, at * d)?;
    }
    Ok((body, f))
}

struct Resolver<'a> {
    cx: &'a Ctx<'a>,
    features: &'a HashMap<String, Features>,
    order: &'a [String],
}

impl Resolver<'_> {
    fn body<'n>(&self, n: &'n Name, owner: &str) -> Result<&'n str, Error> {
        let b = n.get_ref();
        if self.features.contains_key(b) {
            return Ok(b);
        }
        let hint = did_you_mean(b, self.order.iter().map(String::as_str));
        Err(self.cx.err(
            n.span(),
            format!(
                "{owner}: unknown body \"{b}\"{hint} (bodies: {})",
                list(self.order.iter().map(String::as_str))
            ),
        ))
    }

    fn feature(&self, body: &str, n: &Name, owner: &str, points: bool) -> Result<(), Error> {
        let f = &self.features[body];
        let map = if points { &f.points } else { &f.vectors };
        let what = if points { "point" } else { "vector" };
        if map.contains_key(n.get_ref()) {
            return Ok(());
        }
        let hint = did_you_mean(n.get_ref(), map.keys().map(String::as_str));
        let hint = if hint.is_empty() && !points {
            // A vector name that is a point's name, or a common slip.
            did_you_mean(n.get_ref(), map.keys().map(String::as_str))
        } else {
            hint
        };
        Err(self.cx.err(
            n.span(),
            format!(
                "{owner}: body \"{body}\" has no {what} \"{}\"{hint} ({what}s of \"{body}\": {})",
                n.get_ref(),
                list(map.keys().map(String::as_str))
            ),
        ))
    }

    fn point_value(&self, body: &str, n: &str) -> Vector3<f64> {
        self.features[body].points[n].1
    }
}

fn load_joint(r: &Resolver, j: &JointSection) -> Result<JointSpec, Error> {
    let cx = r.cx;
    let name = j.name.get_ref();
    let owner = format!("joint \"{name}\"");
    let Some(kind) = JointKind::from_name(j.kind.get_ref()) else {
        let hint = did_you_mean(j.kind.get_ref(), joint_types());
        return Err(cx.err(
            j.kind.span(),
            format!(
                "{owner}: unknown joint type \"{}\"{hint} (types: {})",
                j.kind.get_ref(),
                list(KINDS.iter().map(|k| k.name))
            ),
        ));
    };
    // Bodies, points and vectors are resolved by the builder; its errors are located at the key
    // or the unknown name (`Spans::locate`).
    let (bi, bj) = (j.body_i.get_ref().as_str(), j.body_j.get_ref().as_str());
    let mut spec = JointSpec::new(
        name.clone(),
        kind,
        (bi, j.point_i.get_ref()),
        (bj, j.point_j.get_ref()),
    );
    let info = kind.info();
    // Which of the axes the kind takes is checked by the builder (located by `Spans::locate`);
    // here only the pairing: both sides, or axis_i alone for a kind that uses frame i only.
    let both = info.axes.on_j();
    match (&j.axis_i, &j.axis_j) {
        (Some(ai), Some(aj)) => spec = spec.axes(ai.get_ref(), aj.get_ref()),
        (Some(ai), None) if !both => spec = spec.axis_i(ai.get_ref()),
        (None, None) if !info.axes.required() => {}
        (None, Some(_)) | (Some(_), None) | (None, None) => {
            let keys = if both { "axis_i and axis_j" } else { "axis_i" };
            return Err(cx.err(
                j.name.span(),
                format!(
                    "{owner}: a {} joint needs {keys} (names of vectors on body \"{bi}\"{})",
                    kind.name(),
                    if both {
                        format!(" and body \"{bj}\"")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
    }
    match (&j.x_axis_i, &j.x_axis_j) {
        (Some(xi), Some(xj)) => spec = spec.x_axes(xi.get_ref(), xj.get_ref()),
        (Some(xi), None) if !both => spec = spec.x_axis_i(xi.get_ref()),
        (None, None) => {}
        (Some(x), None) | (None, Some(x)) => {
            return Err(cx.err(
                x.span(),
                format!("{owner}: give both x_axis_i and x_axis_j, or neither"),
            ))
        }
    }
    if let Some(l) = &j.length {
        // Whether the kind takes a length, and its sign: checked by the builder.
        let v = cx.num(l, format_args!("{owner} length"), Quantity::Length)?;
        spec = spec.length(v);
    }
    if let Some(h) = &j.offset {
        spec = spec.offset(cx.num(h, format_args!("{owner} offset"), Quantity::Length)?);
    }
    if let Some(a) = &j.angle {
        spec = spec.angle(cx.num(a, format_args!("{owner} angle"), Quantity::Angle)?);
    }
    Ok(spec)
}

fn missing(cx: &Ctx, span: Range<usize>, owner: &str, key: &str, why: &str) -> Error {
    cx.err(span, format!("{owner}: missing key \"{key}\" ({why})"))
}

/// A time function whose values are `value_q` (an angle for a rotation driver, a length for the
/// other drivers, a force or torque for force components).
fn load_function(
    cx: &Ctx,
    f: &Spanned<FunctionSpec>,
    owner: &str,
    value_q: Quantity,
) -> Result<TimeFunction, Error> {
    let s = f.get_ref();
    // The quantity of each key: times, the frequency and the phase have theirs; a polynomial
    // coefficient c_k has the unit of the value / s^k, so it is only checked to be finite.
    let quantity = |key: &str| match key {
        "t0" | "t1" | "times" => Quantity::Time,
        "frequency" => Quantity::Frequency,
        "phase" => Quantity::Angle,
        "coefficients" => Quantity::Unbounded,
        _ => value_q,
    };
    let kind = s.kind.get_ref().as_str();
    let span = f.span();
    let req = |v: &Option<Num>, key: &str| -> Result<f64, Error> {
        match v {
            Some(n) => cx.num(n, format_args!("{owner}: function {key}"), quantity(key)),
            None => Err(missing(
                cx,
                span.clone(),
                owner,
                key,
                &format!("a {kind} function needs it"),
            )),
        }
    };
    let opt = |v: &Option<Num>, key: &str, d: f64| -> Result<f64, Error> {
        match v {
            Some(n) => cx.num(n, format_args!("{owner}: function {key}"), quantity(key)),
            None => Ok(d),
        }
    };
    let list_of = |v: &Option<Spanned<Vec<Num>>>, key: &str| -> Result<Vec<f64>, Error> {
        match v {
            Some(l) => l
                .get_ref()
                .iter()
                .enumerate()
                .map(|(k, n)| {
                    let v = cx.num(
                        n,
                        format_args!("{owner}: function {key}[{k}]"),
                        quantity(key),
                    )?;
                    // c_k has the unit of the value / s^k: converted as the value.
                    Ok(if key == "coefficients" {
                        v * cx.units.to_si(value_q)
                    } else {
                        v
                    })
                })
                .collect(),
            None => Err(missing(
                cx,
                span.clone(),
                owner,
                key,
                &format!("a {kind} function needs it"),
            )),
        }
    };
    // Keys that belong to another kind are an error, so a typo in kind does not go unnoticed.
    let allowed: &[&str] = match kind {
        "constant" => &["value"],
        "polynomial" => &["coefficients"],
        "harmonic" => &["amplitude", "frequency", "phase", "offset"],
        "ramp" => &["t0", "t1", "f0", "f1"],
        "spline" => &["times", "values"],
        "expression" => &["text"],
        _ => {
            let hint = did_you_mean(kind, FUNCTION_KINDS.iter().copied());
            return Err(cx.err(
                s.kind.span(),
                format!(
                    "{owner}: unknown function kind \"{kind}\"{hint} (kinds: {})",
                    list(FUNCTION_KINDS.iter().copied())
                ),
            ));
        }
    };
    let present: Vec<(&str, bool)> = vec![
        ("value", s.value.is_some()),
        ("coefficients", s.coefficients.is_some()),
        ("amplitude", s.amplitude.is_some()),
        ("frequency", s.frequency.is_some()),
        ("phase", s.phase.is_some()),
        ("offset", s.offset.is_some()),
        ("t0", s.t0.is_some()),
        ("t1", s.t1.is_some()),
        ("f0", s.f0.is_some()),
        ("f1", s.f1.is_some()),
        ("times", s.times.is_some()),
        ("values", s.values.is_some()),
        ("text", s.text.is_some()),
    ];
    if let Some((k, _)) = present.iter().find(|(k, p)| *p && !allowed.contains(k)) {
        return Err(cx.err(
            span,
            format!(
                "{owner}: a {kind} function does not take \"{k}\" (it takes {})",
                list(allowed.iter().copied())
            ),
        ));
    }
    let tf = match kind {
        "constant" => TimeFunction::Constant(req(&s.value, "value")?),
        "polynomial" => {
            let c = list_of(&s.coefficients, "coefficients")?;
            if c.is_empty() {
                return Err(cx.err(
                    span,
                    format!("{owner}: polynomial needs at least one coefficient"),
                ));
            }
            TimeFunction::Polynomial(c)
        }
        "harmonic" => TimeFunction::Harmonic {
            amplitude: req(&s.amplitude, "amplitude")?,
            frequency: req(&s.frequency, "frequency")?,
            phase: opt(&s.phase, "phase", 0.0)?,
            offset: opt(&s.offset, "offset", 0.0)?,
        },
        "ramp" => TimeFunction::Ramp {
            t0: req(&s.t0, "t0")?,
            t1: req(&s.t1, "t1")?,
            f0: req(&s.f0, "f0")?,
            f1: req(&s.f1, "f1")?,
        },
        "expression" => match &s.text {
            Some(text) => in_si(expression(cx, text, owner)?, cx.units.to_si(value_q)),
            None => return Err(missing(cx, span, owner, "text", "an expression needs it")),
        },
        _ => {
            let t = list_of(&s.times, "times")?;
            let v = list_of(&s.values, "values")?;
            TimeFunction::spline(t, v).map_err(|e| cx.err(span.clone(), format!("{owner}: {e}")))?
        }
    };
    tf.validate()
        .map_err(|e| cx.err(span, format!("{owner}: {e}")))?;
    Ok(tf)
}

/// A general_motion driver: frames i and j (bodies, origins, optional axes), the rotation
/// sequence and the six laws (three translations, three angles).
fn load_general_motion(r: &Resolver, d: &DriverSection) -> Result<(DriverSpec, String), Error> {
    let cx = r.cx;
    let name = d.name.get_ref().clone();
    let owner = format!("driver \"{name}\"");
    let span = d.name.span();
    for (k, given) in [
        ("joint", d.joint.is_some()),
        ("body", d.body.is_some()),
        ("point", d.point.is_some()),
        ("coordinate", d.coordinate.is_some()),
        ("function", d.function.is_some()),
    ] {
        if given {
            return Err(cx.err(
                span,
                format!(
                    "{owner}: a general_motion driver does not take \"{k}\" (its laws are \
                     translation = [three functions] and rotation = [three functions])"
                ),
            ));
        }
    }
    let need = |v: &Option<Name>, key: &str| -> Result<String, Error> {
        v.as_ref().map(|n| n.get_ref().clone()).ok_or_else(|| {
            missing(
                cx,
                span.clone(),
                &owner,
                key,
                "a general motion moves frame j relative to frame i",
            )
        })
    };
    let order = match &d.order {
        None => RotationOrder([0, 1, 2]),
        Some(o) => RotationOrder::parse(o.get_ref()).ok_or_else(|| {
            cx.err(
                o.span(),
                format!(
                    "{owner}: order must be three axis letters with no axis twice in a row (xyz, \
                     xzy, yxz, yzx, zxy, zyx, xyx, xzx, yxy, yzy, zxz, zyz), got \"{}\"",
                    o.get_ref()
                ),
            )
        })?,
    };
    let three = |list: &Option<Spanned<Vec<Spanned<FunctionSpec>>>>, key: &str, q: Quantity| {
        let Some(l) = list else {
            return Err(missing(
                cx,
                span.clone(),
                &owner,
                key,
                "three functions of time",
            ));
        };
        if l.get_ref().len() != 3 {
            return Err(cx.err(
                l.span(),
                format!(
                    "{owner}: {key} needs three functions, got {}",
                    l.get_ref().len()
                ),
            ));
        }
        l.get_ref()
            .iter()
            .map(|f| load_function(cx, f, &owner, q))
            .collect::<Result<Vec<_>, _>>()
    };
    let mut f = three(&d.translation, "translation", Quantity::Length)?;
    f.extend(three(&d.rotation, "rotation", Quantity::Angle)?);
    let functions: [TimeFunction; 6] = f.try_into().expect("three and three");
    let opt = |v: &Option<Name>| v.as_ref().map(|n| n.get_ref().clone());
    let target = PoseTarget {
        body_i: need(&d.body_i, "body_i")?,
        point_i: need(&d.point_i, "point_i")?,
        axis_i: opt(&d.axis_i),
        x_axis_i: opt(&d.x_axis_i),
        body_j: need(&d.body_j, "body_j")?,
        point_j: need(&d.point_j, "point_j")?,
        axis_j: opt(&d.axis_j),
        x_axis_j: opt(&d.x_axis_j),
        order,
        functions,
    };
    let what = format!(
        "pose of {}.{} in {}.{} ({} angles)",
        target.body_j,
        target.point_j,
        target.body_i,
        target.point_i,
        order.name()
    );
    Ok((DriverSpec::pose(name, target), what))
}

/// An expression function; a parse error points at its column inside the TOML string.
fn expression(cx: &Ctx, text: &Name, owner: &str) -> Result<TimeFunction, Error> {
    let t = text.get_ref();
    Expression::parse(t)
        .map(TimeFunction::Expression)
        .map_err(|e| {
            let hint = e
                .unknown
                .as_deref()
                .map(|n| did_you_mean(n, expression::names()))
                .unwrap_or_default();
            let span = string_inner_span(&cx.src.text, text.span(), t, e.span.clone());
            cx.err(
                span,
                format!(
                    "{owner}: expression \"{}\", column {}: {}{hint}",
                    expression::quoted(t),
                    e.column(t),
                    e.message
                ),
            )
        })
}

/// An expression in the file's units as a function of SI value: `factor·(f)` (`f` itself in
/// SI). The text parsed first, so that errors point into the file's string.
fn in_si(f: TimeFunction, factor: f64) -> TimeFunction {
    match f {
        TimeFunction::Expression(e) if factor != 1.0 => {
            match Expression::parse(&format!("{factor:?}*({})", e.text())) {
                Ok(scaled) => TimeFunction::Expression(scaled),
                Err(_) => TimeFunction::Expression(e),
            }
        }
        other => other,
    }
}

/// The file span of `inner` (a byte span of the string's value `value`) when the TOML string at
/// `span` is written without escapes on one line (`"..."` or `'...'`, the value verbatim); else
/// the whole string.
fn string_inner_span(
    file: &str,
    span: Range<usize>,
    value: &str,
    inner: Range<usize>,
) -> Range<usize> {
    let raw = file.get(span.clone()).unwrap_or("");
    let verbatim = raw.len() == value.len() + 2
        && (raw.starts_with('"') || raw.starts_with('\''))
        && &raw[1..raw.len() - 1] == value;
    if !verbatim {
        return span;
    }
    let start = span.start + 1 + inner.start;
    // An empty span (the end of the text) underlines the closing quote.
    start..(span.start + 1 + inner.end).max(start + 1)
}

fn load_driver(r: &Resolver, d: &DriverSection) -> Result<(DriverSpec, String), Error> {
    let cx = r.cx;
    let name = d.name.get_ref().clone();
    let owner = format!("driver \"{name}\"");
    let kind = d.kind.get_ref().as_str();
    let value_q = if kind == "rotation" {
        Quantity::Angle
    } else {
        Quantity::Length
    };
    let span = d.name.span();
    if kind == "general_motion" {
        return load_general_motion(r, d);
    }
    let pose_keys = [
        ("axis_i", d.axis_i.is_some()),
        ("x_axis_i", d.x_axis_i.is_some()),
        ("axis_j", d.axis_j.is_some()),
        ("x_axis_j", d.x_axis_j.is_some()),
        ("order", d.order.is_some()),
        ("translation", d.translation.is_some()),
        ("rotation", d.rotation.is_some()),
    ];
    if let Some((k, _)) = pose_keys.iter().find(|(_, p)| *p) {
        return Err(cx.err(
            span,
            format!("{owner}: a {kind} driver does not take \"{k}\" (a general_motion key)"),
        ));
    }
    let Some(fspec) = &d.function else {
        return Err(missing(
            cx,
            span,
            &owner,
            "function",
            "the law the driven value follows",
        ));
    };
    let function = load_function(cx, fspec, &owner, value_q)?;
    let stray = |keys: &[(&str, bool)]| -> Result<(), Error> {
        if let Some((k, _)) = keys.iter().find(|(_, p)| *p) {
            return Err(cx.err(
                span.clone(),
                format!("{owner}: a {kind} driver does not take \"{k}\""),
            ));
        }
        Ok(())
    };
    // The joint's existence and kind are checked by the builder (located at this key).
    let joint_ref = || -> Result<String, Error> {
        let Some(j) = &d.joint else {
            return Err(missing(
                cx,
                span.clone(),
                &owner,
                "joint",
                &format!("a {kind} driver drives a joint"),
            ));
        };
        Ok(j.get_ref().clone())
    };
    match kind {
        "rotation" | "translation" => {
            stray(&[
                ("body_i", d.body_i.is_some()),
                ("point_i", d.point_i.is_some()),
                ("body_j", d.body_j.is_some()),
                ("point_j", d.point_j.is_some()),
                ("body", d.body.is_some()),
                ("point", d.point.is_some()),
                ("coordinate", d.coordinate.is_some()),
            ])?;
            if kind == "rotation" {
                let j = joint_ref()?;
                Ok((
                    DriverSpec::rotation(name, &j, function),
                    format!("rotation of joint {j}"),
                ))
            } else {
                let j = joint_ref()?;
                Ok((
                    DriverSpec::translation(name, &j, function),
                    format!("translation of joint {j}"),
                ))
            }
        }
        "distance" => {
            stray(&[
                ("joint", d.joint.is_some()),
                ("body", d.body.is_some()),
                ("point", d.point.is_some()),
                ("coordinate", d.coordinate.is_some()),
            ])?;
            let need = |v: &Option<Name>, key: &str| -> Result<Name, Error> {
                v.clone().ok_or_else(|| {
                    missing(
                        cx,
                        span.clone(),
                        &owner,
                        key,
                        "a distance driver is between two points",
                    )
                })
            };
            let (bi, pi, bj, pj) = (
                need(&d.body_i, "body_i")?,
                need(&d.point_i, "point_i")?,
                need(&d.body_j, "body_j")?,
                need(&d.point_j, "point_j")?,
            );
            // Bodies and points (and that they differ) are checked by the builder.
            let (bi_s, bj_s) = (bi.get_ref().as_str(), bj.get_ref().as_str());
            Ok((
                DriverSpec::distance(name, (bi_s, pi.get_ref()), (bj_s, pj.get_ref()), function),
                format!("distance {bi_s}.{} – {bj_s}.{}", pi.get_ref(), pj.get_ref()),
            ))
        }
        "coordinate" => {
            stray(&[
                ("joint", d.joint.is_some()),
                ("body_i", d.body_i.is_some()),
                ("point_i", d.point_i.is_some()),
                ("body_j", d.body_j.is_some()),
                ("point_j", d.point_j.is_some()),
            ])?;
            let (Some(b), Some(p), Some(c)) = (&d.body, &d.point, &d.coordinate) else {
                return Err(missing(
                    cx,
                    span,
                    &owner,
                    "body, point and coordinate",
                    "a coordinate driver moves one coordinate of a body point",
                ));
            };
            // The body (a moving one) and the point are checked by the builder.
            let bs = b.get_ref().as_str();
            let axis = match c.get_ref().as_str() {
                "x" => Axis::X,
                "y" => Axis::Y,
                "z" => Axis::Z,
                other => {
                    return Err(cx.err(
                        c.span(),
                        format!(
                            "{owner}: coordinate must be \"x\", \"y\" or \"z\", got \"{other}\""
                        ),
                    ))
                }
            };
            Ok((
                DriverSpec::coordinate(name, (bs, p.get_ref()), axis, function),
                format!("{} of {bs}.{}", axis.name(), p.get_ref()),
            ))
        }
        _ => {
            let hint = did_you_mean(kind, DRIVER_TYPES.iter().copied());
            Err(cx.err(
                d.kind.span(),
                format!(
                    "{owner}: unknown driver type \"{kind}\"{hint} (types: {})",
                    list(DRIVER_TYPES.iter().copied())
                ),
            ))
        }
    }
}

/// The key that sets a kinematic or inverse dynamics run's position tolerance and its value:
/// `position_tolerance`, or `tolerance`, its older name with the same meaning (a static kind's
/// `tolerance` is its equilibrium's). Both at once, or `position_tolerance` in a static kind,
/// is an error at the key.
fn position_tolerance<'a>(
    cx: &Ctx,
    a: &'a AnalysisSection,
    statics: bool,
) -> Result<(&'static str, Option<&'a Num>), Error> {
    match (&a.position_tolerance, &a.tolerance) {
        (Some(p), _) if statics => Err(cx.err(
            p.span(),
            "position_tolerance applies to kind = \"kinematic\" and \"inverse_dynamics\" (a \
             static, quasi-static or modal analysis sets its equilibrium's tolerance with \
             tolerance)",
        )),
        (Some(p), Some(_)) => Err(cx.err(
            p.span(),
            "give position_tolerance or tolerance, not both (tolerance is the older name of \
             position_tolerance)",
        )),
        (Some(p), None) => Ok(("position_tolerance", Some(p))),
        (None, t) => Ok(("tolerance", t.as_ref())),
    }
}

fn load_analysis(r: &Resolver, a: &AnalysisSection, spans: &Spans) -> Result<Analysis, Error> {
    let cx = r.cx;
    let kind = a.kind.get_ref().as_str();
    let statics = match kind {
        "static" => Some(StaticKind::Static),
        "quasi_static" => Some(StaticKind::QuasiStatic),
        "modal" => Some(StaticKind::Modal),
        _ => None,
    };
    let dynamic = match kind {
        "kinematic" | "inverse_dynamics" | "static" | "quasi_static" | "modal" => {
            let dynamic_only: [(&str, Option<Range<usize>>); 7] = [
                ("integrator", a.integrator.as_ref().map(|n| n.span())),
                ("rtol", a.rtol.as_ref().map(|n| n.span())),
                ("atol", a.atol.as_ref().map(|n| n.span())),
                ("h_max", a.h_max.as_ref().map(|n| n.span())),
                ("rho_inf", a.rho_inf.as_ref().map(|n| n.span())),
                (
                    "newton_tolerance",
                    a.newton_tolerance.as_ref().map(|n| n.span()),
                ),
                ("output_dt", a.output_dt.as_ref().map(|n| n.span())),
            ];
            if let Some((k, Some(s))) = dynamic_only.into_iter().find(|(_, s)| s.is_some()) {
                let this = match kind {
                    "kinematic" => "a kinematic",
                    "inverse_dynamics" => "an inverse dynamics",
                    _ => "a static",
                };
                return Err(cx.err(
                    s,
                    format!(
                        "{k} applies only to kind = \"dynamic\" ({this} analysis has no \
                         integrator; its output step is dt or steps)"
                    ),
                ));
            }
            None
        }
        "dynamic" => {
            for (key, value) in [
                ("tolerance", &a.tolerance),
                ("position_tolerance", &a.position_tolerance),
            ] {
                if let Some(t) = value {
                    return Err(cx.err(
                        t.span(),
                        format!(
                            "{key} applies to kind = \"kinematic\" and \"inverse_dynamics\" \
                             (a dynamic run's accuracy is set by rtol and atol, or \
                             newton_tolerance)"
                        ),
                    ));
                }
            }
            Some(load_integrator(cx, a)?)
        }
        other => {
            let hint = did_you_mean(
                other,
                [
                    "kinematic",
                    "dynamic",
                    "inverse_dynamics",
                    "static",
                    "quasi_static",
                    "modal",
                ],
            );
            return Err(cx.err(
                a.kind.span(),
                format!(
                    "unknown analysis kind \"{other}\"{hint} (kinds: \"kinematic\", \
                     \"dynamic\", \"inverse_dynamics\", \"static\", \"quasi_static\", \
                     \"modal\")"
                ),
            ));
        }
    };
    let (key, given) = position_tolerance(cx, a, statics.is_some())?;
    let tolerance = match given {
        None => KinematicOptions::new(0.0, 1.0, 1).tolerance,
        Some(n) => {
            let v = cx.num(n, key, Quantity::Unbounded)?;
            // The range is the library's; the refusal is placed at the key.
            KinematicOptions::new(0.0, 1.0, 1)
                .tolerance(v)
                .validate()
                .map_err(|e| cx.err(n.span(), e.to_string()))?;
            v
        }
    };
    let load_steps = load_static_keys(cx, a, kind, statics)?;
    let modes = load_modes(cx, a, statics, 6 * r.order.len().saturating_sub(1))?;
    let one_time = matches!(statics, Some(StaticKind::Static | StaticKind::Modal));
    let t_start = match &a.t_start {
        Some(t) => cx.num(t, "t_start", Quantity::Time)?,
        None if one_time => match &a.time {
            Some(t) => cx.num(t, "time", Quantity::Time)?,
            None => 0.0,
        },
        None => 0.0,
    };
    let t_end = match &a.t_end {
        Some(t) => cx.num(t, "t_end", Quantity::Time)?,
        None if one_time => t_start,
        None => {
            return Err(cx.err(
                a.kind.span(),
                format!("[analysis] kind = \"{kind}\" needs t_end (the end time, s)"),
            ))
        }
    };
    if t_end <= t_start && !one_time {
        let span = a.t_end.as_ref().map_or(a.kind.span(), |t| t.span());
        return Err(cx.err(
            span,
            format!("t_end = {t_end} s must be greater than t_start = {t_start} s"),
        ));
    }
    // The output step: dt for kinematics; output_dt for dynamics (where dt is the integration step).
    let (out_dt, out_key) = if dynamic.is_some() {
        (&a.output_dt, "output_dt")
    } else {
        (&a.dt, "dt")
    };
    let steps = match (&a.steps, out_dt) {
        (Some(_), Some(dt)) => {
            return Err(cx.err(
                dt.span(),
                format!("give either steps or {out_key}, not both"),
            ));
        }
        (Some(n), None) => {
            let v = *n.get_ref();
            if !(1..=10_000_000).contains(&v) {
                return Err(cx.err(
                    n.span(),
                    format!("steps must be between 1 and 10000000, got {v}"),
                ));
            }
            v as usize
        }
        (None, Some(dt)) => {
            let h = cx.num(dt, out_key, Quantity::Time)?;
            if h <= 0.0 {
                return Err(cx.err(dt.span(), format!("{out_key} must be positive, got {h} s")));
            }
            let n = ((t_end - t_start) / h).round();
            if n > 1e7 {
                return Err(cx.err(
                    dt.span(),
                    format!("{out_key} = {h} s gives {n:e} steps; at most 10000000 are allowed"),
                ));
            }
            if ((t_end - t_start) / h - n).abs() > 1e-6 * n.max(1.0) {
                return Err(cx.err(
                    dt.span(),
                    format!(
                        "{out_key} = {h} s does not divide t_end − t_start = {} s into whole steps; use steps = N instead",
                        t_end - t_start
                    ),
                ));
            }
            (n as usize).max(1)
        }
        (None, None) if one_time => 0,
        (None, None) => 100,
    };
    // The run stores every moving body and point at every output time: bound the memory.
    let moving = r.order.len().saturating_sub(1);
    let points: usize = r
        .order
        .iter()
        .skip(1)
        .filter_map(|b| r.features.get(b))
        .map(|f| f.points.len())
        .sum();
    let stored = (steps + 1).saturating_mul((moving + points).max(1));
    if stored > MAX_STORED_FRAMES {
        return Err(cx.err(
            a.kind.span(),
            format!(
                "{} output times × {} bodies and points = {stored:e} stored frames; at most \
                 {MAX_STORED_FRAMES:e} are allowed (each takes up to 264 bytes): use fewer steps",
                steps + 1,
                moving + points
            ),
        ));
    }
    let mut outputs = Outputs::default();
    if let Some(o) = &a.outputs {
        let o = o.get_ref();
        for p in &o.points {
            let Some((b, pt)) = p.get_ref().split_once('.') else {
                return Err(cx.err(
                    p.span(),
                    format!(
                        "output point \"{}\" must be written \"body.point\" (e.g. \"crank.B\")",
                        p.get_ref()
                    ),
                ));
            };
            let bname = Spanned::new(p.span(), b.to_string());
            let b = r.body(&bname, "outputs.points")?;
            r.feature(
                b,
                &Spanned::new(p.span(), pt.to_string()),
                "outputs.points",
                true,
            )?;
            outputs.points.push((b.to_string(), pt.to_string()));
        }
        for j in &o.joints {
            if !spans.joints.contains_key(j.get_ref()) {
                let hint = did_you_mean(j.get_ref(), spans.joints.keys().map(String::as_str));
                return Err(cx.err(
                    j.span(),
                    format!("outputs.joints: unknown joint \"{}\"{hint}", j.get_ref()),
                ));
            }
            outputs.joints.push(j.get_ref().clone());
        }
        for b in &o.bodies {
            let bs = r.body(b, "outputs.bodies")?;
            if bs == GROUND {
                return Err(cx.err(b.span(), "outputs.bodies: the ground does not move"));
            }
            outputs.bodies.push(bs.to_string());
        }
        if kind == "kinematic" && (o.reactions.is_some() || o.energy.is_some()) {
            return Err(cx.err(
                a.kind.span(),
                "outputs.reactions and outputs.energy apply only to kind = \"dynamic\" and \
                 kind = \"inverse_dynamics\" (a kinematic run has no forces)",
            ));
        }
        if statics.is_some() && o.energy.is_some() {
            return Err(cx.err(
                a.kind.span(),
                "outputs.energy applies only to kind = \"dynamic\" and \"inverse_dynamics\" (a static analysis has no \
                 motion to conserve energy along)",
            ));
        }
        if let Some(list_) = &o.reactions {
            let mut v = Vec::new();
            for j in list_ {
                let known =
                    |n: &String| spans.joints.contains_key(n) || spans.couplers.contains_key(n);
                if !known(j.get_ref()) {
                    let names = spans.joints.keys().chain(spans.couplers.keys());
                    let hint = did_you_mean(j.get_ref(), names.map(String::as_str));
                    return Err(cx.err(
                        j.span(),
                        format!(
                            "outputs.reactions: unknown joint or coupler \"{}\"{hint}",
                            j.get_ref()
                        ),
                    ));
                }
                v.push(j.get_ref().clone());
            }
            outputs.reactions = Some(v);
        }
        outputs.energy = o.energy.unwrap_or(true);
    } else {
        outputs.energy = true;
    }
    let linearize_at = match &a.linearize_at {
        None => None,
        Some(n) => {
            let t = cx.num(n, "linearize_at", Quantity::Time)?;
            if dynamic.is_none() {
                return Err(cx.err(
                    n.span(),
                    format!(
                        "linearize_at applies only to kind = \"dynamic\" (this is a {kind} \
                         analysis; kind = \"modal\" linearizes about an equilibrium)"
                    ),
                ));
            }
            if !(t_start..=t_end).contains(&t) {
                return Err(cx.err(
                    n.span(),
                    format!(
                        "linearize_at = {t} s must lie between t_start = {t_start} s and \
                         t_end = {t_end} s"
                    ),
                ));
            }
            Some(t)
        }
    };
    let plots = match &a.plots {
        None => true,
        Some(p) => match p.get_ref().as_str() {
            "svg" => true,
            "none" => false,
            other => {
                return Err(cx.err(
                    p.span(),
                    format!("plots = \"{other}\" is not supported: use \"svg\" or \"none\""),
                ))
            }
        },
    };
    let kind = match (dynamic, statics) {
        (Some(i), _) => AnalysisKind::Dynamic(i),
        (None, Some(k)) => AnalysisKind::Static(k),
        (None, None) if kind == "inverse_dynamics" => AnalysisKind::InverseDynamics,
        (None, None) => AnalysisKind::Kinematic,
    };
    Ok(Analysis {
        kind,
        t_start,
        t_end,
        steps,
        outputs,
        plots,
        tolerance,
        load_steps,
        inputs: Vec::new(),
        linearize_at,
        modes,
    })
}

/// `modes = n` (modal only, 1 to 10,000 and at most the model's `unknowns`, 6 per moving
/// body): the number of lowest modes.
fn load_modes(
    cx: &Ctx,
    a: &AnalysisSection,
    statics: Option<StaticKind>,
    unknowns: usize,
) -> Result<Option<usize>, Error> {
    let Some(n) = &a.modes else {
        return Ok(None);
    };
    if statics != Some(StaticKind::Modal) {
        return Err(cx.err(
            n.span(),
            "modes applies only to kind = \"modal\" (how many of the lowest modes)",
        ));
    }
    let v = *n.get_ref();
    if !(1..=10_000).contains(&v) {
        return Err(cx.err(
            n.span(),
            format!("modes must be between 1 and 10000, got {v}"),
        ));
    }
    if v as usize > unknowns {
        return Err(cx.err(
            n.span(),
            format!(
                "modes = {v} is more than the model's {unknowns} unknowns (6 per moving body): \
                 it has at most that many modes"
            ),
        ));
    }
    Ok(Some(v as usize))
}

/// `inputs = [...]` (modal, dynamic with linearize_at): drivers (modal) and point_force and torque elements of the file.
fn load_inputs(
    cx: &Ctx,
    a: &AnalysisSection,
    an: &Analysis,
    forces: &[Force],
    drivers: &[(String, String)],
) -> Result<Vec<String>, Error> {
    let Some(list_) = &a.inputs else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for n in list_ {
        if an.statics() != Some(StaticKind::Modal) && an.linearize_at.is_none() {
            return Err(cx.err(
                n.span(),
                "inputs applies only to kind = \"modal\" and to kind = \"dynamic\" with \
                 linearize_at (the inputs of the state-space model)",
            ));
        }
        let force = forces.iter().any(|f| {
            f.name() == n.get_ref().as_str()
                && matches!(f, Force::PointForce { .. } | Force::PointTorque { .. })
        });
        let driver = drivers.iter().any(|(d, _)| d == n.get_ref());
        if driver && an.statics() != Some(StaticKind::Modal) {
            return Err(cx.err(
                n.span(),
                format!(
                    "inputs: driver \"{}\": driver efforts are inputs of kind = \"modal\" only \
                     (about a moving state the driver prescribes the motion)",
                    n.get_ref()
                ),
            ));
        }
        if !force && !driver {
            return Err(cx.err(
                n.span(),
                format!(
                    "inputs: \"{}\" is not a [[force]] of type point_force or torque, nor a \
                     one-coordinate [[driver]]",
                    n.get_ref()
                ),
            ));
        }
        out.push(n.get_ref().clone());
    }
    Ok(out)
}

/// The keys of the static kinds: `time` (static and modal only; t_start, t_end, steps and dt
/// do not apply to them) and `load_steps` (default 1). Returns load_steps.
fn load_static_keys(
    cx: &Ctx,
    a: &AnalysisSection,
    kind: &str,
    statics: Option<StaticKind>,
) -> Result<usize, Error> {
    match statics {
        None => {
            let only: [(&str, Option<Range<usize>>); 2] = [
                ("time", a.time.as_ref().map(|n| n.span())),
                ("load_steps", a.load_steps.as_ref().map(|n| n.span())),
            ];
            if let Some((k, Some(s))) = only.into_iter().find(|(_, s)| s.is_some()) {
                return Err(cx.err(
                    s,
                    format!(
                        "{k} applies only to kind = \"static\", \"quasi_static\" and \
                         \"modal\" (this is a {kind} analysis)"
                    ),
                ));
            }
        }
        Some(StaticKind::Static | StaticKind::Modal) => {
            let grid: [(&str, Option<Range<usize>>); 4] = [
                ("t_start", a.t_start.as_ref().map(|n| n.span())),
                ("t_end", a.t_end.as_ref().map(|n| n.span())),
                ("steps", a.steps.as_ref().map(|n| n.span())),
                ("dt", a.dt.as_ref().map(|n| n.span())),
            ];
            if let Some((k, Some(s))) = grid.into_iter().find(|(_, s)| s.is_some()) {
                return Err(cx.err(
                    s,
                    format!(
                        "{k} does not apply to kind = \"{kind}\": it has one time, the one the \
                         drivers are held at (time = ..., default 0); use kind = \
                         \"quasi_static\" for a time grid"
                    ),
                ));
            }
        }
        Some(StaticKind::QuasiStatic) => {
            if let Some(t) = &a.time {
                return Err(cx.err(
                    t.span(),
                    "time does not apply to kind = \"quasi_static\": its times are the grid \
                     (t_start, t_end, steps or dt)",
                ));
            }
        }
    }
    match &a.load_steps {
        None => Ok(1),
        Some(n) => {
            let v = *n.get_ref();
            if !(1..=1000).contains(&v) {
                return Err(cx.err(
                    n.span(),
                    format!("load_steps must be between 1 and 1000, got {v}"),
                ));
            }
            Ok(v as usize)
        }
    }
}

/// `velocity`, `angular_velocity` / `angular_velocity_local` of a body, if any is given.
fn body_velocity(cx: &Ctx, b: &BodySection) -> Result<Option<BodyVelocity>, Error> {
    let name = b.name.get_ref();
    if b.velocity.is_none() && b.angular_velocity.is_none() && b.angular_velocity_local.is_none() {
        return Ok(None);
    }
    if let (Some(_), Some(l)) = (&b.angular_velocity, &b.angular_velocity_local) {
        return Err(cx.err(
            l.span(),
            format!(
                "body \"{name}\": give angular_velocity (global components) or \
                 angular_velocity_local (body components), not both"
            ),
        ));
    }
    let velocity = match &b.velocity {
        Some(v) => cx.vec3(
            v,
            format_args!("velocity of body \"{name}\""),
            Quantity::Velocity,
        )?,
        None => Vector3::zeros(),
    };
    let (omega, omega_local) = match (&b.angular_velocity, &b.angular_velocity_local) {
        (Some(w), _) => (
            cx.vec3(
                w,
                format_args!("angular_velocity of body \"{name}\""),
                Quantity::AngularVelocity,
            )?,
            false,
        ),
        (None, Some(w)) => (
            cx.vec3(
                w,
                format_args!("angular_velocity_local of body \"{name}\""),
                Quantity::AngularVelocity,
            )?,
            true,
        ),
        (None, None) => (Vector3::zeros(), false),
    };
    Ok(Some(BodyVelocity {
        body: name.clone(),
        velocity,
        omega,
        omega_local,
    }))
}

const FORCE_TYPES: &[&str] = &[
    "point_force",
    "torque",
    "spring_damper",
    "rotational_spring_damper",
];

fn load_force(
    r: &Resolver,
    f: &ForceSection,
    joint_kinds: &HashMap<String, JointKind>,
    spans: &Spans,
) -> Result<Force, Error> {
    let cx = r.cx;
    let name = f.name.get_ref().clone();
    let owner = format!("force \"{name}\"");
    let kind = f.kind.get_ref().as_str();
    let span = f.name.span();
    let allowed: &[&str] = match kind {
        "point_force" => &["body", "point", "value", "components", "frame"],
        "torque" => &["body", "value", "components", "frame"],
        "spring_damper" => &[
            "body_i",
            "point_i",
            "body_j",
            "point_j",
            "stiffness",
            "damping",
            "free_length",
            "actuator",
        ],
        "rotational_spring_damper" => &["joint", "stiffness", "damping", "rest_angle"],
        _ => {
            let hint = did_you_mean(kind, FORCE_TYPES.iter().copied());
            return Err(cx.err(
                f.kind.span(),
                format!(
                    "{owner}: unknown force type \"{kind}\"{hint} (types: {})",
                    list(FORCE_TYPES.iter().copied())
                ),
            ));
        }
    };
    let present = [
        ("body", f.body.is_some()),
        ("point", f.point.is_some()),
        ("value", f.value.is_some()),
        ("components", f.components.is_some()),
        ("frame", f.frame.is_some()),
        ("body_i", f.body_i.is_some()),
        ("point_i", f.point_i.is_some()),
        ("body_j", f.body_j.is_some()),
        ("point_j", f.point_j.is_some()),
        ("stiffness", f.stiffness.is_some()),
        ("damping", f.damping.is_some()),
        ("free_length", f.free_length.is_some()),
        ("actuator", f.actuator.is_some()),
        ("joint", f.joint.is_some()),
        ("rest_angle", f.rest_angle.is_some()),
    ];
    if let Some((k, _)) = present.iter().find(|(k, p)| *p && !allowed.contains(k)) {
        return Err(cx.err(
            span,
            format!(
                "{owner}: a {kind} force does not take \"{k}\" (it takes {})",
                list(allowed.iter().copied())
            ),
        ));
    }
    let need = |v: &Option<Name>, key: &str| -> Result<Name, Error> {
        v.clone().ok_or_else(|| {
            missing(
                cx,
                span.clone(),
                &owner,
                key,
                &format!("a {kind} force needs it"),
            )
        })
    };
    let coefficient = |v: &Option<Num>, key: &str, q: Quantity| -> Result<f64, Error> {
        let unit = q.unit();
        match v {
            Some(n) => {
                let x = cx.num(n, format_args!("{owner}: {key}"), q)?;
                if x < 0.0 {
                    return Err(cx.err(
                        n.span(),
                        format!("{owner}: {key} must be ≥ 0, got {x} {unit}"),
                    ));
                }
                Ok(x)
            }
            None => Ok(0.0),
        }
    };
    match kind {
        "point_force" | "torque" => {
            let value_q = if kind == "torque" {
                Quantity::Torque
            } else {
                Quantity::Force
            };
            let b = need(&f.body, "body")?;
            let body = r.body(&b, &owner)?;
            if body == GROUND {
                return Err(cx.err(
                    b.span(),
                    format!("{owner}: a force on the ground does nothing; name a moving body"),
                ));
            }
            let value = match (&f.value, &f.components) {
                (Some(v), None) => VectorFunction::Constant(cx.vec3(v, format_args!("{owner}: value"), value_q)?),
                (None, Some(c)) => {
                    let list_ = c.get_ref();
                    if list_.len() != 3 {
                        return Err(cx.err(
                            c.span(),
                            format!(
                                "{owner}: components needs three functions (x, y, z), got {}",
                                list_.len()
                            ),
                        ));
                    }
                    let fx = load_function(cx, &list_[0], &owner, value_q)?;
                    let fy = load_function(cx, &list_[1], &owner, value_q)?;
                    let fz = load_function(cx, &list_[2], &owner, value_q)?;
                    VectorFunction::Components(Box::new([fx, fy, fz]))
                }
                (Some(_), Some(c)) => {
                    return Err(cx.err(
                        c.span(),
                        format!("{owner}: give value (constant) or components (functions), not both"),
                    ))
                }
                (None, None) => {
                    return Err(missing(
                        cx,
                        span,
                        &owner,
                        "value",
                        "a constant vector, or components = [{...}, {...}, {...}] for functions of time",
                    ))
                }
            };
            let frame = match &f.frame {
                None => Frame::Global,
                Some(fr) => match fr.get_ref().as_str() {
                    "global" => Frame::Global,
                    "body" | "local" => Frame::Body,
                    other => {
                        let hint = did_you_mean(other, ["global", "body"]);
                        return Err(cx.err(
                            fr.span(),
                            format!("{owner}: unknown frame \"{other}\"{hint} (frames: \"global\", \"body\")"),
                        ));
                    }
                },
            };
            if kind == "torque" {
                Ok(Force::torque(&name, body, value, frame))
            } else {
                let p = need(&f.point, "point")?;
                r.feature(body, &p, &owner, true)?;
                let local = r.point_value(body, p.get_ref());
                Ok(Force::point_force(
                    &name,
                    body,
                    PointRef::Local(local),
                    value,
                    frame,
                ))
            }
        }
        "spring_damper" => {
            let (bi, pi, bj, pj) = (
                need(&f.body_i, "body_i")?,
                need(&f.point_i, "point_i")?,
                need(&f.body_j, "body_j")?,
                need(&f.point_j, "point_j")?,
            );
            let bi_s = r.body(&bi, &owner)?;
            let bj_s = r.body(&bj, &owner)?;
            r.feature(bi_s, &pi, &owner, true)?;
            r.feature(bj_s, &pj, &owner, true)?;
            if bi_s == bj_s {
                return Err(cx.err(
                    bj.span(),
                    format!(
                        "{owner}: both points are on body \"{bi_s}\"; the spring cannot stretch"
                    ),
                ));
            }
            let stiffness = coefficient(&f.stiffness, "stiffness", Quantity::Stiffness)?;
            let damping = coefficient(&f.damping, "damping", Quantity::Damping)?;
            let free_length = match &f.free_length {
                Some(n) => Some(coefficient(
                    &Some(n.clone()),
                    "free_length",
                    Quantity::Length,
                )?),
                None => None,
            };
            let actuator = match &f.actuator {
                Some(a) => Some(load_function(cx, a, &owner, Quantity::Force)?),
                None => None,
            };
            if stiffness == 0.0 && damping == 0.0 && actuator.is_none() {
                return Err(cx.err(
                    span,
                    format!("{owner}: stiffness, damping and actuator are all absent or zero, so the element does nothing"),
                ));
            }
            let point_i = PointRef::Local(r.point_value(bi_s, pi.get_ref()));
            let point_j = PointRef::Local(r.point_value(bj_s, pj.get_ref()));
            Ok(Force::SpringDamperActuator {
                name,
                body_i: bi_s.into(),
                point_i,
                body_j: bj_s.into(),
                point_j,
                stiffness,
                damping,
                free_length,
                actuator,
            })
        }
        _ => {
            let j = need(&f.joint, "joint")?;
            let jn = j.get_ref();
            match joint_kinds.get(jn) {
                Some(k) if k.info().rotation.is_some() => {}
                Some(k) => {
                    return Err(cx.err(
                        j.span(),
                        format!(
                            "{owner}: a rotational_spring_damper needs {}, but \"{jn}\" is {}",
                            cardan_mechanism::kinds_with(|k| k.rotation.is_some()),
                            k.name()
                        ),
                    ))
                }
                None => {
                    let hint = did_you_mean(jn, joint_kinds.keys().map(String::as_str));
                    let mut names: Vec<&str> = joint_kinds.keys().map(String::as_str).collect();
                    names.sort_by_key(|n| spans.joints.get(*n).map(|s| s.start));
                    return Err(cx.err(
                        j.span(),
                        format!(
                            "{owner}: unknown joint \"{jn}\"{hint} (joints: {})",
                            list(names)
                        ),
                    ));
                }
            }
            let stiffness = coefficient(&f.stiffness, "stiffness", Quantity::RotationalStiffness)?;
            let damping = coefficient(&f.damping, "damping", Quantity::RotationalDamping)?;
            let rest_angle = match &f.rest_angle {
                Some(n) => cx.num(n, format_args!("{owner}: rest_angle"), Quantity::Angle)?,
                None => 0.0,
            };
            Ok(Force::rotational_spring_damper(
                &name, jn, stiffness, damping, rest_angle,
            ))
        }
    }
}

const INTEGRATORS: &[&str] = &["dopri5", "generalized_alpha"];

/// A positive number with a unit, for the dynamic settings.
fn positive(cx: &Ctx, n: &Num, what: &str, unit: &str) -> Result<f64, Error> {
    let v = cx.num(n, what, Quantity::Time)?;
    if v <= 0.0 {
        return Err(cx.err(n.span(), format!("{what} must be positive, got {v}{unit}")));
    }
    Ok(v)
}

/// The integrator of a `kind = "dynamic"` analysis. The values are only read here; their
/// ranges are the library's ([`Integrator::validate`]), and a refusal is placed at the key.
fn load_integrator(cx: &Ctx, a: &AnalysisSection) -> Result<Integrator, Error> {
    let name = a
        .integrator
        .as_ref()
        .map_or("dopri5", |n| n.get_ref().as_str());
    let stray = |keys: &[(&str, &Option<Num>)]| -> Result<(), Error> {
        if let Some((k, n)) = keys.iter().find(|(_, v)| v.is_some()) {
            let s = n.as_ref().map_or(0..0, |n| n.span());
            return Err(cx.err(s, format!("{k} does not apply to integrator = \"{name}\"")));
        }
        Ok(())
    };
    // Tolerances and ρ∞ have their ranges checked by the library; steps are times.
    let read = |n: &Option<Num>, key: &str| -> Result<Option<f64>, Error> {
        let q = match key {
            "dt" | "h_max" => Quantity::Time,
            _ => Quantity::Unbounded,
        };
        n.as_ref().map(|n| cx.num(n, key, q)).transpose()
    };
    let integrator = match name {
        "dopri5" => {
            stray(&[
                ("rho_inf", &a.rho_inf),
                ("newton_tolerance", &a.newton_tolerance),
            ])?;
            let mut o = Dopri5Options::default();
            if let Some(h) = &a.dt {
                if a.rtol.is_some() || a.atol.is_some() {
                    return Err(cx.err(
                        h.span(),
                        "give dt (fixed steps) or rtol/atol (adaptive steps), not both",
                    ));
                }
                o = Dopri5Options::fixed(positive(cx, h, "dt", " s")?);
            }
            o.rtol = read(&a.rtol, "rtol")?.unwrap_or(o.rtol);
            o.atol = read(&a.atol, "atol")?.unwrap_or(o.atol);
            o.h_max = read(&a.h_max, "h_max")?.unwrap_or(o.h_max);
            Integrator::Dopri5(o)
        }
        "generalized_alpha" => {
            stray(&[("rtol", &a.rtol), ("atol", &a.atol), ("h_max", &a.h_max)])?;
            let mut o = GeneralizedAlphaOptions::default();
            o.h = read(&a.dt, "dt")?.unwrap_or(o.h);
            o.rho_inf = read(&a.rho_inf, "rho_inf")?.unwrap_or(o.rho_inf);
            o.tolerance = read(&a.newton_tolerance, "newton_tolerance")?.unwrap_or(o.tolerance);
            Integrator::GeneralizedAlpha(o)
        }
        other => {
            let hint = did_you_mean(other, INTEGRATORS.iter().copied());
            let s = a.integrator.as_ref().map_or(0..0, |n| n.span());
            return Err(cx.err(
                s,
                format!(
                    "unknown integrator \"{other}\"{hint} (integrators: {})",
                    list(INTEGRATORS.iter().copied())
                ),
            ));
        }
    };
    integrator.validate().map_err(|e| {
        // The option struct's field → the file's key.
        let (key, value) = match e.option {
            "step" | "h" => ("dt", &a.dt),
            "tolerance" => ("newton_tolerance", &a.newton_tolerance),
            "rtol" => ("rtol", &a.rtol),
            "atol" => ("atol", &a.atol),
            "h_max" => ("h_max", &a.h_max),
            "rho_inf" => ("rho_inf", &a.rho_inf),
            other => (other, &None),
        };
        let span = value.as_ref().map_or(a.kind.span(), Spanned::span);
        cx.err(span, e.describe(key))
    })?;
    Ok(integrator)
}
