//! The first pass: ASMT text → a tree of labelled lines by TAB depth.
//!
//! ASMT is line oriented and indented by TAB characters only (notes §1.1): a label line at depth
//! n has its values and sub-labels on the following lines at depth n + 1. This pass knows nothing
//! of the sections; it checks the layout (tabs, no jump of more than one level) and keeps the file
//! line of every node, so every later error can name it. The `TimeSeries` block at the end (depth
//! 0, tab-separated table rows) is cut off here: [`Tree::series`] says where it starts, and
//! [`SeriesBlock::rows`] reads its lines only when someone needs them (a run replaces it; in a
//! solved file it is 95 % of the text).

use crate::error::{AsmtError, Result};

/// One line of the file and the lines nested under it (borrowing the text it was parsed
/// from: no copy per line).
#[derive(Debug, Clone, PartialEq)]
pub struct Node<'a> {
    /// The line's text without its leading tabs (trailing blanks kept, as OndselSolver does for
    /// names).
    pub text: &'a str,
    /// 1-based line number in the file.
    pub line: usize,
    /// The lines one level deeper, in order.
    pub children: Vec<Node<'a>>,
}

impl Node<'_> {
    /// The text with surrounding whitespace removed (labels and numbers).
    pub fn label(&self) -> &str {
        self.text.trim()
    }
}

/// The whole file as a tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Tree<'a> {
    /// Line 1 (the writer: `OndselSolver` or the askoh.com Smalltalk banner).
    pub header: Node<'a>,
    /// The top-level nodes after the header (normally one: `Assembly`).
    pub roots: Vec<Node<'a>>,
    /// Where the `TimeSeries` block starts, if the file has one.
    pub series: Option<SeriesBlock>,
    /// The last line of the model: the file's last line, or the `TimeSeries` label's when the
    /// file has one (the table after it, most of a solved file, is not scanned here).
    pub lines: usize,
}

/// The position of the `TimeSeries` block in the text it was parsed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SeriesBlock {
    /// The file line of the `TimeSeries` label.
    pub line: usize,
    /// The byte offset of the line after the label.
    pub start: usize,
}

impl SeriesBlock {
    /// The nonblank table lines of the block in `text` (the text the tree was parsed from),
    /// with their file lines.
    pub fn rows<'a>(&self, text: &'a str) -> impl Iterator<Item = (usize, &'a str)> + 'a {
        let first = self.line + 1;
        text[self.start..]
            .lines()
            .enumerate()
            .map(move |(k, l)| (first + k, l))
            .filter(|(_, l)| !l.trim().is_empty())
    }
}

/// Splits `text` into the tree.
///
/// # Errors
/// Empty file, a line indented with spaces, a line more than one level deeper than the line
/// before it, or a NUL character.
pub fn parse(text: &str) -> Result<Tree<'_>> {
    // (line number, byte offset, text) of each line.
    let mut lines = text.lines().enumerate().map(|(k, l)| {
        let offset = l.as_ptr() as usize - text.as_ptr() as usize;
        (k + 1, offset, l)
    });
    let (first_line, header) = loop {
        match lines.next() {
            None => return Err(AsmtError::new(1, "the file is empty; an ASMT file starts with a header line (\"OndselSolver\" or the askoh.com banner) and \"Assembly\"")),
            Some((n, _, l)) if !l.trim().is_empty() => break (n, l),
            Some(_) => {}
        }
    };
    let header = Node {
        text: header.trim(),
        line: first_line,
        children: Vec::new(),
    };
    // A stack of open nodes: stack[d] is the last node at depth d.
    let mut roots: Vec<Node> = Vec::new();
    let mut stack: Vec<Node> = Vec::new();
    let mut series = None;
    let mut count = first_line;
    let mut rest = lines.by_ref();
    for (n, offset, raw) in &mut rest {
        count = n;
        if raw.contains('\0') {
            return Err(AsmtError::new(
                n,
                "the line holds a NUL character; ASMT is text",
            ));
        }
        if raw.trim().is_empty() {
            continue;
        }
        let depth = raw.len() - raw.trim_start_matches('\t').len();
        let body = &raw[depth..];
        if body.starts_with(' ') {
            return Err(AsmtError::new(
                n,
                "the line is indented with spaces; ASMT indents with TAB characters only (one TAB per level)",
            ));
        }
        if depth == 0 && body.trim_end() == "TimeSeries" {
            let start = (offset + raw.len()).min(text.len());
            let ending = text[start..].find('\n').map_or(0, |k| k + 1); // "\n" or "\r\n"
            let start = start + ending;
            series = Some(SeriesBlock { line: n, start });
            break;
        }
        if depth > stack.len() {
            return Err(AsmtError::new(
                n,
                format!(
                    "the line is indented {depth} TABs deep, more than one level below the line before it ({} TABs)",
                    stack.len().saturating_sub(1)
                ),
            ));
        }
        close_to(&mut stack, &mut roots, depth);
        stack.push(Node {
            text: body,
            line: n,
            children: Vec::new(),
        });
    }
    close_to(&mut stack, &mut roots, 0);
    Ok(Tree {
        header,
        roots,
        series,
        lines: count,
    })
}

/// Pops the stack down to `depth` open nodes, attaching each popped node to its parent.
fn close_to<'a>(stack: &mut Vec<Node<'a>>, roots: &mut Vec<Node<'a>>, depth: usize) {
    while stack.len() > depth {
        let node = stack.pop().expect("nonempty");
        match stack.last_mut() {
            Some(parent) => parent.children.push(node),
            None => roots.push(node),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nests_by_tabs_and_keeps_lines() {
        let t = parse("OndselSolver\nAssembly\n\tName\n\t\tA\n\tNotes\n\t\t\n").unwrap();
        assert_eq!(t.header.text, "OndselSolver");
        assert_eq!(t.roots.len(), 1);
        let a = &t.roots[0];
        assert_eq!(a.children.len(), 2);
        assert_eq!(a.children[0].children[0].text, "A");
        assert_eq!(a.children[0].children[0].line, 4);
    }

    #[test]
    fn spaces_and_jumps_are_errors_with_lines() {
        let e = parse("OndselSolver\nAssembly\n    Name\n").unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("spaces"));
        let e = parse("OndselSolver\nAssembly\n\t\t\tName\n").unwrap_err();
        assert_eq!(e.line, 3);
    }

    #[test]
    fn time_series_is_cut_off() {
        let text = "H\nAssembly\n\tName\n\t\tA\nTimeSeries\r\nNumber\tInput\t1\n\nX\n";
        let t = parse(text).unwrap();
        let block = t.series.unwrap();
        assert_eq!(block.line, 5);
        let rows: Vec<_> = block.rows(text).collect();
        assert_eq!(rows, vec![(6, "Number\tInput\t1"), (8, "X")]);
        assert_eq!(t.lines, 5);
        assert_eq!(parse("H\nAssembly\n\tName\n").unwrap().lines, 3);
    }
}
