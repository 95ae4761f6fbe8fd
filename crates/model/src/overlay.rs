//! Overlays: a model file that names a URDF robot in `[urdf]` and adds what a tree cannot say —
//! joints closing loops (a parallel gripper, a delta robot), drivers moving the joints by
//! functions, forces, shapes, the analysis.
//!
//! ```toml
//! [model]
//! name = "ur5_wave"
//!
//! [urdf]
//! file = "ur5.urdf"        # relative to this file
//! base = "fixed"           # or "floating"; mimic = "couple" | "free"; limits = true | false;
//!                          # damping = true: joints' <dynamics damping> as dampers;
//!                          # friction = true: joints' <dynamics friction> as [[friction]];
//!                          # collision = "steel": the links' <collision> as shapes of a [[material]];
//!                          # self_collision = true: those shapes touch each other too
//!
//! [[driver]]
//! name = "wave"
//! type = "rotation"
//! joint = "shoulder_pan_joint"   # the URDF's joint names (made cardan names: a-z, 0-9, _)
//! function = { kind = "expression", text = "0.5 * sin(2 * t)" }
//!
//! [analysis]
//! kind = "inverse_dynamics"
//! t_end = 2.0
//! output_dt = 0.01
//! ```
//!
//! The robot is imported as `cardan import` would ([`crate::urdf`]) and its bodies, joints,
//! limits, couplers, dampers and ground points are added to the overlay's; the overlay's `[model]`,
//! `[ground]` (merged with the robot's ground points) and `[analysis]` are the model's, with the
//! robot's gravity (0, 0, −9.81) m/s² unless the overlay's `[model]` gives one. Messages
//! about the overlay's own elements point at its lines; the robot's part is checked when it is
//! read, at the URDF's lines.
//!
//! How: the robot's model text is parsed on its own, preceded by the overlay's text blanked to
//! whitespace (every byte a space, line breaks kept), so its spans are offsets into the overlay
//! text followed by the robot's: the source the model keeps for its messages.

use crate::diag::{Error, Source};
use crate::file::{parse, ModelFile};
use crate::urdf::{Base, MimicMode, UrdfOptions};

/// Parses `src`; an overlay (a `[urdf]` table) is expanded with its robot. Returns the source
/// the spans refer to, the file and the import's warnings.
///
/// # Errors
/// As [`parse`]; the URDF's errors at its lines; a `[urdf]` value that is not one of its
/// words.
pub fn parse_overlaid(src: Source) -> Result<(Source, ModelFile, Vec<String>), Error> {
    let mut file = parse(&src)?;
    let Some(urdf) = file.urdf.as_ref() else {
        return Ok((src, file, Vec::new()));
    };
    let options = options(&src, urdf.get_ref())?;
    let dir = src.path.parent().unwrap_or(std::path::Path::new("."));
    let name = urdf.get_ref().file.get_ref();
    let path = dir.join(name);
    let robot = Source::read(&path).map_err(|e| {
        let span = urdf.get_ref().file.span();
        src.error_at(span, format!("[urdf] file: {}", e.message))
    })?;
    let needs_masses = file
        .analysis
        .as_ref()
        .is_none_or(|a| a.get_ref().kind.get_ref() != "kinematic");
    let collision = collision_material(&src, &file)?;
    let (text, warnings) =
        crate::urdf::import_text(&robot, options, needs_masses, false, collision.as_deref())?;
    let blank: String = src
        .text
        .chars()
        .map(|c| {
            if c == '\n' {
                "\n".to_string()
            } else {
                " ".repeat(c.len_utf8())
            }
        })
        .collect();
    let mut combined = Source::from_text(src.path.clone(), format!("{}\n{text}", src.text));
    combined.set = src.set.clone();
    let padded = Source::from_text(src.path.clone(), format!("{blank}\n{text}"));
    let robot_file = parse(&padded)?;
    merge(&combined, &mut file, robot_file)?;
    Ok((combined, file, warnings))
}

/// `[urdf] collision`: the material of the robot's contact shapes, one of the overlay's
/// `[[material]]`s.
///
/// # Errors
/// A name no `[[material]]` has, at the key.
fn collision_material(src: &Source, file: &ModelFile) -> Result<Option<String>, Error> {
    let Some(name) = file
        .urdf
        .as_ref()
        .and_then(|u| u.get_ref().collision.as_ref())
    else {
        return Ok(None);
    };
    // A pair law (`between`) is no material of shapes.
    let known: Vec<&str> = (file.material.iter())
        .filter(|m| m.get_ref().between.is_none())
        .map(|m| m.get_ref().name.get_ref().as_str())
        .collect();
    if known.contains(&name.get_ref().as_str()) {
        return Ok(Some(name.get_ref().clone()));
    }
    let hint = crate::diag::did_you_mean(name.get_ref(), known.iter().copied());
    Err(src.error_at(
        name.span(),
        format!(
            "[urdf] collision = \"{}\": no [[material]] of shapes in this file has that name{hint} (a pair law, with between, is not one); the robot's <collision> shapes are made of it (add a [[material]] with the contact law)",
            name.get_ref()
        ),
    ))
}

/// The import choices of a `[urdf]` table.
fn options(src: &Source, t: &crate::file::UrdfSection) -> Result<UrdfOptions, Error> {
    let word = |v: &Option<crate::file::Name>, key: &str, words: &[&str]| -> Result<usize, Error> {
        let Some(v) = v else { return Ok(0) };
        words.iter().position(|w| w == v.get_ref()).ok_or_else(|| {
            src.error_at(
                v.span(),
                format!(
                    "[urdf] {key} = \"{}\": use {}",
                    v.get_ref(),
                    words.join(" or ")
                ),
            )
        })
    };
    Ok(UrdfOptions {
        base: [Base::Fixed, Base::Floating][word(&t.base, "base", &["fixed", "floating"])?],
        mimic: [MimicMode::Couple, MimicMode::Free][word(&t.mimic, "mimic", &["couple", "free"])?],
        limits: t.limits.unwrap_or(true),
        damping: t.damping.unwrap_or(false),
        friction: t.friction.unwrap_or(false),
        self_collision: t.self_collision.unwrap_or(false),
    })
}

/// Adds the robot's elements to the overlay's. The robot's file is taken apart field by field,
/// so an element kind the import learns to write cannot be left out here unnoticed (the
/// `[[friction]]` tables of `<dynamics friction>` were, at first).
fn merge(src: &Source, file: &mut ModelFile, robot: ModelFile) -> Result<(), Error> {
    let ModelFile {
        model,
        ground,
        body,
        joint,
        curve,
        cam,
        surface,
        driver,
        coupler,
        force,
        limit,
        friction,
        material,
        shape,
        keys,
        // The import writes no [urdf], [analysis] or [parameters] for an overlay.
        urdf: _,
        analysis: _,
        parameters_table: _,
        parameters: _,
    } = robot;
    let gravity = &mut file.model.get_mut().gravity;
    if gravity.is_none() {
        *gravity = model.into_inner().gravity;
    }
    file.body.extend(body);
    file.joint.extend(joint);
    file.curve.extend(curve);
    file.cam.extend(cam);
    file.surface.extend(surface);
    file.driver.extend(driver);
    file.coupler.extend(coupler);
    file.force.extend(force);
    file.limit.extend(limit);
    file.friction.extend(friction);
    file.material.extend(material);
    file.shape.extend(shape);
    file.keys.extend(keys);
    let Some(theirs) = ground else {
        return Ok(());
    };
    let Some(ours) = file.ground.as_mut() else {
        file.ground = Some(theirs);
        return Ok(());
    };
    let (ours, theirs) = (ours.get_mut(), theirs.into_inner());
    for (map, other, what) in [
        (&mut ours.points, theirs.points, "point"),
        (&mut ours.vectors, theirs.vectors, "vector"),
    ] {
        for (k, v) in other {
            if let Some((mine, _)) = map.get_key_value(&k) {
                return Err(src.error_at(
                    mine.span(),
                    format!(
                        "[ground] {what} \"{}\" is also a ground {what} of the robot (its root link's frames); name it otherwise",
                        k.get_ref()
                    ),
                ));
            }
            map.insert(k, v);
        }
    }
    Ok(())
}
