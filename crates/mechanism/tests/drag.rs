//! Issue 53, item 4: dragging (FreeCAD's interaction). A four-bar's crank pin dragged around
//! its circle passes both toggle positions of the rocker on the drawn branch (the coupler pin on
//! its closed form); every step's pose satisfies the optimality conditions of the least-change
//! problem (the weighted change orthogonal to the constraint tangent space, to 1e-10); a limit
//! on the crank stops the drag at its bound and holds it there while the cursor goes on; a
//! long jump toward a point far off the pin's circle is followed in one step.

mod common;
use cardan_mechanism::{
    AssemblyOptions, Drag, DragStop, LimitSpec, Model, Workspace, DRAG_WEIGHTS,
};
use common::{four_bar_b, four_bar_links, FOUR_BAR};
use nalgebra::{DMatrix, DVector, Vector3};
use std::f64::consts::PI;

/// The crank's pin A: the dragged point (crank body frame: its end at +a/2).
fn pin() -> Vector3<f64> {
    Vector3::new(FOUR_BAR.1 / 2.0, 0.0, 0.0)
}

fn setup(limits: &[LimitSpec]) -> (Model, Workspace, Drag) {
    let mut b = four_bar_links(0.3, 0.0);
    for l in limits {
        b.limit(l.clone());
    }
    let model = b.build().unwrap();
    let mut ws = model.workspace();
    model.assemble(&mut ws, &AssemblyOptions::at(0.0)).unwrap();
    let drag = Drag::new(&model, "crank", pin(), 1.0).unwrap();
    (model, ws, drag)
}

/// ∂p/∂π' = ½ [−eᵀ; e₀ I + ẽ] (4 × 3).
fn tangent(p: &[f64]) -> DMatrix<f64> {
    let (e0, e) = (p[0], Vector3::new(p[1], p[2], p[3]));
    let mut q = DMatrix::zeros(4, 3);
    for j in 0..3 {
        q[(0, j)] = -e[j] / 2.0;
        let col = (e0 * Vector3::ith(j, 1.0) + e.cross(&Vector3::ith(j, 1.0))) / 2.0;
        for i in 0..3 {
            q[(1 + i, j)] = col[i];
        }
    }
    q
}

/// The largest component of the objective's gradient g = Qᵀ W (q − q_old) + w_d Bᵀ (P − target)
/// along the null space of Φ_v, over |g|: zero at the exact least-change pose (g = −Φ_vᵀ λ).
/// B = ∂P/∂[Δr; Δπ'] = [I, −A s̃'] for the dragged point P = r + A s'.
fn optimality(
    model: &Model,
    ws: &Workspace,
    old: &[f64],
    (dragged, point): (usize, Vector3<f64>),
    target: Vector3<f64>,
) -> f64 {
    let (least, most) = DRAG_WEIGHTS;
    let nb = model.num_bodies();
    let x = pose(ws, model);
    let mut g = DVector::zeros(6 * nb);
    for b in 0..nb {
        for i in 0..3 {
            g[6 * b + i] = least * (x[7 * b + i] - old[7 * b + i]);
        }
        let dp = DVector::from_fn(4, |i, _| least * (x[7 * b + 3 + i] - old[7 * b + 3 + i]));
        let gr = tangent(&x[7 * b + 3..7 * b + 7]).transpose() * dp;
        for i in 0..3 {
            g[6 * b + 3 + i] = gr[i];
        }
    }
    let a = cardan_eulerparam::a(&ws.p(dragged));
    let miss = ws.r(dragged) + a * point - target;
    let rot = -(a * point.cross_matrix()).transpose() * miss;
    for i in 0..3 {
        g[6 * dragged + i] += most * miss[i];
        g[6 * dragged + 3 + i] += most * rot[i];
    }
    let mut slots = vec![0.0; model.pattern().num_slots()];
    model.eval_jacobian(ws, 0.0, &mut slots);
    let mut j = DMatrix::zeros(model.num_equations(), 6 * nb);
    for (s, v) in model.pattern().entries().zip(&slots) {
        j[s] = *v;
    }
    // J has at least as many rows as columns (4 revolutes: 20 rows for 18 unknowns), so every
    // null vector is a row of Vᵀ.
    assert!(model.num_equations() >= 6 * nb);
    let svd = j.svd(false, true);
    let vt = svd.v_t.unwrap();
    let smax = svd.singular_values.max();
    let mut worst: f64 = 0.0;
    for (k, s) in svd.singular_values.iter().enumerate() {
        if *s < 1e-9 * smax {
            worst = worst.max(vt.row(k).transpose().dot(&g).abs());
        }
    }
    worst / g.norm().max(1e-300)
}

/// The Newton state [r; p] per body.
fn pose(ws: &Workspace, model: &Model) -> Vec<f64> {
    (0..model.num_bodies())
        .flat_map(|b| {
            let (r, p) = (ws.r(b), ws.p(b));
            [r.x, r.y, r.z, p[0], p[1], p[2], p[3]]
        })
        .collect()
}

/// The crank's angle (of its pin A about O2).
fn crank_angle(ws: &Workspace) -> f64 {
    let a = ws.r(0) + cardan_eulerparam::a(&ws.p(0)) * pin();
    a.y.atan2(a.x)
}

fn crank_target(theta: f64) -> Vector3<f64> {
    FOUR_BAR.1 * Vector3::new(theta.cos(), theta.sin(), 0.0)
}

#[test]
fn a_four_bar_dragged_around_passes_its_toggles_on_the_drawn_branch() {
    let (model, mut ws, mut drag) = setup(&[]);
    let steps = 144; // 2.5° each, once round from θ = 0.3
    let (mut worst_b, mut worst_kkt, mut worst_lag): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for k in 1..=steps {
        let theta = 0.3 + 2.0 * PI * k as f64 / steps as f64;
        let target = crank_target(theta);
        let old = pose(&ws, &model);
        let from = crank_angle(&ws);
        let rep = drag.step(&model, &mut ws, 0.0, target).unwrap();
        assert_eq!(rep.stop, DragStop::None, "step {k}");
        // The soft pull: behind the target by about 1e-3 of the step's motion.
        let step_length = (target - crank_target(from)).norm();
        worst_lag = worst_lag.max(rep.distance / step_length);
        let b = ws.r(2) + cardan_eulerparam::a(&ws.p(2)) * Vector3::new(FOUR_BAR.3 / 2.0, 0.0, 0.0);
        worst_b = worst_b.max((b - four_bar_b(crank_angle(&ws))).amax());
        worst_kkt = worst_kkt.max(optimality(&model, &ws, &old, (0, pin()), target));
    }
    eprintln!(
        "B against its closed form {worst_b:.2e} m; optimality {worst_kkt:.2e}; lag {worst_lag:.2e} of a step"
    );
    assert!(worst_b < 1e-9, "B off its closed form by {worst_b} m");
    assert!(worst_kkt < 1e-10, "least-change optimality {worst_kkt}");
    assert!(worst_lag < 1e-2, "the pin lags by {worst_lag} of a step");
    // Repeated toward the same target, the pull closes the lag.
    let target = crank_target(0.3 + 2.0 * PI + 0.1);
    let mut last = f64::INFINITY;
    for _ in 0..4 {
        last = drag.step(&model, &mut ws, 0.0, target).unwrap().distance;
    }
    assert!(
        last < 1e-9,
        "still {last} m from a target dragged to four times"
    );
}

#[test]
fn a_long_jump_is_followed_in_one_step() {
    // The pin pulled in one jump toward a point four crank lengths away at 1.5 rad. Without the
    // goal's curvature term Gauss–Newton overshot by a factor of about 1 + 3 here and the step
    // was cut back to a third, "not converged" (iterations: 499).
    let target = 4.0 * crank_target(1.5);
    let (model, mut ws, mut drag) = setup(&[]);
    let old = pose(&ws, &model);
    let rep = drag.step(&model, &mut ws, 0.0, target).unwrap();
    assert_eq!(rep.stop, DragStop::None, "{rep:?}");
    assert_eq!(rep.reached, 1.0);
    assert!(rep.iterations < 100, "{rep:?}");
    // On its circle toward the target, at the least-change optimum.
    assert!(
        (crank_angle(&ws) - 1.5).abs() < 1e-3,
        "the crank at {} rad",
        crank_angle(&ws)
    );
    let kkt = optimality(&model, &ws, &old, (0, pin()), target);
    assert!(kkt < 1e-10, "least-change optimality {kkt}");
}

#[test]
fn a_point_near_the_hinge_pulled_far_is_followed_in_one_step() {
    // The crank grabbed 0.15 m from its hinge (a sixth of its length) and pulled toward a point
    // 1 m off at 1.5 rad: the grabbed point circles the hinge, not the crank's centre, and
    // Gauss–Newton without the joints' curvature overshot the turn (cut back to 24 % of the
    // step, not converged after 499 iterations); with the Newton step it is one step.
    let near = Vector3::new(-FOUR_BAR.1 / 2.0 + 0.15, 0.0, 0.0);
    let model = four_bar_links(0.3, 0.0).build().unwrap();
    let mut ws = model.workspace();
    model.assemble(&mut ws, &AssemblyOptions::at(0.0)).unwrap();
    let mut drag = Drag::new(&model, "crank", near, 1.0).unwrap();
    let target = Vector3::new(1.5f64.cos(), 1.5f64.sin(), 0.0);
    let old = pose(&ws, &model);
    let rep = drag.step(&model, &mut ws, 0.0, target).unwrap();
    assert_eq!(rep.stop, DragStop::None, "{rep:?}");
    assert_eq!(rep.reached, 1.0);
    // Toward the target, short of 1.5 rad by the soft pull's lag (9.4e-3 rad: the point cannot
    // reach a target 0.85 m off its circle, so the pull stays loaded against the other bodies'
    // weights); the optimality conditions below are the exact check.
    assert!(
        (crank_angle(&ws) - 1.5).abs() < 1e-2,
        "the crank at {} rad",
        crank_angle(&ws)
    );
    let kkt = optimality(&model, &ws, &old, (0, near), target);
    assert!(kkt < 1e-10, "least-change optimality {kkt}");
}

#[test]
fn a_drag_into_a_stop_stops_there() {
    let (model, mut ws, mut drag) = setup(&[LimitSpec::new("crank_stop", "O2").upper(1.0)]);
    let angle = crank_angle;
    let mut stopped = 0;
    for k in 1..=20 {
        let theta = 0.32 + 0.05 * k as f64;
        // Three steps toward each target close the soft pull's lag (1e-3 per step).
        let mut rep = drag
            .step(&model, &mut ws, 0.0, crank_target(theta))
            .unwrap();
        for _ in 0..3 {
            let again = drag
                .step(&model, &mut ws, 0.0, crank_target(theta))
                .unwrap();
            if rep.stop == DragStop::None {
                rep = again;
            }
        }
        if theta < 1.0 {
            assert_eq!(rep.stop, DragStop::None, "θ = {theta}");
            assert!(
                (angle(&ws) - theta).abs() < 1e-9,
                "θ = {theta}: the crank at {}",
                angle(&ws)
            );
        } else {
            assert_eq!(
                rep.stop,
                DragStop::Limit("crank_stop".into()),
                "θ = {theta}"
            );
            assert!(rep.reached < 1.0);
            assert!(
                (angle(&ws) - 1.0).abs() < 1e-9,
                "θ = {theta}: the crank at {} rad, not at its stop",
                angle(&ws)
            );
            stopped += 1;
        }
    }
    assert_eq!(stopped, 7);
    // Dragged back, it leaves the stop.
    for _ in 0..4 {
        let rep = drag.step(&model, &mut ws, 0.0, crank_target(0.8)).unwrap();
        assert_eq!(rep.stop, DragStop::None);
    }
    assert!((angle(&ws) - 0.8).abs() < 1e-9);
}

#[test]
fn hostile_drags_are_errors() {
    let model = four_bar_links(0.3, 0.0).build().unwrap();
    for (body, point) in [
        ("nobody", pin()),
        ("ground", pin()),
        ("crank", Vector3::new(f64::NAN, 0.0, 0.0)),
    ] {
        assert!(Drag::new(&model, body, point, 1.0).is_err(), "{body}");
    }
    assert!(Drag::new(&model, "crank", pin(), 0.0).is_err());
    let (model, mut ws, mut drag) = setup(&[]);
    assert!(drag
        .step(&model, &mut ws, 0.0, Vector3::new(f64::INFINITY, 0.0, 0.0))
        .is_err());
}
