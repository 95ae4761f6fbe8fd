//! Second-order forward-mode jets: a value with its first two time derivatives.
//!
//! A [`Jet`] u = (u, u̇, ü). Every operation returns the jet of its result by the chain rule,
//! written once here: for a function g of one argument,
//!
//! g(u)˙ = g′(u) u̇,   g(u)¨ = g″(u) u̇² + g′(u) ü,
//!
//! and for the arithmetic operators the product and quotient rules
//!
//! (u v)¨ = ü v + 2 u̇ v̇ + u v̈,   (u / v)˙ = (u̇ − f v̇) / v,   (u / v)¨ = (ü − 2 ḟ v̇ − f v̈) / v
//!
//! (f = u / v). Nothing is approximated: the derivatives are exact up to rounding.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// (value, first derivative, second derivative) with respect to time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Jet {
    /// u.
    pub v: f64,
    /// u̇.
    pub d1: f64,
    /// ü.
    pub d2: f64,
}

impl Jet {
    /// A constant: (c, 0, 0).
    pub const fn constant(c: f64) -> Self {
        Self {
            v: c,
            d1: 0.0,
            d2: 0.0,
        }
    }

    /// The time itself: (t, 1, 0).
    pub const fn time(t: f64) -> Self {
        Self {
            v: t,
            d1: 1.0,
            d2: 0.0,
        }
    }

    /// Whether value and both derivatives are finite.
    pub fn is_finite(&self) -> bool {
        self.v.is_finite() && self.d1.is_finite() && self.d2.is_finite()
    }

    /// g(u) from g, g′(u), g″(u): (g, g′ u̇, g″ u̇² + g′ ü).
    #[inline]
    pub fn chain(&self, g: f64, g1: f64, g2: f64) -> Self {
        Self {
            v: g,
            d1: g1 * self.d1,
            d2: g2 * self.d1 * self.d1 + g1 * self.d2,
        }
    }

    /// u^c for a constant c: g′ = c u^(c−1), g″ = c (c − 1) u^(c−2). Integer c accepts u < 0
    /// (and is computed by repeated multiplication when small).
    #[inline]
    pub fn powc(self, c: f64) -> Self {
        let u = self.v;
        if c == 0.0 {
            return Self::constant(1.0);
        }
        if c == 2.0 {
            return self.chain(u * u, 2.0 * u, 2.0);
        }
        if c.fract() == 0.0 && c.abs() <= 64.0 {
            let n = c as i32;
            let (g, g1, g2) = (u.powi(n), u.powi(n - 1), u.powi(n - 2));
            let g1 = if n == 1 { 1.0 } else { c * g1 };
            let g2 = if n == 1 { 0.0 } else { c * (c - 1.0) * g2 };
            return self.chain(g, g1, g2);
        }
        self.chain(
            u.powf(c),
            c * u.powf(c - 1.0),
            c * (c - 1.0) * u.powf(c - 2.0),
        )
    }

    /// u^v with a time-dependent exponent: exp(v ln u), defined for u > 0.
    #[inline]
    pub fn pow(self, o: Self) -> Self {
        let w = o * self.ln();
        let f = self.v.powf(o.v);
        Self {
            v: f,
            d1: f * w.d1,
            d2: f * (w.d1 * w.d1 + w.d2),
        }
    }

    /// sin u.
    pub fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }

    /// cos u.
    pub fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }

    /// tan u: g′ = 1 + tan², g″ = 2 tan (1 + tan²).
    pub fn tan(self) -> Self {
        let g = self.v.tan();
        let g1 = 1.0 + g * g;
        self.chain(g, g1, 2.0 * g * g1)
    }

    /// asin u: g′ = 1/√(1 − u²), g″ = u / (1 − u²)^(3/2).
    pub fn asin(self) -> Self {
        let w = 1.0 - self.v * self.v;
        let g1 = 1.0 / w.sqrt();
        self.chain(self.v.asin(), g1, self.v * g1 / w)
    }

    /// acos u: the negatives of asin's derivatives.
    pub fn acos(self) -> Self {
        let w = 1.0 - self.v * self.v;
        let g1 = -1.0 / w.sqrt();
        self.chain(self.v.acos(), g1, self.v * g1 / w)
    }

    /// atan u: g′ = 1/(1 + u²), g″ = −2u/(1 + u²)².
    pub fn atan(self) -> Self {
        let g1 = 1.0 / (1.0 + self.v * self.v);
        self.chain(self.v.atan(), g1, -2.0 * self.v * g1 * g1)
    }

    /// atan2(y, x) (self = y): ḟ = N / D with N = x ẏ − y ẋ, D = x² + y²;
    /// f̈ = (Ṅ D − N Ḋ) / D² with Ṅ = x ÿ − y ẍ, Ḋ = 2 (x ẋ + y ẏ).
    pub fn atan2(self, x: Self) -> Self {
        let y = self;
        let n = x.v * y.d1 - y.v * x.d1;
        let d = x.v * x.v + y.v * y.v;
        let n1 = x.v * y.d2 - y.v * x.d2;
        let d1 = 2.0 * (x.v * x.d1 + y.v * y.d1);
        Self {
            v: y.v.atan2(x.v),
            d1: n / d,
            d2: (n1 * d - n * d1) / (d * d),
        }
    }

    /// sinh u.
    pub fn sinh(self) -> Self {
        let (s, c) = (self.v.sinh(), self.v.cosh());
        self.chain(s, c, s)
    }

    /// cosh u.
    pub fn cosh(self) -> Self {
        let (s, c) = (self.v.sinh(), self.v.cosh());
        self.chain(c, s, c)
    }

    /// tanh u: g′ = 1 − tanh², g″ = −2 tanh (1 − tanh²).
    pub fn tanh(self) -> Self {
        let g = self.v.tanh();
        let g1 = 1.0 - g * g;
        self.chain(g, g1, -2.0 * g * g1)
    }

    /// exp u.
    pub fn exp(self) -> Self {
        let g = self.v.exp();
        self.chain(g, g, g)
    }

    /// ln u: g′ = 1/u, g″ = −1/u² (u ≤ 0 gives NaN or −∞).
    pub fn ln(self) -> Self {
        let g1 = 1.0 / self.v;
        self.chain(self.v.ln(), g1, -g1 * g1)
    }

    /// √u: g′ = 1/(2√u), g″ = −1/(4 u √u).
    pub fn sqrt(self) -> Self {
        let g = self.v.sqrt();
        let g1 = 0.5 / g;
        self.chain(g, g1, -0.5 * g1 / self.v)
    }

    /// |u|: the derivatives of the active branch, sign(u) u̇ and sign(u) ü (0 at u = 0).
    pub fn abs(self) -> Self {
        let s = sign(self.v);
        self.chain(self.v.abs(), s, 0.0)
    }

    /// sign(u) ∈ {−1, 0, 1}: piecewise constant, derivatives 0 (NaN for a NaN argument).
    pub fn sign(self) -> Self {
        let s = sign(self.v);
        Self {
            v: s,
            d1: 0.0 * self.d1,
            d2: 0.0 * self.d2,
        }
    }

    /// min(u, v): the jet of the smaller (u on ties).
    pub fn min(self, o: Self) -> Self {
        if o.v < self.v || o.v.is_nan() {
            o
        } else {
            self
        }
    }

    /// max(u, v): the jet of the larger (u on ties).
    pub fn max(self, o: Self) -> Self {
        if o.v > self.v || o.v.is_nan() {
            o
        } else {
            self
        }
    }
}

/// −u.
impl Neg for Jet {
    type Output = Jet;
    #[inline]
    fn neg(self) -> Jet {
        Jet {
            v: -self.v,
            d1: -self.d1,
            d2: -self.d2,
        }
    }
}

/// u + v.
impl Add for Jet {
    type Output = Jet;
    #[inline]
    fn add(self, o: Jet) -> Jet {
        Jet {
            v: self.v + o.v,
            d1: self.d1 + o.d1,
            d2: self.d2 + o.d2,
        }
    }
}

/// u − v.
impl Sub for Jet {
    type Output = Jet;
    #[inline]
    fn sub(self, o: Jet) -> Jet {
        Jet {
            v: self.v - o.v,
            d1: self.d1 - o.d1,
            d2: self.d2 - o.d2,
        }
    }
}

/// u v: (u v, u̇ v + u v̇, ü v + 2 u̇ v̇ + u v̈).
impl Mul for Jet {
    type Output = Jet;
    #[inline]
    fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v * o.v,
            d1: self.d1 * o.v + self.v * o.d1,
            d2: self.d2 * o.v + 2.0 * self.d1 * o.d1 + self.v * o.d2,
        }
    }
}

/// u / v (the quotient rule of the module doc).
impl Div for Jet {
    type Output = Jet;
    #[inline]
    fn div(self, o: Jet) -> Jet {
        let f = self.v / o.v;
        let d1 = (self.d1 - f * o.d1) / o.v;
        let d2 = (self.d2 - 2.0 * d1 * o.d1 - f * o.d2) / o.v;
        Jet { v: f, d1, d2 }
    }
}

/// −1, 0 or 1 (NaN for NaN); unlike `f64::signum`, 0 for ±0.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else if x == 0.0 {
        0.0
    } else {
        f64::NAN
    }
}
