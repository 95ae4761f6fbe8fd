//! A [`cardan_dynamics`] error as a message located in the model file: at the first element it
//! names (the body without inertia, the force element, the joints left open, the function that
//! is not finite), or at `[analysis]`. Every analysis that runs the dynamics (dynamic, inverse
//! dynamics, static, quasi-static, modal, and the linearization of a dynamic run) says its
//! errors this way, each naming itself ("dynamic analysis: …", "inverse dynamics: …").

use crate::diag::Error;
use crate::prepare::Prepared;

/// A dynamics error as a message, placed at the first element it names or at `[analysis]`.
pub fn located(p: &Prepared, e: &cardan_dynamics::DynamicsError) -> Error {
    located_as(p, e, "dynamic analysis")
}

/// As [`located`], the message starting with `what` ("dynamic analysis", "inverse dynamics").
pub fn located_as(p: &Prepared, e: &cardan_dynamics::DynamicsError, what: &str) -> Error {
    use cardan_dynamics::DynamicsError as E;
    let spans = &p.loaded.spans;
    let span = match e.cause() {
        E::MissingInertia { body } => spans.element(body),
        E::BadForce { force, .. } | E::ForceLimit { force, .. } => spans.element(force),
        E::NonFinite { time, .. } => crate::functions::first_not_finite(&p.loaded, *time)
            .and_then(|(_, name)| spans.element(&name)),
        E::InconsistentPositions { open } => open.first().and_then(|o| spans.element(&o.element)),
        E::InconsistentVelocities { equations, .. }
        | E::Singular {
            dependent: equations,
            ..
        } => equations.first().and_then(|o| spans.element(&o.element)),
        E::ShapesOverlap { shape_2, .. } | E::BadShape { shape: shape_2, .. } => {
            spans.shapes.get(shape_2).cloned()
        }
        _ => None,
    }
    .unwrap_or_else(|| spans.analysis.clone());
    let mut message = format!("{what}: {}", e.cause());
    if let E::NonFinite { time, .. } = e.cause() {
        if let Some((why, _)) = crate::functions::first_not_finite(&p.loaded, *time) {
            message = format!("{message}; the cause: {why}");
        }
    }
    let mut err = Error::analysis(message);
    err.location = Some(p.source.span_location(span));
    if matches!(
        e.cause(),
        E::MissingInertia { .. } | E::BadForce { .. } | E::ShapesOverlap { .. }
    ) {
        // The file is incomplete, not the analysis failed.
        err.kind = crate::diag::ErrorKind::Input;
    }
    err
}
