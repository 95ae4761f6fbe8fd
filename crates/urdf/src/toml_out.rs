//! An [`Import`] → a cardan model file (TOML, `docs/model-format.md`) with a comment tracing
//! every element to its URDF line. Numbers are written in full (shortest round-trip form), so
//! the text builds the same mechanism as the URDF.

use crate::import::Import;
use crate::names::Namespace;
use crate::robot::JointType;
use nalgebra::{Matrix3, Vector3};
use std::collections::BTreeMap;
use std::fmt::Write as _;

pub(crate) use crate::numbers::{num, vec3};

fn matrix(m: &Matrix3<f64>) -> String {
    let row = |k: usize| {
        format!(
            "[{}, {}, {}]",
            num(m[(k, 0)]),
            num(m[(k, 1)]),
            num(m[(k, 2)])
        )
    };
    format!("[{}, {}, {}]", row(0), row(1), row(2))
}

/// A comment's text: no line breaks.
fn comment(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// A unit vector ⟂ `z`: the global axis least along z, its part ⟂ z.
fn perpendicular(z: &Vector3<f64>) -> Vector3<f64> {
    let k = (0..3)
        .min_by(|&a, &b| z[a].abs().total_cmp(&z[b].abs()))
        .unwrap_or(0);
    let e = Vector3::ith(k, 1.0);
    (e - z * z.dot(&e)).normalize()
}

/// Named points and vectors of one body (or the ground), global at q = 0.
#[derive(Default)]
struct Features {
    points: BTreeMap<String, Vector3<f64>>,
    vectors: BTreeMap<String, Vector3<f64>>,
}

fn inline(map: &BTreeMap<String, Vector3<f64>>) -> String {
    let items: Vec<String> = map
        .iter()
        .map(|(k, v)| format!("{k} = {}", vec3(v)))
        .collect();
    format!("{{ {} }}", items.join(", "))
}

/// The features of every body (index 0 the ground, g + 1 group g).
fn features(import: &Import) -> Vec<Features> {
    let lay = &import.layout;
    let slot = |b: Option<usize>| b.map_or(0, |g| g + 1);
    let mut out: Vec<Features> = (0..=lay.groups.len())
        .map(|_| Features::default())
        .collect();
    for (l, name) in import.link_points.iter().enumerate() {
        out[slot(lay.body_of[l])]
            .points
            .insert(name.clone(), lay.link_pose[l].r);
    }
    for (k, j) in import.robot.joints.iter().enumerate() {
        let (p, c) = import.tree.links[k];
        let (point, zn, xn) = &import.joint_features[k];
        if point.is_empty() {
            continue;
        }
        // The joint frame J on the parent; on the child, J moved by q₀ (module docs of
        // crate::import): the joint's coordinate is q₀ in the drawn pose.
        let frame = lay.joint_frame[k];
        let x0 = perpendicular(&j.axis);
        let moved = frame.then(&crate::bodies::motion(j.kind, &j.axis, lay.q0[k]));
        for (b, f) in [(lay.body_of[p], frame), (lay.body_of[c], moved)] {
            let feats = &mut out[slot(b)];
            feats.points.insert(point.clone(), f.r);
            feats.vectors.insert(zn.clone(), f.a * j.axis);
            feats.vectors.insert(xn.clone(), f.a * x0);
        }
    }
    out
}

/// The cardan model text of `import`; `file` names the URDF in the comments.
pub fn to_toml(import: &Import, file: &str) -> String {
    to_toml_with(import, file, true, &[], &[])
}

/// Whether body `slot` (0 the ground, g + 1 body g) of the model text has a point or vector
/// `name` (for [`crate::collisions::collision_shapes`]).
pub fn feature_taken(import: &Import) -> impl Fn(usize, &str) -> bool {
    let feats = features(import);
    move |slot, name| {
        feats
            .get(slot)
            .is_some_and(|f| f.points.contains_key(name) || f.vectors.contains_key(name))
    }
}

/// [`to_toml`], with or without the default `[analysis]` (an overlay gives its own), with
/// each body's `geometry` items ([`crate::visuals`]; none when `geometry` is empty: the body
/// is drawn from its points and joints) and the collisions' `shapes`
/// ([`crate::collisions`]: their points and vectors join their bodies').
pub fn to_toml_with(
    import: &Import,
    file: &str,
    analysis: bool,
    geometry: &[Vec<String>],
    shapes: &[crate::collisions::CollisionShape],
) -> String {
    let robot = &import.robot;
    let lay = &import.layout;
    let mut out = String::new();
    let moving = robot
        .joints
        .iter()
        .filter(|j| j.kind != JointType::Fixed)
        .count();
    let _ = writeln!(
        out,
        "# Imported from {} (URDF robot \"{}\") by cardan: {} links in {} moving bodies, {} moving joints.\n\
         # Links joined by fixed joints are one body (its frame: the centre of mass, the first link's axes);\n\
         # every joint coordinate is 0 in the pose drawn, the URDF's zero configuration.",
        comment(file),
        comment(&robot.name),
        robot.links.len(),
        lay.groups.len(),
        moving
    );
    for w in &import.warnings {
        let _ = writeln!(
            out,
            "# warning: {}:{}: {}",
            comment(file),
            w.line,
            comment(&w.message)
        );
    }
    let _ = writeln!(
        out,
        "\n[model]\nname = \"{}\"\nunits = \"SI\"\ngravity = [0.0, 0.0, -9.81]",
        crate::names::sanitize(&robot.name)
    );
    let mut feats = features(import);
    for s in shapes {
        let f = &mut feats[s.slot];
        f.points.insert(s.point.0.clone(), s.point.1);
        for (name, v) in &s.vectors {
            f.vectors.insert(name.clone(), *v);
        }
    }
    if !feats[0].points.is_empty() || !feats[0].vectors.is_empty() {
        let _ = writeln!(out, "\n[ground]");
        let _ = writeln!(out, "points = {}", inline(&feats[0].points));
        if !feats[0].vectors.is_empty() {
            let _ = writeln!(out, "vectors = {}", inline(&feats[0].vectors));
        }
    }
    for (g, group) in lay.groups.iter().enumerate() {
        let links: Vec<String> = group
            .links
            .iter()
            .map(|&l| {
                format!(
                    "{} (line {})",
                    comment(&robot.links[l].name),
                    robot.links[l].line
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "\n[[body]]   # link{} {}",
            if links.len() > 1 { "s" } else { "" },
            links.join(", ")
        );
        let _ = writeln!(out, "name = \"{}\"", import.body_names[g]);
        let a = group.axes(lay);
        if group.mass > 0.0 {
            let _ = writeln!(out, "mass = {}", num(group.mass));
            let i = a.transpose() * group.inertia * a;
            let i = (i + i.transpose()) * 0.5;
            let _ = writeln!(out, "inertia = {}", matrix(&i));
        }
        let _ = writeln!(out, "position = {}", vec3(&group.com));
        let _ = writeln!(
            out,
            "orientation = {{ x = {}, z = {} }}",
            vec3(&a.column(0).into_owned()),
            vec3(&a.column(2).into_owned())
        );
        let f = &feats[g + 1];
        let _ = writeln!(out, "global_points = {}", inline(&f.points));
        if !f.vectors.is_empty() {
            let _ = writeln!(out, "global_vectors = {}", inline(&f.vectors));
        }
        if let Some(items) = geometry.get(g).filter(|i| !i.is_empty()) {
            let _ = writeln!(out, "geometry = [\n  {},\n]", items.join(",\n  "));
        }
    }
    joints(import, &mut out);
    for s in shapes {
        out.push_str(&s.table);
    }
    if !analysis {
        return out;
    }
    let _ = writeln!(
        out,
        "\n[analysis]   # the robot released at rest in its zero configuration, under gravity\nkind = \"dynamic\"\nt_end = 2.0\noutput_dt = 0.01"
    );
    out
}

/// `[[joint]]`, `[[limit]]`, `[[coupler]]`, (`damping` chosen) `[[force]]` and (`friction`
/// chosen) `[[friction]]` tables.
fn joints(import: &Import, out: &mut String) {
    let robot = &import.robot;
    let lay = &import.layout;
    let body = |b: Option<usize>| b.map_or("ground", |g| import.body_names[g].as_str());
    let mut elements = Namespace::default();
    for n in &import.joint_names {
        elements.claim(n);
    }
    let mut forces = String::new();
    for (k, j) in robot.joints.iter().enumerate() {
        let kind = match j.kind {
            JointType::Revolute | JointType::Continuous => "revolute",
            JointType::Prismatic => "prismatic",
            JointType::Planar => "planar",
            JointType::Fixed | JointType::Floating => continue,
        };
        let (p, c) = import.tree.links[k];
        let (point, z, x) = &import.joint_features[k];
        let _ = writeln!(
            out,
            "\n[[joint]]   # URDF joint \"{}\" (line {}), {}\nname = \"{}\"\ntype = \"{kind}\"\n\
             body_i = \"{}\"\npoint_i = \"{point}\"\naxis_i = \"{z}\"\nx_axis_i = \"{x}\"\n\
             body_j = \"{}\"\npoint_j = \"{point}\"\naxis_j = \"{z}\"\nx_axis_j = \"{x}\"",
            comment(&j.name),
            j.line,
            j.kind.name(),
            import.joint_names[k],
            body(lay.body_of[p]),
            body(lay.body_of[c]),
        );
        let slide = j.kind == JointType::Prismatic;
        let (damping, friction, line) = j
            .dynamics
            .map_or((0.0, 0.0, 0), |d| (d.damping, d.friction, d.line));
        if crate::import::damped(import, k) {
            let (what, kind) = match slide {
                true => ("force", "translational_spring_damper"),
                false => ("torque", "rotational_spring_damper"),
            };
            let _ = write!(
                forces,
                "\n[[force]]   # <dynamics damping> of joint \"{}\" (line {}): {what} −c q̇\nname = \"{}\"\ntype = \"{kind}\"\njoint = \"{}\"\ndamping = {}\n",
                comment(&j.name),
                line,
                elements.claim(&format!("{}_damping", import.joint_names[k])),
                import.joint_names[k],
                num(damping)
            );
        }
        if crate::import::frictional(import, k) {
            let key = if slide { "force" } else { "torque" };
            let _ = write!(
                forces,
                "\n[[friction]]   # <dynamics friction> of joint \"{}\" (line {}): a constant {key} against the motion\nname = \"{}\"\nlaw = \"constant\"\njoint = \"{}\"\n{key} = {}\n",
                comment(&j.name),
                line,
                elements.claim(&format!("{}_friction", import.joint_names[k])),
                import.joint_names[k],
                num(friction)
            );
        }
        // The actuator's ratings: warnings when a driven motion passes them.
        if let Some(l) = &j.limit {
            for (key, v) in [("effort_limit", l.effort), ("rate_limit", l.velocity)] {
                if let Some(v) = v.filter(|v| v.is_finite() && *v > 0.0) {
                    let _ = writeln!(out, "{key} = {}", num(v));
                }
            }
        }
        let Some(l) = j.limit.filter(|l| l.lower < l.upper) else {
            continue;
        };
        if import.options.limits && matches!(j.kind, JointType::Revolute | JointType::Prismatic) {
            let mut bounds = String::new();
            for (key, v) in [("lower", l.lower), ("upper", l.upper)] {
                if v.is_finite() {
                    let _ = write!(bounds, "\n{key} = {}", num(v));
                }
            }
            if bounds.is_empty() {
                continue;
            }
            let _ = writeln!(
                out,
                "\n[[limit]]   # line {}\nname = \"{}\"\njoint = \"{}\"{bounds}",
                l.line,
                elements.claim(&format!("{}_limit", import.joint_names[k])),
                import.joint_names[k],
            );
        }
    }
    for &(t, k) in &import.couplers {
        let m = robot.joints[k]
            .mimic
            .as_ref()
            .map_or((1.0, 0.0, 0), |m| (m.multiplier, m.offset, m.line));
        let _ = writeln!(
            out,
            "\n[[coupler]]   # <mimic> of joint \"{}\" (line {}): q = {} q_{} + {}\nname = \"{}\"\ntype = \"gear\"\njoint_i = \"{}\"\njoint_j = \"{}\"\nratio = {}\nconstant = {}",
            comment(&robot.joints[k].name),
            m.2,
            num(m.0),
            comment(&robot.joints[t].name),
            num(m.1),
            elements.claim(&format!("{}_mimic", import.joint_names[k])),
            import.joint_names[t],
            import.joint_names[k],
            num(m.0),
            num(m.1)
        );
    }
    out.push_str(&forces);
}
