//! `FrictionState`: the buffers and per-element results of the joints' friction in a run
//! (a leaf; the equations are in the module above).

/// The friction state of a run: the generalized friction forces and each element's power
/// (buffers sized at setup; empty without friction).
#[derive(Debug, Clone, Default)]
pub(crate) struct FrictionState {
    /// h_f (n).
    pub hf: Vec<f64>,
    /// h_f of the previous iterate (n).
    pub hf_prev: Vec<f64>,
    /// The right-hand side without friction (KKT size).
    pub rhs0: Vec<f64>,
    /// Each element's friction force or torque along its axis (N or N m; a ball joint's
    /// magnitude), and its power (W, ≤ 0).
    pub value: Vec<f64>,
    pub power: Vec<f64>,
    /// The multipliers (over the kept rows) an implicit step's iterate gives the friction
    /// ([`crate::system::Dynamics::eval_implicit_forces`]).
    pub frozen: Vec<f64>,
    /// Each element's friction and power at the run's output times.
    pub history: FrictionHistory,
}

/// The joints' friction at each output time of a run
/// ([`crate::system::Dynamics::friction_history`]; empty without friction).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrictionHistory {
    /// Output times.
    pub times: Vec<f64>,
    /// Per time, per friction element ([`cardan_mechanism::Model::frictions`]): its force (N,
    /// along the slide: prismatic and cylindrical joints) or torque (N m, about the axis:
    /// revolute; a ball joint's magnitude), opposing the motion.
    pub value: Vec<Vec<f64>>,
    /// Per time, per element: the power it takes, W (≤ 0).
    pub power: Vec<Vec<f64>>,
}

impl FrictionState {
    pub fn new(model: &cardan_mechanism::Model) -> Self {
        let (nf, n) = (model.frictions().len(), 6 * model.num_bodies());
        if nf == 0 {
            return Self::default();
        }
        Self {
            hf: vec![0.0; n],
            hf_prev: vec![0.0; n],
            rhs0: Vec::new(),
            value: vec![0.0; nf],
            power: vec![0.0; nf],
            frozen: Vec::new(),
            history: FrictionHistory::default(),
        }
    }
}
