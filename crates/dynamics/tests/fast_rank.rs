//! Large models skip the dense rank analysis of Φ_v when the KKT matrix factors (no redundant
//! equations): a chain of spherical joints above the threshold simulates like a small one.

use cardan_dynamics::{
    Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix, SimulationOptions, State,
};
mod common;
use cardan_mechanism::FAST_RANK_MIN_UNKNOWNS;
use common::spherical_chain;
use nalgebra::Vector3;

#[test]
fn large_chain_prepares_without_rank_analysis_and_conserves_energy() {
    let n = FAST_RANK_MIN_UNKNOWNS / 6 + 5;
    let model = spherical_chain(n);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -9.81)))
        .unwrap();
    let s = State::initial(&model, 0.0);
    d.prepare(&s).unwrap();
    assert!(d.redundant_equations().is_empty());
    for matrix in [IterationMatrix::MassOnly, IterationMatrix::Tangent] {
        let opts = SimulationOptions::new(0.02, 4).integrator(Integrator::GeneralizedAlpha(
            GeneralizedAlphaOptions {
                iteration_matrix: matrix,
                rho_inf: 1.0,
                ..GeneralizedAlphaOptions::with_step(1e-3)
            },
        ));
        let r = d.simulate_consistent(s.clone(), &opts).unwrap();
        assert!(r.position_drift.iter().all(|v| *v < 1e-8), "{matrix:?}");
        // The chain falls: the first link's far end moved down.
        let tip = r.point("b0", "b").unwrap();
        assert!(tip.position[4].z < -1e-4, "{matrix:?}");
        assert!(
            r.energy.max_drift() < 1e-3,
            "{matrix:?}: {}",
            r.energy.max_drift()
        );
    }
}
