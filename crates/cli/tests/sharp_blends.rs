//! Issue 53, item 3: piecewise-linear motions whose pieces are blended by arctan steps much
//! narrower than the output step, with the knots on output times (FreeCAD robot assemblies
//! drive their arms and grippers so: `arctan(1000*(time - T))`). At a knot the blend makes the
//! acceleration about 1/(π w) times the change of slope (w the blend's width), so a predictor
//! that extrapolates with it misses the next output time by radians. The runs below must follow
//! every motion to its end, the driven coordinates equal to the formula and a closed loop on its
//! closed form, whatever the predictor does at the knots.

mod common;
use cardan_mechanism::KinematicOptions;
use cardan_model::diag::Source;
use cardan_model::prepare::prepare_source;
use common::rssr_q;
use std::path::PathBuf;

/// Knots at t = 1, 2, …, `knots` (output times of a 0.1 s grid).
const KNOTS: usize = 19;

/// A piecewise-linear motion: slope `slopes[0]` until t = 1, then `slopes[k]` from t = k, each
/// change blended over about 1/`sharpness` seconds: f(t) = s₀ t + Σ (s_k − s_{k−1}) (t − k)
/// (½ + atan(B (t − k))/π).
struct Blended {
    slopes: Vec<f64>,
    sharpness: f64,
}

impl Blended {
    /// Slopes from a small linear congruential generator in [−`scale`, `scale`].
    fn new(seed: u64, scale: f64, sharpness: f64) -> Self {
        let mut s = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let slopes = (0..=KNOTS)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                scale * (2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0)
            })
            .collect();
        Self { slopes, sharpness }
    }

    /// The expression of the model file (cardan's grammar, `t` the time).
    fn text(&self) -> String {
        let mut text = format!("{:.6}*t", self.slopes[0]);
        for k in 1..=KNOTS {
            let d = self.slopes[k] - self.slopes[k - 1];
            text += &format!(
                " + ({d:.6})*(t-{k})*(0.5+atan({}*(t-{k}))/pi)",
                self.sharpness
            );
        }
        text
    }

    /// f(t) and f'(t), with the slopes rounded as in [`text`](Self::text).
    fn eval(&self, t: f64) -> (f64, f64) {
        let round = |x: f64| format!("{x:.6}").parse::<f64>().unwrap();
        let (mut f, mut fd) = (round(self.slopes[0]) * t, round(self.slopes[0]));
        let pi = std::f64::consts::PI;
        for k in 1..=KNOTS {
            let d = round(self.slopes[k] - self.slopes[k - 1]);
            let u = t - k as f64;
            let b = self.sharpness;
            let step = 0.5 + (b * u).atan() / pi;
            f += d * u * step;
            fd += d * (step + u * b / (pi * (1.0 + (b * u).powi(2))));
        }
        (f, fd)
    }
}

fn run(text: &str, name: &str) -> cardan_mechanism::Results {
    let source = Source::from_text(PathBuf::from(format!("{name}.toml")), text.to_string());
    let p = prepare_source(source).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut options = KinematicOptions::new(0.0, 20.0, 200);
    options.outputs = cardan_mechanism::Outputs::with_velocity();
    p.model
        .run_kinematics(&options)
        .unwrap_or_else(|e| panic!("{name}: {}", cardan_model::prepare::analysis_error(&p, &e)))
}

/// An open chain driven by four such motions at once (yaw, shoulder, elbow, a gripper slide):
/// every driven coordinate and its rate equal to the formula at every output time.
fn arm(sharpness: f64) {
    let motions = [
        ("yaw", Blended::new(1, 1.0, sharpness)),
        ("shoulder", Blended::new(2, 0.3, sharpness)),
        ("elbow", Blended::new(3, 0.5, sharpness)),
        ("grip", Blended::new(4, 0.02, sharpness)),
    ];
    let mut text = include_str!("data/blend_arm.toml").to_string();
    for (joint, m) in &motions {
        text = text.replace(&format!("<{joint}>"), &m.text());
    }
    let r = run(&text, "blend_arm");
    assert_eq!(r.times.len(), 201);
    for (joint, m) in &motions {
        let j = r.joint(joint).unwrap();
        for (k, &t) in r.times.iter().enumerate() {
            let (f, fd) = m.eval(t);
            assert!(
                (j.values[k][0] - f).abs() < 1e-9 && (j.rates[k][0] - fd).abs() < 1e-7,
                "B = {sharpness}, {joint} at t = {t}: {} / {} against {f} / {fd}",
                j.values[k][0],
                j.rates[k][0]
            );
        }
    }
}

#[test]
fn an_arm_with_four_blended_motions_follows_them_to_the_end() {
    // Blends of 1/100 and 1/1000 of the 0.1 s output step.
    arm(1e3);
    arm(1e4);
}

#[test]
fn a_closed_loop_with_a_blended_crank_stays_on_its_closed_form() {
    for sharpness in [1e3, 1e4] {
        let m = Blended::new(7, 8.0, sharpness);
        let text = include_str!("../../../examples/rssr_fourbar.toml")
            .replace(
                "function = { kind = \"polynomial\", coefficients = [0.0, 6.283185307179586] }",
                &format!(
                    "function = {{ kind = \"expression\", text = \"{}\" }}",
                    m.text()
                ),
            )
            .replace("t_end = 1.0", "t_end = 20.0");
        assert!(text.contains("expression"));
        let r = run(&text, "rssr_blended");
        let q = r.point("rocker", "Q").unwrap();
        for (k, &t) in r.times.iter().enumerate() {
            let err = (q.position[k] - rssr_q(m.eval(t).0)).amax();
            assert!(err < 1e-9, "B = {sharpness}, t = {t}: |Q − Q(θ)| = {err} m");
        }
    }
}
