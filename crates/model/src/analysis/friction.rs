//! A dynamic or inverse dynamics run's joint friction as an output: the `friction` group, per
//! `[[friction]]` element and output time, its force (a slide: prismatic and cylindrical
//! joints) or torque (a pin; a ball joint's magnitude) opposing the motion, and the power it
//! takes (≤ 0; its work is the element's channel in `energy.csv`). Nothing for a model without
//! friction.

use crate::prepare::Prepared;
use crate::table::Table;
use cardan_constraints::JointKind;
use cardan_dynamics::FrictionHistory;

/// The `friction` group: `<name> force [N]` or `<name> torque [N m]`, then `<name> power [W]`,
/// per element.
pub(super) fn friction_table(p: &Prepared, history: &FrictionHistory) -> Option<Table> {
    let frictions = p.model.frictions();
    if frictions.is_empty() || history.times.is_empty() {
        return None;
    }
    let mut columns = Vec::with_capacity(2 * frictions.len());
    for f in frictions {
        let kind = p.model.joints()[f.joint].joint.kind();
        let along = match kind {
            JointKind::Prismatic | JointKind::Cylindrical => "force [N]",
            _ => "torque [N m]",
        };
        columns.push(format!("{} {along}", f.name));
        columns.push(format!("{} power [W]", f.name));
    }
    let mut t = Table::new(
        "friction",
        "joint friction: force or torque, power",
        columns,
    );
    for (k, &time) in history.times.iter().enumerate() {
        let mut row = Vec::with_capacity(1 + 2 * frictions.len());
        row.push(time);
        for e in 0..frictions.len() {
            row.push(history.value[k][e]);
            row.push(history.power[k][e]);
        }
        t.rows.push(row);
    }
    Some(t)
}
