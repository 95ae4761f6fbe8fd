//! Doubtful results as warnings, one sentence each (printed after the summary line, written to
//! `run.json`): a joint equation dropped as redundant that the solution does not satisfy
//! ([`dropped_row_warnings`], every kind of run), and for a dynamic run an energy balance beyond
//! [`ENERGY_BALANCE_BOUND`] of the energy scale or a constraint drift beyond the integrator's
//! tolerance ([`doubtful`], [`drift_bound`]). The numbers come from every frame
//! ([`DynamicTally`]), not from the decimated copy.

use super::energy::ENERGY_BALANCE_BOUND;
use super::tally::DynamicTally;
use crate::prepare::Prepared;
use cardan_constraints::Dimension;
use cardan_dynamics::{DynamicResults, Integrator};
use cardan_mechanism::DroppedRowResidual;

/// One warning per cam pair whose contact pulled the follower on (it would lift off): the
/// bilateral cam constraint holds it on, so past that time the motion is not that of a follower
/// pressed on by a spring or by gravity.
pub fn cam_pull_warnings(tally: &DynamicTally) -> Vec<String> {
    (tally.cam_pulls.iter())
        .filter_map(|c| {
            let ((t, n), (tl, least)) = (c.first?, c.least?);
            Some(format!(
                "cam \"{}\": the contact pulls the follower on from t = {t} s (normal force \
                 {n:.4e} N; the least {least:.4e} N at t = {tl} s): the follower would lift off \
                 the cam there, and the cam pair, which always keeps contact, holds it on, so \
                 the motion and forces after that time are not those of a follower pressed on \
                 by its spring; stiffen or preload the spring, or lower the speed",
                c.name
            ))
        })
        .collect()
}

/// One warning per joint whose equation was dropped as redundant but not satisfied at the
/// solution (its worst residual in the model's units, relative to the model's size, and when;
/// `cardan_mechanism::analysis::dropped`).
pub fn dropped_row_warnings(p: &Prepared, rows: &[DroppedRowResidual]) -> Vec<String> {
    rows.iter()
        .map(|d| {
            let (unit, factor) = p.units.unit("m");
            let value = match d.dimension {
                Dimension::Dimensionless => format!("{:.2e}", d.value.abs()),
                Dimension::Length => format!("{:.2e} {unit}", d.value.abs() * factor),
                Dimension::Area => format!("{:.2e} {unit}²", d.value.abs() * factor * factor),
            };
            let tol = p.loaded.analysis.as_ref().map_or(1e-10, |a| a.tolerance);
            if d.residual > cardan_mechanism::gross_inconsistency(tol) {
                return format!(
                    "THE MODEL IS INCONSISTENT: {} was dropped and left open by {value} ({:.2e} \
                     relative to the model's size) at worst, at t = {} s; the run goes on only \
                     because inconsistent_joints = \"drop\" (as OndselSolver runs it): the \
                     results satisfy the other equations and violate this one, so they are not \
                     a motion of the mechanism as drawn (make the joints' geometry consistent, \
                     or use a joint with fewer equations)",
                    d.equation, d.residual, d.time
                );
            }
            format!(
                "{} was dropped as redundant but is not satisfied: |Φ| = {value} ({:.2e} \
                 relative to the model's size) at worst, at t = {} s; the model's redundant \
                 joints disagree slightly, so the results satisfy the other equations exactly \
                 and this one only approximately (make the joints' geometry consistent, or use \
                 a joint with fewer equations to remove the redundancy)",
                d.equation, d.residual, d.time
            )
        })
        .collect()
}

/// The warning of a kinematic run that held free degrees of freedom (`free_dof = "hold"`),
/// naming the free joint coordinates where they can be told: their poses are the least change
/// from output time to output time, so they depend on the output step.
pub fn held_dof_warning(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    totals: &cardan_mechanism::RunTotals,
) -> Option<String> {
    let held = totals.held_dof;
    if held == 0 {
        return None;
    }
    let start = match (totals.held_from_assembly, totals.dropped_rows.is_empty()) {
        (false, _) => "",
        (true, true) => {
            "; the least change from the drawn pose did not converge (a distance joint drawn \
             far from its place?), so they start from the pose the minimum-norm assembly \
             reaches instead, which OndselSolver's may not be (draw the parts nearer their \
             places)"
        }
        (true, false) => {
            "; the least change from the drawn pose cannot close the inconsistent rows, so they \
             start from the pose the assembly reaches with those rows dropped, and the least \
             change solves the other rows"
        }
    };
    let names = crate::free_dof::named(&p.model, analysis.t_start);
    let s = if held == 1 { "" } else { "s" };
    Some(format!(
        "{held} degree{s} of freedom no driver prescribes{names} held still by least change \
         (free_dof = \"hold\", OndselSolver's weights): the free parts move only as the joints \
         and drivers force them, and their poses depend on the output step (a path of least \
         changes, not a motion); drive them, or run kind = \"dynamic\" for the motion forces \
         produce{start}"
    ))
}

/// The constraint drift a run may show: the integrator's tolerance on the scaled residual
/// (at least 1e-12, the round-off of a converged projection) times the largest equation scale
/// (the model's length for point equations), in m or -.
pub fn drift_bound(p: &Prepared, integrator: &Integrator) -> f64 {
    let tol = match integrator {
        Integrator::Dopri5(o) => o.projection_tolerance,
        Integrator::GeneralizedAlpha(o) => o.newton_tolerance,
    };
    let scale = p
        .model
        .equation_scales()
        .iter()
        .fold(1.0f64, |a, &s| a.max(s));
    tol.max(1e-12) * scale
}

/// Warnings about doubtful results of a dynamic run: an energy balance beyond
/// [`ENERGY_BALANCE_BOUND`] of the energy scale (the energy change that the work of the
/// drivers and non-conservative forces does not explain: checked for every model, driven,
/// damped or conservative), a row dropped as redundant that stays off by more than the kept
/// rows drift (the redundant joints disagree), a constraint drift beyond [`drift_bound`].
pub fn doubtful_results(p: &Prepared, r: &DynamicResults, integrator: &Integrator) -> Vec<String> {
    let tally = DynamicTally::of(r);
    doubtful(p, &tally, &r.kinematics.dropped_rows, integrator)
}

/// [`doubtful_results`] from the run's numbers over every stored time (`tally`, taken as the
/// times were streamed, not from a decimated copy) and its dropped rows.
pub fn doubtful(
    p: &Prepared,
    tally: &DynamicTally,
    dropped_rows: &[cardan_mechanism::DroppedRowResidual],
    integrator: &Integrator,
) -> Vec<String> {
    let mut warnings = Vec::new();
    let balance = tally.max_balance;
    let scale = tally.energy_scale();
    if balance > ENERGY_BALANCE_BOUND * scale {
        warnings.push(format!(
            "energy balance {balance:.3e} J (the energy change less the work of the drivers and \
             non-conservative forces) is {:.1} % of the model's energy scale {scale:.3e} J \
             (largest kinetic energy + range of the potential energy + largest work of each \
             driver and non-conservative force), more than the {} % allowed: the integration \
             is inaccurate or unstable; use a smaller step (dt) or tighter tolerances (rtol, \
             atol)",
            100.0 * balance / scale,
            100.0 * ENERGY_BALANCE_BOUND
        ));
    }
    warnings.extend(dropped_row_warnings(p, dropped_rows));
    warnings.extend(cam_pull_warnings(tally));
    let worst = tally.max_drift;
    let bound = drift_bound(p, integrator);
    // A drift no larger than the dropped rows' disagreement is that disagreement (warned above),
    // not an integration error.
    let disagreement = dropped_rows
        .iter()
        .fold(0.0f64, |a, d| a.max(d.value.abs()));
    if (worst > bound && worst > disagreement) || worst.is_nan() {
        warnings.push(format!(
            "constraint drift {worst:.3e} (largest |Φ_i|, m or -) exceeds the tolerance \
             {bound:.3e} (the integrator's tolerance times the model's length scale): the \
             joints are not held closely; use a smaller step (dt) or tighter tolerances"
        ));
    }
    warnings
}

/// One warning per driven joint whose ratings its prescribed motion passes (a URDF's
/// `<limit effort velocity>`, a joint's `effort_limit` and `rate_limit`): the driver's largest
/// |effort| (`peaks`, per driver, from an inverse dynamics run; empty otherwise) beyond the
/// effort rating, and the largest |rate| of its function over the output times beyond the rate
/// rating.
pub fn rating_warnings(p: &Prepared, peaks: &[f64]) -> Vec<String> {
    let joints = p.model.joints();
    let times = p
        .loaded
        .analysis
        .as_ref()
        .map(|a| a.times())
        .unwrap_or_default();
    let mut out = Vec::new();
    for (k, d) in p.model.drivers().iter().enumerate() {
        let Some(name) = d.joint.map(|j| &joints[j].name) else {
            continue;
        };
        let Some(entry) = p.loaded.joints.iter().find(|e| &e.name == name) else {
            continue;
        };
        if let (Some(limit), Some(&peak)) = (entry.effort_limit, peaks.get(k)) {
            if peak > limit {
                out.push(format!(
                    "driver \"{}\": its largest effort {peak:.4e} is beyond joint \"{name}\"'s \
                     effort limit {limit} (N m for an angle, N for a slide): its actuator \
                     cannot deliver this motion; slow it down or lighten the load",
                    d.name
                ));
            }
        }
        let (Some(limit), Some((f, _))) = (entry.rate_limit, p.loaded.driver_functions.get(k))
        else {
            continue;
        };
        let (t, rate) = (times.iter())
            .map(|&t| (t, f.eval(t).1.abs()))
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if rate > limit {
            out.push(format!(
                "driver \"{}\": it moves joint \"{name}\" at {rate:.4e} (rad/s or m/s) at t = \
                 {t} s, beyond the joint's rate limit {limit}",
                d.name
            ));
        }
    }
    out
}
