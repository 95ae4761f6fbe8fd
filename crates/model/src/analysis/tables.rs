//! The output groups of a run held whole, as tables: a kinematic run's ([`kinematic_tables`],
//! from the [`Layout`] of its groups), a dynamic run's ([`dynamic_tables`]: with driver and
//! coupler efforts, reactions, energy and constraint drift) and an inverse dynamics run's
//! ([`inverse_tables`], which the static kinds write without the motion groups). A streamed
//! run's layout ([`super::dynamic_layout`]) takes its groups' names, headers and order from
//! these, so a streamed file and a table held whole have the same text.

use super::layout::Layout;
use super::stream::FrameLayout;
use crate::build::Outputs as Requested;
use crate::output_tables::{
    cam_forces_table, coupler_efforts_table, driver_efforts_table, energy_table, reaction_tables,
};
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::DynamicResults;
use cardan_mechanism::Results;

/// Builds the output groups from the results (every frame; `Layout`).
pub fn kinematic_tables(r: &Results, req: &Requested) -> Vec<Table> {
    Layout::new(r, req).into_tables(r)
}

/// The output groups of a dynamic run: the kinematic groups, then driver efforts (when the
/// model has drivers), reactions (global and body components), energy and constraint drift.
pub fn dynamic_tables(p: &Prepared, r: &DynamicResults, req: &Requested) -> Vec<Table> {
    let mut out = kinematic_tables(&r.kinematics, req);
    // The kinematic "residual" group is replaced by the drift group below.
    out.retain(|t| t.name != "residual");
    out.extend(driver_efforts_table(p, r));
    out.extend(coupler_efforts_table(p, r));
    out.extend(cam_forces_table(r));
    out.extend(reaction_tables(r, req));
    let times = r.times();
    let n = times.len();
    if req.energy {
        out.push(energy_table(r));
    }
    let mut t = Table::new(
        "constraint_drift",
        "constraint drift",
        vec![
            "max |Φ| [m or -]".into(),
            "max |Φ_v v − ν| [m/s or 1/s]".into(),
        ],
    );
    for k in 0..n {
        t.rows.push(vec![
            times[k],
            r.position_drift.get(k).copied().unwrap_or(f64::NAN),
            r.velocity_drift.get(k).copied().unwrap_or(f64::NAN),
        ]);
    }
    out.push(t);
    out
}

/// The output groups of an inverse dynamics run: the kinematic groups (with the residual of the
/// position analysis), then driver efforts, reactions (global and body components) and energy
/// (with the drivers' power and work along the prescribed motion, the work by the trapezoidal
/// rule on the time grid).
pub fn inverse_tables(p: &Prepared, r: &DynamicResults, req: &Requested) -> Vec<Table> {
    let mut out = kinematic_tables(&r.kinematics, req);
    out.extend(driver_efforts_table(p, r));
    out.extend(coupler_efforts_table(p, r));
    out.extend(cam_forces_table(r));
    out.extend(reaction_tables(r, req));
    if req.energy {
        out.push(energy_table(r));
    }
    out.extend(super::joint_space::joint_space_tables(p, r));
    out
}
