//! # cardan-bench: the benchmark models and measurements behind `cargo xtask bench`
//!
//! - [`models`]: generated mechanisms of any size (driven revolute chains, closed-loop ladders,
//!   spherical-joint chains) and the example files of `examples/`.
//! - [`asmt`]: cardan against OndselSolver on the ten ASMT files (reading included).
//! - [`animation`]: writing the animation and the report at several sizes (cardan-report).
//! - [`genalpha`]: generalized-α over a developing motion (chain cost and iterations per slice of
//!   a run, slider-crank error), `cardan-bench --genalpha` / `--genalpha-sc`.
//! - [`large`]: `cardan check` and run setup of 10³–10⁵-body chains (time, peak memory).
//! - [`modal_peer`]: eigenfrequencies of a 3D model against Exudyn (`cardan-bench --modal --peers`).
//! - [`measure`]: timing helpers (median of repeated batches), peak memory (`VmHWM`).
//! - [`svg`]: minimal log-log line plots.
//!
//! The binary `cardan-bench` (src/main.rs) runs the measurements and writes the report section of
//! the generated section of `docs/performance.md` and the plots under `docs/performance/`; `benches/frame.rs` is a criterion
//! benchmark of the same kinematic frames.

pub mod animation;
pub mod asmt;
pub mod contact;
pub mod genalpha;
pub mod kinematic_accuracy;
pub mod large;
pub mod measure;
pub mod modal_peer;
pub mod modal_sparse;
pub mod models;
pub mod run_memory;
pub mod svg;
