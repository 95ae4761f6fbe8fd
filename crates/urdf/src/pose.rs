//! Rigid transforms of URDF: `<origin xyz="…" rpy="…"/>`.
//!
//! URDF's `rpy` are fixed-axis roll, pitch, yaw: R = R_z(yaw) R_y(pitch) R_x(roll) (a rotation
//! about the parent's x by roll, then about the parent's y by pitch, then about the parent's z
//! by yaw; the URDF specification, `urdf_model/pose.h` `Rotation::setFromRPY`). A pose maps child
//! coordinates to parent coordinates: p_parent = r + R p_child.

use nalgebra::{Matrix3, Vector3};

/// A rigid transform: the child frame's origin and axes in the parent frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Origin of the child frame, parent coordinates.
    pub r: Vector3<f64>,
    /// Rotation matrix: columns are the child's axes in the parent frame.
    pub a: Matrix3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity.
    pub const IDENTITY: Pose = Pose {
        r: Vector3::new(0.0, 0.0, 0.0),
        a: Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
    };

    /// The pose of `xyz`, `rpy` (R = R_z(yaw) R_y(pitch) R_x(roll)).
    pub fn from_xyz_rpy(xyz: Vector3<f64>, rpy: Vector3<f64>) -> Self {
        Self {
            r: xyz,
            a: rpy_matrix(rpy),
        }
    }

    /// `self ∘ other`: other's child frame in self's parent frame.
    pub fn then(&self, other: &Pose) -> Pose {
        Pose {
            r: self.r + self.a * other.r,
            a: self.a * other.a,
        }
    }

    /// A point given in the child frame, in the parent frame.
    pub fn point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.r + self.a * p
    }
}

/// R = R_z(y) R_y(p) R_x(r) for rpy = (r, p, y).
pub fn rpy_matrix(rpy: Vector3<f64>) -> Matrix3<f64> {
    let (sr, cr) = rpy.x.sin_cos();
    let (sp, cp) = rpy.y.sin_cos();
    let (sy, cy) = rpy.z.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rx(t: f64) -> Matrix3<f64> {
        let (s, c) = t.sin_cos();
        Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
    }
    fn ry(t: f64) -> Matrix3<f64> {
        let (s, c) = t.sin_cos();
        Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
    }
    fn rz(t: f64) -> Matrix3<f64> {
        let (s, c) = t.sin_cos();
        Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    }

    /// URDF's order: roll about x first, then pitch about y, then yaw about z, all fixed axes.
    #[test]
    fn rpy_is_fixed_axis_xyz() {
        let (r, p, y) = (0.3, -0.7, 1.9);
        let a = rpy_matrix(Vector3::new(r, p, y));
        assert!((a - rz(y) * ry(p) * rx(r)).norm() < 1e-15);
        // Not the other order.
        assert!((a - rx(r) * ry(p) * rz(y)).norm() > 0.1);
        // Pitch alone turns x towards −z.
        let a = rpy_matrix(Vector3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0));
        assert!((a * Vector3::x() + Vector3::z()).norm() < 1e-15);
    }

    #[test]
    fn composition_maps_child_points_to_the_grandparent() {
        let a = Pose::from_xyz_rpy(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.1, 0.2, 0.3));
        let b = Pose::from_xyz_rpy(Vector3::new(-0.5, 0.4, 0.0), Vector3::new(1.0, -0.2, 2.3));
        let p = Vector3::new(0.7, -0.1, 0.2);
        assert!((a.then(&b).point(&p) - a.point(&b.point(&p))).norm() < 1e-14);
    }
}
