//! `Prepared`: a model text read, checked and built once, kept by `cardan.Model` beside its
//! text so that its analyses, checks and drag steps do not read the text again.
//!
//! A model text is prepared when the `Model` is made (validation is preparing: parsing,
//! checking names and values, building the mechanism), and an import (ASMT, URDF) prepares
//! its model text as it writes it. Reading the text again on every `run` was a tenth of a
//! small ASMT file's solve. The handle is used only for the text and path it was made from
//! (compared, so a `Model` whose `text` was replaced is prepared afresh) and only where the
//! text is taken as it is: a run that sets the analysis kind or `[analysis]` keys edits the
//! text and prepares the edited one. The handle is not pickled; a model that crossed to
//! another process is prepared there from its text on each call.

use crate::convert::{error_dict, ErrorData};
use cardan_model::diag::Source;
use cardan_model::prepare::prepare_source;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// A prepared model (module docs): opaque to Python. Cloned (two reference counts) into the
/// thread a run goes to.
#[pyclass(frozen, module = "cardan._cardan")]
#[derive(Clone)]
pub struct Prepared {
    /// The text and path it was prepared from (an overlay's prepared source is another text).
    made_from: Arc<(String, String)>,
    /// The prepared model.
    model: Arc<cardan_model::prepare::Prepared>,
}

impl Prepared {
    /// `text` read from `path`, prepared.
    ///
    /// # Errors
    /// As [`model_of`].
    pub fn new(text: String, path: String) -> Result<Self, cardan_model::diag::Error> {
        let model = prepared_text(text.clone(), path.clone())?;
        Ok(Self {
            made_from: Arc::new((text, path)),
            model,
        })
    }
}

/// The model of `text` read from `path`: `handle` when it was prepared from that text and
/// path, else prepared now.
///
/// # Errors
/// What preparing the text reports (syntax, names, values, the builder's errors).
pub fn model_of(
    text: String,
    path: String,
    handle: Option<&Prepared>,
) -> Result<Arc<cardan_model::prepare::Prepared>, cardan_model::diag::Error> {
    match handle.filter(|h| h.made_from.0 == text && h.made_from.1 == path) {
        Some(h) => Ok(Arc::clone(&h.model)),
        None => prepared_text(text, path),
    }
}

/// `text` read from `path`, prepared now.
fn prepared_text(
    text: String,
    path: String,
) -> Result<Arc<cardan_model::prepare::Prepared>, cardan_model::diag::Error> {
    prepare_source(Source::from_text(path, text)).map(Arc::new)
}

/// [`model_of`], or `None` with the error set under the key `error` of `out`.
pub fn model_or_error(
    py: Python<'_>,
    out: &Bound<'_, PyDict>,
    text: String,
    path: String,
    handle: Option<&Prepared>,
) -> PyResult<Option<Arc<cardan_model::prepare::Prepared>>> {
    match py.detach(|| model_of(text, path, handle)) {
        Ok(p) => Ok(Some(p)),
        Err(e) => {
            out.set_item("error", error_dict(py, &ErrorData::from(&e))?)?;
            Ok(None)
        }
    }
}

/// Reads, checks and builds a model text as every analysis does before it runs (syntax,
/// names, numbers, shapes; not the assembly): `{"model": the prepared handle, "error": None}`
/// or `{"model": None, "error": the error dict}`.
#[pyfunction]
pub fn prepare<'py>(py: Python<'py>, text: String, path: String) -> PyResult<Bound<'py, PyDict>> {
    prepared_dict(py, py.detach(|| Prepared::new(text, path)))
}

/// `{"model": handle, "error": None}` or `{"model": None, "error": the error dict}`.
pub fn prepared_dict<'py>(
    py: Python<'py>,
    prepared: Result<Prepared, cardan_model::diag::Error>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    match prepared {
        Ok(handle) => {
            out.set_item("model", handle)?;
            out.set_item("error", py.None())?;
        }
        Err(e) => {
            out.set_item("model", py.None())?;
            out.set_item("error", error_dict(py, &ErrorData::from(&e))?)?;
        }
    }
    Ok(out)
}
