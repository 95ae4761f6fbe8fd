//! Quantities: a value with its dimension, or a plain number.
//!
//! A quantity with a unit (`80 mm`) is held in SI (0.08) with its dimension (length¹). A plain
//! number (`0.01`, `2.0`) has none: it is in the model's units of whatever it meets. So in a
//! model in mm, `crank + 10` is 80 mm + 10 mm, while `2 * crank` is twice 80 mm: a plain number
//! added to a quantity takes the quantity's dimension, multiplied it is a factor.
//!
//! The model's units are m or mm with kg, s and N (a newton stays a newton in a mm model), so a
//! value is written in them as `value_SI / ℓ^e` with ℓ the model's length unit in metres (1 or
//! 0.001) and e the power of metres left when the value is written with newtons
//! ([`Dim::length_exponent`]), as [`crate::units`] writes outputs: N m → N mm (e = 1), N/m →
//! N/mm (e = −1), kg m² → kg mm² (e = 2), N and kg unchanged.

use std::fmt;

/// Exponents of length, mass and time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Dim(pub [i8; 3]);

impl Dim {
    /// Dimensionless.
    pub const NONE: Dim = Dim([0, 0, 0]);

    /// The product's dimension.
    pub fn times(self, o: Dim) -> Dim {
        Dim([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }

    /// The quotient's dimension.
    pub fn over(self, o: Dim) -> Dim {
        Dim([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }

    /// The power of metres in the unit written with newtons for the mass of a quantity that
    /// has a negative power of time (a force, stiffness, damping, energy, power, pressure)
    /// and with kilograms otherwise (a mass, an inertia): N m → 1, N/m → −1, kg m² → 2,
    /// m/s² → 1, N → 0.
    pub fn length_exponent(self) -> i32 {
        let [l, m, t] = self.0.map(i32::from);
        let newtons = if t < 0 { m } else { 0 };
        l - newtons
    }

    /// The dimension raised to `p`, when every exponent stays a small integer.
    pub fn pow(self, p: f64) -> Option<Dim> {
        let mut out = [0i8; 3];
        for (o, &e) in out.iter_mut().zip(&self.0) {
            let x = f64::from(e) * p;
            if (x - x.round()).abs() > 1e-9 || x.abs() > 60.0 {
                return None;
            }
            *o = x.round() as i8;
        }
        Some(Dim(out))
    }
}

impl fmt::Display for Dim {
    /// In SI units: a named unit where one has this dimension (N, J, W, Pa), else
    /// `m kg/s^2`-style products; "1" for dimensionless.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if *self == Dim::NONE {
            return write!(f, "1");
        }
        let named = super::units::UNITS.iter().find(|u| {
            u.factor == 1.0 && u.dim == *self && u.dim.0.iter().filter(|&&e| e != 0).count() > 1
        });
        if let Some(u) = named {
            return write!(f, "{}", u.name);
        }
        let part = |name: &str, e: i8| match e {
            1 => name.to_string(),
            _ => format!("{name}^{e}"),
        };
        let names = ["m", "kg", "s"];
        let up: Vec<String> = (0..3)
            .filter(|&k| self.0[k] > 0)
            .map(|k| part(names[k], self.0[k]))
            .collect();
        let down: Vec<String> = (0..3)
            .filter(|&k| self.0[k] < 0)
            .map(|k| part(names[k], -self.0[k]))
            .collect();
        let up = if up.is_empty() {
            "1".to_string()
        } else {
            up.join(" ")
        };
        if down.is_empty() {
            write!(f, "{up}")
        } else {
            write!(f, "{up}/{}", down.join(" "))
        }
    }
}

/// A value: SI with a dimension, or a plain number (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// SI when `dim` is given, else the plain number.
    pub value: f64,
    /// The dimension; `None` for a plain number.
    pub dim: Option<Dim>,
}

impl Quantity {
    /// A plain number.
    pub fn plain(value: f64) -> Self {
        Self { value, dim: None }
    }

    /// `value` SI of dimension `dim`.
    pub fn si(value: f64, dim: Dim) -> Self {
        Self {
            value,
            dim: Some(dim),
        }
    }

    /// The number written in a model whose length unit is `ell` metres.
    pub fn in_model_units(&self, ell: f64) -> f64 {
        match self.dim {
            Some(d) => self.value / ell.powi(d.length_exponent()),
            None => self.value,
        }
    }

    /// This quantity as one of dimension `dim`: a plain number is read in the model's units
    /// of `dim`.
    pub fn as_dim(&self, dim: Dim, ell: f64) -> f64 {
        match self.dim {
            Some(_) => self.value,
            None => self.value * ell.powi(dim.length_exponent()),
        }
    }

    /// "0.08 m", "2" (plain), "1.5708" (dimensionless).
    pub fn describe(&self) -> String {
        let v = crate::output_tables::g(self.value);
        match self.dim {
            Some(d) if d != Dim::NONE => format!("{v} {d}"),
            _ => v,
        }
    }
}
