//! The subcommands and what they share: loading a model file into a [`Model`] and turning
//! mechanism errors into located, one-paragraph messages.

pub mod check;
pub mod eval;
pub mod run;

use crate::build::{load, Loaded};
use crate::diag::{Error, Source};
use cardan_mechanism::{AnalysisError, Model, ModelError};
use std::path::Path;

/// A model file read, validated and built.
pub struct Prepared {
    /// The file.
    pub source: Source,
    /// What the file says.
    pub loaded: Loaded,
    /// The built mechanism.
    pub model: Model,
}

/// Reads, parses, checks and builds a model file.
///
/// # Errors
/// Unreadable file, TOML syntax, unknown keys, bad values, or a [`ModelError`] from the builder
/// (located at the element it names).
pub fn prepare(path: &Path) -> Result<Prepared, Error> {
    let source = Source::read(path)?;
    let file = crate::model::parse(&source)?;
    let loaded = load(&source, &file)?;
    let model = loaded
        .builder
        .build()
        .map_err(|e| model_error(&source, &loaded, &e))?;
    Ok(Prepared {
        source,
        loaded,
        model,
    })
}

/// The element a builder error is about, if it names one.
fn model_error_element(e: &ModelError) -> Option<String> {
    Some(match e {
        ModelError::DuplicateBody { name } | ModelError::DuplicateElement { name } => name.clone(),
        ModelError::UnknownBody { element, .. }
        | ModelError::UnknownPoint { element, .. }
        | ModelError::UnknownVector { element, .. }
        | ModelError::UnknownJoint { element, .. }
        | ModelError::NotFinite { element, .. }
        | ModelError::Absurd { element, .. }
        | ModelError::SelfConnection { element, .. }
        | ModelError::GroundToGround { element }
        | ModelError::NonPositive { element, .. } => element.clone(),
        ModelError::DuplicateFeature { body, .. }
        | ModelError::ZeroVector { body, .. }
        | ModelError::BadOrientation { body, .. }
        | ModelError::NonPositiveMass { body, .. }
        | ModelError::InertiaNotSymmetric { body, .. }
        | ModelError::InertiaNotPositiveDefinite { body, .. } => body.clone(),
        ModelError::MissingAxis { joint, .. } | ModelError::BadMarker { joint, .. } => {
            joint.clone()
        }
        ModelError::WrongJointKind { driver, .. } | ModelError::BadTimeFunction { driver, .. } => {
            driver.clone()
        }
        _ => return None,
    })
}

/// Strips a `joint "x"` / `driver "x"` / `body "x"` prefix to the bare name.
fn bare(element: &str) -> &str {
    match element.split_once('"') {
        Some((_, rest)) => rest.split('"').next().unwrap_or(rest),
        None => element,
    }
}

fn model_error(src: &Source, loaded: &Loaded, e: &ModelError) -> Error {
    let span = model_error_element(e).and_then(|el| loaded.spans.element(bare(&el)));
    let message = format!("invalid model: {e}");
    match span {
        Some(s) => src.error_at(s, message),
        None => src.error(message),
    }
}

/// Turns an analysis error into a message, located at the element concerned when possible.
pub fn analysis_error(p: &Prepared, e: &AnalysisError) -> Error {
    let spans = &p.loaded.spans;
    let located = |span: Option<std::ops::Range<usize>>, message: String| {
        let mut err = Error::analysis(message);
        if let Some(s) = span {
            err.location = Some(p.source.location(s.start));
        }
        err
    };
    match e {
        AnalysisError::DriverCount { dof, drivers } => {
            let names: Vec<&str> = p.loaded.drivers.iter().map(|(n, _)| n.as_str()).collect();
            let mut err = located(
                spans.first_driver.clone().or(Some(spans.analysis.clone())),
                format!(
                    "a kinematic analysis needs exactly as many drivers as the mechanism has degrees \
                     of freedom: the joints leave {dof} DOF, but the file has {drivers} driver{} ({}); {}",
                    if *drivers == 1 { "" } else { "s" },
                    if names.is_empty() { "none".to_string() } else { names.join(", ") },
                    if dof > drivers {
                        format!("add {} driver{} (or joints)", dof - drivers, if dof - drivers == 1 { "" } else { "s" })
                    } else {
                        format!("remove {} driver{}", drivers - dof, if drivers - dof == 1 { "" } else { "s" })
                    }
                ),
            );
            err.kind = crate::diag::ErrorKind::Input;
            err
        }
        AnalysisError::AssemblyFailed { open, iterations } => {
            let list: Vec<String> = open
                .iter()
                .map(|o| format!("\"{}\" (|Φ| = {:.3e})", o.element, o.residual))
                .collect();
            located(
                open.first().and_then(|o| spans.element(&o.element)),
                format!(
                    "the mechanism cannot be assembled: after {iterations} Newton iterations these \
                     joints/drivers stay open: {}. Check the point coordinates and lengths of these \
                     elements (can the loop close at all?) and the initial positions of the bodies",
                    list.join(", ")
                ),
            )
        }
        AnalysisError::DependentDrivers { dependent } => {
            let names: Vec<String> = dependent.iter().map(|d| d.to_string()).collect();
            located(
                dependent.first().and_then(|d| spans.element(&d.element)),
                format!(
                    "the drivers do not control the mechanism: {} depend on the joints or on other \
                     drivers; drive a different joint",
                    names.join(", ")
                ),
            )
        }
        AnalysisError::Singular {
            time, dependent, ..
        } => {
            let names: Vec<String> = dependent.iter().map(|d| d.to_string()).collect();
            located(
                dependent.first().and_then(|d| spans.element(&d.element)),
                format!(
                    "singular configuration reached at t = {time} s: the constraint Jacobian lost \
                     rank; dependent equations: {} (a dead point, a lock-up or a change of assembly \
                     branch)",
                    if names.is_empty() { "not identified".to_string() } else { names.join(", ") }
                ),
            )
        }
        AnalysisError::NotConverged {
            time,
            iterations,
            worst,
            ..
        } => {
            let names: Vec<String> = worst
                .iter()
                .map(|(e, r)| format!("{e} (scaled residual {r:.3e})"))
                .collect();
            located(
                worst.first().and_then(|(d, _)| spans.element(&d.element)),
                format!(
                    "the position analysis did not converge at t = {time} s after {iterations} \
                     iterations (the mechanism may have reached a limit of its motion or a singular \
                     configuration); worst equations: {}",
                    names.join(", ")
                ),
            )
        }
        other => Error::analysis(format!("{other}")),
    }
}
