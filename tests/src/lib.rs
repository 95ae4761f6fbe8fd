//! Shared helpers for cardan's cross-layer tests.
//!
//! - [`registry`]: every Rust constraint element by its oracle name, built from oracle parameters.
//! - [`expressions`]: the oracle cases of expression time functions.
//! - [`oracle`]: loading `oracle/data/*.json` and comparing the Rust implementation with it.

pub mod expressions;
pub mod oracle;
pub mod registry;
