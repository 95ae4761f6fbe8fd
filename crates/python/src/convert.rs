//! Conversions between cardan's data and the plain Python data the package wraps: tables as
//! packed `float64` rows, errors as dicts.

use cardan_cli::{Error, ErrorKind};
use cardan_model::table::Table;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};

/// An error as Python sees it.
pub struct ErrorData {
    /// "input", "analysis", "strict" (`--strict` with warnings), "output" or "interrupted".
    pub kind: &'static str,
    /// The one-paragraph message (without the location).
    pub message: String,
    /// The message as the command prints it (location and source excerpt included).
    pub printed: String,
    /// The model file, line and column (1-based), when the error is located.
    pub location: Option<(String, usize, usize)>,
}

impl From<&Error> for ErrorData {
    fn from(e: &Error) -> Self {
        let kind = match e.kind {
            // A misused argument (an option that does not apply) is an input error in Python.
            ErrorKind::Input | ErrorKind::Usage => "input",
            ErrorKind::Analysis => "analysis",
            ErrorKind::Output | ErrorKind::BrokenPipe => "output",
            ErrorKind::Interrupted => "interrupted",
        };
        Self {
            kind,
            message: e.message.clone(),
            printed: e.to_string(),
            location: e
                .location
                .as_ref()
                .map(|l| (l.file.display().to_string(), l.line, l.column)),
        }
    }
}

impl ErrorData {
    /// The same error as the failure of a `--strict` run with warnings (kind "strict").
    pub fn strict(self) -> Self {
        Self {
            kind: "strict",
            ..self
        }
    }
}

/// The error as a dict: `kind`, `message`, `printed`, `file`, `line`, `column`.
pub fn error_dict<'py>(py: Python<'py>, e: &ErrorData) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", e.kind)?;
    d.set_item("message", &e.message)?;
    d.set_item("printed", &e.printed)?;
    let (file, line, column) = match &e.location {
        Some((f, l, c)) => (Some(f.clone()), Some(*l), Some(*c)),
        None => (None, None, None),
    };
    d.set_item("file", file)?;
    d.set_item("line", line)?;
    d.set_item("column", column)?;
    Ok(d)
}

/// A table as `(name, title, columns, data, rows)`: `data` holds the rows (time first, then one
/// value per column) as packed little-endian `float64`.
pub fn table_tuple<'py>(py: Python<'py>, t: &Table) -> PyResult<Bound<'py, PyTuple>> {
    let width = t.columns.len() + 1;
    // Written straight into the Python bytes object: one pass, no intermediate buffer.
    let data = PyBytes::new_with(py, t.rows.len() * width * 8, |buf| {
        for (row, out) in t.rows.iter().zip(buf.chunks_exact_mut(width * 8)) {
            for (c, cell) in out.chunks_exact_mut(8).enumerate() {
                let v = row.get(c).copied().unwrap_or(f64::NAN);
                cell.copy_from_slice(&v.to_le_bytes());
            }
        }
        Ok(())
    })?;
    (
        t.name.as_str(),
        t.title.as_str(),
        t.columns.clone(),
        data,
        t.rows.len(),
    )
        .into_pyobject(py)
}

/// The table whose rows `data` packs as [`table_tuple`] does.
///
/// # Errors
/// A length that is not a whole number of rows.
pub fn table_from_bytes(
    name: String,
    title: String,
    columns: Vec<String>,
    data: &[u8],
) -> Result<Table, String> {
    let width = (columns.len() + 1) * 8;
    if !data.len().is_multiple_of(width) {
        return Err(format!(
            "table {name}: {} bytes are not whole rows of {} float64 values",
            data.len(),
            columns.len() + 1
        ));
    }
    let mut t = Table::new(&name, &title, columns);
    for row in data.chunks_exact(width) {
        t.rows.push(
            row.chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
                .collect(),
        );
    }
    Ok(t)
}
