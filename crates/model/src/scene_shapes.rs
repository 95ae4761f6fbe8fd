//! The collision shapes as the 3D report draws them ([`shape_geometry`]): a body with shapes is
//! drawn as its shapes instead of the rods between its points (its joints' parts stay); a
//! capsule as a cylinder and two spheres, a convex mesh as its hull, a ground plane as a thin
//! square slab of the scene's size under its surface, a ground mesh as its triangles.

use cardan_mechanism::{BodyId, Geometry as ShapeGeometry, Model};
use cardan_report::{Geometry, Shape};
use nalgebra::{Matrix3, Vector3};

/// Each shape's drawing, with its body.
pub fn shape_geometry(model: &Model, extent: f64) -> Vec<(BodyId, Geometry)> {
    let mut out = Vec::new();
    for s in model.shapes() {
        let place = |shape: Shape, offset: Vector3<f64>| {
            let c = s.center + s.axes * offset;
            Geometry {
                shape,
                position: [c.x, c.y, c.z],
                rotation: rotation(&s.axes),
            }
        };
        match &s.geometry {
            ShapeGeometry::Sphere { radius } => {
                out.push((
                    s.body,
                    place(Shape::Sphere { radius: *radius }, Vector3::zeros()),
                ));
            }
            ShapeGeometry::Cylinder { radius, length } => out.push((
                s.body,
                place(
                    Shape::Cylinder {
                        radius: *radius,
                        length: *length,
                    },
                    Vector3::zeros(),
                ),
            )),
            ShapeGeometry::Capsule { radius, length } => {
                let body = Shape::Cylinder {
                    radius: *radius,
                    length: *length,
                };
                out.push((s.body, place(body, Vector3::zeros())));
                for end in [-0.5, 0.5] {
                    let cap = Shape::Sphere { radius: *radius };
                    out.push((s.body, place(cap, Vector3::z() * (end * length))));
                }
            }
            ShapeGeometry::Box { size } => out.push((
                s.body,
                place(
                    Shape::Box {
                        size: [size.x, size.y, size.z],
                    },
                    Vector3::zeros(),
                ),
            )),
            ShapeGeometry::Plane => {
                let side = 2.0 * extent;
                let thick = extent / 100.0;
                let slab = Shape::Box {
                    size: [side, side, thick],
                };
                out.push((s.body, place(slab, Vector3::z() * (-0.5 * thick))));
            }
            ShapeGeometry::ConvexMesh { points } => {
                if let Some((v, t)) = cardan_dynamics::collision::hull_triangles(points) {
                    out.extend(mesh(&v, &t).map(|m| (s.body, place(m, Vector3::zeros()))));
                }
            }
            ShapeGeometry::TriangleMesh {
                vertices,
                triangles,
            } => {
                out.extend(mesh(vertices, triangles).map(|m| (s.body, place(m, Vector3::zeros()))))
            }
        }
    }
    out
}

/// A flat-shaded mesh of the triangles; `None` for a vertex that is not finite (checked before).
fn mesh(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Option<Shape> {
    let tri: Vec<[[f32; 3]; 3]> = triangles
        .iter()
        .map(|t| t.map(|i| vertices[i as usize].map(|x| x as f32).into()))
        .collect();
    cardan_report::flat_mesh(&tri, 1.0).ok().map(Shape::Mesh)
}

/// Euler parameters of a rotation matrix (identity if it is not one).
fn rotation(a: &Matrix3<f64>) -> [f64; 4] {
    cardan_eulerparam::EulerParams::from_rotation_matrix(a)
        .map(|p| [p.e0(), p.e().x, p.e().y, p.e().z])
        .unwrap_or([1.0, 0.0, 0.0, 0.0])
}
