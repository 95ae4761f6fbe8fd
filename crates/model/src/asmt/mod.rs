//! ASMT files (OndselSolver / FreeCAD Assembly) on the command line: `cardan import` and the
//! `.asmt` input of `run` and `check` ([`cardan_asmt`]).
//!
//! An ASMT file is read and mapped by `cardan-asmt` (errors at the ASMT line), then written as a
//! cardan model ([`cardan_asmt::toml_out`]) that goes through the same validation and analysis
//! as a TOML model: one path for both. Messages about the model after the import refer to the
//! imported model as `<file>.asmt.toml`, the text `cardan import` writes. Elements the import
//! ignores (AllowRotation, force elements) are warnings: in the summary and `run.json`
//! of a run ([`crate::prepare::Prepared::warnings`]), after `check`'s report, on stderr for
//! `import`, and as comments at the top of the imported model. `--units mm` keeps the file's
//! numbers and writes `[model] units = "mm"`: the model converts them ([`crate::units`]).

use crate::diag::{Error, Location, Source};
use std::path::{Path, PathBuf};

/// Whether `path` names an ASMT file (extension `.asmt`, any case).
pub fn is_asmt(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("asmt"))
}

/// The imported model's name for messages: `<file>.asmt.toml`.
fn imported_path(path: &Path) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".toml");
    PathBuf::from(s)
}

/// The units of an ASMT file's numbers (ASMT has no unit fields).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Units {
    /// m, kg, s, N (the Smalltalk examples).
    #[default]
    Si,
    /// mm, kg, s, N·mm (FreeCAD exports): lengths are converted to m (×1e-3), inertias to
    /// kg m² (×1e-6).
    Mm,
}

/// The analysis an imported model asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Analysis {
    /// The file's: kinematics over tstart..tend by hout.
    #[default]
    Kinematic,
    /// Inverse dynamics on the same time grid (driver efforts, reactions; needs masses).
    #[cfg_attr(feature = "clap", value(name = "inverse_dynamics"))]
    InverseDynamics,
    /// Forward dynamics from the file's pose at rest, output every hout (DOPRI5 with the
    /// file's hmax and errorTol; needs masses).
    Dynamic,
}

impl Analysis {
    /// The importer's analysis kind.
    fn kind(self) -> cardan_asmt::AnalysisKind {
        match self {
            Self::Kinematic => cardan_asmt::AnalysisKind::Kinematic,
            Self::InverseDynamics => cardan_asmt::AnalysisKind::InverseDynamics,
            Self::Dynamic => cardan_asmt::AnalysisKind::Dynamic,
        }
    }
}

/// How `run` and `check` read an ASMT file (`--units`, `--analysis`); TOML models ignore it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct AsmtOptions {
    /// The units of the file's numbers.
    pub units: Units,
    /// The analysis to run.
    pub analysis: Analysis,
    /// How a URDF file is read (`run` and `check` take `.urdf` files too).
    pub urdf: crate::urdf::UrdfOptions,
    /// Parameter values replacing a cardan model file's (`--set name=value`,
    /// [`Source::set`]); refused for ASMT and URDF files, which have no parameters.
    pub set: Vec<(String, String)>,
}

/// Reads an ASMT source and returns the imported cardan model text (as a [`Source`] named
/// `<file>.asmt.toml`, in the file's units: `[model] units = "SI"` or `"mm"`) and the import's
/// warnings (`<file>:<line>: <sentence>`).
///
/// # Errors
/// The reader's first problem, located at the ASMT file's line.
pub fn import_source(
    src: &Source,
    units: Units,
    analysis: Analysis,
) -> Result<(Source, Vec<String>), Error> {
    let located = |e: cardan_asmt::AsmtError| Error {
        location: Some(Location {
            file: src.path.clone(),
            line: e.line,
            column: 1,
            excerpt: None,
        }),
        ..Error::input(e.message.clone())
    };
    let doc = cardan_asmt::read_model(&src.text).map_err(located)?;
    let mut warnings = Vec::new();
    let doc = match units {
        Units::Mm => doc,
        Units::Si => {
            if doc.looks_like_millimetres() {
                warnings.push(format!(
                    "{}:1: the file was written by FreeCAD and reaches {:.0} length units from the origin: it looks like millimetres, but is read as SI (m, kg, s); `--units mm` reads it in millimetres",
                    src.path.display(),
                    doc.size()
                ));
            }
            doc
        }
    };
    let mut import = cardan_asmt::import(&doc).map_err(located)?;
    // Named after the file (most assemblies are called "Assembly1"): out/<file stem>/.
    if let Some(stem) = src.path.file_stem() {
        import.name = cardan_asmt::sanitize(&stem.to_string_lossy());
    }
    import.analysis = analysis.kind();
    if units == Units::Mm {
        import.units = "mm";
    }
    if import.analysis.needs_masses() {
        refuse_massless(&import, &src.path)?;
    }
    let name = src
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut text = cardan_asmt::toml_out::to_toml(&import, &name);
    if units == Units::Mm {
        text.insert_str(
            0,
            "# Read in millimetres (--units mm): the file's numbers, [model] units = \"mm\".\n",
        );
    }
    warnings.extend(
        import
            .warnings
            .iter()
            .map(|w| format!("{}:{}: {}", src.path.display(), w.line, w.message)),
    );
    Ok((Source::from_text(imported_path(&src.path), text), warnings))
}

/// Refuses a dynamic or inverse dynamics analysis of a file with parts of mass 0, naming them.
fn refuse_massless(import: &cardan_asmt::Import, path: &Path) -> Result<(), Error> {
    let massless: Vec<String> = import
        .bodies
        .iter()
        .filter(|b| b.body.mass.is_none())
        .map(|b| format!("{} (line {})", b.path, b.line))
        .collect();
    if massless.is_empty() {
        return Ok(());
    }
    let n = massless.len();
    Err(Error::input(format!(
        "{}: --analysis {} needs a mass and inertia on every part, and {n} part{} {} mass 0: {}. \
         Give {} a mass in FreeCAD (or in the model `cardan import` writes: `mass` and \
         `inertia` of the body) and run again, or run the kinematics (--analysis kinematic)",
        path.display(),
        import.analysis.name(),
        if n == 1 { "" } else { "s" },
        if n == 1 { "has" } else { "have" },
        massless.join(", "),
        if n == 1 { "it" } else { "each" },
    )))
}

/// Reads `path`: a TOML model as it is (no warnings), an ASMT or a URDF file imported as
/// `options` say (with the import's warnings, each a sentence with the file's line).
///
/// # Errors
/// Unreadable file, or an ASMT reader error.
pub fn read_model(path: &Path, options: AsmtOptions) -> Result<(Source, Vec<String>), Error> {
    let mut src = Source::read(path)?;
    if !options.set.is_empty() && (crate::urdf::is_urdf(path) || is_asmt(path)) {
        return Err(Error::usage(format!(
            "--set gives values to a cardan model's [parameters]; {} has none (an overlay model \
             file with [urdf] can have them)",
            path.display()
        )));
    }
    src.set = options.set;
    if crate::urdf::is_urdf(path) {
        return crate::urdf::import_source(&src, options.urdf, true);
    }
    if !is_asmt(path) {
        return Ok((src, Vec::new()));
    }
    import_source(&src, options.units, options.analysis)
}
