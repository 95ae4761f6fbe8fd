//! An [`Import`] → a cardan model file (TOML, `docs/model-format.md`), readable, with a comment
//! tracing every element to its ASMT path and line. Numbers are written in full (shortest
//! round-trip form), so the file builds the same mechanism as the ASMT file.

use crate::import::{BodyMap, Element, Feature, Import, Settings};
use cardan_mechanism::{
    CouplerKind, CouplerSpec, DriverSpec, DriverTarget, GearRatio, JointSpec, LimitSpec,
    TimeFunction, GROUND,
};
use nalgebra::Vector3;
use std::fmt::Write as _;

fn num(x: f64) -> String {
    format!("{x:?}")
}

fn vec3(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

/// A TOML basic string.
fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A comment line's text: no line breaks.
fn comment(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

fn function(f: &TimeFunction) -> String {
    match f {
        TimeFunction::Expression(e) => {
            format!("{{ kind = \"expression\", text = {} }}", string(e.text()))
        }
        TimeFunction::Constant(c) => format!("{{ kind = \"constant\", value = {} }}", num(*c)),
        TimeFunction::Polynomial(c) => format!(
            "{{ kind = \"polynomial\", coefficients = [{}] }}",
            c.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
        ),
        // The importer writes expressions only.
        other => format!("{{ kind = \"expression\", text = \"0\" }}  # unsupported: {other:?}"),
    }
}

fn features(out: &mut String, table: &str, list: &[&Feature]) {
    if list.is_empty() {
        return;
    }
    let _ = writeln!(out, "[{table}]");
    for f in list {
        let _ = writeln!(
            out,
            "{} = {}   # {}",
            f.name,
            vec3(&f.value),
            comment(&f.path)
        );
    }
}

/// The model file text. `source` names the ASMT file in the header comment.
///
/// In the order the file reads best: the header comments and `[model]`, the ground's
/// features, one table per body, joint, coupler, driver and limit, then `[analysis]`.
pub fn to_toml(import: &Import, source: &str) -> String {
    let mut o = String::new();
    header(&mut o, import, source);
    o.push('\n');
    ground(&mut o, import);
    for b in &import.bodies {
        body(&mut o, import, b);
    }
    for j in &import.joints {
        joint(&mut o, j);
    }
    for c in &import.couplers {
        coupler(&mut o, c);
    }
    for d in &import.drivers {
        driver(&mut o, d);
    }
    for l in &import.limits {
        limit(&mut o, l);
    }
    analysis(&mut o, import);
    o
}

/// The header comments (source, conventions, the importer's warnings) and `[model]`.
fn header(o: &mut String, import: &Import, source: &str) {
    let _ = writeln!(
        o,
        "# Imported from {} by `cardan import` (ASMT, OndselSolver / FreeCAD Assembly).",
        comment(source)
    );
    o.push_str(
        "# Body frames are the parts' centre-of-mass frames (ASMT principal mass markers); each\n\
         # marker M is point M with vectors M_x and M_z (its x and z axes) on its body.\n\
         # Comments give each element's ASMT path and line.\n",
    );
    for w in &import.warnings {
        let _ = writeln!(o, "# warning: {}", comment(&w.to_string()));
    }
    let _ = writeln!(
        o,
        "\n[model]\nname = {}   # assembly /{}",
        string(&import.name),
        comment(&import.asmt_name)
    );
    let _ = writeln!(o, "units = {}", string(import.units));
    if let Some(g) = import.gravity {
        let _ = writeln!(o, "gravity = {}", vec3(&g));
    }
}

/// The ground's points and vectors.
fn ground(o: &mut String, import: &Import) {
    let ground: Vec<&Feature> = import.points.iter().filter(|f| f.body == GROUND).collect();
    features(o, "ground.points", &ground);
    let ground: Vec<&Feature> = import.vectors.iter().filter(|f| f.body == GROUND).collect();
    features(o, "ground.vectors", &ground);
}

/// One `[[body]]`: mass, inertia, pose, and its points and vectors.
fn body(o: &mut String, import: &Import, b: &BodyMap) {
    let body = &b.body;
    let _ = writeln!(
        o,
        "\n[[body]]   # {} (line {})\nname = {}",
        comment(&b.path),
        b.line,
        string(&body.name)
    );
    if let Some(m) = body.mass {
        let _ = writeln!(o, "mass = {}", num(m));
    }
    if let Some(i) = body.inertia {
        let _ = writeln!(
            o,
            "inertia = {{ diag = [{}, {}, {}] }}",
            num(i[(0, 0)]),
            num(i[(1, 1)]),
            num(i[(2, 2)])
        );
    }
    let _ = writeln!(o, "position = {}", vec3(&body.position));
    if let cardan_mechanism::Orientation::EulerParams(e) = body.orientation {
        let _ = writeln!(
            o,
            "orientation = {{ euler_parameters = [{}, {}, {}, {}] }}",
            num(e[0]),
            num(e[1]),
            num(e[2]),
            num(e[3])
        );
    }
    let pts: Vec<&Feature> = import
        .points
        .iter()
        .filter(|f| f.body == body.name)
        .collect();
    features(o, "body.points", &pts);
    let vs: Vec<&Feature> = import
        .vectors
        .iter()
        .filter(|f| f.body == body.name)
        .collect();
    features(o, "body.vectors", &vs);
}

/// One `[[joint]]`: its kind, bodies, markers and numbers.
fn joint(o: &mut String, j: &Element<JointSpec>) {
    let s = &j.spec;
    let _ = writeln!(
        o,
        "\n[[joint]]   # {} (line {})\nname = {}\ntype = \"{}\"",
        comment(&j.path),
        j.line,
        string(&s.name),
        s.kind.name()
    );
    let _ = writeln!(
        o,
        "body_i = {}\npoint_i = {}",
        string(&s.body_i),
        string(&s.point_i)
    );
    for (k, v) in [("axis_i", &s.axis_i), ("x_axis_i", &s.x_axis_i)] {
        if let Some(v) = v {
            let _ = writeln!(o, "{k} = {}", string(v));
        }
    }
    let _ = writeln!(
        o,
        "body_j = {}\npoint_j = {}",
        string(&s.body_j),
        string(&s.point_j)
    );
    for (k, v) in [("axis_j", &s.axis_j), ("x_axis_j", &s.x_axis_j)] {
        if let Some(v) = v {
            let _ = writeln!(o, "{k} = {}", string(v));
        }
    }
    for (k, v) in [
        ("length", s.length),
        ("offset", s.offset),
        ("angle", s.angle),
    ] {
        if let Some(v) = v {
            let _ = writeln!(o, "{k} = {}", num(v));
        }
    }
}

/// One `[[coupler]]`: gear, rack and pinion or screw, and its constant.
fn coupler(o: &mut String, c: &Element<CouplerSpec>) {
    let s = &c.spec;
    let _ = writeln!(
        o,
        "\n[[coupler]]   # {} (line {}); constant from the input pose, as OndselSolver\nname = {}\ntype = \"{}\"",
        comment(&c.path),
        c.line,
        string(&s.name),
        s.kind_name()
    );
    match &s.kind {
        CouplerKind::Gear {
            joint_i,
            joint_j,
            ratio,
        } => {
            let _ = writeln!(
                o,
                "joint_i = {}\njoint_j = {}",
                string(joint_i),
                string(joint_j)
            );
            match ratio {
                GearRatio::Ratio(r) => {
                    let _ = writeln!(o, "ratio = {}", num(*r));
                }
                GearRatio::Radii(a, b) => {
                    let _ = writeln!(o, "radius_i = {}\nradius_j = {}", num(*a), num(*b));
                }
            }
        }
        CouplerKind::RackPinion {
            slide_joint,
            angle_joint,
            radius,
        } => {
            let _ = writeln!(
                o,
                "slide_joint = {}\nangle_joint = {}\nradius = {}",
                string(slide_joint),
                string(angle_joint),
                num(*radius)
            );
        }
        CouplerKind::Screw {
            slide_joint,
            angle_joint,
            pitch,
        } => {
            let _ = writeln!(
                o,
                "slide_joint = {}\nangle_joint = {}\npitch = {}",
                string(slide_joint),
                string(angle_joint),
                num(*pitch)
            );
        }
    }
    if let Some(k) = s.constant {
        let _ = writeln!(o, "constant = {}", num(k));
    }
}

/// One `[[driver]]`: a joint rotation or translation with its function, or a general motion
/// with its six functions.
fn driver(o: &mut String, d: &Element<DriverSpec>) {
    let s = &d.spec;
    let _ = writeln!(
        o,
        "\n[[driver]]   # {} (line {})\nname = {}",
        comment(&d.path),
        d.line,
        string(&s.name)
    );
    match &s.target {
        DriverTarget::JointRotation { joint } => {
            let _ = writeln!(o, "type = \"rotation\"\njoint = {}", string(joint));
        }
        DriverTarget::JointTranslation { joint } => {
            let _ = writeln!(o, "type = \"translation\"\njoint = {}", string(joint));
        }
        DriverTarget::Pose(p) => {
            let _ = writeln!(
                o,
                "type = \"general_motion\"\nbody_i = {}\npoint_i = {}\nbody_j = {}\npoint_j = {}\norder = \"{}\"",
                string(&p.body_i),
                string(&p.point_i),
                string(&p.body_j),
                string(&p.point_j),
                p.order.name()
            );
            for (k, v) in [
                ("axis_i", &p.axis_i),
                ("x_axis_i", &p.x_axis_i),
                ("axis_j", &p.axis_j),
                ("x_axis_j", &p.x_axis_j),
            ] {
                if let Some(v) = v {
                    let _ = writeln!(o, "{k} = {}", string(v));
                }
            }
            for (key, fs) in [
                ("translation", &p.functions[..3]),
                ("rotation", &p.functions[3..]),
            ] {
                let _ = writeln!(o, "{key} = [");
                for f in fs {
                    let _ = writeln!(o, "    {},", function(f));
                }
                o.push_str("]\n");
            }
            return;
        }
        // The importer makes no other drivers.
        _ => {}
    }
    let _ = writeln!(o, "function = {}", function(&s.function));
}

/// One `[[limit]]`: a bound on a joint's angle or slide (a rigid stop, e = 0).
fn limit(o: &mut String, l: &Element<LimitSpec>) {
    let s = &l.spec;
    let _ = writeln!(
        o,
        "\n[[limit]]   # {} (line {})\nname = {}\njoint = {}",
        comment(&l.path),
        l.line,
        string(&s.name),
        string(&s.joint)
    );
    if let Some(c) = &s.coordinate {
        let _ = writeln!(o, "coordinate = {}", string(c));
    }
    for (key, v) in [("lower", s.lower), ("upper", s.upper)] {
        if let Some(v) = v {
            let _ = writeln!(o, "{key} = {}", num(v));
        }
    }
}

/// `[analysis]` from SimulationParameters, when the file asks for output steps.
fn analysis(o: &mut String, import: &Import) {
    if let Some(st) = &import.settings {
        if st.steps() > 0 {
            let _ = writeln!(
                o,
                "\n[analysis]   # SimulationParameters: tstart, tend, hout\nkind = \"{}\"\nt_start = {}\nt_end = {}\nsteps = {}",
                import.analysis.name(),
                num(st.t_start),
                num(st.t_end),
                st.steps()
            );
            if import.analysis == crate::AnalysisKind::Dynamic {
                dynamic_settings(o, st);
            }
            if import.analysis == crate::AnalysisKind::Kinematic {
                o.push_str(
                    "free_dof = \"hold\"   # OndselSolver's least change for parts no motion drives\n",
                );
            }
        }
    }
}

/// The integrator settings of a dynamic analysis from SimulationParameters: DOPRI5 (cardan's
/// default integrator) with `h_max = hmax` and `rtol = errorTol` where cardan accepts them
/// (h_max > 0, rtol in [1e-14, 1e-2]); otherwise cardan's defaults. `hmin` has no counterpart
/// (DOPRI5 fails with a message when its step underflows).
fn dynamic_settings(o: &mut String, st: &Settings) {
    o.push_str("# the file's start pose at rest; DOPRI5 with the file's hmax and errorTol\n");
    if st.h_max.is_finite() && st.h_max > 0.0 {
        let _ = writeln!(o, "h_max = {}   # hmax", num(st.h_max));
    }
    if (1e-14..=1e-2).contains(&st.error_tol) {
        let _ = writeln!(o, "rtol = {}   # errorTol", num(st.error_tol));
    }
}
