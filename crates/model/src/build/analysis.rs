//! `[analysis]` to an [`Analysis`]: which keys the kind takes (and the integrator's keys, and
//! `[analysis.outputs]`'s) come from the vocabularies ([`crate::vocabulary::ANALYSES`],
//! [`INTEGRATORS`], [`OUTPUTS`]), checked before anything is read; a number's quantity (its
//! unit and magnitude limit) and a count's range come from the key's table entry. What is left
//! here is what the tables cannot say: the time grid (t_end after t_start, steps or dt, the
//! memory the run would store), the outputs' names, and the integrator's ranges (the library's,
//! [`Integrator::validate`], placed at the key).

use super::context::{Ctx, Resolver};
use super::loaded::{Analysis, AnalysisKind, Outputs, Spans, StaticKind};
use crate::diag::{did_you_mean, Error};
use crate::file::{AnalysisSection, Name, Num};
use crate::vocabulary::{Entry, ANALYSES, INTEGRATORS, OUTPUTS};
use cardan_dynamics::Force;
use cardan_dynamics::{Dopri5Options, GeneralizedAlphaOptions, Integrator};
use cardan_mechanism::{FreeDof, HoldMetric, KinematicOptions, GROUND};
use toml::Spanned;

/// Most (output times) × (moving bodies + their points) a run may store: 10⁷, at most about
/// 2.6 GB of results.
pub const MAX_STORED_FRAMES: usize = 10_000_000;

/// `[analysis]` (the section `section`, whose kind was checked by the vocabulary).
pub(super) fn load_analysis(
    r: &Resolver,
    section: &Spanned<AnalysisSection>,
    spans: &Spans,
) -> Result<Analysis, Error> {
    let cx = r.cx;
    let a = section.get_ref();
    let table = section.span().start;
    let entry = cx.check(&ANALYSES, "", &a.kind, table, a.kind.span())?;
    if let Some(o) = &a.outputs {
        cx.check(
            &OUTPUTS,
            "[analysis.outputs]",
            &a.kind,
            o.span().start,
            a.kind.span(),
        )?;
    }
    let kind = match entry.name {
        "kinematic" => AnalysisKind::Kinematic,
        "inverse_dynamics" => AnalysisKind::InverseDynamics,
        "dynamic" => AnalysisKind::Dynamic(load_integrator(cx, a, table)?),
        "static" => AnalysisKind::Static(StaticKind::Static),
        "quasi_static" => AnalysisKind::Static(StaticKind::QuasiStatic),
        _ => AnalysisKind::Static(StaticKind::Modal),
    };
    let tolerance = tolerance(cx, a, entry)?;
    let load_steps = count(cx, entry, "load_steps", &a.load_steps)?.unwrap_or(1);
    let modes = load_modes(cx, a, entry, 6 * r.order.len().saturating_sub(1))?;
    let (t_start, t_end, steps) = time_grid(cx, a, entry, &kind)?;
    check_stored_frames(r, a, steps)?;
    let outputs = load_outputs(r, a, spans)?;
    let linearize_at = match &a.linearize_at {
        None => None,
        Some(n) => {
            let t = cx.num(n, "linearize_at", entry.quantity("linearize_at"))?;
            if !(t_start..=t_end).contains(&t) {
                return Err(cx.err(
                    n.span(),
                    format!(
                        "linearize_at = {t} s must lie between t_start = {t_start} s and \
                         t_end = {t_end} s"
                    ),
                ));
            }
            Some(t)
        }
    };
    let plots = a.plots.as_ref().is_none_or(|p| p.get_ref() == "svg");
    // OndselSolver's weights on coordinates in the file's length unit.
    let free_dof = match a.free_dof.as_ref().map(|f| f.get_ref().as_str()) {
        Some("hold") => FreeDof::Hold(HoldMetric::Ondsel {
            metres_per_unit: cx.units.to_si(cardan_mechanism::Quantity::Length),
        }),
        _ => FreeDof::Refuse,
    };
    let drop_inconsistent = a
        .inconsistent_joints
        .as_ref()
        .is_some_and(|f| f.get_ref() == "drop");
    Ok(Analysis {
        kind,
        t_start,
        t_end,
        steps,
        outputs,
        plots,
        tolerance,
        load_steps,
        inputs: Vec::new(),
        linearize_at,
        modes,
        free_dof,
        drop_inconsistent,
    })
}

/// A count key of `entry` (`steps`, `load_steps`, `modes`) in the range of its table entry.
fn count(
    cx: &Ctx,
    entry: &Entry,
    key: &str,
    value: &Option<Spanned<i64>>,
) -> Result<Option<usize>, Error> {
    let Some(n) = value else {
        return Ok(None);
    };
    let v = *n.get_ref();
    if let Some(crate::vocabulary::Value::Count { min, max }) = entry.key(key).map(|k| k.value) {
        if !(min..=max).contains(&v) {
            return Err(cx.err(
                n.span(),
                format!("{key} must be between {min} and {max}, got {v}"),
            ));
        }
    }
    Ok(Some(v as usize))
}

/// The kind's tolerance: `position_tolerance` (kinematic, inverse dynamics) or
/// `equilibrium_tolerance` (static kinds), `tolerance` being the older name of either (both
/// at once are refused by the vocabulary check); dynamic runs have their integrator's. The range
/// is the library's, the refusal placed at the key.
fn tolerance(cx: &Ctx, a: &AnalysisSection, entry: &Entry) -> Result<f64, Error> {
    let given = [
        ("position_tolerance", &a.position_tolerance),
        ("equilibrium_tolerance", &a.equilibrium_tolerance),
        ("tolerance", &a.tolerance),
    ]
    .into_iter()
    .find_map(|(k, v)| v.as_ref().map(|n| (k, n)));
    let default = KinematicOptions::new(0.0, 1.0, 1).tolerance;
    let Some((key, n)) = given.filter(|_| entry.name != "dynamic") else {
        return Ok(default);
    };
    let v = cx.num(n, key, cardan_mechanism::Quantity::Unbounded)?;
    KinematicOptions::new(0.0, 1.0, 1)
        .tolerance(v)
        .validate()
        .map_err(|e| cx.err(n.span(), e.to_string()))?;
    Ok(v)
}

/// `modes` (modal only, checked by the vocabulary; its range by the table), at most the model's
/// unknowns (6 per moving body).
fn load_modes(
    cx: &Ctx,
    a: &AnalysisSection,
    entry: &Entry,
    unknowns: usize,
) -> Result<Option<usize>, Error> {
    let Some(v) = count(cx, entry, "modes", &a.modes)? else {
        return Ok(None);
    };
    if v > unknowns {
        let span = a.modes.as_ref().map_or(0..0, Spanned::span);
        return Err(cx.err(
            span,
            format!(
                "modes = {v} is more than the model's {unknowns} unknowns (6 per moving body): \
                 it has at most that many modes"
            ),
        ));
    }
    Ok(Some(v))
}

/// The time grid (t_start, t_end, steps): one time for static and modal (`time`); otherwise
/// t_end after t_start and the steps, given or from the output step (`dt`; `output_dt` for a
/// dynamic analysis, whose `dt` is the integration step).
fn time_grid(
    cx: &Ctx,
    a: &AnalysisSection,
    entry: &Entry,
    kind: &AnalysisKind,
) -> Result<(f64, f64, usize), Error> {
    let time = |n: &Num, key: &str| cx.num(n, key, entry.quantity(key));
    if entry.key("time").is_some() {
        let t = a.time.as_ref().map(|n| time(n, "time")).transpose()?;
        let t = t.unwrap_or(0.0);
        return Ok((t, t, 0));
    }
    let t_start = a.t_start.as_ref().map(|n| time(n, "t_start")).transpose()?;
    let t_start = t_start.unwrap_or(0.0);
    // Required: the vocabulary check refused a kind without it.
    let t_end = match &a.t_end {
        Some(n) => time(n, "t_end")?,
        None => return Err(cx.err(a.kind.span(), "[analysis] needs t_end (the end time, s)")),
    };
    if t_end <= t_start {
        let span = a.t_end.as_ref().map_or(a.kind.span(), |n| n.span());
        return Err(cx.err(
            span,
            format!("t_end = {t_end} s must be greater than t_start = {t_start} s"),
        ));
    }
    let (out_dt, out_key) = match kind {
        AnalysisKind::Dynamic(_) => (&a.output_dt, "output_dt"),
        _ => (&a.dt, "dt"),
    };
    let steps = match (count(cx, entry, "steps", &a.steps)?, out_dt) {
        (Some(_), Some(dt)) => {
            return Err(cx.err(
                dt.span(),
                format!("give either steps or {out_key}, not both"),
            ))
        }
        (Some(n), None) => n,
        (None, Some(dt)) => steps_of(cx, dt, out_key, t_end - t_start)?,
        (None, None) => 100,
    };
    Ok((t_start, t_end, steps))
}

/// The number of steps the output step `dt` gives over `span` (a whole number, at most 10⁷).
fn steps_of(cx: &Ctx, dt: &Num, key: &str, span: f64) -> Result<usize, Error> {
    let h = cx.num(dt, key, cardan_mechanism::Quantity::Time)?;
    if h <= 0.0 {
        return Err(cx.err(dt.span(), format!("{key} must be positive, got {h} s")));
    }
    let n = (span / h).round();
    if n > 1e7 {
        return Err(cx.err(
            dt.span(),
            format!("{key} = {h} s gives {n:e} steps; at most 10000000 are allowed"),
        ));
    }
    if (span / h - n).abs() > 1e-6 * n.max(1.0) {
        return Err(cx.err(
            dt.span(),
            format!(
                "{key} = {h} s does not divide t_end − t_start = {span} s into whole steps; use \
                 steps = N instead"
            ),
        ));
    }
    Ok((n as usize).max(1))
}

/// The run stores every moving body and point at every output time: the memory is bounded.
fn check_stored_frames(r: &Resolver, a: &AnalysisSection, steps: usize) -> Result<(), Error> {
    let moving = r.order.len().saturating_sub(1);
    let points: usize = r
        .order
        .iter()
        .skip(1)
        .filter_map(|b| r.features.get(b))
        .map(|f| f.points.len())
        .sum();
    let stored = (steps + 1).saturating_mul((moving + points).max(1));
    if stored > MAX_STORED_FRAMES {
        return Err(r.cx.err(
            a.kind.span(),
            format!(
                "{} output times × {} bodies and points = {stored:e} stored frames; at most \
                 {MAX_STORED_FRAMES:e} are allowed (each takes up to 264 bytes): use fewer steps",
                steps + 1,
                moving + points
            ),
        ));
    }
    Ok(())
}

/// `[analysis.outputs]`: the names it lists exist (which groups the kind takes was checked by
/// the vocabulary).
fn load_outputs(r: &Resolver, a: &AnalysisSection, spans: &Spans) -> Result<Outputs, Error> {
    let cx = r.cx;
    let mut outputs = Outputs {
        energy: true,
        ..Outputs::default()
    };
    let Some(o) = &a.outputs else {
        return Ok(outputs);
    };
    let o = o.get_ref();
    outputs.listed = o.points.is_some() || o.joints.is_some() || o.bodies.is_some();
    for p in o.points.iter().flatten() {
        outputs.points.push(body_point(r, p, "outputs.points")?);
    }
    for p in &o.jacobians {
        outputs
            .jacobians
            .push(body_point(r, p, "outputs.jacobians")?);
    }
    outputs.joint_space = o.joint_space.unwrap_or(false);
    for j in o.joints.iter().flatten() {
        let names = spans.joints.keys().chain(spans.curves.keys());
        known(cx, j, "outputs.joints: unknown joint or curve", names)?;
        outputs.joints.push(j.get_ref().clone());
    }
    for b in o.bodies.iter().flatten() {
        let bs = r.body(b, "outputs.bodies")?;
        if bs == GROUND {
            return Err(cx.err(b.span(), "outputs.bodies: the ground does not move"));
        }
        outputs.bodies.push(bs.to_string());
    }
    if let Some(list) = &o.reactions {
        let mut v = Vec::new();
        for j in list {
            let names = spans.joints.keys().chain(spans.couplers.keys());
            known(cx, j, "outputs.reactions: unknown joint or coupler", names)?;
            v.push(j.get_ref().clone());
        }
        outputs.reactions = Some(v);
    }
    outputs.energy = o.energy.unwrap_or(true);
    Ok(outputs)
}

/// A `"body.point"` of `[analysis.outputs] key`: the body and the point, which exist.
fn body_point(r: &Resolver, p: &Name, key: &str) -> Result<(String, String), Error> {
    let Some((b, pt)) = p.get_ref().split_once('.') else {
        return Err(r.cx.err(
            p.span(),
            format!(
                "{key}: \"{}\" must be written \"body.point\" (e.g. \"crank.B\")",
                p.get_ref()
            ),
        ));
    };
    let bname = Spanned::new(p.span(), b.to_string());
    let b = r.body(&bname, key)?;
    r.feature(b, &Spanned::new(p.span(), pt.to_string()), key, true)?;
    Ok((b.to_string(), pt.to_string()))
}

/// Refuses `name` when it is not one of `names` ("{what} \"x\"; did you mean …").
fn known<'a>(
    cx: &Ctx,
    name: &Name,
    what: &str,
    names: impl Iterator<Item = &'a String> + Clone,
) -> Result<(), Error> {
    if names.clone().any(|n| n == name.get_ref()) {
        return Ok(());
    }
    let hint = did_you_mean(name.get_ref(), names.map(String::as_str));
    Err(cx.err(name.span(), format!("{what} \"{}\"{hint}", name.get_ref())))
}

/// The integrator of a `kind = "dynamic"` analysis (the section at `table`). Which keys it
/// takes comes from [`INTEGRATORS`]; the values are only read here; their ranges are the
/// library's ([`Integrator::validate`]), and a refusal is placed at the key.
fn load_integrator(cx: &Ctx, a: &AnalysisSection, table: usize) -> Result<Integrator, Error> {
    let selected = a
        .integrator
        .clone()
        .unwrap_or_else(|| Spanned::new(a.kind.span(), "dopri5".to_string()));
    let entry = crate::vocabulary::check(
        cx.src,
        &INTEGRATORS,
        "",
        &selected,
        (cx.keys, table),
        |k| !INTEGRATORS.taking(k).is_empty(),
        a.kind.span(),
    )?;
    let read = |n: &Option<Num>, key: &str| -> Result<Option<f64>, Error> {
        n.as_ref()
            .map(|n| cx.num(n, key, entry.quantity(key)))
            .transpose()
    };
    let integrator = if entry.name == "dopri5" {
        let mut o = Dopri5Options::default();
        if let Some(h) = &a.dt {
            if a.rtol.is_some() || a.atol.is_some() {
                return Err(cx.err(
                    h.span(),
                    "give dt (fixed steps) or rtol/atol (adaptive steps), not both",
                ));
            }
            o = Dopri5Options::fixed(read(&a.dt, "dt")?.unwrap_or_default());
        }
        o.rtol = read(&a.rtol, "rtol")?.unwrap_or(o.rtol);
        o.atol = read(&a.atol, "atol")?.unwrap_or(o.atol);
        o.h_max = read(&a.h_max, "h_max")?.unwrap_or(o.h_max);
        Integrator::Dopri5(o)
    } else {
        let mut o = GeneralizedAlphaOptions::default();
        o.dt = read(&a.dt, "dt")?.unwrap_or(o.dt);
        o.rho_inf = read(&a.rho_inf, "rho_inf")?.unwrap_or(o.rho_inf);
        o.newton_tolerance =
            read(&a.newton_tolerance, "newton_tolerance")?.unwrap_or(o.newton_tolerance);
        Integrator::GeneralizedAlpha(o)
    };
    integrator.validate().map_err(|e| {
        // The options are named as the file's keys: the error is placed at the key's value.
        let value = match e.option {
            "dt" => &a.dt,
            "newton_tolerance" => &a.newton_tolerance,
            "rtol" => &a.rtol,
            "atol" => &a.atol,
            "h_max" => &a.h_max,
            "rho_inf" => &a.rho_inf,
            _ => &None,
        };
        let span = value.as_ref().map_or(a.kind.span(), |n| n.span());
        cx.err(span, e.describe(e.option))
    })?;
    Ok(integrator)
}

/// `inputs = [...]` (modal, dynamic with linearize_at): drivers (modal) and point_force and torque elements of the file.
pub(super) fn load_inputs(
    cx: &Ctx,
    a: &AnalysisSection,
    an: &Analysis,
    forces: &[Force],
    drivers: &[(String, String)],
) -> Result<Vec<String>, Error> {
    let Some(list_) = &a.inputs else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for n in list_ {
        if an.statics() != Some(StaticKind::Modal) && an.linearize_at.is_none() {
            return Err(cx.err(
                n.span(),
                "inputs applies only to kind = \"modal\" and to kind = \"dynamic\" with \
                 linearize_at (the inputs of the state-space model)",
            ));
        }
        let force = forces.iter().any(|f| {
            f.name() == n.get_ref().as_str()
                && matches!(f, Force::PointForce { .. } | Force::PointTorque { .. })
        });
        let driver = drivers.iter().any(|(d, _)| d == n.get_ref());
        if driver && an.statics() != Some(StaticKind::Modal) {
            return Err(cx.err(
                n.span(),
                format!(
                    "inputs: driver \"{}\": driver efforts are inputs of kind = \"modal\" only \
                     (about a moving state the driver prescribes the motion)",
                    n.get_ref()
                ),
            ));
        }
        if !force && !driver {
            return Err(cx.err(
                n.span(),
                format!(
                    "inputs: \"{}\" is not a [[force]] of type point_force or torque, nor a \
                     one-coordinate [[driver]]",
                    n.get_ref()
                ),
            ));
        }
        out.push(n.get_ref().clone());
    }
    Ok(out)
}
