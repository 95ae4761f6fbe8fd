//! Each surface's jet against central differences of its own lower derivatives, and its
//! nearest-point projection returning the parameters of points on it.

use super::*;
use crate::marker::Marker;
use nalgebra::{Matrix3, Vector3};

fn frame() -> Marker {
    let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
    Marker::new(Vector3::new(0.2, -0.1, 0.4), r).unwrap()
}

fn every() -> Vec<Surface> {
    let m = frame();
    let mut pts = [[Vector3::zeros(); 4]; 4];
    for (i, row) in pts.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            let (x, y) = (i as f64 / 3.0, j as f64 / 3.0);
            *p = Vector3::new(x, y, 0.3 * (x * y) + 0.1 * (i * j % 3) as f64);
        }
    }
    vec![
        Plane::new(&m).into(),
        Sphere::new(&m, 0.7).unwrap().into(),
        Cylinder::new(&m, 0.5).unwrap().into(),
        Torus::new(&m, 1.2, 0.4).unwrap().into(),
        BicubicPatch::new(pts).unwrap().into(),
    ]
}

#[test]
fn jets_are_the_derivatives_of_the_points() {
    let h = 1e-5;
    for s in every() {
        for &(u, v) in &[(0.31, -0.22), (0.8, 0.45), (-1.3, 0.1)] {
            let j = s.jet(u, v);
            let d = |f: &dyn Fn(f64, f64) -> Vector3<f64>, du: f64, dv: f64| {
                (f(u + du * h, v + dv * h) - f(u - du * h, v - dv * h)) / (2.0 * h)
            };
            let checks = [
                (j.s_u, d(&|u, v| s.jet(u, v).s, 1.0, 0.0)),
                (j.s_v, d(&|u, v| s.jet(u, v).s, 0.0, 1.0)),
                (j.s_uu, d(&|u, v| s.jet(u, v).s_u, 1.0, 0.0)),
                (j.s_uv, d(&|u, v| s.jet(u, v).s_u, 0.0, 1.0)),
                (j.s_uv, d(&|u, v| s.jet(u, v).s_v, 1.0, 0.0)),
                (j.s_vv, d(&|u, v| s.jet(u, v).s_v, 0.0, 1.0)),
            ];
            for (k, (exact, fd)) in checks.iter().enumerate() {
                let err = (exact - fd).norm();
                assert!(
                    err < 1e-8,
                    "{} derivative {k} at ({u}, {v}): {err}",
                    s.kind()
                );
            }
        }
    }
}

#[test]
fn the_nearest_point_of_a_surface_point_is_itself() {
    for s in every() {
        let (u, v) = match s {
            Surface::Bicubic(_) => (0.37, 0.61),
            _ => (0.21, 0.13),
        };
        let p = s.jet(u, v).s;
        let [a, b] = s.closest(&p);
        let err = (s.jet(a, b).s - p).norm();
        assert!(err < 1e-12, "{}: {err}", s.kind());
    }
}

#[test]
fn a_flat_patch_is_its_plane_and_bad_data_is_refused() {
    let mut pts = [[Vector3::zeros(); 4]; 4];
    for (i, row) in pts.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            *p = Vector3::new(i as f64, j as f64, 0.0);
        }
    }
    let patch = BicubicPatch::new(pts).unwrap();
    let j = patch.jet(0.4, 0.7);
    assert!((j.s - Vector3::new(1.2, 2.1, 0.0)).norm() < 1e-15);
    assert!((j.s_u - Vector3::new(3.0, 0.0, 0.0)).norm() < 1e-14);
    pts[2][1].x = f64::NAN;
    assert!(BicubicPatch::new(pts).is_err());
    assert!(BicubicPatch::new([[Vector3::zeros(); 4]; 4]).is_err());
    let m = Marker::new(Vector3::zeros(), Matrix3::identity()).unwrap();
    assert!(Torus::new(&m, 1.0, 1.5).is_err());
    assert!(Sphere::new(&m, -1.0).is_err());
    assert!(Cylinder::new(&m, 0.0).is_err());
}
