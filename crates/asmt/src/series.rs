//! The `TimeSeries` block: OndselSolver's results table (notes §1.8).
//!
//! ```text
//! TimeSeries
//! Number  Input  1  2  …  N
//! Time    Input  t1 t2 …  tN
//! AssemblySeries  /<asm>                   18 rows (the ground)
//! PartSeries      /<asm>/<part>            18 rows: X Y Z Bryantx..z VX..VZ OmegaX..Z AX..AZ AlphaX..Z
//! <Kind>Series    /<asm>/<joint>           6 rows: FXonI FYonI FZonI TXonI TYonI TZonI
//! ```
//!
//! Each data row is a label, the value at the input pose (column `Input`), then one value per
//! time. The Smalltalk writer puts a space between `…Series` and the path, the C++ writer a TAB;
//! items are matched by path, never by label (the C++ writer mangles some labels).

use crate::error::{AsmtError, Result};
use crate::scalar::{clip, number};

/// The 18 rows of a part (and of the assembly).
pub const PART_ROWS: [&str; 18] = [
    "X", "Y", "Z", "Bryantx", "Bryanty", "Bryantz", "VX", "VY", "VZ", "OmegaX", "OmegaY", "OmegaZ",
    "AX", "AY", "AZ", "AlphaX", "AlphaY", "AlphaZ",
];

/// The 6 rows of a joint or motion.
pub const REACTION_ROWS: [&str; 6] = ["FXonI", "FYonI", "FZonI", "TXonI", "TYonI", "TZonI"];

/// One row: label, value at the input pose, one value per time.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// `X`, `FXonI`, ...
    pub label: String,
    /// The `Input` column.
    pub input: f64,
    /// One value per time.
    pub values: Vec<f64>,
}

/// One item's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// `PartSeries`, `RevoluteJointSeries`, ...
    pub kind: String,
    /// The item's full path.
    pub path: String,
    /// Line of the item header.
    pub line: usize,
    /// Its rows.
    pub rows: Vec<Row>,
}

impl Item {
    /// Row `label`'s values.
    pub fn row(&self, label: &str) -> Option<&[f64]> {
        self.rows
            .iter()
            .find(|r| r.label == label)
            .map(|r| r.values.as_slice())
    }
}

/// A results table.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TimeSeries {
    /// Output times.
    pub times: Vec<f64>,
    /// Items in order.
    pub items: Vec<Item>,
}

impl TimeSeries {
    /// The item with path `path`.
    pub fn item(&self, path: &str) -> Option<&Item> {
        self.items.iter().find(|i| i.path == path)
    }

    /// Writes the block (from the `TimeSeries` line) in the C++ writer's layout, full precision.
    pub fn write(&self, out: &mut String) {
        let rows: Vec<&[f64]> = (self.items.iter())
            .flat_map(|i| i.rows.iter().map(|r| r.values.as_slice()))
            .collect();
        // Writing to memory cannot fail: every piece write_block writes is a whole `str`.
        let _ = write_block(
            &mut StrSink(out),
            self.times.len(),
            &self.items,
            &mut |i, emit| emit(if i == 0 { &self.times } else { rows[i - 1] }),
        );
    }
}

/// `write_block`'s output appended to a `String`: each piece it writes is the bytes of a whole
/// `str`, checked (ASCII fast path) and appended once, without a byte buffer in between.
struct StrSink<'a>(&'a mut String);

impl std::io::Write for StrSink<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let text = std::str::from_utf8(buf)
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))?;
        self.0.push_str(text);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Passes row i's values of a block (0: the times; then the items' rows in order) to `emit`,
/// in time order, in one or more pieces.
pub type RowValues<'a> =
    dyn FnMut(usize, &mut dyn FnMut(&[f64]) -> std::io::Result<()>) -> std::io::Result<()> + 'a;

/// Writes a `TimeSeries` block (from the `TimeSeries` line) of `times` times in the C++
/// writer's layout, full precision: the items' kinds, paths, row labels and inputs from `items`
/// (their rows' values are not read), the values from `values`, one row at a time, so that a
/// block larger than memory can be written from a [`crate::transpose::Transposer`].
///
/// # Errors
/// A write error of `out` or an error of `values`.
pub fn write_block(
    out: &mut dyn std::io::Write,
    times: usize,
    items: &[Item],
    values: &mut RowValues<'_>,
) -> std::io::Result<()> {
    use std::fmt::Write as _;
    const CHUNK: usize = 1 << 16;
    // Written out whenever the text reaches CHUNK bytes.
    let spill = |text: &mut String, out: &mut dyn std::io::Write| {
        if text.len() >= CHUNK {
            out.write_all(text.as_bytes())?;
            text.clear();
        }
        Ok::<(), std::io::Error>(())
    };
    let mut text = String::with_capacity(CHUNK);
    let mut buf = ryu::Buffer::new();
    let mut numbers = |text: &mut String, out: &mut dyn std::io::Write, v: &[f64]| {
        for &x in v {
            text.push('\t');
            text.push_str(buf.format(x));
            spill(text, out)?;
        }
        Ok::<(), std::io::Error>(())
    };
    text.push_str("TimeSeries\nNumber\tInput");
    for k in 1..=times {
        let _ = write!(text, "\t{k}");
        spill(&mut text, out)?;
    }
    text.push_str("\t\nTime\tInput");
    values(0, &mut |v| numbers(&mut text, out, v))?;
    text.push_str("\t\n");
    let mut i = 0;
    for item in items {
        let _ = writeln!(text, "{}\t{}", item.kind, item.path);
        for r in &item.rows {
            i += 1;
            text.push_str(&r.label);
            numbers(&mut text, out, &[r.input])?;
            values(i, &mut |v| numbers(&mut text, out, v))?;
            text.push_str("\t\n");
        }
    }
    out.write_all(text.as_bytes())
}

/// Parses the lines after `TimeSeries` (`line` is that label's line).
///
/// # Errors
/// A missing `Time` row, a row of the wrong length, or a value that is not a finite number.
pub fn parse<'a>(
    line: usize,
    rows: impl IntoIterator<Item = (usize, &'a str)>,
) -> Result<TimeSeries> {
    let mut series = TimeSeries::default();
    let mut have_time = false;
    for (n, raw) in rows {
        let cells: Vec<&str> = raw.split('\t').map(str::trim).collect();
        let head = cells[0];
        if let Some((kind, path)) = item_header(raw) {
            series.items.push(Item {
                kind,
                path,
                line: n,
                rows: Vec::new(),
            });
            continue;
        }
        let values: Vec<&str> = cells
            .iter()
            .skip(1)
            .copied()
            .filter(|c| !c.is_empty())
            .collect();
        match head {
            "Number" => {}
            "Time" => {
                if values.first() != Some(&"Input") {
                    return Err(AsmtError::new(
                        n,
                        "the Time row of the TimeSeries must start with \"Input\"",
                    ));
                }
                series.times = values[1..]
                    .iter()
                    .map(|v| number(v, n, "a time of the TimeSeries"))
                    .collect::<Result<_>>()?;
                have_time = true;
            }
            label => {
                if !have_time {
                    return Err(AsmtError::new(n, "a TimeSeries row before the Time row"));
                }
                let Some(item) = series.items.last_mut() else {
                    return Err(AsmtError::new(
                        n,
                        format!(
                            "TimeSeries row \"{}\" before any item header (\"PartSeries /…\")",
                            clip(label)
                        ),
                    ));
                };
                if values.len() != series.times.len() + 1 {
                    return Err(AsmtError::new(
                        n,
                        format!(
                            "TimeSeries row \"{}\" of {} has {} values; expected {} (Input and one per time)",
                            clip(label),
                            item.path,
                            values.len(),
                            series.times.len() + 1
                        ),
                    ));
                }
                let what = format!("row \"{}\" of {}", clip(label), item.path);
                let nums = values
                    .iter()
                    .map(|v| number(v, n, &what))
                    .collect::<Result<Vec<f64>>>()?;
                item.rows.push(Row {
                    label: label.to_string(),
                    input: nums[0],
                    values: nums[1..].to_vec(),
                });
            }
        }
    }
    if !have_time {
        return Err(AsmtError::new(line, "the TimeSeries has no Time row"));
    }
    Ok(series)
}

/// `<Kind>Series<TAB or space>/<path>` → (kind, path).
fn item_header(raw: &str) -> Option<(String, String)> {
    let t = raw.trim();
    let k = t.find("Series")?;
    let rest = &t[k + "Series".len()..];
    let path = rest.trim();
    if !path.starts_with('/') || t[..k].contains(char::is_whitespace) {
        return None;
    }
    Some((t[..k + "Series".len()].to_string(), path.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let s = TimeSeries {
            times: vec![0.0, 0.1],
            items: vec![Item {
                kind: "PartSeries".into(),
                path: "/A/P".into(),
                line: 0,
                rows: vec![Row {
                    label: "X".into(),
                    input: 1.0,
                    values: vec![0.1 + 0.2, -3e-17],
                }],
            }],
        };
        let mut text = String::new();
        s.write(&mut text);
        let rows = text.lines().skip(1).enumerate().map(|(k, l)| (k + 2, l));
        let mut back = parse(1, rows).unwrap();
        back.items[0].line = 0;
        assert_eq!(back, s);
    }

    #[test]
    fn short_row_is_an_error_with_its_line() {
        let rows = [
            (2, "Time\tInput\t0\t1"),
            (3, "PartSeries /A/P"),
            (4, "X\t0\t1"),
        ];
        assert_eq!(parse(1, rows).unwrap_err().line, 4);
    }
}
