//! # cardan-asmt: FreeCAD / OndselSolver assemblies (ASMT) for cardan
//!
//! ASMT is the text format of OndselSolver, the solver of FreeCAD's Assembly workbench. This
//! crate reads it into a typed [`Document`] (every element with its file line), maps the document
//! to cardan's elements ([`Import`], each with its ASMT path) and from there to a
//! [`cardan_mechanism::MechanismBuilder`]; and it writes results back as an OndselSolver
//! `TimeSeries` ([`solved`]).
//!
//! ```no_run
//! let text = std::fs::read_to_string("crank_slider.asmt").unwrap();
//! let (doc, import) = cardan_asmt::load(&text)?;
//! for w in &import.warnings {
//!     eprintln!("warning: {w}");
//! }
//! let model = import.builder().build().expect("a valid mechanism");
//! # let _ = (doc, model);
//! # Ok::<(), cardan_asmt::AsmtError>(())
//! ```
//!
//! ## Layers
//! - [`tree`]: lines → a tree by TAB depth (layout errors: spaces, jumps).
//! - `scalar`: number fields (with the Smalltalk `d` exponent) and the clipped text of messages.
//! - [`document`]: the tree → [`Document`] (sections, fields, numbers, joint kinds).
//! - [`series`]: the `TimeSeries` table.
//! - [`expr`]: ASMT motion expressions → cardan's expression grammar.
//! - [`mod@import`]: [`Document`] → [`Import`] (frames, markers, joints, couplers, motions,
//!   names).
//! - [`toml_out`]: [`Import`] → a cardan model file (TOML) with comments tracing each element.
//! - [`solved`]: cardan results → an OndselSolver `TimeSeries` (part-frame origin, Bryant angles,
//!   velocities, accelerations), whole or frame by frame ([`solved::SeriesPlan`]).
//! - [`transpose`]: frames in, rows out, spilled to a file in blocks: the `TimeSeries` of a
//!   run longer than memory.
//!
//! The format and OndselSolver's behaviour are described in `docs/asmt.md`.
//! Bad input never panics: every problem is an [`AsmtError`] with the file line.

pub mod document;
pub mod error;
pub mod expr;
pub mod import;
mod scalar;
pub mod series;
pub mod solved;
pub mod toml_out;
pub mod transpose;
pub mod tree;

pub use document::{read, read_model, Document};
pub use error::{AsmtError, Warning};
pub use import::{import, sanitize, AnalysisKind, BodyMap, Element, Import, Settings};
pub use series::TimeSeries;

/// Reads and maps an ASMT text (its model: a stored `TimeSeries` is not read, see
/// [`read_model`]).
///
/// # Errors
/// The first problem, at its file line.
pub fn load(text: &str) -> Result<(Document, Import), AsmtError> {
    let doc = read_model(text)?;
    let import = import(&doc)?;
    Ok((doc, import))
}

/// Reads only the `TimeSeries` of an ASMT text (the rest is checked for layout only), e.g. of
/// a file written by OndselSolver's C++ writer, whose joint labels are mangled (`luteJointE`
/// for `RevoluteJoint`; notes §1.8).
///
/// # Errors
/// A layout error or a bad TimeSeries row, at its line.
pub fn read_time_series(text: &str) -> Result<Option<TimeSeries>, AsmtError> {
    let tree = tree::parse(text)?;
    tree.series
        .map(|block| series::parse(block.line, block.rows(text)))
        .transpose()
}
