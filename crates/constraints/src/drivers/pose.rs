//! Pose driver (general motion): the full pose of marker frame j relative to marker frame i
//! follows six time functions, three translations in frame i and three angles in a rotation
//! sequence. Six rows, one [`PoseDriver`] each (row k of the same prescription).
//!
//! With the marker frames A_I = A_i L_i, A_J = A_j L_j (L the marker frames in body
//! coordinates), the prescribed frame is E(t) = A_I R(t), R(t) = R_{o1}(a₁(t)) R_{o2}(a₂(t))
//! R_{o3}(a₃(t)) for a sequence o (e.g. x-y-z, or z-x-z), and d = P_j − P_i:
//!
//! ```text
//! rows 0–2:  x_Iᵀ d − f₁(t),  y_Iᵀ d − f₂(t),  z_Iᵀ d − f₃(t)          (as the translation driver)
//! rows 3–5:  x_Eᵀ z_J,  y_Eᵀ z_J,  x_Eᵀ y_J                            (as the fixed joint, to E)
//! x_E = A_i c_x(t), c_x(t) = L_i R(t) e_x: a body-i vector that turns with time
//! Φ_q  = the n1 / n2 rows at time t
//! ν    = ḟ (rows 0–2);  −(A_i ċ)ᵀ s_J (rows 3–5)
//! γ#   = −quad + f̈ (rows 0–2);  −[(A_i c)¨ᵀ s_J + 2 (A_i c)˙ᵀ ṡ_J + (A_i c)ᵀ s̈_J]_{q̈ = 0} (rows 3–5)
//! ```
//! where (A_i c)˙ = Ȧ_i c + A_i ċ and (A_i c)¨ at q̈ = 0 = (Ä_i c)_quad + 2 Ȧ_i ċ + A_i c̈; Ṙ, R̈
//! by the product rule over the three factors (d/da R_e(a) = [e×] R_e(a)). The rotation rows hold
//! on A_J = E(t) (and on the half-turn flips a Newton start near the pose never reaches), with
//! the fixed joint's full rank. Nikravesh 1988 §7.5 (drivers), Haug 1989 §9.5; OndselSolver's
//! GeneralMotion (`FullMotion`) prescribes the same.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;
use nalgebra::{Matrix3, Vector3};

/// A rotation sequence: the axes (0 = x, 1 = y, 2 = z) of R_{o1} R_{o2} R_{o3}, no axis twice in
/// a row (the 6 Cardan/Bryant and 6 proper Euler sequences).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RotationOrder(pub [usize; 3]);

impl RotationOrder {
    /// The sequence named by three letters, e.g. "xyz" or "zxz".
    pub fn parse(s: &str) -> Option<Self> {
        let axes: Vec<usize> = s
            .chars()
            .map(|c| match c {
                'x' | 'X' => Some(0),
                'y' | 'Y' => Some(1),
                'z' | 'Z' => Some(2),
                _ => None,
            })
            .collect::<Option<_>>()?;
        match axes[..] {
            [a, b, c] if a != b && b != c => Some(Self([a, b, c])),
            _ => None,
        }
    }

    /// Its three letters.
    pub fn name(self) -> String {
        self.0.iter().map(|&k| ['x', 'y', 'z'][k]).collect()
    }

    /// R(t), Ṙ(t), R̈(t) for the angles and their rates.
    fn rotation(self, a: [(f64, f64, f64); 3]) -> [Matrix3<f64>; 3] {
        let mut r = [Matrix3::identity(), Matrix3::zeros(), Matrix3::zeros()];
        for (axis, (v, d1, d2)) in self.0.into_iter().zip(a) {
            let e = Vector3::ith(axis, 1.0);
            let f = *nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(e), v)
                .matrix();
            let k = e.cross_matrix();
            let f = [f, k * f * d1, k * k * f * d1 * d1 + k * f * d2];
            r = [
                r[0] * f[0],
                r[1] * f[0] + r[0] * f[1],
                r[2] * f[0] + 2.0 * r[1] * f[1] + r[0] * f[2],
            ];
        }
        r
    }
}

/// Names of the six rows (translations along x_I, y_I, z_I, then the three angles).
pub const POSE_ROWS: [&str; 6] = ["x", "y", "z", "angle_1", "angle_2", "angle_3"];

/// Row `row` (0–5) of a pose prescription between `marker_i` and `marker_j`.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseDriver {
    /// Marker on body i: the frame the pose is given in.
    pub marker_i: Marker,
    /// Marker on body j: the frame that is moved.
    pub marker_j: Marker,
    /// The rotation sequence of the three angles.
    pub order: RotationOrder,
    /// f₁, f₂, f₃ (m) and a₁, a₂, a₃ (rad).
    pub functions: Box<[TimeFunction; 6]>,
    /// Which row (0–5).
    pub row: usize,
}

impl PoseDriver {
    /// Row `row` of the prescription; `row` < 6.
    pub fn new(
        marker_i: Marker,
        marker_j: Marker,
        order: RotationOrder,
        functions: [TimeFunction; 6],
        row: usize,
    ) -> Self {
        assert!(row < 6, "a pose driver has rows 0 to 5");
        Self {
            marker_i,
            marker_j,
            order,
            functions: Box::new(functions),
            row,
        }
    }

    /// The row's (body-i vector c, its first and second time derivatives) and the body-j
    /// vector it is dotted with, for the rotation rows 3–5.
    fn rotation_vectors(&self, t: f64) -> ([Vector3<f64>; 3], Vector3<f64>) {
        let f = &self.functions;
        let r = self
            .order
            .rotation([f[3].eval(t), f[4].eval(t), f[5].eval(t)]);
        let (ea, sj) = match self.row {
            3 => (0, self.marker_j.z()),
            4 => (1, self.marker_j.z()),
            _ => (0, self.marker_j.y()),
        };
        let li = &self.marker_i.frame;
        (r.map(|m| li * m.column(ea)), sj)
    }

    /// How far the marker frame J is from the prescribed E(t) in sign (row 3 only; 0 for the
    /// other rows): the rotation rows also hold on the half-turn flips of A_J about an axis of
    /// E, where x_Eᵀ x_J or z_Eᵀ z_J is −1 instead of 1. Returns 1 − min(x_Eᵀ x_J, z_Eᵀ z_J)
    /// when that minimum is not positive (≥ 1: a spurious root), 0 otherwise.
    pub fn branch_error(&self, x: &BodyPair, t: f64) -> f64 {
        if self.row != 3 {
            return 0.0;
        }
        let f = &self.functions;
        let [r, ..] = self
            .order
            .rotation([f[3].eval(t), f[4].eval(t), f[5].eval(t)]);
        let e = x.i.a * self.marker_i.frame * r;
        let j = x.j.a * self.marker_j.frame;
        let m = e
            .column(0)
            .dot(&j.column(0))
            .min(e.column(2).dot(&j.column(2)));
        if m > 0.0 {
            0.0
        } else {
            1.0 - m
        }
    }

    /// A translation row's coordinate x_Iᵀ d (m); for a rotation row, the angle its function
    /// prescribes (the three angles are not separable row by row, so a rotation row reports
    /// its prescription at t = 0: assembly moves pose drivers in one piece, not by continuation).
    pub fn coordinate(&self, x: &BodyPair) -> f64 {
        if self.row < 3 {
            let d = x.j.point(&self.marker_j.point) - x.i.point(&self.marker_i.point);
            x.i.vector(&self.axis_i()).dot(&d)
        } else {
            self.functions[self.row].eval(0.0).0
        }
    }

    /// The body-i axis of a translation row (x, y or z of marker i).
    fn axis_i(&self) -> Vector3<f64> {
        self.marker_i.frame.column(self.row).into()
    }
}

impl Constraint for PoseDriver {
    fn dimension(&self, _row: usize) -> Dimension {
        if self.row < 3 {
            Dimension::Length
        } else {
            Dimension::Dimensionless
        }
    }
    fn name(&self) -> &'static str {
        "pose_driver"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        let u = if self.row < 3 {
            BlockUse::RP
        } else {
            BlockUse::P
        };
        Footprint { i: u, j: u }
    }
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = if self.row < 3 {
            let d = x.j.point(&self.marker_j.point) - x.i.point(&self.marker_i.point);
            x.i.vector(&self.axis_i()).dot(&d) - self.functions[self.row].eval(t).0
        } else {
            let ([c, ..], sj) = self.rotation_vectors(t);
            x.i.vector(&c).dot(&x.j.vector(&sj))
        };
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let g = if self.row < 3 {
            let a = Grad::dir::<F>(x.i, x.j, Side::I, &self.axis_i());
            a.dot(&Grad::between::<F>(
                x.i,
                x.j,
                &self.marker_i.point,
                &self.marker_j.point,
            ))
        } else {
            let ([c, ..], sj) = self.rotation_vectors(t);
            Grad::dir::<F>(x.i, x.j, Side::I, &c).dot(&Grad::dir::<F>(x.i, x.j, Side::J, &sj))
        };
        g.write(&mut out_i[0], &mut out_j[0]);
    }
    fn nu(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = if self.row < 3 {
            self.functions[self.row].eval(t).1
        } else {
            let ([_, dc, _], sj) = self.rotation_vectors(t);
            -x.i.vector(&dc).dot(&x.j.vector(&sj))
        };
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = if self.row < 3 {
            let a = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.axis_i());
            let d = Motion::between::<N, F>(x.i, x.j, &self.marker_i.point, &self.marker_j.point);
            -a.dot(&d).quad + self.functions[self.row].eval(t).2
        } else {
            let ([c, dc, ddc], sj) = self.rotation_vectors(t);
            // A_i c(t): its rate and q̈-free acceleration include the turning of c.
            let mut u = Motion::dir::<N, F>(x.i, x.j, Side::I, &c);
            let du = Motion::dir::<N, F>(x.i, x.j, Side::I, &dc);
            u.rate += du.v;
            u.quad += 2.0 * du.rate + x.i.vector(&ddc);
            -u.dot(&Motion::dir::<N, F>(x.i, x.j, Side::J, &sj)).quad
        };
    }
}
