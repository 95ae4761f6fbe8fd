//! `kind = "dynamic"`: a model file's forces, initial velocities and integrator settings turned
//! into a [`cardan_dynamics`] simulation, and its results into output tables (reactions,
//! energy, constraint drift, besides the kinematic groups). Before the run, a run too long to
//! be meant is refused ([`check_length`], `--allow-long`); after it, doubtful results (an energy
//! balance E − E(t₀) − W_nc beyond 1 % of the energy scale, a constraint drift) become warnings
//! ([`doubtful_results`]).
//!
//! The benchmark tests call [`simulate`] directly, so what is tested is the model file itself.
//!
//! What the other analyses share with this one sits below them all and is re-exported here,
//! under the paths the benchmarks, the tests and the Python package use: the dynamics problem
//! ([`dynamics`], [`initial_state`], [`options`]: `setup`), its errors located in the file
//! (`located`), the energy balance (`energy`), the warnings about doubtful results
//! ([`doubtful_results`], [`drift_bound`]: `warnings`) and the tables held whole (`tables`).

use super::dynamic_layout::{DynamicLayout, Kind};
use super::stream::{Recorder, Tap};
use super::summary::{Analysed, DynamicSummary, RunFlags, Summary};
use crate::diag::Error;
use crate::files::{FrameTap, OutputFiles};
use crate::output_tables::{computed, peak_efforts_of, requested};
use crate::prepare::Prepared;
use cardan_dynamics::{DynamicResults, Integrator, SimulationOptions};
use std::path::PathBuf;
use std::time::Instant;

// Shared with the other analyses (module docs).
pub use super::energy::{energy_scale, ENERGY_BALANCE_BOUND};
pub use super::located::{located, located_as};
pub use super::setup::{dynamics, initial_state, options};
pub use super::tables::dynamic_tables as tables;
pub use super::warnings::{doubtful, doubtful_results, drift_bound};

/// `kind = "dynamic"`: simulate, the tables, the summary. A failure mid-run keeps the results
/// so far with the error. With `dir`, the CSV files are written there output by output and only
/// a decimated copy of the results is kept (every output goes to `solved`, an ASMT run's
/// TimeSeries); without, every output is kept
/// ([`super::stream`]). The summary and the warnings are taken over every output.
pub(super) fn run_dynamic(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    flags: &RunFlags,
    dir: Option<&mut (dyn OutputFiles + 'static)>,
    solved: Option<&mut (dyn FrameTap + 'static)>,
) -> Result<Analysed, Error> {
    let mut opts = options(p, None)?;
    check_length(p, &mut opts, flags.allow_long)?;
    let mut d = dynamics(p)?;
    let initial = initial_state(p);
    let req = requested(p, &analysis.outputs);
    opts = opts.outputs(computed(&req));
    let planned = opts.times(initial.t).len();
    let make = |f: &DynamicResults| DynamicLayout::new(p, f, &req, Kind::Dynamic);
    let tap = solved.map(|s| s as &mut dyn Tap<DynamicResults>);
    let mut rec = Recorder::new(p.units, planned, dir, tap, make);
    let start = Instant::now();
    // Progress in parts of the time span (the number of adaptive steps is not known).
    const PARTS: f64 = 10_000.0;
    let (t0, span) = (analysis.t_start, analysis.t_end - analysis.t_start);
    let mut bar = crate::progress::Progress::new(flags.progress, PARTS as u64);
    let mut sink = |_: usize, frame: &DynamicResults| rec.frame(frame);
    let outcome = d.simulate_into(&initial, &opts, &mut sink, |t| {
        bar.tick(((t - t0) / span * PARTS) as u64, t)
    });
    drop(bar);
    let wall = start.elapsed();
    let events = super::stops::events_csv(p, d.impact_events());
    let impacts = d.impact_events().to_vec();
    let counts = super::stops::counts(p, d.impact_events(), d.stop_history());
    let stops = super::stops::stops_table(p, d.stop_history());
    let friction = super::friction::friction_table(p, d.friction_history());
    drop(d);
    let (totals, failure) = match outcome {
        Ok(r) => (r, None),
        Err(e) => match e.partial_results() {
            Some(r) if matches!(e.cause(), cardan_dynamics::DynamicsError::Stopped { .. }) => (
                r.clone(),
                Some(crate::progress::interrupted(rec.last_time().as_slice())),
            ),
            Some(r) => (r.clone(), Some(located(p, &e))),
            None => return Err(located(p, &e)),
        },
    };
    // A write error stopped the run: it is the error.
    let rec = rec.finish()?;
    let mut r = rec.results;
    r.stats = totals.stats;
    r.redundant = totals.redundant;
    r.kinematics.set_totals(totals.kinematics.totals());
    let mut tables = rec.tables;
    let mut files = Vec::new();
    if let (Some(t), None) = (analysis.linearize_at, &failure) {
        let (lt, lf) = super::linearize::about_dynamic(p, &opts, t, &req, &analysis.inputs)?;
        tables.extend(lt);
        files = lf;
    }
    tables.extend(stops);
    tables.extend(friction);
    files.extend(events);
    let tally = rec.tally;
    files.extend(super::contacts::contacts_csv(p, &tally.contacts));
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: rec.frames,
        noun: ["step", "steps"],
        iterations: r.stats.newton_iterations,
        max_residual: tally.max_drift,
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: Some(DynamicSummary {
            steps: r.stats.steps,
            rejected: r.stats.rejected,
            newton_iterations: r.stats.newton_iterations,
            max_constraint_drift: tally.max_drift,
            energy_drift: tally.max_energy_drift,
            stops: counts,
        }),
        energy_balance: Some(tally.energy_balance()),
        peak_efforts: peak_efforts_of(p, &r, &tally.peak_efforts),
        warnings: doubtful(p, &tally, &r.kinematics.dropped_rows, &opts.integrator)
            .into_iter()
            .chain(super::contacts::penetration_warning(p, &tally.contacts))
            .chain(super::contacts::step_warning(&r.stats))
            .collect(),
        subdivided_steps: None,
        row_reselections: r.stats.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r),
        failure,
        strict_failure: None,
        files,
        modes: Vec::new(),
        events: impacts,
        streamed: rec.streamed,
    })
}

/// Runs the file's dynamic analysis (or with another integrator).
///
/// # Errors
/// As [`dynamics`] and [`options`]; inconsistent initial conditions; integration failures
/// (located at the element concerned when the error names one).
pub fn simulate(p: &Prepared, integrator: Option<Integrator>) -> Result<DynamicResults, Error> {
    let opts = options(p, integrator)?;
    let mut d = dynamics(p)?;
    let s = initial_state(p);
    d.simulate(&s, &opts).map_err(|e| located(p, &e))
}

/// Most integration steps a dynamic run may need without `--allow-long`: as many as a kinematic
/// run may have, and the integrators' own step limit
/// ([`SimulationOptions::max_steps`]'s default).
pub const MAX_STEPS: usize = 10_000_000;

/// The least number of integration steps the run needs and the step it assumes: t span / h for
/// fixed steps (DOPRI5 with `dt`, generalized-α), t span / h_max for adaptive DOPRI5 with
/// `h_max`; `None` when it cannot be told before the run (adaptive without `h_max`: the step
/// follows the motion, and the integrators' limit of [`MAX_STEPS`] steps applies).
pub fn step_estimate(opts: &SimulationOptions, span: f64) -> Option<(f64, f64)> {
    use cardan_dynamics::StepControl;
    let h = match opts.integrator {
        Integrator::Dopri5(o) => match o.step {
            StepControl::Fixed(h) => h,
            StepControl::Adaptive { .. } if o.h_max.is_finite() => o.h_max,
            StepControl::Adaptive { .. } => return None,
        },
        Integrator::GeneralizedAlpha(o) => o.dt,
    };
    Some(((span / h).ceil(), h))
}

/// Refuses a dynamic run estimated to need more than [`MAX_STEPS`] steps unless `allow_long`;
/// with `allow_long`, lifts the integrators' step limit (a long adaptive run is then stopped by
/// Ctrl-C only).
///
/// # Errors
/// An input error at `[analysis]` with the estimate and the flag that overrides it.
pub fn check_length(
    p: &Prepared,
    opts: &mut SimulationOptions,
    allow_long: bool,
) -> Result<(), Error> {
    if allow_long {
        opts.max_steps = usize::MAX;
        return Ok(());
    }
    let Some(a) = p.loaded.analysis.as_ref() else {
        return Ok(());
    };
    let span = a.t_end - a.t_start;
    match step_estimate(opts, span) {
        Some((n, h)) if n > MAX_STEPS as f64 => Err(p.source.error_at(
            p.loaded.spans.analysis.clone(),
            format!(
                "this dynamic run needs at least {n:.2e} integration steps (t_end − t_start = \
                 {span} s with steps of at most {h:e} s); runs of more than {MAX_STEPS} steps \
                 are refused as a likely mistake: use a larger step, or pass --allow-long to \
                 run it anyway (Ctrl-C stops it and keeps the results so far)"
            ),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::stream::MAX_PLOTTED_FRAMES;
    use crate::analysis::tally::DynamicTally;
    use cardan_dynamics::DynamicsError;
    use std::ops::ControlFlow;

    /// A constraint drift and an energy balance spike at one output that the decimated copy
    /// does not keep: the summary and the warnings, taken over every output, still report them;
    /// the same checks over the kept copy (what the summary was made from before the run
    /// streamed) miss them.
    #[test]
    fn a_spike_between_two_kept_frames_is_still_summed_up_and_warned_about() {
        let model = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/slider_crank_dynamic.toml");
        let p = crate::prepare::prepare(&model).unwrap();
        let analysis = p.loaded.analysis.clone().unwrap();
        let opts = options(&p, None).unwrap();
        let req = requested(&p, &analysis.outputs);
        let path =
            std::env::temp_dir().join(format!("cardan-dynamic-spike-{}", std::process::id()));
        std::fs::create_dir_all(&path).unwrap();
        let mut dir = crate::files::Directory(path);
        // As planned for 10 × (the plotted frames − 1) + 2 outputs: every 11th of the 501
        // outputs is kept (the stride keeps the first, every s-th and the last frame).
        let planned = 10 * (MAX_PLOTTED_FRAMES - 1) + 2;
        let make = |f: &DynamicResults| DynamicLayout::new(&p, f, &req, Kind::Dynamic);
        let mut rec = Recorder::new(p.units, planned, Some(&mut dir), None, make);
        let bound = drift_bound(&p, &opts.integrator);
        let spike = 3 * 11 + 5;
        let mut spike_time = f64::NAN;
        let mut sink = |k: usize, frame: &DynamicResults| {
            if k != spike {
                return rec.frame(frame);
            }
            let mut f = frame.clone();
            f.position_drift[0] = 100.0 * bound;
            f.energy.total[0] += 1e6;
            spike_time = f.times()[0];
            rec.frame(&f)
        };
        let mut d = dynamics(&p).unwrap();
        let run = d.simulate_into(&initial_state(&p), &opts, &mut sink, |_| {
            ControlFlow::<()>::Continue(())
        });
        run.map_err(|e: DynamicsError| e.to_string()).unwrap();
        let rec = rec.finish().unwrap();
        assert_eq!(rec.frames, 501);
        assert!(rec.streamed.as_ref().is_some_and(|s| s.stride == 11));
        assert!(!rec.results.times().contains(&spike_time));
        // Over every output.
        assert_eq!(rec.tally.max_drift, 100.0 * bound);
        assert!(rec.tally.max_balance >= 1e6 - 1.0);
        let every = doubtful(&p, &rec.tally, &[], &opts.integrator);
        assert!(
            every.iter().any(|w| w.starts_with("constraint drift")),
            "{every:?}"
        );
        assert!(
            every.iter().any(|w| w.starts_with("energy balance")),
            "{every:?}"
        );
        // Over the kept copy: both lost.
        let kept = doubtful_results(&p, &rec.results, &opts.integrator);
        assert!(kept.is_empty(), "{kept:?}");
        assert!(DynamicTally::of(&rec.results).max_drift < bound);
    }
}
