//! The scene as glTF 2.0 binary (`.glb`): the JSON through `gltf-json`, one binary buffer
//! packed here.
//!
//! Layout: a root node per body (its name, the pose at the first time as its translation and
//! rotation), with one child node per geometry item (the item's pose in the body frame and its
//! mesh); one material per body (its colour, metallic 0, roughness 0.6); one animation, with per
//! moving body a translation and a rotation channel (LINEAR: linear interpolation of the
//! position, spherical of the rotation), all sharing one time accessor with its min and max.
//! Rotations are the Euler parameters as [x, y, z, w] = [e1, e2, e3, e0], normalized in double
//! precision before rounding to single. The buffer: per distinct shape POSITION (with min/max),
//! NORMAL and u32 indices (bodies with equal box, cylinder or sphere dimensions share them; each
//! body's mesh still has its own material); then the times, then per moving body its translations and rotations. Every
//! component is 4 bytes, so every view is 4-byte aligned.
//!
//! The GLB container (glTF 2.0 spec., §4.4): a 12-byte header (magic `glTF`, version 2, total
//! length), the JSON chunk padded with spaces and the BIN chunk padded with zeros to 4 bytes.

use crate::scene::{gltf_rotation, Mesh, Scene, Shape};
use crate::tessellate::mesh_of;
use crate::Error;
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use std::collections::{BTreeMap, HashMap};

/// The `.glb` file of `scene`.
///
/// # Errors
/// [`Error::Scene`] if the scene is inconsistent ([`Scene::validate`]) or a mesh is malformed.
pub fn write_glb(scene: &Scene) -> Result<Vec<u8>, Error> {
    scene.validate()?;
    let mut w = Writer::default();
    let mut roots = Vec::with_capacity(scene.bodies.len());
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    let time = (scene.times.len() > 1).then(|| w.times(&scene.times));
    for body in &scene.bodies {
        let material = w.root.push(material(&body.name, body.colour));
        let mut children = Vec::with_capacity(body.geometry.len());
        for (k, g) in body.geometry.iter().enumerate() {
            let data = w.shape(&g.shape, &body.name, k)?;
            let mesh = w.mesh(&format!("{}.{k}", body.name), data, material);
            children.push(w.root.push(json::Node {
                mesh: Some(mesh),
                name: Some(format!("{}.geometry.{k}", body.name)),
                translation: Some(f3(g.position)),
                rotation: Some(json::scene::UnitQuaternion(gltf_rotation(&g.rotation))),
                ..Default::default()
            }));
        }
        let (translation, rotation) = match (body.positions.first(), body.rotations.first()) {
            (Some(r), Some(p)) => (
                Some(f3(*r)),
                Some(json::scene::UnitQuaternion(gltf_rotation(p))),
            ),
            _ => (None, None),
        };
        let node = w.root.push(json::Node {
            name: Some(body.name.clone()),
            children: (!children.is_empty()).then_some(children),
            translation,
            rotation,
            ..Default::default()
        });
        roots.push(node);
        if let (Some(input), true) = (time, body.moves()) {
            let tr = w.vectors(&body.positions.iter().map(|r| f3(*r)).collect::<Vec<_>>());
            let rot = w.quaternions(&body.rotations.iter().map(gltf_rotation).collect::<Vec<_>>());
            for (output, path) in [
                (tr, json::animation::Property::Translation),
                (rot, json::animation::Property::Rotation),
            ] {
                let sampler = json::Index::new(samplers.len() as u32);
                samplers.push(json::animation::Sampler {
                    input,
                    interpolation: Valid(json::animation::Interpolation::Linear),
                    output,
                    extensions: None,
                    extras: Default::default(),
                });
                channels.push(json::animation::Channel {
                    sampler,
                    target: json::animation::Target {
                        node,
                        path: Valid(path),
                        extensions: None,
                        extras: Default::default(),
                    },
                    extensions: None,
                    extras: Default::default(),
                });
            }
        }
    }
    if !channels.is_empty() {
        w.root.push(json::Animation {
            name: Some("motion".into()),
            channels,
            samplers,
            extensions: None,
            extras: Default::default(),
        });
    }
    let scene_index = w.root.push(json::Scene {
        name: Some(scene.name.clone()),
        nodes: roots,
        extensions: None,
        extras: Default::default(),
    });
    w.root.scene = Some(scene_index);
    w.finish()
}

fn f3(v: [f64; 3]) -> [f32; 3] {
    [v[0] as f32, v[1] as f32, v[2] as f32]
}

/// Indices in range, whole triangles, finite positions and normals.
fn check_mesh(m: &Mesh, body: &str, item: usize) -> Result<(), Error> {
    let n = m.positions.len();
    let bad = |why: &str| {
        Err(Error::Scene(format!(
            "body \"{body}\", geometry item {}: {why}",
            item + 1
        )))
    };
    if !m.indices.len().is_multiple_of(3) || m.indices.iter().any(|&i| i as usize >= n) {
        return bad("a triangle index is out of range");
    }
    if m.normals.len() != n {
        return bad("the number of normals differs from the number of vertices");
    }
    if m.positions
        .iter()
        .chain(&m.normals)
        .flatten()
        .any(|x| !x.is_finite())
    {
        return bad("a vertex or normal is not finite");
    }
    Ok(())
}

/// Opaque, not metallic, of colour `rgb`.
fn material(name: &str, rgb: [f32; 3]) -> json::Material {
    json::Material {
        name: Some(name.to_string()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([rgb[0], rgb[1], rgb[2], 1.0]),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.6),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The JSON being built and the binary buffer.
#[derive(Default)]
struct Writer {
    root: json::Root,
    bin: Vec<u8>,
    /// The vertex data of each primitive shape written so far, by [`shape_key`]: bodies with
    /// equal shapes share it (a chain of 10⁴ equal rods stores one rod).
    shapes: HashMap<Vec<u64>, MeshData>,
}

/// The accessors of one tessellated shape: positions, normals, triangle indices.
#[derive(Clone, Copy)]
struct MeshData {
    positions: json::Index<json::Accessor>,
    normals: json::Index<json::Accessor>,
    indices: json::Index<json::Accessor>,
}

/// A key equal for equal primitive shapes (their variant and dimensions, bit for bit); `None`
/// for meshes from files (written once per use).
fn shape_key(shape: &Shape) -> Option<Vec<u64>> {
    let bits = |tag: u64, v: &[f64]| {
        let mut key = vec![tag];
        key.extend(v.iter().map(|x| x.to_bits()));
        key
    };
    match shape {
        Shape::Box { size } => Some(bits(0, size)),
        Shape::Cylinder { radius, length } => Some(bits(1, &[*radius, *length])),
        Shape::Sphere { radius } => Some(bits(2, &[*radius])),
        Shape::Mesh(_) => None,
    }
}

impl Writer {
    /// Appends `data` (4-byte components) as a buffer view; returns it.
    fn view(
        &mut self,
        data: impl Iterator<Item = f32>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        for x in data {
            self.bin.extend_from_slice(&x.to_le_bytes());
        }
        self.view_from(offset, target)
    }

    fn view_from(
        &mut self,
        offset: usize,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(self.bin.len() - offset),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    fn accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let (min, max) = match bounds {
            Some((lo, hi)) => (Some(json::Value::from(lo)), Some(json::Value::from(hi))),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// The shared keyframe times (scalar, with min and max as the spec requires).
    fn times(&mut self, t: &[f64]) -> json::Index<json::Accessor> {
        let v = self.view(t.iter().map(|&x| x as f32), None);
        let (lo, hi) = (t[0] as f32, t[t.len() - 1] as f32);
        self.accessor(
            v,
            t.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Scalar,
            Some((vec![lo], vec![hi])),
        )
    }

    fn vectors(&mut self, v: &[[f32; 3]]) -> json::Index<json::Accessor> {
        let view = self.view(v.iter().flatten().copied(), None);
        self.accessor(
            view,
            v.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            None,
        )
    }

    fn quaternions(&mut self, q: &[[f32; 4]]) -> json::Index<json::Accessor> {
        let view = self.view(q.iter().flatten().copied(), None);
        self.accessor(
            view,
            q.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec4,
            None,
        )
    }

    /// The vertex data of `shape` (item `item` of `body`, for messages): written on its first
    /// use, shared after.
    ///
    /// # Errors
    /// A mesh with bad indices or non-finite vertices.
    fn shape(&mut self, shape: &Shape, body: &str, item: usize) -> Result<MeshData, Error> {
        let key = shape_key(shape);
        if let Some(data) = key.as_ref().and_then(|k| self.shapes.get(k)) {
            return Ok(*data);
        }
        let m = mesh_of(shape);
        check_mesh(&m, body, item)?;
        let data = self.mesh_data(&m);
        if let Some(k) = key {
            self.shapes.insert(k, data);
        }
        Ok(data)
    }

    /// A mesh of one triangle primitive with `material`.
    fn mesh(
        &mut self,
        name: &str,
        data: MeshData,
        material: json::Index<json::Material>,
    ) -> json::Index<json::Mesh> {
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), data.positions);
        attributes.insert(Valid(json::mesh::Semantic::Normals), data.normals);
        self.root.push(json::Mesh {
            name: Some(name.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                indices: Some(data.indices),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
                extensions: None,
                extras: Default::default(),
            }],
            weights: None,
            extensions: None,
            extras: Default::default(),
        })
    }

    /// Writes the vertex data of `m`.
    fn mesh_data(&mut self, m: &Mesh) -> MeshData {
        let array = Some(json::buffer::Target::ArrayBuffer);
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &m.positions {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let pv = self.view(m.positions.iter().flatten().copied(), array);
        let position = self.accessor(
            pv,
            m.positions.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            Some((lo.to_vec(), hi.to_vec())),
        );
        let nv = self.view(m.normals.iter().flatten().copied(), array);
        let normal = self.accessor(
            nv,
            m.normals.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            None,
        );
        let offset = self.bin.len();
        for i in &m.indices {
            self.bin.extend_from_slice(&i.to_le_bytes());
        }
        let iv = self.view_from(offset, Some(json::buffer::Target::ElementArrayBuffer));
        let indices = self.accessor(
            iv,
            m.indices.len(),
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
            None,
        );
        MeshData {
            positions: position,
            normals: normal,
            indices,
        }
    }

    /// The buffer, the asset, then the GLB container.
    fn finish(mut self) -> Result<Vec<u8>, Error> {
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
        }
        self.root.asset = json::Asset {
            generator: Some(format!("cardan-report {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        };
        let mut text = self
            .root
            .to_vec()
            .map_err(|e| Error::Scene(format!("glTF JSON: {e}")))?;
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let bin_chunk = if self.bin.is_empty() {
            0
        } else {
            8 + self.bin.len()
        };
        let total = 12 + 8 + text.len() + bin_chunk;
        let total32 = u32::try_from(total).map_err(|_| {
            Error::Scene(format!(
                "the animation would be {total} bytes, beyond the 4 GiB of a .glb"
            ))
        })?;
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&total32.to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        if !self.bin.is_empty() {
            out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
            out.extend_from_slice(b"BIN\0");
            out.extend_from_slice(&self.bin);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Body, Geometry};

    fn body(name: &str, radius: f64) -> Body {
        Body {
            name: name.into(),
            colour: [0.5, 0.5, 0.5],
            geometry: vec![
                Geometry::at(Shape::Sphere { radius }, [0.0; 3]),
                Geometry::at(
                    Shape::Box {
                        size: [1.0, 0.1, 0.1],
                    },
                    [0.5, 0.0, 0.0],
                ),
            ],
            points: Vec::new(),
            positions: vec![[0.0; 3], [0.1, 0.0, 0.0]],
            rotations: vec![[1.0, 0.0, 0.0, 0.0]; 2],
        }
    }

    /// Bodies with equal shapes share their vertex data (one accessor set per distinct shape)
    /// and keep their own meshes and materials.
    #[test]
    fn equal_shapes_share_their_vertex_data() {
        let scene = Scene {
            name: "s".into(),
            times: vec![0.0, 1.0],
            bodies: vec![body("a", 0.05), body("b", 0.05), body("c", 0.07)],
            axes: Vec::new(),
            extent: 1.0,
        };
        let g = gltf::Gltf::from_slice(&write_glb(&scene).unwrap()).unwrap();
        let position = |body: &str, item: usize| {
            let node = g.nodes().find(|n| n.name() == Some(body)).unwrap();
            let child = node.children().nth(item).unwrap();
            let p = child.mesh().unwrap().primitives().next().unwrap();
            let material = p.material().index();
            (p.get(&gltf::Semantic::Positions).unwrap().index(), material)
        };
        assert_eq!(position("a", 0).0, position("b", 0).0, "equal spheres");
        assert_ne!(position("a", 0).0, position("c", 0).0, "another radius");
        assert_eq!(position("a", 1).0, position("c", 1).0, "equal boxes");
        assert_ne!(position("a", 0).1, position("b", 0).1, "own materials");
        assert_eq!(g.meshes().count(), 6);
        // 2 spheres' and 1 box's positions, normals and indices, 1 time accessor, 3 × 2 tracks.
        assert_eq!(g.accessors().count(), 3 * 3 + 1 + 6);
    }
}
