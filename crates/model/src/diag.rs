//! Errors of the command line: one paragraph each, with file, line and column when the problem
//! is in the model file, and under it that line of the file with the key or value underlined:
//!
//! ```text
//! model.toml:29:8: error: joint "pivot": unknown joint type "revolut"; did you mean "revolute"?
//!    |
//! 29 | type = "revolut"
//!    |        ^^^^^^^^^
//! ```

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// What kind of failure an [`Error`] is; it selects the exit code, one meaning per code
/// (docs/cli.md, "Exit codes"): 0 success (warnings allowed), 1 a file problem (the model cannot
/// be read, parsed or validated, or an output cannot be written), 2 command-line misuse, 3 the
/// analysis failed (or `--strict` found a warning), 130 stopped by Ctrl-C.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The model file cannot be read, parsed or validated (exit code 1).
    Input,
    /// The command line asks for something that cannot be done: an unknown flag or a bad flag
    /// value, a flag that does not apply to the model, an output path that is the input or
    /// cannot be a run's directory (exit code 2, as clap's own errors).
    Usage,
    /// The model is valid but the analysis failed (assembly, singular configuration), or
    /// `--strict` found a warning (exit 3).
    Analysis,
    /// Writing an output failed: a full disk, no permission, another run's lock (exit code 1).
    Output,
    /// Standard output was closed by its reader (exit code 0, no message).
    BrokenPipe,
    /// The run was stopped by Ctrl-C; its results so far were written (exit code 130, as a
    /// shell reports a process ended by SIGINT).
    Interrupted,
}

impl ErrorKind {
    /// The process exit code for this kind.
    pub fn exit_code(self) -> i32 {
        match self {
            ErrorKind::Input | ErrorKind::Output => 1,
            ErrorKind::Usage => 2,
            ErrorKind::Analysis => 3,
            ErrorKind::BrokenPipe => 0,
            ErrorKind::Interrupted => 130,
        }
    }
}

/// A place in a source file (1-based line and column).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file.
    pub file: PathBuf,
    /// Line, from 1.
    pub line: usize,
    /// Column (in characters), from 1.
    pub column: usize,
    /// The source line and the part of it to underline, shown under the message.
    pub excerpt: Option<Excerpt>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

/// A source line with the span to underline (a window of it when the line is long).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Excerpt {
    /// The line as shown (control characters replaced, long lines cut to a window).
    pub text: String,
    /// Characters before the underline in `text`.
    pub indent: usize,
    /// Underlined characters (at least 1).
    pub width: usize,
}

/// Longest excerpt shown, in characters; a longer line is cut to a window around the span.
const EXCERPT_MAX: usize = 100;

impl Excerpt {
    /// The excerpt of `line` underlining characters `col..col + width` (0-based).
    fn new(line: &str, col: usize, width: usize) -> Self {
        let chars: Vec<char> = line
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let width = width.clamp(1, EXCERPT_MAX / 2);
        let (start, prefix) = if chars.len() <= EXCERPT_MAX || col < EXCERPT_MAX / 3 {
            (0, "")
        } else {
            (col - EXCERPT_MAX / 3, "…")
        };
        let end = (start + EXCERPT_MAX).min(chars.len());
        let suffix = if end < chars.len() { "…" } else { "" };
        let body: String = chars[start.min(end)..end].iter().collect();
        Self {
            text: format!("{prefix}{}{suffix}", body.trim_end()),
            indent: col - start + prefix.chars().count(),
            width,
        }
    }
}

/// An error of the `cardan` command: kind, optional location and a one-paragraph message.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Selects the exit code.
    pub kind: ErrorKind,
    /// Where in the model file, when known.
    pub location: Option<Location>,
    /// What went wrong and, where possible, how to fix it.
    pub message: String,
}

impl Error {
    /// An input error without a location.
    pub fn input(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Input,
            location: None,
            message: message.into(),
        }
    }

    /// An analysis error.
    pub fn analysis(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Analysis,
            location: None,
            message: message.into(),
        }
    }

    /// A command-line misuse (exit code 2).
    pub fn usage(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Usage,
            location: None,
            message: message.into(),
        }
    }

    /// An output error.
    pub fn output(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Output,
            location: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => {
                write!(f, "{loc}: error: {}", self.message)?;
                if let Some(x) = &loc.excerpt {
                    let n = loc.line.to_string();
                    let pad = " ".repeat(n.len());
                    write!(
                        f,
                        "\n{pad} |\n{n} | {}\n{pad} | {}{}",
                        x.text,
                        " ".repeat(x.indent),
                        "^".repeat(x.width)
                    )?;
                }
                Ok(())
            }
            None => write!(f, "error: {}", self.message),
        }
    }
}

/// The message of an error as printed, without the source excerpt under it (for tests that
/// check a message is one paragraph).
pub fn message_paragraph(printed: &str) -> &str {
    let t = printed.trim_end();
    let cut = t.find("\n").filter(|&k| {
        t[k + 1..].lines().all(|l| {
            l.trim_start()
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start()
                .starts_with('|')
        })
    });
    cut.map_or(t, |k| &t[..k])
}

impl std::error::Error for Error {}

/// A model file's text, to turn byte spans into line and column.
#[derive(Debug, Clone)]
pub struct Source {
    /// The path as given on the command line.
    pub path: PathBuf,
    /// The contents.
    pub text: String,
    /// Parameter values given from outside the file (`--set name=value`, Python's
    /// `with_parameters`), in their order: they replace the file's definitions
    /// ([`crate::parameters`]).
    pub set: Vec<(String, String)>,
}

impl Source {
    /// Reads a file; an unreadable file is an input error naming the path and the cause.
    pub fn read(path: &Path) -> Result<Self, Error> {
        // Refuse an oversized file before reading it (the size limit is checked again on the
        // text by `model::parse`; `take` bounds the read if the file grows meanwhile).
        let limit = crate::limits::MAX_FILE_BYTES as u64;
        if let Ok(meta) = std::fs::metadata(path) {
            if meta.is_file() && meta.len() > limit {
                return Err(Error::input(format!(
                    "the model file {} is {} bytes long; at most {limit} bytes ({} MiB) are accepted",
                    path.display(),
                    meta.len(),
                    limit >> 20
                )));
            }
        }
        let read = std::fs::File::open(path).and_then(|f| {
            use std::io::Read as _;
            let mut bytes = Vec::new();
            f.take(limit + 1).read_to_end(&mut bytes)?;
            Ok(bytes)
        });
        match read {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(text) => Ok(Self {
                    path: path.to_path_buf(),
                    text,
                    set: Vec::new(),
                }),
                Err(e) => {
                    let at = e.utf8_error().valid_up_to();
                    let asmt = path
                        .extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case("asmt"));
                    let kind = if asmt {
                        "ASMT files are UTF-8 text, as FreeCAD writes them"
                    } else {
                        "cardan model files are UTF-8 TOML"
                    };
                    let mut err = Error::input(format!(
                        "the model file is not valid UTF-8 text ({kind}); is it the right file?"
                    ));
                    let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
                    let src = Self {
                        path: path.to_path_buf(),
                        text,
                        set: Vec::new(),
                    };
                    err.location = Some(src.location(at));
                    Err(err)
                }
            },
            Err(e) => Err(Error::input(format!(
                "cannot read the model file {}: {}",
                path.display(),
                describe_io(&e)
            ))),
        }
    }

    /// A source from text (tests, stdin).
    pub fn from_text(path: impl Into<PathBuf>, text: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            text: text.into(),
            set: Vec::new(),
        }
    }

    /// Line and column (1-based, column in characters) of a byte offset, with the character
    /// there underlined.
    pub fn location(&self, offset: usize) -> Location {
        self.span_location(offset..offset)
    }

    /// The location of the start of a byte span, with the span underlined (up to the end of
    /// its first line).
    pub fn span_location(&self, span: Range<usize>) -> Location {
        let offset = span.start.min(self.text.len());
        let mut start = offset;
        while !self.text.is_char_boundary(start) {
            start -= 1;
        }
        let before = &self.text[..start];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |k| k + 1);
        let column = before[line_start..].chars().count() + 1;
        let line_end = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |k| start + k);
        let mut end = span.end.clamp(start, line_end);
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        let width = self.text[start..end].chars().count();
        Location {
            file: self.path.clone(),
            line,
            column,
            excerpt: Some(Excerpt::new(
                &self.text[line_start..line_end],
                column - 1,
                width,
            )),
        }
    }

    /// An input error at a span of this file.
    pub fn error_at(&self, span: Range<usize>, message: impl Into<String>) -> Error {
        Error {
            kind: ErrorKind::Input,
            location: Some(self.span_location(span)),
            message: message.into(),
        }
    }

    /// An input error located at the start of the file (no better place known).
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error {
            kind: ErrorKind::Input,
            location: Some(self.location(0)),
            message: message.into(),
        }
    }
}

/// A short human description of an I/O error.
pub fn describe_io(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::IsADirectory => "it is a directory".into(),
        _ => {
            // A directory read as a file gives "Is a directory (os error 21)" on Linux.
            let s = e.to_string();
            s.split(" (os error").next().unwrap_or(&s).to_lowercase()
        }
    }
}

pub use cardan_mechanism::nearest;

/// ", did you mean `x`?" or "" when nothing is close.
pub fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    match nearest(word, candidates) {
        Some(c) => format!("; did you mean \"{c}\"?"),
        None => String::new(),
    }
}

/// "a, b, c" (quoted), for "valid names are ..." lists.
pub fn list<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let v: Vec<String> = names.into_iter().map(|n| format!("\"{n}\"")).collect();
    if v.is_empty() {
        "(none)".into()
    } else {
        v.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let s = Source::from_text("m.toml", "a = 1\nbb = é2\n");
        let l = s.location(6);
        assert_eq!((l.line, l.column), (2, 1));
        let l = s.location(11);
        assert_eq!((l.line, l.column), (2, 6));
    }

    #[test]
    fn excerpt_underlines_the_span() {
        let s = Source::from_text("m.toml", "a = 1\ntype = \"revolut\"\n");
        let e = s.error_at(13..22, "unknown joint type");
        assert_eq!(
            e.to_string(),
            "m.toml:2:8: error: unknown joint type\n  |\n2 | type = \"revolut\"\n  |        ^^^^^^^^^"
        );
        assert_eq!(
            message_paragraph(&e.to_string()),
            "m.toml:2:8: error: unknown joint type"
        );
        // A long line is cut to a window around the span; control characters are blanked.
        let long = format!("x = \"{}\tEND\"", "y".repeat(500));
        let s = Source::from_text("m.toml", long.clone());
        let at = long.find("END").unwrap();
        let x = s
            .error_at(at..at + 3, "bad")
            .location
            .unwrap()
            .excerpt
            .unwrap();
        assert!(x.text.chars().count() <= EXCERPT_MAX + 2, "{}", x.text);
        assert_eq!(
            x.text.chars().skip(x.indent).take(3).collect::<String>(),
            "END"
        );
        assert!(!x.text.contains('\t'));
    }

    #[test]
    fn suggestions() {
        assert_eq!(
            nearest("crnak", ["crank", "conrod", "slider"]),
            Some("crank")
        );
        assert_eq!(nearest("zzzzzz", ["crank", "conrod"]), None);
        assert_eq!(nearest("mas", ["mass", "name"]), Some("mass"));
    }
}
