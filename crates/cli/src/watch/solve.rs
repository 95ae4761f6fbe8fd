//! One solve of the live preview: the model file read with the sliders' values, its analysis
//! run in memory and its report page made, or the error as `cardan run` prints it.

use super::drag::Snapshot;
use cardan_model::analysis::{analyse, animation, RunFlags, Shown};
use cardan_model::diag::{Error, Source};
use cardan_model::parameters::expr;
use cardan_model::plot::PlotFiles;
use cardan_model::prepare::prepare_source;
use std::path::Path;
use std::sync::Arc;

/// A parameter the page offers a slider for: one defined by a value, not from others.
#[derive(Debug, Clone, PartialEq)]
pub struct Slider {
    /// The parameter.
    pub name: String,
    /// Its value in the model's units (what `--set NAME=VALUE` gives).
    pub value: f64,
    /// Its SI unit as the page shows it ("m", "1/s"; empty when plain).
    pub unit: String,
}

/// What a solve gives the page.
#[derive(Debug, Clone, Default)]
pub struct Solved {
    /// What the report page shows, when the run produced results: made into the page
    /// ([`page`]) or an update of a page already open ([`Shown::update`]) when the page asks.
    pub shown: Option<Arc<Shown>>,
    /// The model and its poses over the run, for dragging a body.
    pub snapshot: Option<Arc<Snapshot>>,
    /// The error as the command prints it (file, line, excerpt), or a run's failure.
    pub error: Option<String>,
    /// The warnings of the run.
    pub warnings: Vec<String>,
    /// The sliders (the model's independent parameters).
    pub sliders: Vec<Slider>,
}

/// Reads `path` with `set`, runs its analysis and makes its report page.
pub fn solve(path: &Path, set: &[(String, String)]) -> Solved {
    match run(path, set) {
        Ok(s) => s,
        Err(e) => Solved {
            error: Some(e.to_string()),
            ..Solved::default()
        },
    }
}

/// The report page of `shown` with three.js as a link to the server's `/three.js` instead of
/// inline: the browser keeps that script (and its compiled code) between solves, and each new
/// report is 0.67 MB lighter to load.
///
/// # Errors
/// As [`Shown::html`].
pub fn page(shown: &Shown) -> Result<String, Error> {
    let html = shown.html()?;
    let [head, _, tail] = html.parts();
    let head = head.strip_suffix("<script>").unwrap_or(head);
    let tail = tail.strip_prefix("</script>").unwrap_or(tail);
    Ok(format!("{head}<script src=\"/three.js\"></script>{tail}"))
}

fn run(path: &Path, set: &[(String, String)]) -> Result<Solved, Error> {
    let mut src = Source::read(path)?;
    src.set = set.to_vec();
    let p = prepare_source(src)?;
    let sliders = (p.loaded.parameters.list.iter())
        .filter(|q| expr::parse(&q.written).is_ok_and(|e| e.names().is_empty()))
        .map(|q| Slider {
            name: q.name.clone(),
            value: q.value.in_model_units(p.loaded.parameters.ell),
            unit: q
                .value
                .dim
                .map(|d| d.to_string())
                .filter(|u| u != "1")
                .unwrap_or_default(),
        })
        .collect();
    let Some(a) = p.loaded.analysis.clone() else {
        return Err(p
            .source
            .error("the model has no [analysis] table: the preview runs it on every save"));
    };
    let declared = p.geometry.declared()?;
    let (kind, mut analysed) = analyse(&p, &a, &RunFlags::default())?;
    let names: Vec<String> = analysed
        .tables
        .iter()
        .map(|t| format!("{}.csv", t.name))
        .collect();
    let plots = PlotFiles {
        svg: a.plots,
        png: false,
    };
    let svgs = (analysed.tables.iter())
        .filter(|t| plots.plots(&t.name))
        .map(|t| (t.name.clone(), t.to_svg()))
        .collect();
    let shown = animation(&p, kind, &mut analysed, &declared, svgs, names).map(Arc::new);
    let error = analysed.failure.as_ref().map(ToString::to_string);
    let warnings = analysed.summary.warnings.clone();
    Ok(Solved {
        shown,
        snapshot: Some(Arc::new(Snapshot {
            prepared: p,
            results: std::mem::take(&mut analysed.results),
        })),
        error,
        warnings,
        sliders,
    })
}
