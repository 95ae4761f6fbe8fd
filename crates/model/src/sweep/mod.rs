//! Sweeps: one model run over many parameter values, each run reduced to a row of numbers
//! (`cardan sweep`).
//!
//! The cases ([`grid`]) are a grid of `--set` axes or the rows of a CSV file; each is the
//! model file read with those values (as `cardan run --set` reads them, [`Source::set`]) and
//! its analysis run in memory, with no file written; the outputs ([`outputs`]) reduce its
//! tables to numbers. Cases run on `jobs` threads (each reads its own model); a case that fails
//! (a model error for those values, an analysis that stops) is a row with its error, not the
//! end of the sweep. The rows come back in case order.

pub mod grid;
pub mod outputs;
pub mod plots;

use crate::analysis::{analyse, RunFlags};
use crate::diag::{Error, Source};
use crate::prepare::prepare_source;
use grid::Cases;
use outputs::Output;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// What a sweep runs.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The cases.
    pub cases: Cases,
    /// The outputs, in column order.
    pub outputs: Vec<Output>,
    /// Threads (at least 1).
    pub jobs: usize,
}

/// One case's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The values set, as given.
    pub set: Vec<(String, String)>,
    /// Each swept parameter's value in the model's units (NaN when the model was not read).
    pub parameters: Vec<f64>,
    /// Each output (NaN for a failed case).
    pub outputs: Vec<f64>,
    /// The case's error, if it failed.
    pub error: Option<String>,
    /// The case's warnings (doubtful results).
    pub warnings: Vec<String>,
}

/// Runs every case of `sweep` on the model text `src` (its own `set` ignored).
///
/// # Errors
/// The first case's model error when it names no parameter value (a mistake in the file or
/// in a `--set` name, the same for every case), an output naming a column the first case's
/// tables do not have. Later failures are rows.
pub fn run(src: &Source, sweep: &Sweep) -> Result<Vec<Row>, Error> {
    let n = usize::try_from(sweep.cases.count()).map_err(|_| Error::usage("too many cases"))?;
    // The first case alone: a mistake common to all cases stops the sweep before it starts.
    let first = case(src, sweep, 0);
    if let Err(e) = &first {
        return Err(e.clone());
    }
    let first = first.expect("checked");
    if let Some(e) = first.error.as_deref().filter(|e| e.starts_with("output ")) {
        return Err(Error::usage(e.to_string()));
    }
    let rows: Mutex<Vec<Option<Row>>> = Mutex::new(vec![None; n]);
    rows.lock().expect("fresh")[0] = Some(first);
    let next = AtomicUsize::new(1);
    std::thread::scope(|s| {
        for _ in 0..sweep.jobs.clamp(1, n.max(1)) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= n || crate::progress::stop_requested() {
                    break;
                }
                let row = match case(src, sweep, k) {
                    Ok(r) => r,
                    Err(e) => failed(sweep, k, e.to_string()),
                };
                if let Ok(mut rows) = rows.lock() {
                    rows[k] = Some(row);
                }
            });
        }
    });
    let rows = rows
        .into_inner()
        .map_err(|_| Error::output("a sweep thread panicked"))?;
    Ok(rows.into_iter().flatten().collect())
}

fn failed(sweep: &Sweep, k: usize, error: String) -> Row {
    Row {
        set: sweep.cases.case(k),
        parameters: vec![f64::NAN; sweep.cases.names().len()],
        outputs: vec![f64::NAN; sweep.outputs.len()],
        error: Some(error),
        warnings: Vec::new(),
    }
}

/// Case `k`: its row; `Err` only for a usage error (a `--set` name the file lacks, a value in
/// another unit than the file's), the same for every case.
fn case(src: &Source, sweep: &Sweep, k: usize) -> Result<Row, Error> {
    let set = sweep.cases.case(k);
    let mut source = src.clone();
    source.set = set.clone();
    let p = match prepare_source(source) {
        Ok(p) => p,
        Err(e) if e.kind == crate::diag::ErrorKind::Usage => return Err(e),
        Err(e) => return Ok(failed(sweep, k, e.to_string())),
    };
    let parameters = (set.iter())
        .map(|(name, _)| p.loaded.parameters.constant(name).unwrap_or(f64::NAN))
        .collect();
    let mut row = Row {
        set,
        parameters,
        outputs: vec![f64::NAN; sweep.outputs.len()],
        error: None,
        warnings: Vec::new(),
    };
    let Some(a) = p.loaded.analysis.clone() else {
        return Err(p
            .source
            .error("the model has no [analysis] table: a sweep runs it for every case"));
    };
    match analyse(&p, &a, &RunFlags::default()) {
        Err(e) => row.error = Some(e.to_string()),
        Ok((_, analysed)) => {
            row.warnings = analysed.summary.warnings.clone();
            if let Some(e) = &analysed.failure {
                row.error = Some(e.to_string());
            } else {
                for (slot, o) in row.outputs.iter_mut().zip(&sweep.outputs) {
                    match o.eval(&analysed.tables) {
                        Ok(v) => *slot = v,
                        Err(e) => {
                            row.error = Some(e);
                            break;
                        }
                    }
                }
            }
        }
    }
    Ok(row)
}

/// sweep.csv: a column per swept parameter (its value in the model's units), per output, then
/// `status` (ok or error) and `error` (the message, one line).
pub fn csv(sweep: &Sweep, rows: &[Row]) -> String {
    let mut header: Vec<String> = sweep.cases.names();
    header.extend(sweep.outputs.iter().map(|o| o.name.clone()));
    header.extend(["status".to_string(), "error".to_string()]);
    let mut out = header.join(",") + "\n";
    for r in rows {
        let mut f: Vec<String> = (r.parameters.iter().chain(&r.outputs))
            .map(|&v| {
                if v.is_nan() {
                    String::new()
                } else {
                    format!("{v:?}")
                }
            })
            .collect();
        f.push(if r.error.is_some() { "error" } else { "ok" }.to_string());
        let message = r.error.as_deref().unwrap_or("").replace('\n', " ");
        f.push(crate::table::csv_field(&message).into_owned());
        out += &f.join(",");
        out.push('\n');
    }
    out
}

/// run.json of a sweep: the counts, each failed case's values and error, the parameters,
/// outputs, threads, wall time and files.
pub fn run_json(
    spec: &Sweep,
    rows: &[Row],
    n: usize,
    jobs: usize,
    seconds: f64,
    stopped: bool,
    files: &[String],
) -> String {
    let failed: Vec<serde_json::Value> = (rows.iter().filter(|r| r.error.is_some()))
        .map(|r| {
            serde_json::json!({
                "set": r.set.iter().map(|(k, v)| (k.clone(), serde_json::Value::from(v.clone()))).collect::<serde_json::Map<_, _>>(),
                "error": r.error,
            })
        })
        .collect();
    let warned = rows.iter().filter(|r| !r.warnings.is_empty()).count();
    let json = serde_json::json!({
        "kind": "sweep",
        "status": if stopped { "partial" } else { "complete" },
        "cases": n,
        "run": rows.len(),
        "ok": rows.len() - failed.len(),
        "failed": failed,
        "cases_with_warnings": warned,
        "parameters": spec.cases.names(),
        "outputs": spec.outputs.iter().map(|o| serde_json::json!({"name": o.name, "expression": o.text})).collect::<Vec<_>>(),
        "jobs": jobs,
        "wall_time": seconds,
        "files": files.iter().chain(std::iter::once(&"run.json".to_string())).collect::<Vec<_>>(),
    });
    serde_json::to_string_pretty(&json).unwrap_or_default() + "\n"
}
