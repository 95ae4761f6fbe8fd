//! `run.json`: what a run did, written beside its tables (docs/model-format.md, "Output of
//! `cardan run`").

use serde::Serialize;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The analysis reached `t_end` (there may still be warnings).
    Complete,
    /// The analysis stopped early (a failure mid-run, Ctrl-C); the tables hold the results up
    /// to `t_reached`.
    Partial,
}

/// The model a run read.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelRef {
    /// The model file as given on the command line.
    pub path: String,
    /// `[model] name`.
    pub name: String,
}

/// The frames a long run's plots, animation and report show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct PlottedFrames {
    /// Frames shown: the first, every `every`-th, and the last.
    pub kept: usize,
    /// Frames the run stored (all in the CSV files).
    pub of: usize,
    /// The decimation step.
    pub every: usize,
}

/// The contents of `run.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunReport {
    /// The model file and name.
    pub model: ModelRef,
    /// `"kinematic"`, `"dynamic"` or `"inverse_dynamics"`.
    pub analysis: &'static str,
    /// The units of the output tables: `"SI"`, or `"mm"` (mm, kg, s, N, N mm; `--units mm`
    /// of an ASMT file). The numbers of this file (drifts, energies, residuals) are SI.
    pub units: &'static str,
    /// Complete or partial.
    pub status: Status,
    /// Why a partial run stopped (the error message); `null` when complete.
    pub reason: Option<String>,
    /// The exit code of `cardan run` (0, 3 for a failure or `--strict` with warnings, 130 for
    /// Ctrl-C).
    pub exit_code: i32,
    /// How far the run got and what it took.
    #[serde(flatten)]
    pub progress: Progress,
    /// How well the results satisfy the constraints and the energy balance.
    #[serde(flatten)]
    pub accuracy: Accuracy,
    /// Doubtful results and other remarks, one sentence each.
    pub warnings: Vec<String>,
    /// Kinematic and inverse dynamics: grid steps solved in substeps because the full step
    /// left the assembly branch (a note, not a warning: `--strict` ignores it); `null` for a
    /// dynamic run.
    pub subdivided_steps: Option<usize>,
    /// Times the independent equations of a model with redundant equations were chosen again
    /// because the kept ones lost rank where the full set has not (a note, not a warning).
    pub row_reselections: usize,
    /// A run whose plots, animation and report show a decimated copy of its frames (the CSV
    /// files hold every frame): how; `null` when they show every frame.
    pub plotted_frames: Option<PlottedFrames>,
    /// The files written besides `run.json`, in the order written.
    pub files: Vec<String>,
    /// Wall time of the analysis, without the writing (s).
    pub wall_time_s: f64,
}

/// `run.json`'s counts: how far the run got and the work it took (flattened into the report).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Progress {
    /// The last stored time (s).
    pub t_reached: Option<f64>,
    /// Stored output times.
    pub steps: usize,
    /// Dynamic: accepted integration steps; `null` otherwise.
    pub integration_steps: Option<usize>,
    /// Dynamic: rejected integration steps; `null` otherwise.
    pub rejected_steps: Option<usize>,
    /// Newton iterations (position solves; for a dynamic run implicit steps and projections).
    pub newton_iterations: usize,
    /// Dynamic runs of a model with limits: the end stops' impacts and releases (left out of
    /// the file for other runs, so theirs is unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stops: Option<StopCounts>,
}

/// A dynamic run's end-stop events (`events.csv` lists each).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct StopCounts {
    /// Impacts (rebounds, and impacts that left the stop held closed).
    pub impacts: usize,
    /// Of those, the impacts that held the stop closed (e = 0, or below the rest velocity).
    pub held_impacts: usize,
    /// Held stops that opened again (their multiplier changed sign).
    pub releases: usize,
    /// Stops held closed at the last output time.
    pub held_at_end: usize,
}

/// `run.json`'s accuracy figures: residuals, drifts and the energy balance (flattened into
/// the report).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Accuracy {
    /// Largest max |Φ_i| over the stored times.
    pub largest_residual: f64,
    /// Dynamic: largest constraint drift max |Φ_i| (m or -); `null` otherwise.
    pub constraint_drift: Option<f64>,
    /// Dynamic: max |E − E(t_start)| (J), the work of drivers and non-conservative forces plus
    /// the integration error; `null` otherwise.
    pub energy_drift: Option<f64>,
    /// Dynamic and inverse dynamics: max |E − E(t_start) − W_nc| (J), the integration error
    /// (inverse dynamics: the error of the work's quadrature on the time grid); `null` otherwise.
    pub energy_balance: Option<f64>,
    /// Dynamic and inverse dynamics: the run's energy scale (J), which the balance is judged
    /// against; `null` otherwise.
    pub energy_scale: Option<f64>,
}

impl RunReport {
    /// The JSON text (pretty-printed, with a final newline; non-finite numbers as `null`).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_else(|e| {
            // Serializing plain data cannot fail; if it ever did, say so in the file.
            format!("{{\"error\": \"run.json could not be written: {e}\"}}")
        });
        s.push('\n');
        s
    }
}
