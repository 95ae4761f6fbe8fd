//! Large meshes made small for drawing: vertex clustering (Rossignac and Borrel, "Multi-resolution
//! 3D approximations for rendering complex scenes", 1993). The mesh's bounding box is cut into
//! cubic cells of edge h; every vertex moves to the first vertex of its cell, and a triangle whose
//! three vertices fall in fewer than three cells disappears. Each vertex moves by less than the
//! cell's diagonal √3 h, so the drawn surface stays within √3 h of the file's; h is the largest
//! cell for which at most the target number of triangles remains, found by growing h from the
//! estimate that a surface of area A keeps about 2 A / h² triangles.
//!
//! Robot descriptions ship visual meshes of 10⁴–10⁵ triangles a link; the report (`index.html`,
//! `animation.glb`) carries every drawn triangle, so the model library draws a model's meshes
//! with a budget of triangles, each decimated to its share. Contact shapes read their meshes
//! whole.

use crate::mesh_file::flat_mesh;
use crate::scene::Mesh;
use std::collections::HashMap;

/// `mesh` with at most `target` triangles (itself when it has no more), and the cell edge h used
/// (0 when unchanged).
pub fn decimate(mesh: &Mesh, target: usize) -> (Mesh, f64) {
    let n = mesh.indices.len() / 3;
    if n <= target || target == 0 {
        return (mesh.clone(), 0.0);
    }
    let tri = |k: usize| [0, 1, 2].map(|j| mesh.positions[mesh.indices[3 * k + j] as usize]);
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &mesh.positions {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let area: f64 = (0..n)
        .map(|k| {
            let [a, b, c] = tri(k).map(|v| v.map(f64::from));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let w = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
        })
        .sum();
    let extent = (0..3).map(|a| f64::from(hi[a] - lo[a])).fold(0.0, f64::max);
    let mut h = (2.0 * area / target as f64).sqrt().max(extent * 1e-6);
    loop {
        let kept = cluster(mesh, n, &tri, lo, h);
        if kept.len() <= target || h > extent {
            let m = flat_mesh(&kept, 1.0).unwrap_or_else(|_| mesh.clone());
            return (m, h);
        }
        h *= 1.25;
    }
}

/// The triangles left when every vertex moves to its cell's first vertex.
fn cluster(
    mesh: &Mesh,
    n: usize,
    tri: &dyn Fn(usize) -> [[f32; 3]; 3],
    lo: [f32; 3],
    h: f64,
) -> Vec<[[f32; 3]; 3]> {
    let mut cells: HashMap<[i64; 3], [f32; 3]> = HashMap::with_capacity(mesh.positions.len() / 4);
    let mut snap = |p: [f32; 3]| {
        let key = [0, 1, 2].map(|a| (f64::from(p[a] - lo[a]) / h).floor() as i64);
        (key, *cells.entry(key).or_insert(p))
    };
    let mut kept = Vec::new();
    for k in 0..n {
        let [(ka, a), (kb, b), (kc, c)] = tri(k).map(&mut snap);
        if ka != kb && kb != kc && ka != kc {
            kept.push([a, b, c]);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit sphere of 2 · m · (m − 1)… triangles (latitude–longitude).
    fn sphere(m: usize) -> Mesh {
        let p = |i: usize, j: usize| {
            let (th, ph) = (
                std::f64::consts::PI * i as f64 / m as f64,
                2.0 * std::f64::consts::PI * j as f64 / m as f64,
            );
            [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()].map(|x| x as f32)
        };
        let mut t = Vec::new();
        for i in 0..m {
            for j in 0..m {
                let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                if i + 1 < m {
                    t.push([a, b, c]);
                }
                if i > 0 {
                    t.push([a, c, d]);
                }
            }
        }
        flat_mesh(&t, 1.0).unwrap()
    }

    #[test]
    fn a_fine_sphere_is_drawn_with_the_target_and_stays_on_its_surface() {
        let fine = sphere(300);
        assert!(fine.triangles() > 170_000);
        let (coarse, h) = decimate(&fine, 5_000);
        assert!(coarse.triangles() <= 5_000, "{}", coarse.triangles());
        assert!(coarse.triangles() > 1_000, "{}", coarse.triangles());
        // Every drawn triangle's centroid within √3 h of the unit sphere (its vertices are the
        // file's); the cell a few hundredths of the radius.
        let radius = |p: [f64; 3]| p.iter().map(|x| x * x).sum::<f64>().sqrt();
        let worst = (coarse.positions.chunks_exact(3))
            .map(|t| {
                let c = [0, 1, 2].map(|a| t.iter().map(|v| f64::from(v[a])).sum::<f64>() / 3.0);
                (radius(c) - 1.0).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst <= 3f64.sqrt() * h, "{worst} {h}");
        assert!(worst > 1e-4, "{worst}: the test sees the coarsening");
        assert!(h < 0.1, "{h}");
        // A small mesh is left alone.
        let (same, h0) = decimate(&sphere(10), 5_000);
        assert_eq!((same.triangles(), h0), (sphere(10).triangles(), 0.0));
    }
}
