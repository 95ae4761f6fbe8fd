//! The constraint elements of a model (joints, drivers, couplers, curve elements) as the KKT
//! system meets them: each with its rows and its two bodies, evaluated row block by row block.
//!
//! An element's Φ_v is two blocks, rows × 6 for body i and body j (v = [ṙ; ω'] per body);
//! its right-hand sides are Φ (positions), ν (velocities, Φ_v v = ν) and γ#_v
//! (accelerations, Φ_v v̇ = γ#). A coupler's angle is continued over turns from the reference
//! of the run (`turns`), which only Φ depends on. A curve element's rows are its reduced rows,
//! its parameters eliminated at the synced bodies ([`super::curves`]).

use super::curves::{st, CurveTrack};
use cardan_constraints::{BodyPair, BodyState, Constraint};
use cardan_mechanism::{BodyId, Model};
use std::ops::Range;

/// One joint, driver, coupler or curve element: its rows, bodies.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub rows: Range<usize>,
    pub bi: BodyId,
    pub bj: BodyId,
    /// Joint index, or `joints.len() + driver index`, or
    /// `joints.len() + drivers.len() + coupler index`, or that + `couplers.len()` + curve
    /// element index.
    pub index: usize,
    /// The last rows, zero and never active: a curve element's eliminated parameters.
    pub eliminated: usize,
}

impl Element {
    /// The rows that carry equations (all but the eliminated ones).
    pub fn live_rows(&self) -> Range<usize> {
        self.rows.start..self.rows.end - self.eliminated
    }
}

/// The constraint of element `e` (a coupler with the model's references: right for Φ_v, ν and
/// γ#, which do not depend on them; Φ takes the references of the run, see [`eval_rows`]).
enum Of<'a> {
    Joint(&'a cardan_constraints::Joint),
    Driver(&'a cardan_constraints::Driver),
    Coupler(&'a cardan_constraints::Coupler, usize),
    Curve(&'a cardan_mechanism::CurveElement, usize),
}

fn of<'a>(model: &'a Model, e: &Element) -> Of<'a> {
    let (nj, nd, nc) = (
        model.joints().len(),
        model.drivers().len(),
        model.couplers().len(),
    );
    if e.index < nj {
        Of::Joint(&model.joints()[e.index].joint)
    } else if e.index < nj + nd {
        Of::Driver(&model.drivers()[e.index - nj].driver)
    } else if e.index < nj + nd + nc {
        let k = e.index - nj - nd;
        Of::Coupler(&model.couplers()[k].coupler, k)
    } else {
        let k = e.index - nj - nd - nc;
        Of::Curve(&model.curves()[k].element, k)
    }
}

macro_rules! with_constraint {
    ($of:expr, $c:ident => $e:expr) => {
        match $of {
            Of::Joint($c) => $e,
            Of::Driver($c) => $e,
            Of::Coupler($c, _) => $e,
            Of::Curve($c, _) => $e,
        }
    };
}

/// The model's elements: joints, then drivers, then couplers, then curve elements.
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
            eliminated: 0,
        })
        .collect();
    v.extend(model.drivers().iter().enumerate().map(|(k, d)| Element {
        rows: d.rows.clone(),
        bi: d.body_i,
        bj: d.body_j,
        index: nj + k,
        eliminated: 0,
    }));
    let nd = model.drivers().len();
    v.extend(model.couplers().iter().enumerate().map(|(k, c)| Element {
        rows: c.rows.clone(),
        bi: c.body_i,
        bj: c.body_j,
        index: nj + nd + k,
        eliminated: 0,
    }));
    let nc = model.couplers().len();
    v.extend(model.curves().iter().enumerate().map(|(k, c)| Element {
        rows: c.rows.clone(),
        bi: c.body_i,
        bj: c.body_j,
        index: nj + nd + nc + k,
        eliminated: c.element.extra(),
    }));
    v
}

/// Evaluates one element's Φ_v blocks (rows × 6 for body i and j; a curve element's reduced
/// rows at the synced bodies, from `curves`).
pub(crate) fn element_blocks(
    model: &Model,
    e: &Element,
    bodies: &[BodyState],
    curves: &CurveTrack,
    t: f64,
    bi: &mut [[f64; 6]; 6],
    bj: &mut [[f64; 6]; 6],
) {
    let g = BodyState::ground();
    let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
    let n = e.rows.len();
    match of(model, e) {
        Of::Curve(_, k) => {
            let tr = &curves.elements[k];
            bi[..n].copy_from_slice(&tr.bi[..n]);
            bj[..n].copy_from_slice(&tr.bj[..n]);
        }
        other => with_constraint!(other, c => c.phi_v(&pair, t, &mut bi[..n], &mut bj[..n])),
    }
}

/// Which vector of an element to evaluate.
#[derive(Clone, Copy)]
pub(crate) enum Rhs {
    Phi,
    Nu,
    Gamma,
}

/// Φ, ν or γ#_v of all model rows; the couplers' angles continued from `turns` (one entry per
/// coupler, see [`cardan_mechanism::Model::accept_turns`]); the curve elements' reduced rows
/// at their parameters in `curves`. No allocation.
#[allow(clippy::too_many_arguments)]
pub(crate) fn eval_rows(
    model: &Model,
    elements: &[Element],
    bodies: &[BodyState],
    turns: &[[f64; 2]],
    curves: &CurveTrack,
    t: f64,
    what: Rhs,
    out: &mut [f64],
) {
    let g = BodyState::ground();
    for e in elements {
        let (si, sj) = (st(bodies, &g, e.bi), st(bodies, &g, e.bj));
        let pair = BodyPair::new(si, sj);
        let o = &mut out[e.rows.clone()];
        match of(model, e) {
            Of::Coupler(c, k) => rows(&c.with_reference(turns[k]), &pair, t, what, o),
            Of::Curve(c, k) => {
                let tr = &curves.elements[k];
                let (r, n) = (c.rows(), c.extra());
                let pair = BodyPair::with_extra(si, sj, &tr.u[..n], &tr.u_dot[..n]);
                let mut full = [0.0; super::curves::MAX_ROWS];
                rows(c, &pair, t, what, &mut full[..r]);
                tr.reduce(&full, r, n, o);
            }
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
