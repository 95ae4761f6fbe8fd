//! The `geometry = [...]` key of a body: what the animation (`animation.glb`, `index.html`)
//! draws for it, read and checked before the analysis runs (docs/animation.md).
//!
//! Items: `{ shape = "box", size = [a, b, c] }`, `{ shape = "cylinder", radius, length,
//! axis = [..] }` (axis default z), `{ shape = "sphere", radius }`, `{ shape = "mesh", file =
//! "part.stl", scale = 0.001 }` (STL or OBJ, the path relative to the model file, `scale` from
//! the file's coordinates to metres), each with an optional `position = [..]` (body
//! coordinates, m) and `orientation = { ... }` (the forms of a body's orientation, relative to
//! the body frame). Lengths are in the model's units (`[model] units`; a mesh's `scale` goes
//! from the file's coordinates to them) and converted to metres.
//!
//! Errors name the body, the item and the line: an unknown shape or a key the shape does not
//! take, a missing or non-positive size, a missing or unreadable mesh file, a malformed mesh,
//! more than [`MAX_TRIANGLES`] triangles in the whole model, a non-finite vertex.

use crate::build::orientation_matrix;
use crate::diag::{did_you_mean, Error, Source};
use crate::file::{GeometrySpec, Num, Vec3};
use cardan_eulerparam::EulerParams;
use cardan_report::{read_mesh, Geometry, Shape};
use nalgebra::{Matrix3, Vector3};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, OnceLock};
use toml::Spanned;

/// Most triangles of all mesh files of a model together.
pub const MAX_TRIANGLES: usize = 2_000_000;

/// The shapes a geometry item may have.
pub const SHAPES: [&str; 4] = ["box", "cylinder", "sphere", "mesh"];

/// What the model file says about the animation.
#[derive(Debug, Clone, Default)]
pub struct Declared {
    /// Body name → its declared geometry items (a body absent here gets derived geometry).
    pub bodies: BTreeMap<String, Vec<Geometry>>,
    /// The direction drawn upwards: against `[model] gravity` if given, else zero.
    pub up: [f64; 3],
}

/// Reads the bodies' `geometry` keys (and gravity, for the view's up direction).
///
/// # Errors
/// An input error naming the body, the item and the line (module docs).
pub fn load(src: &Source) -> Result<Declared, Error> {
    let (src, mut file, _) = crate::overlay::parse_overlaid(src.clone())?;
    LazyGeometry::take(&src, &mut file).declared()
}

/// The bodies' `geometry` keys taken from a parsed file, read (mesh files included) the first
/// time they are asked for ([`LazyGeometry::declared`]) and kept: only the commands that draw
/// or check the geometry read its meshes, not every analysis (a robot's visual meshes were
/// 60 ms of a two-sample inverse dynamics from Python). Clones share the reading.
#[derive(Debug, Clone)]
pub struct LazyGeometry {
    pending: Arc<Pending>,
    read: Arc<OnceLock<Result<Declared, Error>>>,
}

/// What reading the geometry needs from the model file.
#[derive(Debug)]
struct Pending {
    src: Source,
    /// The model's length unit in metres, or why the units are wrong.
    length: Result<f64, Error>,
    up: [f64; 3],
    /// Each body with a `geometry` key: its name and items.
    bodies: Vec<(String, Spanned<Vec<Spanned<GeometrySpec>>>)>,
}

impl LazyGeometry {
    /// Takes the `geometry` keys out of `file` (parsed from `src`), to be read when asked for.
    pub fn take(src: &Source, file: &mut crate::file::ModelFile) -> Self {
        let length = crate::build::model_units(src, file).map(|u| u.length());
        let up = file.model.get_ref().gravity.as_ref().map_or([0.0; 3], |g| {
            let g = g.get_ref();
            [*g[0].get_ref(), *g[1].get_ref(), *g[2].get_ref()].map(|x| -x)
        });
        let bodies = (file.body.iter_mut())
            .filter_map(|b| {
                let b = b.get_mut();
                b.geometry.take().map(|g| (b.name.get_ref().clone(), g))
            })
            .collect();
        Self {
            pending: Arc::new(Pending {
                src: src.clone(),
                length,
                up,
                bodies,
            }),
            read: Arc::new(OnceLock::new()),
        }
    }

    /// The declared geometry, its mesh files read (the first call reads them).
    ///
    /// # Errors
    /// An input error naming the body, the item and the line (module docs).
    pub fn declared(&self) -> Result<Declared, Error> {
        self.read.get_or_init(|| self.pending.read()).clone()
    }

    /// Whether the declared geometry can be read (reading it, without a copy).
    ///
    /// # Errors
    /// As [`Self::declared`].
    pub fn readable(&self) -> Result<(), Error> {
        let read = self.read.get_or_init(|| self.pending.read());
        read.as_ref().map(drop).map_err(Clone::clone)
    }
}

impl Pending {
    fn read(&self) -> Result<Declared, Error> {
        let src = &self.src;
        let length = self.length.clone()?;
        let mut out = Declared {
            up: self.up,
            ..Declared::default()
        };
        let dir = src.path.parent().unwrap_or(Path::new("."));
        let mut budget = MAX_TRIANGLES;
        for (name, items) in &self.bodies {
            let mut list = Vec::with_capacity(items.get_ref().len());
            for (k, item) in items.get_ref().iter().enumerate() {
                let cx = Item {
                    src,
                    body: name,
                    number: k + 1,
                    length,
                };
                let g = cx.geometry(item, dir, &mut budget)?;
                list.push(g);
            }
            out.bodies.insert(name.clone(), list);
        }
        draw_small(&mut out);
        Ok(out)
    }
}

/// The meshes of a model drawn with at most [`DRAWN_TRIANGLES`] together: when they have more,
/// each is decimated ([`cardan_report::decimate`]) to its share, so a robot's report stays a few
/// megabytes whatever its meshes (the file's triangles are checked against [`MAX_TRIANGLES`]
/// first).
fn draw_small(declared: &mut Declared) {
    let meshes = || declared.bodies.values().flatten();
    let total: usize = meshes()
        .map(|g| match &g.shape {
            Shape::Mesh(m) => m.triangles(),
            _ => 0,
        })
        .sum();
    if total <= DRAWN_TRIANGLES {
        return;
    }
    for g in declared.bodies.values_mut().flatten() {
        if let Shape::Mesh(m) = &mut g.shape {
            let share = (m.triangles() * DRAWN_TRIANGLES).div_ceil(total).max(200);
            *m = cardan_report::decimate::decimate(m, share).0;
        }
    }
}

/// The most triangles the meshes of a model are drawn with (about 5 MB of report).
pub const DRAWN_TRIANGLES: usize = 60_000;

/// One item being read: for its messages.
struct Item<'a> {
    src: &'a Source,
    body: &'a str,
    number: usize,
    /// The model's length unit in metres.
    length: f64,
}

impl Item<'_> {
    fn err(&self, span: std::ops::Range<usize>, why: impl std::fmt::Display) -> Error {
        self.src.error_at(
            span,
            format!(
                "body \"{}\": geometry item {}: {why}",
                self.body, self.number
            ),
        )
    }

    fn positive(
        &self,
        n: &Option<Num>,
        key: &str,
        whole: &Spanned<GeometrySpec>,
    ) -> Result<f64, Error> {
        let Some(n) = n else {
            return Err(self.err(whole.span(), format!("{key} = .. is missing")));
        };
        let v = *n.get_ref();
        if !(v.is_finite() && v > 0.0 && v < 1e6) {
            return Err(self.err(
                n.span(),
                format!("{key} = {v} must be positive, finite and below 10⁶"),
            ));
        }
        Ok(v)
    }

    fn vec3(&self, v: &Vec3, key: &str) -> Result<Vector3<f64>, Error> {
        let a = v.get_ref();
        let x = Vector3::new(*a[0].get_ref(), *a[1].get_ref(), *a[2].get_ref());
        if x.iter().any(|c| !c.is_finite() || c.abs() > 1e6) {
            return Err(self.err(
                v.span(),
                format!("{key} must hold finite numbers below 10⁶ in magnitude"),
            ));
        }
        Ok(x)
    }

    /// Refuses the keys `shape` does not take.
    fn only(&self, s: &Spanned<GeometrySpec>, shape: &str, allowed: &[&str]) -> Result<(), Error> {
        let g = s.get_ref();
        let given = [
            ("size", g.size.as_ref().map(Spanned::span)),
            ("radius", g.radius.as_ref().map(|n| n.span())),
            ("length", g.length.as_ref().map(|n| n.span())),
            ("axis", g.axis.as_ref().map(|n| n.span())),
            ("file", g.file.as_ref().map(|n| n.span())),
            ("scale", g.scale.as_ref().map(|n| n.span())),
        ];
        for (key, span) in given {
            if let (Some(span), false) = (span, allowed.contains(&key)) {
                return Err(self.err(
                    span,
                    format!(
                        "a {shape} takes no {key} (its keys: {}, position, orientation)",
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn geometry(
        &self,
        s: &Spanned<GeometrySpec>,
        dir: &Path,
        budget: &mut usize,
    ) -> Result<Geometry, Error> {
        let g = s.get_ref();
        let shape_name = g.shape.get_ref().as_str();
        let mut frame = match &g.orientation {
            Some(o) => orientation_matrix(self.src, o).map_err(|e| self.prefix(e))?,
            None => Matrix3::identity(),
        };
        let shape = match shape_name {
            "box" => {
                self.only(s, "box", &["size"])?;
                let Some(size) = &g.size else {
                    return Err(self.err(s.span(), "size = [a, b, c] is missing"));
                };
                let v = self.vec3(size, "size")?;
                if v.iter().any(|c| *c <= 0.0) {
                    return Err(self.err(size.span(), "size must be positive along every axis"));
                }
                let v = v * self.length;
                Shape::Box {
                    size: [v.x, v.y, v.z],
                }
            }
            "cylinder" => {
                self.only(s, "cylinder", &["radius", "length", "axis"])?;
                let radius = self.positive(&g.radius, "radius", s)?;
                let length = self.positive(&g.length, "length", s)?;
                if let Some(a) = &g.axis {
                    let v = self.vec3(a, "axis")?;
                    let f = cardan_eulerparam::frame_from_axis(&v)
                        .map_err(|e| self.err(a.span(), format!("axis: {e}")))?;
                    frame *= f;
                }
                Shape::Cylinder {
                    radius: radius * self.length,
                    length: length * self.length,
                }
            }
            "sphere" => {
                self.only(s, "sphere", &["radius"])?;
                Shape::Sphere {
                    radius: self.positive(&g.radius, "radius", s)? * self.length,
                }
            }
            "mesh" => {
                self.only(s, "mesh", &["file", "scale"])?;
                let Some(file) = &g.file else {
                    return Err(self.err(s.span(), "file = \"part.stl\" is missing"));
                };
                let scale = match &g.scale {
                    Some(_) => self.positive(&g.scale, "scale", s)?,
                    None => 1.0,
                };
                let path = dir.join(file.get_ref());
                let mesh = read_mesh(&path, scale * self.length, *budget)
                    .map_err(|e| self.err(file.span(), e))?;
                *budget -= mesh.triangles();
                Shape::Mesh(mesh)
            }
            other => {
                return Err(self.err(
                    g.shape.span(),
                    format!("unknown shape \"{other}\"{}", did_you_mean(other, SHAPES)),
                ))
            }
        };
        let position = match &g.position {
            Some(p) => self.vec3(p, "position")? * self.length,
            None => Vector3::zeros(),
        };
        let p = EulerParams::from_rotation_matrix(&frame)
            .map_err(|e| self.err(s.span(), format!("orientation: {e}")))?;
        Ok(Geometry {
            shape,
            position: [position.x, position.y, position.z],
            rotation: [p.e0(), p.e().x, p.e().y, p.e().z],
        })
    }

    /// An orientation error with the body and item in front.
    fn prefix(&self, mut e: Error) -> Error {
        e.message = format!(
            "body \"{}\": geometry item {}: {}",
            self.body, self.number, e.message
        );
        e
    }
}
