//! A tour of the Euler-parameter layer: build p several ways, rotate vectors, map velocities.
//!
//! Run with `cargo run -p cardan-eulerparam --example rotations`.

use cardan_eulerparam::{
    a, da_dp, euler_313_from_p, frame_from_two_axes, g, l, omega_local, p_dot_from_local,
    p_from_euler_313, EulerParams,
};
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 120° about the body diagonal maps x → y → z → x.
    let p = EulerParams::from_axis_angle(&Vector3::new(1.0, 1.0, 1.0), 120f64.to_radians())?;
    println!("p (120° about [1,1,1]) = {:?}", p.as_vector().as_slice());
    println!(
        "A(p) x = {:?}",
        (a(p.as_vector()) * Vector3::x()).as_slice()
    );
    println!(
        "A = G Lᵀ: |A − G Lᵀ| = {:.1e}",
        (p.a() - g(p.as_vector()) * l(p.as_vector()).transpose()).norm()
    );

    // Shepperd's method at exactly 180°.
    let half_turn =
        EulerParams::from_axis_angle(&Vector3::new(0.0, 1.0, 1.0), std::f64::consts::PI)?;
    let back = EulerParams::from_rotation_matrix(&half_turn.a())?;
    println!(
        "180° round trip: {:?} -> {:?}",
        half_turn.as_vector().as_slice(),
        back.as_vector().as_slice()
    );

    // Euler angles 3-1-3.
    let q = p_from_euler_313(0.3, 1.1, -0.7)?;
    println!(
        "3-1-3 (0.3, 1.1, -0.7) round trip: {:?}",
        euler_313_from_p(&q)
    );

    // A joint marker frame from a z axis and an x hint.
    let frame = frame_from_two_axes(&Vector3::new(0.0, 0.0, 2.0), &Vector3::new(1.0, 1.0, 0.0))?;
    println!("frame from z = [0,0,2], x ~ [1,1,0]:\n{frame}");

    // Velocity maps and the derivative ∂(A a')/∂p.
    let w_local = Vector3::new(0.0, 0.0, 6.0);
    let p_dot = p_dot_from_local(p.as_vector(), &w_local);
    println!(
        "ω' = {:?} -> ṗ = {:?} -> ω' = {:?}",
        w_local.as_slice(),
        p_dot.as_slice(),
        omega_local(p.as_vector(), &p_dot).as_slice()
    );
    println!("∂(A x')/∂p =\n{}", da_dp(p.as_vector(), &Vector3::x()));
    Ok(())
}
