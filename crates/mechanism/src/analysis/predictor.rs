//! The kinematic predictor: the Newton start of the next frame, predicted body by body relative
//! to a parent along a spanning tree of the joints.
//!
//! # Why relative
//! A Taylor step of each body's absolute pose, x ⊕ (v dt + ½ v̇ dt² + ⅙ j dt³), is fourth-order
//! accurate, but its error constant is the body's absolute motion. Far down an open chain that
//! motion composes every joint before it: in a chain of N links whose joints all turn at 0.1 rad/s,
//! the last link turns at up to 0.07·N rad/s although each joint turns slowly and uniformly. The
//! absolute prediction of such a link misses by scaled steps of 3 to 7 at 10,000 links, and the
//! position Newton needs 5 to 7 iterations and two factorizations per frame instead of one or
//! none.
//!
//! Predicting instead the motion of each body relative to its parent in a spanning tree
//! (breadth-first from the ground, so each body is as few joints from the ground as the
//! mechanism allows) and composing the predicted relative poses from the ground outwards keeps
//! the error constant at the relative motion, which a joint keeps slow and smooth: a revolute
//! joint turning at a constant rate is predicted exactly, whatever the chain's length.
//!
//! # The relative motion of a tree edge
//! Parent P (a moving body), child C, the joint's points s'_P on P and s'_C on C (body
//! coordinates). With A_rel = A_Pᵀ A_C (p_rel = p_P* ⊗ p_C) and
//! the offset of the child's joint point from the parent's, in the parent's frame,
//!
//! - Δ = r_C + A_C s'_C − r_P − A_P s'_P, e = A_Pᵀ Δ (zero for a spherical or revolute joint),
//! - ė = A_Pᵀ Δ̇ − ω'_P × e,
//! - ë = A_Pᵀ Δ̈ − ω̇'_P × e − 2 ω'_P × ė − ω'_P × (ω'_P × e),
//! - ω'_rel = ω'_C − A_relᵀ ω'_P (so that Ȧ_rel = A_rel ω̃'_rel),
//! - ω̇'_rel = ω̇'_C − A_relᵀ ω̇'_P + ω'_rel × (A_relᵀ ω'_P),
//!
//! with Δ̇ = ṙ_C + A_C (ω'_C × s'_C) − (the same for P) and
//! Δ̈ = r̈_C + A_C (ω̇'_C × s'_C + ω'_C × (ω'_C × s'_C)) − (the same for P), the velocity and
//! acceleration of the points r^P = r + A s'^P (`shared/notation.md`) with Ȧ = A ω̃'. The
//! prediction at t + dt:
//!
//! - e ← e + ė dt + ½ ë dt² + ⅙ j_e dt³,
//! - p_rel ← p_rel ⊗ exp(½ θ'), θ' = ω'_rel dt + ½ ω̇'_rel dt² + ⅙ j_ω dt³ + (dt³/12) ω'_rel × ω̇'_rel
//!   (the second Magnus term),
//!
//! with the jerks j from the relative accelerations [ë; ω̇'_rel] of the last two acceleration
//! analyses (stored by [`Model::acceleration`](crate::Model::acceleration)). Then, parents
//! first: p_C = p_P ⊗ p_rel, r_C = r_P + A_P (s'_P + e) − A_C s'_C.
//!
//! # Where the absolute step stays
//! The relative motion is not always the slower one: a slider-crank's connecting rod rocks
//! gently while its parent, the crank, spins, so relative to the crank it turns at about the
//! crank's rate. Each frame, a body is therefore predicted relative to its parent only when
//! |ω'_rel| ≤ |ω'_C|, and by its absolute Taylor step otherwise; bodies under the ground (and
//! bodies that no joint path reaches) always take the absolute step, as before. The
//! slider-crank then needs the same Newton iterations as with the absolute step (1,210 in 400
//! frames); taking every body relative cost it 10 % more. Cut joints
//! (those that close loops) are left to Newton, as all joints were before.
//!
//! Measured (`cardan-bench --point kin chain N`, 2-core VM): the driven revolute chain of the
//! scaling benchmark goes from 4.0 / 5.35 Newton iterations and 2 factorizations per frame to
//! 0.15 / 0.8 and 1 at 1,000 / 10,000 links, its frame from 4.5 / 77 ms to 2.4 / 34 ms.

use crate::model::{BodyId, JointInfo, Model};
use crate::workspace::Workspace;
use cardan_constraints::BodyState;
use cardan_eulerparam::EulerParams;
use nalgebra::{Matrix3, Vector3};
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

/// Pose, velocity and acceleration of moving body `b`: the pose from its body state (kept in
/// step with the Newton state by every analysis), the rest from the workspace vectors.
struct Frame {
    r: Vector3<f64>,
    p: EulerParams,
    a: Matrix3<f64>,
    rd: Vector3<f64>,
    w: Vector3<f64>,
    rdd: Vector3<f64>,
    wd: Vector3<f64>,
}

fn v3(s: &[f64]) -> Vector3<f64> {
    Vector3::new(s[0], s[1], s[2])
}

impl Frame {
    fn of(b: usize, bodies: &[BodyState], v: &[f64], vdot: Option<&[f64]>) -> Self {
        let s = &bodies[b];
        let (rdd, wd) = vdot.map_or((Vector3::zeros(), Vector3::zeros()), |a| {
            (v3(&a[6 * b..]), v3(&a[6 * b + 3..]))
        });
        Self {
            r: s.r,
            p: EulerParams::new(s.p[0], s.p[1], s.p[2], s.p[3]),
            a: s.a,
            rd: v3(&v[6 * b..]),
            w: v3(&v[6 * b + 3..]),
            rdd,
            wd,
        }
    }
}

/// ω'_rel = ω'_C − A_Cᵀ A_P ω'_P: the child's angular velocity relative to the parent.
fn relative_w(pf: &Frame, cf: &Frame) -> Vector3<f64> {
    cf.w - cf.a.tr_mul(&(pf.a * pf.w))
}

/// The relative motion of a tree edge (see the module docs).
struct Relative {
    p_rel: EulerParams,
    e: Vector3<f64>,
    e_dot: Vector3<f64>,
    e_ddot: Vector3<f64>,
    w: Vector3<f64>,
    w_dot: Vector3<f64>,
}

fn relative(edge: &TreeEdge, pf: &Frame, cf: &Frame) -> Relative {
    let (sp, sc) = (&edge.s_parent, &edge.s_child);
    let wp_sp = pf.w.cross(sp);
    let wc_sc = cf.w.cross(sc);
    let delta = cf.r + cf.a * sc - pf.r - pf.a * sp;
    let delta_dot = cf.rd + cf.a * wc_sc - pf.rd - pf.a * wp_sp;
    let delta_ddot = cf.rdd + cf.a * (cf.wd.cross(sc) + cf.w.cross(&wc_sc))
        - pf.rdd
        - pf.a * (pf.wd.cross(sp) + pf.w.cross(&wp_sp));
    let e = pf.a.tr_mul(&delta);
    let e_dot = pf.a.tr_mul(&delta_dot) - pf.w.cross(&e);
    let e_ddot = pf.a.tr_mul(&delta_ddot)
        - pf.wd.cross(&e)
        - 2.0 * pf.w.cross(&e_dot)
        - pf.w.cross(&pf.w.cross(&e));
    // A_relᵀ = A_Cᵀ A_P, applied as two products with vectors.
    let wp_in_c = cf.a.tr_mul(&(pf.a * pf.w));
    let w = cf.w - wp_in_c;
    let w_dot = cf.wd - cf.a.tr_mul(&(pf.a * pf.wd)) + w.cross(&wp_in_c);
    Relative {
        p_rel: pf.p.conjugate().compose(&cf.p),
        e,
        e_dot,
        e_ddot,
        w,
        w_dot,
    }
}

/// The relative accelerations [ë; ω̇'_rel] of every body under a moving parent (6 per body; the
/// others are not written) at the given poses, velocities and accelerations, into `out`: the
/// samples of the predictor's jerk.
pub(crate) fn relative_accelerations(
    model: &Model,
    bodies: &[BodyState],
    v: &[f64],
    vdot: &[f64],
    out: &mut [f64],
) {
    for (b, edge) in model.tree.edges.iter().enumerate() {
        let Some(parent) = edge.parent else {
            continue;
        };
        let pf = Frame::of(parent, bodies, v, Some(vdot));
        let cf = Frame::of(b, bodies, v, Some(vdot));
        let rel = relative(edge, &pf, &cf);
        out[6 * b..6 * b + 3].copy_from_slice(rel.e_ddot.as_slice());
        out[6 * b + 3..6 * b + 6].copy_from_slice(rel.w_dot.as_slice());
    }
}

/// Moves the workspace's poses to the prediction at `ws.t + dt` from the current velocities
/// (and, with `acc`, accelerations; with `c3` = dt³ / (6 h) ≠ 0, the jerk from the last two
/// relative accelerations, h apart). Requires valid velocities. No allocation.
pub(crate) fn predict(model: &Model, ws: &mut Workspace, dt: f64, acc: bool, c3: f64) {
    let tree = &model.tree;
    let jerk = |last: &[f64], prev: &[f64], k: usize| {
        if c3 == 0.0 {
            Vector3::zeros()
        } else {
            (v3(&last[k..]) - v3(&prev[k..])) * c3
        }
    };
    let step = |w: &Vector3<f64>, w_dot: &Vector3<f64>, j: Vector3<f64>| {
        let mut th = w * dt + w_dot * (0.5 * dt * dt) + j;
        if acc {
            th += w.cross(w_dot) * (dt * dt * dt / 12.0);
        }
        EulerParams::from_rotation_vector(&th)
    };
    // Pass 1: each body's predicted pose relative to its parent [p_rel (4); e (3)], or its
    // absolute pose [p; r] (under the ground, or when it turns faster relative to its parent
    // than absolutely).
    for (b, edge) in tree.edges.iter().enumerate() {
        let vdot = acc.then_some(ws.vdot.as_slice());
        let cf = Frame::of(b, &ws.bodies, &ws.v, vdot);
        let parent = edge
            .parent
            .map(|k| Frame::of(k, &ws.bodies, &ws.v, vdot))
            .filter(|pf| relative_w(pf, &cf).norm_squared() <= cf.w.norm_squared());
        ws.pred_absolute[b] = parent.is_none();
        let (p, e) = if let Some(pf) = parent {
            let rel = relative(edge, &pf, &cf);
            let (last, prev) = (&ws.edge_acc_last[6 * b..], &ws.edge_acc_prev[6 * b..]);
            let e = rel.e + rel.e_dot * dt + rel.e_ddot * (0.5 * dt * dt) + jerk(last, prev, 0);
            let p = rel
                .p_rel
                .compose(&step(&rel.w, &rel.w_dot, jerk(last, prev, 3)));
            (p, e)
        } else {
            let (last, prev) = (&ws.vdot_last[6 * b..], &ws.vdot_prev[6 * b..]);
            let r = cf.r + cf.rd * dt + cf.rdd * (0.5 * dt * dt) + jerk(last, prev, 0);
            let p = cf.p.compose_unit(&step(&cf.w, &cf.wd, jerk(last, prev, 3)));
            (p, r)
        };
        let out = &mut ws.pred[7 * b..7 * b + 7];
        out[..4].copy_from_slice(p.as_vector().as_slice());
        out[4..].copy_from_slice(e.as_slice());
    }
    // Pass 2: compose from the ground outwards (parents already hold their predicted poses).
    for &b in &tree.order {
        let edge = &tree.edges[b];
        let q = &ws.pred[7 * b..7 * b + 7];
        let (p, e) = (EulerParams::new(q[0], q[1], q[2], q[3]), v3(&q[4..]));
        let (r, pc) = match edge.parent {
            Some(k) if !ws.pred_absolute[b] => {
                let x = &ws.x[7 * k..7 * k + 7];
                let (rp, pp) = (v3(x), EulerParams::new(x[3], x[4], x[5], x[6]));
                let pc = pp.compose_unit(&p);
                (
                    rp + pp.a() * (edge.s_parent + e) - pc.a() * edge.s_child,
                    pc,
                )
            }
            _ => (e, p),
        };
        let xs = &mut ws.x[7 * b..7 * b + 7];
        xs[..3].copy_from_slice(r.as_slice());
        xs[3..].copy_from_slice(pc.as_vector().as_slice());
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
