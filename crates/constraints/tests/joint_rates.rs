//! The exact joint coordinate rates and accelerations (`Joint::coordinate_rates`) against
//! central differences of the coordinates along a motion with the same velocities and
//! accelerations, for every kind of the kind table.

use cardan_constraints::conformance::Sampler;
use cardan_constraints::joints::{BodyAcceleration, CoordinateQuantity};
use cardan_constraints::{unwrap_angle, BodyPair, BodyState, KINDS};
use cardan_eulerparam::p_from_rotation_matrix;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// A body moving with r(t) = r + ṙt + r̈t²/2 and A(t) = A exp([ω't + ω̇'t²/2]×), whose first two
/// derivatives at t = 0 are those of (ṙ, ω') and (r̈, ω̇').
struct Motion {
    r: Vector3<f64>,
    a: Matrix3<f64>,
    v: Vector3<f64>,
    w: Vector3<f64>,
    acc: BodyAcceleration,
}

impl Motion {
    fn random(s: &mut Sampler) -> Self {
        Motion {
            r: s.point(),
            a: s.rotation(),
            v: s.point(),
            w: s.direction(),
            acc: BodyAcceleration {
                r_ddot: s.point(),
                omega_dot_local: s.direction(),
            },
        }
    }

    fn at(&self, t: f64) -> BodyState {
        let r = self.r + self.v * t + 0.5 * self.acc.r_ddot * t * t;
        let turn = self.w * t + 0.5 * self.acc.omega_dot_local * t * t;
        let a = self.a * Rotation3::new(turn).matrix();
        let p = p_from_rotation_matrix(&a).unwrap();
        let w = self.w + self.acc.omega_dot_local * t; // not used off t = 0
        BodyState::at(r, *p.as_vector()).with_v(self.v, w)
    }
}

#[test]
fn joint_rates_and_accelerations_match_differences_of_the_coordinates() {
    let h = 1e-4;
    let mut worst: Vec<(f64, &str)> = Vec::new();
    for seed in 0..20u64 {
        let mut s = Sampler::new(seed, 1.0, false);
        for info in KINDS {
            let joint = s.joint(info.kind);
            let (mi, mj) = (Motion::random(&mut s), Motion::random(&mut s));
            let c = |t: f64| {
                let (bi, bj) = (mi.at(t), mj.at(t));
                joint.coordinates(&BodyPair::new(&bi, &bj))
            };
            let (c0, cm, cp) = (c(0.0), c(-h), c(h));
            let (b0i, b0j) = (mi.at(0.0), mj.at(0.0));
            let exact = joint.coordinate_rates(&BodyPair::new(&b0i, &b0j), &mi.acc, &mj.acc);
            for (k, coord) in info.coordinates.iter().enumerate() {
                let (mut lo, mut hi) = (cm.values[k], cp.values[k]);
                if coord.measure.quantity() == CoordinateQuantity::Angle {
                    lo = unwrap_angle(c0.values[k], lo);
                    hi = unwrap_angle(c0.values[k], hi);
                }
                let rate = (hi - lo) / (2.0 * h);
                let acc = (hi - 2.0 * c0.values[k] + lo) / (h * h);
                let scale = 1.0 + exact.rates[k].abs() + exact.accelerations[k].abs();
                let e = ((rate - exact.rates[k]).abs()
                    + 1e-3 * (acc - exact.accelerations[k]).abs())
                    / scale;
                worst.push((e, info.name));
                assert!(
                    (rate - exact.rates[k]).abs() < 1e-6 * scale
                        && (acc - exact.accelerations[k]).abs() < 1e-3 * scale,
                    "{} {} (seed {seed}): rate {} vs {rate}, acceleration {} vs {acc}",
                    info.name,
                    coord.name,
                    exact.rates[k],
                    exact.accelerations[k]
                );
            }
        }
    }
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    eprintln!("largest relative differences: {:?}", &worst[..3]);
}
