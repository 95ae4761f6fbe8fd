//! Output groups: a time column and named columns with units, written as CSV and plotted as SVG
//! (the plot, `Table::to_svg`, and its layout are [`crate::plot`]'s).

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
        csv_header(&self.columns)
    }
}

/// Appends one CSV row and its line break: each value in the shortest form that reads back to
/// it exactly ("0.25", "1e-7", "-3.5e20", "NaN", "inf"; ryu's, about three times faster than
/// the standard library's `{:e}`: a long run's rows were a tenth of its time).
pub fn push_csv_row(s: &mut String, row: &[f64]) {
    let mut buf = ryu::Buffer::new();
    for (k, &v) in row.iter().enumerate() {
        if k > 0 {
            s.push(',');
        }
        s.push_str(buf.format(v));
    }
    s.push('\n');
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
pub(crate) fn csv_field(s: &str) -> std::borrow::Cow<'_, str> {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\"")).into()
    } else {
        s.into()
    }
}

/// The CSV header line of a table of `columns`: the time, then each column.
pub fn csv_header(columns: &[String]) -> String {
    let mut s = String::with_capacity(columns.iter().map(|c| c.len() + 1).sum::<usize>() + 8);
    s.push_str("t [s]");
    for c in columns {
        s.push(',');
        s.push_str(&csv_field(c));
    }
    s.push('\n');
    s
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

    /// Every value reads back exactly, the special ones included.
    #[test]
    fn csv_numbers_read_back_exactly() {
        let mut row = vec![0.0, -0.0, 0.1, 1.0 / 3.0, 123456.0, 1e16, 1e-7, -2.5e-17];
        row.extend([
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]);
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            row.push(f64::from_bits(x));
        }
        row.retain(|v| !v.is_nan());
        let mut s = String::new();
        push_csv_row(&mut s, &row);
        let back: Vec<f64> = s
            .trim_end()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(back.len(), row.len());
        for (a, b) in back.iter().zip(&row) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a} read back from {b}");
        }
        let mut s = String::new();
        push_csv_row(&mut s, &[f64::NAN]);
        assert!(s.trim_end().parse::<f64>().unwrap().is_nan());
    }
}
