//! `kind = "dynamic"` with `linearize_at = t`: the linearization about the state of the dynamic
//! run at t ([`cardan_dynamics::Dynamics::linearize_moving`]), its modes (`modes.csv`,
//! `mode_shapes.csv`) and matrices (`lin_*.mtx`, `ss_*.mtx`, `state_space.txt`) written with
//! the run's outputs.
//!
//! The state at t comes from integrating from t_start to t with the run's integrator and its
//! settings (a run of its own, one output at t), so t need not be an output time.

use super::located::located;
use super::matrices::matrix_files;
use super::modes::mode_tables;
use super::setup::{dynamics, initial_state};
use crate::build::Outputs as Requested;
use crate::diag::Error;
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::{SimulationOptions, State};
use cardan_mechanism::Outputs;

/// Output tables and named files (name, text).
type Written = (Vec<Table>, Vec<(String, String)>);

/// The tables and files of the linearization about the state at `t` of the run with options
/// `opts`: the modes and the matrices.
///
/// # Errors
/// The run to t or the linearization failed (located as the dynamic run's errors).
pub(super) fn about_dynamic(
    p: &Prepared,
    opts: &SimulationOptions,
    t: f64,
    req: &Requested,
    inputs: &[String],
) -> Result<Written, Error> {
    let mut d = dynamics(p)?;
    let initial = initial_state(p);
    let state = if t > initial.t {
        let mut o = SimulationOptions::new(t, 1).integrator(opts.integrator);
        o.max_steps = opts.max_steps;
        o.outputs = Outputs {
            velocity: true,
            acceleration: false,
            points: false,
            joints: false,
        };
        let r = d.simulate(&initial, &o).map_err(|e| located(p, &e))?;
        let k = &r.kinematics;
        let last = k.len() - 1;
        let mut s = State::initial(&p.model, t);
        for (i, b) in k.bodies.iter().enumerate() {
            s.set_pose(i, b.r[last], b.p[last]);
            s.set_velocity(i, b.r_dot[last], b.omega_local[last]);
        }
        s
    } else {
        d.consistent_state(&initial).map_err(|e| located(p, &e))?
    };
    let lin = d.linearize_moving(&state).map_err(|e| located(p, &e))?;
    let modes = d.modes(&state, &lin).map_err(|e| located(p, &e))?;
    let bodies: Vec<&str> = p.model.bodies().iter().map(|b| b.name.as_str()).collect();
    let rest: Vec<_> = (0..bodies.len()).map(|k| state.p(k)).collect();
    let tables = mode_tables(t, &bodies, &rest, &modes);
    let about = format!("the state of the dynamic run at t = {t} s");
    let files = matrix_files(p, &mut d, &state, &lin, req, inputs, &about, true)
        .map_err(|e| located(p, &e))?;
    Ok((tables, files))
}
