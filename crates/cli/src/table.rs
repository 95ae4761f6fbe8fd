//! Output groups: a time column and named columns with units, written as CSV and plotted as SVG
//! (the layout of the plot: [`crate::plot`]).

use std::fmt::Write as _;

/// One output group (one CSV file, one plot).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// File stem, e.g. "points".
    pub name: String,
    /// Plot title.
    pub title: String,
    /// Column headers without the time column, e.g. `"crank.B.x [m]"`.
    pub columns: Vec<String>,
    /// Rows: time first, then one value per column.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// An empty group.
    pub fn new(name: &str, title: &str, columns: Vec<String>) -> Self {
        Self {
            name: name.into(),
            title: title.into(),
            columns,
            rows: Vec::new(),
        }
    }

    /// The CSV text: header `t [s],<columns>`, then one row per time (17 significant digits).
    pub fn to_csv(&self) -> String {
        let mut s = self.csv_header();
        for row in &self.rows {
            push_csv_row(&mut s, row);
        }
        s
    }

    /// The CSV header line `t [s],<columns>` with its line break.
    pub fn csv_header(&self) -> String {
        let mut s = String::from("t [s]");
        for c in &self.columns {
            s.push(',');
            s.push_str(&csv_field(c));
        }
        s.push('\n');
        s
    }

    /// The SVG plot of the table: small multiples, one unit per panel ([`crate::plot`]).
    pub fn to_svg(&self) -> String {
        cardan_plot::render_svg(&crate::plot::figure(self))
    }
}

/// Appends one CSV row (shortest round-trip exponent form of each value) and its line break.
pub fn push_csv_row(s: &mut String, row: &[f64]) {
    for (k, v) in row.iter().enumerate() {
        if k > 0 {
            s.push(',');
        }
        let _ = write!(s, "{v:e}");
    }
    s.push('\n');
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Parses a CSV written by [`Table::to_csv`] (tests and tools): header and rows.
pub fn parse_csv(text: &str) -> Option<(Vec<String>, Vec<Vec<f64>>)> {
    let mut lines = text.lines();
    let header = lines.next()?.split(',').map(str::to_string).collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(|v| v.parse::<f64>().ok()).collect())
        .collect::<Option<Vec<Vec<f64>>>>()?;
    Some((header, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trip() {
        let mut t = Table::new("g", "G", vec!["a.x [m]".into(), "b [rad]".into()]);
        t.rows.push(vec![0.0, 1.0 / 3.0, -2.5e-17]);
        t.rows.push(vec![0.1, f64::NAN, 7.0]);
        let (h, rows) = parse_csv(&t.to_csv()).unwrap();
        assert_eq!(h, ["t [s]", "a.x [m]", "b [rad]"]);
        assert_eq!(rows[0], t.rows[0]);
        assert!(rows[1][1].is_nan());
    }
}
