//! The subcommands and what they share: loading a model file into a [`Model`] and turning
//! mechanism errors into located, one-paragraph messages.

use crate::build::{load, Loaded};
use crate::diag::{Error, Source};
use crate::number::num;
use crate::units::coordinate_units;
use cardan_mechanism::{AnalysisError, Model, ModelError};
use std::path::Path;

/// A model file read, validated and built.
pub struct Prepared {
    /// The file that was read (an ASMT file's own path; `source` is then its imported model).
    pub file: std::path::PathBuf,
    /// The model text (an ASMT file's imported model, named `<file>.asmt.toml` in messages).
    pub source: Source,
    /// What the file says.
    pub loaded: Loaded,
    /// The built mechanism.
    pub model: Model,
    /// Warnings about the model itself, before any analysis: an ASMT file's elements read and
    /// ignored (`<file>:<line>: <sentence>`). A run puts them first in its summary's warnings.
    pub warnings: Vec<String>,
    /// The model's units (`[model] units`), in which the outputs are written (the analyses
    /// work in SI).
    pub units: crate::units::UnitSystem,
    /// The animation's declared geometry, taken from the file as it is parsed (once) and read
    /// (mesh files) when first asked for: by the commands that draw or check it (`run`,
    /// `check`), which refuse a model whose geometry cannot be read.
    pub geometry: crate::geometry::LazyGeometry,
}

/// Reads, parses, checks and builds a model file.
///
/// # Errors
/// Unreadable file, TOML syntax, unknown keys, bad values, or a [`ModelError`] from the builder
/// (located at the element it names).
pub fn prepare(path: &Path) -> Result<Prepared, Error> {
    prepare_with(path, crate::asmt::AsmtOptions::default())
}

/// [`prepare`] reading an ASMT file as `options` say (`--units`, `--analysis`), with the
/// import's warnings in [`Prepared::warnings`].
///
/// # Errors
/// As [`prepare`].
pub fn prepare_with(path: &Path, options: crate::asmt::AsmtOptions) -> Result<Prepared, Error> {
    let (source, warnings) = crate::asmt::read_model(path, options)?;
    let mut p = prepare_source(source)?;
    p.warnings.splice(0..0, warnings);
    p.file = path.to_path_buf();
    Ok(p)
}

/// [`prepare`] for a model file already read (or written by a program): `source.path` names it
/// in messages and anchors the paths the file refers to.
///
/// # Errors
/// As [`prepare`], except reading.
pub fn prepare_source(source: Source) -> Result<Prepared, Error> {
    let (source, mut file, warnings) = crate::overlay::parse_overlaid(source)?;
    let loaded = load(&source, &file)?;
    let geometry = crate::geometry::LazyGeometry::take(&source, &mut file);
    drop(file);
    let model = loaded
        .builder
        .build()
        .map_err(|e| model_error(&source, &loaded, &e))?;
    validate_forces(&source, &loaded, &model)?;
    if let Some(a) = &loaded.analysis {
        check_driver_values(&source, &loaded, &a.times())?;
        if a.has_forces() {
            crate::functions::check_force_values(&source, &loaded, &a.times())?;
        }
    }
    let units = loaded.units;
    Ok(Prepared {
        file: source.path.clone(),
        source,
        loaded,
        model,
        warnings,
        units,
        geometry,
    })
}

/// The one validation of the force elements and the collision shapes, the dynamics. own
/// ([`cardan_dynamics::Force::validate`]), run when the model is read (so `cardan check` reports
/// it too), its error placed at the key it names.
///
/// # Errors
/// An input error naming the force, at the key (or at the element's name).
fn validate_forces(src: &Source, loaded: &Loaded, model: &Model) -> Result<(), Error> {
    for f in &loaded.forces {
        let Err(e) = f.validate(model) else {
            continue;
        };
        let span = match &e {
            cardan_dynamics::DynamicsError::BadForce { force, key, .. } => {
                let site = cardan_mechanism::Site {
                    kind: cardan_mechanism::ElementKind::Force,
                    name: force.clone(),
                    field: key.map(str::to_string),
                    value: None,
                };
                loaded.spans.locate(&src.text, &site)
            }
            _ => None,
        };
        return Err(match span {
            Some(s) => src.error_at(s, e.to_string()),
            None => src.error(e.to_string()),
        });
    }
    // The collision shapes as the geometry library takes them (a hull it cannot build, a
    // triangle mesh that is not manifold), at the shape's mesh.
    if let Err((shape, reason)) = cardan_dynamics::collision::validate_shapes(model) {
        let span = loaded
            .spans
            .locate_contact(&src.text, "shape", &shape, "file")
            .or_else(|| {
                loaded
                    .spans
                    .locate_contact(&src.text, "shape", &shape, "points")
            });
        let message = format!("shape \"{shape}\": {reason}");
        return Err(match span {
            Some(s) => src.error_at(s, message),
            None => src.error(message),
        });
    }
    Ok(())
}

/// Refuses a driver whose prescribed value, rate or acceleration is not finite at one of
/// `times` (a polynomial that overflows, `eval --t 1e308`), or whose value is beyond the
/// magnitude limit of its quantity (an angle or a length, `cardan_mechanism::Quantity`): the
/// analysis would fail there with a message about an equation number instead of the driver.
/// Located at the driver.
///
/// # Errors
/// An input error naming the driver and the time.
pub fn check_driver_values(src: &Source, loaded: &Loaded, times: &[f64]) -> Result<(), Error> {
    let names = loaded.drivers.iter().map(|(n, _)| n);
    for (name, (f, q)) in names.zip(&loaded.driver_functions) {
        let located = |message: String| match loaded.spans.drivers.get(name) {
            Some(s) => src.error_at(s.clone(), message),
            None => src.error(message),
        };
        for &t in times {
            if let Some(why) = crate::functions::not_finite(f, t) {
                return Err(located(format!(
                    "driver \"{name}\": its function is not finite at t = {} s ({why}): the \
                     prescribed motion is undefined or overflows there; use another time span \
                     or change the function",
                    num(t)
                )));
            }
            let v = f.eval(t).0;
            q.check(
                format_args!("driver \"{name}\": at t = {} s its value", num(t)),
                v,
            )
            .map_err(located)?;
        }
    }
    Ok(())
}

/// A builder error, located at what it is about (the key's value, the unknown name, or the
/// element) in the model file.
fn model_error(src: &Source, loaded: &Loaded, e: &ModelError) -> Error {
    let span = match (e.limit_site(), e.contact_site()) {
        (Some((name, key)), _) => loaded.spans.locate_limit(&src.text, name, key),
        (None, Some((table, name, key))) => {
            loaded.spans.locate_contact(&src.text, table, name, key)
        }
        (None, None) => e.site().and_then(|s| loaded.spans.locate(&src.text, &s)),
    };
    let message = format!("invalid model: {e}");
    match span {
        Some(s) => src.error_at(s, message),
        None => src.error(message),
    }
}

/// "s" for a count other than 1.
fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// What to add to a mechanism with `missing` undriven degrees of freedom, naming the free joint
/// coordinates where they can be told ([`crate::free_dof::free_coordinates`]), and the dynamic analysis
/// that needs no drivers.
pub fn under_driven_advice(p: &Prepared, missing: usize) -> String {
    let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let free = match crate::free_dof::free_coordinates(&p.model, t0) {
        Some(names) => format!(" ({} free)", names.join(", ")),
        None => String::new(),
    };
    format!(
        "add {missing} driver{}{free}, a rotation or translation driver for each coordinate \
         whose motion you prescribe, or use kind = \"dynamic\" to simulate the motion that \
         gravity and the forces produce",
        plural(missing)
    )
}

/// The one-paragraph error of an inverse dynamics run on a model that is not fully driven.
pub fn not_fully_driven(p: &Prepared, dof: usize, drivers: usize) -> Error {
    let names: Vec<&str> = p.loaded.drivers.iter().map(|(n, _)| n.as_str()).collect();
    let s = |n: usize| if n == 1 { "" } else { "s" };
    let advice = if dof > drivers && !p.model.stops().is_empty() {
        format!(
            "{}; a coordinate whose start lies on a [[limit]]'s bound counts as driven (its stop \
             holds it and reports the reaction) when as many stops as missing drivers are met",
            under_driven_advice(p, dof - drivers)
        )
    } else if dof > drivers {
        under_driven_advice(p, dof - drivers)
    } else if drivers > dof {
        let n = drivers - dof;
        format!("remove {n} driver{} (or add joints)", s(n))
    } else {
        "the model is a structure: nothing moves and no driver exerts an effort; add the joint \
         to drive and its driver"
            .to_string()
    };
    let span = p
        .loaded
        .spans
        .first_driver
        .clone()
        .unwrap_or_else(|| p.loaded.spans.analysis.clone());
    p.source.error_at(
        span,
        format!(
            "inverse dynamics needs a fully driven mechanism, with as many drivers as the joints \
             leave degrees of freedom (at least one): the joints leave {dof} DOF and the file \
             has {drivers} driver{} ({}); {advice}",
            s(drivers),
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            },
        ),
    )
}

/// Turns an analysis error into a message, located at the element concerned when possible.
pub fn analysis_error(p: &Prepared, e: &AnalysisError) -> Error {
    let spans = &p.loaded.spans;
    let located = |span: Option<std::ops::Range<usize>>, message: String| {
        let mut err = Error::analysis(message);
        if let Some(s) = span {
            err.location = Some(p.source.span_location(s));
        }
        err
    };
    match e {
        AnalysisError::DriverCount { dof, drivers } => {
            let names: Vec<&str> = p.loaded.drivers.iter().map(|(n, _)| n.as_str()).collect();
            let advice = if dof > drivers {
                under_driven_advice(p, dof - drivers)
            } else {
                format!("remove {} driver{}", drivers - dof, plural(drivers - dof))
            };
            let mut err = located(
                spans.first_driver.clone().or(Some(spans.analysis.clone())),
                format!(
                    "a kinematic analysis needs exactly as many drivers as the mechanism has degrees \
                     of freedom: the joints leave {dof} DOF, but the file has {drivers} driver{} ({}); {advice}",
                    plural(*drivers),
                    if names.is_empty() { "none".to_string() } else { names.join(", ") },
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
            partial,
        } => {
            let names: Vec<String> = worst
                .iter()
                .take(3)
                .map(|(e, r)| format!("{e} (scaled residual {r:.3e})"))
                .collect();
            let cond = partial.as_deref().and_then(|r| conditioning(p, r));
            let hint = cond.as_ref().map_or(String::new(), |c| c.describe());
            located(
                worst.first().and_then(|(d, _)| spans.element(&d.element)),
                format!(
                    "the position analysis did not converge at t = {time} s after {iterations} \
                     iterations ({}); worst equations: {}{hint}",
                    Conditioning::cause(cond.as_ref()),
                    names.join(", ")
                ),
            )
        }
        AnalysisError::Discontinuous { worst, .. } => located(
            worst.first().and_then(|(d, _)| spans.element(&d.element)),
            format!("{e}"),
        ),
        AnalysisError::InconsistentJoints { dropped, .. } => located(
            dropped
                .first()
                .and_then(|d| spans.element(&d.equation.element)),
            format!(
                "{e}. To run it as OndselSolver does, with these rows dropped and left open (a \
                 warning names them and their residual), set inconsistent_joints = \"drop\" in \
                 [analysis]{}",
                if p.source.path.to_string_lossy().contains(".asmt") {
                    " of the model `cardan import` writes from this file"
                } else {
                    ""
                }
            ),
        ),
        AnalysisError::DriverBranch { driver, .. } => {
            located(spans.element(driver), format!("{e}"))
        }
        AnalysisError::LimitReached {
            limit,
            joint,
            coordinate,
            bound_name,
            bound,
            time,
            value,
            ..
        } => {
            // In the model's units, as the file says the bound.
            let si = (p.model.limits().iter().find(|l| &l.name == limit))
                .map_or("rad", |l| coordinate_units(l.measure.quantity()).coordinate);
            let (unit, f) = p.units.unit(si);
            let shown = |x: f64| num(format!("{:.11e}", x * f).parse().unwrap_or(x));
            located(
                spans.locate_limit(&p.source.text, limit, bound_name),
                format!(
                    "limit \"{limit}\" reached at t = {time}: joint \"{joint}\" has {coordinate} = \
                     {} {unit} at its {bound_name} bound {} {unit}; the prescribed motion drives it \
                     past the stop",
                    shown(*value),
                    shown(*bound)
                ),
            )
        }
        other => Error::analysis(format!("{other}")),
    }
}

/// How close the constraint Jacobian was to singular at the last stored step of a run.
#[derive(Debug, Clone)]
pub struct Conditioning {
    /// Time of the step.
    pub time: f64,
    /// σ_min / σ_max of the column-scaled Jacobian Φ_v (drivers included).
    pub ratio: f64,
    /// The equations that make up the (nearly) dependent combination, largest weight first.
    pub dependent: Vec<cardan_mechanism::EquationName>,
}

impl Conditioning {
    /// A sentence for an error message.
    pub fn describe(&self) -> String {
        let names: Vec<String> = self.dependent.iter().map(|e| e.to_string()).collect();
        let dependent = if self.ratio < WELL_CONDITIONED_RATIO {
            format!("; dependent equations: {}", names.join(", "))
        } else {
            String::new()
        };
        format!(
            ". At the last solved time t = {} s the constraint Jacobian was {} (σ_min/σ_max = \
             {:.2e}){dependent}",
            self.time,
            self.verdict(),
            self.ratio,
        )
    }

    /// "singular" below [`SINGULAR_RATIO`], "nearly singular" below [`WELL_CONDITIONED_RATIO`],
    /// else "well conditioned".
    pub fn verdict(&self) -> &'static str {
        if self.ratio < SINGULAR_RATIO {
            "singular"
        } else if self.ratio < WELL_CONDITIONED_RATIO {
            "nearly singular"
        } else {
            "well conditioned"
        }
    }

    /// The likely cause of a position solve that did not converge, from the conditioning at
    /// the last solved time: a limit of the motion or a singular configuration only when the
    /// Jacobian was (nearly) singular there; with a well conditioned Jacobian, a prescribed
    /// motion that changes faster than the steps follow; without a solved time (`None`, a
    /// failure at the first), not known, and said so.
    pub fn cause(c: Option<&Conditioning>) -> &'static str {
        match c {
            Some(c) if c.ratio >= WELL_CONDITIONED_RATIO => {
                "not a singular configuration: the constraint Jacobian is well conditioned there, \
                 so the prescribed motion probably changes faster than the steps can follow (a \
                 driver's function with a sharp step or a jump?); give more output steps or smooth \
                 the function"
            }
            Some(_) => "the mechanism reached a limit of its motion or a singular configuration",
            None => {
                "no time was solved before it, so the cause is not known: a limit of the \
                 motion, a singular configuration, or equations that cannot all hold there"
            }
        }
    }
}

/// σ_min/σ_max below which the column-scaled Φ_v is called singular in messages.
pub const SINGULAR_RATIO: f64 = 1e-4;

/// σ_min/σ_max from which the column-scaled Φ_v is called well conditioned in messages (a
/// failure there is not blamed on a singular configuration).
pub const WELL_CONDITIONED_RATIO: f64 = 1e-2;

/// The conditioning of Φ_v at the last step of `r` (a dense SVD; for diagnostics only).
pub fn conditioning(p: &Prepared, r: &cardan_mechanism::Results) -> Option<Conditioning> {
    let k = r.len().checked_sub(1)?;
    let model = &p.model;
    let mut ws = model.workspace();
    for (b, h) in r.bodies.iter().enumerate() {
        ws.set_pose(b, *h.r.get(k)?, *h.p.get(k)?);
    }
    let t = r.times[k];
    ws.set_time(t);
    let (m, n) = (model.num_equations(), model.num_unknowns());
    let mut slots = vec![0.0; model.pattern().num_slots()];
    model.eval_jacobian(&ws, t, &mut slots);
    let mut j = nalgebra::DMatrix::<f64>::zeros(m, n);
    for (s, v) in model.pattern().entries().zip(&slots) {
        j[s] = *v;
    }
    // Rows to unit length (equations in different units), columns by the model's scales.
    let scales = model.unknown_scales();
    for c in 0..n {
        let sc = scales.get(c).copied().unwrap_or(1.0);
        for rr in 0..m {
            j[(rr, c)] *= sc;
        }
    }
    for rr in 0..m {
        let norm = j.row(rr).norm();
        if norm > 0.0 {
            for c in 0..n {
                j[(rr, c)] /= norm;
            }
        }
    }
    let svd = j.clone().svd(true, false);
    let sv = &svd.singular_values;
    let (imin, smin) = sv.argmin();
    let smax = sv.max();
    if smax.is_nan() || smax <= 0.0 {
        return None;
    }
    let u = svd.u.as_ref()?.column(imin).into_owned();
    let umax = u.amax();
    let mut rows: Vec<(usize, f64)> = (0..m)
        .filter(|&rr| u[rr].abs() > 0.2 * umax)
        .map(|rr| (rr, u[rr].abs()))
        .collect();
    rows.sort_by(|a, b| b.1.total_cmp(&a.1));
    Some(Conditioning {
        time: t,
        ratio: smin / smax,
        dependent: rows
            .iter()
            .filter_map(|&(rr, _)| model.equation(rr))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::Conditioning;

    fn at(ratio: f64) -> Conditioning {
        Conditioning {
            time: 8.0,
            ratio,
            dependent: Vec::new(),
        }
    }

    /// σ_min/σ_max = 7e-2 (issue 53's robot at t = 8 s) is not called singular, nor blamed for
    /// the failure; 1e-6 is; without a solved time the cause is not guessed.
    #[test]
    fn a_well_conditioned_jacobian_is_not_called_singular() {
        assert!(at(7e-2).describe().contains("well conditioned"));
        assert!(!at(7e-2).describe().contains("singular"));
        assert!(Conditioning::cause(Some(&at(7e-2))).starts_with("not a singular"));
        assert!(at(1e-3).describe().contains("nearly singular"));
        assert!(at(1e-6).describe().contains("was singular"));
        assert!(Conditioning::cause(Some(&at(1e-6))).contains("singular configuration"));
        // No solved time (a failure at the first): no conditioning to blame, and no
        // singularity named as the cause.
        assert!(Conditioning::cause(None).contains("the cause is not known"));
        assert!(!Conditioning::cause(None).contains("reached"));
    }
}
