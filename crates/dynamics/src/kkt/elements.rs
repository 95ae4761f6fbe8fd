//! The constraint elements of a model (joints, drivers, couplers) as the KKT system meets
//! them: each with its rows and its two bodies, evaluated row block by row block.
//!
//! An element's Φ_v is two blocks, rows × 6 for body i and body j (v = [ṙ; ω'] per body);
//! its right-hand sides are Φ (positions), ν (velocities, Φ_v v = ν) and γ#_v
//! (accelerations, Φ_v v̇ = γ#). A coupler's angle is continued over turns from the reference
//! of the run (`turns`), which only Φ depends on.

use cardan_constraints::{BodyPair, BodyState, Constraint};
use cardan_mechanism::{BodyId, Model};
use std::ops::Range;

/// One joint, driver or coupler: its rows, bodies.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub rows: Range<usize>,
    pub bi: BodyId,
    pub bj: BodyId,
    /// Joint index, or `joints.len() + driver index`, or
    /// `joints.len() + drivers.len() + coupler index`.
    pub index: usize,
}

/// The constraint of element `e` (a coupler with the model's references: right for Φ_v, ν and
/// γ#, which do not depend on them; Φ takes the references of the run, see [`eval_rows`]).
enum Of<'a> {
    Joint(&'a cardan_constraints::Joint),
    Driver(&'a cardan_constraints::Driver),
    Coupler(&'a cardan_constraints::Coupler, usize),
}

fn of<'a>(model: &'a Model, e: &Element) -> Of<'a> {
    let (nj, nd) = (model.joints().len(), model.drivers().len());
    if e.index < nj {
        Of::Joint(&model.joints()[e.index].joint)
    } else if e.index < nj + nd {
        Of::Driver(&model.drivers()[e.index - nj].driver)
    } else {
        let k = e.index - nj - nd;
        Of::Coupler(&model.couplers()[k].coupler, k)
    }
}

macro_rules! with_constraint {
    ($of:expr, $c:ident => $e:expr) => {
        match $of {
            Of::Joint($c) => $e,
            Of::Driver($c) => $e,
            Of::Coupler($c, _) => $e,
        }
    };
}

/// The model's elements: joints, then drivers, then couplers (the order of their rows).
pub(crate) fn elements(model: &Model) -> Vec<Element> {
    let nj = model.joints().len();
    let mut v: Vec<Element> = model
        .joints()
        .iter()
        .enumerate()
        .map(|(k, j)| Element {
            rows: j.rows.clone(),
            bi: j.body_i,
            bj: j.body_j,
            index: k,
        })
        .collect();
    v.extend(model.drivers().iter().enumerate().map(|(k, d)| Element {
        rows: d.rows.clone(),
        bi: d.body_i,
        bj: d.body_j,
        index: nj + k,
    }));
    let nd = model.drivers().len();
    v.extend(model.couplers().iter().enumerate().map(|(k, c)| Element {
        rows: c.rows.clone(),
        bi: c.body_i,
        bj: c.body_j,
        index: nj + nd + k,
    }));
    v
}

fn st<'a>(bodies: &'a [BodyState], g: &'a BodyState, id: BodyId) -> &'a BodyState {
    match id {
        BodyId::Ground => g,
        BodyId::Moving(k) => &bodies[k],
    }
}

/// Evaluates one element's Φ_v blocks (rows × 6 for body i and j).
pub(crate) fn element_blocks(
    model: &Model,
    e: &Element,
    bodies: &[BodyState],
    t: f64,
    bi: &mut [[f64; 6]; 6],
    bj: &mut [[f64; 6]; 6],
) {
    let g = BodyState::ground();
    let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
    let n = e.rows.len();
    with_constraint!(of(model, e), c => c.phi_v(&pair, t, &mut bi[..n], &mut bj[..n]));
}

/// Which vector of an element to evaluate.
#[derive(Clone, Copy)]
pub(crate) enum Rhs {
    Phi,
    Nu,
    Gamma,
}

/// Φ, ν or γ#_v of all model rows; the couplers' angles continued from `turns` (one entry per
/// coupler, see [`cardan_mechanism::Model::accept_turns`]). No allocation.
pub(crate) fn eval_rows(
    model: &Model,
    elements: &[Element],
    bodies: &[BodyState],
    turns: &[[f64; 2]],
    t: f64,
    what: Rhs,
    out: &mut [f64],
) {
    let g = BodyState::ground();
    for e in elements {
        let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
        let o = &mut out[e.rows.clone()];
        match of(model, e) {
            Of::Coupler(c, k) => rows(&c.with_reference(turns[k]), &pair, t, what, o),
            other => with_constraint!(other, c => rows(c, &pair, t, what, o)),
        }
    }
}

/// Φ, ν or γ#_v of one constraint.
fn rows<C: Constraint>(c: &C, pair: &BodyPair, t: f64, what: Rhs, o: &mut [f64]) {
    match what {
        Rhs::Phi => c.phi(pair, t, o),
        Rhs::Nu => c.nu(pair, t, o),
        Rhs::Gamma => c.gamma_sharp_v(pair, t, o),
    }
}
