//! Errors and warnings of the reader, each located at a line of the ASMT file.

use std::fmt;

/// A problem that stops reading: the file line (1-based) and a one-sentence message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct AsmtError {
    /// 1-based line of the ASMT file.
    pub line: usize,
    /// What is wrong, naming the element.
    pub message: String,
}

impl AsmtError {
    /// An error at `line`.
    pub fn new(line: usize, message: impl Into<String>) -> Self {
        Self {
            line,
            message: message.into(),
        }
    }
}

/// Result of the reader.
pub type Result<T> = std::result::Result<T, AsmtError>;

/// Something read but not used, or used with a caveat: reported, never dropped silently.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    /// 1-based line of the ASMT file.
    pub line: usize,
    /// The message, naming the element by its ASMT path.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}
