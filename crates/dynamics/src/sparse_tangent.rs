//! Sparse tangents of the static equations by column-grouped (graph-coloured) central
//! differences: the sparse counterparts of the dense K_t and C_t of the `tangent` module.
//!
//! ## Theory
//! The residual r₁ = Φ_vᵀλ − h_s of body j (its six rows) depends only on the poses of the
//! bodies it is coupled with: j itself and the other body of each joint, driver, coupler,
//! spring or rotational spring that acts on j. So K_t = ∂r₁/∂δ has a 6×6 block (j, k) only
//! where k is a neighbour of j (or k = j), and the same holds for C_t = −∂h/∂v.
//!
//! Two bodies whose neighbourhoods are disjoint perturb disjoint rows, so their columns can
//! be differenced together (Curtis, Powell & Reid 1974; Coleman & Moré 1983): a greedy
//! distance-2 colouring of the body graph splits the bodies into groups, and one central
//! difference per group and component (6 per group, two residuals each) gives every column of
//! the group. A chain needs 3 groups: 36 residual evaluations whatever its length, instead of
//! the 12 nb of the dense tangent. The steps are those of the dense tangent (1e-6 L for a
//! translation, 1e-6 rad for a rotation; 1e-6 (1 + |v|) for a velocity), so both give the same
//! entries to round-off.
//!
//! A user force callback can couple any bodies: its pattern is unknown, and the sparse path is
//! not used with one ([`Dynamics::sparse_path`]).

use crate::state::State;
use crate::system::Dynamics;
use cardan_mechanism::{apply_rotation_step, BodyId};
use nalgebra::DMatrix;

/// Relative finite-difference step (as the dense tangent's).
const FD_STEP: f64 = 1e-6;

/// The sparse path (sparse tangents, sparse saddle-point factorizations, a few lowest modes by
/// shift-invert Lanczos) is taken from this many moving bodies on, when the model has no user
/// force callback. The one switch point between the dense and the sparse path of the static,
/// quasi-static and modal analyses.
///
/// Below it the dense path (null-space basis by SVD, all modes) costs milliseconds (50 bodies)
/// to a few tenths of a second (100 bodies); above it its O(n³) cost and n² memory grow
/// quickly (1,000 bodies: minutes and gigabytes) while the sparse path stays near linear.
pub const SPARSE_MIN_BODIES: usize = 100;

/// A sparse n × n matrix as (row, column, value) triplets (no duplicates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SparseMatrix {
    /// Rows (= columns).
    pub n: usize,
    /// The entries.
    pub entries: Vec<(usize, usize, f64)>,
}

impl SparseMatrix {
    /// The dense matrix (for tests and small models).
    pub fn to_dense(&self) -> DMatrix<f64> {
        let mut a = DMatrix::zeros(self.n, self.n);
        for &(r, c, v) in &self.entries {
            a[(r, c)] += v;
        }
        a
    }

    /// y = A x.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for &(r, c, v) in &self.entries {
            y[r] += v * x[c];
        }
        y
    }

    /// Largest |entry| (0 when empty).
    pub fn amax(&self) -> f64 {
        self.entries.iter().fold(0.0f64, |a, e| a.max(e.2.abs()))
    }
}

/// The body graph of the static residual and its distance-2 colouring (module docs).
#[derive(Debug, Clone)]
pub(crate) struct BodyGraph {
    /// k and the bodies coupled with k, increasing.
    pub neighbours: Vec<Vec<usize>>,
    /// Groups of bodies with pairwise disjoint neighbourhoods.
    pub groups: Vec<Vec<usize>>,
}

impl BodyGraph {
    /// The graph of `pairs` (moving body pairs) over `nb` bodies, coloured greedily.
    pub fn new(nb: usize, pairs: &[(usize, usize)]) -> Self {
        let mut neighbours: Vec<Vec<usize>> = (0..nb).map(|k| vec![k]).collect();
        for &(i, j) in pairs {
            if i != j {
                neighbours[i].push(j);
                neighbours[j].push(i);
            }
        }
        for v in &mut neighbours {
            v.sort_unstable();
            v.dedup();
        }
        let mut colour = vec![usize::MAX; nb];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut taken = Vec::new();
        for k in 0..nb {
            taken.clear();
            for &j in &neighbours[k] {
                for &i in &neighbours[j] {
                    if colour[i] != usize::MAX {
                        taken.push(colour[i]);
                    }
                }
            }
            let c = (0..).find(|c| !taken.contains(c)).expect("unbounded");
            colour[k] = c;
            if c == groups.len() {
                groups.push(Vec::new());
            }
            groups[c].push(k);
        }
        Self { neighbours, groups }
    }
}

impl Dynamics<'_> {
    /// Whether the analyses of this model take the sparse path: at least
    /// [`SPARSE_MIN_BODIES`] moving bodies and no user force callback.
    pub fn sparse_path(&self) -> bool {
        self.user.is_none() && self.model.num_bodies() >= SPARSE_MIN_BODIES
    }

    /// The body graph of the static residual: bodies coupled by a constraint element or a
    /// force element.
    pub(crate) fn body_graph(&self) -> BodyGraph {
        let mut pairs = self.coupled_pairs();
        for e in &self.elements {
            if let (BodyId::Moving(i), BodyId::Moving(j)) = (e.bi, e.bj) {
                pairs.push((i, j));
            }
        }
        BodyGraph::new(self.model.num_bodies(), &pairs)
    }

    /// K_t = ∂r₁/∂δ at fixed λ (sparse, module docs).
    pub(crate) fn static_tangent_sparse(
        &mut self,
        graph: &BodyGraph,
        state: &State,
        lambda: &[f64],
        s: f64,
    ) -> SparseMatrix {
        let n = state.v.len();
        let l = self.model.characteristic_length();
        let mut p = state.clone();
        let mut dq = vec![0.0; n];
        let mut entries = Vec::new();
        for group in &graph.groups {
            for c in 0..6 {
                let e = if c < 3 { FD_STEP * l } else { FD_STEP };
                let mut r = [Vec::new(), Vec::new()];
                for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                    p.q.copy_from_slice(&state.q);
                    dq.fill(0.0);
                    for &k in group {
                        dq[6 * k + c] = sign * e;
                    }
                    apply_rotation_step(&mut p.q, &dq);
                    r[i] = self.static_residual(&p, lambda, s).0.as_slice().to_vec();
                }
                scatter_group(graph, group, c, &r, 2.0 * e, 1.0, &mut entries);
            }
        }
        self.sync(state);
        SparseMatrix { n, entries }
    }

    /// C_t = −∂h/∂v at `state` (sparse, all forces at full load).
    pub(crate) fn damping_tangent_sparse(
        &mut self,
        graph: &BodyGraph,
        state: &State,
    ) -> SparseMatrix {
        let n = state.v.len();
        let mut p = state.clone();
        let mut entries = Vec::new();
        for group in &graph.groups {
            for c in 0..6 {
                let mut h = [Vec::new(), Vec::new()];
                for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                    p.v.copy_from_slice(&state.v);
                    for &k in group {
                        p.v[6 * k + c] += sign * FD_STEP * (1.0 + state.v[6 * k + c].abs());
                    }
                    self.sync(&p);
                    self.eval_static_forces(state.t, 1.0);
                    h[i] = self.h.clone();
                }
                // Steps differ per body: scale each column by its own.
                for &k in group {
                    let e = FD_STEP * (1.0 + state.v[6 * k + c].abs());
                    scatter_group(graph, &[k], c, &h, 2.0 * e, -1.0, &mut entries);
                }
            }
        }
        self.sync(state);
        SparseMatrix { n, entries }
    }
}

/// The columns 6k + c (k in `group`) of a grouped central difference (r[0] − r[1]) / `step`,
/// times `sign`, on the rows of k's neighbours; exact zeros are dropped.
fn scatter_group(
    graph: &BodyGraph,
    group: &[usize],
    c: usize,
    r: &[Vec<f64>; 2],
    step: f64,
    sign: f64,
    entries: &mut Vec<(usize, usize, f64)>,
) {
    for &k in group {
        for &j in &graph.neighbours[k] {
            for i in 0..6 {
                let row = 6 * j + i;
                let d = sign * (r[0][row] - r[1][row]) / step;
                if d != 0.0 {
                    entries.push((row, 6 * k + c, d));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::BodyGraph;

    #[test]
    fn a_chain_needs_three_groups_and_neighbourhoods_in_a_group_are_disjoint() {
        let pairs: Vec<(usize, usize)> = (0..9).map(|k| (k, k + 1)).collect();
        let g = BodyGraph::new(10, &pairs);
        assert_eq!(g.groups.len(), 3);
        for group in &g.groups {
            for (a, &i) in group.iter().enumerate() {
                for &j in &group[a + 1..] {
                    assert!(g.neighbours[i].iter().all(|x| !g.neighbours[j].contains(x)));
                }
            }
        }
    }
}
