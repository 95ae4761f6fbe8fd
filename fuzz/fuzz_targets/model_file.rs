//! Arbitrary bytes → the CLI's parse + validate + build (+ assemble, DOF and a short
//! kinematic run when the file asks for one). Must never panic; results never NaN.
#![no_main]

use cardan_model::{build::load, diag::Source, file::parse};
use cardan_mechanism::{AssemblyOptions, KinematicOptions, Outputs};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let src = Source::from_text("fuzz.toml", text);
    let Ok(file) = parse(&src) else { return };
    let Ok(loaded) = load(&src, &file) else {
        return;
    };
    let Ok(model) = loaded.builder.build() else {
        return;
    };
    let t0 = loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let mut ws = model.workspace();
    let opts = AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(t0)
    };
    if model.assemble(&mut ws, &opts).is_err() {
        return;
    }
    for &x in ws.state() {
        assert!(x.is_finite(), "assembled state not finite");
    }
    let _ = model.dof(&ws);
    if let Some(a) = &loaded.analysis {
        if a.dynamic.is_none() {
            let steps = a.steps.min(4);
            let o = KinematicOptions::new(a.t_start, a.t_end, steps).outputs(Outputs::default());
            let results = match model.run_kinematics(&o) {
                Ok(r) => r,
                Err(e) => match e.into_partial_results() {
                    Some(r) => r,
                    None => return,
                },
            };
            for b in &results.bodies {
                for k in 0..b.r.len() {
                    assert!(b.r[k].iter().all(|v| v.is_finite()), "r not finite");
                    assert!(b.p[k].iter().all(|v| v.is_finite()), "p not finite");
                }
            }
        }
    }
});
