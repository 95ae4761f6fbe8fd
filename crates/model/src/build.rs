//! From a parsed model file to a [`MechanismBuilder`], checking everything that can be pinned to
//! a place in the file: names (with suggestions), duplicates, numbers, axes, mass and inertia,
//! self-joints, function parameters. What only the mechanism can judge (DOF, assembly) is
//! checked later, and mapped back to the element's line through [`Spans`].

mod analysis;
mod coupler;
mod force;

use crate::diag::{did_you_mean, list, Error, Source};
use crate::file::{
    BodySection, DriverSection, FunctionSpec, InertiaSpec, JointSection, ModelFile, Name, Num,
    OrientationSpec, Vec3,
};
use crate::units::UnitSystem;
use crate::vocabulary::{COUPLERS, DRIVERS, FORCES, FUNCTIONS};
use cardan_constraints::drivers::POSE_ROWS;
use cardan_constraints::expression::{self, Expression};
use cardan_constraints::{JointKind, RotationOrder, TimeFunction, KINDS};
use cardan_dynamics::{Force, Integrator};
use cardan_mechanism::{
    pose_row_name, Axis, Body, DriverSpec, DriverTarget, ElementKind, JointSpec, MechanismBuilder,
    Orientation, PoseTarget, Quantity, Site, GROUND,
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
    /// The joints, in file order (for `check`).
    pub joints: Vec<JointEntry>,
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

/// One `[[joint]]` as read: its name, kind and the two bodies it connects.
#[derive(Debug, Clone, PartialEq)]
pub struct JointEntry {
    /// The joint's name.
    pub name: String,
    /// Its kind.
    pub kind: JointKind,
    /// Body i.
    pub body_i: String,
    /// Body j.
    pub body_j: String,
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
    /// The keys written in the sections with vocabularies ([`crate::vocabulary`]).
    keys: &'a crate::vocabulary::KeySpans,
}

impl Ctx<'_> {
    /// Checks the table whose span starts at `table` against `vocab` (its entry `selected`
    /// exists, it takes every key given, every key it needs is given; [`crate::vocabulary`]).
    fn check(
        &self,
        vocab: &crate::vocabulary::Vocabulary,
        owner: &str,
        selected: &Name,
        table: usize,
        element: Range<usize>,
    ) -> Result<&'static crate::vocabulary::Entry, Error> {
        crate::vocabulary::check(
            self.src,
            vocab,
            owner,
            selected,
            (self.keys, table),
            |_| true,
            element,
        )
    }

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

/// Turns a parsed file into a builder, checking everything that has a place in the file.
///
/// The sections are read in the order their references need: ground and bodies (their points
/// and vectors), joints, couplers, drivers, forces (which name joints), then the analysis.
pub fn load(src: &Source, file: &ModelFile) -> Result<Loaded, Error> {
    let units = model_units(src, file)?;
    let cx = Ctx {
        src,
        units,
        keys: &file.keys,
    };
    let mut spans = Spans::default();
    let mut builder = MechanismBuilder::new();
    let name = model_name(&cx, file)?;
    let mut forces = Vec::new();
    if let Some(g) = &file.model.get_ref().gravity {
        forces.push(Force::gravity(cx.vec3(
            g,
            "gravity",
            Quantity::Acceleration,
        )?));
    }
    let mut features: HashMap<String, Features> = HashMap::new();
    features.insert(GROUND.to_string(), load_ground(&cx, file, &mut builder)?);
    let bodies = load_bodies(&cx, file, &mut spans, &mut builder, &mut features)?;
    let resolver = Resolver {
        cx: &cx,
        features: &features,
        order: &bodies.order,
    };
    let joints = load_joints(&resolver, file, &mut spans, &mut builder)?;
    load_couplers(&cx, file, &mut spans, &mut builder)?;
    let drivers = load_drivers(&resolver, file, &mut spans, &mut builder)?;
    load_forces(&resolver, file, &joints.kinds, &mut spans, &mut forces)?;

    spans.analysis = 0..0;
    let analysis = match &file.analysis {
        Some(a) => {
            spans.analysis = a.get_ref().kind.span();
            let mut an = analysis::load_analysis(&resolver, a, &spans)?;
            an.inputs = analysis::load_inputs(&cx, a.get_ref(), &an, &forces, &drivers.names)?;
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
        joints: joints.list,
        bodies: bodies.masses,
        drivers: drivers.names,
        driver_functions: drivers.functions,
        forces,
        velocities: bodies.velocities,
    })
}

/// `[model] name`, trimmed, refused when it cannot name the output directory.
fn model_name(cx: &Ctx, file: &ModelFile) -> Result<String, Error> {
    let model = file.model.get_ref();
    let name = model.name.get_ref().trim().to_string();
    if let Some(why) = unusable_directory_name(&name) {
        return Err(cx.err(
            model.name.span(),
            format!("model name {why}; it names the output directory out/<name>/"),
        ));
    }
    Ok(name)
}

/// `[ground]`: the fixed body's points and vectors.
fn load_ground(
    cx: &Ctx,
    file: &ModelFile,
    builder: &mut MechanismBuilder,
) -> Result<Features, Error> {
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
    Ok(ground)
}

/// What `[[body]]` sections give besides the builder's bodies.
struct LoadedBodies {
    /// Body names with mass, in file order.
    masses: Vec<(String, Option<f64>)>,
    /// Initial velocities given in the file.
    velocities: Vec<BodyVelocity>,
    /// Ground, then the bodies in file order (the order of "did you mean" lists).
    order: Vec<String>,
}

/// `[[body]]`: each body, its points and vectors (into `features`) and its initial velocity.
fn load_bodies(
    cx: &Ctx,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
    features: &mut HashMap<String, Features>,
) -> Result<LoadedBodies, Error> {
    let mut out = LoadedBodies {
        masses: Vec::new(),
        velocities: Vec::new(),
        order: vec![GROUND.into()],
    };
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
            let l = cx.src.location(first.start);
            return Err(cx.err(
                b.name.span(),
                format!(
                    "duplicate body name \"{bname}\" (first defined at line {})",
                    l.line
                ),
            ));
        }
        spans.bodies.insert(bname.clone(), b.name.span());
        let (body, f) = load_body(cx, b)?;
        if let Some(v) = body_velocity(cx, b)? {
            out.velocities.push(v);
        }
        for (n, (_, v)) in &f.points {
            builder.point(&bname, n, *v);
        }
        for (n, (_, v)) in &f.vectors {
            builder.vector(&bname, n, *v);
        }
        out.masses.push((bname.clone(), body.mass));
        builder.body(body);
        features.insert(bname.clone(), f);
        out.order.push(bname);
    }
    Ok(out)
}

/// What `[[joint]]` sections give besides the builder's joints.
struct LoadedJoints {
    /// In file order.
    list: Vec<JointEntry>,
    /// Name → kind (forces name the joint they act in).
    kinds: HashMap<String, JointKind>,
}

/// `[[joint]]`: each joint, resolved against the bodies' points and vectors.
fn load_joints(
    r: &Resolver,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<LoadedJoints, Error> {
    let mut out = LoadedJoints {
        list: Vec::new(),
        kinds: HashMap::new(),
    };
    for j in &file.joint {
        let j = j.get_ref();
        let jname = j.name.get_ref().clone();
        check_unique_element(r.cx, spans, &j.name, "joint")?;
        spans.joints.insert(jname.clone(), j.name.span());
        let spec = load_joint(r, j)?;
        out.list.push(JointEntry {
            name: jname.clone(),
            kind: spec.kind,
            body_i: spec.body_i.clone(),
            body_j: spec.body_j.clone(),
        });
        out.kinds.insert(jname, spec.kind);
        builder.joint(spec);
    }
    Ok(out)
}

/// `[[coupler]]`: each coupler, its kind checked against the coupler table.
fn load_couplers(
    cx: &Ctx,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<(), Error> {
    for section in &file.coupler {
        let c = section.get_ref();
        check_unique_element(cx, spans, &c.name, "coupler")?;
        let owner = format!("coupler \"{}\"", c.name.get_ref());
        cx.check(
            &COUPLERS,
            &owner,
            &c.kind,
            section.span().start,
            c.name.span(),
        )?;
        spans
            .couplers
            .insert(c.name.get_ref().clone(), c.name.span());
        builder.coupler(coupler::load_coupler(cx, c)?);
    }
    Ok(())
}

/// What `[[driver]]` sections give besides the builder's drivers: one entry per driver row (a
/// general motion is six).
struct LoadedDrivers {
    /// Row name and what it drives, in file order.
    names: Vec<(String, String)>,
    /// Each row's time function and the quantity of its value.
    functions: Vec<(TimeFunction, Quantity)>,
}

/// `[[driver]]`: each driver, its kind checked against the driver table.
fn load_drivers(
    r: &Resolver,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<LoadedDrivers, Error> {
    let mut out = LoadedDrivers {
        names: Vec::new(),
        functions: Vec::new(),
    };
    for section in &file.driver {
        let d = section.get_ref();
        check_unique_element(r.cx, spans, &d.name, "driver")?;
        let owner = format!("driver \"{}\"", d.name.get_ref());
        r.cx.check(
            &DRIVERS,
            &owner,
            &d.kind,
            section.span().start,
            d.name.span(),
        )?;
        spans
            .drivers
            .insert(d.name.get_ref().clone(), d.name.span());
        if spans.first_driver.is_none() {
            spans.first_driver = Some(d.name.span());
        }
        let (spec, what) = load_driver(r, d)?;
        match &spec.target {
            // A general motion is six driver rows: each is listed, located and checked.
            DriverTarget::Pose(t) => {
                for (k, f) in t.functions.iter().enumerate() {
                    let row = pose_row_name(&spec.name, k);
                    spans.drivers.insert(row.clone(), d.name.span());
                    out.names
                        .push((row, format!("{} of the {what}", POSE_ROWS[k])));
                    let q = if k < 3 {
                        Quantity::Length
                    } else {
                        Quantity::Angle
                    };
                    out.functions.push((f.clone(), q));
                }
            }
            target => {
                out.names.push((d.name.get_ref().clone(), what));
                let q = match target {
                    DriverTarget::JointRotation { .. } => Quantity::Angle,
                    _ => Quantity::Length,
                };
                out.functions.push((spec.function.clone(), q));
            }
        }
        builder.driver(spec);
    }
    Ok(out)
}

/// `[[force]]`: each force element, its kind checked against the force table, appended to
/// `forces`.
fn load_forces(
    r: &Resolver,
    file: &ModelFile,
    joint_kinds: &HashMap<String, JointKind>,
    spans: &mut Spans,
    forces: &mut Vec<Force>,
) -> Result<(), Error> {
    for section in &file.force {
        let f = section.get_ref();
        check_unique_element(r.cx, spans, &f.name, "force")?;
        let owner = format!("force \"{}\"", f.name.get_ref());
        let table = section.span().start;
        let entry = r.cx.check(&FORCES, &owner, &f.kind, table, f.name.span())?;
        spans.forces.insert(f.name.get_ref().clone(), f.name.span());
        forces.push(force::load_force(r, f, entry, joint_kinds, spans)?);
    }
    Ok(())
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
    let keys = crate::vocabulary::KeySpans::default();
    let cx = Ctx {
        src,
        units: UnitSystem::Si,
        keys: &keys,
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
    cx.check(
        &FUNCTIONS,
        &format!("{owner}: function"),
        &s.kind,
        span.start,
        span.clone(),
    )?;
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
            let hint = did_you_mean(kind, DRIVERS.names());
            Err(cx.err(
                d.kind.span(),
                format!(
                    "{owner}: unknown driver type \"{kind}\"{hint} (types: {})",
                    list(DRIVERS.names())
                ),
            ))
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
