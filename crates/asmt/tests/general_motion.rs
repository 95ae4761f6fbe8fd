//! GeneralMotion (none of the ten testapp files has one): `general_motion.asmt` is piston.asmt
//! cut down to its first part, moved relative to a ground marker by a GeneralMotion with
//! RotationOrder 3 1 3. The solved pose must be the prescribed one: marker J = marker I
//! translated by rIJI(t) along I's axes and turned by Rz(a₁) Rx(a₂) Rz(a₃).

use cardan_mechanism::KinematicOptions;
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::path::PathBuf;

fn frame(import: &cardan_asmt::Import, body: &str, m: &str) -> (Vector3<f64>, Matrix3<f64>) {
    let get = |list: &[cardan_asmt::import::Feature], n: &str| {
        list.iter()
            .find(|f| f.body == body && f.name == n)
            .unwrap()
            .value
    };
    let p = get(&import.points, m);
    let x = get(&import.vectors, &format!("{m}_x")).normalize();
    let z = get(&import.vectors, &format!("{m}_z")).normalize();
    (p, Matrix3::from_columns(&[x, z.cross(&x), z]))
}

#[test]
fn general_motion_puts_marker_j_where_prescribed() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/general_motion.asmt");
    let (_, import) = cardan_asmt::load(&std::fs::read_to_string(p).unwrap()).unwrap();
    let model = import.builder().build().unwrap();
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 20))
        .unwrap();
    let (ri, ai) = frame(&import, "ground", "Marker1");
    let (sj, aj_local) = frame(&import, "Part1", "Marker1");
    let body = res.body("Part1").unwrap();
    for (k, &t) in res.times.iter().enumerate() {
        let a = cardan_eulerparam::a(&body.p[k]);
        let rj = body.r[k] + a * sj;
        let aj = a * aj_local;
        let f = Vector3::new(0.1 * t.sin(), 0.2, -0.3 * t);
        let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.5 * t)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), 0.25)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI * t * t);
        assert!((rj - (ri + ai * f)).norm() < 1e-12, "t = {t}: position");
        assert!(
            (aj - ai * rot.matrix()).abs().max() < 1e-12,
            "t = {t}: rotation"
        );
    }
}
