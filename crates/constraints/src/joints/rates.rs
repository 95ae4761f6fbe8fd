//! Rates and accelerations of the joint coordinates, exact (no differencing): each coordinate is
//! a function of dot products, cross products and lengths of marker vectors, evaluated here on
//! second-order jets (value, first and second time derivative) of those vectors.
//!
//! A vector fixed in body k (local s') is s = A_k s' with ṡ = A_k (ω'_k × s') and
//! s̈ = A_k (ω̇'_k × s' + ω'_k × (ω'_k × s')); a point adds r_k, ṙ_k, r̈_k. Then
//! (aᵀb)˙ = ȧᵀb + aᵀḃ, (aᵀb)¨ = äᵀb + 2ȧᵀḃ + aᵀb̈; for θ = atan2(u, w) with n = u² + w²,
//! θ̇ = (w u̇ − u ẇ)/n and θ̈ = (w ü − u ẅ)/n − θ̇ ṅ/n; for |d|, (|d|)˙ = dᵀḋ/|d|. The Bryant
//! angles of the spherical joint use R = A_Iᵀ A_J = R_x(φ) R_y(θ) R_z(ψ): φ = atan2(−R₂₃, R₃₃),
//! θ = asin R₁₃, ψ = atan2(−R₁₂, R₁₁) (their rates are undefined at gimbal lock, θ = ±90°).

use super::{Axis, Joint, Measure, MAX_COORDINATES};
use crate::state::{BodyPair, BodyState};
use nalgebra::{Matrix3, Vector3};

/// A body's accelerations: r̈ (global) and ω̇' (body frame). Zero for ground.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyAcceleration {
    /// r̈, global.
    pub r_ddot: Vector3<f64>,
    /// ω̇', body components.
    pub omega_dot_local: Vector3<f64>,
}

/// The rates and accelerations of a joint's coordinates (the first `coordinates.len()` entries
/// of [`Joint::coordinates`] are meaningful), rad/s or m/s and rad/s² or m/s².
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointRates {
    /// ċ.
    pub rates: [f64; MAX_COORDINATES],
    /// c̈.
    pub accelerations: [f64; MAX_COORDINATES],
}

/// A scalar with its first two time derivatives.
#[derive(Debug, Clone, Copy)]
struct Jet {
    v: f64,
    d: f64,
    dd: f64,
}

impl Jet {
    fn neg(self) -> Jet {
        Jet {
            v: -self.v,
            d: -self.d,
            dd: -self.dd,
        }
    }

    /// atan2(self, w).
    fn atan2(self, w: Jet) -> Jet {
        let u = self;
        let n = u.v * u.v + w.v * w.v;
        let d = (w.v * u.d - u.v * w.d) / n;
        let dn = 2.0 * (u.v * u.d + w.v * w.d);
        Jet {
            v: u.v.atan2(w.v),
            d,
            dd: (w.v * u.dd - u.v * w.dd) / n - d * dn / n,
        }
    }

    fn asin(self) -> Jet {
        let c2 = 1.0 - self.v * self.v;
        let c = c2.sqrt();
        Jet {
            v: self.v.asin(),
            d: self.d / c,
            dd: self.dd / c + self.v * self.d * self.d / (c2 * c),
        }
    }
}

/// A 3-vector with its first two time derivatives.
#[derive(Debug, Clone, Copy)]
struct Jet3 {
    v: Vector3<f64>,
    d: Vector3<f64>,
    dd: Vector3<f64>,
}

impl Jet3 {
    /// A direction fixed in a body.
    fn dir(b: &BodyState, acc: &BodyAcceleration, s: &Vector3<f64>) -> Jet3 {
        let w = &b.omega_local;
        Jet3 {
            v: b.a * s,
            d: b.a * w.cross(s),
            dd: b.a * (acc.omega_dot_local.cross(s) + w.cross(&w.cross(s))),
        }
    }

    /// A point fixed in a body.
    fn point(b: &BodyState, acc: &BodyAcceleration, s: &Vector3<f64>) -> Jet3 {
        let mut p = Jet3::dir(b, acc, s);
        p.v += b.r;
        p.d += b.r_dot;
        p.dd += acc.r_ddot;
        p
    }

    fn sub(&self, o: &Jet3) -> Jet3 {
        Jet3 {
            v: self.v - o.v,
            d: self.d - o.d,
            dd: self.dd - o.dd,
        }
    }

    fn dot(&self, o: &Jet3) -> Jet {
        Jet {
            v: self.v.dot(&o.v),
            d: self.d.dot(&o.v) + self.v.dot(&o.d),
            dd: self.dd.dot(&o.v) + 2.0 * self.d.dot(&o.d) + self.v.dot(&o.dd),
        }
    }

    fn cross(&self, o: &Jet3) -> Jet3 {
        Jet3 {
            v: self.v.cross(&o.v),
            d: self.d.cross(&o.v) + self.v.cross(&o.d),
            dd: self.dd.cross(&o.v) + 2.0 * self.d.cross(&o.d) + self.v.cross(&o.dd),
        }
    }

    fn norm(&self) -> Jet {
        let n = self.v.norm();
        let dn = self.v.dot(&self.d) / n;
        Jet {
            v: n,
            d: dn,
            dd: (self.d.dot(&self.d) + self.v.dot(&self.dd)) / n - dn * dn / n,
        }
    }
}

impl Joint {
    /// The rates and accelerations of [`Joint::coordinates`] from the bodies' velocities (in
    /// `x`) and accelerations (`acc_i`, `acc_j`; zero for ground). Angles' rates do not depend
    /// on the turn count; the Bryant angles' are undefined at gimbal lock.
    pub fn coordinate_rates(
        &self,
        x: &BodyPair,
        acc_i: &BodyAcceleration,
        acc_j: &BodyAcceleration,
    ) -> JointRates {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let axes = |b: &BodyState, acc: &BodyAcceleration, f: &Matrix3<f64>| {
            [0, 1, 2].map(|k| Jet3::dir(b, acc, &f.column(k).into_owned()))
        };
        let [xi, yi, zi] = axes(x.i, acc_i, &mi.frame);
        let [xj, yj, zj] = axes(x.j, acc_j, &mj.frame);
        let d = Jet3::point(x.j, acc_j, &mj.point).sub(&Jet3::point(x.i, acc_i, &mi.point));
        let axis_i = |a: Axis| match a {
            Axis::X => &xi,
            Axis::Y => &yi,
            Axis::Z => &zi,
        };
        let r = |a: &Jet3, b: &Jet3| a.dot(b);
        let mut out = JointRates::default();
        for (k, c) in self.kind.info().coordinates.iter().enumerate() {
            let j = match c.measure {
                Measure::Angle => r(&yi, &xj).atan2(r(&xi, &xj)),
                Measure::Slide => r(&zi, &d),
                Measure::Offset(a) => r(axis_i(a), &d),
                Measure::Distance => d.norm(),
                Measure::CrossAngleI => r(&yi, &zj).atan2(r(&xi, &zj)),
                Measure::CrossAngleJ => r(&yj, &zi).atan2(r(&xj, &zi)),
                Measure::AxisAngle => r(&yi, &zj).neg().atan2(r(&zi, &zj)),
                Measure::Bend => zi.cross(&zj).norm().atan2(r(&zi, &zj)),
                Measure::Azimuth => r(&yi, &d).atan2(r(&xi, &d)),
                Measure::Bryant(0) => r(&yi, &zj).neg().atan2(r(&zi, &zj)),
                Measure::Bryant(1) => r(&xi, &zj).asin(),
                Measure::Bryant(_) => r(&xi, &yj).neg().atan2(r(&xi, &xj)),
            };
            out.rates[k] = j.d;
            out.accelerations[k] = j.dd;
        }
        out
    }
}
