//! The commands that write files: `cardan run` (the output directory) and `cardan import` (the
//! imported model, and an ASMT run's `*.solved.asmt`). `check` and `eval` print what the model
//! library reports ([`cardan_model::check`], [`cardan_model::eval`]).

pub mod asmt;
pub mod run;
pub mod sweep;
