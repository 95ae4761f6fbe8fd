//! URDF robot descriptions on the command line and in Python: `cardan import`, and the `.urdf`
//! input of `run` and `check` ([`cardan_urdf`]).
//!
//! As for ASMT files, a URDF is read and mapped by `cardan-urdf` (errors at the URDF line), then
//! written as a cardan model (`<file>.urdf.toml`, the text `cardan import` writes) that goes
//! through the same validation and analysis as a TOML model. Its analysis is the robot released
//! at rest in its zero configuration under gravity for 2 s (a dynamic run); an overlay model file
//! (`[urdf] file = "robot.urdf"`, [`crate::overlay`]) adds drivers, joints, forces and any other
//! analysis. Mesh paths (`package://pkg/…`, `file://…`, relative) are resolved by
//! [`resolve_mesh`] against a search path (`CARDAN_PACKAGE_PATH`, then `ROS_PACKAGE_PATH`) and
//! the file's parent directories.

use crate::diag::{Error, Location, Source};
pub use cardan_urdf::{Base, MimicMode};
use std::path::{Path, PathBuf};

/// Whether `path` names a URDF file (extension `.urdf`, any case).
pub fn is_urdf(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
}

/// How a URDF file is read (`--base`, `--mimic`, `--no-limits`, `--damping`,
/// `--friction`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UrdfOptions {
    /// The root link fixed to the ground or floating.
    pub base: Base,
    /// Mimic joints as gear couplers or free joints.
    pub mimic: MimicMode,
    /// The position limits as stops.
    pub limits: bool,
    /// Joints' `<dynamics damping>` as dampers (`--damping`).
    pub damping: bool,
    /// Joints' `<dynamics friction>` as constant friction (`--friction`).
    pub friction: bool,
    /// The links' collision shapes touch each other too (an overlay's `[urdf] self_collision`).
    pub self_collision: bool,
}

impl Default for UrdfOptions {
    fn default() -> Self {
        Self {
            base: Base::Fixed,
            mimic: MimicMode::Couple,
            limits: true,
            damping: false,
            friction: false,
            self_collision: false,
        }
    }
}

/// The imported model's name for messages: `<file>.urdf.toml`.
fn imported_path(path: &Path) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".toml");
    PathBuf::from(s)
}

/// Reads a URDF source and returns the imported cardan model text (a [`Source`] named
/// `<file>.urdf.toml`) and the import's warnings (`<file>:<line>: <sentence>`).
/// `needs_masses`: the analysis is dynamic, so a massless moving link is an error naming it.
///
/// # Errors
/// The reader's first problem, at the URDF file's line.
pub fn import_source(
    src: &Source,
    options: UrdfOptions,
    needs_masses: bool,
) -> Result<(Source, Vec<String>), Error> {
    let (text, warnings) = import_text(src, options, needs_masses, true, None)?;
    Ok((Source::from_text(imported_path(&src.path), text), warnings))
}

/// [`import_source`]'s text, with or without its default `[analysis]` (an overlay's robot,
/// [`crate::overlay`], has the overlay's), and with the links' `<collision>` elements as
/// shapes of `collision`, a material's name (an overlay's `[urdf] collision`;
/// [`cardan_urdf::collisions`]).
///
/// # Errors
/// As [`import_source`].
pub fn import_text(
    src: &Source,
    options: UrdfOptions,
    needs_masses: bool,
    analysis: bool,
    collision: Option<&str>,
) -> Result<(String, Vec<String>), Error> {
    let import = cardan_urdf::import(
        &src.text,
        cardan_urdf::Options {
            base: options.base,
            limits: options.limits,
            mimic: options.mimic,
            damping: options.damping,
            friction: options.friction,
            self_collision: options.self_collision,
            needs_masses,
        },
    )
    .map_err(|e| located(src, e))?;
    let name = src
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let search = package_path();
    let resolve = |f: &str| {
        resolve_mesh(f, &src.path, &search).map(|p| std::fs::canonicalize(&p).unwrap_or(p))
    };
    let (geometry, mesh_warnings) = cardan_urdf::visuals::visuals(&import, &resolve);
    let (shapes, shape_warnings) = match collision {
        Some(material) => {
            let taken = cardan_urdf::toml_out::feature_taken(&import);
            cardan_urdf::collisions::collision_shapes(&import, material, &resolve, &taken)
        }
        None => Default::default(),
    };
    let text = cardan_urdf::toml_out::to_toml_with(&import, &name, analysis, &geometry, &shapes);
    let warnings = import
        .warnings
        .iter()
        .chain(&mesh_warnings)
        .chain(&shape_warnings)
        .map(|w| format!("{}:{}: {}", src.path.display(), w.line, w.message))
        .collect();
    Ok((text, warnings))
}

/// A reader error at its URDF line.
pub(crate) fn located(src: &Source, e: cardan_urdf::UrdfError) -> Error {
    Error {
        location: (e.line > 0).then(|| Location {
            file: src.path.clone(),
            line: e.line,
            column: 1,
            excerpt: None,
        }),
        ..Error::input(e.message)
    }
}

/// The file a URDF mesh name refers to: `package://pkg/rest` is `<dir>/pkg/rest` for the first
/// directory of `search` that has `pkg` (or, when none has, a directory of the URDF's ancestors
/// named `pkg`); `file:///abs` is `/abs`; a relative name is relative to the URDF's directory.
/// None when no such file exists.
pub fn resolve_mesh(filename: &str, urdf: &Path, search: &[PathBuf]) -> Option<PathBuf> {
    let dir = urdf.parent().unwrap_or(Path::new("."));
    let found = |p: PathBuf| p.is_file().then_some(p);
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, tail) = rest.split_once('/')?;
        for root in search {
            if let Some(p) = found(root.join(pkg).join(tail)) {
                return Some(p);
            }
        }
        return dir
            .ancestors()
            .find(|a| a.file_name().is_some_and(|n| n == pkg))
            .and_then(|a| found(a.join(tail)))
            .or_else(|| dir.ancestors().find_map(|a| found(a.join(pkg).join(tail))));
    }
    if let Some(abs) = filename.strip_prefix("file://") {
        return found(PathBuf::from(abs));
    }
    found(dir.join(filename))
}

/// The package search path: `CARDAN_PACKAGE_PATH`, then `ROS_PACKAGE_PATH` (colon-separated).
pub fn package_path() -> Vec<PathBuf> {
    ["CARDAN_PACKAGE_PATH", "ROS_PACKAGE_PATH"]
        .iter()
        .filter_map(std::env::var_os)
        .flat_map(|v| std::env::split_paths(&v).collect::<Vec<_>>())
        .collect()
}
