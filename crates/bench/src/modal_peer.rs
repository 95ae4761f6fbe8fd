//! The eigenfrequencies of one 3D model against Exudyn's `ComputeODE2Eigenvalues` (issue 26):
//! `cardan-bench --modal --peers PYTHON` (the Python with exudyn and scipy, e.g. the venv of
//! `cargo xtask bench --peers`).
//!
//! The model: three rigid links hanging from the ground, each joined to the one above by a
//! revolute joint on a skew axis (no two axes parallel, none along gravity), every inertia
//! tensor full (products of inertia in the drawn frame), and two linear springs at their free
//! length, one from the ground to the middle link and one from the top link to the bottom one,
//! their attachment points off the links' line. The joints and the centres of mass lie on one
//! vertical line, so the drawn pose is a static equilibrium (gravity has no moment about any
//! joint, the springs carry no force); both sides check that. Three degrees of freedom, coupled:
//! no closed form.
//!
//! The numbers live here once ([`LINKS`], [`SPRINGS`], [`GRAVITY`]): [`model`] builds cardan's
//! mechanism from them, [`peer_input`] writes them as the text `bench/peers/modal_exudyn.py`
//! reads. cardan: [`Dynamics::modal`] (static equilibrium, linearization with the geometric
//! stiffness of the constraint forces, null space of Φ_v, all modes). Exudyn: the same links as
//! an `ObjectKinematicTree` (minimal coordinates), `SolveStatic`, `ComputeODE2Eigenvalues`; see
//! the script for why not rigid bodies with joints (its constrained eigenvalues leave out the
//! constraint forces' geometric stiffness).
//!
//! The section fails (non-zero exit) when a frequency differs by more than [`TOLERANCE`]
//! relative, or when Exudyn places a centre of mass elsewhere than cardan (the frames differ).

use cardan_dynamics::{Dynamics, Force, ModalOptions, ModeKind};
use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::{Matrix3, Vector3};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Largest relative difference of a frequency allowed (the peer criterion).
pub const TOLERANCE: f64 = 1e-6;

/// Gravity (m/s²).
pub const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// A link: a rigid body joined to `parent` (`GROUND` or an earlier link) by a revolute joint
/// at `joint` about `axis`; all global at the drawn pose, the body frame parallel to the
/// global one.
#[derive(Debug, Clone, Copy)]
pub struct Link {
    /// Name.
    pub name: &'static str,
    /// The body above.
    pub parent: &'static str,
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass (m).
    pub com: [f64; 3],
    /// Inertia about the centre of mass (kg m²): Jxx, Jyy, Jzz, Jxy, Jxz, Jyz (tensor entries).
    pub inertia: [f64; 6],
    /// The joint's point (m).
    pub joint: [f64; 3],
    /// The joint's axis (any length).
    pub axis: [f64; 3],
}

/// A linear spring between a point of `body_i` and one of `body_j` (global, m) at its free
/// length, stiffness `k` (N/m).
#[derive(Debug, Clone, Copy)]
pub struct Spring {
    /// Body i.
    pub body_i: &'static str,
    /// Body j.
    pub body_j: &'static str,
    /// End on i.
    pub a: [f64; 3],
    /// End on j.
    pub b: [f64; 3],
    /// Stiffness (N/m).
    pub k: f64,
}

/// The three links.
pub const LINKS: [Link; 3] = [
    Link {
        name: "l1",
        parent: GROUND,
        mass: 2.0,
        com: [0.0, 0.0, -0.5],
        inertia: [0.09, 0.07, 0.06, 0.01, -0.015, 0.02],
        joint: [0.0, 0.0, 0.0],
        axis: [1.0, 0.3, 0.2],
    },
    Link {
        name: "l2",
        parent: "l1",
        mass: 1.5,
        com: [0.0, 0.0, -1.45],
        inertia: [0.06, 0.08, 0.05, -0.012, 0.008, 0.011],
        joint: [0.0, 0.0, -1.0],
        axis: [0.2, 1.0, -0.4],
    },
    Link {
        name: "l3",
        parent: "l2",
        mass: 1.0,
        com: [0.0, 0.0, -2.2],
        inertia: [0.03, 0.02, 0.025, 0.004, -0.006, 0.003],
        joint: [0.0, 0.0, -1.9],
        axis: [0.6, -0.5, 0.3],
    },
];

/// The two springs.
pub const SPRINGS: [Spring; 2] = [
    Spring {
        body_i: GROUND,
        body_j: "l2",
        a: [0.5, 0.6, -1.2],
        b: [0.1, 0.05, -1.4],
        k: 80.0,
    },
    Spring {
        body_i: "l1",
        body_j: "l3",
        a: [0.15, -0.1, -0.7],
        b: [-0.1, 0.12, -2.3],
        k: 40.0,
    },
];

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

/// The inertia tensor of a link.
fn tensor(j: [f64; 6]) -> Matrix3<f64> {
    let [xx, yy, zz, xy, xz, yz] = j;
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

/// The centre of mass of `body` (the origin for the ground).
fn origin(body: &str) -> Vector3<f64> {
    LINKS
        .iter()
        .find(|l| l.name == body)
        .map_or(Vector3::zeros(), |l| v(l.com))
}

/// cardan's mechanism (the springs are forces: see [`dynamics`]).
///
/// # Panics
/// If the builder rejects it (it does not).
pub fn model() -> Model {
    let mut b = MechanismBuilder::new();
    for l in &LINKS {
        b.body(
            Body::new(l.name)
                .mass(l.mass)
                .inertia(tensor(l.inertia))
                .position(v(l.com)),
        );
    }
    for (k, l) in LINKS.iter().enumerate() {
        let (p, a) = (v(l.joint), v(l.axis).normalize());
        for body in [l.parent, l.name] {
            b.point(body, &format!("j{k}"), p - origin(body))
                .vector(body, &format!("a{k}"), a);
        }
        b.joint(
            JointSpec::new(
                format!("pin{k}"),
                JointKind::Revolute,
                (l.parent, &format!("j{k}")),
                (l.name, &format!("j{k}")),
            )
            .axes(&format!("a{k}"), &format!("a{k}")),
        );
    }
    for (k, s) in SPRINGS.iter().enumerate() {
        b.point(s.body_i, &format!("s{k}a"), v(s.a) - origin(s.body_i))
            .point(s.body_j, &format!("s{k}b"), v(s.b) - origin(s.body_j));
    }
    b.build().expect("a valid mechanism")
}

/// cardan's dynamics of `model`: gravity and the springs (free length: the drawn distance).
///
/// # Panics
/// If a force does not resolve (they do).
pub fn dynamics(model: &Model) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).expect("dynamics");
    d.add_force(Force::gravity(v(GRAVITY))).expect("gravity");
    for (k, s) in SPRINGS.iter().enumerate() {
        let (a, b) = (format!("s{k}a"), format!("s{k}b"));
        d.add_force(Force::spring_damper(
            &format!("spring{k}"),
            (s.body_i, a.as_str()),
            (s.body_j, b.as_str()),
            s.k,
            0.0,
            None,
        ))
        .expect("spring");
    }
    d
}

/// cardan's elastic frequencies (Hz, ascending) and the Newton iterations of its equilibrium.
///
/// # Panics
/// If the modal analysis fails.
pub fn cardan_frequencies() -> (Vec<f64>, usize) {
    let model = model();
    let mut d = dynamics(&model);
    let r = d.modal(&ModalOptions::default()).expect("modal analysis");
    let f = r
        .modes
        .iter()
        .filter(|m| m.kind == ModeKind::Elastic)
        .map(|m| m.frequency)
        .collect();
    (f, r.equilibrium.equilibria[0].iterations)
}

/// The model as the lines `bench/peers/modal_exudyn.py` reads (its docs).
pub fn peer_input() -> String {
    let mut s = String::new();
    let [gx, gy, gz] = GRAVITY;
    let _ = writeln!(s, "gravity {gx:e} {gy:e} {gz:e}");
    let f = |a: &[f64]| a.iter().map(|x| format!("{x:e}")).collect::<Vec<_>>();
    for l in &LINKS {
        let mut w = vec![format!("{:e}", l.mass)];
        w.extend(f(&l.com));
        w.extend(f(&l.inertia));
        w.extend(f(&l.joint));
        w.extend(f(&l.axis));
        let _ = writeln!(s, "link {} {} {}", l.name, l.parent, w.join(" "));
    }
    for sp in &SPRINGS {
        let mut w = f(&sp.a);
        w.extend(f(&sp.b));
        w.push(format!("{:e}", sp.k));
        let _ = writeln!(s, "spring {} {} {}", sp.body_i, sp.body_j, w.join(" "));
    }
    s
}

/// What Exudyn reported.
#[derive(Debug, Clone, Default)]
pub struct PeerResult {
    /// Exudyn's version.
    pub version: String,
    /// Largest joint angle of its static solve from the drawn pose (rad): 0 at an equilibrium.
    pub equilibrium_shift: f64,
    /// Each link's centre of mass as Exudyn places it.
    pub coms: Vec<(String, Vector3<f64>)>,
    /// Eigenfrequencies (Hz, ascending; negative: √|ω²| of a negative ω²).
    pub frequencies: Vec<f64>,
}

/// Runs `script` (`bench/peers/modal_exudyn.py`) in `python` on [`peer_input`].
///
/// # Errors
/// When Python does not start or the script reports no frequencies (its stderr's last lines).
pub fn exudyn(python: &str, script: &Path) -> Result<PeerResult, String> {
    use std::io::Write as _;
    let mut child = Command::new(python)
        .arg(script)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {python}: {e}"))?;
    child
        .stdin
        .take()
        .expect("piped")
        .write_all(peer_input().as_bytes())
        .map_err(|e| format!("writing to {python}: {e}"))?;
    let o = child
        .wait_with_output()
        .map_err(|e| format!("{python}: {e}"))?;
    let out = String::from_utf8_lossy(&o.stdout);
    let mut r = PeerResult::default();
    for line in out.lines().filter_map(|l| l.strip_prefix("RESULT ")) {
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        match key {
            "version" => r.version = value.to_string(),
            "equilibrium_shift" => r.equilibrium_shift = value.parse().unwrap_or(f64::NAN),
            "f" => r.frequencies.push(value.parse().unwrap_or(f64::NAN)),
            "com" => {
                let w: Vec<&str> = value.split_whitespace().collect();
                let x: Vec<f64> = w[1..]
                    .iter()
                    .map(|s| s.parse().unwrap_or(f64::NAN))
                    .collect();
                if x.len() == 3 {
                    r.coms
                        .push((w[0].to_string(), Vector3::new(x[0], x[1], x[2])));
                }
            }
            _ => {}
        }
    }
    if r.frequencies.is_empty() {
        let err = String::from_utf8_lossy(&o.stderr);
        let last: Vec<&str> = err.lines().rev().take(3).collect();
        return Err(format!(
            "{}: no frequencies ({})",
            script.display(),
            last.into_iter().rev().collect::<Vec<_>>().join(" / ")
        ));
    }
    Ok(r)
}

/// The largest relative difference of two frequency lists, mode by mode (infinite when their
/// lengths differ).
pub fn worst_difference(ours: &[f64], theirs: &[f64]) -> f64 {
    if ours.len() != theirs.len() {
        return f64::INFINITY;
    }
    ours.iter()
        .zip(theirs)
        .map(|(a, b)| (a - b).abs() / b.abs())
        .fold(0.0f64, f64::max)
}

/// The markdown section and whether the check passed (every frequency within [`TOLERANCE`],
/// the same equilibrium and frames).
pub fn section(python: &str, root: &Path) -> (String, bool) {
    let mut md = String::from(
        "### Modal analysis against Exudyn\n\nThree links on revolutes with skew axes, full \
         inertia tensors, two springs, hanging at a static equilibrium \
         (`crates/bench/src/modal_peer.rs`); cardan's `Dynamics::modal` against Exudyn's \
         `ComputeODE2Eigenvalues` on the same links as a kinematic tree \
         (`bench/peers/modal_exudyn.py`).\n\n",
    );
    let (ours, iterations) = cardan_frequencies();
    let theirs = match exudyn(python, &root.join("bench/peers/modal_exudyn.py")) {
        Ok(r) => r,
        Err(e) => {
            let _ = writeln!(md, "Exudyn did not run: {e}\n");
            return (md, false);
        }
    };
    let frames = LINKS
        .iter()
        .map(|l| {
            theirs
                .coms
                .iter()
                .find(|(n, _)| n == l.name)
                .map_or(f64::INFINITY, |(_, x)| (x - v(l.com)).norm())
        })
        .fold(0.0f64, f64::max);
    let _ = writeln!(
        md,
        "| mode | cardan (Hz) | Exudyn {} (Hz) | relative difference |\n|---|---|---|---|",
        theirs.version
    );
    let worst = worst_difference(&ours, &theirs.frequencies);
    let n = ours.len().max(theirs.frequencies.len());
    for i in 0..n {
        let (a, b) = (ours.get(i), theirs.frequencies.get(i));
        let rel = match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() / b.abs(),
            _ => f64::INFINITY,
        };
        let show = |x: Option<&f64>| x.map_or("–".to_string(), |x| format!("{x:.12}"));
        let _ = writeln!(md, "| {} | {} | {} | {rel:.1e} |", i + 1, show(a), show(b));
    }
    let ok = worst <= TOLERANCE && frames <= 1e-12 && theirs.equilibrium_shift <= 1e-12;
    let _ = writeln!(
        md,
        "\nWorst relative difference {worst:.1e} (criterion {TOLERANCE:.0e}): {}. Equilibrium: \
         cardan's static solve took {iterations} Newton iteration(s) from the drawn pose, \
         Exudyn's moved it by {:.1e} rad; centres of mass as Exudyn places them within \
         {frames:.1e} m of cardan's.\n",
        if ok { "pass" } else { "FAIL" },
        theirs.equilibrium_shift
    );
    (md, ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_drawn_pose_is_an_equilibrium_with_three_elastic_modes() {
        let (f, iterations) = cardan_frequencies();
        assert_eq!(f.len(), 3, "{f:?}");
        assert!(iterations <= 1, "{iterations} Newton iterations");
        assert!(f.iter().all(|x| *x > 0.1 && *x < 10.0), "{f:?}");
    }

    #[test]
    fn a_difference_above_the_tolerance_or_a_missing_mode_fails() {
        let f = [0.4395, 0.6603, 1.4013];
        assert_eq!(worst_difference(&f, &f), 0.0);
        let off = [0.4395 * (1.0 + 7e-6), 0.6603, 1.4013];
        assert!(worst_difference(&f, &off) > TOLERANCE);
        assert!(worst_difference(&f, &f[..2]).is_infinite());
    }

    #[test]
    fn the_peer_input_lists_every_link_and_spring() {
        let s = peer_input();
        assert_eq!(s.lines().filter(|l| l.starts_with("link ")).count(), 3);
        assert_eq!(s.lines().filter(|l| l.starts_with("spring ")).count(), 2);
        assert!(s.starts_with("gravity 0e0 0e0 -9.81e0\n"));
    }
}
