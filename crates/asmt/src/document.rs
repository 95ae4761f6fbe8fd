//! The second pass: the tree of lines → a typed [`Document`], every element with its file line.
//!
//! Sections and fields follow OndselSolver's reader (`ASMTAssembly::parseASMT` and the item
//! classes; project notes `shared/asmt/README.md` §1.2–1.7). The reader is stricter than
//! OndselSolver where OndselSolver would crash or guess: a missing required field, a number that
//! does not parse or is not finite, or an unknown joint kind is an error naming the line.
//! Sections cardan does not use (AllowRotation, force elements, curves and surfaces, animation
//! settings) are read and listed in [`Document::ignored`]; limits are read ([`Limit`]).

use crate::error::{AsmtError, Result};
use crate::scalar::{clip, number};
use crate::series::{self, TimeSeries};
use crate::tree::{self, Node};
use nalgebra::{Matrix3, Vector3};

/// A frame given in its parent: origin and the rotation matrix whose columns are the frame's
/// axes in the parent's components (r_parent = position + rotation · r_local).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Origin in the parent frame.
    pub position: Vector3<f64>,
    /// Direction-cosine matrix (local → parent).
    pub rotation: Matrix3<f64>,
}

impl Frame {
    /// The identity frame.
    pub fn identity() -> Self {
        Self {
            position: Vector3::zeros(),
            rotation: Matrix3::identity(),
        }
    }

    /// This frame followed by `inner` (inner given in this frame): the composition
    /// r = p + A (p_inner + A_inner r_local).
    pub fn then(&self, inner: &Frame) -> Frame {
        Frame {
            position: self.position + self.rotation * inner.position,
            rotation: self.rotation * inner.rotation,
        }
    }
}

/// A marker: a named frame, given in its part frame (or the assembly frame for ground markers),
/// its RefPoint composed in.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// The marker's name (the last element of its path).
    pub name: String,
    /// Line of its `Marker` label.
    pub line: usize,
    /// The frame in the part (or assembly) frame: RefPoint ∘ Marker.
    pub frame: Frame,
}

/// The principal mass marker: the centre-of-mass frame with principal axes, given in the part
/// frame, and the mass data.
#[derive(Debug, Clone, PartialEq)]
pub struct MassMarker {
    /// Line of `PrincipalMassMarker`.
    pub line: usize,
    /// The CM frame in the part frame.
    pub frame: Frame,
    /// Mass.
    pub mass: f64,
    /// Principal moments of inertia about the CM axes.
    pub inertias: [f64; 3],
}

/// A part (a moving body).
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Name.
    pub name: String,
    /// Line of its `Part` label.
    pub line: usize,
    /// The part frame P in the assembly frame (the input pose).
    pub frame: Frame,
    /// Velocity of P (global; an initial guess in OndselSolver).
    pub velocity: Vector3<f64>,
    /// Angular velocity (global).
    pub omega: Vector3<f64>,
    /// The CM frame and mass data.
    pub mass: MassMarker,
    /// Its markers, in file order.
    pub markers: Vec<Marker>,
}

/// A path to a marker or joint with the line it is written on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PathRef {
    /// The full path, e.g. `/Assembly1/Part1/Marker1`.
    pub path: String,
    /// Its line.
    pub line: usize,
}

/// The 22 joint kinds OndselSolver reads (notes §1.4).
pub const JOINT_KINDS: [&str; 22] = [
    "AngleJoint",
    "GearJoint",
    "NoRotationJoint",
    "ParallelAxesJoint",
    "PerpendicularJoint",
    "RackPinionJoint",
    "ScrewJoint",
    "ConstantVelocityJoint",
    "FixedJoint",
    "RevoluteJoint",
    "SphericalJoint",
    "UniversalJoint",
    "SphSphJoint",
    "CylSphJoint",
    "RevCylJoint",
    "RevRevJoint",
    "CylindricalJoint",
    "PointInLineJoint",
    "TranslationalJoint",
    "LineInPlaneJoint",
    "PlanarJoint",
    "PointInPlaneJoint",
];

/// The number fields joints take (lower case; 0 when absent in OndselSolver).
const JOINT_NUMBERS: [&str; 8] = [
    "distanceIJ",
    "theIzJz",
    "radiusI",
    "radiusJ",
    "pitchRadius",
    "pitch",
    "offset",
    "aConstant",
];

/// A joint block.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// One of [`JOINT_KINDS`].
    pub kind: String,
    /// Name.
    pub name: String,
    /// Line of the kind label.
    pub line: usize,
    /// Marker I.
    pub marker_i: PathRef,
    /// Marker J.
    pub marker_j: PathRef,
    /// The numeric fields present (`distanceIJ`, `radiusI`, ...), with their lines.
    pub numbers: Vec<Field<f64>>,
}

impl Joint {
    /// The value of number field `name`, if present.
    pub fn number(&self, name: &str) -> Option<f64> {
        self.numbers
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.value)
    }
}

/// A named field of a block: its name, its value and the file line of the value.
#[derive(Debug, Clone, PartialEq)]
pub struct Field<T> {
    /// The field's label (`distanceIJ`, `RotationZ`, ...).
    pub name: String,
    /// Its value.
    pub value: T,
    /// The file line of the value.
    pub line: usize,
}

/// A value with the file line it was read from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Located<T> {
    /// The value.
    pub value: T,
    /// Its file line.
    pub line: usize,
}

/// The motion kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// `RotationalMotion`: `RotationZ` (the joint angle).
    Rotational,
    /// `TranslationalMotion`: `TranslationZ` (the slide along z_I).
    Translational,
    /// `GeneralMotion`: `rIJI1..3`, `angIJJ1..3`, `RotationOrder`.
    General,
}

/// A motion block.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// Kind.
    pub kind: MotionKind,
    /// Name.
    pub name: String,
    /// Line of the kind label.
    pub line: usize,
    /// `MotionJoint`, if given.
    pub joint: Option<PathRef>,
    /// `MarkerI`, if given.
    pub marker_i: Option<PathRef>,
    /// `MarkerJ`, if given.
    pub marker_j: Option<PathRef>,
    /// The expressions by field (`RotationZ`, or the six of a general motion), each with its
    /// text and line.
    pub expressions: Vec<Field<String>>,
    /// `RotationOrder` of a general motion (e.g. [1, 2, 3]).
    pub rotation_order: Option<Located<[u8; 3]>>,
}

/// A limit block (`RotationLimit`, `TranslationLimit`; notes §1.6): the angle or the slide of
/// a joint (AngleZ(I→J), z_I·(r_J − r_I), as a motion measures it) bounded by a constant.
#[derive(Debug, Clone, PartialEq)]
pub struct Limit {
    /// A `RotationLimit` (else a `TranslationLimit`).
    pub rotation: bool,
    /// Name.
    pub name: String,
    /// Line of the kind label.
    pub line: usize,
    /// `MotionJoint`, if given.
    pub joint: Option<PathRef>,
    /// `MarkerI`, if given.
    pub marker_i: Option<PathRef>,
    /// `MarkerJ`, if given.
    pub marker_j: Option<PathRef>,
    /// `Limit`: the bound's expression.
    pub limit: Field<String>,
    /// `Type`: `=<` (the coordinate stays at most the limit: an upper bound) or `=>` (at least:
    /// a lower bound).
    pub upper: bool,
}

/// An element read and not used (limits, AllowRotation, force elements, ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ignored {
    /// Its block label (`RotationLimit`, `AllowRotation`, `ForceTorque`, ...).
    pub kind: String,
    /// Its name when it has one.
    pub name: Option<String>,
    /// Its line.
    pub line: usize,
    /// Why it is ignored.
    pub reason: &'static str,
}

/// `SimulationParameters`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Simulation {
    /// Line of the section.
    pub line: usize,
    /// Start time.
    pub tstart: f64,
    /// End time.
    pub tend: f64,
    /// Minimum step.
    pub hmin: f64,
    /// Maximum step.
    pub hmax: f64,
    /// Output interval.
    pub hout: f64,
    /// Error tolerance (read, unused by OndselSolver).
    pub error_tol: f64,
}

/// A whole ASMT file.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// Line 1: the writer.
    pub header: String,
    /// The assembly's name.
    pub name: String,
    /// The assembly's `Notes` line (may be empty).
    pub notes: String,
    /// The assembly frame (identity in every known file).
    pub frame: Frame,
    /// Ground markers (in the assembly frame).
    pub ground: Vec<Marker>,
    /// Parts, in file order.
    pub parts: Vec<Part>,
    /// Joints, in file order.
    pub joints: Vec<Joint>,
    /// Motions, in file order.
    pub motions: Vec<Motion>,
    /// The limits (`ConstraintSets` → `Limits`).
    pub limits: Vec<Limit>,
    /// Elements read and not used.
    pub ignored: Vec<Ignored>,
    /// `ConstantGravity` and its line.
    pub gravity: Option<Located<Vector3<f64>>>,
    /// `SimulationParameters`.
    pub simulation: Option<Simulation>,
    /// The stored `TimeSeries`, if any.
    pub series: Option<TimeSeries>,
    /// The last line of the model: the file's last line, or the `TimeSeries` label's line.
    pub lines: usize,
}

impl Document {
    /// Whether the file was written by OndselSolver's C++ code (FreeCAD), not the Smalltalk
    /// program (FreeCAD exports are in millimetres).
    pub fn written_by_freecad(&self) -> bool {
        self.header.starts_with("OndselSolver")
    }

    /// The largest distance of a part frame or marker from the assembly origin, in the file's
    /// units.
    pub fn size(&self) -> f64 {
        let mut size: f64 = 0.0;
        for m in &self.ground {
            size = size.max(m.frame.position.norm());
        }
        for p in &self.parts {
            size = size.max(p.frame.position.norm());
            for m in &p.markers {
                size = size.max(p.frame.then(&m.frame).position.norm());
            }
        }
        size
    }

    /// Whether the file looks like a FreeCAD export in millimetres: written by OndselSolver's
    /// C++ code with parts or markers more than 10 length units from the origin (FreeCAD's
    /// positions are 13–1900 mm in OndselSolver's examples; SI mechanisms of that size are
    /// rare).
    pub fn looks_like_millimetres(&self) -> bool {
        self.written_by_freecad() && self.size() > 10.0
    }

    /// The document with every length multiplied by `s` (e.g. 1e-3 for a file in millimetres
    /// read as SI): positions, velocities, gravity, joint lengths, offsets, pitches and radii,
    /// translational motion expressions (wrapped as `s*(…)`); inertias by s². Masses, angles
    /// and times are unchanged; the TimeSeries is dropped (it is in the file's units).
    pub fn scaled(&self, s: f64) -> Document {
        let mut d = self.clone();
        let frame = |f: &mut Frame| f.position *= s;
        frame(&mut d.frame);
        for m in &mut d.ground {
            frame(&mut m.frame);
        }
        for p in &mut d.parts {
            frame(&mut p.frame);
            frame(&mut p.mass.frame);
            p.velocity *= s;
            for i in &mut p.mass.inertias {
                *i *= s * s;
            }
            for m in &mut p.markers {
                frame(&mut m.frame);
            }
        }
        for j in &mut d.joints {
            for Field { name, value: v, .. } in &mut j.numbers {
                if matches!(
                    name.as_str(),
                    "distanceIJ" | "offset" | "pitch" | "pitchRadius" | "radiusI" | "radiusJ"
                ) {
                    *v *= s;
                }
            }
        }
        for m in &mut d.motions {
            for Field {
                name: field,
                value: text,
                ..
            } in &mut m.expressions
            {
                let length = field == "TranslationZ" || field.starts_with("rIJI");
                if length && !text.trim().is_empty() {
                    *text = format!("{s:?}*({text})");
                }
            }
        }
        if let Some(Located { value: g, .. }) = &mut d.gravity {
            *g *= s;
        }
        d.series = None;
        d
    }
}

/// Reads an ASMT text, its stored `TimeSeries` included.
///
/// # Errors
/// The first problem, located at its line.
pub fn read(text: &str) -> Result<Document> {
    read_with(text, true)
}

/// Reads the model of an ASMT text: everything but the rows of a stored `TimeSeries`
/// ([`Document::series`] is `None`), which a run replaces (in a solved file they are 95 % of the
/// text).
///
/// # Errors
/// The first problem, located at its line.
pub fn read_model(text: &str) -> Result<Document> {
    read_with(text, false)
}

fn read_with(text: &str, with_series: bool) -> Result<Document> {
    let tree = tree::parse(text)?;
    let header = tree.header.text.to_string();
    if !(header.starts_with("OndselSolver") || header.starts_with("freeCAD")) {
        return Err(AsmtError::new(
            tree.header.line,
            format!("the first line is \"{}\"; an ASMT file starts with \"OndselSolver\" or \"freeCAD: 3D CAD with Motion Simulation  by  askoh.com\"", clip(&header)),
        ));
    }
    let end = tree.lines;
    let asm = match tree.roots.as_slice() {
        [a] if a.label() == "Assembly" => a,
        [] => {
            return Err(AsmtError::new(
                end,
                "the file ends before its \"Assembly\" block",
            ))
        }
        [a, ..] if a.label() != "Assembly" => {
            return Err(AsmtError::new(
                a.line,
                format!("expected \"Assembly\", found \"{}\"", clip(a.label())),
            ))
        }
        [a] => {
            return Err(AsmtError::new(
                a.line,
                format!("expected \"Assembly\", found \"{}\"", clip(a.label())),
            ))
        }
        [_, b, ..] => {
            return Err(AsmtError::new(
                b.line,
                format!(
                    "unexpected \"{}\" after the Assembly block (only a TimeSeries may follow it)",
                    clip(b.label())
                ),
            ))
        }
    };
    let mut doc = assembly(asm, header, end)?;
    if let Some(block) = tree.series.filter(|_| with_series) {
        doc.series = Some(series::parse(block.line, block.rows(text))?);
    }
    Ok(doc)
}

/// The fields of a block: its child labels, looked up by name.
struct Block<'a> {
    node: &'a Node<'a>,
    what: String,
}

impl<'a> Block<'a> {
    fn new(node: &'a Node<'a>, what: impl Into<String>) -> Self {
        Self {
            node,
            what: what.into(),
        }
    }

    fn get(&self, label: &str) -> Option<&'a Node<'a>> {
        self.node.children.iter().find(|c| c.label() == label)
    }

    fn require(&self, label: &str) -> Result<&'a Node<'a>> {
        self.get(label).ok_or_else(|| {
            AsmtError::new(
                self.node.line,
                format!("{} has no \"{label}\" field", self.what),
            )
        })
    }

    /// The first value line under field `label`.
    fn value(&self, label: &str) -> Result<&'a Node<'a>> {
        let f = self.require(label)?;
        f.children.first().ok_or_else(|| {
            AsmtError::new(
                f.line,
                format!("the field \"{label}\" of {} has no value line", self.what),
            )
        })
    }

    fn string(&self, label: &str) -> Result<String> {
        Ok(self.value(label)?.text.trim_start().to_string())
    }

    // The element's description is formatted only for a message (a file has hundreds of
    // numbers and no error, usually).
    fn number(&self, label: &str) -> Result<f64> {
        let v = self.value(label)?;
        number(v.label(), v.line, "")
            .or_else(|_| number(v.label(), v.line, &format!("\"{label}\" of {}", self.what)))
    }

    fn vector(&self, label: &str) -> Result<Vector3<f64>> {
        let v = self.value(label)?;
        vector(v, "").or_else(|_| vector(v, &format!("\"{label}\" of {}", self.what)))
    }

    fn matrix(&self, label: &str) -> Result<Matrix3<f64>> {
        let f = self.require(label)?;
        if f.children.len() != 3 {
            return Err(AsmtError::new(
                f.line,
                format!(
                    "\"{label}\" of {} has {} rows; a rotation matrix has 3",
                    self.what,
                    f.children.len()
                ),
            ));
        }
        let mut m = Matrix3::zeros();
        for (i, row) in f.children.iter().enumerate() {
            let r = vector(row, "").or_else(|_| {
                vector(
                    row,
                    &format!("row {} of \"{label}\" of {}", i + 1, self.what),
                )
            })?;
            m.set_row(i, &r.transpose());
        }
        check_rotation(&m, f.line, "")
            .or_else(|_| check_rotation(&m, f.line, &format!("\"{label}\" of {}", self.what)))
    }

    fn frame(&self) -> Result<Frame> {
        Ok(Frame {
            position: self.vector("Position3D")?,
            rotation: self.matrix("RotationMatrix")?,
        })
    }

    fn path(&self, label: &str) -> Result<PathRef> {
        let v = self.value(label)?;
        Ok(PathRef {
            path: v.label().to_string(),
            line: v.line,
        })
    }

    fn optional_path(&self, label: &str) -> Result<Option<PathRef>> {
        match self.get(label) {
            None => Ok(None),
            Some(_) => self.path(label).map(Some),
        }
    }
}

fn vector(node: &Node, what: &str) -> Result<Vector3<f64>> {
    let parts: Vec<&str> = node.text.split_whitespace().collect();
    if parts.len() != 3 {
        return Err(AsmtError::new(
            node.line,
            format!(
                "{what}: expected 3 numbers separated by blanks, found {}",
                parts.len()
            ),
        ));
    }
    let mut v = Vector3::zeros();
    for (k, p) in parts.iter().enumerate() {
        v[k] = number(p, node.line, what)?;
    }
    Ok(v)
}

/// Largest |AᵀA − I| accepted in a rotation matrix. Smalltalk-written files round their
/// matrices (circular.asmt: 4e-6); OndselSolver converts them to Euler parameters as they are.
const ROTATION_TOLERANCE: f64 = 1e-3;

/// A rotation matrix must be orthonormal with determinant +1 to [`ROTATION_TOLERANCE`]; the
/// nearest rotation (polar decomposition A (AᵀA)^(−1/2) = U Vᵀ from the SVD) is returned.
fn check_rotation(m: &Matrix3<f64>, line: usize, what: &str) -> Result<Matrix3<f64>> {
    let orth = (m.transpose() * m - Matrix3::identity()).abs().max();
    let det = m.determinant();
    if orth.is_nan() || orth > ROTATION_TOLERANCE || det <= 0.0 {
        return Err(AsmtError::new(
            line,
            format!("{what} is not a rotation matrix (|AᵀA − I| = {orth:.2e}, det = {det:.6})"),
        ));
    }
    if orth <= 1e-13 {
        return Ok(*m);
    }
    let svd = m.svd(true, true);
    match (svd.u, svd.v_t) {
        (Some(u), Some(v_t)) => Ok(u * v_t),
        _ => Err(AsmtError::new(
            line,
            format!("{what}: no nearest rotation found"),
        )),
    }
}

fn assembly(asm: &Node, header: String, end: usize) -> Result<Document> {
    let b = Block::new(asm, "the assembly");
    let name = b.string("Name")?;
    let notes = b
        .get("Notes")
        .and_then(|n| n.children.first())
        .map(|n| n.text.to_string())
        .unwrap_or_default();
    let frame = Frame {
        position: b
            .get("Position3D")
            .map(|_| b.vector("Position3D"))
            .transpose()?
            .unwrap_or_else(Vector3::zeros),
        rotation: b
            .get("RotationMatrix")
            .map(|_| b.matrix("RotationMatrix"))
            .transpose()?
            .unwrap_or_else(Matrix3::identity),
    };
    let mut ignored = Vec::new();
    let ground = match b.get("RefPoints") {
        Some(r) => ref_points(r, &format!("the assembly \"{name}\""))?,
        None => Vec::new(),
    };
    ignore_geometry(&b, &mut ignored);
    let parts = parts(&b, &mut ignored)?;
    require_sections(&b)?;
    let mut limits = Vec::new();
    let (joints, motions) = constraint_sets(&b, &mut ignored, &mut limits)?;
    ignore_force_torques(&b, &mut ignored);
    let gravity = match b.get("ConstantGravity") {
        Some(g) => Some(Located {
            value: b.vector("ConstantGravity")?,
            line: g.line,
        }),
        None => None,
    };
    let simulation = simulation(&b)?;
    Ok(Document {
        header,
        name,
        notes,
        frame,
        ground,
        parts,
        joints,
        motions,
        limits,
        ignored,
        gravity,
        simulation,
        series: None,
        lines: end,
    })
}

/// The assembly's curves, surfaces and kinematic IJs, listed as ignored.
fn ignore_geometry(b: &Block, ignored: &mut Vec<Ignored>) {
    for sec in ["RefCurves", "RefSurfaces", "KinematicIJs"] {
        if let Some(s) = b.get(sec) {
            for c in &s.children {
                ignored.push(Ignored {
                    kind: c.label().to_string(),
                    name: None,
                    line: c.line,
                    reason: "curves, surfaces and kinematic IJs are not read by cardan (nor solved by OndselSolver's C++ code)",
                });
            }
        }
    }
}

/// The `Parts` list (required), each part read by [`part`].
fn parts(b: &Block, ignored: &mut Vec<Ignored>) -> Result<Vec<Part>> {
    let parts_node = b.require("Parts")?;
    let mut parts = Vec::new();
    for p in &parts_node.children {
        if p.label() != "Part" {
            return Err(AsmtError::new(
                p.line,
                format!(
                    "expected \"Part\" in the Parts list, found \"{}\"",
                    clip(p.label())
                ),
            ));
        }
        parts.push(part(p, ignored)?);
    }
    Ok(parts)
}

/// The sections OndselSolver requires (`ConstraintSets`, `ConstantGravity`,
/// `SimulationParameters`, `AnimationParameters`) and the fields of `AnimationParameters`.
fn require_sections(b: &Block) -> Result<()> {
    // OndselSolver reads the sections in order and all of them; a missing one is a truncated
    // or damaged file.
    for sec in [
        "ConstraintSets",
        "ConstantGravity",
        "SimulationParameters",
        "AnimationParameters",
    ] {
        b.require(sec)?;
    }
    let anim = Block::new(b.require("AnimationParameters")?, "AnimationParameters");
    for f in [
        "nframe",
        "icurrent",
        "istart",
        "iend",
        "isForward",
        "framesPerSecond",
    ] {
        anim.value(f)?;
    }
    Ok(())
}

/// The joints, motions and limits of `ConstraintSets`; `AllowRotation` motions and general
/// constraint sets are listed as ignored.
fn constraint_sets(
    b: &Block,
    ignored: &mut Vec<Ignored>,
    limits: &mut Vec<Limit>,
) -> Result<(Vec<Joint>, Vec<Motion>)> {
    let mut joints = Vec::new();
    let mut motions = Vec::new();
    if let Some(cs) = b.get("ConstraintSets") {
        for sec in &cs.children {
            match sec.label() {
                "Joints" => {
                    for j in &sec.children {
                        joints.push(joint(j)?);
                    }
                }
                "Motions" => {
                    for m in &sec.children {
                        if m.label() == "AllowRotation" {
                            ignored.push(ignored_item(
                                m,
                                "AllowRotation is a dragging helper; OndselSolver drops it after assembly",
                            ));
                        } else {
                            motions.push(motion(m)?);
                        }
                    }
                }
                "Limits" => {
                    for l in &sec.children {
                        limits.push(limit(l)?);
                    }
                }
                "GeneralConstraintSets" => {
                    for g in &sec.children {
                        ignored.push(ignored_item(g, "general constraint sets are not read"));
                    }
                }
                other => {
                    return Err(AsmtError::new(
                        sec.line,
                        format!("unknown section \"{}\" in ConstraintSets (expected Joints, Motions, Limits, GeneralConstraintSets)", clip(other)),
                    ))
                }
            }
        }
    }
    Ok((joints, motions))
}

/// The force elements of `ForceTorques`, listed as ignored.
fn ignore_force_torques(b: &Block, ignored: &mut Vec<Ignored>) {
    if let Some(ft) = b.get("ForceTorques") {
        for f in &ft.children {
            ignored.push(ignored_item(
                f,
                "force elements are not read (OndselSolver has no solver object for them either)",
            ));
        }
    }
}

/// `SimulationParameters`, if present: times and steps, with OndselSolver's defaults for
/// `hmin`, `hmax` and `errorTol`; tend ≥ tstart and a positive hout when they differ.
fn simulation(b: &Block) -> Result<Option<Simulation>> {
    let simulation = match b.get("SimulationParameters") {
        Some(s) => {
            let sb = Block::new(s, "SimulationParameters");
            let sim = Simulation {
                line: s.line,
                tstart: sb.number("tstart")?,
                tend: sb.number("tend")?,
                hmin: sb
                    .get("hmin")
                    .map(|_| sb.number("hmin"))
                    .transpose()?
                    .unwrap_or(1e-9),
                hmax: sb
                    .get("hmax")
                    .map(|_| sb.number("hmax"))
                    .transpose()?
                    .unwrap_or(1.0),
                hout: sb.number("hout")?,
                error_tol: sb
                    .get("errorTol")
                    .map(|_| sb.number("errorTol"))
                    .transpose()?
                    .unwrap_or(1e-6),
            };
            if sim.tend < sim.tstart {
                return Err(AsmtError::new(
                    s.line,
                    format!(
                        "SimulationParameters: tend = {} is before tstart = {}",
                        sim.tend, sim.tstart
                    ),
                ));
            }
            if sim.tend > sim.tstart && sim.hout <= 0.0 {
                return Err(AsmtError::new(
                    s.line,
                    format!("SimulationParameters: hout = {} must be positive", sim.hout),
                ));
            }
            Some(sim)
        }
        None => None,
    };
    Ok(simulation)
}

fn ignored_item(node: &Node, reason: &'static str) -> Ignored {
    Ignored {
        kind: node.label().to_string(),
        name: Block::new(node, "")
            .get("Name")
            .and_then(|n| n.children.first())
            .map(|n| n.label().to_string()),
        line: node.line,
        reason,
    }
}

fn ref_points(node: &Node, owner: &str) -> Result<Vec<Marker>> {
    let mut markers = Vec::new();
    for rp in &node.children {
        if rp.label() != "RefPoint" {
            return Err(AsmtError::new(
                rp.line,
                format!(
                    "expected \"RefPoint\" in the RefPoints of {owner}, found \"{}\"",
                    clip(rp.label())
                ),
            ));
        }
        let b = Block::new(rp, format!("a RefPoint of {owner}"));
        let base = b.frame()?;
        let Some(list) = b.get("Markers") else {
            continue;
        };
        for m in &list.children {
            if m.label() != "Marker" {
                return Err(AsmtError::new(
                    m.line,
                    format!(
                        "expected \"Marker\" in a Markers list of {owner}, found \"{}\"",
                        clip(m.label())
                    ),
                ));
            }
            let mb = Block::new(m, format!("a marker of {owner}"));
            let name = mb.string("Name")?;
            let mb = Block::new(m, format!("marker \"{name}\" of {owner}"));
            let frame = base.then(&mb.frame()?);
            markers.push(Marker {
                name,
                line: m.line,
                frame,
            });
        }
    }
    Ok(markers)
}

fn part(node: &Node, ignored: &mut Vec<Ignored>) -> Result<Part> {
    let b = Block::new(node, "a part");
    let name = b.string("Name")?;
    let what = format!("part \"{name}\"");
    let b = Block::new(node, what.clone());
    let frame = b.frame()?;
    let zero = |label: &str| -> Result<Vector3<f64>> {
        match b.get(label) {
            Some(_) => b.vector(label),
            None => Ok(Vector3::zeros()),
        }
    };
    let velocity = zero("Velocity3D")?;
    let omega = zero("Omega3D")?;
    let pm = b.require("PrincipalMassMarker")?;
    let mb = Block::new(pm, format!("the principal mass marker of {what}"));
    let inertia_node = mb.value("MomentOfInertias")?;
    let inertias = vector(inertia_node, &format!("\"MomentOfInertias\" of {what}"))?;
    let mass = MassMarker {
        line: pm.line,
        frame: mb.frame()?,
        mass: mb.number("Mass")?,
        inertias: [inertias[0], inertias[1], inertias[2]],
    };
    if mass.mass < 0.0 || inertias.iter().any(|i| *i < 0.0) {
        return Err(AsmtError::new(
            pm.line,
            format!("{what} has a negative mass or moment of inertia"),
        ));
    }
    let markers = match b.get("RefPoints") {
        Some(r) => ref_points(r, &what)?,
        None => Vec::new(),
    };
    for sec in ["RefCurves", "RefSurfaces"] {
        if let Some(s) = b.get(sec) {
            for c in &s.children {
                ignored.push(Ignored {
                    kind: c.label().to_string(),
                    name: Some(name.clone()),
                    line: c.line,
                    reason: "curves and surfaces of parts are not read",
                });
            }
        }
    }
    Ok(Part {
        name,
        line: node.line,
        frame,
        velocity,
        omega,
        mass,
        markers,
    })
}

fn joint(node: &Node) -> Result<Joint> {
    let kind = node.label();
    if !JOINT_KINDS.contains(&kind) {
        return Err(AsmtError::new(
            node.line,
            format!(
                "unknown joint kind \"{}\"; OndselSolver's kinds are {}",
                clip(kind),
                JOINT_KINDS.join(", ")
            ),
        ));
    }
    let b = Block::new(node, format!("a {kind}"));
    let name = b.string("Name")?;
    let b = Block::new(node, format!("{kind} \"{name}\""));
    let mut numbers = Vec::new();
    for field in JOINT_NUMBERS {
        if b.get(field).is_some() {
            let v = b.value(field)?;
            numbers.push(Field {
                name: field.to_string(),
                value: b.number(field)?,
                line: v.line,
            });
        }
    }
    Ok(Joint {
        kind: kind.to_string(),
        name,
        line: node.line,
        marker_i: b.path("MarkerI")?,
        marker_j: b.path("MarkerJ")?,
        numbers,
    })
}

fn motion(node: &Node) -> Result<Motion> {
    let (kind, fields): (MotionKind, &[&str]) = match node.label() {
        "RotationalMotion" => (MotionKind::Rotational, &["RotationZ"]),
        "TranslationalMotion" => (MotionKind::Translational, &["TranslationZ"]),
        "GeneralMotion" => (
            MotionKind::General,
            &["rIJI1", "rIJI2", "rIJI3", "angIJJ1", "angIJJ2", "angIJJ3"],
        ),
        other => {
            return Err(AsmtError::new(
                node.line,
                format!("unknown motion kind \"{}\"; known: RotationalMotion, TranslationalMotion, GeneralMotion, AllowRotation", clip(other)),
            ))
        }
    };
    let b = Block::new(node, format!("a {}", node.label()));
    let name = b.string("Name")?;
    let b = Block::new(node, format!("{} \"{name}\"", node.label()));
    let mut expressions = Vec::new();
    for f in fields {
        // An absent or empty expression is 0 (OndselSolver parses empty text as 0).
        match b.get(f) {
            None => expressions.push(Field {
                name: f.to_string(),
                value: String::new(),
                line: node.line,
            }),
            Some(field) => {
                let text: Vec<&str> = field.children.iter().map(|c| c.text.trim()).collect();
                let line = field.children.first().map_or(field.line, |c| c.line);
                expressions.push(Field {
                    name: f.to_string(),
                    value: text.join(" "),
                    line,
                });
            }
        }
    }
    let rotation_order = match b.get("RotationOrder") {
        None => None,
        Some(_) => {
            let v = b.value("RotationOrder")?;
            let axes: Vec<&str> = v.text.split_whitespace().collect();
            let parsed: Option<Vec<u8>> = axes
                .iter()
                .map(|a| a.parse::<u8>().ok().filter(|k| (1..=3).contains(k)))
                .collect();
            match parsed.as_deref() {
                Some(&[a, b, c]) if a != b && b != c => Some(Located {
                    value: [a, b, c],
                    line: v.line,
                }),
                _ => {
                    return Err(AsmtError::new(
                        v.line,
                        format!(
                            "RotationOrder of motion \"{name}\" is \"{}\"; expected three axis numbers 1–3, neighbours different (e.g. \"1 2 3\")",
                            clip(v.label())
                        ),
                    ))
                }
            }
        }
    };
    let joint = b.optional_path("MotionJoint")?;
    let marker_i = b.optional_path("MarkerI")?;
    let marker_j = b.optional_path("MarkerJ")?;
    if joint.is_none() && (marker_i.is_none() || marker_j.is_none()) {
        return Err(AsmtError::new(
            node.line,
            format!("motion \"{name}\" names neither a MotionJoint nor both MarkerI and MarkerJ"),
        ));
    }
    Ok(Motion {
        kind,
        name,
        line: node.line,
        joint,
        marker_i,
        marker_j,
        expressions,
        rotation_order,
    })
}

/// A `RotationLimit` or `TranslationLimit` block: `Name`, `MotionJoint` or `MarkerI` and
/// `MarkerJ`, `Limit` (an expression), `Type` (`=<` or `=>`; `<=`, `>=` accepted), `Tol` (the
/// drag solver's tolerance: read past).
fn limit(node: &Node) -> Result<Limit> {
    let rotation = match node.label() {
        "RotationLimit" => true,
        "TranslationLimit" => false,
        other => {
            return Err(AsmtError::new(
                node.line,
                format!(
                    "unknown limit kind \"{}\"; known: RotationLimit, TranslationLimit",
                    clip(other)
                ),
            ))
        }
    };
    let b = Block::new(node, format!("a {}", node.label()));
    let name = b.string("Name")?;
    let b = Block::new(node, format!("{} \"{name}\"", node.label()));
    let value = b.value("Limit")?;
    let limit = Field {
        name: "Limit".into(),
        value: value.text.trim().to_string(),
        line: value.line,
    };
    let kind = b.value("Type")?;
    let upper = match kind.text.trim() {
        "=<" | "<=" => true,
        "=>" | ">=" => false,
        other => {
            return Err(AsmtError::new(
                kind.line,
                format!(
                    "Type of limit \"{name}\" is \"{}\"; expected =< (at most the limit) or => (at least)",
                    clip(other)
                ),
            ))
        }
    };
    let joint = b.optional_path("MotionJoint")?;
    let marker_i = b.optional_path("MarkerI")?;
    let marker_j = b.optional_path("MarkerJ")?;
    if joint.is_none() && (marker_i.is_none() || marker_j.is_none()) {
        return Err(AsmtError::new(
            node.line,
            format!("limit \"{name}\" names neither a MotionJoint nor both MarkerI and MarkerJ"),
        ));
    }
    Ok(Limit {
        rotation,
        name,
        line: node.line,
        joint,
        marker_i,
        marker_j,
        limit,
        upper,
    })
}
