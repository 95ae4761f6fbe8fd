//! The kinematic predictor's spanning tree of the joints: each moving body's parent and the
//! joint points that link them, breadth-first from the ground (so each body is as few joints
//! from the ground as the mechanism allows), with an order that lists every parent before its
//! children. Built once with the model; the predictor (`analysis/predictor.rs`, which explains
//! why a body is predicted relative to its parent) walks it every frame.

use super::elements::{BodyId, JointInfo};
use nalgebra::Vector3;
use std::collections::VecDeque;

/// A body's parent in the spanning tree and the joint points that link them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TreeEdge {
    /// The parent body (`None`: the ground).
    pub parent: Option<usize>,
    /// s'_P: the joint's point on the parent (body coordinates; global for the ground).
    pub s_parent: Vector3<f64>,
    /// s'_C: the joint's point on the child (body coordinates).
    pub s_child: Vector3<f64>,
}

/// The spanning tree of the predictor: one edge per moving body, and an order with every
/// parent before its children.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PredictorTree {
    pub edges: Vec<TreeEdge>,
    pub order: Vec<usize>,
}

impl PredictorTree {
    /// Breadth-first from the ground over the joints (drivers add no edges); bodies that no
    /// joint path reaches from the ground start their own trees, rooted at the ground with the
    /// body origin as the point (the absolute prediction).
    pub(crate) fn new(num_bodies: usize, joints: &[JointInfo]) -> Self {
        let node = |b: BodyId| match b {
            BodyId::Ground => num_bodies,
            BodyId::Moving(k) => k,
        };
        // Adjacency: for each node, (joint, side of the node: true for body i).
        let mut adjacent: Vec<Vec<(usize, bool)>> = vec![Vec::new(); num_bodies + 1];
        for (k, j) in joints.iter().enumerate() {
            let (a, b) = (node(j.body_i), node(j.body_j));
            if a != b {
                adjacent[a].push((k, true));
                adjacent[b].push((k, false));
            }
        }
        let root = TreeEdge {
            parent: None,
            s_parent: Vector3::zeros(),
            s_child: Vector3::zeros(),
        };
        let mut edges: Vec<Option<TreeEdge>> = vec![None; num_bodies];
        let mut order = Vec::with_capacity(num_bodies);
        let mut queue = VecDeque::new();
        let mut visit =
            |start: usize, edges: &mut Vec<Option<TreeEdge>>, order: &mut Vec<usize>| {
                queue.push_back(start);
                while let Some(u) = queue.pop_front() {
                    for &(k, u_is_i) in &adjacent[u] {
                        let j = &joints[k];
                        let (mu, mw, w) = if u_is_i {
                            (j.joint.marker_i(), j.joint.marker_j(), node(j.body_j))
                        } else {
                            (j.joint.marker_j(), j.joint.marker_i(), node(j.body_i))
                        };
                        if w == num_bodies || edges[w].is_some() {
                            continue;
                        }
                        edges[w] = Some(TreeEdge {
                            parent: (u != num_bodies).then_some(u),
                            s_parent: mu.point,
                            s_child: mw.point,
                        });
                        order.push(w);
                        queue.push_back(w);
                    }
                }
            };
        visit(num_bodies, &mut edges, &mut order);
        for b in 0..num_bodies {
            if edges[b].is_none() {
                edges[b] = Some(root.clone());
                order.push(b);
                visit(b, &mut edges, &mut order);
            }
        }
        Self {
            edges: edges
                .into_iter()
                .map(|e| e.expect("every body visited"))
                .collect(),
            order,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{Body, JointKind, JointSpec, MechanismBuilder, GROUND};
    use nalgebra::Vector3;

    /// Breadth-first from the ground, parents before children, the joint points taken from
    /// the side of each body (whichever of body i and j it is), and a body no joint reaches
    /// rooted at the ground with its origin.
    #[test]
    fn the_tree_runs_breadth_first_from_the_ground() {
        let mut b = MechanismBuilder::new();
        b.point(GROUND, "O", Vector3::new(0.0, 0.0, 1.0));
        for (k, name) in ["b0", "b1", "b2", "lone"].iter().enumerate() {
            b.body(Body::new(*name).position(Vector3::new(k as f64, 0.0, 0.0)));
            b.point(name, "a", Vector3::new(-0.5, 0.0, 0.0)).point(
                name,
                "b",
                Vector3::new(0.5, 0.0, 0.0),
            );
        }
        // Listed out of tree order, b2 as body i of its joint with b1.
        b.joint(JointSpec::new(
            "s2",
            JointKind::Spherical,
            ("b2", "a"),
            ("b1", "b"),
        ));
        b.joint(JointSpec::new(
            "s1",
            JointKind::Spherical,
            ("b0", "b"),
            ("b1", "a"),
        ));
        b.joint(JointSpec::new(
            "s0",
            JointKind::Spherical,
            (GROUND, "O"),
            ("b0", "a"),
        ));
        let model = b.build().unwrap();
        let tree = &model.tree;
        let id = |n: &str| match model.body_id(n) {
            Some(crate::BodyId::Moving(k)) => k,
            other => panic!("{n}: {other:?}"),
        };
        assert_eq!(tree.order, vec![id("b0"), id("b1"), id("b2"), id("lone")]);
        let e = |n: &str| &tree.edges[id(n)];
        assert_eq!(e("b0").parent, None);
        assert_eq!(e("b0").s_parent, Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(e("b1").parent, Some(id("b0")));
        assert_eq!(e("b1").s_parent, Vector3::new(0.5, 0.0, 0.0));
        assert_eq!(e("b1").s_child, Vector3::new(-0.5, 0.0, 0.0));
        assert_eq!(e("b2").parent, Some(id("b1")));
        assert_eq!(e("b2").s_parent, Vector3::new(0.5, 0.0, 0.0));
        assert_eq!(e("b2").s_child, Vector3::new(-0.5, 0.0, 0.0));
        assert_eq!(e("lone").parent, None);
        assert_eq!(e("lone").s_child, Vector3::zeros());
    }
}
