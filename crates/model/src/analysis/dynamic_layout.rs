//! The output groups of a dynamic or inverse dynamics run as a layout over its frames
//! ([`DynamicResults`] holding one time, streamed by [`super::stream::Recorder`]): the kinematic
//! groups (`Layout`), then driver efforts, coupler efforts, reactions, energy and (dynamic
//! runs) constraint drift. Each group's header is the header of the table written whole
//! ([`super::dynamic::tables`], [`super::inverse::inverse_tables`]) and each row comes from the
//! same row functions, so a streamed file and a table held whole have the same text.
//!
//! The summary's numbers are a [`DynamicTally`] over every frame.

use super::layout::Layout;
use super::stream::FrameLayout;
use crate::build::Outputs as Requested;
use crate::output_tables::{
    coupler_efforts_row, driver_efforts_row, energy_row, fold_peak_efforts, reaction_selection,
    reactions_row, ReactionRef,
};
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::DynamicResults;

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
    Reactions {
        local: bool,
    },
    Energy,
    ConstraintDrift,
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
            Kind::Dynamic => super::dynamic::tables(p, first, req),
            Kind::Inverse => super::inverse::inverse_tables(p, first, req),
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
                    "reactions" => Group::Reactions { local: false },
                    "reactions_local" => Group::Reactions { local: true },
                    "energy" => Group::Energy,
                    "constraint_drift" => Group::ConstraintDrift,
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
            Group::Reactions { local } => reactions_row(r, &self.selected, local, k, row),
            Group::Energy => energy_row(&r.energy, self.e0, k, row),
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

/// The numbers a dynamic or inverse dynamics run's summary and warnings take over every
/// frame, as running maxima (the same folds as over the whole histories, so the same numbers).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DynamicTally {
    /// Times taken.
    pub frames: usize,
    /// Newton iterations of the kinematics (inverse dynamics).
    pub iterations: usize,
    /// The largest max |Φ| (the constraint drift of a dynamic run, the residual of an inverse
    /// one).
    pub max_drift: f64,
    /// The total energy at the first time, E(t₀).
    pub e0: f64,
    /// max |E − E(t₀)|.
    pub max_energy_drift: f64,
    /// max |E − E(t₀) − W_nc|.
    pub max_balance: f64,
    /// The largest kinetic energy.
    pub max_kinetic: f64,
    /// The least and the largest potential energy (gravity and springs).
    pub potential: (f64, f64),
    /// Per work channel, the largest |W|.
    pub max_work: Vec<f64>,
    /// Per driver, the largest |effort|.
    pub peak_efforts: Vec<f64>,
}

impl DynamicTally {
    /// The tally over every time of `r`.
    pub fn of(r: &DynamicResults) -> Self {
        let mut t = Self::default();
        t.take(r);
        t
    }

    /// Takes the times of `r` (the first ever taken sets E(t₀) and the per-element storage).
    pub fn take(&mut self, r: &DynamicResults) {
        let e = &r.energy;
        if self.frames == 0 {
            self.e0 = e.total.first().copied().unwrap_or(0.0);
            self.potential = (f64::INFINITY, f64::NEG_INFINITY);
            self.max_work = vec![0.0; e.elements.len()];
            self.peak_efforts = vec![0.0; r.drivers.len()];
        }
        self.frames += r.len();
        self.iterations += r.kinematics.iterations.iter().sum::<usize>();
        self.max_drift = (r.position_drift.iter()).fold(self.max_drift, |a, &b| a.max(b));
        let e0 = self.e0;
        for &t in &e.total {
            self.max_energy_drift = self.max_energy_drift.max((t - e0).abs());
        }
        for (&t, &w) in e.total.iter().zip(&e.work) {
            self.max_balance = self.max_balance.max((t - e0 - w).abs());
        }
        self.max_kinetic = e.kinetic.iter().fold(self.max_kinetic, |a, &t| a.max(t));
        for (g, s) in e.gravity.iter().zip(&e.spring) {
            let v = g + s;
            self.potential = (self.potential.0.min(v), self.potential.1.max(v));
        }
        for (m, w) in self.max_work.iter_mut().zip(&e.elements) {
            *m = w.work.iter().fold(*m, |a, x| a.max(x.abs()));
        }
        fold_peak_efforts(r, &mut self.peak_efforts);
    }

    /// The energy scale ([`super::dynamic::energy_scale`]) over the times taken.
    pub fn energy_scale(&self) -> f64 {
        let (lo, hi) = self.potential;
        let range = if hi >= lo { hi - lo } else { 0.0 };
        self.max_kinetic + range + self.max_work.iter().sum::<f64>()
    }

    /// The energy balance of the summary.
    pub fn energy_balance(&self) -> super::summary::EnergyBalance {
        super::summary::EnergyBalance {
            max_abs: self.max_balance,
            scale: self.energy_scale(),
        }
    }
}
