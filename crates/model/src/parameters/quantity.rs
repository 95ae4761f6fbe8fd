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

pub use super::units::Dim;

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

    /// The value as the language reads it back exactly: `"0.08 m"`, `"6.283185307179586 s^-1"`,
    /// `"2"` (plain or dimensionless).
    pub fn exact_text(&self) -> String {
        let mut text = format!("{:?}", self.value);
        let Some(d) = self.dim.filter(|d| *d != Dim::NONE) else {
            return text;
        };
        for (name, e) in ["m", "kg", "s"].iter().zip(d.0) {
            match e {
                0 => {}
                1 => text += &format!(" {name}"),
                _ => text += &format!(" {name}^{e}"),
            }
        }
        text
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
