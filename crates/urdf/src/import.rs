//! A checked [`Robot`] → cardan's elements: a body per rigid group of links
//! ([`crate::bodies`]), a joint per moving URDF joint, a limit per bounded joint, a gear coupler
//! per mimic joint; names made cardan names ([`crate::names`]) and kept beside the URDF names.
//!
//! | URDF joint | cardan element |
//! |---|---|
//! | `revolute` | `revolute` joint, its angle = q; `[[limit]]` lower/upper |
//! | `continuous` | `revolute` joint, no limit |
//! | `prismatic` | `prismatic` joint, its slide = q; `[[limit]]` lower/upper |
//! | `fixed` | none: the child link is part of the parent's body |
//! | `floating` | none: the child's body is free |
//! | `planar` | `planar` joint (axis = the plane normal) |
//! | `mimic` | `gear` coupler θ_j = multiplier · θ_i + offset (two revolute joints sharing a body); on a fixed joint ignored with a warning |
//!
//! Both sides of a joint get the joint frame J: the point `<joint>` and the vectors `<joint>_z`
//! (the axis) and `<joint>_x` (a perpendicular, the zero of the angle) — on the parent's body J
//! itself, on the child's body J moved by the drawn coordinate q₀ ([`crate::bodies`]) — so the
//! joint's cardan coordinate is the URDF's q, turning (sliding) positively about (along) the
//! URDF axis. Every link's origin is a point named after the link on its body.

use crate::bodies::{initial_q, layout, Base, Layout};
use crate::error::{listing, Result, UrdfError, Warning};
use crate::names::Namespace;
use crate::robot::{JointType, Robot};
use crate::tree::{tree, Tree};

/// How mimic joints are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MimicMode {
    /// As couplers (an error where cardan has no coupler for the pair).
    #[default]
    Couple,
    /// As independent joints (Pinocchio's default), with a warning.
    Free,
}

/// Import choices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// The root link fixed or floating.
    pub base: Base,
    /// Write the position limits as `[[limit]]` stops.
    pub limits: bool,
    /// Mimic joints as couplers or free.
    pub mimic: MimicMode,
    /// The `<dynamics damping>` of revolute, continuous and prismatic joints as dampers.
    pub damping: bool,
    /// The `<dynamics friction>` of revolute, continuous and prismatic joints as constant
    /// friction (`[[friction]] law = "constant"`).
    pub friction: bool,
    /// The links' collision shapes (when made) touch each other too, except between the two
    /// bodies of a joint.
    pub self_collision: bool,
    /// The analysis needs masses (dynamics): a massless moving body is an error naming its links.
    pub needs_masses: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            base: Base::Fixed,
            limits: true,
            mimic: MimicMode::Couple,
            damping: false,
            friction: false,
            self_collision: false,
            needs_masses: true,
        }
    }
}

/// The robot mapped to cardan's elements.
#[derive(Debug, Clone)]
pub struct Import {
    /// The robot as read.
    pub robot: Robot,
    /// Its tree.
    pub tree: Tree,
    /// Bodies and link poses at q = 0.
    pub layout: Layout,
    /// The cardan name of each body (per [`Layout::groups`]).
    pub body_names: Vec<String>,
    /// The cardan name of each URDF joint (fixed joints included: they name nothing).
    pub joint_names: Vec<String>,
    /// The point naming each link's origin on its body.
    pub link_points: Vec<String>,
    /// Per URDF joint, the point and vector names of its frame (the same on both bodies).
    pub joint_features: Vec<(String, String, String)>,
    /// Mimic joints that become couplers: (joint followed, joint following).
    pub couplers: Vec<(usize, usize)>,
    /// The choices it was made with.
    pub options: Options,
    /// What was read but not used.
    pub warnings: Vec<Warning>,
}

/// Reads, checks and maps a URDF text.
///
/// # Errors
/// The first problem, at its line.
pub fn import(text: &str, options: Options) -> Result<Import> {
    let robot = crate::read::read(text)?;
    let mut warnings = Vec::new();
    let tree = tree(&robot)?;
    if options.mimic == MimicMode::Couple {
        crate::tree::check_mimics(&robot)?;
    }
    let layout = layout(&robot, &tree, options.base, &initial_q(&robot));
    if layout.groups.is_empty() {
        return Err(UrdfError::new(
            robot.links[tree.root].line,
            format!(
                "robot \"{}\" has no moving joint, so with its root link fixed nothing moves; read it with --base floating (the root link's body moves freely)",
                robot.name
            ),
        ));
    }
    let mut bodies = Namespace::with_reserved(&["ground"]);
    let body_names = layout
        .groups
        .iter()
        .map(|g| bodies.claim(&robot.links[g.links[0]].name))
        .collect();
    let mut elements = Namespace::default();
    let joint_names: Vec<String> = robot
        .joints
        .iter()
        .map(|j| elements.claim(&j.name))
        .collect();
    // Point and vector names: one namespace per body, link origins first.
    let mut per_body: Vec<Namespace> = vec![Namespace::default(); layout.groups.len() + 1];
    let slot = |b: Option<usize>| b.map_or(0, |g| g + 1);
    let link_points = (0..robot.links.len())
        .map(|l| per_body[slot(layout.body_of[l])].claim(&robot.links[l].name))
        .collect();
    let mut joint_features = Vec::with_capacity(robot.joints.len());
    for (k, j) in robot.joints.iter().enumerate() {
        let (p, c) = tree.links[k];
        let sides = [slot(layout.body_of[p]), slot(layout.body_of[c])];
        if j.kind == JointType::Fixed || sides[0] == sides[1] {
            joint_features.push(Default::default());
            continue;
        }
        // One name free on both bodies for the point and its two vectors.
        let base = crate::names::sanitize(&joint_names[k]);
        let mut point = base.clone();
        let mut n = 2;
        let names = |p: &str| [p.to_string(), format!("{p}_z"), format!("{p}_x")];
        while sides
            .iter()
            .any(|&b| names(&point).iter().any(|x| per_body[b].taken(x)))
        {
            point = format!("{base}_{n}");
            n += 1;
        }
        for b in sides {
            for x in names(&point) {
                per_body[b].claim(&x);
            }
        }
        let [point, z, x] = names(&point);
        joint_features.push((point, z, x));
    }
    let mut import = Import {
        body_names,
        joint_names,
        link_points,
        joint_features,
        couplers: Vec::new(),
        options,
        warnings: Vec::new(),
        robot,
        tree,
        layout,
    };
    import.couplers = mimic_couplers(&import, &mut warnings)?;
    limit_warnings(&import, &mut warnings);
    dynamics_warning(&import, &mut warnings);
    if options.needs_masses {
        refuse_negative_inertia(&import.robot)?;
        refuse_massless(&import)?;
        refuse_non_rigid(&import)?;
    }
    import.warnings = warnings;
    Ok(import)
}

/// Whether joint `j`'s `<dynamics damping>` becomes a damper (`damping` chosen; a revolute,
/// continuous or prismatic joint between two bodies; a damping above 0): a
/// `rotational_spring_damper` or a `translational_spring_damper`.
pub fn damped(import: &Import, j: usize) -> bool {
    import.options.damping && modelled(import, j, |d| d.damping)
}

/// Whether joint `j`'s `<dynamics friction>` becomes a constant friction (`friction` chosen; a
/// revolute, continuous or prismatic joint between two bodies; a friction above 0).
pub fn frictional(import: &Import, j: usize) -> bool {
    import.options.friction && modelled(import, j, |d| d.friction)
}

/// Whether joint `j` has the `<dynamics>` value `value` above 0 and is a joint a damper or a
/// friction can act on: a revolute, continuous or prismatic joint (one coordinate) between two
/// bodies.
fn modelled(import: &Import, j: usize, value: impl Fn(&crate::robot::Dynamics) -> f64) -> bool {
    let joint = &import.robot.joints[j];
    matches!(
        joint.kind,
        JointType::Revolute | JointType::Continuous | JointType::Prismatic
    ) && !import.joint_features[j].0.is_empty()
        && joint.dynamics.is_some_and(|d| value(&d) > 0.0)
}

/// One warning for every joint whose `<dynamics>` is not modelled (a robot often has it on
/// every joint): damping unless `damping` is chosen, friction unless `friction` is (and a
/// planar joint's either way).
fn dynamics_warning(import: &Import, warnings: &mut Vec<Warning>) {
    let left: Vec<(usize, &crate::robot::Joint)> = (import.robot.joints.iter().enumerate())
        .filter(|(k, j)| {
            j.dynamics.is_some_and(|d| {
                (d.friction > 0.0 && !frictional(import, *k))
                    || (d.damping > 0.0 && !damped(import, *k))
            }) && !import.joint_features[*k].0.is_empty()
        })
        .collect();
    let Some((_, first)) = left.first() else {
        return;
    };
    let listed = listing(
        left.iter().map(|(_, j)| {
            let line = j.dynamics.map_or(j.line, |d| d.line);
            format!("\"{}\" (line {line})", j.name)
        }),
        left.len(),
        6,
    );
    let what = match (import.options.damping, import.options.friction) {
        (true, true) => "damping or friction on a planar joint, which is not modelled",
        (true, false) => {
            "friction (or a planar joint's damping), which is not modelled (--friction, or friction = true in an overlay's [urdf], makes it a constant friction)"
        }
        (false, true) => {
            "damping (or a planar joint's friction), which is not modelled (--damping, or damping = true in an overlay's [urdf], makes it a damper)"
        }
        (false, false) => {
            "damping or friction, which is not modelled (--damping and --friction, or damping = true and friction = true in an overlay's [urdf], make them dampers and constant friction)"
        }
    };
    warnings.push(Warning {
        line: first.dynamics.map_or(first.line, |d| d.line),
        message: format!(
            "{} with <dynamics> {what}: {listed}; add dampers or [[friction]] in an overlay",
            counted(left.len(), "joint"),
        ),
    });
}

/// "N joint(s)" (or another noun), for a warning that lists joints.
fn counted(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// The mimic joints that become gear couplers (two revolute joints whose bodies share one).
fn mimic_couplers(import: &Import, warnings: &mut Vec<Warning>) -> Result<Vec<(usize, usize)>> {
    let robot = &import.robot;
    let mut out = Vec::new();
    let mut fixed = Vec::new();
    for (k, j) in robot.joints.iter().enumerate() {
        let Some(m) = &j.mimic else { continue };
        if j.kind == JointType::Fixed {
            // No coordinate to couple (Talos's grippers carry such tags for a Gazebo plugin).
            fixed.push((j.name.as_str(), m.line));
            continue;
        }
        let t = robot
            .joints
            .iter()
            .position(|x| x.name == m.joint)
            .unwrap_or(k);
        if import.options.mimic == MimicMode::Free {
            warnings.push(Warning {
                line: m.line,
                message: format!(
                    "joint \"{}\" mimics joint \"{}\" and is read as a free joint (--mimic free)",
                    j.name, m.joint
                ),
            });
            continue;
        }
        let bodies = |x: usize| {
            let (p, c) = import.tree.links[x];
            [import.layout.body_of[p], import.layout.body_of[c]]
        };
        let share = bodies(k).iter().any(|b| bodies(t).contains(b));
        let turning = |x: usize| {
            matches!(
                robot.joints[x].kind,
                JointType::Revolute | JointType::Continuous
            )
        };
        if !(turning(k) && turning(t) && share) {
            return Err(UrdfError::new(
                m.line,
                format!(
                    "joint \"{}\" ({}) mimics joint \"{}\" ({}): cardan couples two revolute joints whose links share a body (a gear coupler); {} — read it with --mimic free (the joints independent, as Pinocchio's default) or relate them in an overlay",
                    j.name,
                    j.kind.name(),
                    t_name(robot, t),
                    robot.joints[t].kind.name(),
                    if share { "this pair does not turn both" } else { "these two share no body" }
                ),
            ));
        }
        out.push((t, k));
    }
    if let Some(&(_, line)) = fixed.first() {
        let names = listing(
            fixed.iter().map(|(n, _)| format!("\"{n}\"")),
            fixed.len(),
            6,
        );
        warnings.push(Warning {
            line,
            message: format!(
                "{} with <mimic> ({names}): a fixed joint has no coordinate to follow another joint's, so the tag is ignored and the links stay fixed",
                counted(fixed.len(), "fixed joint"),
            ),
        });
    }
    Ok(out)
}

fn t_name(robot: &Robot, t: usize) -> &str {
    &robot.joints[t].name
}

/// Position limits that are not stops: lower = upper (often a limit written for its effort and
/// velocity only).
fn limit_warnings(import: &Import, warnings: &mut Vec<Warning>) {
    for j in &import.robot.joints {
        if let (Some(l), JointType::Revolute | JointType::Prismatic) = (&j.limit, j.kind) {
            if l.lower == l.upper && import.options.limits {
                warnings.push(Warning {
                    line: l.line,
                    message: format!("joint \"{}\": <limit> has lower = upper = {}: read as no position limit (the joint would be locked)", j.name, l.lower),
                });
            }
        }
    }
}

/// A link's inertia about its centre of mass is symmetric positive semi-definite (a point mass
/// or a thin rod is a link's idealisation; the body its links form must be definite,
/// [`refuse_non_rigid`]); negative principal moments beyond round-off are refused.
fn refuse_negative_inertia(robot: &Robot) -> Result<()> {
    for l in &robot.links {
        let Some(i) = &l.inertial else { continue };
        let e = i.inertia.symmetric_eigenvalues();
        if e.min() < -1e-9 * e.amax().max(1e-9) {
            return Err(UrdfError::new(
                i.line,
                format!(
                    "link \"{}\": the inertia tensor has a negative principal moment ({:.4e}, {:.4e}, {:.4e} kg m²), which no body of mass {} kg has: correct the <inertia> (a kinematic analysis in an overlay does not need it)",
                    l.name, e[0], e[1], e[2], i.mass
                ),
            ));
        }
    }
    Ok(())
}

/// A moving body of zero mass cannot be in a dynamic analysis.
fn refuse_massless(import: &Import) -> Result<()> {
    let robot = &import.robot;
    for g in &import.layout.groups {
        if g.mass == 0.0 {
            let l = &robot.links[g.links[0]];
            let names: Vec<&str> = g
                .links
                .iter()
                .map(|&k| robot.links[k].name.as_str())
                .collect();
            return Err(UrdfError::new(
                l.line,
                format!(
                    "link \"{}\" moves and has no mass (links of its body: {}); a dynamic analysis needs a mass and inertia on every moving body: give it an <inertial>, fix it to a link with mass, or run the kinematics in an overlay",
                    l.name,
                    names.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// A moving body's inertia must be positive definite and its principal moments satisfy
/// I₁ + I₂ ≥ I₃ (cardan accepts 0.1 % slack), as the mechanism requires of every body.
fn refuse_non_rigid(import: &Import) -> Result<()> {
    for g in &import.layout.groups {
        if g.mass == 0.0 {
            continue;
        }
        let mut e: Vec<f64> = g.inertia.symmetric_eigenvalues().iter().copied().collect();
        e.sort_by(f64::total_cmp);
        let l = &import.robot.links[g.links[0]];
        let names: Vec<&str> = g
            .links
            .iter()
            .map(|&k| import.robot.links[k].name.as_str())
            .collect();
        let why = if e[0] <= 1e-12 * e[2] {
            "is not positive definite (a point mass or a thin rod): a dynamic analysis needs three positive principal moments; give the link a body's <inertia>"
        } else if e[0] + e[1] < (1.0 - 1e-3) * e[2] {
            "violates the triangle inequality (the two smaller principal moments must add up to the largest): no rigid body has it; correct the <inertia>"
        } else {
            continue;
        };
        return Err(UrdfError::new(
            l.line,
            format!(
                "link \"{}\": the inertia of its body (links {}) {why}: principal moments {:.6e}, {:.6e}, {:.6e} kg m²",
                l.name,
                names.join(", "),
                e[0],
                e[1],
                e[2]
            ),
        ));
    }
    Ok(())
}
