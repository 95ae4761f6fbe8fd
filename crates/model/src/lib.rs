//! # cardan-model: model files as a library
//!
//! A cardan model file (TOML, docs/model-format.md) or an ASMT assembly (FreeCAD /
//! OndselSolver, docs/asmt.md) → a [`cardan_mechanism::Model`] and its analysis → the results
//! as tables with units, `run.json`, plots and the 3D scene. The `cardan` command
//! (`cardan-cli`: arguments, the progress bar, the output directory), the Python package and the
//! benchmarks are built on it.
//!
//! - Reading: [`file`](mod@file) (the file as written, every value spanned), [`build`] (the builders and
//!   the analysis from it, located errors), [`units`], [`diag`] (errors with file, line, column
//!   and the source line), [`asmt`] (an ASMT file imported as a model text), [`urdf`] (a URDF
//!   robot imported as a model text), [`geometry`] (what
//!   the animation draws).
//! - [`prepare`](mod@prepare): read, check and build in one call ([`prepare::prepare`]), and the analysis
//!   errors located in the file.
//! - [`analysis`]: runs the file's analysis into tables ([`analysis::analyse`]), streaming the
//!   CSV files to an [`files::OutputFiles`] when given one; [`run_json`], [`plot`], [`scene`].
//! - [`check`] and [`eval`]: the model's report and Φ, Φ_q, ν, γ# at its assembled state.
//! - [`progress`]: the stop request (Ctrl-C, a host's interrupt) that every analysis loop reads.
//!
//! Every failure is a [`diag::Error`] with a one-paragraph message (file:line:column when it
//! comes from the model file) and a kind that selects the command's exit code; bad input never
//! panics.

pub mod analysis;
pub mod asmt;
pub mod build;
pub mod check;
pub mod diag;
pub mod eval;
pub mod file;
pub mod files;
pub mod free_dof;
pub mod functions;
pub mod geometry;
pub mod limits;
mod number;
pub mod output_tables;
pub mod overlay;
pub mod parameters;
pub mod plot;
pub mod prepare;
pub mod progress;
pub mod run_json;
pub mod scene;
pub mod scene_curves;
pub mod scene_shapes;
pub mod sweep;
pub mod table;
pub mod units;
pub mod urdf;
pub mod vocabulary;

pub use diag::{Error, ErrorKind, Location, Source};
pub use prepare::{prepare, Prepared};
