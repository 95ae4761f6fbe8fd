//! Criterion benchmark of kinematic frames (position Newton + velocity + acceleration): the
//! spatial slider-crank example and driven revolute chains of 10, 100 and 1,000 bodies.
//! `cargo bench -p cardan-bench --bench frame` (`-- --quick` for a fast pass).

use cardan_bench::models;
use cardan_mechanism::{AssemblyOptions, Model};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::PathBuf;

fn frames(c: &mut Criterion, label: &str, model: &Model, dt: f64) {
    let mut ws = model.workspace();
    model
        .assemble(&mut ws, &AssemblyOptions::at(0.0))
        .expect("assemble");
    model.prepare_kinematics(&mut ws).expect("prepare");
    let mut t = 0.0;
    let mut dir = 1.0;
    c.bench_function(label, |b| {
        b.iter(|| {
            if !(0.0..=1.0).contains(&t) {
                dir = -dir;
            }
            t += dir * dt;
            model.position(&mut ws, t).expect("position");
            model.velocity(&mut ws).expect("velocity");
            model.acceleration(&mut ws).expect("acceleration");
        })
    });
}

fn bench(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/slider_crank.toml");
    let p = cardan_model::prepare::prepare(&path).expect("slider_crank.toml");
    frames(c, "frame/slider_crank", &p.model, 0.01);
    for n in [10, 100, 1000] {
        let m = models::revolute_chain(n);
        frames(c, &format!("frame/revolute_chain/{n}"), &m, 0.02);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
