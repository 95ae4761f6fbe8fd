//! From a parsed model file to a [`MechanismBuilder`], checking everything that can be pinned to
//! a place in the file: names (with suggestions), duplicates, numbers, axes, mass and inertia,
//! self-joints, function parameters. What only the mechanism can judge (DOF, assembly) is
//! checked later, and mapped back to the element's line through [`Spans`].

mod analysis;
mod body;
mod cam;
mod context;
mod coupler;
mod curve;
mod driver;
mod force;
mod joint;
mod limit;
mod loaded;
mod shape;
mod surface;

pub use analysis::MAX_STORED_FRAMES;
pub(crate) use body::orientation_matrix;
pub use context::fmt_vec;
pub use loaded::{
    Analysis, AnalysisKind, BodyVelocity, JointEntry, Loaded, Outputs, Spans, StaticKind,
    DEFAULT_SPARSE_MODES,
};

use body::{body_velocity, load_body};
use context::{check_unique_element, Ctx, Features, Resolver};
use driver::load_driver;
use joint::load_joint;

use crate::diag::{Error, Source};
use crate::file::ModelFile;
use crate::units::UnitSystem;
use crate::vocabulary::{CAMS, COUPLERS, CURVES, DRIVERS, FORCES, MATERIALS, SHAPES, SURFACES};
use cardan_constraints::drivers::POSE_ROWS;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::Force;
use cardan_mechanism::{pose_row_name, DriverTarget, MechanismBuilder, Quantity, GROUND};
use std::collections::HashMap;

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
        parameters: &file.parameters,
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
    load_curves(&resolver, file, &mut spans, &mut builder)?;
    load_couplers(&cx, file, &mut spans, &mut builder)?;
    let drivers = load_drivers(&resolver, file, &mut spans, &mut builder)?;
    load_forces(&resolver, file, &joints.kinds, &mut spans, &mut forces)?;
    load_limits(&cx, file, &joints.kinds, &mut spans, &mut builder)?;
    load_shapes(&resolver, file, &mut spans, &mut builder)?;

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
        parameters: file.parameters.clone(),
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
        let rating = |v: &Option<crate::file::Num>, key: &str| -> Result<Option<f64>, Error> {
            let Some(v) = v else { return Ok(None) };
            let x = *v.get_ref();
            if x.is_finite() && x > 0.0 {
                Ok(Some(x))
            } else {
                Err(r.cx.err(
                    v.span(),
                    format!("joint \"{jname}\": {key} = {x} must be a positive number"),
                ))
            }
        };
        out.list.push(JointEntry {
            name: jname.clone(),
            kind: spec.kind,
            body_i: spec.body_i.clone(),
            body_j: spec.body_j.clone(),
            effort_limit: rating(&j.effort_limit, "effort_limit")?,
            rate_limit: rating(&j.rate_limit, "rate_limit")?,
        });
        out.kinds.insert(jname, spec.kind);
        builder.joint(spec);
    }
    Ok(out)
}

/// `[[curve]]`, `[[cam]]` and `[[surface]]`: each point-on-curve element, cam pair and
/// point-on-surface element, its kind checked against its table (`build/curve.rs`,
/// `build/cam.rs`, `build/surface.rs`).
fn load_curves(
    r: &Resolver,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<(), Error> {
    for section in &file.curve {
        let c = section.get_ref();
        check_unique_element(r.cx, spans, &c.name, "curve")?;
        let owner = format!("curve \"{}\"", c.name.get_ref());
        let table = section.span().start;
        let entry = r.cx.check(&CURVES, &owner, &c.kind, table, c.name.span())?;
        spans.curves.insert(c.name.get_ref().clone(), c.name.span());
        builder.curve(curve::load_curve(r, section, entry.name)?);
    }
    for section in &file.cam {
        let c = section.get_ref();
        check_unique_element(r.cx, spans, &c.name, "cam")?;
        let owner = format!("cam \"{}\"", c.name.get_ref());
        let table = section.span().start;
        let entry =
            r.cx.check(&CAMS, &owner, &c.follower, table, c.name.span())?;
        spans.curves.insert(c.name.get_ref().clone(), c.name.span());
        builder.cam(cam::load_cam(r, section, entry.name)?);
    }
    for section in &file.surface {
        let c = section.get_ref();
        check_unique_element(r.cx, spans, &c.name, "surface")?;
        let owner = format!("surface \"{}\"", c.name.get_ref());
        let table = section.span().start;
        let entry =
            r.cx.check(&SURFACES, &owner, &c.kind, table, c.name.span())?;
        spans.curves.insert(c.name.get_ref().clone(), c.name.span());
        builder.surface(surface::load_surface(r, section, entry.name)?);
    }
    Ok(())
}

/// `[[material]]` and `[[shape]]`: the contact materials and the collision shapes
/// (`build/shape.rs`); a shape's mesh file is relative to the model file.
fn load_shapes(
    r: &Resolver,
    file: &ModelFile,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<(), Error> {
    let cx = r.cx;
    for section in &file.material {
        let m = section.get_ref();
        let owner = format!("material \"{}\"", m.name.get_ref());
        let law = m
            .law
            .clone()
            .unwrap_or_else(|| toml::Spanned::new(m.name.span(), "hunt_crossley".to_string()));
        cx.check(
            &MATERIALS,
            &owner,
            &law,
            section.span().start,
            m.name.span(),
        )?;
        if let Some(first) = spans
            .materials
            .insert(m.name.get_ref().clone(), m.name.span())
        {
            return Err(duplicate(cx, &m.name, "material", &first));
        }
        builder.material(shape::load_material(cx, section)?);
    }
    let dir = cx.src.path.parent().unwrap_or(std::path::Path::new("."));
    for section in &file.shape {
        let s = section.get_ref();
        let owner = format!("shape \"{}\"", s.name.get_ref());
        let entry = cx.check(
            &SHAPES,
            &owner,
            &s.kind,
            section.span().start,
            s.name.span(),
        )?;
        if let Some(first) = spans.shapes.insert(s.name.get_ref().clone(), s.name.span()) {
            return Err(duplicate(cx, &s.name, "shape", &first));
        }
        builder.shape(shape::load_shape(r, section, entry.name, dir)?);
    }
    Ok(())
}

/// A second `what` of the name at `name`, the first at `first`.
fn duplicate(
    cx: &Ctx,
    name: &crate::file::Name,
    what: &str,
    first: &std::ops::Range<usize>,
) -> Error {
    let l = cx.src.location(first.start);
    cx.err(
        name.span(),
        format!(
            "duplicate {what} name \"{}\" (first defined at line {})",
            name.get_ref(),
            l.line
        ),
    )
}

/// `[[limit]]` and `[[friction]]`: each limit and joint friction (`build/limit.rs`).
fn load_limits(
    cx: &Ctx,
    file: &ModelFile,
    kinds: &HashMap<String, JointKind>,
    spans: &mut Spans,
    builder: &mut MechanismBuilder,
) -> Result<(), Error> {
    for section in &file.limit {
        let l = section.get_ref();
        check_unique_element(cx, spans, &l.name, "limit")?;
        spans.limits.insert(l.name.get_ref().clone(), l.name.span());
        builder.limit(limit::load_limit(cx, section, kinds)?);
    }
    for section in &file.friction {
        let f = section.get_ref();
        check_unique_element(cx, spans, &f.name, "friction")?;
        spans
            .frictions
            .insert(f.name.get_ref().clone(), f.name.span());
        builder.friction(limit::load_friction(cx, section, kinds)?);
    }
    Ok(())
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
        if d.kind.get_ref() == "path" {
            let path = driver::load_path(r.cx, d)?;
            let what = format!("parameter of curve {}", path.curve);
            out.names.push((path.name.clone(), what));
            out.functions
                .push((path.function.clone(), Quantity::Length));
            builder.path(path);
            continue;
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
