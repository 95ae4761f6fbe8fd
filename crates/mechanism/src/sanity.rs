//! Physical sanity of input data, in one place for the builder and for any reader of model
//! files (the `cardan` command places the same refusals at a line of the file).
//!
//! ## Inertia tensors
//! A tensor J about the centre of mass is a rigid body's when it is symmetric, positive
//! definite, and its principal moments I₁ ≤ I₂ ≤ I₃ satisfy the triangle inequality
//! I₁ + I₂ ≥ I₃. (With the second moments of mass Sₖ = ∫ xₖ² dm along the principal axes,
//! I₃ = S₁ + S₂ and I₁ + I₂ − I₃ = 2 S₃ ≥ 0.) A thin disk or plate has I₁ + I₂ = I₃ exactly;
//! values rounded to four digits may miss it by a few 1e-4 relative, so the test allows
//! [`INERTIA_TRIANGLE_TOLERANCE`] × I₃.

use crate::error::ModelError;
use nalgebra::{Matrix3, Vector3};

/// Relative slack of the triangle inequality: I₁ + I₂ ≥ (1 − 1e-3) I₃ is accepted.
pub const INERTIA_TRIANGLE_TOLERANCE: f64 = 1e-3;

/// Relative asymmetry max |J − Jᵀ| / max |J| accepted (roundoff of a rotated tensor).
pub const INERTIA_ASYMMETRY_TOLERANCE: f64 = 1e-9;

/// Checks that `inertia` (kg m², about the centre of mass) can be a rigid body's: finite,
/// symmetric, positive definite, principal moments satisfying the triangle inequality.
///
/// # Errors
/// [`ModelError::NotFinite`], [`ModelError::InertiaNotSymmetric`],
/// [`ModelError::InertiaNotPositiveDefinite`] or [`ModelError::InertiaTriangle`], naming `body`.
pub fn check_inertia(body: &str, inertia: &Matrix3<f64>) -> Result<(), ModelError> {
    if let Some(&v) = inertia.iter().find(|v| !v.is_finite()) {
        return Err(ModelError::NotFinite {
            element: format!("body \"{body}\""),
            what: "inertia".into(),
            value: v,
        });
    }
    let scale = inertia.amax();
    let asym = (inertia - inertia.transpose()).amax();
    if scale > 0.0 && asym > INERTIA_ASYMMETRY_TOLERANCE * scale {
        return Err(ModelError::InertiaNotSymmetric {
            body: body.into(),
            asymmetry: asym / scale,
        });
    }
    let moments = principal_moments(inertia);
    let sym = 0.5 * (inertia + inertia.transpose());
    if scale == 0.0 || sym.cholesky().is_none() {
        return Err(ModelError::InertiaNotPositiveDefinite {
            body: body.into(),
            min_eigenvalue: moments[0],
        });
    }
    let [i1, i2, i3] = moments;
    if i1 + i2 < (1.0 - INERTIA_TRIANGLE_TOLERANCE) * i3 {
        return Err(ModelError::InertiaTriangle {
            body: body.into(),
            moments,
        });
    }
    Ok(())
}

/// The eigenvalues of the symmetric part of `j`, ascending.
pub fn principal_moments(j: &Matrix3<f64>) -> [f64; 3] {
    let sym = 0.5 * (j + j.transpose());
    let e = sym.symmetric_eigenvalues();
    let mut m = [e[0], e[1], e[2]];
    m.sort_by(f64::total_cmp);
    m
}

/// Smallest angle between the two arms of a universal joint's cross at the drawn pose, in
/// degrees: 45°, the arms closer to perpendicular than to parallel.
pub const UNIVERSAL_ARMS_MIN_ANGLE_DEG: f64 = 45.0;

/// Checks that the arms of universal joint `joint` (global directions `arm_i`, `arm_j` at the
/// drawn pose) are at least [`UNIVERSAL_ARMS_MIN_ANGLE_DEG`] apart. The joint keeps them
/// perpendicular (n1: arm_iᵀ arm_j = 0); drawn parallel, that equation has a zero gradient and
/// the assembly cannot close it, drawn nearly parallel it has to turn a body by most of 90°.
///
/// # Errors
/// [`ModelError::UniversalArms`] with the angle.
pub fn check_universal_arms(
    joint: &str,
    arm_i: &Vector3<f64>,
    arm_j: &Vector3<f64>,
) -> Result<(), ModelError> {
    let cos = arm_i.dot(arm_j) / (arm_i.norm() * arm_j.norm());
    let angle = cos.abs().min(1.0).acos().to_degrees();
    if angle < UNIVERSAL_ARMS_MIN_ANGLE_DEG {
        return Err(ModelError::UniversalArms {
            joint: joint.into(),
            angle_deg: angle,
        });
    }
    Ok(())
}

/// What a number in a model means, for the magnitude limits ([`Quantity::limit`]).
///
/// ## Magnitude limits
/// A number far beyond anything a mechanism can have is a typo (a wrong exponent, a value in
/// the wrong unit), and it would wreck the solution (a point at 1e12 m leaves f64 a resolution
/// of 1e-4 m). Each quantity has its own bound in SI units, generous enough for large machines
/// (a 100 000 t ship, a steel contact's stiffness) and far below overflow:
///
/// | quantity | limit |
/// |---|---|
/// | length (positions, points, lengths) | 1e7 m |
/// | mass | 1e10 kg |
/// | inertia | 1e15 kg m² |
/// | time | 1e9 s |
/// | angle | 1e7 rad |
/// | velocity | 1e6 m/s |
/// | angular velocity, frequency | 1e6 rad/s |
/// | acceleration (gravity) | 1e6 m/s² |
/// | force | 1e12 N |
/// | torque | 1e12 N m |
/// | stiffness | 1e15 N/m, N m/rad |
/// | damping | 1e12 N s/m, N m s/rad |
/// | ratio (a gear's angle ratio) | 1e6 |
/// | direction (only its direction counts) | 1e150 |
/// | coefficient (a polynomial's c_k: its unit depends on k) | none: finite |
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// m.
    Length,
    /// kg.
    Mass,
    /// kg m².
    Inertia,
    /// s.
    Time,
    /// rad.
    Angle,
    /// m/s.
    Velocity,
    /// rad/s.
    AngularVelocity,
    /// rad/s (of a harmonic function).
    Frequency,
    /// m/s².
    Acceleration,
    /// N.
    Force,
    /// N m.
    Torque,
    /// N/m.
    Stiffness,
    /// N m/rad.
    RotationalStiffness,
    /// N s/m.
    Damping,
    /// N m s/rad.
    RotationalDamping,
    /// A dimensionless ratio (a gear's θ_j / θ_i).
    Ratio,
    /// A direction vector's component (any unit, only the direction counts).
    Direction,
    /// A number whose unit the reader cannot tell (a polynomial coefficient, a tolerance
    /// checked elsewhere): finite is all that is asked.
    Unbounded,
}

impl Quantity {
    /// The largest magnitude accepted, in the SI unit [`Quantity::unit`].
    pub fn limit(self) -> f64 {
        match self {
            Quantity::Length | Quantity::Angle => 1e7,
            Quantity::Mass => 1e10,
            Quantity::Inertia | Quantity::Stiffness | Quantity::RotationalStiffness => 1e15,
            Quantity::Time => 1e9,
            Quantity::Velocity
            | Quantity::AngularVelocity
            | Quantity::Frequency
            | Quantity::Acceleration => 1e6,
            Quantity::Force
            | Quantity::Torque
            | Quantity::Damping
            | Quantity::RotationalDamping => 1e12,
            Quantity::Ratio => 1e6,
            Quantity::Direction => 1e150,
            Quantity::Unbounded => f64::MAX,
        }
    }

    /// The SI unit ("" for directions and unbounded numbers).
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Length => "m",
            Quantity::Mass => "kg",
            Quantity::Inertia => "kg m²",
            Quantity::Time => "s",
            Quantity::Angle => "rad",
            Quantity::Velocity => "m/s",
            Quantity::AngularVelocity | Quantity::Frequency => "rad/s",
            Quantity::Acceleration => "m/s²",
            Quantity::Force => "N",
            Quantity::Torque => "N m",
            Quantity::Stiffness => "N/m",
            Quantity::RotationalStiffness => "N m/rad",
            Quantity::Damping => "N s/m",
            Quantity::RotationalDamping => "N m s/rad",
            Quantity::Ratio | Quantity::Direction | Quantity::Unbounded => "",
        }
    }

    /// The quantity's name in messages ("a length", "a mass", ...).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Length => "a length",
            Quantity::Mass => "a mass",
            Quantity::Inertia => "an inertia",
            Quantity::Time => "a time",
            Quantity::Angle => "an angle",
            Quantity::Velocity => "a velocity",
            Quantity::AngularVelocity => "an angular velocity",
            Quantity::Frequency => "a frequency",
            Quantity::Acceleration => "an acceleration",
            Quantity::Force => "a force",
            Quantity::Torque => "a torque",
            Quantity::Stiffness | Quantity::RotationalStiffness => "a stiffness",
            Quantity::Damping | Quantity::RotationalDamping => "a damping coefficient",
            Quantity::Ratio => "a ratio",
            Quantity::Direction => "a direction component",
            Quantity::Unbounded => "a number",
        }
    }

    /// `Err(message)` when `value` is not finite or beyond [`Quantity::limit`]; the message
    /// starts with "`what` = value unit" and says what to check.
    ///
    /// # Errors
    /// The message, for the caller to wrap with the element and place.
    pub fn check(self, what: impl std::fmt::Display, value: f64) -> Result<(), String> {
        if value.is_nan() {
            return Err(format!("{what} is NaN; a finite number is needed"));
        }
        if value.is_infinite() {
            return Err(format!("{what} is infinite; a finite number is needed"));
        }
        if value.abs() > self.limit() {
            let unit = match self.unit() {
                "" => String::new(),
                u => format!(" {u}"),
            };
            return Err(format!(
                "{what} = {}{unit} is beyond the limit of {:e}{unit} for {} (model values \
                 are in SI units); check the exponent and the unit",
                scientific(value),
                self.limit(),
                self.name(),
            ));
        }
        Ok(())
    }
}

/// `x` in scientific notation with at most six significant digits ("1e298", "2.5e10").
pub fn scientific(x: f64) -> String {
    let s = format!("{x:.5e}");
    match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => s,
    }
}
