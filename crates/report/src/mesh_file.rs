//! Mesh files as triangle meshes: STL (binary or ASCII, through `stl_io`), Wavefront OBJ
//! (through `tobj`, polygons triangulated, materials ignored) and COLLADA (`.dae`, through
//! `mesh-loader`: the document's unit and node transforms applied, materials ignored), the
//! formats robot descriptions use.
//!
//! Each triangle gets its own three vertices and its face normal (flat shading: mechanical
//! parts have sharp edges; a degenerate triangle gets +z). Coordinates are multiplied by
//! `scale` (e.g. 0.001 for a file in millimetres). Refused, with the file named: an unreadable
//! or malformed file, a file beyond [`MAX_MESH_BYTES`], more than `max_triangles` triangles
//! (for binary STL checked from its header before the rest is read), a non-finite vertex.

use crate::scene::Mesh;
use crate::Error;
use std::io::{BufReader, Read, Seek};
use std::path::Path;

/// Largest mesh file read [bytes]: 1 GiB.
pub const MAX_MESH_BYTES: u64 = 1 << 30;

/// The kind of a mesh file, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// `.stl`, binary or ASCII.
    Stl,
    /// `.obj`.
    Obj,
    /// `.dae` (COLLADA).
    Dae,
}

impl MeshFormat {
    /// The format of `path` by its extension (case-insensitive), if it is one.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Self::Stl),
            "obj" => Some(Self::Obj),
            "dae" => Some(Self::Dae),
            _ => None,
        }
    }
}

/// Reads the mesh file at `path`, scaled by `scale`, with at most `max_triangles` triangles.
///
/// # Errors
/// [`Error::Mesh`] naming the file: unknown extension, unreadable, malformed, too large, too
/// many triangles, a non-finite vertex (its number).
pub fn read_mesh(path: &Path, scale: f64, max_triangles: usize) -> Result<Mesh, Error> {
    let fail = |why: String| Error::Mesh(format!("mesh file {}: {why}", path.display()));
    let format = MeshFormat::of(path).ok_or_else(|| {
        fail("unknown kind of mesh file; the extension must be .stl, .obj or .dae".into())
    })?;
    let mut file = std::fs::File::open(path).map_err(|e| fail(format!("cannot open it ({e})")))?;
    let bytes = file
        .metadata()
        .map_err(|e| fail(format!("cannot read it ({e})")))?
        .len();
    if bytes > MAX_MESH_BYTES {
        return Err(fail(format!(
            "it is {bytes} bytes long; at most {MAX_MESH_BYTES} bytes (1 GiB) are read"
        )));
    }
    let triangles: Vec<[[f32; 3]; 3]> = match format {
        MeshFormat::Stl => {
            if let Some(n) = binary_stl_count(&mut file, bytes) {
                check_count(n, max_triangles).map_err(fail)?;
            }
            let mut reader = BufReader::new(file);
            let m = stl_io::read_stl(&mut reader)
                .map_err(|e| fail(format!("not a readable STL file ({e})")))?;
            let mut out = Vec::with_capacity(m.faces.len());
            for f in &m.faces {
                let v = |k: usize| m.vertices.get(f.vertices[k]).map(|v| v.0);
                match (v(0), v(1), v(2)) {
                    (Some(a), Some(b), Some(c)) => out.push([a, b, c]),
                    _ => return Err(fail("a triangle refers to a missing vertex".into())),
                }
            }
            out
        }
        MeshFormat::Obj => {
            let mut reader = BufReader::new(file);
            let opts = tobj::LoadOptions {
                triangulate: true,
                single_index: true,
                ..Default::default()
            };
            let (models, _) =
                tobj::load_obj_buf(&mut reader, &opts, |_| Err(tobj::LoadError::OpenFileFailed))
                    .map_err(|e| fail(format!("not a readable OBJ file ({e})")))?;
            let mut out = Vec::new();
            for m in &models {
                let p = &m.mesh.positions;
                let v = |i: u32| -> Option<[f32; 3]> {
                    let i = 3 * i as usize;
                    Some([*p.get(i)?, *p.get(i + 1)?, *p.get(i + 2)?])
                };
                for t in m.mesh.indices.chunks_exact(3) {
                    match (v(t[0]), v(t[1]), v(t[2])) {
                        (Some(a), Some(b), Some(c)) => out.push([a, b, c]),
                        _ => return Err(fail("a face refers to a missing vertex".into())),
                    }
                }
            }
            out
        }
        MeshFormat::Dae => {
            let mut bytes = Vec::new();
            file.read_to_end(&mut bytes)
                .map_err(|e| fail(format!("cannot read it ({e})")))?;
            let scene = mesh_loader::collada::from_slice(&bytes)
                .map_err(|e| fail(format!("not a readable COLLADA file ({e})")))?;
            let mut out = Vec::new();
            for m in &scene.meshes {
                for f in &m.faces {
                    let v = |i: u32| m.vertices.get(i as usize).copied();
                    match (v(f[0]), v(f[1]), v(f[2])) {
                        (Some(a), Some(b), Some(c)) => out.push([a, b, c]),
                        _ => return Err(fail("a face refers to a missing vertex".into())),
                    }
                }
                check_count(out.len(), max_triangles).map_err(fail)?;
            }
            out
        }
    };
    check_count(triangles.len(), max_triangles).map_err(fail)?;
    if triangles.is_empty() {
        return Err(fail("it holds no triangle".into()));
    }
    flat_mesh(&triangles, scale).map_err(fail)
}

/// The triangle count in a binary STL's header, when the file's length is exactly that of a
/// binary STL with that many triangles (84 + 50 n bytes).
fn binary_stl_count(file: &mut std::fs::File, bytes: u64) -> Option<usize> {
    let mut header = [0u8; 84];
    file.read_exact(&mut header).ok()?;
    file.rewind().ok()?;
    let n = u32::from_le_bytes([header[80], header[81], header[82], header[83]]);
    (84 + 50 * u64::from(n) == bytes).then_some(n as usize)
}

fn check_count(n: usize, max: usize) -> Result<(), String> {
    if n > max {
        Err(format!(
            "it has {n} triangles; at most {max} are accepted (the meshes of a model may have \
             2·10⁶ triangles together: simplify the mesh, e.g. with a decimate modifier)"
        ))
    } else {
        Ok(())
    }
}

/// Three vertices per triangle with its face normal, scaled (flat shading).
///
/// # Errors
/// A non-finite vertex, named by its number and its triangle's.
pub fn flat_mesh(triangles: &[[[f32; 3]; 3]], scale: f64) -> Result<Mesh, String> {
    let mut m = Mesh {
        positions: Vec::with_capacity(3 * triangles.len()),
        normals: Vec::with_capacity(3 * triangles.len()),
        indices: (0..3 * triangles.len() as u32).collect(),
    };
    for (k, t) in triangles.iter().enumerate() {
        let p = t.map(|v| v.map(|x| f64::from(x) * scale));
        if let Some(j) = p.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(format!(
                "vertex {} of triangle {} is not finite ({:?})",
                j + 1,
                k + 1,
                t[j]
            ));
        }
        let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = if len > 0.0 && len.is_finite() {
            [n[0] / len, n[1] / len, n[2] / len]
        } else {
            [0.0, 0.0, 1.0]
        };
        let nf = n.map(|x| x as f32);
        for v in p {
            m.positions.push(v.map(|x| x as f32));
            m.normals.push(nf);
        }
    }
    Ok(m)
}
