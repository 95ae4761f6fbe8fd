//! The preallocated buffers of a DOPRI5 step: the values of y = [q; v] and of the work W at the
//! step's ends and at a stage or output time ([`Values`]), and the stage derivatives with the
//! stage powers ([`Stages`]).

use crate::state::State;

/// y and the work W ([`crate::work`]) at the step's start (0), its end (1), and a stage or
/// output time (t), with the [`State`] they are read into.
#[derive(Debug)]
pub(super) struct Values {
    pub y0: Vec<f64>,
    pub y1: Vec<f64>,
    /// A stage value Y_j, the error estimate, or an output value.
    pub yt: Vec<f64>,
    pub w0: Vec<f64>,
    pub w1: Vec<f64>,
    pub wt: Vec<f64>,
    /// y read as a state (p normalized), for the evaluations and the outputs.
    pub scratch: State,
}

impl Values {
    /// Zeros for states shaped like `state` and `channels` work channels.
    pub fn new(state: &State, channels: usize) -> Self {
        let len = state.q.len() + state.v.len();
        Self {
            y0: vec![0.0; len],
            y1: vec![0.0; len],
            yt: vec![0.0; len],
            w0: vec![0.0; channels],
            w1: vec![0.0; channels],
            wt: vec![0.0; channels],
            scratch: state.clone(),
        }
    }
}

/// The stage derivatives k_j = f(t + c_j h, Y_j) and the power of each work channel at each
/// stage, j = 1..7 (indices 0..6).
#[derive(Debug)]
pub(super) struct Stages {
    pub k: [Vec<f64>; 7],
    pub kw: [Vec<f64>; 7],
}

impl Stages {
    /// Zeros for states of `len` numbers and `channels` work channels.
    pub fn new(len: usize, channels: usize) -> Self {
        Self {
            k: std::array::from_fn(|_| vec![0.0; len]),
            kw: std::array::from_fn(|_| vec![0.0; channels]),
        }
    }
}
