//! The model's time functions at given times: which one is not finite, and why (for an
//! expression: the operation that fails, e.g. "sqrt of -1", with its column).

use crate::build::Loaded;
use crate::diag::{Error, Source};
use crate::number::num;
use cardan_constraints::expression::quoted;
use cardan_constraints::TimeFunction;
use cardan_dynamics::{Force, VectorFunction};
use cardan_mechanism::Quantity;

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
            Some(m) => format!("expression \"{}\": {m}", quoted(e.text())),
            None => format!("expression \"{}\": {values}", quoted(e.text())),
        },
        _ => values,
    })
}

/// A time function of a force element: its owner ("force \"push\" component y", "force
/// \"spring\" actuator"), the force's name, the function and what its value is (a force or a
/// torque).
pub struct ForceFunction<'a> {
    /// The owner, for messages.
    pub owner: String,
    /// The force element's name.
    pub name: &'a str,
    /// The function.
    pub function: &'a TimeFunction,
    /// [`Quantity::Force`] or [`Quantity::Torque`].
    pub quantity: Quantity,
}

/// Every time function of the force elements.
pub fn force_functions(forces: &[Force]) -> Vec<ForceFunction<'_>> {
    let mut out = Vec::new();
    for f in forces {
        let name = f.name();
        let (values, quantity): (Vec<(String, &TimeFunction)>, _) = match f {
            Force::PointForce { value, .. } | Force::PointTorque { value, .. } => {
                let quantity = match f {
                    Force::PointTorque { .. } => Quantity::Torque,
                    _ => Quantity::Force,
                };
                let components = match value {
                    VectorFunction::Components(c) => c
                        .iter()
                        .enumerate()
                        .map(|(k, g)| (format!("component {}", ["x", "y", "z"][k]), g))
                        .collect(),
                    _ => Vec::new(),
                };
                (components, quantity)
            }
            Force::SpringDamperActuator {
                actuator: Some(a), ..
            } => (vec![("actuator".to_string(), a)], Quantity::Force),
            _ => (Vec::new(), Quantity::Force),
        };
        for (part, function) in values {
            out.push(ForceFunction {
                owner: format!("force \"{name}\" {part}"),
                name,
                function,
                quantity,
            });
        }
    }
    out
}

/// Refuses a force whose time function is not finite at one of `times`, or whose value there
/// is beyond the magnitude limit of a constant force or torque (`cardan_mechanism::Quantity`:
/// 1e12 N, 1e12 N m), located at the force. The times are the run's output times: a function
/// that grows past the limit between them is stopped by the run at that step
/// (`DynamicsError::ForceLimit`).
///
/// # Errors
/// An input error naming the force, the time and the function (its value and the limit).
pub fn check_force_values(src: &Source, loaded: &Loaded, times: &[f64]) -> Result<(), Error> {
    for ff in force_functions(&loaded.forces) {
        let f = ff.function;
        let owner = &ff.owner;
        let message = times.iter().find_map(|&t| {
            if let Some(why) = not_finite(f, t) {
                return Some(format!(
                    "{owner}: the function is not finite at t = {} s: {why}",
                    num(t)
                ));
            }
            let what = format_args!("{owner}: at t = {} s its value", num(t));
            ff.quantity.check(what, f.eval(t).0).err()
        });
        if let Some(message) = message {
            return Err(match loaded.spans.forces.get(ff.name) {
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
        .chain(
            force_functions(&loaded.forces)
                .into_iter()
                .map(|ff| (ff.owner, ff.name, ff.function)),
        )
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
