//! The curves of a model's curve elements drawn in the animation: each curve (a slot, a track,
//! a path, a cam's profile, a follower's face or roller) as a chain of thin rods on the body that
//! carries it, sampled in that body's coordinates.
//!
//! What is drawn of each curve: a circle or a closed spline whole (96 rods); an open spline over
//! its data (16 rods per segment, at most 512); a line or a helix over the stretch its parameter
//! covered in the run, widened by a tenth of the mechanism's extent at each end (a helix: 48 rods
//! per turn, at most 512). The rods' radius is L/150, thinner than the bodies' rods (L/100).

use cardan_constraints::Curve;
use cardan_mechanism::{BodyId, Model, Results};
use cardan_report::{Geometry, Shape};
use nalgebra::Vector3;

/// Each curve element's curves as rods: (the carrying body, as `BodyId`, and its rods in its
/// coordinates).
pub fn curve_rods(model: &Model, results: &Results, extent: f64) -> Vec<(BodyId, Vec<Geometry>)> {
    let mut out = Vec::new();
    for c in model.curves() {
        let bodies = [c.body_i, c.body_j];
        let params = c.element.parameters();
        for (k, curve) in c.element.curves().into_iter().enumerate() {
            let Some(curve) = curve else {
                continue;
            };
            let history = results.curve_parameter(&c.name, params[k]);
            let covered = history.map_or((c.initial[k], c.initial[k]), |h| {
                (h.u.iter()).fold((c.initial[k], c.initial[k]), |(a, b), &u| {
                    (a.min(u), b.max(u))
                })
            });
            let samples = samples(curve, covered, extent);
            out.push((bodies[k], rods(curve, &samples, extent / 150.0)));
        }
    }
    out
}

/// The parameters at which `curve` is sampled (module docs).
fn samples(curve: &Curve, (lo, hi): (f64, f64), extent: f64) -> Vec<f64> {
    let (a, b, n) = match (curve.domain(), curve.period(), curve) {
        (Some((a, b)), _, Curve::Cubic(c)) => (a, b, 16 * (c.knots().len() - 1)),
        (_, Some(l), _) => (0.0, l, 96),
        (_, _, Curve::Helix(h)) => {
            let (a, b) = (lo - 0.1 * extent, hi + 0.1 * extent);
            let turn = std::f64::consts::TAU * h.radius() / (h.curvature() * h.radius()).sqrt();
            (a, b, (48.0 * (b - a) / turn).ceil() as usize)
        }
        _ => (lo - 0.1 * extent, hi + 0.1 * extent, 1),
    };
    let n = n.clamp(1, 512);
    (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

/// Rods of radius `radius` between the curve's points at consecutive `samples`.
fn rods(curve: &Curve, samples: &[f64], radius: f64) -> Vec<Geometry> {
    let points: Vec<Vector3<f64>> = samples.iter().map(|&u| curve.jet(u).c).collect();
    (points.windows(2))
        .filter_map(|w| {
            let s = w[1] - w[0];
            let length = s.norm();
            (length > 0.0).then(|| {
                let mid = (w[0] + w[1]) / 2.0;
                Geometry {
                    shape: Shape::Cylinder { radius, length },
                    position: [mid.x, mid.y, mid.z],
                    rotation: along(&s),
                }
            })
        })
        .collect()
}

/// Euler parameters of a frame whose z axis is along `s`.
pub(crate) fn along(s: &Vector3<f64>) -> [f64; 4] {
    cardan_eulerparam::frame_from_axis(s)
        .and_then(|f| cardan_eulerparam::EulerParams::from_rotation_matrix(&f))
        .map(|p| [p.e0(), p.e().x, p.e().y, p.e().z])
        .unwrap_or([1.0, 0.0, 0.0, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use cardan_mechanism::KinematicOptions;

    fn run(name: &str) -> (crate::prepare::Prepared, Results) {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(format!("{name}.toml"));
        let p = crate::prepare::prepare(&path).unwrap();
        let a = p.loaded.analysis.as_ref().unwrap();
        let r = (p.model)
            .run_kinematics(&KinematicOptions::new(a.t_start, a.t_end, 20))
            .unwrap();
        (p, r)
    }

    /// The rods' ends, back from their midpoints, lengths and directions.
    fn ends(g: &Geometry) -> (Vector3<f64>, Vector3<f64>) {
        let Shape::Cylinder { length, .. } = g.shape else {
            panic!("a rod is a cylinder")
        };
        let q = g.rotation;
        let a = cardan_eulerparam::a(&nalgebra::Vector4::new(q[0], q[1], q[2], q[3]));
        let half = a.column(2) * (length / 2.0);
        let mid = Vector3::from(g.position);
        (mid - half, mid + half)
    }

    #[test]
    fn a_cam_disc_is_drawn_whole_on_the_camshaft_and_the_face_over_its_contacts() {
        let (p, r) = run("valve_train");
        let drawn = curve_rods(&p.model, &r, 0.05);
        assert_eq!(drawn.len(), 2);
        let (cam, face) = (&drawn[0], &drawn[1]);
        assert_eq!(cam.0, BodyId::Moving(0));
        assert_eq!(cam.1.len(), 96);
        // Every rod's ends on the disc: radius 0.02 about C = (0, −0.005, 0) of the camshaft.
        let centre = Vector3::new(0.0, -0.005, 0.0);
        for g in &cam.1 {
            let (a, b) = ends(g);
            assert!(((a - centre).norm() - 0.02).abs() < 1e-12);
            assert!(((b - centre).norm() - 0.02).abs() < 1e-12);
        }
        // The face: one rod along the tappet's x over the contact's travel w ∈ [−e, e], widened
        // by a tenth of the extent at each end.
        assert_eq!(face.0, BodyId::Moving(1));
        assert_eq!(face.1.len(), 1);
        let (a, b) = ends(&face.1[0]);
        assert!(
            (a - Vector3::new(-0.005 - 0.005, 0.0, 0.0)).norm() < 1e-6,
            "{a}"
        );
        assert!(
            (b - Vector3::new(0.005 + 0.005, 0.0, 0.0)).norm() < 1e-6,
            "{b}"
        );
    }
}
