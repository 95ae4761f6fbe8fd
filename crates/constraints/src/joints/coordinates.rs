//! Relative joint coordinates for output: angles and slides measured between the markers.

use super::{Joint, JointKind};
use crate::state::BodyPair;
use cardan_eulerparam::{euler_123_from_p, p_from_rotation_matrix};
use std::f64::consts::PI;

/// The relative coordinates of a joint, named.
///
/// Angles are principal values in (−π, π]; follow them over many turns with [`unwrap_angle`]
/// (a time-stepping caller keeps the previous value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointCoordinates {
    /// The names of the coordinates (e.g. ["angle"] or ["angle", "slide"]).
    pub names: &'static [&'static str],
    /// Their values (the first `names.len()` entries are meaningful).
    pub values: [f64; 3],
}

impl JointCoordinates {
    /// The meaningful values.
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.names.len()]
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

impl Joint {
    /// The joint's relative coordinates at the bodies' current poses.
    ///
    /// - revolute: `angle` of x_j from x_i about z_i, atan2(y_iᵀ x_j, x_iᵀ x_j);
    /// - prismatic: `slide` z_iᵀ d, d = P_j − P_i;
    /// - cylindrical: `angle` and `slide` as above;
    /// - universal: `angle_i`, the cross's rotation about arm z_i relative to body i,
    ///   atan2(y_iᵀ z_j, x_iᵀ z_j), and `angle_j`, body j's rotation about arm z_j relative to the
    ///   cross, atan2(y_jᵀ z_i, x_jᵀ z_i);
    /// - spherical: Bryant 1-2-3 angles of marker frame j relative to marker frame i;
    /// - planar: `x`, `y` of P_j in marker frame i and `angle` about z_i;
    /// - spherical-spherical: the current `distance` |d|;
    /// - fixed: none.
    pub fn coordinates(&self, x: &BodyPair) -> JointCoordinates {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let fi = x.i.a * mi.frame; // global columns x_i, y_i, z_i
        let fj = x.j.a * mj.frame;
        let (xi, yi, zi) = (fi.column(0), fi.column(1), fi.column(2));
        let (xj, yj, zj) = (fj.column(0), fj.column(1), fj.column(2));
        let d = x.j.point(&mj.point) - x.i.point(&mi.point);
        let angle = yi.dot(&xj).atan2(xi.dot(&xj));
        let c = |names: &'static [&'static str], v: [f64; 3]| JointCoordinates { names, values: v };
        match self.kind {
            JointKind::Revolute => c(&["angle"], [angle, 0.0, 0.0]),
            JointKind::Prismatic => c(&["slide"], [zi.dot(&d), 0.0, 0.0]),
            JointKind::Cylindrical => c(&["angle", "slide"], [angle, zi.dot(&d), 0.0]),
            JointKind::Universal => c(
                &["angle_i", "angle_j"],
                [
                    yi.dot(&zj).atan2(xi.dot(&zj)),
                    yj.dot(&zi).atan2(xj.dot(&zi)),
                    0.0,
                ],
            ),
            JointKind::Spherical => {
                let rel = fi.transpose() * fj;
                let (a, b, g) = p_from_rotation_matrix(&rel)
                    .map(|p| euler_123_from_p(&p))
                    .unwrap_or((f64::NAN, f64::NAN, f64::NAN));
                c(&["angle_x", "angle_y", "angle_z"], [a, b, g])
            }
            JointKind::Planar => c(&["x", "y", "angle"], [xi.dot(&d), yi.dot(&d), angle]),
            JointKind::SphericalSpherical => c(&["distance"], [d.norm(), 0.0, 0.0]),
            JointKind::Fixed => c(&[], [0.0; 3]),
        }
    }
}
