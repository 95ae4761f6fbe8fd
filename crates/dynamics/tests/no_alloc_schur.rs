//! "No allocation per step" on the Schur-complement path of the equations of motion: a chain of
//! 40 spherical-joint links (n + m_a = 360, so the KKT system is solved through S = Φ_v M⁻¹ Φ_vᵀ
//! and a sparse Cholesky). Two runs with the same outputs and 10× more steps allocate exactly
//! as often, and one solve of the equations of motion after setup allocates nothing.
//!
//! One test function only: the counter is global, and parallel tests would pollute it.

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix,
    SimulationOptions,
};
use common::spherical_chain;
use nalgebra::Vector3;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

fn allocations(f: impl FnOnce()) -> usize {
    let region = Region::new(GLOBAL);
    f();
    let stats = region.change();
    stats.allocations + stats.reallocations
}

#[test]
fn schur_steps_do_not_allocate() {
    let model = spherical_chain(40);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 2.0, -9.81)))
        .unwrap();
    let s0 = d.consistent_state(&d.initial_guess()).unwrap();

    let mut vdot = vec![0.0; model.num_unknowns()];
    let mut lambda = vec![0.0; model.num_equations()];
    d.accelerations(&s0, &mut vdot, &mut lambda).unwrap();
    let n = allocations(|| {
        for _ in 0..50 {
            d.accelerations(&s0, &mut vdot, &mut lambda).unwrap();
        }
    });
    assert_eq!(
        n, 0,
        "{n} allocations in 50 solves of the equations of motion"
    );

    for (label, coarse, fine) in [
        (
            "generalized-α, mass-only",
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                iteration_matrix: IterationMatrix::MassOnly,
                ..GeneralizedAlphaOptions::with_step(2e-3)
            }),
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                iteration_matrix: IterationMatrix::MassOnly,
                ..GeneralizedAlphaOptions::with_step(2e-4)
            }),
        ),
        (
            "DOPRI5 fixed step",
            Integrator::Dopri5(Dopri5Options::fixed(2e-3)),
            Integrator::Dopri5(Dopri5Options::fixed(2e-4)),
        ),
    ] {
        let mut steps = [0, 0];
        let mut counts = [0, 0];
        for (k, integ) in [coarse, fine].into_iter().enumerate() {
            let opts = SimulationOptions::new(0.1, 5).integrator(integ);
            let s = s0.clone();
            counts[k] = allocations(|| {
                let r = d.simulate_consistent(s, &opts).unwrap();
                steps[k] = r.stats.steps;
            });
        }
        eprintln!(
            "{label}: {} allocations for {} steps, {} for {} steps",
            counts[0], steps[0], counts[1], steps[1]
        );
        assert!(steps[1] >= 9 * steps[0]);
        assert_eq!(
            counts[0], counts[1],
            "{label}: allocations grow with the step count"
        );
    }
}
