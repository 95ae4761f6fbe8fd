//! Force tangents of the implicit iteration matrix, C_t = −∂h/∂v and K_t = −∂h/∂q (q: r and
//! the rotation increment π'), by forward finite differences, block-sparse and coloured.
//!
//! The generalized forces h of body j depend only on body j's own coordinates (gravity, the
//! gyroscopic term −ω̃'J'ω', point forces) and on those of the bodies joined to it by force
//! elements (spring-dampers, actuators, rotational spring-dampers). So the tangents have
//! nonzero 6×6 blocks only on the diagonal and at the pairs coupled by force elements, the same
//! blocks the KKT layout reserves, and only those are computed and stored (O(n) memory).
//!
//! Coloured differences (Curtis, Powell & Reid 1974): bodies that share no force element and
//! no force-element partner (distance-2 colouring of the coupling graph) are perturbed
//! together, so one evaluation of h gives a column of every block of all of them. A chain of
//! spherical links under gravity has one colour: 12 evaluations of h per tangent instead of
//! 12 nb (the dense differences before: 0.95 s per step and 572 MB at 1,000 bodies).
//!
//! A user force callback may couple any bodies, so with one every body is its own colour
//! (still only the reserved blocks are read: couplings the layout has no block for are not
//! part of the iteration matrix).

use crate::state::State;
use crate::system::Dynamics;
use cardan_mechanism::apply_rotation_step;

/// Block-sparse force tangents at one state.
#[derive(Debug)]
pub(crate) struct Tangents {
    /// Bodies perturbed together, one list per colour.
    colours: Vec<Vec<usize>>,
    /// For each column body k: (row body j, block index) of the blocks ∂h_j/∂(coordinates of
    /// k), the diagonal one first.
    columns: Vec<Vec<(usize, usize)>>,
    /// For each row body j: (column body k, block index).
    rows: Vec<Vec<(usize, usize)>>,
    /// C_t and K_t blocks, row-major 6×6.
    ct: Vec<[f64; 36]>,
    kt: Vec<[f64; 36]>,
    /// h at the unperturbed state.
    h0: Vec<f64>,
    pert: State,
    dq: Vec<f64>,
    /// Perturbation of each body in the current pass.
    eps: Vec<f64>,
}

impl Tangents {
    /// The colouring and block layout for `d`'s force elements (and user callback), with
    /// buffers shaped like `state`.
    pub fn new(d: &Dynamics, state: &State) -> Self {
        let nb = state.v.len() / 6;
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nb];
        let mut columns: Vec<Vec<(usize, usize)>> = (0..nb).map(|k| vec![(k, k)]).collect();
        let mut rows: Vec<Vec<(usize, usize)>> = (0..nb).map(|k| vec![(k, k)]).collect();
        let mut nblocks = nb;
        for (i, j) in d.coupled_pairs() {
            if i == j || rows[i].iter().any(|&(c, _)| c == j) {
                continue;
            }
            for (r, c) in [(i, j), (j, i)] {
                columns[c].push((r, nblocks));
                rows[r].push((c, nblocks));
                nblocks += 1;
            }
        }
        // The colours from the differenced couplings alone: the contacts' blocks are added in
        // closed form ([`crate::collision::Collisions::tangents`]).
        for (i, j) in d.differenced_pairs() {
            if i != j && !adj[i].contains(&j) {
                adj[i].push(j);
                adj[j].push(i);
            }
        }
        let colours = if d.user.is_some() {
            (0..nb).map(|k| vec![k]).collect()
        } else {
            distance2_colouring(&adj)
        };
        Self {
            colours,
            columns,
            rows,
            ct: vec![[0.0; 36]; nblocks],
            kt: vec![[0.0; 36]; nblocks],
            h0: vec![0.0; state.v.len()],
            pert: state.clone(),
            dq: vec![0.0; state.v.len()],
            eps: vec![0.0; nb],
        }
    }

    /// Evaluates C_t and K_t at `at`. Perturbations: 1e-7 (1 + |v_c|) for a velocity,
    /// 1e-7 L (L the model's characteristic length) for a translation, 1e-7 rad for a
    /// rotation. `contacts_at`: the forces were last evaluated at `at` (the Newton iterate),
    /// so the contacts found there serve their closed-form blocks as they are (finding them
    /// again was a third of a pile's tangent). No allocation.
    pub fn eval(&mut self, d: &mut Dynamics, at: &State, contacts_at: bool) {
        let l = d.model.characteristic_length();
        d.sync(at);
        let contacts = d.collisions.is_some();
        if contacts {
            // The contacts at `at`, for their closed-form blocks; then differences without them.
            if !contacts_at {
                d.eval_implicit_forces(at.t);
            }
            d.contacts_off = true;
        }
        d.eval_implicit_forces(at.t);
        self.h0.copy_from_slice(&d.h);
        self.pert.t = at.t;
        for colour in &self.colours {
            for loc in 0..6 {
                for velocity in [true, false] {
                    // Columns 6k + loc of the colour's bodies: velocity, then position (r or
                    // π').
                    self.pert.q.copy_from_slice(&at.q);
                    self.pert.v.copy_from_slice(&at.v);
                    if velocity {
                        for &k in colour {
                            let c = 6 * k + loc;
                            self.eps[k] = 1e-7 * (1.0 + at.v[c].abs());
                            self.pert.v[c] += self.eps[k];
                        }
                    } else {
                        self.dq.fill(0.0);
                        let e = if loc < 3 { 1e-7 * l } else { 1e-7 };
                        for &k in colour {
                            self.dq[6 * k + loc] = e;
                            self.eps[k] = e;
                        }
                        apply_rotation_step(&mut self.pert.q, &self.dq);
                    }
                    d.sync(&self.pert);
                    d.eval_implicit_forces(at.t);
                    let out = if velocity { &mut self.ct } else { &mut self.kt };
                    // −(h − h0)/ε over the rows of each block of the perturbed bodies.
                    for &k in colour {
                        for &(j, b) in &self.columns[k] {
                            for rr in 0..6 {
                                let i = 6 * j + rr;
                                out[b][rr * 6 + loc] = -(d.h[i] - self.h0[i]) / self.eps[k];
                            }
                        }
                    }
                }
            }
        }
        if contacts {
            d.contacts_off = false;
            d.sync(at);
            let c = d.collisions.as_ref().expect("collisions");
            let (rows, ct, kt) = (&self.rows, &mut self.ct, &mut self.kt);
            c.tangents(&d.bodies, |j, k, cb, kb| {
                // A pair laid out after these tangents' blocks were made has none: left out
                // until the stepper lays out again.
                if let Some(&(_, b)) = rows[j].iter().find(|&&(col, _)| col == k) {
                    for e in 0..36 {
                        ct[b][e] += cb[e];
                        kt[b][e] += kb[e];
                    }
                }
            });
        }
    }

    /// The size of γ' C_t + β' K_t against the mass matrix M = diag(m_k I, J'_k):
    /// max |(γ' C_t + β' K_t)_rc| / √(M_rr M_cc) over the stored entries, a bound (up to the
    /// block size) on ‖M^(−1/2)(γ' C_t + β' K_t)M^(−1/2)‖ that does not depend on units. A
    /// chord iteration with M instead of M + γ' C_t + β' K_t contracts at about this rate.
    pub fn relative_size(
        &self,
        gamma_p: f64,
        beta_p: f64,
        mass: &[f64],
        inertia: &[nalgebra::Matrix3<f64>],
    ) -> f64 {
        let diag = |k: usize, i: usize| {
            if i < 3 {
                mass[k]
            } else {
                inertia[k][(i - 3, i - 3)]
            }
        };
        let mut size = 0.0f64;
        for (j, row) in self.rows.iter().enumerate() {
            for &(k, b) in row {
                for r in 0..6 {
                    for c in 0..6 {
                        let e = r * 6 + c;
                        let t = gamma_p * self.ct[b][e] + beta_p * self.kt[b][e];
                        size = size.max(t.abs() / (diag(j, r) * diag(k, c)).sqrt());
                    }
                }
            }
        }
        size
    }

    /// Entry (r, c) of γ' C_t + β' K_t (zero outside the stored blocks).
    pub fn entry(&self, r: usize, c: usize, gamma_p: f64, beta_p: f64) -> f64 {
        let (j, k) = (r / 6, c / 6);
        match self.rows[j].iter().find(|&&(col, _)| col == k) {
            Some(&(_, b)) => {
                let e = (r % 6) * 6 + c % 6;
                gamma_p * self.ct[b][e] + beta_p * self.kt[b][e]
            }
            None => 0.0,
        }
    }
}

/// Greedy distance-2 colouring: two bodies get the same colour only when they are not
/// adjacent and have no common neighbour, so perturbing a colour's bodies together leaves
/// every body's rows depending on at most one of them.
fn distance2_colouring(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let nb = adj.len();
    let mut colour = vec![usize::MAX; nb];
    let mut taken: Vec<bool> = Vec::new();
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for k in 0..nb {
        taken.clear();
        taken.resize(colours.len(), false);
        for &j in &adj[k] {
            for &i in std::iter::once(&j).chain(&adj[j]) {
                if colour[i] != usize::MAX {
                    taken[colour[i]] = true;
                }
            }
        }
        let c = taken.iter().position(|t| !t).unwrap_or(colours.len());
        if c == colours.len() {
            colours.push(Vec::new());
        }
        colour[k] = c;
        colours[c].push(k);
    }
    colours
}

#[cfg(test)]
mod tests {
    use super::{distance2_colouring, Tangents};
    use crate::{Dynamics, Force, State};
    use cardan_mechanism::{Body, MechanismBuilder, GROUND};
    use nalgebra::Vector3;

    /// The coloured block tangents equal one-coordinate-at-a-time differences (the same
    /// formula) on every stored block, and the dense differences vanish outside those blocks:
    /// six spinning free bodies, springs 0–1, 1–2, 2–3 and 4–ground (body 5 only under gravity
    /// and its gyroscopic term). Colours: 3 (the path 0–1–2–3 needs three; 4 and 5 join them).
    #[test]
    fn coloured_blocks_equal_dense_differences() {
        let mut b = MechanismBuilder::new();
        b.point(GROUND, "a", Vector3::new(0.3, 1.0, 0.0));
        for k in 0..6 {
            let name = format!("b{k}");
            let x = k as f64;
            b.body(
                Body::new(&name)
                    .mass(1.0 + 0.1 * x)
                    .inertia_diagonal(0.1, 0.2 + 0.01 * x, 0.3)
                    .position(Vector3::new(x, 0.1 * x, 0.0)),
            );
            b.point(&name, "p", Vector3::new(0.2, 0.1, -0.1));
        }
        let model = b.build().unwrap();
        let mut d = Dynamics::new(&model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
            .unwrap();
        for (i, j) in [("b0", "b1"), ("b1", "b2"), ("b2", "b3"), ("b4", "ground")] {
            d.add_force(Force::spring_damper(
                &format!("{i}{j}"),
                (i, "p"),
                (j, if j == "ground" { "a" } else { "p" }),
                40.0,
                3.0,
                Some(0.5),
            ))
            .unwrap();
        }
        let mut s = State::initial(&model, 0.0);
        for k in 0..6 {
            let x = k as f64;
            s.set_velocity(
                k,
                Vector3::new(0.3, -0.2 * x, 0.1),
                Vector3::new(1.0 + x, -2.0, 0.5 * x),
            );
        }
        let mut tan = Tangents::new(&d, &s);
        assert_eq!(tan.colours.len(), 3);
        tan.eval(&mut d, &s, false);
        // Dense differences, one coordinate at a time.
        let n = s.v.len();
        let l = model.characteristic_length();
        d.sync(&s);
        d.eval_forces(0.0);
        let h0 = d.h.clone();
        let (mut nonzero_blocks, mut checked) = (0, 0);
        for c in 0..n {
            for velocity in [true, false] {
                let mut p = s.clone();
                let e = if velocity {
                    let e = 1e-7 * (1.0 + s.v[c].abs());
                    p.v[c] += e;
                    e
                } else {
                    let e = if c % 6 < 3 { 1e-7 * l } else { 1e-7 };
                    let mut dq = vec![0.0; n];
                    dq[c] = e;
                    cardan_mechanism::apply_rotation_step(&mut p.q, &dq);
                    e
                };
                d.sync(&p);
                d.eval_forces(0.0);
                for r in 0..n {
                    let dense = -(d.h[r] - h0[r]) / e;
                    let (gp, bp) = if velocity { (1.0, 0.0) } else { (0.0, 1.0) };
                    let stored = tan.rows[r / 6].iter().any(|&(k, _)| k == c / 6);
                    if stored {
                        let got = tan.entry(r, c, gp, bp);
                        assert!(
                            (got - dense).abs() <= 1e-12 * (1.0 + dense.abs()),
                            "({r}, {c}) velocity {velocity}: {got} vs {dense}"
                        );
                        checked += 1;
                        nonzero_blocks += usize::from(dense != 0.0);
                    } else {
                        assert_eq!(dense, 0.0, "({r}, {c}) outside the blocks");
                    }
                }
            }
        }
        assert!(
            nonzero_blocks > checked / 4,
            "{nonzero_blocks} of {checked}"
        );
    }

    /// Bodies at distance ≤ 2 in the coupling graph never share a colour; isolated bodies all
    /// share one.
    #[test]
    fn colouring_separates_bodies_at_distance_two() {
        // Path 0-1-2-3-4, and 5, 6 isolated.
        let mut adj = vec![Vec::new(); 7];
        for (i, j) in [(0, 1), (1, 2), (2, 3), (3, 4)] {
            adj[i].push(j);
            adj[j].push(i);
        }
        let colours = distance2_colouring(&adj);
        let mut of = [usize::MAX; 7];
        for (c, bodies) in colours.iter().enumerate() {
            for &k in bodies {
                of[k] = c;
            }
        }
        for i in 0..5usize {
            for j in i + 1..5usize.min(i + 3) {
                assert_ne!(of[i], of[j], "bodies {i} and {j}");
            }
        }
        assert_eq!(colours.len(), 3);
        assert_eq!(of[5], of[6]);
        assert_eq!(of[5], of[0]);
    }
}
