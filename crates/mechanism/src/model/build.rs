//! [`MechanismBuilder::build`]: a [`MechanismBuilder`] checked and turned into a [`Model`].
//! Names are resolved ([`super::resolve`], one function per element kind), then the rows laid
//! out ([`super::layout`]). Every element name is unique across joints, couplers, drivers and
//! forces. The method is defined here, not in `builder.rs`, so that the builder (the
//! specifications) does not depend on the model.

use super::tree::PredictorTree;
use super::{couplers, curve, friction, layout, limits, resolve, shapes, CurveInfo, Model};
use crate::builder::MechanismBuilder;
use crate::error::ModelError;
use std::collections::HashMap;

impl MechanismBuilder {
    /// Validates everything and builds the immutable [`Model`] (sparsity pattern, row ranges and
    /// index maps computed here, once).
    ///
    /// # Errors
    /// The first problem found, as a [`ModelError`] naming the element.
    pub fn build(&self) -> Result<Model, ModelError> {
        build(self)
    }
}

fn build(b: &MechanismBuilder) -> Result<Model, ModelError> {
    let (mut names, bodies) = resolve::bodies(b)?;
    let (points, vectors) = resolve::features(b, &mut names)?;
    let length = layout::characteristic_length(b, &bodies, &points);

    // Every element name, with the joint index for joints (drivers look their joint up here: a
    // linear search would make building a long driven chain quadratic).
    let mut element_names: HashMap<&str, Option<usize>> = HashMap::new();
    let mut joints = Vec::with_capacity(b.joints.len());
    for spec in &b.joints {
        let what = format!("a {} joint", spec.kind.name());
        unique(&mut element_names, &spec.name, Some(joints.len()), &what)?;
        joints.push(resolve::joint(spec, &names, &bodies)?);
    }
    let mut curves = Vec::with_capacity(b.curves.len());
    for spec in &b.curves {
        unique(
            &mut element_names,
            &spec.name,
            None,
            "a point-on-curve element",
        )?;
        curves.push(curve::curve(spec, curves.len(), &names, &bodies)?);
    }
    for spec in &b.cams {
        unique(&mut element_names, &spec.name, None, "a cam")?;
        let extra = curves.last().map_or(0, |c: &CurveInfo| c.extras().end);
        curves.push(curve::cam(spec, extra, &names, &bodies)?);
    }
    for spec in &b.surfaces {
        unique(
            &mut element_names,
            &spec.name,
            None,
            "a point-on-surface element",
        )?;
        let extra = curves.last().map_or(0, |c: &CurveInfo| c.extras().end);
        curves.push(curve::surface(spec, extra, &names, &bodies)?);
    }
    let mut drivers = Vec::with_capacity(b.drivers.len());
    for spec in &b.drivers {
        unique(&mut element_names, &spec.name, None, "a driver")?;
        drivers.extend(resolve::driver(spec, &names, &joints, &element_names)?);
    }
    let mut paths = Vec::with_capacity(b.paths.len());
    for spec in &b.paths {
        unique(&mut element_names, &spec.name, None, "a path driver")?;
        paths.push(curve::path(spec, &curves)?);
    }
    let mut couplers = Vec::with_capacity(b.couplers.len());
    for spec in &b.couplers {
        unique(&mut element_names, &spec.name, None, "a coupler")?;
    }
    let cx = couplers::Context {
        joints: &joints,
        bodies: &bodies,
        element_names: &element_names,
        length,
    };
    for spec in &b.couplers {
        couplers.push(couplers::coupler(spec, &cx)?);
    }
    let mut forces = Vec::with_capacity(b.forces.len());
    for spec in &b.forces {
        let name = spec.name();
        unique(&mut element_names, name, None, "a force element")?;
        forces.push(resolve::force(spec, name, &names, &bodies)?);
    }

    let (mut limit_infos, mut stops) = (Vec::new(), Vec::new());
    for spec in &b.limits {
        unique(&mut element_names, &spec.name, None, "a limit")?;
        let (info, s) = limits::limit(spec, limit_infos.len(), &joints, &bodies, length)?;
        limit_infos.push(info);
        stops.extend(s);
    }
    let mut frictions = Vec::new();
    for spec in &b.frictions {
        unique(&mut element_names, &spec.name, None, "a friction")?;
        frictions.push(friction::friction(spec, &joints)?);
    }

    let (shapes, materials) =
        shapes::shapes_and_materials(&b.shapes, &b.materials, &bodies, &joints)?;

    let nb = bodies.len();
    let lay = layout::rows(
        &mut joints,
        &mut curves,
        &mut couplers,
        &mut drivers,
        &mut paths,
        nb,
        length,
    );
    let tree = PredictorTree::new(nb, &joints);
    let index = |names: Vec<&str>| -> HashMap<String, usize> {
        names
            .into_iter()
            .enumerate()
            .map(|(k, n)| (n.to_string(), k))
            .collect()
    };
    Ok(Model {
        tree,
        body_at: index(bodies.iter().map(|b| b.name.as_str()).collect()),
        joint_at: index(joints.iter().map(|j| j.name.as_str()).collect()),
        bodies,
        points,
        vectors,
        joints,
        curves,
        paths,
        drivers,
        couplers,
        forces,
        limits: limit_infos,
        stops,
        frictions,
        shapes,
        materials,
        pattern: lay.pattern,
        equation_scales: lay.equation_scales,
        unknown_scales: lay.unknown_scales,
        length,
        num_rows: lay.num_rows,
        joint_rows: lay.joint_rows,
    })
}

/// Enters an element name (with its joint index, for a joint): not empty, not taken by another
/// joint, driver or force (`what` names the element in the empty-name error).
fn unique<'a>(
    names: &mut HashMap<&'a str, Option<usize>>,
    name: &'a str,
    joint: Option<usize>,
    what: &str,
) -> Result<(), ModelError> {
    if name.is_empty() {
        return Err(ModelError::EmptyName { what: what.into() });
    }
    if names.insert(name, joint).is_some() {
        return Err(ModelError::DuplicateElement { name: name.into() });
    }
    Ok(())
}
