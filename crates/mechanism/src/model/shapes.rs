//! Collision shapes and materials: [`ShapeSpec`] and [`MaterialSpec`] checked and turned into
//! [`ShapeInfo`] and [`MaterialInfo`], with errors naming the shape or material and the key.

use super::elements::{BodyInfo, JointInfo};
use super::validate::suggest;
use super::Model;
use crate::builder::GROUND;
use crate::error::ModelError;
use crate::shape_spec::{Geometry, MaterialSpec, ShapeSpec, Stiffness};
use crate::BodyId;
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;

/// The most vertices (or hull points) one mesh may have: beyond, a model error (decimate the
/// mesh; a collision mesh needs far fewer points than a visual one).
pub const MESH_VERTEX_LIMIT: usize = 200_000;

/// A checked collision shape.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeInfo {
    /// Name.
    pub name: String,
    /// The body.
    pub body: BodyId,
    /// The geometry.
    pub geometry: Geometry,
    /// The centre s' (body frame).
    pub center: Vector3<f64>,
    /// The shape's axes in body components (a rotation).
    pub axes: Matrix3<f64>,
    /// Index into [`Model::materials`].
    pub material: usize,
    /// Collision groups (bits).
    pub groups: u32,
    /// The groups it collides with (bits).
    pub collides_with: u32,
}

/// A checked contact material (see [`MaterialSpec`]).
pub type MaterialInfo = MaterialSpec;

fn bad_shape(spec: &ShapeSpec, key: &str, reason: String) -> ModelError {
    ModelError::BadShape {
        shape: spec.name.clone(),
        key: key.into(),
        reason,
    }
}

fn bad_material(spec: &MaterialSpec, key: &str, reason: String) -> ModelError {
    ModelError::BadMaterial {
        material: spec.name.clone(),
        key: key.into(),
        reason,
    }
}

/// Checks a material's numbers.
pub(crate) fn material(spec: &MaterialSpec) -> Result<MaterialInfo, ModelError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    match spec.stiffness {
        Stiffness::Direct { k, exponent } => {
            if !positive(k) {
                return Err(bad_material(
                    spec,
                    "stiffness",
                    format!("must be > 0, got {k}"),
                ));
            }
            if !(exponent.is_finite() && (1.0..=3.0).contains(&exponent)) {
                return Err(bad_material(
                    spec,
                    "exponent",
                    format!("must lie in [1, 3] (1.5 for Hertz), got {exponent}"),
                ));
            }
        }
        Stiffness::Elastic {
            youngs_modulus,
            poisson_ratio,
        } => {
            if !positive(youngs_modulus) {
                return Err(bad_material(
                    spec,
                    "youngs_modulus",
                    format!("must be > 0, got {youngs_modulus}"),
                ));
            }
            if !(poisson_ratio.is_finite() && (0.0..0.5).contains(&poisson_ratio)) {
                return Err(bad_material(
                    spec,
                    "poisson_ratio",
                    format!("must lie in [0, 0.5), got {poisson_ratio}"),
                ));
            }
        }
    }
    let e = spec.restitution;
    if !(e.is_finite() && e > 0.0 && e <= 1.0) {
        return Err(bad_material(
            spec,
            "restitution",
            format!("must lie in (0, 1], got {e} (a perfectly plastic contact, e = 0, has no finite damping law: use a small e such as 0.05)"),
        ));
    }
    let (ms, md) = (spec.friction_static, spec.friction_dynamic);
    if !(md.is_finite() && md >= 0.0) {
        return Err(bad_material(
            spec,
            "friction",
            format!("μ must be ≥ 0, got {md}"),
        ));
    }
    if !(ms.is_finite() && ms >= md) {
        return Err(bad_material(
            spec,
            "friction_static",
            format!("μ_s must be ≥ μ_d = {md}, got {ms}"),
        ));
    }
    if !positive(spec.slip_velocity) {
        return Err(bad_material(
            spec,
            "slip_velocity",
            format!("must be > 0, got {}", spec.slip_velocity),
        ));
    }
    Ok(spec.clone())
}

/// Checks a geometry's dimensions and points.
fn geometry(spec: &ShapeSpec, ground: bool) -> Result<(), ModelError> {
    let positive = |key: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(bad_shape(spec, key, format!("must be > 0, got {v}")))
        }
    };
    let finite_points = |key: &str, points: &[Vector3<f64>]| {
        if points.is_empty() {
            return Err(bad_shape(spec, key, "the mesh has no points".into()));
        }
        if points.len() > MESH_VERTEX_LIMIT {
            return Err(bad_shape(
                spec,
                key,
                format!(
                    "the mesh has {} points, more than {MESH_VERTEX_LIMIT}: decimate it for collision",
                    points.len()
                ),
            ));
        }
        match points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            Some(i) => Err(bad_shape(
                spec,
                key,
                format!("point {i} is not finite: {:?}", points[i].as_slice()),
            )),
            None => Ok(()),
        }
    };
    match &spec.geometry {
        Geometry::Sphere { radius } => positive("radius", *radius),
        Geometry::Capsule { radius, length } | Geometry::Cylinder { radius, length } => {
            positive("radius", *radius)?;
            positive("length", *length)
        }
        Geometry::Box { size } => size.iter().try_for_each(|&v| positive("size", v)),
        Geometry::Plane => Ok(()),
        Geometry::ConvexMesh { points } => {
            finite_points("mesh", points)?;
            if !spans_volume(points) {
                return Err(bad_shape(
                    spec,
                    "mesh",
                    "the points lie in a plane or a line (a convex mesh needs a volume)".into(),
                ));
            }
            Ok(())
        }
        Geometry::TriangleMesh {
            vertices,
            triangles,
        } => {
            if !ground {
                return Err(bad_shape(
                    spec,
                    "type",
                    "a triangle mesh is a static shape of the ground; on a moving body use a \
                     convex mesh (type = \"convex_mesh\") or split the part into convex pieces"
                        .into(),
                ));
            }
            finite_points("mesh", vertices)?;
            if triangles.is_empty() {
                return Err(bad_shape(spec, "mesh", "the mesh has no triangles".into()));
            }
            let n = vertices.len();
            for (t, tri) in triangles.iter().enumerate() {
                if tri.iter().any(|&i| i as usize >= n) {
                    return Err(bad_shape(
                        spec,
                        "mesh",
                        format!("triangle {t} names vertex {tri:?}, beyond the {n} vertices"),
                    ));
                }
                let [a, b, c] = tri.map(|i| vertices[i as usize]);
                if (b - a).cross(&(c - a)).norm() == 0.0 {
                    return Err(bad_shape(
                        spec,
                        "mesh",
                        format!("triangle {t} is degenerate (zero area)"),
                    ));
                }
            }
            Ok(())
        }
    }
}

/// Whether points span a volume (four of them not in a plane, to roundoff of their extent).
fn spans_volume(points: &[Vector3<f64>]) -> bool {
    let p0 = points[0];
    let extent = points.iter().map(|p| (p - p0).norm()).fold(0.0, f64::max);
    if extent == 0.0 {
        return false;
    }
    let tol = 1e-9 * extent;
    let Some(p1) = points.iter().find(|p| (*p - p0).norm() > tol) else {
        return false;
    };
    let u = (p1 - p0).normalize();
    let Some(p2) = points.iter().find(|p| (*p - p0).cross(&u).norm() > tol) else {
        return false;
    };
    let n = u.cross(&(p2 - p0)).normalize();
    points.iter().any(|p| (p - p0).dot(&n).abs() > tol)
}

/// Checks a shape against the bodies and materials.
pub(crate) fn shape(
    spec: &ShapeSpec,
    bodies: &[BodyInfo],
    materials: &[MaterialInfo],
) -> Result<ShapeInfo, ModelError> {
    let body = if spec.body == GROUND {
        BodyId::Ground
    } else {
        let k = bodies
            .iter()
            .position(|b| b.name == spec.body)
            .ok_or_else(|| ModelError::UnknownBody {
                element: format!("shape \"{}\"", spec.name),
                name: spec.body.clone(),
                suggestion: suggest(&spec.body, bodies.iter().map(|b| b.name.as_str())),
                known: std::iter::once(GROUND.to_string())
                    .chain(bodies.iter().map(|b| b.name.clone()))
                    .collect(),
            })?;
        BodyId::Moving(k)
    };
    geometry(spec, body == BodyId::Ground)?;
    if !spec.center.iter().all(|c| c.is_finite()) {
        return Err(bad_shape(spec, "center", "must be finite".into()));
    }
    let a = spec.axes;
    let orthonormal = a.iter().all(|c| c.is_finite())
        && (a.transpose() * a - Matrix3::identity()).norm() < 1e-9
        && a.determinant() > 0.0;
    if !orthonormal {
        return Err(bad_shape(
            spec,
            "axis",
            "the shape's axes must be a rotation (give a non-zero z axis and an x axis not \
             along it)"
                .into(),
        ));
    }
    let material = materials
        .iter()
        .position(|m| m.name == spec.material)
        .ok_or_else(|| {
            let known: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
            bad_shape(
                spec,
                "material",
                format!(
                    "no material \"{}\"{} (materials: {})",
                    spec.material,
                    suggest(&spec.material, known.iter().copied())
                        .map(|s| format!("; did you mean \"{s}\"?"))
                        .unwrap_or_default(),
                    if known.is_empty() {
                        "none declared".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })?;
    if let Some([a, b]) = &materials[material].between {
        return Err(bad_shape(
            spec,
            "material",
            format!(
                "\"{}\" is the pair law between \"{a}\" and \"{b}\", not a material of shapes; \
                 name \"{a}\" or \"{b}\"",
                spec.material
            ),
        ));
    }
    if spec.groups == 0 {
        return Err(bad_shape(
            spec,
            "groups",
            "a shape in no group collides with nothing; leave the key out for group 1".into(),
        ));
    }
    Ok(ShapeInfo {
        name: spec.name.clone(),
        body,
        geometry: spec.geometry.clone(),
        center: spec.center,
        axes: spec.axes,
        material,
        groups: spec.groups,
        collides_with: spec.collides_with,
    })
}

/// The pair laws ([`MaterialSpec::between`]): two materials that exist and are not pair laws
/// themselves, a direct stiffness, one law per pair.
fn check_material_pairs(materials: &[MaterialInfo]) -> Result<(), ModelError> {
    let mut pairs = HashMap::new();
    for m in materials {
        let Some([a, b]) = &m.between else { continue };
        for name in [a, b] {
            match materials.iter().find(|o| &o.name == name) {
                None => {
                    let known = materials.iter().filter(|o| o.between.is_none());
                    return Err(bad_material(
                        m,
                        "between",
                        format!(
                            "no material \"{name}\"{} (materials: {})",
                            suggest(name, known.clone().map(|o| o.name.as_str()))
                                .map(|s| format!("; did you mean \"{s}\"?"))
                                .unwrap_or_default(),
                            known
                                .map(|o| o.name.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                }
                Some(o) if o.between.is_some() => {
                    return Err(bad_material(
                        m,
                        "between",
                        format!("\"{name}\" is a pair law itself; name the materials of shapes"),
                    ))
                }
                Some(_) => {}
            }
        }
        if !matches!(m.stiffness, Stiffness::Direct { .. }) {
            return Err(bad_material(
                m,
                "youngs_modulus",
                "a pair law takes the pair's stiffness K directly (stiffness = K, N/mⁿ), not a \
                 Young's modulus"
                    .into(),
            ));
        }
        let key = if a <= b { (a, b) } else { (b, a) };
        if let Some(first) = pairs.insert(key, &m.name) {
            return Err(bad_material(
                m,
                "between",
                format!("material \"{first}\" is already the law between \"{a}\" and \"{b}\""),
            ));
        }
    }
    Ok(())
}

/// Two elastic materials between two flat shapes have no Hertz stiffness (R* = ∞): an error
/// naming the first such pair that may touch.
pub(crate) fn check_pairs(
    shapes: &[ShapeInfo],
    materials: &[MaterialInfo],
    joints: &[JointInfo],
) -> Result<(), ModelError> {
    let flat_elastic: Vec<&ShapeInfo> = shapes
        .iter()
        .filter(|s| {
            s.geometry.curvature_radius().is_infinite()
                && matches!(materials[s.material].stiffness, Stiffness::Elastic { .. })
        })
        .collect();
    for (i, a) in flat_elastic.iter().enumerate() {
        for b in &flat_elastic[i + 1..] {
            let law = pair_law(materials, a.material, b.material);
            if law.is_none() && may_touch(a, b, |i, j| joined(joints, i, j)) {
                return Err(ModelError::BadShape {
                    shape: b.name.clone(),
                    key: "material".into(),
                    reason: format!(
                        "shapes \"{}\" and \"{}\" are both flat (R = ∞) and their materials \
                         give Young's moduli: Hertz's stiffness 4/3 E* √R* needs a curved shape \
                         on one side; give one material a stiffness (N/m^1.5) instead",
                        a.name, b.name
                    ),
                });
            }
        }
    }
    Ok(())
}

/// Whether two shapes may touch: different bodies, not two moving bodies joined by a joint
/// (a body jointed to the ground still touches the ground's shapes, as in MuJoCo: a wheel on
/// its axle rolls on the floor), and each one's filter admitting the other's groups.
/// `joined(i, j)` tells whether moving bodies i and j are joined (a scan of the joints here, a
/// sorted table in the dynamics' broad phase).
pub fn may_touch(a: &ShapeInfo, b: &ShapeInfo, joined: impl FnOnce(usize, usize) -> bool) -> bool {
    if a.body == b.body {
        return false;
    }
    if a.groups & b.collides_with == 0 || b.groups & a.collides_with == 0 {
        return false;
    }
    match (a.body, b.body) {
        (BodyId::Moving(i), BodyId::Moving(j)) => !joined(i, j),
        _ => true,
    }
}

/// Whether a joint joins moving bodies i and j.
fn joined(joints: &[JointInfo], i: usize, j: usize) -> bool {
    let (bi, bj) = (BodyId::Moving(i), BodyId::Moving(j));
    joints
        .iter()
        .any(|jt| (jt.body_i == bi && jt.body_j == bj) || (jt.body_i == bj && jt.body_j == bi))
}

/// Checks the shapes and materials of a model: names unique, every key valid, the pairs.
pub(crate) fn shapes_and_materials(
    shape_specs: &[ShapeSpec],
    material_specs: &[MaterialSpec],
    bodies: &[BodyInfo],
    joints: &[JointInfo],
) -> Result<(Vec<ShapeInfo>, Vec<MaterialInfo>), ModelError> {
    let mut seen = HashMap::new();
    let mut materials = Vec::with_capacity(material_specs.len());
    for m in material_specs {
        if seen.insert(m.name.as_str(), ()).is_some() {
            return Err(bad_material(
                m,
                "name",
                "another material has this name".into(),
            ));
        }
        materials.push(material(m)?);
    }
    check_material_pairs(&materials)?;
    seen.clear();
    let mut shapes = Vec::with_capacity(shape_specs.len());
    for s in shape_specs {
        if s.name.is_empty() {
            return Err(ModelError::EmptyName {
                what: "a shape".into(),
            });
        }
        if seen.insert(s.name.as_str(), ()).is_some() {
            return Err(bad_shape(s, "name", "another shape has this name".into()));
        }
        shapes.push(shape(s, bodies, &materials)?);
    }
    check_pairs(&shapes, &materials, joints)?;
    Ok((shapes, materials))
}

/// The pair law between materials `a` and `b` (indices), if one is declared.
fn pair_law(materials: &[MaterialInfo], a: usize, b: usize) -> Option<usize> {
    let (na, nb) = (&materials[a].name, &materials[b].name);
    materials.iter().position(|m| {
        m.between
            .as_ref()
            .is_some_and(|[x, y]| (x == na && y == nb) || (x == nb && y == na))
    })
}

impl Model {
    /// The pair law ([`MaterialSpec::between`]) between materials `a` and `b` (indices into
    /// [`Model::materials`]), if the model declares one.
    pub fn material_pair(&self, a: usize, b: usize) -> Option<usize> {
        pair_law(&self.materials, a, b)
    }

    /// The collision shapes.
    pub fn shapes(&self) -> &[ShapeInfo] {
        &self.shapes
    }

    /// The contact materials.
    pub fn materials(&self) -> &[MaterialInfo] {
        &self.materials
    }

    /// Whether shapes `a` and `b` (indices into [`Model::shapes`]) may touch
    /// ([`may_touch`]).
    pub fn shapes_may_touch(&self, a: usize, b: usize) -> bool {
        may_touch(&self.shapes[a], &self.shapes[b], |i, j| {
            joined(&self.joints, i, j)
        })
    }
}
