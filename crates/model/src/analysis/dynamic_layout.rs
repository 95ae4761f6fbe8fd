//! The output groups of a dynamic or inverse dynamics run as a layout over its frames
//! ([`DynamicResults`] holding one time, streamed by [`super::stream::Recorder`]): the kinematic
//! groups (`Layout`), then driver efforts, coupler efforts, cam forces, reactions, energy and (dynamic
//! runs) constraint drift. Each group's header is the header of the table written whole
//! (`tables`) and each row comes from the same row functions, so a streamed file and a table
//! held whole have the same text.
//!
//! The summary's numbers are a [`DynamicTally`] over every frame (`tally`).

use super::layout::Layout;
use super::stream::FrameLayout;
use super::tables::{dynamic_tables, inverse_tables};
use crate::build::Outputs as Requested;
use crate::output_tables::{
    cam_forces_row, coupler_efforts_row, driver_efforts_row, energy_row, reaction_selection,
    reactions_row, ReactionRef,
};
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::DynamicResults;

/// The summary's numbers of these frames (declared below the analyses that read them).
pub use super::tally::{CamPull, DynamicTally};

/// Which analysis wrote the frames: their groups differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Forward dynamics: the constraint drift replaces the kinematic residual group.
    Dynamic,
    /// Inverse dynamics: the kinematic residual group, no drift group.
    Inverse,
}

/// One output group: where its row comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Group {
    /// The kinematic group g of [`Layout`].
    Kinematic(usize),
    DriverEfforts,
    CouplerEfforts,
    CamForces,
    Reactions {
        local: bool,
    },
    Energy,
    ConstraintDrift,
    /// The joint space's group g ([`super::joint_space::joint_space_row`]).
    JointSpace(usize),
}

/// The groups of a dynamic or inverse dynamics run (module docs).
pub struct DynamicLayout {
    kinematic: Layout,
    groups: Vec<Group>,
    /// The tables without rows.
    empty: Vec<Table>,
    selected: Vec<ReactionRef>,
    /// The total energy at the run's first frame (the energy table's drift and balance).
    e0: f64,
}

impl DynamicLayout {
    /// The layout of a run whose first frame is `first`, writing the groups `req` asks for.
    pub fn new(p: &Prepared, first: &DynamicResults, req: &Requested, kind: Kind) -> Self {
        // The whole-run tables of the first frame: their names, headers and order.
        let mut empty = match kind {
            Kind::Dynamic => dynamic_tables(p, first, req),
            Kind::Inverse => inverse_tables(p, first, req),
        };
        let kinematic = Layout::new(&first.kinematics, req);
        let names: Vec<String> = (0..kinematic.groups())
            .map(|g| kinematic.empty_table(g).name.clone())
            .collect();
        let groups = empty
            .iter_mut()
            .map(|t| {
                t.rows.clear();
                match t.name.as_str() {
                    "driver_efforts" => Group::DriverEfforts,
                    "coupler_efforts" => Group::CouplerEfforts,
                    "cam_forces" => Group::CamForces,
                    "reactions" => Group::Reactions { local: false },
                    "reactions_local" => Group::Reactions { local: true },
                    "energy" => Group::Energy,
                    "constraint_drift" => Group::ConstraintDrift,
                    "mass_matrix" => Group::JointSpace(0),
                    "bias_forces" => Group::JointSpace(1),
                    "jacobians" => Group::JointSpace(2),
                    name => Group::Kinematic(names.iter().position(|n| n == name).unwrap_or(0)),
                }
            })
            .collect();
        Self {
            kinematic,
            groups,
            empty,
            selected: reaction_selection(first, req),
            e0: first.energy.total.first().copied().unwrap_or(0.0),
        }
    }
}

impl FrameLayout for DynamicLayout {
    type Frame = DynamicResults;
    type Tally = DynamicTally;

    fn groups(&self) -> usize {
        self.empty.len()
    }

    fn empty_table(&self, g: usize) -> &Table {
        &self.empty[g]
    }

    fn into_empty_tables(self) -> Vec<Table> {
        self.empty
    }

    fn row(&self, g: usize, r: &DynamicResults, k: usize, row: &mut Vec<f64>) {
        if let Group::Kinematic(i) = self.groups[g] {
            return self.kinematic.row(i, &r.kinematics, k, row);
        }
        row.clear();
        row.push(r.times()[k]);
        match self.groups[g] {
            Group::Kinematic(_) => {}
            Group::DriverEfforts => driver_efforts_row(r, k, row),
            Group::CouplerEfforts => coupler_efforts_row(r, k, row),
            Group::CamForces => cam_forces_row(r, k, row),
            Group::Reactions { local } => reactions_row(r, &self.selected, local, k, row),
            Group::Energy => energy_row(&r.energy, self.e0, k, row),
            Group::JointSpace(j) => super::joint_space::joint_space_row(r, j, k, row),
            Group::ConstraintDrift => row.extend([
                r.position_drift.get(k).copied().unwrap_or(f64::NAN),
                r.velocity_drift.get(k).copied().unwrap_or(f64::NAN),
            ]),
        }
    }

    fn tally(tally: &mut DynamicTally, frame: &DynamicResults) {
        tally.take(frame);
    }
}
