//! Triangle meshes of the primitive shapes (box, cylinder along z, sphere), centred at the
//! origin, with outward unit normals and counter-clockwise triangles seen from outside.

use crate::scene::{Mesh, Shape};
use std::f64::consts::TAU;

/// Segments around a cylinder or a sphere's equator.
const AROUND: u32 = 24;
/// Segments of a sphere from pole to pole.
const POLES: u32 = 12;

/// The mesh of `shape` (a mesh is returned as it is).
pub fn mesh_of(shape: &Shape) -> Mesh {
    match shape {
        Shape::Box { size } => cuboid(*size),
        Shape::Cylinder { radius, length } => cylinder(*radius, *length),
        Shape::Sphere { radius } => sphere(*radius),
        Shape::Mesh(m) => m.clone(),
    }
}

fn f(v: [f64; 3]) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

/// A box with edge lengths `size`: 6 faces of 4 vertices (flat normals).
fn cuboid(size: [f64; 3]) -> Mesh {
    let h = [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0];
    let mut m = Mesh::default();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            // The face's normal n = sign e_axis; u, v span it with u × v = n.
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = m.positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign * h[axis];
                p[a] = su * h[a];
                p[b] = sign * sv * h[b];
                let mut n = [0.0; 3];
                n[axis] = sign;
                m.positions.push(f(p));
                m.normals.push(f(n));
            }
            m.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    m
}

/// A cylinder of `radius` and `length` along z: a smooth side and two flat caps.
fn cylinder(radius: f64, length: f64) -> Mesh {
    let mut m = Mesh::default();
    let h = length / 2.0;
    let ring = |k: u32| {
        let a = TAU * f64::from(k) / f64::from(AROUND);
        (a.cos(), a.sin())
    };
    for k in 0..AROUND {
        let (c, s) = ring(k);
        m.positions.push(f([radius * c, radius * s, -h]));
        m.positions.push(f([radius * c, radius * s, h]));
        m.normals.push(f([c, s, 0.0]));
        m.normals.push(f([c, s, 0.0]));
    }
    for k in 0..AROUND {
        let (i0, i1) = (2 * k, 2 * ((k + 1) % AROUND));
        m.indices.extend([i0, i1, i1 + 1, i0, i1 + 1, i0 + 1]);
    }
    for (z, nz) in [(h, 1.0), (-h, -1.0)] {
        let centre = m.positions.len() as u32;
        m.positions.push(f([0.0, 0.0, z]));
        m.normals.push(f([0.0, 0.0, nz]));
        for k in 0..AROUND {
            let (c, s) = ring(k);
            m.positions.push(f([radius * c, radius * s, z]));
            m.normals.push(f([0.0, 0.0, nz]));
        }
        for k in 0..AROUND {
            let (a, b) = (centre + 1 + k, centre + 1 + (k + 1) % AROUND);
            if nz > 0.0 {
                m.indices.extend([centre, a, b]);
            } else {
                m.indices.extend([centre, b, a]);
            }
        }
    }
    m
}

/// A sphere of `radius`: latitude-longitude grid, normals radial.
fn sphere(radius: f64) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=POLES {
        let theta = std::f64::consts::PI * f64::from(i) / f64::from(POLES);
        for k in 0..=AROUND {
            let phi = TAU * f64::from(k) / f64::from(AROUND);
            let n = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ];
            m.positions
                .push(f([radius * n[0], radius * n[1], radius * n[2]]));
            m.normals.push(f(n));
        }
    }
    let row = AROUND + 1;
    for i in 0..POLES {
        for k in 0..AROUND {
            let (a, b) = (i * row + k, (i + 1) * row + k);
            if i > 0 {
                m.indices.extend([a, b, a + 1]);
            }
            if i + 1 < POLES {
                m.indices.extend([a + 1, b, b + 1]);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle faces outward: its normal (by the winding) points away from the centre.
    fn outward(m: &Mesh) -> bool {
        m.indices.chunks(3).all(|t| {
            let p = |i: u32| {
                let v = m.positions[i as usize];
                [f64::from(v[0]), f64::from(v[1]), f64::from(v[2])]
            };
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let centroid = [
                (a[0] + b[0] + c[0]) / 3.0,
                (a[1] + b[1] + c[1]) / 3.0,
                (a[2] + b[2] + c[2]) / 3.0,
            ];
            n[0] * centroid[0] + n[1] * centroid[1] + n[2] * centroid[2] > 0.0
        })
    }

    #[test]
    fn primitives_are_closed_outward_and_sized() {
        let b = mesh_of(&Shape::Box {
            size: [1.0, 2.0, 3.0],
        });
        assert_eq!((b.positions.len(), b.triangles()), (24, 12));
        assert!(outward(&b));
        let c = mesh_of(&Shape::Cylinder {
            radius: 0.5,
            length: 2.0,
        });
        assert!(outward(&c));
        assert!(c.positions.iter().all(|p| p[2].abs() <= 1.0 + 1e-6));
        let s = mesh_of(&Shape::Sphere { radius: 2.0 });
        assert!(outward(&s));
        for p in &s.positions {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((r - 2.0).abs() < 1e-5);
        }
        for m in [&b, &c, &s] {
            assert_eq!(m.normals.len(), m.positions.len());
            assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
        }
    }
}
