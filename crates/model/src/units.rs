//! Output units: a run computes in SI and writes its outputs in the model's unit system.
//!
//! The unit systems are coherent (mm, kg, s, N: a newton is still kg m/s², so forces keep
//! their unit and only lengths change), and every derived unit of an output column follows
//! from its length exponent:
//!
//! ```text
//! value_out = value_SI · (1 m / 1 mm)^e,   e = the column's length exponent
//! m, m/s, m/s², N m, J, W: e = 1     kg m²: e = 2     N/m, N s/m: e = −1
//! ```
//!
//! Angles, times, masses and forces are the same in both systems.

use crate::table::Table;
use cardan_constraints::joints::CoordinateQuantity;
use cardan_mechanism::sanity::Quantity;

/// The SI units of a joint coordinate and of what acts along it (a limit's bound, a stop's
/// rate, force and impulse), for an angle or a length.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoordinateUnits {
    /// The coordinate's (and a bound's) unit.
    pub coordinate: &'static str,
    /// Its rate's.
    pub rate: &'static str,
    /// A force (or torque) along it.
    pub force: &'static str,
    /// An impulse along it.
    pub impulse: &'static str,
}

/// [`CoordinateUnits`] of a coordinate of `quantity`: rad, rad/s, N m, N m s for an angle;
/// m, m/s, N, N s for a length.
pub fn coordinate_units(quantity: CoordinateQuantity) -> CoordinateUnits {
    match quantity {
        CoordinateQuantity::Angle => CoordinateUnits {
            coordinate: "rad",
            rate: "rad/s",
            force: "N m",
            impulse: "N m s",
        },
        CoordinateQuantity::Length => CoordinateUnits {
            coordinate: "m",
            rate: "m/s",
            force: "N",
            impulse: "N s",
        },
    }
}

/// A unit system of cardan outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UnitSystem {
    /// m, kg, s, N, N m, J.
    #[default]
    Si,
    /// mm, kg, s, N, N mm; energy in mJ (= N mm).
    Mm,
}

impl UnitSystem {
    /// The unit of a quantity written in SI as `si`, and the factor from SI to it. Units the
    /// system leaves alone (rad, s, kg, N, rad/s, …) come back with factor 1.
    pub fn unit(self, si: &str) -> (String, f64) {
        if self == Self::Si {
            return (si.to_string(), 1.0);
        }
        let (unit, factor) = match si {
            "m" => ("mm", 1e3),
            "m/s" => ("mm/s", 1e3),
            "m/s²" => ("mm/s²", 1e3),
            "N m" => ("N mm", 1e3),
            "N m/rad" => ("N mm/rad", 1e3),
            "N m s/rad" => ("N mm s/rad", 1e3),
            "J" => ("mJ", 1e3),
            "W" => ("mW", 1e3),
            "kg m²" => ("kg mm²", 1e6),
            "kg m" => ("kg mm", 1e3),
            "rad/m" => ("rad/mm", 1e-3),
            "N/m" => ("N/mm", 1e-3),
            "N s/m" => ("N s/mm", 1e-3),
            _ => return (si.to_string(), 1.0),
        };
        (unit.to_string(), factor)
    }

    /// The system of `[model] units = "..."` (`"SI"` or `"mm"`, any case), or `None`.
    pub fn parse(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "si" => Some(Self::Si),
            "mm" => Some(Self::Mm),
            _ => None,
        }
    }

    /// The factor from a value of `q` written in this system to SI: model inputs are converted
    /// by it on reading, so the analyses and the magnitude checks see SI values. A polynomial
    /// coefficient (`Quantity::Unbounded`) is converted by its function's quantity instead.
    pub fn to_si(self, q: Quantity) -> f64 {
        if self == Self::Si {
            return 1.0;
        }
        match q {
            // mm, mm/s, mm/s², N mm, N mm/rad, N mm s/rad.
            Quantity::Length
            | Quantity::Velocity
            | Quantity::Acceleration
            | Quantity::Torque
            | Quantity::RotationalStiffness
            | Quantity::RotationalDamping => 1e-3,
            // kg mm².
            Quantity::Inertia => 1e-6,
            // N/mm, N s/mm.
            Quantity::Stiffness | Quantity::Damping => 1e3,
            _ => 1.0,
        }
    }

    /// The factor from this system's lengths to metres.
    pub fn length(self) -> f64 {
        self.to_si(Quantity::Length)
    }

    /// The table's columns (headers `name [unit]`) in this system: headers and values.
    pub fn convert_table(self, table: &mut Table) {
        if self == Self::Si {
            return;
        }
        let factors = self.convert_columns(&mut table.columns);
        for row in &mut table.rows {
            self.convert_row(row, &factors);
        }
    }

    /// Headers `name [unit]` in this system; returns each column's factor from SI.
    pub fn convert_columns(self, columns: &mut [String]) -> Vec<f64> {
        if self == Self::Si {
            return vec![1.0; columns.len()];
        }
        columns
            .iter_mut()
            .map(|c| {
                let Some((name, unit)) = c
                    .strip_suffix(']')
                    .and_then(|h| h.rsplit_once(" ["))
                    .map(|(n, u)| (n.to_string(), u.to_string()))
                else {
                    return 1.0;
                };
                let (unit, factor) = self.unit(&unit);
                *c = format!("{name} [{unit}]");
                factor
            })
            .collect()
    }

    /// A row (time first, then the columns with `factors` from [`Self::convert_columns`]) in
    /// this system.
    pub fn convert_row(self, row: &mut [f64], factors: &[f64]) {
        if self == Self::Si {
            return;
        }
        // Time first.
        for (v, f) in row.iter_mut().skip(1).zip(factors) {
            *v *= f;
        }
    }

    /// The name written in `check` and run summaries.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Si => "SI units (m, kg, s, rad)",
            Self::Mm => "millimetre units (mm, kg, s, N, N mm, rad)",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_convert_by_their_length_exponent() {
        let mut t = Table::new(
            "g",
            "G",
            vec![
                "a.x [m]".into(),
                "b [rad]".into(),
                "k.T.z [N m]".into(),
                "no unit".into(),
            ],
        );
        t.rows.push(vec![0.5, 0.25, 1.0, 2.0, 3.0]);
        UnitSystem::Mm.convert_table(&mut t);
        assert_eq!(
            t.columns,
            ["a.x [mm]", "b [rad]", "k.T.z [N mm]", "no unit"]
        );
        assert_eq!(t.rows[0], [0.5, 250.0, 1.0, 2000.0, 3.0]);
        assert_eq!(UnitSystem::Mm.unit("N/m"), ("N/mm".to_string(), 1e-3));
        assert_eq!(UnitSystem::Si.unit("m"), ("m".to_string(), 1.0));
    }
}
