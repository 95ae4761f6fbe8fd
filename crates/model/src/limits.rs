//! The model file's size limits: what a file may hold before it is refused unread
//! (docs/model-format.md, "Limits"). A leaf module: reading the file (`diag::Source::read`)
//! and parsing it (`file::parse`) both check them.

/// Largest model file accepted, in bytes (128 MiB; real models are a few kB to tens of kB, a
/// generated 100,000-body chain about 60 MB).
pub const MAX_FILE_BYTES: usize = 128 << 20;
/// Most `[[body]]` entries. Checking and preparing a model costs about linear time and memory
/// in the body count (the sparse rank analysis of cardan-solver); see
/// docs/model-format.md, "Limits", for the measured memory per body.
pub const MAX_BODIES: usize = 100_000;
/// Most `[[joint]]`, `[[driver]]` or `[[force]]` entries of each kind.
pub const MAX_ELEMENTS: usize = 200_000;
/// Longest array accepted (polynomial coefficients, spline knots, output lists).
pub const MAX_ARRAY_LEN: usize = 10_000;
/// Longest expression text accepted, in bytes.
pub const MAX_EXPRESSION_LEN: usize = 10_000;
/// Deepest nesting of arrays and inline tables accepted (a model file needs 3).
pub const MAX_NESTING: usize = 32;
