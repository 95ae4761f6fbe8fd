//! Links → rigid bodies: links joined by `fixed` joints are one body (as Pinocchio merges them
//! into their parent's body), placed at the zero configuration (every joint coordinate 0).
//!
//! ## The drawn configuration
//! A joint's `<origin>` is the joint frame J in the parent link's frame, and the child link's
//! frame is J moved by the joint: T_child = T_parent · T_origin · M(q), M a rotation by q about
//! the axis (revolute, continuous) or a translation by q along it (prismatic), from the root link
//! at the identity (the world frame). The bodies are drawn at q₀: every joint at 0, or at its
//! nearest position limit when 0 is outside them ([`initial_q`]; many quadrupeds' knees).
//!
//! ## Mass properties of a body
//! A link's `<inertial>` gives its centre of mass c_k and its inertia I_k about it in the
//! inertial frame's axes R_k (link frame · inertial origin). A body of links k has
//!
//! ```text
//! m = Σ m_k,   c = Σ m_k c_k / m,   I_c = Σ R_k I_k R_kᵀ + m_k (|d_k|² E − d_k d_kᵀ),  d_k = c_k − c
//! ```
//!
//! (Steiner's theorem; global axes), and its body frame has its origin at c and the axes of its
//! first link (the one nearest the root), so a body's orientation is that link's orientation:
//! I_body = Aᵀ I_c A.

use crate::pose::Pose;
use crate::robot::{JointType, Robot};
use crate::tree::Tree;
use nalgebra::{Matrix3, Vector3};

/// How the root link is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Base {
    /// The root link is the ground (Pinocchio's default model).
    #[default]
    Fixed,
    /// The root link's body moves freely (a free-flyer root joint: a humanoid, a quadruped).
    Floating,
}

/// A rigid body of one or more links.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Its links, the first nearest the root.
    pub links: Vec<usize>,
    /// Total mass \[kg\].
    pub mass: f64,
    /// Centre of mass at q = 0, global (the first link's origin when massless).
    pub com: Vector3<f64>,
    /// Inertia about the centre of mass in global axes at q = 0.
    pub inertia: Matrix3<f64>,
}

impl Group {
    /// The body axes at q = 0: the first link's.
    pub fn axes(&self, layout: &Layout) -> Matrix3<f64> {
        layout.link_pose[self.links[0]].a
    }
}

/// Bodies and link poses at the drawn configuration q₀.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Every link's frame at q₀, global.
    pub link_pose: Vec<Pose>,
    /// Every joint's frame J (parent link · origin) at q₀, global.
    pub joint_frame: Vec<Pose>,
    /// Every joint's drawn coordinate q₀.
    pub q0: Vec<f64>,
    /// Every link's body: None for the ground.
    pub body_of: Vec<Option<usize>>,
    /// The moving bodies.
    pub groups: Vec<Group>,
    /// The ground's links (empty with a floating base).
    pub ground_links: Vec<usize>,
}

/// The drawn coordinate of each joint: 0, or the nearest bound of a revolute or prismatic
/// joint's limits (lower < upper) when 0 is outside them.
pub fn initial_q(robot: &Robot) -> Vec<f64> {
    robot
        .joints
        .iter()
        .map(|j| match (j.kind, j.limit) {
            (JointType::Revolute | JointType::Prismatic, Some(l)) if l.lower < l.upper => {
                0.0f64.clamp(l.lower, l.upper)
            }
            _ => 0.0,
        })
        .collect()
}

/// The joint's motion M(q) in the joint frame.
pub fn motion(kind: JointType, axis: &Vector3<f64>, q: f64) -> Pose {
    match kind {
        JointType::Revolute | JointType::Continuous => Pose {
            r: Vector3::zeros(),
            a: *nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(*axis), q)
                .matrix(),
        },
        JointType::Prismatic => Pose {
            r: axis * q,
            a: Matrix3::identity(),
        },
        _ => Pose::IDENTITY,
    }
}

/// Groups the links of `robot` into bodies, drawn at `q0` (per joint, [`initial_q`]).
pub fn layout(robot: &Robot, tree: &Tree, base: Base, q0: &[f64]) -> Layout {
    let n = robot.links.len();
    let mut link_pose = vec![Pose::IDENTITY; n];
    let mut joint_frame = vec![Pose::IDENTITY; robot.joints.len()];
    let mut body_of: Vec<Option<usize>> = vec![None; n];
    let mut groups: Vec<Group> = Vec::new();
    let mut ground_links = Vec::new();
    let new_group = |groups: &mut Vec<Group>, link: usize| {
        groups.push(Group {
            links: vec![link],
            mass: 0.0,
            com: Vector3::zeros(),
            inertia: Matrix3::zeros(),
        });
        Some(groups.len() - 1)
    };
    for &l in &tree.order {
        match tree.parent_joint[l] {
            None => match base {
                Base::Fixed => ground_links.push(l),
                Base::Floating => body_of[l] = new_group(&mut groups, l),
            },
            Some(j) => {
                let joint = &robot.joints[j];
                let p = tree.links[j].0;
                joint_frame[j] = link_pose[p].then(&joint.origin);
                link_pose[l] = joint_frame[j].then(&motion(joint.kind, &joint.axis, q0[j]));
                if joint.kind == JointType::Fixed {
                    body_of[l] = body_of[p];
                    match body_of[l] {
                        Some(g) => groups[g].links.push(l),
                        None => ground_links.push(l),
                    }
                } else {
                    body_of[l] = new_group(&mut groups, l);
                }
            }
        }
    }
    for g in &mut groups {
        mass_properties(robot, &link_pose, g);
    }
    Layout {
        link_pose,
        joint_frame,
        q0: q0.to_vec(),
        body_of,
        groups,
        ground_links,
    }
}

/// m, c, I_c of a group (module docs).
fn mass_properties(robot: &Robot, link_pose: &[Pose], g: &mut Group) {
    let parts: Vec<(f64, Vector3<f64>, Matrix3<f64>)> = g
        .links
        .iter()
        .filter_map(|&l| {
            let i = robot.links[l].inertial.as_ref()?;
            let frame = link_pose[l].then(&i.origin);
            Some((i.mass, frame.r, frame.a * i.inertia * frame.a.transpose()))
        })
        .filter(|(m, _, _)| *m > 0.0)
        .collect();
    g.mass = parts.iter().map(|p| p.0).sum();
    if g.mass == 0.0 {
        g.com = link_pose[g.links[0]].r;
        return;
    }
    g.com = parts.iter().map(|(m, c, _)| *m * c).sum::<Vector3<f64>>() / g.mass;
    g.inertia = parts
        .iter()
        .map(|(m, c, i)| {
            let d = c - g.com;
            i + *m * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
        })
        .sum();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::read::read;
    use crate::tree::tree;

    /// A joint's origin comes first, its motion after it: the child link's frame is
    /// T_parent · T_origin · M(q), so a link 1 m along the origin's rotated x, then turned by q
    /// about the joint's z, has its own x axis turned by the origin's yaw plus q.
    #[test]
    fn the_joint_origin_comes_before_the_joint_motion() {
        let text = r#"<robot name="r"><link name="world"/><link name="a"/>
          <joint name="j" type="revolute"><parent link="world"/><child link="a"/>
          <origin xyz="1 0 0" rpy="0 0 0.5"/><axis xyz="0 0 1"/><limit lower="0.25" upper="1"/></joint>
        </robot>"#;
        let robot = read(text).unwrap();
        let t = tree(&robot).unwrap();
        // 0 is outside [0.25, 1]: drawn at the lower limit.
        let q0 = initial_q(&robot);
        assert_eq!(q0, vec![0.25]);
        let lay = layout(&robot, &t, Base::Fixed, &q0);
        let a = lay.link_pose[1];
        assert!((a.r - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
        let x = a.a * Vector3::x();
        let angle = x.y.atan2(x.x);
        assert!((angle - 0.75).abs() < 1e-15, "{angle}");
        let xj = lay.joint_frame[0].a * Vector3::x();
        assert!((xj.y.atan2(xj.x) - 0.5).abs() < 1e-15);
    }

    /// Two unit point-like cubes merged through a fixed joint: the parallel-axis theorem.
    #[test]
    fn a_fixed_child_merges_into_its_parent_by_steiner() {
        let text = r#"<robot name="r">
          <link name="world"/>
          <link name="a"><inertial><mass value="2"/><inertia ixx="1" iyy="2" izz="3"/></inertial></link>
          <link name="b"><inertial><origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/><mass value="2"/><inertia ixx="1" iyy="2" izz="3"/></inertial></link>
          <joint name="j" type="revolute"><parent link="world"/><child link="a"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>
          <joint name="f" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0 2 0"/></joint>
        </robot>"#;
        let robot = read(text).unwrap();
        let t = tree(&robot).unwrap();
        let lay = layout(&robot, &t, Base::Fixed, &initial_q(&robot));
        assert_eq!(lay.groups.len(), 1);
        let g = &lay.groups[0];
        assert_eq!(g.mass, 4.0);
        // b's centre at (1, 2, 0.5), a's at (1, 0, 0): c = (1, 1, 0.25).
        assert!((g.com - Vector3::new(1.0, 1.0, 0.25)).norm() < 1e-15);
        // b's inertia turned by 90° about z: diag(2, 1, 3); d = ±(0, 1, 0.25).
        let d2 = 1.0 + 0.0625;
        let expect_xx = 1.0 + 2.0 + 2.0 * 2.0 * d2;
        let expect_yy = 2.0 + 1.0 + 2.0 * 2.0 * 0.0625;
        let expect_zz = 3.0 + 3.0 + 2.0 * 2.0 * 1.0;
        let expect_yz = -2.0 * 2.0 * 0.25;
        assert!((g.inertia[(0, 0)] - expect_xx).abs() < 1e-14);
        assert!((g.inertia[(1, 1)] - expect_yy).abs() < 1e-14);
        assert!((g.inertia[(2, 2)] - expect_zz).abs() < 1e-14);
        assert!((g.inertia[(1, 2)] - expect_yz).abs() < 1e-14);
        assert_eq!(lay.ground_links, vec![0]);
        // The child link's frame: the joint origin.
        assert!((lay.link_pose[2].r - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-15);
    }
}
