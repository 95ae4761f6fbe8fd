//! The model's collision shapes as parry3d-f64 shapes, and their poses from the body states.
//!
//! parry's frames differ from cardan's shape frames in one place: its cylinder's axis is y, so
//! a cylinder carries a fixed rotation of +90° about x (y → z) after the shape's axes. Poses
//! are parry's `Pose` (a unit quaternion and a translation); a body's Euler parameters
//! p = [e₀, e₁, e₂, e₃] are the quaternion (w, x, y, z) (Nikravesh 1988 §6.3).

use cardan_constraints::BodyState;
use cardan_mechanism::{BodyId, Geometry, ShapeInfo};
use nalgebra::{Matrix3, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::shape::{
    Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, HalfSpace, SharedShape, TriMesh,
    TriMeshFlags,
};

/// A vector in parry's type.
pub(crate) fn to_parry(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// A vector in nalgebra's type.
pub(crate) fn from_parry(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// A rotation matrix as a unit quaternion.
fn rotation(a: &Matrix3<f64>) -> Rotation {
    let m = parry3d_f64::math::Matrix::from_cols(
        to_parry(&a.column(0).into_owned()),
        to_parry(&a.column(1).into_owned()),
        to_parry(&a.column(2).into_owned()),
    );
    Rotation::from_mat3(&m).normalize()
}

/// One shape ready for the queries: parry's shape and its fixed placement on the body.
#[derive(Clone)]
pub(crate) struct Placed {
    /// The body.
    pub body: BodyId,
    /// parry's shape.
    pub shape: SharedShape,
    /// The centre s' in the body frame.
    pub center: Vector3<f64>,
    /// The rotation from parry's shape frame to the body frame.
    pub rotation: Rotation,
    /// The shape is a plane (an unbounded half-space: no box for the broad phase).
    pub unbounded: bool,
}

impl std::fmt::Debug for Placed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Placed")
            .field("body", &self.body)
            .field("center", &self.center)
            .finish_non_exhaustive()
    }
}

/// parry's shape of a checked model shape; `Err` with the reason for a mesh parry refuses.
pub(crate) fn place(info: &ShapeInfo) -> Result<Placed, String> {
    let mut rotation = rotation(&info.axes);
    let shape = match &info.geometry {
        Geometry::Sphere { radius } => SharedShape::new(Ball::new(*radius)),
        Geometry::Capsule { radius, length } => {
            SharedShape::new(Capsule::new_z(0.5 * length, *radius))
        }
        Geometry::Cylinder { radius, length } => {
            rotation *= Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2);
            SharedShape::new(Cylinder::new(0.5 * length, *radius))
        }
        Geometry::Box { size } => SharedShape::new(Cuboid::new(to_parry(&(0.5 * size)))),
        Geometry::Plane => SharedShape::new(HalfSpace::new(Vector::Z)),
        Geometry::ConvexMesh { points } => {
            let pts: Vec<Vector> = points.iter().map(to_parry).collect();
            let hull = ConvexPolyhedron::from_convex_hull(&pts).ok_or(
                "the convex hull of the points could not be built (are they all in a plane?)",
            )?;
            SharedShape::new(hull)
        }
        Geometry::TriangleMesh {
            vertices,
            triangles,
        } => {
            let v: Vec<Vector> = vertices.iter().map(to_parry).collect();
            // Welded, with its half-edge topology (a non-manifold mesh is refused) and its
            // internal edges fixed (a ball rolling over a seam gets no bump).
            let flags = TriMeshFlags::MERGE_DUPLICATE_VERTICES
                | TriMeshFlags::HALF_EDGE_TOPOLOGY
                | TriMeshFlags::FIX_INTERNAL_EDGES;
            // (`TriMesh::with_flags` drops the topology's error: set the flags after.)
            let mut mesh = TriMesh::new(v, triangles.clone())
                .map_err(|e| format!("the triangle mesh is not valid: {e}"))?;
            mesh.set_flags(flags).map_err(|e| {
                format!(
                    "the triangle mesh is not manifold ({e}): each edge must be shared by at \
                     most two triangles, consistently oriented"
                )
            })?;
            SharedShape::new(mesh)
        }
    };
    Ok(Placed {
        body: info.body,
        shape,
        center: info.center,
        rotation,
        unbounded: matches!(info.geometry, Geometry::Plane),
    })
}

/// A triangle mesh: vertices and the vertex indices of each triangle.
pub type Triangles = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// The triangles of the convex hull of `points` (counter-clockwise from outside), for drawing
/// a convex mesh; `None` when the hull cannot be built.
pub fn hull_triangles(points: &[Vector3<f64>]) -> Option<Triangles> {
    let pts: Vec<Vector> = points.iter().map(to_parry).collect();
    let (v, t) = parry3d_f64::transformation::try_convex_hull(&pts).ok()?;
    Some((v.into_iter().map(from_parry).collect(), t))
}

impl Placed {
    /// The shape's pose at the body states (ground shapes: their fixed placement).
    pub fn pose(&self, bodies: &[BodyState]) -> Pose {
        match self.body {
            BodyId::Ground => Pose::from_parts(to_parry(&self.center), self.rotation),
            BodyId::Moving(k) => {
                let b = &bodies[k];
                let p = &b.p;
                let q = Rotation::from_xyzw(p[1], p[2], p[3], p[0]).normalize();
                let c = b.r + b.a * self.center;
                Pose::from_parts(to_parry(&c), q * self.rotation)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cardan_mechanism::ShapeInfo;

    #[test]
    fn a_non_manifold_mesh_is_refused() {
        let v = |x: f64, y: f64, z: f64| Vector3::new(x, y, z);
        let info = ShapeInfo {
            name: "fan".into(),
            body: BodyId::Ground,
            geometry: Geometry::TriangleMesh {
                vertices: vec![
                    v(0., 0., 0.),
                    v(1., 0., 0.),
                    v(0., 1., 0.),
                    v(0., -1., 0.),
                    v(0., 0., 1.),
                ],
                triangles: vec![[0, 1, 2], [0, 1, 3], [0, 1, 4]],
            },
            center: Vector3::zeros(),
            axes: Matrix3::identity(),
            material: 0,
            groups: 1,
            collides_with: u32::MAX,
        };
        let e = place(&info).unwrap_err();
        assert!(e.contains("manifold"), "{e}");
    }
}
