//! Vibration modes as the report animates them, without any mechanics: per mode its label
//! numbers and, per body, the increment of the body coordinates q = [r; p] (position of the
//! body frame's origin and Euler parameters) along the mode.
//!
//! ## The animated pose
//! Mode k with shape φ_k = [δr; δp] per body (δp tangent to the unit sphere, p₀ᵀδp = 0) is
//! drawn at phase τ ∈ [0, 1) of one period as
//!
//! ```text
//! s = g a sin(2πτ),   r(τ) = r₀ + s δr,   p(τ) = (p₀ + s δp) / |p₀ + s δp|
//! ```
//!
//! about the rest pose q₀ = [r₀; p₀] (the equilibrium): the linearized motion q₀ + s φ_k with
//! the Euler parameters brought back to unit norm, so at a quarter period (τ = ¼) the pose is
//! q₀ + g a φ_k. The amplitude a ([`amplitude`]) makes the largest displacement of a body
//! origin or named point [`MODE_FRACTION`] of the model's size; g is the page's amplitude
//! slider (1 by default). The page's script computes the same pose ([`mode_pose`]) from the
//! shapes embedded in it, so one period costs 7 numbers per body and mode, not a keyframe per
//! frame.
//!
//! A small rotation δθ (global components) is the Euler-parameter increment
//! δp = ½ Gᵀ(p₀) δθ (Nikravesh 1988 ch. 6: ω = 2 G ṗ, ṗ = ½ Gᵀ ω), and back δθ = 2 G(p₀) δp, the
//! vector part of 2 δp ⊗ p̄₀; a point s' of the body moves by δr + δθ × A(p₀) s'.

use crate::rotate::rotate;
use crate::scene::Scene;
use crate::Error;

/// The largest displacement of a body origin or named point in a mode, as a fraction of the
/// model's size ([`Scene::extent`]), at the default amplitude.
pub const MODE_FRACTION: f64 = 0.1;

/// At most this many modes are animated (the lowest); a note on the page says how many more
/// the run computed (all of them are in `mode_shapes.csv`).
pub const MAX_ANIMATED_MODES: usize = 100;

/// One body's increment in a mode: δr and δp of its body coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyIncrement {
    /// δr of the body frame's origin [m per unit amplitude].
    pub dr: [f64; 3],
    /// δp of its Euler parameters [e0, e1, e2, e3] (tangent: p₀ᵀδp = 0).
    pub dp: [f64; 4],
}

/// One mode as the page lists and animates it.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeShape {
    /// Its number in `modes.csv` (1, 2, …).
    pub number: usize,
    /// `"elastic"`, `"rigid"`, `"unstable"` or `"overdamped"`.
    pub kind: String,
    /// Natural frequency \[Hz\] (0 for a rigid mode).
    pub frequency: f64,
    /// Damping ratio ζ [-].
    pub damping_ratio: f64,
    /// One increment per body of [`Scene::bodies`], in order; zero for a fixed body.
    pub bodies: Vec<BodyIncrement>,
}

impl ModeShape {
    /// The list entry: `2 · 3.142 Hz · ζ 0.0500`, `1 · rigid`.
    pub fn label(&self) -> String {
        match self.kind.as_str() {
            "rigid" => format!("{} · rigid", self.number),
            "elastic" => format!(
                "{} · {} Hz · ζ {:.4}",
                self.number,
                significant(self.frequency),
                self.damping_ratio
            ),
            other => format!(
                "{} · {other} · {} Hz",
                self.number,
                significant(self.frequency)
            ),
        }
    }
}

/// x with 4 significant digits, plainly when it reads well.
fn significant(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        let digits = (3 - x.abs().log10().floor().max(-3.0) as i32).clamp(0, 6) as usize;
        format!("{x:.digits$}")
    }
}

/// The pose of a body at s = g a sin(2πτ) of a mode (module docs): r₀ + s δr and the unit
/// Euler parameters along p₀ + s δp.
pub fn mode_pose(
    r0: &[f64; 3],
    p0: &[f64; 4],
    inc: &BodyIncrement,
    s: f64,
) -> ([f64; 3], [f64; 4]) {
    let r = [0, 1, 2].map(|c| r0[c] + s * inc.dr[c]);
    let p = [0, 1, 2, 3].map(|c| p0[c] + s * inc.dp[c]);
    let n = p.iter().map(|x| x * x).sum::<f64>().sqrt();
    (r, p.map(|x| x / n))
}

/// δθ = 2 G(p₀) δp (global components), the vector part of 2 δp ⊗ p̄₀ for a unit p₀.
pub fn small_rotation(p0: &[f64; 4], dp: &[f64; 4]) -> [f64; 3] {
    let n2: f64 = p0.iter().map(|x| x * x).sum();
    let [e0, e1, e2, e3] = p0.map(|x| x / n2.sqrt());
    let [d0, d1, d2, d3] = *dp;
    // vec(δp ⊗ p̄₀) = −δe0 e + e0 δe − δe × e.
    [
        2.0 * (-d0 * e1 + e0 * d1 - (d2 * e3 - d3 * e2)),
        2.0 * (-d0 * e2 + e0 * d2 - (d3 * e1 - d1 * e3)),
        2.0 * (-d0 * e3 + e0 * d3 - (d1 * e2 - d2 * e1)),
    ]
}

/// The default amplitude a of `mode` in `scene`: [`MODE_FRACTION`] of the model's size over
/// the largest displacement per unit amplitude of a moving body's origin or named point,
/// |δr + δθ × A(p₀) s'| at the scene's first pose. 1 if nothing moves.
pub fn amplitude(scene: &Scene, mode: &ModeShape) -> f64 {
    let mut largest: f64 = 0.0;
    for (b, inc) in scene.bodies.iter().zip(&mode.bodies) {
        let (Some(_), Some(p0)) = (b.positions.first(), b.rotations.first()) else {
            continue;
        };
        let dtheta = small_rotation(p0, &inc.dp);
        let moved = |s: [f64; 3]| {
            let arm = rotate(p0, s, &[0.0; 3]);
            let cross = [
                dtheta[1] * arm[2] - dtheta[2] * arm[1],
                dtheta[2] * arm[0] - dtheta[0] * arm[2],
                dtheta[0] * arm[1] - dtheta[1] * arm[0],
            ];
            (0..3)
                .map(|c| (inc.dr[c] + cross[c]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        largest = largest.max(moved([0.0; 3]));
        for p in &b.points {
            largest = largest.max(moved(p.local));
        }
    }
    if largest.is_finite() && largest > 0.0 {
        MODE_FRACTION * scene.extent / largest
    } else {
        1.0
    }
}

/// Checks the modes against `scene`: one increment per body, finite numbers, a rest pose
/// (one output time) for every moving body.
///
/// # Errors
/// [`Error::Scene`] naming the mode and the body.
pub fn validate_modes(scene: &Scene, modes: &[ModeShape]) -> Result<(), Error> {
    for m in modes {
        if m.bodies.len() != scene.bodies.len() {
            return Err(Error::Scene(format!(
                "mode {}: {} body increments for {} bodies",
                m.number,
                m.bodies.len(),
                scene.bodies.len()
            )));
        }
        let finite = m.frequency.is_finite() && m.damping_ratio.is_finite();
        for (b, inc) in scene.bodies.iter().zip(&m.bodies) {
            if !finite || inc.dr.iter().chain(&inc.dp).any(|x| !x.is_finite()) {
                return Err(Error::Scene(format!(
                    "mode {}: body \"{}\": its shape is not finite",
                    m.number, b.name
                )));
            }
        }
    }
    Ok(())
}

/// The modes' part of the page's data: the rest pose of each body (`null` for a fixed one),
/// and per animated mode its label, kind, frequency, damping ratio, amplitude and the shape
/// as [δr, δp] per body (`null` for a fixed body), in single precision.
pub(crate) fn modes_json(scene: &Scene, modes: &[ModeShape]) -> serde_json::Value {
    let rest: Vec<serde_json::Value> = scene
        .bodies
        .iter()
        .map(|b| match (b.positions.first(), b.rotations.first()) {
            (Some(r), Some(p)) => serde_json::json!([r, p]),
            _ => serde_json::Value::Null,
        })
        .collect();
    let list: Vec<serde_json::Value> = modes
        .iter()
        .take(MAX_ANIMATED_MODES)
        .map(|m| {
            let shape: Vec<serde_json::Value> = scene
                .bodies
                .iter()
                .zip(&m.bodies)
                .map(|(b, inc)| {
                    if b.moves() {
                        let v: Vec<f32> = inc.dr.iter().chain(&inc.dp).map(|x| *x as f32).collect();
                        serde_json::json!(v)
                    } else {
                        serde_json::Value::Null
                    }
                })
                .collect();
            serde_json::json!({
                "number": m.number,
                "label": m.label(),
                "kind": m.kind,
                "frequency": m.frequency,
                "damping_ratio": m.damping_ratio,
                "amplitude": amplitude(scene, m),
                "shape": shape,
            })
        })
        .collect();
    serde_json::json!({
        "fraction": MODE_FRACTION,
        "computed": modes.len(),
        "rest": rest,
        "list": list,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_rotation_inverts_the_euler_parameter_increment() {
        // δp = ½ Gᵀ(p₀) δθ for a p₀ a third of a turn about (1, 1, 1)/√3, then back.
        let h = 0.5;
        let p0 = [h, h, h, h];
        let dtheta = [0.3, -0.2, 0.7];
        // ½ Gᵀ δθ with G = [−e, ẽ + e0 I] (Nikravesh: ω = 2 G ṗ).
        let [e0, e1, e2, e3] = p0;
        let g = [[-e1, e0, -e3, e2], [-e2, e3, e0, -e1], [-e3, -e2, e1, e0]];
        let dp = [0, 1, 2, 3].map(|c| 0.5 * (0..3).map(|r| g[r][c] * dtheta[r]).sum::<f64>());
        let back = small_rotation(&p0, &dp);
        for c in 0..3 {
            assert!((back[c] - dtheta[c]).abs() < 1e-15, "{back:?}");
        }
    }

    #[test]
    fn a_quarter_period_is_the_rest_pose_plus_the_shape() {
        let r0 = [1.0, 2.0, 3.0];
        let p0 = [1.0, 0.0, 0.0, 0.0];
        let inc = BodyIncrement {
            dr: [0.1, 0.0, -0.2],
            dp: [0.0, 0.0, 0.0, 0.5],
        };
        let a = 0.2;
        let s = a * (2.0 * std::f64::consts::PI * 0.25).sin();
        let (r, p) = mode_pose(&r0, &p0, &inc, s);
        assert_eq!(r, [1.02, 2.0, 2.96]);
        let n = (1.0f64 + 0.01).sqrt();
        let want = [1.0 / n, 0.0, 0.0, 0.1 / n];
        for c in 0..4 {
            assert!((p[c] - want[c]).abs() < 1e-15);
        }
        assert!((p.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn labels_say_rigid_and_the_frequency() {
        let m = |kind: &str, f: f64| ModeShape {
            number: 2,
            kind: kind.into(),
            frequency: f,
            damping_ratio: 0.05,
            bodies: vec![],
        };
        assert_eq!(m("rigid", 0.0).label(), "2 · rigid");
        assert_eq!(m("elastic", 3.45678).label(), "2 · 3.457 Hz · ζ 0.0500");
        assert_eq!(m("elastic", 0.0192).label(), "2 · 0.01920 Hz · ζ 0.0500");
        assert_eq!(m("elastic", 1234.4).label(), "2 · 1234 Hz · ζ 0.0500");
        assert_eq!(m("unstable", 0.5).label(), "2 · unstable · 0.5000 Hz");
    }
}
