//! `[[material]]` and `[[shape]]` sections to [`MaterialSpec`]s and [`ShapeSpec`]s: the numbers
//! converted from the model's units (a stiffness K in N/uⁿ for the length unit u, a Young's
//! modulus in N/u²), the shape placed at a named point with named axes of its body, a mesh
//! read from its file (STL or OBJ, relative to the model file) with the reader's errors at the
//! `file` key. The builder checks the rest (positive sizes, e ∈ (0, 1], μ_s ≥ μ_d, a known
//! material, a triangle mesh on the ground only); its errors are placed at the key
//! ([`cardan_mechanism::ModelError::contact_site`]).

use super::context::{missing, Ctx, Resolver};
use crate::diag::Error;
use crate::file::{MaterialSection, Num, ShapeSection};
use cardan_mechanism::{Geometry, MaterialSpec, Quantity, ShapeSpec, Stiffness};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;
use toml::Spanned;

/// Most triangles of one collision mesh file.
pub const MAX_MESH_TRIANGLES: usize = 1_000_000;

/// `[[material]]`: one material (its law checked against the vocabulary already).
pub(super) fn load_material(
    cx: &Ctx,
    section: &Spanned<MaterialSection>,
) -> Result<MaterialSpec, Error> {
    let m = section.get_ref();
    let owner = format!("material \"{}\"", m.name.get_ref());
    let num = |n: &Num, key: &str, q: Quantity| cx.num(n, format_args!("{owner}: {key}"), q);
    let unit = cx.units.length();
    let stiffness = match (&m.stiffness, &m.youngs_modulus) {
        (Some(k), None) => {
            if m.poisson_ratio.is_some() {
                let span = m.poisson_ratio.as_ref().map_or(0..0, |n| n.span());
                return Err(cx.err(
                    span,
                    format!("{owner}: poisson_ratio goes with youngs_modulus, not stiffness"),
                ));
            }
            let exponent = match &m.exponent {
                Some(n) => num(n, "exponent", Quantity::Ratio)?,
                None => 1.5,
            };
            // K δⁿ with δ in the file's length unit u: K_SI = K · u^(−n).
            let k = num(k, "stiffness", Quantity::Unbounded)? * unit.powf(-exponent);
            Stiffness::Direct { k, exponent }
        }
        (None, Some(e)) => {
            if let Some(n) = &m.exponent {
                return Err(cx.err(
                    n.span(),
                    format!(
                        "{owner}: exponent goes with stiffness; a Young's modulus gives Hertz's \
                         n = 1.5"
                    ),
                ));
            }
            Stiffness::Elastic {
                youngs_modulus: num(e, "youngs_modulus", Quantity::Unbounded)? / (unit * unit),
                poisson_ratio: match &m.poisson_ratio {
                    Some(nu) => num(nu, "poisson_ratio", Quantity::Ratio)?,
                    None => 0.3,
                },
            }
        }
        (Some(_), Some(e)) => {
            return Err(cx.err(
                e.span(),
                format!("{owner}: give stiffness or youngs_modulus, not both"),
            ))
        }
        (None, None) => {
            return Err(missing(
                cx,
                m.name.span(),
                &owner,
                "stiffness",
                "give stiffness = K (N/m^1.5) or youngs_modulus = E (Pa)",
            ))
        }
    };
    let e = match &m.restitution {
        Some(e) => num(e, "restitution", Quantity::Ratio)?,
        None => {
            return Err(missing(
                cx,
                m.name.span(),
                &owner,
                "restitution",
                "every material needs its coefficient of restitution e ∈ (0, 1]",
            ))
        }
    };
    let mut spec = MaterialSpec::new(m.name.get_ref().clone(), stiffness, e);
    if let Some(mu) = &m.friction {
        let mu = num(mu, "friction", Quantity::Ratio)?;
        spec = spec.friction(mu);
    }
    if let Some(mu_s) = &m.friction_static {
        spec.friction_static = num(mu_s, "friction_static", Quantity::Ratio)?;
    }
    if let Some(v) = &m.slip_velocity {
        spec = spec.slip_velocity(num(v, "slip_velocity", Quantity::Velocity)?);
    }
    if let Some(between) = &m.between {
        let [a, b] = &between.get_ref()[..] else {
            return Err(cx.err(
                between.span(),
                format!(
                    "{owner}: between names two materials (the same one twice for a material \
                     against itself), got {}",
                    between.get_ref().len()
                ),
            ));
        };
        spec = spec.between(a.get_ref().clone(), b.get_ref().clone());
    }
    Ok(spec)
}

/// The collision groups of `list` as bits (1 – 32).
fn groups(cx: &Ctx, list: &Spanned<Vec<Num>>, owner: &str, key: &str) -> Result<u32, Error> {
    let mut bits = 0u32;
    for g in list.get_ref() {
        let v = *g.get_ref();
        if !(v.fract() == 0.0 && (1.0..=32.0).contains(&v)) {
            return Err(cx.err(
                g.span(),
                format!("{owner}: {key} holds group numbers 1 – 32, got {v}"),
            ));
        }
        bits |= 1 << (v as u32 - 1);
    }
    if bits == 0 {
        return Err(cx.err(
            list.span(),
            format!("{owner}: {key} is empty; leave the key out for the default"),
        ));
    }
    Ok(bits)
}

/// `[[shape]]`: one shape, its kind checked against the vocabulary (`kind` the entry's name).
pub(super) fn load_shape(
    r: &Resolver,
    section: &Spanned<ShapeSection>,
    kind: &str,
    dir: &Path,
) -> Result<ShapeSpec, Error> {
    let cx = r.cx;
    let s = section.get_ref();
    let owner = format!("shape \"{}\"", s.name.get_ref());
    let body = r.body(&s.body, &owner)?;
    let need = |key: &str| missing(cx, s.name.span(), &owner, key, "the shape needs it");
    let length = |n: &Option<Num>, key: &str| -> Result<f64, Error> {
        let n = n.as_ref().ok_or_else(|| need(key))?;
        cx.num(n, format_args!("{owner}: {key}"), Quantity::Length)
    };
    let geometry = match kind {
        "sphere" => Geometry::Sphere {
            radius: length(&s.radius, "radius")?,
        },
        "capsule" => Geometry::Capsule {
            radius: length(&s.radius, "radius")?,
            length: length(&s.length, "length")?,
        },
        "cylinder" => Geometry::Cylinder {
            radius: length(&s.radius, "radius")?,
            length: length(&s.length, "length")?,
        },
        "box" => {
            let size = s.size.as_ref().ok_or_else(|| need("size"))?;
            Geometry::Box {
                size: cx.vec3(size, format_args!("{owner}: size"), Quantity::Length)?,
            }
        }
        "plane" => Geometry::Plane,
        "convex_mesh" => Geometry::ConvexMesh {
            points: match (&s.file, &s.points) {
                (Some(_), Some(p)) => {
                    return Err(cx.err(p.span(), format!("{owner}: give file or points, not both")))
                }
                (None, Some(p)) => p
                    .get_ref()
                    .iter()
                    .enumerate()
                    .map(|(k, v)| {
                        cx.vec3(v, format_args!("{owner}: points[{k}]"), Quantity::Length)
                    })
                    .collect::<Result<Vec<_>, _>>()?,
                (Some(_), None) => mesh(cx, s, &owner, dir)?.0,
                (None, None) => return Err(need("file")),
            },
        },
        _ => {
            let (vertices, triangles) = mesh(cx, s, &owner, dir)?;
            Geometry::TriangleMesh {
                vertices,
                triangles,
            }
        }
    };
    let (center, axes) = placement(r, s, body, &owner)?;
    let mut spec = ShapeSpec::new(
        s.name.get_ref().clone(),
        body,
        geometry,
        s.material.get_ref(),
    );
    spec.center = center;
    spec.axes = axes;
    if let Some(g) = &s.groups {
        spec.groups = groups(cx, g, &owner, "groups")?;
    }
    if let Some(g) = &s.collides_with {
        spec.collides_with = groups(cx, g, &owner, "collides_with")?;
    }
    Ok(spec)
}

/// The shape's centre and axes in body coordinates from its named point and vectors.
fn placement(
    r: &Resolver,
    s: &ShapeSection,
    body: &str,
    owner: &str,
) -> Result<(Vector3<f64>, Matrix3<f64>), Error> {
    let center = match &s.point {
        Some(p) => {
            r.feature(body, p, owner, true)?;
            r.point_value(body, p.get_ref())
        }
        None => Vector3::zeros(),
    };
    let z = match &s.axis {
        Some(a) => {
            r.feature(body, a, owner, false)?;
            r.vector_value(body, a.get_ref()).normalize()
        }
        None => Vector3::z(),
    };
    let x = match &s.x_axis {
        Some(x) => {
            r.feature(body, x, owner, false)?;
            let xv = r.vector_value(body, x.get_ref());
            let across = xv - z * z.dot(&xv);
            if across.norm() < 1e-6 * xv.norm() {
                return Err(r.cx.err(
                    x.span(),
                    format!("{owner}: x_axis \"{}\" is parallel to axis", x.get_ref()),
                ));
            }
            across.normalize()
        }
        None => {
            // The body's x (or y) across z.
            let seed = if z.x.abs() < 0.9 {
                Vector3::x()
            } else {
                Vector3::y()
            };
            (seed - z * z.dot(&seed)).normalize()
        }
    };
    Ok((center, Matrix3::from_columns(&[x, z.cross(&x), z])))
}

/// A welded triangle mesh: its vertices and the vertex indices of each triangle.
type Welded = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// The vertices and triangles of the shape's mesh file (welded: the reader gives each triangle
/// its own vertices), in the model's length unit converted to metres.
fn mesh(cx: &Ctx, s: &ShapeSection, owner: &str, dir: &Path) -> Result<Welded, Error> {
    let file = s.file.as_ref().ok_or_else(|| {
        missing(
            cx,
            s.name.span(),
            owner,
            "file",
            "give the mesh file (STL or OBJ)",
        )
    })?;
    let scale = match &s.scale {
        Some(k) => {
            let v = cx.num(k, format_args!("{owner}: scale"), Quantity::Ratio)?;
            if v <= 0.0 {
                return Err(cx.err(k.span(), format!("{owner}: scale must be > 0, got {v}")));
            }
            v
        }
        None => 1.0,
    };
    let path = dir.join(file.get_ref());
    let m = cardan_report::read_mesh(&path, scale * cx.units.length(), MAX_MESH_TRIANGLES)
        .map_err(|e| cx.err(file.span(), format!("{owner}: {e}")))?;
    // Weld the vertices the reader duplicated per triangle (exact matches).
    let mut index = std::collections::HashMap::new();
    let mut vertices = Vec::new();
    let mut ids = Vec::with_capacity(m.positions.len());
    for p in &m.positions {
        let key = p.map(f32::to_bits);
        let id = *index.entry(key).or_insert_with(|| {
            vertices.push(Vector3::new(
                f64::from(p[0]),
                f64::from(p[1]),
                f64::from(p[2]),
            ));
            vertices.len() - 1
        });
        ids.push(id as u32);
    }
    let triangles = m
        .indices
        .chunks_exact(3)
        .map(|t| [ids[t[0] as usize], ids[t[1] as usize], ids[t[2] as usize]])
        .collect();
    Ok((vertices, triangles))
}
