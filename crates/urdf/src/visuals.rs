//! The links' `<visual>` elements → the `geometry` items of their bodies (what the 3D animation
//! and the report draw): boxes, cylinders, spheres and mesh files, placed in the body frame.
//!
//! A visual's frame is V = T_link · T_origin; in the body frame (origin c, axes A) it is at
//! Aᵀ (r_V − c) with axes Aᵀ A_V. Mesh file names (`package://…`, `file://…`, relative) are
//! resolved by the caller ([`crate::toml_out::to_toml_with`]); a mesh that cannot be found or a
//! non-uniform scale is a warning naming the link and the line (the body is drawn without it).

use crate::error::Warning;
use crate::import::Import;
use crate::robot::Geometry;
use crate::toml_out::{num, vec3};
use std::path::PathBuf;

/// The geometry items (TOML inline tables) of every body, and the warnings.
pub fn visuals(
    import: &Import,
    resolve: &dyn Fn(&str) -> Option<PathBuf>,
) -> (Vec<Vec<String>>, Vec<Warning>) {
    let lay = &import.layout;
    let mut items = vec![Vec::new(); lay.groups.len()];
    let mut warnings = Vec::new();
    for (g, group) in lay.groups.iter().enumerate() {
        let a = group.axes(lay);
        for &l in &group.links {
            let link = &import.robot.links[l];
            for v in &link.visuals {
                let frame = lay.link_pose[l].then(&v.origin);
                let r = a.transpose() * (frame.r - group.com);
                let rot = a.transpose() * frame.a;
                let place = format!(
                    "position = {}, orientation = {{ x = {}, z = {} }}",
                    vec3(&r),
                    vec3(&rot.column(0).into_owned()),
                    vec3(&rot.column(2).into_owned())
                );
                let shape = match &v.geometry {
                    Geometry::Box(size) => format!("shape = \"box\", size = {}", vec3(size)),
                    Geometry::Cylinder { radius, length }
                    | Geometry::Capsule { radius, length } => {
                        format!(
                            "shape = \"cylinder\", radius = {}, length = {}",
                            num(*radius),
                            num(*length)
                        )
                    }
                    Geometry::Sphere(radius) => {
                        format!("shape = \"sphere\", radius = {}", num(*radius))
                    }
                    Geometry::Mesh { filename, scale } => {
                        let Some(path) = resolve(filename) else {
                            warnings.push(Warning {
                                line: v.line,
                                message: format!(
                                    "link \"{}\": mesh \"{filename}\" not found (package:// names are looked up in CARDAN_PACKAGE_PATH, ROS_PACKAGE_PATH and the URDF's parent directories); the body is drawn without it",
                                    link.name
                                ),
                            });
                            continue;
                        };
                        // The drawing takes one positive factor: a non-uniform or mirroring scale
                        // (left and right parts from one file) is drawn at the mean magnitude.
                        let s = (scale.x * scale.y * scale.z).abs().cbrt();
                        if (scale.max() - scale.min()).abs() > 1e-9 * scale.amax() || s == 0.0 {
                            warnings.push(Warning {
                                line: v.line,
                                message: format!(
                                    "link \"{}\": mesh \"{filename}\" has the scale {} {} {} (non-uniform or mirrored); it is drawn at the uniform scale {s}, unmirrored",
                                    link.name, scale.x, scale.y, scale.z
                                ),
                            });
                            if s == 0.0 {
                                continue;
                            }
                        }
                        let file = path
                            .to_string_lossy()
                            .replace('\\', "\\\\")
                            .replace('"', "\\\"");
                        format!("shape = \"mesh\", file = \"{file}\", scale = {}", num(s))
                    }
                };
                items[g].push(format!("{{ {shape}, {place} }}"));
            }
        }
    }
    (items, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{import, Options};

    #[test]
    fn visuals_are_placed_in_the_body_frame_and_missing_meshes_warn() {
        let text = r#"<robot name="r"><link name="world"/>
<link name="arm"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial>
  <visual><origin xyz="0 0 0.5" rpy="0 1.5707963267948966 0"/><geometry><box size="0.1 0.2 0.3"/></geometry></visual>
  <visual><geometry><mesh filename="package://nowhere/arm.stl" scale="0.001 0.001 0.001"/></geometry></visual>
  <visual><geometry><mesh filename="arm.dae" scale="1 1 -1"/></geometry></visual>
</link>
<joint name="j" type="continuous"><parent link="world"/><child link="arm"/><origin xyz="1 0 0"/></joint></robot>"#;
        let i = import(text, Options::default()).unwrap();
        let found = |f: &str| (f == "arm.dae").then(|| PathBuf::from("/meshes/arm.dae"));
        let (items, warnings) = visuals(&i, &found);
        assert_eq!(items.len(), 1);
        assert_eq!(items[0].len(), 2, "{:?}", items[0]);
        // The box 0.3 m above the centre of mass, its x turned onto −z.
        assert!(
            items[0][0].contains("position = [0.0, 0.0, 0.3"),
            "{}",
            items[0][0]
        );
        assert!(
            items[0][0].contains("x = [6.123233995736766e-17, 0.0, -1.0]"),
            "{}",
            items[0][0]
        );
        assert!(
            items[0][1].contains("file = \"/meshes/arm.dae\", scale = 1.0"),
            "{}",
            items[0][1]
        );
        assert_eq!(warnings.len(), 2);
        assert_eq!(warnings[0].line, 4);
        assert!(warnings[0].message.contains("not found"), "{}", warnings[0]);
        assert!(warnings[1].message.contains("mirrored"), "{}", warnings[1]);
    }
}
