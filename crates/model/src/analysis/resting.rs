//! Static equilibria resting on end stops (`[[limit]]`): which stops an equilibrium leans on
//! is found by an active-set iteration (Haug 1989 §11.6 for the active-set view of unilateral
//! constraints). Starting with every stop open, the equilibrium is solved; each stop the
//! equilibrium passes is held at its bound ([`cardan_mechanism::MechanismBuilder::holding_stop`]:
//! a constant driver named `<limit>.<lower|upper>`, whose effort is the stop's reaction), each
//! held stop whose reaction pulls (negative along the coordinate at a lower stop, positive at
//! an upper one) is released, and the equilibrium solved again until the set no longer changes.
//! The held stops then act as joints: a modal analysis linearizes about the equilibrium with
//! them bilateral, and their reactions are columns of `driver_efforts.csv`.

use crate::diag::Error;
use crate::prepare::Prepared;
use cardan_constraints::joints::CoordinateQuantity;
use cardan_constraints::{BodyState, Bound, TimeFunction};
use cardan_dynamics::{StaticOptions, StaticResults};
use cardan_mechanism::Quantity;

/// How far (rad, or relative to the model's length) an equilibrium may pass a bound before the
/// stop is held.
const PASS_TOLERANCE: f64 = 1e-9;

/// The model of `p` with the stops an equilibrium rests on held, and their names; `None` when it
/// rests on none (or the model has no limits). `solve` solves an equilibrium of a prepared
/// model (at `options.time`: for a quasi-static analysis, the first time of each segment of
/// its path, [`super::quasi_stops`]).
///
/// # Errors
/// The equilibrium's errors; an active set that does not settle.
pub(super) fn resting(
    p: &Prepared,
    options: &StaticOptions,
    solve: impl Fn(&Prepared, &StaticOptions) -> Result<StaticResults, Error>,
) -> Result<Option<Prepared>, Error> {
    let stops = p.model.stops();
    if stops.is_empty() {
        return Ok(None);
    }
    let mut held: Vec<usize> = Vec::new();
    let mut built: Option<Prepared> = None;
    for _ in 0..=2 * stops.len() {
        let q = built.as_ref().unwrap_or(p);
        let r = match solve(q, options) {
            Ok(r) => r,
            // No equilibrium with every stop open (a load the mechanism cannot carry without a
            // stop): start from a stop that carries it.
            Err(e) if held.is_empty() => match carrying_stop(p, options, &solve) {
                Some((s, q1)) => {
                    (held, built) = (vec![s], Some(q1));
                    continue;
                }
                None => return Err(e),
            },
            Err(e) => return Err(e),
        };
        let gaps = gaps(q, &r);
        let mut next: Vec<usize> = held.iter().copied().filter(|&s| !pulls(q, &r, s)).collect();
        next.extend((0..stops.len()).filter(|s| !held.contains(s) && gaps[*s] < -scale(q, *s)));
        next.sort_unstable();
        if next == held {
            return Ok(built);
        }
        held = next;
        built = if held.is_empty() {
            None
        } else {
            Some(holding(p, &held)?)
        };
    }
    Err(p.source.error_at(
        p.loaded.spans.analysis.clone(),
        "static analysis: the stops the equilibrium rests on did not settle (each set tried \
         passed another stop or pulled on a held one); check the limits' bounds and the loads"
            .to_string(),
    ))
}

/// The first stop that, held alone, gives an equilibrium it pushes on (not pulls), with the
/// model holding it; `None` when none does.
fn carrying_stop(
    p: &Prepared,
    options: &StaticOptions,
    solve: &impl Fn(&Prepared, &StaticOptions) -> Result<StaticResults, Error>,
) -> Option<(usize, Prepared)> {
    (0..p.model.stops().len()).find_map(|s| {
        let q = holding(p, &[s]).ok()?;
        let r = solve(&q, options).ok()?;
        (!pulls(&q, &r, s)).then_some((s, q))
    })
}

/// The tolerance of stop `s`'s gap: rad for an angle, relative to the model's length else.
fn scale(p: &Prepared, s: usize) -> f64 {
    PASS_TOLERANCE * p.model.stop_scale(s)
}

/// Each stop's gap g (≥ 0 inside the range) at the last equilibrium of `r`.
fn gaps(p: &Prepared, r: &StaticResults) -> Vec<f64> {
    let last = r.results.kinematics.times.len().saturating_sub(1);
    gaps_at(p, &r.results, last)
}

/// Each stop's gap g at output `k` of `r`.
fn gaps_at(p: &Prepared, r: &cardan_dynamics::DynamicResults, k: usize) -> Vec<f64> {
    let kin = &r.kinematics;
    let bodies: Vec<BodyState> = p
        .model
        .bodies()
        .iter()
        .map(|b| {
            let h = kin.body(&b.name).expect("every body has results");
            BodyState::at(h.r[k], h.p[k])
        })
        .collect();
    let turns = p.model.initial_turns();
    (0..p.model.stops().len())
        .map(|s| p.model.stop_gap(s, &bodies, &turns))
        .collect()
}

/// Where a quasi-static path stops resting on the stops held at its first time (`p`'s model,
/// from [`resting`]): the index of the first equilibrium of `r` that passes an open stop or
/// whose held stop would pull, and what happens there. `None` when the set holds along the
/// whole path.
pub(super) fn set_change(
    p: &Prepared,
    r: &cardan_dynamics::DynamicResults,
) -> Option<(usize, String)> {
    let stops = p.model.stops();
    if stops.is_empty() {
        return None;
    }
    let held = |s: usize| (p.model.drivers().iter()).position(|d| d.name == stops[s].name);
    // Per stop: its holding driver's efforts and their largest |value| (held stops only).
    let efforts: Vec<Option<(&[f64], f64)>> = (0..stops.len())
        .map(|s| {
            let e = r.drivers.get(held(s)?)?;
            Some((
                &e.effort[..],
                e.effort.iter().fold(0.0f64, |a, f| a.max(f.abs())),
            ))
        })
        .collect();
    for k in 0..r.kinematics.times.len() {
        let gaps = gaps_at(p, r, k);
        for (s, stop) in stops.iter().enumerate() {
            let what = match efforts[s] {
                Some((effort, peak)) => match effort.get(k) {
                    Some(&f) if pulls_with(f * stop.row.bound.sign(), peak) => {
                        format!("stop {} would pull (its reaction is {f:.4e})", stop.name)
                    }
                    _ => continue,
                },
                None if gaps[s] < -scale(p, s) => {
                    format!(
                        "the equilibrium passes stop {} by {:.4e}",
                        stop.name, -gaps[s]
                    )
                }
                None => continue,
            };
            return Some((k, what));
        }
    }
    None
}

/// Whether held stop `s` pulls: its holding driver's effort along the coordinate points out of
/// the range.
fn pulls(p: &Prepared, r: &StaticResults, s: usize) -> bool {
    let stop = &p.model.stops()[s];
    let effort = r
        .results
        .driver(&stop.name)
        .and_then(|d| d.effort.last().copied())
        .unwrap_or(0.0);
    pulls_with(effort * stop.row.bound.sign(), effort.abs())
}

/// Whether a held stop's reaction along its pushing direction, `pushing`, is a pull: below
/// −1e-9 of the reaction's scale `size` (at least 1 N or N m), so that roundoff does not
/// release a stop that carries nothing. The one test of [`pulls`], [`set_change`] and
/// [`PullWatch`].
fn pulls_with(pushing: f64, size: f64) -> bool {
    pushing < -1e-9 * size.max(1.0)
}

/// `p` rebuilt with the stops `held` held at their bounds (drivers named after the stops).
fn holding(p: &Prepared, held: &[usize]) -> Result<Prepared, Error> {
    let mut builder = p.loaded.builder.clone();
    let mut loaded = p.loaded.clone();
    for &s in held {
        let stop = &p.model.stops()[s];
        let limit = &p.model.limits()[stop.limit];
        let bound = stop.row.bound;
        builder = builder
            .holding_stop(&limit.name, bound)
            .map_err(|e| p.source.error(format!("holding stop {}: {e}", stop.name)))?;
        let value = match bound {
            Bound::Lower => limit.lower,
            Bound::Upper => limit.upper,
        }
        .unwrap_or(0.0);
        let quantity = match limit.measure.quantity() {
            CoordinateQuantity::Angle => Quantity::Angle,
            CoordinateQuantity::Length => Quantity::Length,
        };
        loaded.drivers.push((
            stop.name.clone(),
            format!("the {} stop of limit {}", bound.name(), limit.name),
        ));
        loaded
            .driver_functions
            .push((TimeFunction::Constant(value), quantity));
    }
    let model = builder.build().map_err(|e| {
        p.source
            .error(format!("holding the stops the model rests on: {e}"))
    })?;
    loaded.builder = builder;
    Ok(Prepared {
        file: p.file.clone(),
        source: p.source.clone(),
        loaded,
        model,
        warnings: p.warnings.clone(),
        units: p.units,
        geometry: p.geometry.clone(),
    })
}

/// How far (rad, or relative to the model's length) the pose at the start of an inverse
/// dynamics run may be from a bound and still rest on it.
const ON_BOUND: f64 = 1e-6;

/// The model of `p` for an inverse dynamics run whose drivers leave k degrees of freedom and
/// whose pose at `t_start` lies on k stops: those stops held at their bounds (the prescribed
/// motion rests on them; their holding drivers' efforts, `<limit>.<lower|upper>` in
/// `driver_efforts.csv`, are the stops' reactions). `None` when the model has no limits, when
/// the drivers leave no degree of freedom, or when the pose lies on another number of stops
/// than the degrees of freedom left (the run then says what is missing).
///
/// # Errors
/// Holding the stops (a stop whose coordinate the model cannot hold).
pub(crate) fn resting_motion(p: &Prepared, t_start: f64) -> Result<Option<Prepared>, Error> {
    if p.model.stops().is_empty() || p.model.drivers().is_empty() {
        return Ok(None);
    }
    let mut ws = p.model.workspace();
    let assembled = p
        .model
        .assemble(&mut ws, &cardan_mechanism::AssemblyOptions::at(t_start));
    let Ok(dof) = assembled.and_then(|_| p.model.dof(&ws)) else {
        // The run reports its own assembly failure.
        return Ok(None);
    };
    let missing = dof.dof.saturating_sub(dof.drivers);
    let on: Vec<usize> = (p.model.stop_status(&ws).iter().enumerate())
        .filter(|(s, (_, g))| g.abs() <= ON_BOUND * p.model.stop_scale(*s))
        .map(|(s, _)| s)
        .collect();
    if missing == 0 || on.len() != missing {
        return Ok(None);
    }
    // The held stops must drive exactly the missing coordinates: not one a driver already
    // fixes (a motion starting at its own stroke end), nor each other's.
    let held = holding(p, &on)?;
    let mut ws = held.model.workspace();
    let driven = (held.model)
        .assemble(&mut ws, &cardan_mechanism::AssemblyOptions::at(t_start))
        .and_then(|_| held.model.dof(&ws))
        .is_ok_and(|dof| dof.dof == dof.drivers)
        && held.model.prepare_kinematics(&mut ws).is_ok();
    Ok(driven.then_some(held))
}

/// The first output time at which a stop held by [`resting_motion`] pulls (its reaction points
/// out of the range: the prescribed motion leaves the stop there, which inverse dynamics does
/// not follow), watched frame by frame.
#[derive(Debug, Default)]
pub(super) struct PullWatch {
    held: Vec<HeldStop>,
    /// The first pull: stop name, the time interpolated between the last pushing and the first
    /// pulling output, that output's time and reaction.
    first: Option<(String, f64, f64, f64)>,
}

/// A stop held through an inverse dynamics run.
#[derive(Debug)]
struct HeldStop {
    /// Its holding driver's index in the results.
    driver: usize,
    /// The sign of a pushing reaction along the coordinate (+1 at a lower stop).
    sign: f64,
    name: String,
    /// The last output's time and reaction.
    last: Option<(f64, f64)>,
    /// The largest |reaction| so far.
    peak: f64,
}

impl PullWatch {
    /// Watches the stops `p` holds (none for a model that holds none).
    pub(super) fn new(p: &Prepared) -> Self {
        let held = (p.model.stops().iter())
            .filter_map(|st| {
                let driver = p.model.drivers().iter().position(|d| d.name == st.name)?;
                Some(HeldStop {
                    driver,
                    sign: st.row.bound.sign(),
                    name: st.name.clone(),
                    last: None,
                    peak: 0.0,
                })
            })
            .collect();
        Self { held, first: None }
    }

    /// Takes the frames of `r`.
    pub(super) fn take(&mut self, r: &cardan_dynamics::DynamicResults) {
        if self.first.is_some() {
            return;
        }
        for h in &mut self.held {
            let Some(d) = r.drivers.get(h.driver) else {
                continue;
            };
            for (&t, &f) in r.times().iter().zip(&d.effort) {
                h.peak = h.peak.max(f.abs());
                if pulls_with(h.sign * f, h.peak) {
                    let at = match h.last {
                        Some((t0, f0)) if h.sign * f0 >= 0.0 => t0 + (t - t0) * f0 / (f0 - f),
                        _ => t,
                    };
                    self.first = Some((h.name.clone(), at, t, f));
                    return;
                }
                h.last = Some((t, f));
            }
        }
    }

    /// The warning of a stop that pulls.
    pub(super) fn warning(&self, p: &Prepared) -> Option<String> {
        let (name, at, t, f) = self.first.as_ref()?;
        let unit = (p.model.stops().iter().find(|s| &s.name == name)).map_or("N m", |s| {
            crate::units::coordinate_units(s.row.measure.quantity()).force
        });
        Some(format!(
            "the prescribed motion leaves stop {name} at about t = {at:.6} s (its reaction \
             changes sign: {f:.4e} {unit} at t = {t} s pulls): inverse dynamics keeps holding \
             the stop from there, so the efforts after that time are not the mechanism's; a \
             dynamic analysis shows it leave"
        ))
    }
}
