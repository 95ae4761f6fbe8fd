//! A [`Document`] → cardan's elements ([`Import`]), each with the ASMT path and line it comes
//! from; [`Import::builder`] turns them into a [`MechanismBuilder`].
//!
//! ## Frames (notes §1.3)
//! A part's frame P is given in the assembly frame; its principal mass marker (the CM frame with
//! principal axes) in P; each marker in a RefPoint in P. cardan's body frame is the CM frame, so
//!
//! ```text
//! body position      r_cm = r_P + A_P r_Pcm           orientation  A_cm = A_P A_Pcm
//! marker in the body  s'  = A_Pcmᵀ (r_Pm − r_Pcm)      axes         A_Pcmᵀ A_Pm  (columns x, y, z)
//! ```
//!
//! (OndselSolver's `rpmp`, `aApm`). A marker m becomes point `m` and vectors `m_x`, `m_z` on its
//! body; joint point_i/axis_i/x_axis_i = origin, z and x of marker I (likewise J).
//!
//! ## Joints, motions and couplers
//! Each ASMT joint kind maps to the cardan kind with the same equations (notes §3):
//! Fixed → fixed, Revolute → revolute, Cylindrical → cylindrical, Translational → prismatic,
//! Spherical → spherical, Universal → universal, Planar → planar, SphSph → spherical_spherical,
//! PointInPlane → point_in_plane, PointInLine → point_in_line, LineInPlane → line_in_plane,
//! NoRotation → no_rotation, ParallelAxes → parallel_axes, Perpendicular → perpendicular,
//! Angle → cone, ConstantVelocity → constant_velocity (marker J's z reversed: OndselSolver's
//! markers face each other, x_Iᵀy_J + y_Iᵀx_J, cardan's point the same way, x_iᵀy_j − y_iᵀx_j),
//! CylSph → cyl_sph, RevCyl → rev_cyl, RevRev → rev_rev.
//!
//! RotationalMotion and TranslationalMotion on a joint become rotation and translation drivers of
//! that joint (the same rows: notes §3); GeneralMotion a `general_motion` (pose) driver between
//! its two marker frames. The expressions are translated ([`crate::expr`]).
//!
//! Gear, RackPinion and Screw joints are cardan couplers, which relate the coordinates of two
//! joints on a common carrier. The importer finds, for the parts of markers I and J, the two joints
//! that hold them on one common body and writes OndselSolver's law in those joints' coordinates:
//! with u = ±1 the direction of each motion along or about the ASMT marker's axis (the joint's
//! axis direction relative to the marker's, and whether the part is body j or body i of its joint),
//!
//! ```text
//! gear   θ_orb(I in J) + (r_I/r_J) θ_orb(J in I) = c   ⇒  θ_B = −(r_I/r_J) u_A u_B θ_A + c
//! rack   x_Iᵀd + R θz(I→J) = c                         ⇒  s + R u_S u_R θ = c
//! screw  2π z_Iᵀd − p θz(I→J) = c                      ⇒  s = (p/2π) u_S u_R θ + c
//! ```
//!
//! The constants come from the input pose, as in OndselSolver. A screw whose two parts are held
//! by one joint that turns and slides (a cylindrical joint) becomes cardan's one-joint screw
//! s − (p/2π) θ = c on that joint. Couplers whose parts are held neither way (a gear or rack whose
//! joints share no body) are refused at their line: cardan's couplers relate joint coordinates.
//!
//! ## Names
//! cardan names are ASCII letters, digits and `_`: every other character becomes `_`, a leading
//! digit gets a `_` before it, and a clash gets `_2`, `_3`, …; the ASMT path of each element is
//! kept ([`Element::path`]) for messages and for `cardan import`'s comments.

use crate::document::{Document, Field, Frame, Joint, Located, Motion, MotionKind, Part, PathRef};
use crate::error::{AsmtError, Result, Warning};
use crate::expr;
use cardan_constraints::expression::Expression;
use cardan_constraints::{JointKind, RotationOrder, TimeFunction};
use cardan_eulerparam::p_from_rotation_matrix;
use cardan_mechanism::{
    Body, CouplerSpec, DriverSpec, ForceSpec, GearRatio, JointSpec, LimitSpec, MechanismBuilder,
    Orientation, PoseTarget, GROUND,
};
use nalgebra::{Matrix3, Vector3};
use std::collections::{HashMap, HashSet};

/// A cardan element and where it comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Element<T> {
    /// The element.
    pub spec: T,
    /// Its ASMT path (`/Assembly1/Joint1`).
    pub path: String,
    /// Its ASMT line.
    pub line: usize,
}

/// A named point or vector on a body.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    /// Body name (`ground` for the assembly).
    pub body: String,
    /// Feature name.
    pub name: String,
    /// Body-frame components (global for ground).
    pub value: Vector3<f64>,
    /// The marker's ASMT path.
    pub path: String,
}

/// A moving body and its part.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyMap {
    /// The body (CM frame).
    pub body: Body,
    /// The part's ASMT path.
    pub path: String,
    /// The part's line.
    pub line: usize,
    /// The CM frame in the part frame (to convert results back to the part frame).
    pub cm: Frame,
}

impl BodyMap {
    /// The part frame (origin, rotation) from the body's CM position and rotation:
    /// A_P = A_cm A_Pcmᵀ, r_P = r_cm − A_P r_Pcm.
    pub fn part_frame(&self, r_cm: &Vector3<f64>, a_cm: &Matrix3<f64>) -> Frame {
        let rotation = a_cm * self.cm.rotation.transpose();
        Frame {
            position: r_cm - rotation * self.cm.position,
            rotation,
        }
    }
}

/// The simulation settings of the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Output interval.
    pub dt: f64,
    /// Largest integration step (`hmax`; a dynamic analysis's `h_max`).
    pub h_max: f64,
    /// The integrator's error tolerance (`errorTol`; a dynamic analysis's `rtol` when cardan
    /// accepts it).
    pub error_tol: f64,
}

impl Settings {
    /// Number of output steps (round((t_end − t_start)/dt); 0 for a single configuration).
    pub fn steps(&self) -> usize {
        if self.t_end <= self.t_start || self.dt <= 0.0 {
            0
        } else {
            ((self.t_end - self.t_start) / self.dt).round() as usize
        }
    }
}

/// An ASMT file as cardan elements.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    /// Model name (the assembly's, sanitised).
    pub name: String,
    /// The assembly's ASMT name.
    pub asmt_name: String,
    /// Moving bodies, in part order.
    pub bodies: Vec<BodyMap>,
    /// Points (ground and bodies).
    pub points: Vec<Feature>,
    /// Vectors (ground and bodies).
    pub vectors: Vec<Feature>,
    /// Joints.
    pub joints: Vec<Element<JointSpec>>,
    /// Couplers (gear, rack and pinion, screw joints).
    pub couplers: Vec<Element<CouplerSpec>>,
    /// Drivers (motions).
    pub drivers: Vec<Element<DriverSpec>>,
    /// Limits (`RotationLimit`, `TranslationLimit`).
    pub limits: Vec<Element<LimitSpec>>,
    /// Gravity, if the file has a nonzero one.
    pub gravity: Option<Vector3<f64>>,
    /// The file's analysis.
    pub settings: Option<Settings>,
    /// What was read and not used, or used with a caveat.
    pub warnings: Vec<Warning>,
    /// The analysis the model file written by [`crate::toml_out`] asks for (the file's time
    /// grid in every case).
    pub analysis: AnalysisKind,
    /// The units of the numbers, written as the model file's `[model] units`: `"SI"`, or
    /// `"mm"` for a document read in millimetres (not converted: the model file converts).
    pub units: &'static str,
}

/// The analysis of an imported model: the file's kinematics (OndselSolver's own), or more.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AnalysisKind {
    /// Kinematics over tstart..tend by hout.
    #[default]
    Kinematic,
    /// Inverse dynamics on the same grid (driver efforts, reactions; needs masses).
    InverseDynamics,
    /// Forward dynamics from the input pose at rest, output every hout (needs masses).
    Dynamic,
}

impl AnalysisKind {
    /// The model file's `[analysis] kind`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kinematic => "kinematic",
            Self::InverseDynamics => "inverse_dynamics",
            Self::Dynamic => "dynamic",
        }
    }

    /// Whether the analysis needs a mass on every part.
    pub fn needs_masses(self) -> bool {
        self != Self::Kinematic
    }
}

impl Import {
    /// The mechanism (bodies, features, joints, couplers, drivers, limits, gravity).
    pub fn builder(&self) -> MechanismBuilder {
        let mut b = MechanismBuilder::new();
        for m in &self.bodies {
            b.body(m.body.clone());
        }
        for p in &self.points {
            b.point(&p.body, &p.name, p.value);
        }
        for v in &self.vectors {
            b.vector(&v.body, &v.name, v.value);
        }
        for j in &self.joints {
            b.joint(j.spec.clone());
        }
        for c in &self.couplers {
            b.coupler(c.spec.clone());
        }
        for d in &self.drivers {
            b.driver(d.spec.clone());
        }
        for l in &self.limits {
            b.limit(l.spec.clone());
        }
        if let Some(g) = self.gravity {
            b.force(ForceSpec::Gravity { g });
        }
        b
    }

    /// The body mapped from the part with ASMT path `path`.
    pub fn body_of_part(&self, path: &str) -> Option<&BodyMap> {
        self.bodies.iter().find(|b| b.path == path)
    }

    /// The cardan name of the element with ASMT path `path` (body, joint, coupler or driver).
    pub fn name_of(&self, path: &str) -> Option<&str> {
        self.bodies
            .iter()
            .find(|b| b.path == path)
            .map(|b| b.body.name.as_str())
            .or_else(|| {
                self.joints
                    .iter()
                    .find(|j| j.path == path)
                    .map(|j| j.spec.name.as_str())
            })
            .or_else(|| {
                self.couplers
                    .iter()
                    .find(|j| j.path == path)
                    .map(|j| j.spec.name.as_str())
            })
            .or_else(|| {
                self.drivers
                    .iter()
                    .find(|j| j.path == path)
                    .map(|j| j.spec.name.as_str())
            })
    }
}

/// A marker resolved: its body, point and vectors, its frame in the body (CM) frame and in
/// global coordinates at the input pose.
#[derive(Debug, Clone)]
struct MarkerRef {
    body: String,
    point: String,
    x: String,
    z: String,
    local: Frame,
    global: Frame,
}

/// Unique cardan names.
#[derive(Default)]
struct Names {
    used: HashSet<String>,
}

impl Names {
    fn reserve(&mut self, name: &str) {
        self.used.insert(name.to_string());
    }

    fn unique(&mut self, asmt: &str) -> String {
        let base = sanitize(asmt);
        let mut name = base.clone();
        let mut k = 2;
        while self.used.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.used.insert(name.clone());
        name
    }
}

/// ASCII letters, digits and `_`; other characters become `_`; never empty, never a leading
/// digit.
pub fn sanitize(name: &str) -> String {
    let mut s: String = name
        .trim()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

struct Ctx<'a> {
    doc: &'a Document,
    markers: HashMap<String, MarkerRef>,
    /// Joint path → (cardan name, kind, body_i, body_j, global z of marker i).
    joints: HashMap<String, JointRef>,
    joint_order: Vec<String>,
    element_names: Names,
    import: Import,
}

#[derive(Debug, Clone)]
struct JointRef {
    name: String,
    kind: JointKind,
    body_i: String,
    body_j: String,
    z_i: Vector3<f64>,
    marker_i: String,
    marker_j: String,
}

/// Maps a document to cardan elements.
///
/// # Errors
/// A marker path that names no marker, a joint between markers of one part, a motion on a
/// missing joint or on a joint that cannot take it, an expression that does not translate, a
/// coupler whose parts are not held on a common body: each at its line.
pub fn import(doc: &Document) -> Result<Import> {
    let name = sanitize(&doc.name);
    let mut cx = Ctx {
        doc,
        markers: HashMap::new(),
        joints: HashMap::new(),
        joint_order: Vec::new(),
        element_names: Names::default(),
        import: Import {
            name,
            asmt_name: doc.name.clone(),
            bodies: Vec::new(),
            points: Vec::new(),
            vectors: Vec::new(),
            joints: Vec::new(),
            couplers: Vec::new(),
            drivers: Vec::new(),
            limits: Vec::new(),
            gravity: None,
            settings: None,
            warnings: Vec::new(),
            analysis: AnalysisKind::Kinematic,
            units: "SI",
        },
    };
    cx.ground()?;
    let mut body_names = Names::default();
    body_names.reserve(GROUND);
    for part in &doc.parts {
        cx.part(part, &mut body_names)?;
    }
    for j in &doc.joints {
        if !matches!(
            j.kind.as_str(),
            "GearJoint" | "RackPinionJoint" | "ScrewJoint"
        ) {
            cx.joint(j)?;
        }
    }
    for j in &doc.joints {
        if matches!(
            j.kind.as_str(),
            "GearJoint" | "RackPinionJoint" | "ScrewJoint"
        ) {
            cx.coupler(j)?;
        }
    }
    for m in &doc.motions {
        cx.motion(m)?;
    }
    for l in &doc.limits {
        cx.limit(l)?;
    }
    for ig in &doc.ignored {
        let named = ig
            .name
            .as_ref()
            .map(|n| format!(" \"{n}\""))
            .unwrap_or_default();
        cx.import.warnings.push(Warning {
            line: ig.line,
            message: format!("{}{named} ignored: {}", ig.kind, ig.reason),
        });
    }
    if let Some(Located { value: g, .. }) = doc.gravity {
        if g != Vector3::zeros() {
            cx.import.gravity = Some(doc.frame.rotation * g);
        }
    }
    if let Some(s) = &doc.simulation {
        cx.import.settings = Some(Settings {
            t_start: s.tstart,
            t_end: s.tend,
            dt: s.hout,
            h_max: s.hmax,
            error_tol: s.error_tol,
        });
    }
    Ok(cx.import)
}

impl Ctx<'_> {
    fn asm_path(&self) -> String {
        format!("/{}", self.doc.name)
    }

    fn ground(&mut self) -> Result<()> {
        let mut names = Names::default();
        for m in &self.doc.ground {
            let path = format!("{}/{}", self.asm_path(), m.name);
            let global = self.doc.frame.then(&m.frame);
            let point = names.unique(&m.name);
            self.feature(GROUND, &point, &global, &global, &path, m.line)?;
        }
        Ok(())
    }

    /// Declares point, x and z of a marker and records it.
    fn feature(
        &mut self,
        body: &str,
        point: &str,
        local: &Frame,
        global: &Frame,
        path: &str,
        line: usize,
    ) -> Result<()> {
        if self.markers.contains_key(path) {
            return Err(AsmtError::new(
                line,
                format!("a second marker with the path {path}"),
            ));
        }
        let (x, z) = (format!("{point}_x"), format!("{point}_z"));
        let f = |name: &str, value| Feature {
            body: body.into(),
            name: name.into(),
            value,
            path: path.into(),
        };
        self.import.points.push(f(point, local.position));
        self.import
            .vectors
            .push(f(&x, local.rotation.column(0).into_owned()));
        self.import
            .vectors
            .push(f(&z, local.rotation.column(2).into_owned()));
        self.markers.insert(
            path.to_string(),
            MarkerRef {
                body: body.into(),
                point: point.into(),
                x,
                z,
                local: *local,
                global: *global,
            },
        );
        Ok(())
    }

    fn part(&mut self, part: &Part, body_names: &mut Names) -> Result<()> {
        let path = format!("{}/{}", self.asm_path(), part.name);
        let name = body_names.unique(&part.name);
        let frame = self.doc.frame.then(&part.frame);
        let cm_global = frame.then(&part.mass.frame);
        let p = p_from_rotation_matrix(&cm_global.rotation)
            .map_err(|e| AsmtError::new(part.line, format!("part {path}: orientation: {e}")))?;
        let mut body = Body::new(name.clone())
            .position(cm_global.position)
            .orientation(Orientation::EulerParams({
                let v: nalgebra::Vector4<f64> = p.into();
                [v[0], v[1], v[2], v[3]]
            }));
        let m = &part.mass;
        if m.mass > 0.0 {
            body = body
                .mass(m.mass)
                .inertia_diagonal(m.inertias[0], m.inertias[1], m.inertias[2]);
        } else {
            self.import.warnings.push(Warning {
                line: m.line,
                message: format!(
                    "part {path} has no mass (mass {}): fine for kinematics; inverse and forward dynamics need masses",
                    m.mass
                ),
            });
        }
        self.import.bodies.push(BodyMap {
            body,
            path: path.clone(),
            line: part.line,
            cm: m.frame,
        });
        let cm_t = m.frame.rotation.transpose();
        let mut names = Names::default();
        for mk in &part.markers {
            let local = Frame {
                position: cm_t * (mk.frame.position - m.frame.position),
                rotation: cm_t * mk.frame.rotation,
            };
            let global = frame.then(&mk.frame);
            let point = names.unique(&mk.name);
            let mpath = format!("{path}/{}", mk.name);
            self.feature(&name, &point, &local, &global, &mpath, mk.line)?;
        }
        Ok(())
    }

    fn marker(&self, path: &str, line: usize, what: &str) -> Result<MarkerRef> {
        self.markers.get(path).cloned().ok_or_else(|| {
            AsmtError::new(
                line,
                format!(
                    "{what}: no marker has the path \"{}\" (marker paths are /<assembly>/<marker> or /<assembly>/<part>/<marker>)",
                    crate::scalar::clip(path)
                ),
            )
        })
    }

    fn joint(&mut self, j: &Joint) -> Result<()> {
        let path = format!("{}/{}", self.asm_path(), j.name);
        let what = format!("{} {path}", j.kind);
        let mi = self.marker(&j.marker_i.path, j.marker_i.line, &what)?;
        let mj = self.marker(&j.marker_j.path, j.marker_j.line, &what)?;
        if mi.body == mj.body {
            return Err(AsmtError::new(
                j.line,
                format!(
                    "{what} joins two markers of the same {}; a joint connects two parts",
                    if mi.body == GROUND {
                        "assembly (ground)"
                    } else {
                        "part"
                    }
                ),
            ));
        }
        let kind = match j.kind.as_str() {
            "FixedJoint" => JointKind::Fixed,
            "RevoluteJoint" => JointKind::Revolute,
            "CylindricalJoint" => JointKind::Cylindrical,
            "TranslationalJoint" => JointKind::Prismatic,
            "SphericalJoint" => JointKind::Spherical,
            "UniversalJoint" => JointKind::Universal,
            "PlanarJoint" => JointKind::Planar,
            "SphSphJoint" => JointKind::SphericalSpherical,
            "PointInPlaneJoint" => JointKind::PointInPlane,
            "PointInLineJoint" => JointKind::PointInLine,
            "LineInPlaneJoint" => JointKind::LineInPlane,
            "NoRotationJoint" => JointKind::NoRotation,
            "ParallelAxesJoint" => JointKind::ParallelAxes,
            "PerpendicularJoint" => JointKind::Perpendicular,
            "AngleJoint" => JointKind::Cone,
            "ConstantVelocityJoint" => JointKind::ConstantVelocity,
            "CylSphJoint" => JointKind::CylSph,
            "RevCylJoint" => JointKind::RevCyl,
            "RevRevJoint" => JointKind::RevRev,
            other => {
                return Err(AsmtError::new(
                    j.line,
                    format!("joint kind {other} has no cardan counterpart"),
                ))
            }
        };
        let name = self.element_names.unique(&j.name);
        let mut spec = JointSpec::new(
            name.clone(),
            kind,
            (&mi.body, &mi.point),
            (&mj.body, &mj.point),
        );
        let info = kind.info();
        use cardan_constraints::joints::Axes;
        let mut zj = mj.z.clone();
        if kind == JointKind::ConstantVelocity {
            // OndselSolver's markers face each other; cardan's shafts point the same way.
            zj = format!("{}_zr", mj.point);
            let local = -mj.local.rotation.column(2).into_owned();
            self.import.vectors.push(Feature {
                body: mj.body.clone(),
                name: zj.clone(),
                value: local,
                path: j.marker_j.path.clone(),
            });
        }
        match info.axes {
            Axes::Required(_) | Axes::Optional(_) => {
                spec = spec.axes(&mi.z, &zj);
                if info.x_axes {
                    spec = spec.x_axes(&mi.x, &mj.x);
                }
            }
            Axes::OnlyI(_) => {
                spec = spec.axis_i(&mi.z);
                if info.x_axes {
                    spec = spec.x_axis_i(&mi.x);
                }
            }
            Axes::Unused => {}
        }
        if info.length {
            match j.number("distanceIJ") {
                Some(d) if d > 0.0 => spec = spec.length(d),
                _ => self.import.warnings.push(Warning {
                    line: j.line,
                    message: format!(
                        "{what} has no positive distanceIJ (OndselSolver takes 0 when absent); cardan uses the distance as drawn"
                    ),
                }),
            }
        }
        if info.offset {
            if let Some(h) = j.number("offset") {
                spec = spec.offset(h);
            }
        }
        if kind == JointKind::Cone {
            // OndselSolver's AngleJoint: z_I·z_J − cos θ, cardan's cone (θ = 0 when absent).
            let (a, line) = j
                .numbers
                .iter()
                .find(|f| f.name == "theIzJz")
                .map_or((0.0, j.line), |f| (f.value, f.line));
            let m = cardan_constraints::joints::CONE_MARGIN;
            if !(m..=std::f64::consts::PI - m).contains(&a) {
                return Err(AsmtError::new(
                    line,
                    format!(
                        "{what}: theIzJz = {a} rad; cardan's cone joint (z_I·z_J − cos θ) \
                         needs θ from 0.001 to π − 0.001 rad: nearer 0 or π the row loses rank \
                         (OndselSolver leaves it unenforced). For parallel axes use a \
                         ParallelAxesJoint"
                    ),
                ));
            }
            spec = spec.angle(a);
        }
        self.import.joints.push(Element {
            spec,
            path: path.clone(),
            line: j.line,
        });
        self.joints.insert(
            path.clone(),
            JointRef {
                name,
                kind,
                body_i: mi.body.clone(),
                body_j: mj.body.clone(),
                z_i: mi.global.rotation.column(2).into_owned(),
                marker_i: j.marker_i.path.clone(),
                marker_j: j.marker_j.path.clone(),
            },
        );
        self.joint_order.push(path);
        Ok(())
    }

    /// The joints (in file order) holding `body` to another body, with a capability.
    fn holders(&self, body: &str, able: fn(JointKind) -> bool) -> Vec<(JointRef, String, f64)> {
        self.joint_order
            .iter()
            .map(|p| &self.joints[p])
            .filter(|j| able(j.kind))
            .filter_map(|j| {
                if j.body_j == body {
                    Some((j.clone(), j.body_i.clone(), 1.0))
                } else if j.body_i == body {
                    Some((j.clone(), j.body_j.clone(), -1.0))
                } else {
                    None
                }
            })
            .collect()
    }

    fn coupler(&mut self, j: &Joint) -> Result<()> {
        let path = format!("{}/{}", self.asm_path(), j.name);
        let what = format!("{} {path}", j.kind);
        let mi = self.marker(&j.marker_i.path, j.marker_i.line, &what)?;
        let mj = self.marker(&j.marker_j.path, j.marker_j.line, &what)?;
        let turns = |k: JointKind| k.info().rotation.is_some();
        let slides = |k: JointKind| k.info().translation.is_some();
        let need = |field: &str| -> Result<f64> {
            match j.number(field) {
                Some(v) if v != 0.0 => Ok(v),
                _ => Err(AsmtError::new(
                    j.line,
                    format!("{what} needs a nonzero \"{field}\""),
                )),
            }
        };
        // The motion sign u of the part carrying marker m through joint (J, σ) along or about
        // the marker's axis a: σ · sign(a · z_joint).
        let sign = |a: &Vector3<f64>, jr: &JointRef, sigma: f64| -> Result<f64> {
            let c = a.dot(&jr.z_i);
            if c.abs() < 1.0 - 1e-6 {
                return Err(AsmtError::new(
                    j.line,
                    format!(
                        "{what}: the marker axis is not along the axis of joint \"{}\" (cos = {c:.6}); cardan's couplers relate joint coordinates",
                        jr.name
                    ),
                ));
            }
            Ok(sigma * c.signum())
        };
        let zi = mi.global.rotation.column(2).into_owned();
        let xi = mi.global.rotation.column(0).into_owned();
        let name = self.element_names.unique(&j.name);
        let spec = match j.kind.as_str() {
            "GearJoint" => {
                let (ri, rj) = (need("radiusI")?, need("radiusJ")?);
                let (a, b) = self.pair(&mi.body, turns, &mj.body, turns, &what, j.line)?;
                let zj = mj.global.rotation.column(2).into_owned();
                let ua = sign(&zi, &a.0, a.2)?;
                let ub = sign(&zj, &b.0, b.2)?;
                CouplerSpec::gear(
                    name,
                    &a.0.name,
                    &b.0.name,
                    GearRatio::Ratio(-(ri / rj) * ua * ub),
                )
            }
            "ScrewJoint" if self.direct(&mi.body, &mj.body).is_some() => {
                // One joint both turns and slides between the two parts (a cylindrical joint):
                // cardan's one-joint screw s − (p/2π) θ = c. Whichever way the joint and the
                // marker axes point, 2π z_Iᵀd − p θz(I→J) changes by u (2π Δs − p Δθ), u = ±1,
                // so the pitch carries over unchanged.
                let c = self.direct(&mi.body, &mj.body).expect("checked");
                sign(&zi, &c, 1.0)?;
                CouplerSpec::screw(name, &c.name, &c.name, need("pitch")?)
            }
            "RackPinionJoint" | "ScrewJoint" => {
                let rack = j.kind == "RackPinionJoint";
                // Which part slides: marker I's or marker J's (the other turns).
                let direct = self.pair(&mi.body, slides, &mj.body, turns, &what, j.line);
                let (s, r, slide_on_i) = match direct {
                    Ok((s, r)) => (s, r, true),
                    Err(e) => match self.pair(&mj.body, slides, &mi.body, turns, &what, j.line) {
                        Ok((s, r)) => (s, r, false),
                        Err(_) => return Err(e),
                    },
                };
                let axis = if rack { &xi } else { &zi };
                // d = r_J − r_I: the slide moves d by −u (part of I) or +u (part of J).
                let us = sign(axis, &s.0, s.2)? * if slide_on_i { -1.0 } else { 1.0 };
                // θz(I→J): the turn of part J (+) or part I (−) about z_I.
                let ur = sign(&zi, &r.0, r.2)? * if slide_on_i { 1.0 } else { -1.0 };
                if rack {
                    let radius = need("pitchRadius")?;
                    // us·s + R·ur·θ = c  ⇔  s + R·us·ur·θ = c'.
                    CouplerSpec::rack_pinion(name, &s.0.name, &r.0.name, radius * us * ur)
                } else {
                    let pitch = need("pitch")?;
                    // 2π us s − p ur θ = c  ⇔  s = (p us ur / 2π) θ + c'.
                    CouplerSpec::screw(name, &s.0.name, &r.0.name, pitch * us * ur)
                }
            }
            _ => unreachable!("only couplers reach here"),
        };
        self.import.couplers.push(Element {
            spec,
            path,
            line: j.line,
        });
        Ok(())
    }

    /// The first joint (file order) between bodies `a` and `b` that both turns and slides (a
    /// cylindrical joint): the one joint of a screw.
    fn direct(&self, a: &str, b: &str) -> Option<JointRef> {
        self.joint_order
            .iter()
            .map(|p| &self.joints[p])
            .find(|j| {
                let info = j.kind.info();
                info.rotation.is_some()
                    && info.translation.is_some()
                    && ((j.body_i == a && j.body_j == b) || (j.body_i == b && j.body_j == a))
            })
            .cloned()
    }

    /// Two joints, one holding `body_a` (of kind `able_a`) and one holding `body_b`, with one
    /// common other body.
    #[allow(clippy::type_complexity)]
    fn pair(
        &self,
        body_a: &str,
        able_a: fn(JointKind) -> bool,
        body_b: &str,
        able_b: fn(JointKind) -> bool,
        what: &str,
        line: usize,
    ) -> Result<((JointRef, String, f64), (JointRef, String, f64))> {
        for a in self.holders(body_a, able_a) {
            for b in self.holders(body_b, able_b) {
                if a.1 == b.1 && a.1 != body_a && b.1 != body_b && a.0.name != b.0.name {
                    return Ok((a, b));
                }
            }
        }
        Err(AsmtError::new(
            line,
            format!(
                "{what}: cardan couples two joints on a common body, and no such joints hold \"{body_a}\" and \"{body_b}\" (e.g. two revolute joints to the ground for a gear pair)"
            ),
        ))
    }

    fn function(&self, m: &Motion, k: usize) -> Result<TimeFunction> {
        let Field {
            name: field,
            value: text,
            line,
        } = &m.expressions[k];
        let translated = expr::translate(text)
            .map_err(|e| AsmtError::new(*line, format!("{field} of motion \"{}\": {e}", m.name)))?;
        let e = Expression::parse(&translated).map_err(|e| {
            AsmtError::new(
                *line,
                format!(
                    "{field} of motion \"{}\": the translated expression \"{}\" does not parse: {e}",
                    m.name,
                    cardan_constraints::expression::quoted(&translated)
                ),
            )
        })?;
        Ok(TimeFunction::Expression(e))
    }

    fn motion(&mut self, m: &Motion) -> Result<()> {
        let path = format!("{}/{}", self.asm_path(), m.name);
        let what = format!("motion {path}");
        let name = self.element_names.unique(&m.name);
        let spec = match m.kind {
            MotionKind::General => {
                let (Some(pi), Some(pj)) = (&m.marker_i, &m.marker_j) else {
                    return Err(AsmtError::new(
                        m.line,
                        format!("{what}: a GeneralMotion needs MarkerI and MarkerJ"),
                    ));
                };
                let mi = self.marker(&pi.path, pi.line, &what)?;
                let mj = self.marker(&pj.path, pj.line, &what)?;
                let order = m.rotation_order.map_or([1, 2, 3], |o| o.value);
                let letters: String = order
                    .iter()
                    .map(|k| ['x', 'y', 'z'][*k as usize - 1])
                    .collect();
                let order = RotationOrder::parse(&letters).expect("checked by the reader");
                let f = |k| self.function(m, k);
                let functions = [f(0)?, f(1)?, f(2)?, f(3)?, f(4)?, f(5)?];
                DriverSpec::pose(
                    name,
                    PoseTarget {
                        body_i: mi.body.clone(),
                        point_i: mi.point.clone(),
                        axis_i: Some(mi.z.clone()),
                        x_axis_i: Some(mi.x.clone()),
                        body_j: mj.body.clone(),
                        point_j: mj.point.clone(),
                        axis_j: Some(mj.z.clone()),
                        x_axis_j: Some(mj.x.clone()),
                        order,
                        functions,
                    },
                )
            }
            MotionKind::Rotational | MotionKind::Translational => {
                let joint = self.motion_joint(m, &what)?;
                let rotation = m.kind == MotionKind::Rotational;
                let info = joint.kind.info();
                let able = if rotation {
                    info.rotation.is_some()
                } else {
                    info.translation.is_some()
                };
                if !able {
                    return Err(AsmtError::new(
                        m.line,
                        format!(
                            "{what}: its joint \"{}\" is a {}, which cardan cannot drive by {}",
                            joint.name,
                            joint.kind.name(),
                            if rotation { "an angle" } else { "a slide" }
                        ),
                    ));
                }
                let f = self.function(m, 0)?;
                if rotation {
                    DriverSpec::rotation(name, &joint.name, f)
                } else {
                    DriverSpec::translation(name, &joint.name, f)
                }
            }
        };
        self.import.drivers.push(Element {
            spec,
            path,
            line: m.line,
        });
        Ok(())
    }

    /// A limit on a joint's angle or slide (notes §1.6): the joint of its MotionJoint or
    /// markers, as a motion's, the coordinate a RotationalMotion or TranslationalMotion would
    /// drive, bounded by the constant `Limit` from above (`=<`) or below (`=>`). OndselSolver
    /// enforces limits only while dragging; cardan enforces them in every analysis (a
    /// kinematic run stops at one with an error naming it).
    fn limit(&mut self, l: &crate::document::Limit) -> Result<()> {
        let path = format!("{}/{}", self.asm_path(), l.name);
        let what = format!("limit {path}");
        let joint = self.joint_of(
            (&l.joint, &l.marker_i, &l.marker_j),
            l.line,
            &what,
            ("limits", "limit"),
        )?;
        let info = joint.kind.info();
        let coordinate = if l.rotation {
            info.rotation
        } else {
            info.translation
        };
        let Some(coordinate) = coordinate else {
            return Err(AsmtError::new(
                l.line,
                format!(
                    "{what}: its joint \"{}\" is a {}, which has no {} to limit",
                    joint.name,
                    joint.kind.name(),
                    if l.rotation { "angle" } else { "slide" }
                ),
            ));
        };
        let Field {
            value: text, line, ..
        } = &l.limit;
        let translated = expr::translate(text)
            .map_err(|e| AsmtError::new(*line, format!("Limit of {what}: {e}")))?;
        let e = Expression::parse(&translated).map_err(|e| {
            AsmtError::new(
                *line,
                format!("Limit of {what}: \"{translated}\" does not parse: {e}"),
            )
        })?;
        let value = e.eval(0.0).0;
        if !value.is_finite() || e.uses_time() {
            return Err(AsmtError::new(
                *line,
                format!("Limit of {what} is \"{text}\": a limit must be a finite constant"),
            ));
        }
        let name = self.element_names.unique(&l.name);
        let spec = LimitSpec::new(name, &joint.name).coordinate(coordinate);
        let spec = if l.upper {
            spec.upper(value)
        } else {
            spec.lower(value)
        };
        self.import.limits.push(Element {
            spec,
            path,
            line: l.line,
        });
        Ok(())
    }

    /// The joint a rotational or translational motion acts on: its MotionJoint, or the joint
    /// between exactly its two markers.
    fn motion_joint(&self, m: &Motion, what: &str) -> Result<JointRef> {
        let acts = ("drives", "drive");
        self.joint_of((&m.joint, &m.marker_i, &m.marker_j), m.line, what, acts)
    }

    /// The joint named by a MotionJoint, or between exactly two markers (a motion's or a
    /// limit's, at `line`); `acts` says what cardan does with the joint's coordinate
    /// ("drives", "drive").
    fn joint_of(
        &self,
        (joint, marker_i, marker_j): (&Option<PathRef>, &Option<PathRef>, &Option<PathRef>),
        line: usize,
        what: &str,
        (acts, act): (&str, &str),
    ) -> Result<JointRef> {
        if let Some(jp) = joint {
            let Some(j) = self.joints.get(&jp.path) else {
                let coupler = self.import.couplers.iter().any(|c| c.path == jp.path);
                return Err(AsmtError::new(
                    jp.line,
                    if coupler {
                        format!(
                            "{what}: its MotionJoint \"{}\" is a coupler, which cardan cannot {act}",
                            jp.path
                        )
                    } else {
                        format!(
                            "{what}: no joint has the path \"{}\" (MotionJoint must name a joint: /<assembly>/<joint>)",
                            crate::scalar::clip(&jp.path)
                        )
                    },
                ));
            };
            for (given, own) in [(marker_i, &j.marker_i), (marker_j, &j.marker_j)] {
                if let Some(g) = given {
                    if &g.path != own {
                        return Err(AsmtError::new(
                            g.line,
                            format!("{what}: marker {} differs from its joint's marker {own}; cardan {acts} the joint's own coordinate", g.path),
                        ));
                    }
                }
            }
            return Ok(j.clone());
        }
        let (Some(pi), Some(pj)) = (marker_i, marker_j) else {
            unreachable!("the reader requires a joint or two markers")
        };
        self.joint_order
            .iter()
            .map(|p| &self.joints[p])
            .find(|j| j.marker_i == pi.path && j.marker_j == pj.path)
            .cloned()
            .ok_or_else(|| {
                AsmtError::new(
                    line,
                    format!(
                        "{what} has no MotionJoint and no joint connects its markers {} and {}; cardan {acts} joint coordinates",
                        pi.path, pj.path
                    ),
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_sanitised_and_unique() {
        assert_eq!(
            sanitize("Angle:2(0.00 deg)|(Angle)"),
            "Angle_2_0_00_deg___Angle_"
        );
        assert_eq!(sanitize("1st"), "_1st");
        assert_eq!(sanitize(""), "_");
        let mut n = Names::default();
        assert_eq!(n.unique("a b"), "a_b");
        assert_eq!(n.unique("a:b"), "a_b_2");
    }
}
