//! What the animation shows, without any mechanics: bodies with geometry, named points and
//! colours, joint axes, and each body's pose at the output times.
//!
//! A pose is the position r of the body frame's origin (global, metres) and its Euler
//! parameters p = [e0, e1, e2, e3] (scalar first), the unit quaternion of the rotation
//! A(p) = (2e0² − 1) I + 2(e eᵀ + e0 ẽ) from body to global coordinates. glTF stores the same
//! quaternion as [x, y, z, w] = [e1, e2, e3, e0].

use crate::Error;

/// A triangle mesh in body (or geometry-item) coordinates, metres.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals (one per position).
    pub normals: Vec<[f32; 3]>,
    /// Three indices into `positions` per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }
}

/// The shape of one geometry item, in its own frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A box centred at the origin with edge lengths `size` along x, y, z.
    Box {
        /// Edge lengths \[m\].
        size: [f64; 3],
    },
    /// A cylinder centred at the origin, its axis along z.
    Cylinder {
        /// Radius \[m\].
        radius: f64,
        /// Length along z \[m\].
        length: f64,
    },
    /// A sphere centred at the origin.
    Sphere {
        /// Radius \[m\].
        radius: f64,
    },
    /// A triangle mesh (from a mesh file, already scaled to metres).
    Mesh(Mesh),
}

/// One geometry item of a body: a shape placed in the body frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// The shape in its own frame.
    pub shape: Shape,
    /// Origin of the item's frame in body coordinates \[m\].
    pub position: [f64; 3],
    /// Euler parameters of the item's frame relative to the body frame.
    pub rotation: [f64; 4],
}

impl Geometry {
    /// `shape` at `position` in the body frame, not rotated.
    pub fn at(shape: Shape, position: [f64; 3]) -> Self {
        Self {
            shape,
            position,
            rotation: [1.0, 0.0, 0.0, 0.0],
        }
    }
}

/// A named point of a body, in body coordinates \[m\] (a trail can follow it).
#[derive(Debug, Clone, PartialEq)]
pub struct NamedPoint {
    /// The point's name.
    pub name: String,
    /// Body coordinates \[m\].
    pub local: [f64; 3],
}

/// One body: its look and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name (the glTF node's name).
    pub name: String,
    /// Linear RGB in 0..1 of its material.
    pub colour: [f32; 3],
    /// What is drawn, in the body frame.
    pub geometry: Vec<Geometry>,
    /// Named points in body coordinates.
    pub points: Vec<NamedPoint>,
    /// Position of the body frame's origin at each of [`Scene::times`] \[m\]; empty for a fixed
    /// body (the ground), which stays at the global frame.
    pub positions: Vec<[f64; 3]>,
    /// Euler parameters [e0, e1, e2, e3] at each of [`Scene::times`]; empty for a fixed body.
    pub rotations: Vec<[f64; 4]>,
}

impl Body {
    /// A body that moves (has poses).
    pub fn moves(&self) -> bool {
        !self.positions.is_empty()
    }
}

/// A joint axis drawn by the axis toggle: a line through `point` along `direction`, both in the
/// coordinates of body `body`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointAxis {
    /// The joint's name.
    pub name: String,
    /// Index into [`Scene::bodies`].
    pub body: usize,
    /// A point of the axis, body coordinates \[m\].
    pub point: [f64; 3],
    /// Its direction, body coordinates (need not be unit).
    pub direction: [f64; 3],
}

/// Everything the animation and the report show.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scene {
    /// The model's name (the glTF scene's name, the page title).
    pub name: String,
    /// Output times \[s\], strictly increasing.
    pub times: Vec<f64>,
    /// The bodies, each with a pose per time (or none for a fixed body).
    pub bodies: Vec<Body>,
    /// Joint axes for the axis toggle.
    pub axes: Vec<JointAxis>,
    /// Size of the mechanism \[m\] (the diagonal of the box around its points over the run): the
    /// length of the body-frame arrows and the camera's distance scale.
    pub extent: f64,
}

impl Scene {
    /// Checks what the writers rely on: times finite and strictly increasing (also as f32, the
    /// precision of glTF), one pose per time for each moving body, finite numbers, nonzero
    /// Euler parameters, unique body names, joint axes on existing bodies.
    ///
    /// # Errors
    /// [`Error::Scene`] naming the body, the time or the axis.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |m: String| Err(Error::Scene(m));
        if let Some(t) = self.times.iter().find(|t| !t.is_finite()) {
            return bad(format!("an output time is not finite ({t})"));
        }
        let increasing = |a: f64, b: f64| a < b && (a as f32) < (b as f32);
        for (k, w) in self.times.windows(2).enumerate() {
            if !increasing(w[0], w[1]) {
                return bad(format!(
                    "output times {} and {} (numbers {k} and {}) are not strictly increasing \
                     in single precision, which glTF keyframes need",
                    w[0],
                    w[1],
                    k + 1
                ));
            }
        }
        let mut names = std::collections::HashSet::with_capacity(self.bodies.len());
        for b in &self.bodies {
            if !names.insert(b.name.as_str()) {
                return bad(format!("two bodies are named \"{}\"", b.name));
            }
            if b.moves()
                && (b.positions.len() != self.times.len() || b.rotations.len() != self.times.len())
            {
                return bad(format!(
                    "body \"{}\": {} positions and {} rotations for {} output times",
                    b.name,
                    b.positions.len(),
                    b.rotations.len(),
                    self.times.len()
                ));
            }
            if let Some(k) = b
                .positions
                .iter()
                .position(|r| r.iter().any(|x| !x.is_finite()))
            {
                return bad(format!(
                    "body \"{}\": its position at t = {} s is not finite",
                    b.name, self.times[k]
                ));
            }
            if let Some(k) = b.rotations.iter().position(|p| !unit_ok(p)) {
                return bad(format!(
                    "body \"{}\": its Euler parameters at t = {} s are not finite or zero",
                    b.name, self.times[k]
                ));
            }
        }
        for a in &self.axes {
            if a.body >= self.bodies.len() {
                return bad(format!("joint axis \"{}\" names no body", a.name));
            }
        }
        Ok(())
    }
}

/// p is finite and of a length that can be normalized.
fn unit_ok(p: &[f64; 4]) -> bool {
    let n2: f64 = p.iter().map(|x| x * x).sum();
    n2.is_finite() && n2 > 1e-12
}

/// p / |p| as the glTF quaternion [x, y, z, w] = [e1, e2, e3, e0] in single precision.
pub fn gltf_rotation(p: &[f64; 4]) -> [f32; 4] {
    let n = p.iter().map(|x| x * x).sum::<f64>().sqrt();
    [
        (p[1] / n) as f32,
        (p[2] / n) as f32,
        (p[3] / n) as f32,
        (p[0] / n) as f32,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(name: &str) -> Body {
        Body {
            name: name.into(),
            colour: [0.5; 3],
            geometry: Vec::new(),
            points: Vec::new(),
            positions: vec![[0.0; 3]],
            rotations: vec![[1.0, 0.0, 0.0, 0.0]],
        }
    }

    #[test]
    fn a_repeated_body_name_is_refused_by_name() {
        let mut scene = Scene {
            name: "s".into(),
            times: vec![0.0],
            bodies: (0..1000).map(|k| body(&format!("b{k}"))).collect(),
            axes: Vec::new(),
            extent: 1.0,
        };
        assert!(scene.validate().is_ok());
        scene.bodies.push(body("b7"));
        let e = scene.validate().unwrap_err().to_string();
        assert!(e.contains("two bodies are named \"b7\""), "{e}");
    }
}
