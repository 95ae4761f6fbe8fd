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

use crate::model::{Model, TreeEdge};
use crate::workspace::Workspace;
use cardan_constraints::BodyState;
use cardan_eulerparam::EulerParams;
use nalgebra::{Matrix3, Vector3};

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

/// Moves the workspace's poses to the prediction at `ws.pose.t + dt` from the current velocities
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
        let vdot = acc.then_some(ws.motion.vdot.as_slice());
        let cf = Frame::of(b, &ws.pose.bodies, &ws.motion.v, vdot);
        let parent = edge
            .parent
            .map(|k| Frame::of(k, &ws.pose.bodies, &ws.motion.v, vdot))
            .filter(|pf| relative_w(pf, &cf).norm_squared() <= cf.w.norm_squared());
        ws.prediction.pred_absolute[b] = parent.is_none();
        let (p, e) = if let Some(pf) = parent {
            let rel = relative(edge, &pf, &cf);
            let (last, prev) = (
                &ws.jerk.edge_acc_last[6 * b..],
                &ws.jerk.edge_acc_prev[6 * b..],
            );
            let e = rel.e + rel.e_dot * dt + rel.e_ddot * (0.5 * dt * dt) + jerk(last, prev, 0);
            let p = rel
                .p_rel
                .compose(&step(&rel.w, &rel.w_dot, jerk(last, prev, 3)));
            (p, e)
        } else {
            let (last, prev) = (&ws.jerk.vdot_last[6 * b..], &ws.jerk.vdot_prev[6 * b..]);
            let r = cf.r + cf.rd * dt + cf.rdd * (0.5 * dt * dt) + jerk(last, prev, 0);
            let p = cf.p.compose_unit(&step(&cf.w, &cf.wd, jerk(last, prev, 3)));
            (p, r)
        };
        let out = &mut ws.prediction.pred[7 * b..7 * b + 7];
        out[..4].copy_from_slice(p.as_vector().as_slice());
        out[4..].copy_from_slice(e.as_slice());
    }
    // Pass 2: compose from the ground outwards (parents already hold their predicted poses).
    for &b in &tree.order {
        let edge = &tree.edges[b];
        let q = &ws.prediction.pred[7 * b..7 * b + 7];
        let (p, e) = (EulerParams::new(q[0], q[1], q[2], q[3]), v3(&q[4..]));
        let (r, pc) = match edge.parent {
            Some(k) if !ws.prediction.pred_absolute[b] => {
                let x = &ws.pose.x[7 * k..7 * k + 7];
                let (rp, pp) = (v3(x), EulerParams::new(x[3], x[4], x[5], x[6]));
                let pc = pp.compose_unit(&p);
                (
                    rp + pp.a() * (edge.s_parent + e) - pc.a() * edge.s_child,
                    pc,
                )
            }
            _ => (e, p),
        };
        let xs = &mut ws.pose.x[7 * b..7 * b + 7];
        xs[..3].copy_from_slice(r.as_slice());
        xs[3..].copy_from_slice(pc.as_vector().as_slice());
    }
}
