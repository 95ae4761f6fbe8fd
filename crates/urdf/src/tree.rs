//! The kinematic tree of a [`Robot`]: every joint's links exist, every link has at most one
//! parent, exactly one root, no cycle; every mimic joint follows another, non-mimic joint
//! ([`check_mimics`]).

use crate::error::{listing, Result, UrdfError};
use crate::robot::Robot;
use std::collections::HashMap;

/// The checked tree: link and joint indices.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tree {
    /// The root link.
    pub root: usize,
    /// Per link, the joint from its parent (None for the root).
    pub parent_joint: Vec<Option<usize>>,
    /// Links in breadth-first order from the root (parents before children).
    pub order: Vec<usize>,
    /// Per joint, its parent and child link.
    pub links: Vec<(usize, usize)>,
}

/// Checks the topology of `robot`.
///
/// # Errors
/// A duplicate name, a joint naming a missing link, a link with two parents, no root or
/// several, a cycle, a bad mimic joint: at the joint's or link's line.
pub fn tree(robot: &Robot) -> Result<Tree> {
    let mut link_index = HashMap::with_capacity(robot.links.len());
    for (k, l) in robot.links.iter().enumerate() {
        if let Some(&first) = link_index.get(l.name.as_str()) {
            let first: usize = first;
            return Err(UrdfError::new(
                l.line,
                format!(
                    "link \"{}\" is defined twice (first at line {}); link names must be unique",
                    l.name, robot.links[first].line
                ),
            ));
        }
        link_index.insert(l.name.as_str(), k);
    }
    let mut joint_index: HashMap<&str, usize> = HashMap::with_capacity(robot.joints.len());
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
    let mut links = Vec::with_capacity(robot.joints.len());
    for (k, j) in robot.joints.iter().enumerate() {
        if let Some(&first) = joint_index.get(j.name.as_str()) {
            return Err(UrdfError::new(
                j.line,
                format!(
                    "joint \"{}\" is defined twice (first at line {}); joint names must be unique",
                    j.name, robot.joints[first].line
                ),
            ));
        }
        joint_index.insert(j.name.as_str(), k);
        let find = |name: &str, role: &str| {
            link_index.get(name).copied().ok_or_else(|| {
                UrdfError::new(
                    j.line,
                    format!(
                        "joint \"{}\": its {role} link \"{name}\" is not a <link> of the robot",
                        j.name
                    ),
                )
            })
        };
        let (p, c) = (find(&j.parent, "parent")?, find(&j.child, "child")?);
        if p == c {
            return Err(UrdfError::new(
                j.line,
                format!("joint \"{}\" joins link \"{}\" to itself", j.name, j.parent),
            ));
        }
        if let Some(other) = parent_joint[c] {
            return Err(UrdfError::new(
                j.line,
                format!(
                    "link \"{}\" has two parents: joint \"{}\" (line {}) and joint \"{}\"; a URDF is a tree (close a loop with a joint in an overlay)",
                    j.child, robot.joints[other].name, robot.joints[other].line, j.name
                ),
            ));
        }
        parent_joint[c] = Some(k);
        children[p].push(c);
        links.push((p, c));
    }
    let roots: Vec<usize> = (0..robot.links.len())
        .filter(|&l| parent_joint[l].is_none())
        .collect();
    let root = match roots.as_slice() {
        [r] => *r,
        [] => {
            return Err(UrdfError::new(
                robot.joints.first().map_or(1, |j| j.line),
                "every link has a parent: the joints form a cycle, and a URDF is a tree with one root link".to_string(),
            ))
        }
        many => {
            let link = |&l: &usize| format!("\"{}\" (line {})", robot.links[l].name, robot.links[l].line);
            let names = listing(many.iter().map(link), many.len(), 5);
            return Err(UrdfError::new(
                robot.links[many[1]].line,
                format!(
                    "the robot has {} root links (links no joint has as its child): {names}; join them into one tree",
                    many.len(),
                ),
            ));
        }
    };
    let mut order = Vec::with_capacity(robot.links.len());
    order.push(root);
    let mut k = 0;
    while k < order.len() {
        order.extend(children[order[k]].iter().copied());
        k += 1;
    }
    if order.len() < robot.links.len() {
        let mut reached = vec![false; robot.links.len()];
        order.iter().for_each(|&l| reached[l] = true);
        let l = (0..robot.links.len()).find(|&l| !reached[l]).unwrap_or(0);
        let j = parent_joint[l].map_or(robot.links[l].line, |j| robot.joints[j].line);
        return Err(UrdfError::new(
            j,
            format!(
                "link \"{}\" is on a cycle of joints, not in the tree under the root link \"{}\"",
                robot.links[l].name, robot.links[root].name
            ),
        ));
    }
    Ok(Tree {
        root,
        parent_joint,
        order,
        links,
    })
}

/// Every mimic joint follows another joint of the robot that is not itself a mimic joint, and
/// both move with one coordinate.
///
/// # Errors
/// The first bad `<mimic>`, at its line.
pub fn check_mimics(robot: &Robot) -> Result<()> {
    let joint_index: HashMap<&str, usize> = robot
        .joints
        .iter()
        .enumerate()
        .map(|(k, j)| (j.name.as_str(), k))
        .collect();
    for j in robot
        .joints
        .iter()
        .filter(|j| j.kind != crate::robot::JointType::Fixed)
    {
        let Some(m) = &j.mimic else { continue };
        let Some(&target) = joint_index.get(m.joint.as_str()) else {
            return Err(UrdfError::new(
                m.line,
                format!(
                    "joint \"{}\" mimics joint \"{}\", which is not a <joint> of the robot",
                    j.name, m.joint
                ),
            ));
        };
        let t = &robot.joints[target];
        if t.name == j.name {
            return Err(UrdfError::new(
                m.line,
                format!("joint \"{}\" mimics itself", j.name),
            ));
        }
        if t.mimic.is_some() {
            return Err(UrdfError::new(
                m.line,
                format!("joint \"{}\" mimics joint \"{}\", which mimics another joint; make both follow the same free joint", j.name, t.name),
            ));
        }
        use crate::robot::JointType::{Continuous, Prismatic, Revolute};
        let one_dof = |k| matches!(k, Revolute | Continuous | Prismatic);
        if !one_dof(j.kind) || !one_dof(t.kind) {
            return Err(UrdfError::new(
                m.line,
                format!("joint \"{}\" ({}) mimics joint \"{}\" ({}); mimic joints relate revolute, continuous and prismatic joints", j.name, j.kind.name(), t.name, t.kind.name()),
            ));
        }
    }
    Ok(())
}
