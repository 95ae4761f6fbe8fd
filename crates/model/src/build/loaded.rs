//! What [`load`](super::load) returns: the [`Loaded`] model (builder, names, functions, forces,
//! initial velocities), the requested [`Analysis`] and its [`Outputs`], and the [`Spans`] that
//! place the builder's later errors back in the file.

use crate::units::UnitSystem;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{Force, Integrator};
use cardan_mechanism::{ElementKind, MechanismBuilder, Quantity, Site};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::ops::Range;

/// Where each named element is defined, to place errors found after parsing.
#[derive(Debug, Clone, Default)]
pub struct Spans {
    /// Body name → span of its `[[body]]` name value.
    pub bodies: HashMap<String, Range<usize>>,
    /// Joint name → span.
    pub joints: HashMap<String, Range<usize>>,
    /// Curve (point-on-curve element) name → span.
    pub curves: HashMap<String, Range<usize>>,
    /// Driver name → span.
    pub drivers: HashMap<String, Range<usize>>,
    /// Coupler name → span.
    pub couplers: HashMap<String, Range<usize>>,
    /// Force name → span.
    pub forces: HashMap<String, Range<usize>>,
    /// Limit name → span.
    pub limits: HashMap<String, Range<usize>>,
    /// Joint friction name → span.
    pub frictions: HashMap<String, Range<usize>>,
    /// Collision shape name → span.
    pub shapes: HashMap<String, Range<usize>>,
    /// Contact material name → span.
    pub materials: HashMap<String, Range<usize>>,
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
            ElementKind::Joint if self.curves.contains_key(&site.name) => &self.curves,
            ElementKind::Joint => &self.joints,
            ElementKind::Driver => &self.drivers,
            ElementKind::Coupler => &self.couplers,
            ElementKind::Force => &self.forces,
        };
        let name = table.get(&site.name)?.clone();
        Some(Self::within(
            text,
            name,
            site.field.as_deref(),
            site.value.as_deref(),
        ))
    }

    /// The span of a limit's or a joint friction's key `key` (the elements the builder names
    /// by [`cardan_mechanism::ModelError::limit_site`]), else of its name.
    pub fn locate_limit(&self, text: &str, name: &str, key: &str) -> Option<Range<usize>> {
        let at = self.limits.get(name).or_else(|| self.frictions.get(name))?;
        Some(Self::within(text, at.clone(), Some(key), None))
    }

    /// The span of a collision shape's or a material's key `key` (`table` "shape" or
    /// "material", [`cardan_mechanism::ModelError::contact_site`]), else of its name.
    pub fn locate_contact(
        &self,
        text: &str,
        table: &str,
        name: &str,
        key: &str,
    ) -> Option<Range<usize>> {
        let at = if table == "shape" {
            self.shapes.get(name)
        } else {
            self.materials.get(name)
        }?;
        if key == "mesh" {
            // A mesh's points come from its file or its points key.
            let file = Self::within(text, at.clone(), Some("file"), None);
            if file != *at {
                return Some(file);
            }
            return Some(Self::within(text, at.clone(), Some("points"), None));
        }
        Some(Self::within(text, at.clone(), Some(key), None))
    }

    /// Inside the section whose name value is at `name`: the value of the key `field`, or the
    /// quoted name `value`; else `name`.
    fn within(
        text: &str,
        name: Range<usize>,
        field: Option<&str>,
        value: Option<&str>,
    ) -> Range<usize> {
        // The section: from its header to the next header.
        let start = text[..name.start].rfind("\n[").map_or(0, |k| k + 1);
        let end = text[name.end..]
            .find("\n[")
            .map_or(text.len(), |k| name.end + k);
        let section = &text[start..end];
        let found = field.and_then(|f| key_value_span(section, f)).or_else(|| {
            let v = format!("\"{}\"", value?);
            section.find(&v).map(|k| k..k + v.len())
        });
        found.map_or(name, |r| start + r.start..start + r.end)
    }

    /// The span of a joint or driver or body by name.
    pub fn element(&self, name: &str) -> Option<Range<usize>> {
        self.joints
            .get(name)
            .or_else(|| self.curves.get(name))
            .or_else(|| self.drivers.get(name))
            .or_else(|| self.couplers.get(name))
            .or_else(|| self.bodies.get(name))
            .or_else(|| self.forces.get(name))
            .or_else(|| self.limits.get(name))
            .or_else(|| self.frictions.get(name))
            .cloned()
    }
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

/// What to write.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outputs {
    /// (body, point).
    pub points: Vec<(String, String)>,
    /// Joint names.
    pub joints: Vec<String>,
    /// Body names.
    pub bodies: Vec<String>,
    /// Whether `[analysis.outputs]` gives `points`, `joints` or `bodies` (even an empty list):
    /// then only the groups listed are written; otherwise every element of the three groups.
    pub listed: bool,
    /// Dynamic: joints whose reactions are written (`None`: all joints).
    pub reactions: Option<Vec<String>>,
    /// Dynamic and inverse dynamics: write the energy table (with power, work and balance).
    pub energy: bool,
    /// Inverse dynamics: write the mass matrix and bias forces in the drivers' coordinates.
    pub joint_space: bool,
    /// Inverse dynamics: (body, point) whose Jacobians are written.
    pub jacobians: Vec<(String, String)>,
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
    /// Kinematic: degrees of freedom no driver prescribes refused or held (`free_dof`).
    pub free_dof: cardan_mechanism::FreeDof,
    /// Kinematic, inverse dynamics: run an inconsistent over-constrained model with its
    /// disagreeing rows dropped (`inconsistent_joints = "drop"`).
    pub drop_inconsistent: bool,
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
    /// `[parameters]`, evaluated (with the values given from outside).
    pub parameters: std::sync::Arc<crate::parameters::Parameters>,
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
    /// The effort rating (`effort_limit`, SI), if given.
    pub effort_limit: Option<f64>,
    /// The rate rating (`rate_limit`, SI), if given.
    pub rate_limit: Option<f64>,
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
