//! The units a parameter's value may carry (`crank = "80 mm"`), as a table: each unit's name,
//! its size in SI and its dimension (the exponents of length, mass and time). Angles are
//! dimensionless, as in SI (rad = 1, deg = π/180), so `"90 deg"` is the number π/2.
//!
//! Adding a unit is adding a row.

use super::quantity::Dim;

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
