//! The oracle data of expression time functions (`oracle/data/expressions.json`, written by
//! `oracle/gen_expressions.py`): text, time and the CasADi f, ḟ, f̈ of each case; the check that
//! the cases use every function, constant and operator of the grammar.

use crate::oracle::{data_dir, RTOL};
use cardan_constraints::expression::{self, Expression};
use serde_json::Value;

/// The file name in `oracle/data/` (not a constraint element: the element gate skips it).
pub const FILE: &str = "expressions.json";

/// One case: f, ḟ, f̈ of `text` at `t`.
#[derive(Debug, Clone)]
pub struct Case {
    /// Label.
    pub label: String,
    /// The expression in cardan's grammar.
    pub text: String,
    /// The time.
    pub t: f64,
    /// [f, ḟ, f̈] from CasADi.
    pub f: [f64; 3],
}

/// Reads the cases.
pub fn load() -> Result<Vec<Case>, String> {
    let path = data_dir().join(FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{FILE}: {e}"))?;
    let cases = v["cases"].as_array().ok_or("no `cases`")?;
    cases
        .iter()
        .map(|c| {
            let f = c["f"]
                .as_array()
                .filter(|f| f.len() == 3)
                .ok_or("`f` needs 3 numbers")?;
            let num = |x: &Value| x.as_f64().ok_or("non-number");
            Ok(Case {
                label: c["label"].as_str().ok_or("no label")?.to_string(),
                text: c["text"].as_str().ok_or("no text")?.to_string(),
                t: num(&c["t"])?,
                f: [num(&f[0])?, num(&f[1])?, num(&f[2])?],
            })
        })
        .collect()
}

/// Where Rust disagrees with the case (relative [`RTOL`] of the larger magnitude, floored at 1),
/// or the parse error.
pub fn compare(case: &Case) -> Option<String> {
    let e = match Expression::parse(&case.text) {
        Ok(e) => e,
        Err(err) => return Some(format!("{}: \"{}\" {err}", case.label, case.text)),
    };
    let (v, d1, d2) = e.eval(case.t);
    let got = [v, d1, d2];
    let bad: Vec<String> = (0..3)
        .filter(|&k| {
            let (a, b) = (got[k], case.f[k]);
            // Written so that NaN disagrees.
            let agrees = (a - b).abs() <= RTOL * a.abs().max(b.abs()).max(1.0);
            !agrees
        })
        .map(|k| format!("f{} = {} vs {}", ["", "'", "''"][k], got[k], case.f[k]))
        .collect();
    (!bad.is_empty()).then(|| {
        format!(
            "{} (\"{}\" at t = {}): {}",
            case.label,
            case.text,
            case.t,
            bad.join(", ")
        )
    })
}

/// Names of the grammar (functions, variables, constants) and operators no case uses.
pub fn uncovered<'a>(names: impl IntoIterator<Item = &'a str>, cases: &[Case]) -> Vec<&'a str> {
    let words: std::collections::BTreeSet<&str> = cases
        .iter()
        .flat_map(|c| {
            c.text
                .split(|ch: char| !(ch.is_ascii_alphanumeric() || ch == '_'))
        })
        .collect();
    names
        .into_iter()
        .filter(|n| {
            if n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                !words.contains(n)
            } else {
                !cases.iter().any(|c| c.text.contains(n))
            }
        })
        .collect()
}

/// Everything the expression cases must use: the grammar's names and its operators.
pub fn vocabulary() -> Vec<&'static str> {
    expression::names()
        .chain(["+", "-", "*", "/", "^", "(", "[", "e-"])
        .collect()
}
