//! What the analyses of `cardan run` hand to [`super::analyse_into`]: an [`Analysed`] run
//! (its output groups, its [`Summary`], its results) under the [`RunFlags`] it was asked to run
//! with. These types sit below the analyses so that they and [`super`] share them without using
//! each other; [`super`] exports the public ones.

use super::energy::EnergyBalance;
use crate::diag::Error;
use crate::table::Table;
use cardan_mechanism::Results;
use std::path::PathBuf;
use std::time::Duration;

/// What a run did.
#[derive(Debug, Clone)]
pub struct Summary {
    /// The model name.
    pub name: String,
    /// Stored time steps (static kinds: equilibria).
    pub steps: usize,
    /// What `steps` counts in the summary line, singular and plural: `["step", "steps"]`, or
    /// `["equilibrium", "equilibria"]` for the static kinds.
    pub noun: [&'static str; 2],
    /// Total Newton iterations.
    pub iterations: usize,
    /// Largest max |Φ_i| over the run.
    pub max_residual: f64,
    /// Wall time of the analysis (not the writing).
    pub wall: Duration,
    /// Output directory.
    pub dir: PathBuf,
    /// Files written (`run.json` last).
    pub files: Vec<PathBuf>,
    /// Dynamic runs: integration counters and drifts.
    pub dynamic: Option<DynamicSummary>,
    /// Dynamic and inverse dynamics runs: the energy balance E − E(t₀) − W_nc.
    pub energy_balance: Option<EnergyBalance>,
    /// Dynamic and inverse dynamics runs: per driver, its name, the largest |effort| over the
    /// run and the unit ("N m" or "N").
    pub peak_efforts: Vec<(String, f64, &'static str)>,
    /// Doubtful results and other remarks, one sentence each: printed after the summary line
    /// and written to `run.json`. Any check may push to it.
    pub warnings: Vec<String>,
    /// Kinematic and inverse dynamics runs: grid steps solved in substeps to stay on the
    /// assembly branch (`Results::subdivided_steps`; not a warning); `None` for dynamic runs.
    pub subdivided_steps: Option<usize>,
    /// Times the independent equations of a model with redundant equations were chosen again
    /// because the kept ones lost rank (a note, not a warning).
    pub row_reselections: usize,
}

/// What a dynamic run adds to the summary line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicSummary {
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Newton iterations (implicit steps and projections).
    pub newton_iterations: usize,
    /// Largest max |Φ| over the stored times.
    pub max_constraint_drift: f64,
    /// max |E − E(t0)| (J).
    pub energy_drift: f64,
    /// A model with limits: its end stops' impacts and releases.
    pub stops: Option<crate::run_json::StopCounts>,
}

/// How `cardan run` was asked to run.
#[derive(Debug, Clone, Default)]
pub struct RunFlags {
    /// The progress bar to draw (the command's terminal bar; `None`: none).
    pub progress: Option<crate::progress::MakeBar>,
    /// `--strict`: warnings make the run fail with exit code 3 (the results are still written).
    pub strict: bool,
    /// `--allow-long`: run a dynamic analysis beyond [`super::dynamic::MAX_STEPS`] estimated
    /// steps.
    pub allow_long: bool,
    /// `--png`: write a PNG beside each SVG plot.
    pub png: bool,
    /// `--units`, `--analysis`: how an ASMT file is read.
    pub asmt: crate::asmt::AsmtOptions,
    /// `--outputs`: which files a run writes besides `run.json`.
    pub outputs: OutputSet,
}

/// The files `cardan run` writes besides `run.json` (`--outputs`; all by default).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputSet {
    /// The tables as CSV files.
    pub csv: bool,
    /// Their plots (SVG, and PNG with `--png`).
    pub plots: bool,
    /// `animation.glb` and `index.html`.
    pub report: bool,
    /// An ASMT model's `<name>.solved.asmt`.
    pub asmt: bool,
}

impl Default for OutputSet {
    fn default() -> Self {
        Self::ALL
    }
}

impl OutputSet {
    /// Every output.
    pub const ALL: OutputSet = OutputSet {
        csv: true,
        plots: true,
        report: true,
        asmt: true,
    };

    /// Nothing but `run.json`.
    pub const NONE: OutputSet = OutputSet {
        csv: false,
        plots: false,
        report: false,
        asmt: false,
    };
}

/// An analysis that has run, before anything is written.
pub struct Analysed {
    /// The output groups.
    pub tables: Vec<Table>,
    /// The summary (files and directory are filled in when written).
    pub summary: Summary,
    /// The results (the kinematic part for dynamic runs).
    pub results: Results,
    /// Dynamic and inverse dynamics runs: everything they computed.
    pub dynamic: Option<cardan_dynamics::DynamicResults>,
    /// The failure that stopped the run early; `None` when it reached `t_end`.
    pub failure: Option<Error>,
    /// `--strict` with warnings: the error to return after writing (the run is complete).
    pub strict_failure: Option<Error>,
    /// Files other than the tables, (name, contents): the modal run's matrices.
    pub files: Vec<(String, String)>,
    /// A modal run's modes (the report animates them); empty for the other kinds.
    pub modes: Vec<cardan_dynamics::Mode>,
    /// A dynamic run's impacts and releases of its end stops (`events.csv`; the report marks
    /// them); empty for the other kinds.
    pub events: Vec<cardan_dynamics::ImpactEvent>,
    /// A streamed run (`cardan run` of a kinematic, dynamic or inverse dynamics analysis): the
    /// CSV files already written
    /// frame by frame, and how `results` and `tables` were decimated. `None`: `results` and
    /// `tables` hold every frame and nothing was written yet.
    pub streamed: Option<super::stream::Streamed>,
}
