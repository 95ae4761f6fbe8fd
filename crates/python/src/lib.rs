//! # cardan-python: the native part of the `cardan` Python package
//!
//! The extension module `cardan._cardan`, wrapped by the pure-Python package in `python/cardan`
//! (which users import). It runs a model file's analysis through the same code as the `cardan`
//! command ([`cardan_cli`]), so the tables, their headers and their CSV text are the command's
//! own, and hands them to Python as plain data:
//!
//! - `run`: a model text (with the path it came from, for messages and relative files), an
//!   optional analysis kind and `[analysis]` keys to set → a dict with every output table as
//!   packed little-endian `float64` rows (numpy reads them without a copy per value), the
//!   `run.json` text, and the error if the run failed or stopped early (with its partial
//!   tables). The analysis runs on another thread (module `workers`: kept for the next run) with
//!   the GIL released; the calling thread polls for Python signals, so Ctrl-C stops the run at
//!   its next step and keeps its results.
//! - `check`: degrees of freedom, redundant equations and driver counts.
//! - `table_csv`: a table's CSV text exactly as `cardan run` writes it.
//! - `prepare`: a model text read, validated and built (what `cardan.Model` does when it is
//!   made), as an opaque handle (module `prepared`) that `run`, `check` and `drag` take beside the
//!   text so as not to read it again.
//! - `import_asmt`: an ASMT file as model text (and prepared).
//! - `import_urdf`: a URDF robot as model text (and prepared).
//! - `drag`: one drag step (a point of a body pulled toward a target, the rest by least change).
//! - `main`: the `cardan` command itself (`python -m cardan`).
//!
//! Errors of the model or the analysis are returned as data (`kind`, `message`, `file`,
//! `line`, `column`), and the Python layer raises `cardan.ModelError`, `cardan.SolverError` or
//! `cardan.AnalysisError` from them.

mod analysis;
mod convert;
mod drag;
mod prepared;
mod workers;

use cardan_cli::Error;
use cardan_mechanism::AssemblyOptions;
use cardan_model::analysis::{analyse, animation, run_json, RunFlags};
use cardan_model::diag::Source;
use cardan_model::plot::PlotFiles;
use cardan_model::prepare::analysis_error;
use cardan_model::progress;
use cardan_model::table::Table;
use convert::{error_dict, table_tuple, ErrorData};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

/// How often the calling thread looks for Ctrl-C while an analysis runs.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// What a run hands back to Python.
struct RunData {
    /// "kinematic", "inverse_dynamics" or "dynamic" (empty when nothing ran).
    kind: &'static str,
    /// The output tables (partial when `error` is set).
    tables: Vec<Table>,
    /// `run.json` as `cardan run` would write it (empty when nothing ran).
    run_json: String,
    /// The failure, if any.
    error: Option<ErrorData>,
    /// Wall time of the Rust side: reading, building, analysing [s].
    seconds: f64,
    /// With `report`: `animation.glb` and `index.html`.
    report: Option<(Vec<u8>, String)>,
    /// Files other than the tables (name, text): a modal run's matrices.
    files: Vec<(String, String)>,
}

/// What `run` was asked for: the model text `text` (read from `path`; `handle` its `Model`'s
/// prepared text, used when the text the run takes is that one), the analysis `kind` and
/// `[analysis]` keys `options` set over the file's, `strict` as `--strict` and `report` for the
/// animation and the report page.
struct Request {
    text: String,
    path: String,
    handle: Option<prepared::Prepared>,
    kind: Option<String>,
    options: Vec<(String, analysis::Value)>,
    strict: bool,
    report: bool,
}

/// Runs the analysis of a [`Request`].
fn run_text(r: Request) -> RunData {
    let start = Instant::now();
    let failed = |e: &Error| RunData {
        kind: "",
        tables: Vec::new(),
        run_json: String::new(),
        error: Some(ErrorData::from(e)),
        seconds: start.elapsed().as_secs_f64(),
        report: None,
        files: Vec::new(),
    };
    // Without analysis keys to set, the text is the Model's own and its handle serves.
    let prepared = analysis::set_analysis(&r.text, r.kind.as_deref(), &r.options)
        .map_err(Error::input)
        .and_then(|text| prepared::model_of(text, r.path, r.handle.as_ref()));
    let p = match prepared {
        Ok(p) => p,
        Err(e) => return failed(&e),
    };
    let Some(a) = p.loaded.analysis.clone() else {
        return failed(&p.source.error(
            "the model has no [analysis] table, so there is nothing to run; give the analysis \
             settings as arguments, e.g. model.kinematics(t_end=1.0, steps=100)",
        ));
    };
    let flags = RunFlags {
        strict: r.strict,
        ..RunFlags::default()
    };
    // The geometry is checked before the analysis, as `cardan run` does.
    let declared = match r.report.then(|| p.geometry.declared()).transpose() {
        Ok(d) => d,
        Err(e) => return failed(&e),
    };
    match analyse(&p, &a, &flags) {
        Err(e) => failed(&e),
        Ok((kind, mut analysed)) => {
            let names: Vec<String> = analysed
                .tables
                .iter()
                .map(|t| format!("{}.csv", t.name))
                .collect();
            let page = match &declared {
                Some(d) => {
                    let svgs = analysed
                        .tables
                        .iter()
                        .filter(|t| {
                            PlotFiles {
                                svg: a.plots,
                                png: false,
                            }
                            .plots(&t.name)
                        })
                        .map(|t| (t.name.clone(), t.to_svg()))
                        .collect();
                    match animation(&p, kind, &mut analysed, d, svgs, names.clone()) {
                        Some(shown) => match shown.html() {
                            Ok(html) => Some((shown.glb, html.to_string())),
                            Err(e) => return failed(&e),
                        },
                        None => None,
                    }
                }
                None => None,
            };
            let json = run_json(&p, kind, &analysed, names);
            // A `strict` failure (warnings) is told apart from the solver's own.
            let error = analysed.failure.as_ref().map(ErrorData::from).or_else(|| {
                analysed
                    .strict_failure
                    .as_ref()
                    .map(|e| ErrorData::from(e).strict())
            });
            RunData {
                kind,
                tables: analysed.tables,
                run_json: json,
                error,
                seconds: start.elapsed().as_secs_f64(),
                report: page,
                files: std::mem::take(&mut analysed.files),
            }
        }
    }
}

/// Runs a model's analysis (see the module docs). Returns a dict with `kind`, `tables` (a
/// list of `(name, title, columns, data, rows)`), `run_json`, `error` (a dict or `None`),
/// `interrupted` (Ctrl-C), `seconds` (the Rust side's wall time), `glb` and `html` (the
/// animation and the report page, with `report`; else `None`) and `files` (other output
/// files as `(name, text)`: a modal run's matrices).
#[pyfunction]
#[pyo3(signature = (text, path, kind=None, options=None, strict=false, report=false, model=None))]
#[allow(clippy::too_many_arguments)]
fn run<'py>(
    py: Python<'py>,
    text: String,
    path: String,
    kind: Option<String>,
    options: Option<&Bound<'py, PyDict>>,
    strict: bool,
    report: bool,
    model: Option<&Bound<'py, prepared::Prepared>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = match options {
        Some(d) => analysis::options_from_dict(d)?,
        None => Vec::new(),
    };
    let handle = model.map(|m| m.get().clone());
    let (send, recv) = mpsc::channel();
    // A Mutex makes the receiver shareable with the GIL-free closure below.
    let recv = Mutex::new(recv);
    let started = workers::run(move || {
        let _ = send.send(run_text(Request {
            text,
            path,
            handle,
            kind,
            options,
            strict,
            report,
        }));
    });
    if let Err(e) = started {
        return Err(pyo3::exceptions::PyRuntimeError::new_err(format!(
            "cannot start a thread for the analysis: {e}"
        )));
    }
    let mut interrupt: Option<PyErr> = None;
    let data = loop {
        let wait = || match recv.lock() {
            Ok(r) => r.recv_timeout(SIGNAL_POLL),
            Err(_) => Err(mpsc::RecvTimeoutError::Disconnected),
        };
        match py.detach(wait) {
            Ok(data) => break data,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if interrupt.is_none() {
                    if let Err(e) = py.check_signals() {
                        progress::request_stop();
                        interrupt = Some(e);
                    }
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                progress::clear_stop();
                return Err(pyo3::exceptions::PyRuntimeError::new_err(
                    "the analysis thread ended without a result (a bug in cardan: please report \
                     it with the model file)",
                ));
            }
        }
    };
    progress::clear_stop();
    let out = PyDict::new(py);
    out.set_item("kind", data.kind)?;
    let tables = PyList::empty(py);
    for t in &data.tables {
        tables.append(table_tuple(py, t)?)?;
    }
    out.set_item("tables", tables)?;
    out.set_item("run_json", data.run_json)?;
    match &data.error {
        Some(e) => out.set_item("error", error_dict(py, e)?)?,
        None => out.set_item("error", py.None())?,
    }
    out.set_item("interrupted", interrupt.is_some())?;
    out.set_item("seconds", data.seconds)?;
    match data.report {
        Some((glb, html)) => {
            out.set_item("glb", pyo3::types::PyBytes::new(py, &glb))?;
            out.set_item("html", html)?;
        }
        None => {
            out.set_item("glb", py.None())?;
            out.set_item("html", py.None())?;
        }
    }
    out.set_item("files", data.files)?;
    Ok(out)
}

/// Degrees of freedom, redundant equations and element counts of a model text: a dict, or an
/// error dict under the key `error`.
#[pyfunction]
#[pyo3(signature = (text, path, model=None))]
fn check<'py>(
    py: Python<'py>,
    text: String,
    path: String,
    model: Option<&Bound<'py, prepared::Prepared>>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let Some(p) = prepared::model_or_error(py, &out, text, path, model.map(Bound::get))? else {
        return Ok(out);
    };
    let model = &p.model;
    let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let mut ws = model.workspace();
    let opts = cardan_mechanism_assembly(t0);
    let dof = model.assemble(&mut ws, &opts).and_then(|_| model.dof(&ws));
    let dof = match dof {
        Ok(d) => d,
        Err(e) => {
            let err = analysis_error(&p, &e);
            out.set_item("error", error_dict(py, &ErrorData::from(&err))?)?;
            return Ok(out);
        }
    };
    out.set_item("name", &p.loaded.name)?;
    out.set_item(
        "bodies",
        model
            .bodies()
            .iter()
            .map(|b| b.name.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "joints",
        model
            .joints()
            .iter()
            .map(|j| j.name.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "drivers",
        model
            .drivers()
            .iter()
            .map(|d| d.name.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item("unknowns", model.num_unknowns())?;
    out.set_item("joint_equations", model.num_joint_equations())?;
    out.set_item("equations", model.num_equations())?;
    out.set_item("rank", dof.rank)?;
    out.set_item("dof", dof.dof)?;
    let redundant: Vec<String> = dof.redundant.iter().map(|e| e.to_string()).collect();
    out.set_item("redundant", redundant)?;
    out.set_item("error", py.None())?;
    Ok(out)
}

/// Assembly options of `cardan check`: the joints alone, at the analysis start time.
fn cardan_mechanism_assembly(t0: f64) -> AssemblyOptions {
    AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(t0)
    }
}

/// The CSV text of a table as `cardan run` writes it: `data` holds the rows (time first) as
/// packed little-endian `float64`, `columns` the headers without the time column.
#[pyfunction]
fn table_csv(name: String, title: String, columns: Vec<String>, data: &[u8]) -> PyResult<String> {
    let table = convert::table_from_bytes(name, title, columns, data)
        .map_err(pyo3::exceptions::PyValueError::new_err)?;
    Ok(table.to_csv())
}

/// An ASMT assembly (OndselSolver / FreeCAD) as cardan model text: a dict with `text` (the
/// imported model in the file's units, `[model] units`), `path` (its name, `<file>.asmt.toml`)
/// and `warnings` (the elements read but ignored, a millimetre file read as SI), or `error`.
/// `units` is `"si"` or `"mm"` (`[model] units = "mm"`: results in mm). `text` is the file's
/// text, or `None` to read the file at `path`.
#[pyfunction]
#[pyo3(signature = (text, path, units="si", inverse_dynamics=false))]
fn import_asmt<'py>(
    py: Python<'py>,
    text: Option<String>,
    path: String,
    units: &str,
    inverse_dynamics: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use cardan_model::asmt::{import_source, Analysis, Units};
    let units = match units {
        "si" | "SI" => Units::Si,
        "mm" => Units::Mm,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "units {other:?}: use \"si\" (m, kg, s) or \"mm\" (FreeCAD's millimetres)"
            )))
        }
    };
    let analysis = if inverse_dynamics {
        Analysis::InverseDynamics
    } else {
        Analysis::Kinematic
    };
    imported(
        py,
        py.detach(|| source(text, path).and_then(|s| import_source(&s, units, analysis))),
    )
}

/// The file an import reads: `text` read from `path`, or (`None`) the file at `path` read here
/// (Rust reads a large assembly faster than Python hands its text over).
fn source(text: Option<String>, path: String) -> Result<Source, cardan_model::diag::Error> {
    match text {
        Some(text) => Ok(Source::from_text(path, text)),
        None => Source::read(std::path::Path::new(&path)),
    }
}

/// The dict of an import: `text`, `path`, `warnings`, `prepared` (the model text prepared, as
/// `prepare` returns it) and `error` None, or `error`.
fn imported<'py>(
    py: Python<'py>,
    result: Result<(Source, Vec<String>), cardan_model::diag::Error>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    match result {
        Ok((model, warnings)) => {
            let path = model.path.display().to_string();
            let handle = py.detach(|| prepared::Prepared::new(model.text.clone(), path.clone()));
            out.set_item("prepared", prepared::prepared_dict(py, handle)?)?;
            out.set_item("text", model.text)?;
            out.set_item("path", path)?;
            out.set_item("warnings", warnings)?;
            out.set_item("error", py.None())?;
        }
        Err(e) => out.set_item("error", error_dict(py, &ErrorData::from(&e))?)?,
    }
    Ok(out)
}

/// A URDF robot as cardan model text: a dict with `text` (the imported model), `path` (its
/// name, `<file>.urdf.toml`) and `warnings`, or `error`. `base` is `"fixed"` or `"floating"`,
/// `mimic` `"couple"` or `"free"`; `limits` writes the position limits as stops; `damping`
/// the joints' `<dynamics damping>` as dampers, `friction` their `<dynamics friction>` as
/// constant friction. `text` is the file's text, or `None` to read the file at `path`.
#[pyfunction]
#[pyo3(signature = (text, path, base="fixed", mimic="couple", limits=true, damping=false, friction=false))]
fn import_urdf<'py>(
    py: Python<'py>,
    text: Option<String>,
    path: String,
    base: &str,
    mimic: &str,
    limits: bool,
    damping: bool,
    friction: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use cardan_model::urdf::{import_source, Base, MimicMode, UrdfOptions};
    let bad = |key: &str, v: &str, words: &str| {
        pyo3::exceptions::PyValueError::new_err(format!("{key}={v:?}: use {words}"))
    };
    let base = match base {
        "fixed" => Base::Fixed,
        "floating" => Base::Floating,
        other => return Err(bad("base", other, "\"fixed\" or \"floating\"")),
    };
    let mimic = match mimic {
        "couple" => MimicMode::Couple,
        "free" => MimicMode::Free,
        other => return Err(bad("mimic", other, "\"couple\" or \"free\"")),
    };
    let options = UrdfOptions {
        base,
        mimic,
        limits,
        damping,
        friction,
        // Collision shapes come from an overlay's [urdf] only.
        self_collision: false,
    };
    imported(
        py,
        py.detach(|| source(text, path).and_then(|s| import_source(&s, options, true))),
    )
}

/// The model text with parameters given values (`values`: name → text, as `--set` reads them):
/// `{"text": new text, "error": None}` or `{"text": None, "error": error dict}`.
#[pyfunction]
fn with_parameters<'py>(
    py: Python<'py>,
    text: String,
    path: String,
    values: Vec<(String, String)>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = py.detach(|| {
        let mut src = Source::from_text(path, text);
        src.set = values;
        cardan_model::parameters::rewrite(&src).map_err(|e| ErrorData::from(&e))
    });
    outcome_dict(py, "text", out)
}

/// `{key: value, "error": None}` or `{key: None, "error": error dict}`.
fn outcome_dict<'py, T: IntoPyObject<'py>>(
    py: Python<'py>,
    key: &str,
    out: Result<T, ErrorData>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match out {
        Ok(value) => {
            d.set_item(key, value)?;
            d.set_item("error", py.None())?;
        }
        Err(e) => {
            d.set_item(key, py.None())?;
            d.set_item("error", error_dict(py, &e)?)?;
        }
    }
    Ok(d)
}

/// The model's parameters: `{"parameters": [(name, SI value, SI unit, number in the model's
/// units, as written), ...], "error": None}` or `{"parameters": None, "error": error dict}`.
#[pyfunction]
fn parameters<'py>(py: Python<'py>, text: String, path: String) -> PyResult<Bound<'py, PyDict>> {
    type Row = (String, f64, String, f64, String);
    let out = py.detach(|| -> Result<Vec<Row>, ErrorData> {
        let src = Source::from_text(path, text);
        let file = cardan_model::file::parse(&src).map_err(|e| ErrorData::from(&e))?;
        let p = &file.parameters;
        Ok((p.list.iter())
            .map(|q| {
                let unit = q.value.dim.map_or(String::new(), |d| {
                    if d == cardan_model::parameters::quantity::Dim::NONE {
                        String::new()
                    } else {
                        d.to_string()
                    }
                });
                let model = q.value.in_model_units(p.ell);
                (
                    q.name.clone(),
                    q.value.value,
                    unit,
                    model,
                    q.written.clone(),
                )
            })
            .collect())
    });
    outcome_dict(py, "parameters", out)
}

/// The `cardan` command itself with the arguments `argv` (the first is the program name, as
/// in `sys.argv`): what `python -m cardan` runs. Prints as the command does and returns its
/// exit code; runs with the GIL released.
#[pyfunction]
fn main(py: Python<'_>, argv: Vec<String>) -> i32 {
    py.detach(|| cardan_cli::main_with_args(argv.into_iter().map(std::ffi::OsString::from)))
}

/// The extension module `cardan._cardan`.
#[pymodule]
fn _cardan(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(prepared::prepare, m)?)?;
    m.add_class::<prepared::Prepared>()?;
    m.add_function(wrap_pyfunction!(with_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(parameters, m)?)?;
    m.add_function(wrap_pyfunction!(main, m)?)?;
    m.add_function(wrap_pyfunction!(table_csv, m)?)?;
    m.add_function(wrap_pyfunction!(import_asmt, m)?)?;
    m.add_function(wrap_pyfunction!(import_urdf, m)?)?;
    m.add_function(wrap_pyfunction!(drag::drag, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
