//! Placeholder: see crates/solver issue.
