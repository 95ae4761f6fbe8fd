//! The model's time functions at given times: which one is not finite, and why (for an
//! expression: the operation that fails, e.g. "sqrt of -1", with its column).

use super::num;
use crate::build::Loaded;
use crate::diag::{Error, Source};
use cardan_constraints::TimeFunction;
use cardan_dynamics::{Force, VectorFunction};

/// Why `f` is not finite at t (`None` when f, ḟ and f̈ are finite).
pub fn not_finite(f: &TimeFunction, t: f64) -> Option<String> {
    let (v, rate, acc) = f.eval(t);
    if v.is_finite() && rate.is_finite() && acc.is_finite() {
        return None;
    }
    let values = format!(
        "value {}, rate {}, acceleration {}",
        num(v),
        num(rate),
        num(acc)
    );
    Some(match f {
        TimeFunction::Expression(e) => match e.domain_message(t) {
            Some(m) => format!("expression \"{}\": {m}", e.text()),
            None => format!("expression \"{}\": {values}", e.text()),
        },
        _ => values,
    })
}

/// Every time function of the force elements, with its owner ("force \"push\" component y",
/// "force \"spring\" actuator") and the force's name.
pub fn force_functions(forces: &[Force]) -> Vec<(String, &str, &TimeFunction)> {
    let mut out = Vec::new();
    for f in forces {
        let name = f.name();
        match f {
            Force::PointForce { value, .. } | Force::PointTorque { value, .. } => {
                if let VectorFunction::Components(c) = value {
                    for (k, g) in c.iter().enumerate() {
                        let owner = format!("force \"{name}\" component {}", ["x", "y", "z"][k]);
                        out.push((owner, name, g));
                    }
                }
            }
            Force::SpringDamperActuator {
                actuator: Some(a), ..
            } => out.push((format!("force \"{name}\" actuator"), name, a)),
            _ => {}
        }
    }
    out
}

/// Refuses a force whose time function is not finite at one of `times`, located at the force.
///
/// # Errors
/// An input error naming the force, the time and the function.
pub fn check_force_values(src: &Source, loaded: &Loaded, times: &[f64]) -> Result<(), Error> {
    for (owner, name, f) in force_functions(&loaded.forces) {
        if let Some(&t) = times.iter().find(|&&t| not_finite(f, t).is_some()) {
            let why = not_finite(f, t).unwrap_or_default();
            let message = format!(
                "{owner}: the function is not finite at t = {} s: {why}",
                num(t)
            );
            return Err(match loaded.spans.forces.get(name) {
                Some(s) => src.error_at(s.clone(), message),
                None => src.error(message),
            });
        }
    }
    Ok(())
}

/// The first driver or force function not finite at t, as "driver \"x\": ..." and the
/// element's name (to explain a run that met non-finite values between output times).
pub fn first_not_finite(loaded: &Loaded, t: f64) -> Option<(String, String)> {
    let drivers = loaded
        .drivers
        .iter()
        .zip(&loaded.driver_functions)
        .map(|((n, _), (f, _))| (format!("driver \"{n}\""), n.as_str(), f));
    drivers
        .chain(force_functions(&loaded.forces))
        .find_map(|(owner, name, f)| {
            not_finite(f, t).map(|why| {
                (
                    format!(
                        "{owner}: its function is not finite at t = {} s: {why}",
                        num(t)
                    ),
                    name.to_string(),
                )
            })
        })
}
