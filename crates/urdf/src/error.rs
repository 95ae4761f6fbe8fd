//! Errors and warnings of the reader, each at a line of the URDF file and naming the element.

use std::fmt;

/// A problem that stops reading: the file line (1-based) and a sentence naming the element.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct UrdfError {
    /// 1-based line of the URDF file (0 when the problem is the whole file).
    pub line: usize,
    /// What is wrong, naming the element, and what to do.
    pub message: String,
}

impl UrdfError {
    /// An error at `line`.
    pub fn new(line: usize, message: impl Into<String>) -> Self {
        Self {
            line,
            message: message.into(),
        }
    }
}

/// Result of the reader.
pub type Result<T> = std::result::Result<T, UrdfError>;

/// Something read but not used, or used with a caveat: reported, never dropped silently.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    /// 1-based line of the URDF file.
    pub line: usize,
    /// The message, naming the element.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// The first `max` of `items` (there are `total`), joined by commas, with "…" when some are
/// left out: the lists of names in messages.
pub(crate) fn listing(items: impl Iterator<Item = String>, total: usize, max: usize) -> String {
    let shown: Vec<String> = items.take(max).collect();
    format!(
        "{}{}",
        shown.join(", "),
        if total > max { ", …" } else { "" }
    )
}
