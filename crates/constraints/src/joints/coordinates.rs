//! Relative joint coordinates for output: angles and slides measured between the markers.

use super::{Axis, Coordinate, Joint, Measure, MAX_COORDINATES};
use crate::state::BodyPair;
use cardan_eulerparam::{euler_123_from_p, p_from_rotation_matrix};
use std::f64::consts::PI;

/// The relative coordinates of a joint, named.
///
/// Angles are principal values in (−π, π]; follow them over many turns with [`unwrap_angle`]
/// (a time-stepping caller keeps the previous value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointCoordinates {
    /// The coordinates (names and measures; e.g. `angle`, or `angle` and `slide`).
    pub coordinates: &'static [Coordinate],
    /// Their values (the first `names.len()` entries are meaningful).
    pub values: [f64; MAX_COORDINATES],
}

impl JointCoordinates {
    /// The meaningful values.
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.coordinates.len()]
    }
}

/// Continues an angle over many turns: the value congruent to `principal` (mod 2π) nearest to
/// `previous`. Valid as long as the angle changes by less than π between two calls.
pub fn unwrap_angle(previous: f64, principal: f64) -> f64 {
    let mut d = (principal - previous) % (2.0 * PI);
    if d > PI {
        d -= 2.0 * PI;
    } else if d <= -PI {
        d += 2.0 * PI;
    }
    previous + d
}

/// Continues an angle from its previous output value `previous` to the principal value
/// `principal` measured `dt` later, with the rates at both ends when they are known: the value
/// congruent to `principal` nearest to the trapezoidal prediction previous + dt (ω₀ + ω₁)/2.
/// With rates the angle may turn by many half-turns between outputs (the prediction errs by
/// O(dt³)); without, it must change by less than π ([`unwrap_angle`]). Rates that differ by
/// more than π/dt (a rate that jumps, as at a singular configuration) are not trusted: the
/// nearest-value rule is used.
pub fn continue_angle(previous: f64, rates: Option<(f64, f64)>, dt: f64, principal: f64) -> f64 {
    let guess = match rates {
        Some((w0, w1)) if ((w1 - w0) * dt).abs() < PI => previous + 0.5 * dt * (w0 + w1),
        _ => previous,
    };
    unwrap_angle(guess, principal)
}

impl Joint {
    /// The joint's relative coordinates at the bodies' current poses: its kind's
    /// [`KindInfo::coordinates`](super::KindInfo::coordinates), each by its [`Measure`] (with
    /// d = P_j − P_i and the global marker axes x_k, y_k, z_k):
    ///
    /// - [`Measure::Angle`]: x_j from x_i about z_i, atan2(y_iᵀ x_j, x_iᵀ x_j);
    /// - [`Measure::Slide`]: z_iᵀ d; [`Measure::Offset`]: x_iᵀ d or y_iᵀ d;
    /// - [`Measure::Distance`]: the length of d;
    /// - [`Measure::CrossAngleI`]: the universal joint's cross about arm z_i relative to body i,
    ///   atan2(y_iᵀ z_j, x_iᵀ z_j); [`Measure::CrossAngleJ`]: body j about arm z_j relative to
    ///   the cross, atan2(y_jᵀ z_i, x_jᵀ z_i);
    /// - [`Measure::Bryant`]: Bryant 1-2-3 angles of marker frame j relative to marker frame i;
    /// - [`Measure::AxisAngle`]: z_j from z_i about x_i, atan2(−y_iᵀ z_j, z_iᵀ z_j);
    /// - [`Measure::Bend`]: the angle between z_i and z_j, atan2(|z_i × z_j|, z_iᵀ z_j);
    /// - [`Measure::Azimuth`]: the direction of d across z_i, atan2(y_iᵀ d, x_iᵀ d).
    pub fn coordinates(&self, x: &BodyPair) -> JointCoordinates {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let fi = x.i.a * mi.frame; // global columns x_i, y_i, z_i
        let fj = x.j.a * mj.frame;
        let (xi, yi, zi) = (fi.column(0), fi.column(1), fi.column(2));
        let (xj, yj, zj) = (fj.column(0), fj.column(1), fj.column(2));
        let d = x.j.point(&mj.point) - x.i.point(&mi.point);
        let info = self.kind.info();
        let mut values = [0.0; MAX_COORDINATES];
        let mut bryant = None;
        for (v, c) in values.iter_mut().zip(info.coordinates) {
            *v = match c.measure {
                Measure::Angle => yi.dot(&xj).atan2(xi.dot(&xj)),
                Measure::Slide => zi.dot(&d),
                Measure::Offset(Axis::X) => xi.dot(&d),
                Measure::Offset(Axis::Y) => yi.dot(&d),
                Measure::Offset(Axis::Z) => zi.dot(&d),
                Measure::Distance => d.norm(),
                Measure::CrossAngleI => yi.dot(&zj).atan2(xi.dot(&zj)),
                Measure::CrossAngleJ => yj.dot(&zi).atan2(xj.dot(&zi)),
                Measure::AxisAngle => (-yi.dot(&zj)).atan2(zi.dot(&zj)),
                Measure::Bend => zi.cross(&zj).norm().atan2(zi.dot(&zj)),
                Measure::Azimuth => yi.dot(&d).atan2(xi.dot(&d)),
                Measure::Bryant(k) => {
                    let (a, b, g) = *bryant.get_or_insert_with(|| {
                        p_from_rotation_matrix(&(fi.transpose() * fj))
                            .map(|p| euler_123_from_p(&p))
                            .unwrap_or((f64::NAN, f64::NAN, f64::NAN))
                    });
                    [a, b, g][k]
                }
            };
        }
        JointCoordinates {
            coordinates: info.coordinates,
            values,
        }
    }
}
