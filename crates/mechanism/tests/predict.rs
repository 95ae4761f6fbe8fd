//! `Model::predict_poses`: the time grid's Taylor predictor for callers that step frames
//! themselves. Same converged poses, fewer Newton iterations.

mod common;

use cardan_mechanism::AssemblyOptions;

#[test]
fn predicted_frames_converge_to_the_same_poses_in_fewer_iterations() {
    let model = common::slider_crank();
    let run = |predict: bool| {
        let mut ws = model.workspace();
        model
            .assemble(&mut ws, &AssemblyOptions::default())
            .unwrap();
        model.prepare_kinematics(&mut ws).unwrap();
        let mut iterations = 0;
        let dt = 0.01;
        for k in 1..=100 {
            let t = k as f64 * dt;
            if predict {
                let dt = t - ws.time();
                model.predict_poses(&mut ws, dt);
            }
            iterations += model.position(&mut ws, t).unwrap().iterations;
            model.velocity(&mut ws).unwrap();
            model.acceleration(&mut ws).unwrap();
        }
        (iterations, ws.state().to_vec())
    };
    let (plain, x_plain) = run(false);
    let (predicted, x_predicted) = run(true);
    assert!(predicted < plain, "{predicted} vs {plain} iterations");
    for (a, b) in x_plain.iter().zip(&x_predicted) {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
    // Without valid velocities the predictor does nothing.
    let mut ws = model.workspace();
    let before = ws.state().to_vec();
    model.predict_poses(&mut ws, 0.1);
    assert_eq!(ws.state(), &before[..]);
}
