//! The links' `<collision>` elements → `[[shape]]` tables of one material (an overlay's
//! `[urdf] collision = "MATERIAL"`): boxes, cylinders, spheres, capsules and convex hulls of
//! STL or OBJ meshes, each at a point of its body with its z and x axes as vectors of the body.
//!
//! A collision's frame is C = T_link · T_origin, written in global coordinates at q = 0 (the
//! body's `global_points` and `global_vectors`, as the link origins and joint frames are). URDF
//! cylinders and capsules lie along their frame's z axis, as cardan's do, so the shape's axis
//! is C's z and its x axis C's x.
//!
//! The robot's shapes are in collision group 2 and touch group 1 only: they do not touch each
//! other (a robot's collision geometry overlaps between links, which URDF readers filter by
//! adjacency or leave to the user), and they touch the shapes an overlay adds (group 1 by
//! default: a floor, a part to grip). With `self_collision` ([`crate::Options`]) they touch
//! group 2 too: every pair of links whose bodies are not the two bodies of one joint (the
//! model's rule for every shape; MuJoCo's default for a URDF, which filters parent and child).
//!
//! A mesh that cannot be found, a COLLADA mesh (the shapes read STL and OBJ) or a non-uniform
//! scale leaves the collision out, with a warning at its line.

use crate::error::Warning;
use crate::import::Import;
use crate::numbers::num;
use crate::robot::Geometry;
use nalgebra::Vector3;
use std::fmt::Write;
use std::path::PathBuf;

/// One collision as a shape: the body slot (0 ground, g + 1 body g), its point and vectors
/// (name and global value at q = 0), and the `[[shape]]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct CollisionShape {
    /// 0 for the ground, g + 1 for body g.
    pub slot: usize,
    /// The point's name and place.
    pub point: (String, Vector3<f64>),
    /// The z and x axes' names and directions.
    pub vectors: [(String, Vector3<f64>); 2],
    /// The `[[shape]]` table's text.
    pub table: String,
}

/// The shapes of every link's collisions in `material`, and the warnings. `taken(slot, name)`
/// says whether a body already has a point or vector of that name.
pub fn collision_shapes(
    import: &Import,
    material: &str,
    resolve: &dyn Fn(&str) -> Option<PathBuf>,
    taken: &dyn Fn(usize, &str) -> bool,
) -> (Vec<CollisionShape>, Vec<Warning>) {
    let lay = &import.layout;
    let mut out: Vec<CollisionShape> = Vec::new();
    let mut warnings = Vec::new();
    let mut names = crate::names::Namespace::default();
    for (l, link) in import.robot.links.iter().enumerate() {
        let slot = lay.body_of[l].map_or(0, |g| g + 1);
        let body = lay.body_of[l].map_or("ground", |g| import.body_names[g].as_str());
        for c in &link.collisions {
            let kind = match shape_keys(&c.geometry, resolve) {
                Ok(kind) => kind,
                Err(why) => {
                    warnings.push(Warning {
                        line: c.line,
                        message: format!(
                            "link \"{}\": its <collision> is not a contact shape: {why}",
                            link.name
                        ),
                    });
                    continue;
                }
            };
            let name = names.claim(&format!("{}_collision", import.link_points[l]));
            let mut point = name.clone();
            let mut n = 2;
            let free = |p: &str, out: &[CollisionShape]| {
                [p.to_string(), format!("{p}_z"), format!("{p}_x")]
                    .iter()
                    .all(|x| {
                        !taken(slot, x) && !out.iter().any(|s| s.slot == slot && s.point.0 == *x)
                    })
            };
            while !free(&point, &out) {
                point = format!("{name}_{n}");
                n += 1;
            }
            let touches = match import.options.self_collision {
                true => "[1, 2]",
                false => "[1]",
            };
            let frame = lay.link_pose[l].then(&c.origin);
            let mut table = String::new();
            let _ = write!(
                table,
                "\n[[shape]]   # <collision> of link \"{}\" (line {})\nname = \"{name}\"\n{kind}\n\
                 body = \"{body}\"\nmaterial = \"{material}\"\npoint = \"{point}\"\n\
                 axis = \"{point}_z\"\nx_axis = \"{point}_x\"\ngroups = [2]\ncollides_with = {touches}\n",
                link.name.replace(['\n', '\r'], " "),
                c.line
            );
            out.push(CollisionShape {
                slot,
                vectors: [
                    (format!("{point}_z"), frame.a.column(2).into_owned()),
                    (format!("{point}_x"), frame.a.column(0).into_owned()),
                ],
                point: (point, frame.r),
                table,
            });
        }
    }
    (out, warnings)
}

/// The shape's `type` and size keys, or why the geometry makes none.
fn shape_keys(g: &Geometry, resolve: &dyn Fn(&str) -> Option<PathBuf>) -> Result<String, String> {
    Ok(match g {
        Geometry::Box(s) => format!(
            "type = \"box\"\nsize = [{}, {}, {}]",
            num(s.x),
            num(s.y),
            num(s.z)
        ),
        Geometry::Cylinder { radius, length } => format!(
            "type = \"cylinder\"\nradius = {}\nlength = {}",
            num(*radius),
            num(*length)
        ),
        Geometry::Capsule { radius, length } => format!(
            "type = \"capsule\"\nradius = {}\nlength = {}",
            num(*radius),
            num(*length)
        ),
        Geometry::Sphere(r) => format!("type = \"sphere\"\nradius = {}", num(*r)),
        Geometry::Mesh { filename, scale } => {
            let lower = filename.to_ascii_lowercase();
            if !(lower.ends_with(".stl") || lower.ends_with(".obj")) {
                return Err(format!(
                    "mesh \"{filename}\" is neither STL nor OBJ (convert it, or add a [[shape]] in the overlay)"
                ));
            }
            if (scale.max() - scale.min()).abs() > 1e-9 * scale.amax() || scale.x <= 0.0 {
                return Err(format!(
                    "mesh \"{filename}\" has the scale {} {} {} (a shape takes one positive factor)",
                    scale.x, scale.y, scale.z
                ));
            }
            let Some(path) = resolve(filename) else {
                return Err(format!(
                    "mesh \"{filename}\" not found (package:// names are looked up in CARDAN_PACKAGE_PATH, ROS_PACKAGE_PATH and the URDF's parent directories)"
                ));
            };
            let file = path
                .to_string_lossy()
                .replace('\\', "\\\\")
                .replace('"', "\\\"");
            format!(
                "type = \"convex_mesh\"\nfile = \"{file}\"\nscale = {}",
                num(scale.x)
            )
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{import, Options};

    #[test]
    fn collisions_become_shapes_at_their_frames_and_unusable_ones_warn() {
        let text = r#"<robot name="r"><link name="world"><collision><geometry><box size="2 2 0.1"/></geometry></collision></link>
<link name="arm"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial>
  <collision><origin xyz="0 0 0.5" rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  <collision><geometry><mesh filename="arm.dae"/></geometry></collision>
  <collision><geometry><mesh filename="arm.stl" scale="1 1 2"/></geometry></collision>
  <collision><geometry><mesh filename="package://nowhere/arm.stl"/></geometry></collision>
</link>
<joint name="j" type="continuous"><parent link="world"/><child link="arm"/><origin xyz="1 0 0"/></joint></robot>"#;
        let i = import(text, Options::default()).unwrap();
        let (shapes, warnings) =
            collision_shapes(&i, "steel", &|_| None, &|_, n| n == "arm_collision");
        assert_eq!(shapes.len(), 2, "{shapes:?}");
        // The ground's box, then the arm's cylinder: its point 0.5 m up the arm's z from the
        // joint origin (1, 0, 0), its axis turned from z onto −y.
        assert_eq!(shapes[0].slot, 0);
        assert!(
            shapes[0].table.contains("body = \"ground\""),
            "{}",
            shapes[0].table
        );
        let s = &shapes[1];
        assert_eq!(s.slot, 1);
        assert_eq!(
            s.point.0, "arm_collision_2",
            "a name the body has is not reused"
        );
        assert!((s.point.1 - Vector3::new(1.0, 0.0, 0.5)).norm() < 1e-15);
        assert!((s.vectors[0].1 - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
        assert!(
            s.table
                .contains("type = \"cylinder\"\nradius = 0.05\nlength = 0.4"),
            "{}",
            s.table
        );
        assert!(s.table.contains("material = \"steel\""));
        assert_eq!(warnings.len(), 3);
        assert!(
            warnings[0].message.contains("neither STL nor OBJ"),
            "{}",
            warnings[0]
        );
        assert!(
            warnings[1].message.contains("one positive factor"),
            "{}",
            warnings[1]
        );
        assert!(warnings[2].message.contains("not found"), "{}", warnings[2]);
        assert_eq!(warnings[2].line, 6);
    }
}
