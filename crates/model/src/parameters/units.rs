//! The units a parameter's value may carry (`crank = "80 mm"`), as a table: each unit's name,
//! its size in SI and its dimension (the exponents of length, mass and time). Angles are
//! dimensionless, as in SI (rad = 1, deg = π/180), so `"90 deg"` is the number π/2.
//!
//! Adding a unit is adding a row. [`Dim`] is the dimension of units and quantities.

use std::fmt;

/// One unit: `value_SI = number · factor`.
#[derive(Debug, Clone, Copy)]
pub struct Unit {
    /// How it is written after a number.
    pub name: &'static str,
    /// Its size in SI units.
    pub factor: f64,
    /// Exponents of length, mass, time.
    pub dim: Dim,
    /// What it is, for `cardan check` and the manual.
    pub meaning: &'static str,
}

const fn u(name: &'static str, factor: f64, dim: [i8; 3], meaning: &'static str) -> Unit {
    Unit {
        name,
        factor,
        dim: Dim(dim),
        meaning,
    }
}

const DEG: f64 = std::f64::consts::PI / 180.0;
const RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;

/// Every unit, SI first in each quantity.
pub const UNITS: &[Unit] = &[
    u("m", 1.0, [1, 0, 0], "metre"),
    u("mm", 1e-3, [1, 0, 0], "millimetre"),
    u("cm", 1e-2, [1, 0, 0], "centimetre"),
    u("km", 1e3, [1, 0, 0], "kilometre"),
    u("in", 0.0254, [1, 0, 0], "inch"),
    u("ft", 0.3048, [1, 0, 0], "foot"),
    u("kg", 1.0, [0, 1, 0], "kilogram"),
    u("g", 1e-3, [0, 1, 0], "gram"),
    u("s", 1.0, [0, 0, 1], "second"),
    u("ms", 1e-3, [0, 0, 1], "millisecond"),
    u("min", 60.0, [0, 0, 1], "minute"),
    u("h", 3600.0, [0, 0, 1], "hour"),
    u("Hz", 1.0, [0, 0, -1], "hertz (1/s)"),
    u("rad", 1.0, [0, 0, 0], "radian (dimensionless)"),
    u("deg", DEG, [0, 0, 0], "degree (π/180)"),
    u(
        "rpm",
        RPM,
        [0, 0, -1],
        "revolution per minute (2π/60 rad/s)",
    ),
    u("N", 1.0, [1, 1, -2], "newton"),
    u("kN", 1e3, [1, 1, -2], "kilonewton"),
    u("J", 1.0, [2, 1, -2], "joule"),
    u("W", 1.0, [2, 1, -3], "watt"),
    u("kW", 1e3, [2, 1, -3], "kilowatt"),
    u("Pa", 1.0, [-1, 1, -2], "pascal"),
    u("kPa", 1e3, [-1, 1, -2], "kilopascal"),
    u("MPa", 1e6, [-1, 1, -2], "megapascal"),
    u("GPa", 1e9, [-1, 1, -2], "gigapascal"),
];

/// The unit written `name`.
pub fn unit(name: &str) -> Option<&'static Unit> {
    UNITS.iter().find(|u| u.name == name)
}

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
        let named = UNITS.iter().find(|u| {
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
        // kg first: kg m^2, kg m/s^2.
        let order = [1, 0, 2];
        let up: Vec<String> = (order.iter().copied())
            .filter(|&k| self.0[k] > 0)
            .map(|k| part(names[k], self.0[k]))
            .collect();
        let down: Vec<String> = (order.iter().copied())
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
