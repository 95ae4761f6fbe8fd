//! The cases of a sweep: the Cartesian grid of `--set` axes, or the rows of a CSV file.
//!
//! An axis is `NAME=A:B:N` (N values evenly from A to B, both ends included; A and B numbers
//! with units, `"60 mm:100 mm:5"`), `NAME=V1,V2,...` (a list, each value as `--set` reads it)
//! or `NAME=V` (one value). Cases run the last axis fastest. A cases file has the parameter
//! names in its header and one case per row.

use crate::diag::Error;
use crate::parameters::expr;
use crate::parameters::quantity::Quantity;

/// Most cases a sweep runs without `--allow-long`.
pub const MAX_CASES: u128 = 100_000;
/// Most values of one axis (a range's N).
pub const MAX_AXIS: usize = 1_000_000;

/// One parameter's values.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The parameter.
    pub name: String,
    /// Its values, as `--set` texts.
    pub values: Vec<String>,
}

/// What a sweep runs.
#[derive(Debug, Clone, PartialEq)]
pub enum Cases {
    /// The grid of the axes.
    Grid(Vec<Axis>),
    /// Listed cases: parameter names and one row of values per case.
    Listed {
        /// The header.
        names: Vec<String>,
        /// The cases.
        rows: Vec<Vec<String>>,
    },
}

impl Cases {
    /// The parameters the cases set, in column order.
    pub fn names(&self) -> Vec<String> {
        match self {
            Cases::Grid(axes) => axes.iter().map(|a| a.name.clone()).collect(),
            Cases::Listed { names, .. } => names.clone(),
        }
    }

    /// How many cases (saturating).
    pub fn count(&self) -> u128 {
        match self {
            Cases::Grid(axes) => {
                (axes.iter()).fold(1u128, |n, a| n.saturating_mul(a.values.len() as u128))
            }
            Cases::Listed { rows, .. } => rows.len() as u128,
        }
    }

    /// Case `k`: the `--set` pairs.
    pub fn case(&self, mut k: usize) -> Vec<(String, String)> {
        match self {
            Cases::Grid(axes) => {
                let mut out = vec![(String::new(), String::new()); axes.len()];
                for (slot, a) in out.iter_mut().zip(axes).rev() {
                    let n = a.values.len();
                    *slot = (a.name.clone(), a.values[k % n].clone());
                    k /= n;
                }
                out
            }
            Cases::Listed { names, rows } => {
                names.iter().cloned().zip(rows[k].iter().cloned()).collect()
            }
        }
    }

    /// Refuses more than [`MAX_CASES`] cases unless `allow_long`, naming the count.
    ///
    /// # Errors
    /// A usage error with the count and its factors.
    pub fn check_count(&self, allow_long: bool) -> Result<(), Error> {
        let n = self.count();
        if n == 0 {
            return Err(Error::usage("the sweep has no cases"));
        }
        if n > MAX_CASES && !allow_long {
            let factors = match self {
                Cases::Grid(axes) => format!(
                    " ({})",
                    axes.iter()
                        .map(|a| format!("{} {}", a.values.len(), a.name))
                        .collect::<Vec<_>>()
                        .join(" × ")
                ),
                Cases::Listed { .. } => String::new(),
            };
            return Err(Error::usage(format!(
                "the sweep has {n} cases{factors}, more than {MAX_CASES}: give fewer values, or \
                 --allow-long to run them all"
            )));
        }
        if n > usize::MAX as u128 {
            return Err(Error::usage(format!(
                "the sweep has {n} cases: more than can be counted"
            )));
        }
        Ok(())
    }
}

/// A constant quantity of a range's end (no parameter names).
fn constant(text: &str, spec: &str) -> Result<Quantity, Error> {
    let bad = |m: String| Error::usage(format!("--set {spec}: \"{text}\": {m}"));
    let e = expr::parse(text).map_err(|e| bad(e.message))?;
    let none = |n: &str| {
        Err(format!(
            "a range's ends are numbers with units, not the name \"{n}\""
        ))
    };
    e.eval(&none, 1.0).map_err(|e| bad(e.message))
}

/// One `NAME=SPEC` of `cardan sweep --set`.
///
/// # Errors
/// A usage error: not `NAME=SPEC`, a range whose ends differ in unit or whose count is not a
/// whole number from 1 to [`MAX_AXIS`], an empty list entry.
pub fn axis(name: &str, spec: &str) -> Result<Axis, Error> {
    let whole = format!("{name}={spec}");
    let parts: Vec<&str> = spec.split(':').map(str::trim).collect();
    let values = match parts.as_slice() {
        [a, b, n] => {
            let count: usize = match n.parse() {
                Ok(c) if (1..=MAX_AXIS).contains(&c) => c,
                _ => {
                    return Err(Error::usage(format!(
                    "--set {whole}: the count \"{n}\" is not a whole number from 1 to {MAX_AXIS}"
                )))
                }
            };
            let (qa, qb) = (constant(a, &whole)?, constant(b, &whole)?);
            let dim = match (qa.dim, qb.dim) {
                (Some(x), Some(y)) if x != y => {
                    return Err(Error::usage(format!(
                        "--set {whole}: the ends are in different units ({x} and {y})"
                    )))
                }
                (d, None) | (None, d) => d,
                (d, _) => d,
            };
            // A plain end meets a quantity in the other's unit (SI here; --set reads the
            // plain value in the model's units only when both are plain).
            let (va, vb) = (qa.value, qb.value);
            (0..count)
                .map(|k| {
                    let f = if count == 1 {
                        0.0
                    } else {
                        k as f64 / (count - 1) as f64
                    };
                    let v = if k + 1 == count && count > 1 {
                        vb
                    } else {
                        va + (vb - va) * f
                    };
                    Quantity { value: v, dim }.exact_text()
                })
                .collect()
        }
        [_] => spec
            .split(',')
            .map(|v| v.trim().to_string())
            .collect::<Vec<_>>(),
        _ => {
            return Err(Error::usage(format!(
                "--set {whole}: a range is A:B:N (N values from A to B), a list V1,V2,..."
            )))
        }
    };
    if values.iter().any(String::is_empty) {
        return Err(Error::usage(format!(
            "--set {whole}: an empty value in the list"
        )));
    }
    Ok(Axis {
        name: name.to_string(),
        values,
    })
}

/// The cases of a CSV file: a header of parameter names, a row per case (values as `--set`
/// takes them; a field with commas in double quotes).
///
/// # Errors
/// An unreadable file; a row whose field count differs from the header's (at its line).
pub fn read_cases(path: &std::path::Path) -> Result<Cases, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        Error::usage(format!(
            "cannot read the cases file {}: {}",
            path.display(),
            crate::diag::describe_io(&e)
        ))
    })?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err(Error::usage(format!(
            "the cases file {} is empty",
            path.display()
        )));
    };
    let names = fields(header);
    let mut rows = Vec::new();
    for (k, line) in lines {
        let row = fields(line);
        if row.len() != names.len() {
            return Err(Error::usage(format!(
                "{}:{}: {} values for {} parameters ({})",
                path.display(),
                k + 1,
                row.len(),
                names.len(),
                names.join(", ")
            )));
        }
        rows.push(row);
    }
    Ok(Cases::Listed { names, rows })
}

/// A CSV line's fields (double quotes around a field with commas; `""` inside one is `"`).
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut field).trim().to_string()),
            _ => field.push(c),
        }
    }
    out.push(field.trim().to_string());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_lists_and_the_grid_order() {
        let a = axis("crank", "60 mm:100 mm:5").unwrap();
        assert_eq!(a.values.len(), 5);
        assert_eq!(a.values[0], "0.06 m");
        assert_eq!(a.values[4], "0.1 m");
        let b = axis("speed", "1, 2,4").unwrap();
        assert_eq!(b.values, ["1", "2", "4"]);
        let g = Cases::Grid(vec![a, b]);
        assert_eq!(g.count(), 15);
        assert_eq!(
            g.case(1),
            [
                ("crank".into(), "0.06 m".into()),
                ("speed".into(), "2".into())
            ]
        );
        assert_eq!(g.case(14)[0].1, "0.1 m");
    }

    #[test]
    fn bad_axes_and_huge_grids_are_refused() {
        assert!(axis("a", "1:2").is_err());
        assert!(axis("a", "1 m:2 s:3")
            .unwrap_err()
            .message
            .contains("different units"));
        assert!(axis("a", "1:2:0")
            .unwrap_err()
            .message
            .contains("whole number"));
        assert!(axis("a", "1,,2")
            .unwrap_err()
            .message
            .contains("empty value"));
        let big = |n: usize| Axis {
            name: "x".into(),
            values: vec!["1".into(); n],
        };
        let g = Cases::Grid(vec![big(1000), big(1000), big(1000)]);
        let e = g.check_count(false).unwrap_err();
        assert!(
            e.message
                .contains("1000000000 cases (1000 x × 1000 x × 1000 x)"),
            "{}",
            e.message
        );
        assert!(g.check_count(true).is_ok());
    }

    #[test]
    fn csv_fields_with_quotes() {
        assert_eq!(fields("a, \"min(1, 2)\" ,c"), ["a", "min(1, 2)", "c"]);
    }
}
