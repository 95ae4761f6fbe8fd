//! A dynamic run's end stops as outputs: the `stops` group (per output time, each stop held
//! closed or not and its force along the joint coordinate: the active set and the stops'
//! reactions) and `events.csv` (each impact and release: time, stop, rates before and after,
//! impulse, kinetic energy taken). Nothing for a model without limits.

use crate::prepare::Prepared;
use crate::table::{csv_field, Table};
use crate::units::{coordinate_units, CoordinateUnits, UnitSystem};
use cardan_dynamics::{ImpactEvent, StopHistory};

/// The SI units along stop `stop`'s coordinate.
fn units(p: &Prepared, stop: usize) -> CoordinateUnits {
    coordinate_units(p.model.stops()[stop].row.measure.quantity())
}

/// The `stops` group: for each stop, `<limit>.<end> held [-]` (1 while held closed) and
/// `<limit>.<end> force [N or N m]` (along the coordinate; ≥ 0 at a lower stop while it pushes).
pub(super) fn stops_table(p: &Prepared, history: &StopHistory) -> Option<Table> {
    let stops = p.model.stops();
    if stops.is_empty() || history.times.is_empty() {
        return None;
    }
    let mut columns = Vec::with_capacity(2 * stops.len());
    for (s, stop) in stops.iter().enumerate() {
        columns.push(format!("{} held [-]", stop.name));
        columns.push(format!("{} force [{}]", stop.name, units(p, s).force));
    }
    let mut t = Table::new("stops", "end stops: held closed, force", columns);
    for (k, &time) in history.times.iter().enumerate() {
        let mut row = Vec::with_capacity(1 + 2 * stops.len());
        row.push(time);
        for s in 0..stops.len() {
            row.push(if history.held[k][s] { 1.0 } else { 0.0 });
            row.push(history.force[k][s]);
        }
        t.rows.push(row);
    }
    Some(t)
}

/// The run's impacts, releases and the stops held at its last output (`None` without limits).
pub(super) fn counts(
    p: &Prepared,
    events: &[ImpactEvent],
    history: &StopHistory,
) -> Option<crate::run_json::StopCounts> {
    if p.model.stops().is_empty() {
        return None;
    }
    let impacts = events.iter().filter(|e| !e.release);
    Some(crate::run_json::StopCounts {
        impacts: impacts.clone().count(),
        held_impacts: impacts.filter(|e| e.held).count(),
        releases: events.iter().filter(|e| e.release).count(),
        held_at_end: history
            .held
            .last()
            .map_or(0, |h| h.iter().filter(|&&x| x).count()),
    })
}

/// `events.csv`: one row per impact or release, in time order, in the model's units.
pub(super) fn events_csv(p: &Prepared, events: &[ImpactEvent]) -> Option<(String, String)> {
    if p.model.stops().is_empty() {
        return None;
    }
    let (energy_unit, energy_factor) = p.units.unit("J");
    let mut s = format!(
        "t [s],stop,joint,event,impact rate,rebound rate,rate unit,impulse,impulse unit,\
         energy change [{energy_unit}]\n"
    );
    for e in events {
        let stop = p
            .model
            .stops()
            .iter()
            .position(|st| st.name == e.stop)
            .unwrap_or(0);
        let u = units(p, stop);
        let (rate_unit, rate_factor) = p.units.unit(u.rate);
        let (impulse_unit, impulse_factor) = impulse_in(p.units, u.impulse);
        let joint = &p.model.joints()[p.model.limits()[e.limit].joint].name;
        let event = match (e.release, e.held) {
            (true, _) => "release",
            (false, true) => "impact_held",
            (false, false) => "impact",
        };
        let mut b = ryu::Buffer::new();
        let mut num = |v: f64| b.format(v).to_string();
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            num(e.time),
            csv_field(&e.stop),
            csv_field(joint),
            csv_field(event),
            num(e.impact_velocity * rate_factor),
            num(e.rebound_velocity * rate_factor),
            rate_unit,
            num(e.impulse * impulse_factor),
            impulse_unit,
            num(e.energy_change * energy_factor),
        ));
    }
    Some(("events.csv".into(), s))
}

/// An impulse's unit in the model's units: N s stays, N m s becomes N mm s in mm.
fn impulse_in(units: UnitSystem, si: &str) -> (String, f64) {
    match (units, si) {
        (UnitSystem::Mm, "N m s") => ("N mm s".into(), 1e3),
        _ => (si.into(), 1.0),
    }
}
