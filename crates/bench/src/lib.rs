//! # cardan-bench: the benchmark models and measurements behind `cargo xtask bench`
//!
//! - [`models`]: generated mechanisms of any size (driven revolute chains, closed-loop ladders,
//!   spherical-joint chains) and the example files of `examples/`.
//! - [`animation`]: writing the animation and the report at several sizes (cardan-report).
//! - [`measure`]: timing helpers (median of repeated batches), peak memory (`VmHWM`).
//! - [`svg`]: minimal log-log line plots.
//!
//! The binary `cardan-bench` (src/main.rs) runs the measurements and writes the report section of
//! `docs/benchmarks.md` and the plots under `docs/benchmarks/`; `benches/frame.rs` is a criterion
//! benchmark of the same kinematic frames.

pub mod animation;
pub mod kinematic_accuracy;
pub mod measure;
pub mod models;
pub mod run_memory;
pub mod svg;
