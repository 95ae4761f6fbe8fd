//! Contact between bodies: collision shapes ([`cardan_mechanism::ShapeSpec`]) found touching by
//! parry3d-f64 and pushed apart by a compliant contact law with friction ([`law`]).
//!
//! ## Where it enters the equations of motion
//! Contact forces are applied forces: at every evaluation of h (every stage of DOPRI5, every
//! Newton iterate and tangent difference of generalized-α) the shapes are placed at the synced
//! body poses, the pairs whose boxes overlap are found (the broad phase: parry's BVH over the
//! shapes' world boxes, refitted at each evaluation, traversed against itself — O(n log n), not
//! O(n²); planes, which have no box, are tried against every shape), each pair's contact
//! manifold is computed (the narrow phase: parry's `contact_manifolds`, up to four points per
//! face contact so a box rests on its face), and every point of penetration δ = −dist > 0 gets
//! the law's force. With n the normal of the manifold (from shape 1 towards shape 2), P the
//! midpoint of the two surface points and v_rel = v₂(P) − v₁(P) the relative velocity there:
//!
//! ```text
//! δ̇ = −nᵀ v_rel,   v_t = v_rel − n nᵀ v_rel,   f = F_n n + f_t   on body 2 at P,  −f on body 1
//! ```
//!
//! (applied through [`crate::AppliedForces::add_force_at`], so each body's Newton–Euler
//! balance holds them like any other force). The power of the contact forces, fᵀ v_rel summed
//! over the points, is the "contact" work channel: it holds the energy the contacts store
//! while pressed and what their damping and friction dissipate, so E − E₀ − W still closes.
//!
//! ## Memory of a contact
//! The damping of a pair is scaled by its approach speed v₀ at the onset ([`law`]). A pair is
//! followed within a margin (a quarter of the thinner shape's thickness) before it touches, and
//! keeps its approach rate at the last accepted state at which it was apart; at the first
//! accepted state it touches, v₀ is the larger of that and its approach rate there (DOPRI5 cuts
//! its step at the onset, so the latter is exact; generalized-α's is the approach one step
//! before), and v₀ is kept until the first accepted state it does not touch
//! (`Collisions::accept`). Trial states of a rejected step leave no trace.
//!
//! ## Implicit steps
//! A touching pair of moving bodies couples their forces: its bodies become a coupled pair of
//! the generalized-α iteration matrix (its 6×6 blocks are laid out and its tangents computed by
//! the coloured differences), from the first evaluation the pair touches at: a new pair asks
//! for a new layout (`Collisions::take_new_pairs`), which the stepper makes before its next
//! attempt. Pairs once laid out stay (a rare event per pair, not per step).

pub(crate) mod geometry;
pub mod law;
mod point;
mod slip;
pub use geometry::hull_triangles;
pub use point::ContactPoint;

use crate::forces::AppliedForces;
use cardan_constraints::BodyState;
use cardan_mechanism::{BodyId, Model};
use geometry::{from_parry, Placed};
use law::PairLaw;
use nalgebra::Vector3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use parry3d_f64::query::{
    ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher,
};
use slip::SlipMemory;
use std::collections::{HashMap, HashSet};

/// A penetration deeper than this fraction of the thinner shape's thickness
/// ([`cardan_mechanism::Geometry::thickness`]) is doubtful: at the start of a run an error
/// ([`DynamicsError::ShapesOverlap`](crate::DynamicsError::ShapesOverlap)), during it a warning
/// of the front end.
pub const DEEP_PENETRATION: f64 = 0.1;

/// A contact's penetration relative to the thinner of its shapes' thicknesses
/// ([`cardan_mechanism::Geometry::thickness`]); not finite between a plane and a mesh.
pub fn depth_ratio(model: &Model, c: &ContactPoint) -> f64 {
    let shapes = model.shapes();
    let thin =
        (shapes[c.shapes[0]].geometry.thickness()).min(shapes[c.shapes[1]].geometry.thickness());
    c.penetration / thin
}

/// Builds every shape of `model` as the geometry library takes it.
///
/// # Errors
/// The first shape it refuses (a convex hull it cannot build, a triangle mesh that is not
/// manifold), with the reason.
pub fn validate_shapes(model: &Model) -> Result<(), (String, String)> {
    for s in model.shapes() {
        geometry::place(s).map_err(|e| (s.name.clone(), e))?;
    }
    Ok(())
}

/// The margin of a shape, relative to its thickness: pairs closer than it are followed (their
/// approach rate kept) before they touch.
const MARGIN: f64 = 0.25;

/// The derivatives of one point's law at an evaluation ([`Collisions::tangents`]).
#[derive(Debug, Clone, Copy)]
struct Slopes {
    /// ∂F_n/∂δ.
    k: f64,
    /// ∂F_n/∂δ̇.
    c: f64,
    /// φ of f_t = −φ F_n v_t.
    phi: f64,
    /// The slope of the friction's magnitude along the slip that the tangent takes, per unit
    /// F_n: dψ/ds, a chord or φ (`slip::along_slope`).
    along: f64,
}

/// A pair of shapes whose boxes overlap, with parry's persistent manifolds.
struct Pair {
    law: PairLaw,
    manifolds: Vec<ContactManifold<(), ()>>,
    workspace: Option<ContactManifoldsWorkspace>,
    /// v₀ kept from the accepted states (NaN: not touching at the last accepted state).
    v0: f64,
    /// Touching at the last evaluation, and its largest approach rate there.
    touching: bool,
    rate: f64,
    /// The largest approach rate of its points within the margin but apart, at the last
    /// evaluation, and at the last accepted state at which the pair was apart.
    approach: f64,
    pre: f64,
    /// The distance within which the pair's points are followed before they touch.
    margin: f64,
    /// The evaluation counter when the pair was last a candidate.
    seen: u64,
    /// The slips of its first four contact points at its last evaluations, and how many
    /// evaluations in a row (each the one after the other) came before this one.
    slips: [SlipMemory; 4],
    run: u32,
}

/// The contact state of a run (module docs). Allocates when pairs first meet; the steps of a
/// settled scene do not.
pub(crate) struct Collisions {
    shapes: Vec<Placed>,
    /// Leaf index (in the BVH) → shape; the planes are not leaves.
    leaves: Vec<usize>,
    planes: Vec<usize>,
    poses: Vec<Pose>,
    /// Each shape's margin: a quarter of its thickness (0 for a plane or a ground mesh).
    margins: Vec<f64>,
    /// Each shape's bounding radius about its centre, and whether it is a ball (for the step
    /// cap).
    reach: Vec<f64>,
    round: Vec<bool>,
    bvh: Bvh,
    bvh_workspace: BvhWorkspace,
    /// Moving body pairs joined by a joint, sorted.
    jointed: Vec<(usize, usize)>,
    pairs: HashMap<(u32, u32), Pair, foldhash::fast::FixedState>,
    candidates: Vec<(u32, u32)>,
    /// The contact points of the last evaluation.
    pub points: Vec<ContactPoint>,
    /// Each point's law derivatives at the last evaluation (for the implicit tangents).
    slopes: Vec<Slopes>,
    /// Moving body pairs coupled by a contact, in the order they first touched, and as a set
    /// (a pile has hundreds: a search of the list at every touching pair's evaluation grew
    /// with their square).
    pub coupled: Vec<(usize, usize)>,
    coupled_set: HashSet<(usize, usize), foldhash::fast::FixedState>,
    new_pairs: bool,
    stamp: u64,
    /// The pairs that took their onset speed at the last [`Collisions::accept`].
    pub onsets: Vec<(u32, u32)>,
    /// Storage for the onsets' event location.
    pub scratch: Vec<(usize, usize)>,
}

impl std::fmt::Debug for Collisions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Collisions")
            .field("shapes", &self.shapes.len())
            .field("pairs", &self.pairs.len())
            .field("points", &self.points.len())
            .finish_non_exhaustive()
    }
}

fn ordered(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// The velocity of the body point at global position `p`: ṙ + A (ω̃' A ᵀ(p − r)).
fn point_velocity(s: &BodyState, p: &Vector3<f64>) -> Vector3<f64> {
    s.r_dot + s.a * s.omega_local.cross(&s.a.tr_mul(&(p - s.r)))
}

impl Collisions {
    /// The collision state of `model` at rest bodies `bodies`; `None` without shapes.
    ///
    /// # Errors
    /// The shape's name and the reason for a mesh parry refuses.
    pub fn new(model: &Model, bodies: &[BodyState]) -> Result<Option<Self>, (String, String)> {
        if model.shapes().is_empty() {
            return Ok(None);
        }
        let shapes = model
            .shapes()
            .iter()
            .map(|s| geometry::place(s).map_err(|e| (s.name.clone(), e)))
            .collect::<Result<Vec<_>, _>>()?;
        let poses: Vec<Pose> = shapes.iter().map(|s| s.pose(bodies)).collect();
        let margins: Vec<f64> = (model.shapes().iter())
            .map(|s| {
                let t = s.geometry.thickness();
                if t.is_finite() {
                    MARGIN * t
                } else {
                    0.0
                }
            })
            .collect();
        let reach: Vec<f64> = (shapes.iter())
            .map(|p| p.shape.compute_local_aabb().half_extents().length())
            .collect();
        let round: Vec<bool> = (model.shapes().iter())
            .map(|s| matches!(s.geometry, cardan_mechanism::Geometry::Sphere { .. }))
            .collect();
        let (planes, leaves): (Vec<usize>, Vec<usize>) =
            (0..shapes.len()).partition(|&k| shapes[k].unbounded);
        let boxes: Vec<Aabb> = leaves
            .iter()
            .map(|&k| shapes[k].shape.compute_aabb(&poses[k]).loosened(margins[k]))
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &boxes);
        let mut jointed: Vec<(usize, usize)> = (model.joints().iter())
            .filter_map(|j| match (j.body_i, j.body_j) {
                (BodyId::Moving(a), BodyId::Moving(b)) => Some(ordered(a, b)),
                _ => None,
            })
            .collect();
        jointed.sort_unstable();
        jointed.dedup();
        Ok(Some(Self {
            shapes,
            leaves,
            planes,
            poses,
            margins,
            reach,
            round,
            bvh,
            bvh_workspace: BvhWorkspace::default(),
            jointed,
            pairs: HashMap::with_hasher(foldhash::fast::FixedState::default()),
            candidates: Vec::new(),
            points: Vec::new(),
            slopes: Vec::new(),
            coupled: Vec::new(),
            coupled_set: HashSet::with_hasher(foldhash::fast::FixedState::default()),
            new_pairs: false,
            stamp: 0,
            onsets: Vec::new(),
            scratch: Vec::new(),
        }))
    }

    /// Whether shapes a and b may touch ([`cardan_mechanism::may_touch`], the joined bodies
    /// from the sorted table).
    fn may_touch(&self, model: &Model, a: usize, b: usize) -> bool {
        let (sa, sb) = (&model.shapes()[a], &model.shapes()[b]);
        let jointed = &self.jointed;
        cardan_mechanism::may_touch(sa, sb, |i, j| jointed.binary_search(&ordered(i, j)).is_ok())
    }

    /// The candidate pairs at the current poses (broad phase) into `self.candidates`.
    fn broad_phase(&mut self, model: &Model) {
        for (leaf, &k) in self.leaves.iter().enumerate() {
            if let BodyId::Moving(_) = self.shapes[k].body {
                let aabb =
                    (self.shapes[k].shape.compute_aabb(&self.poses[k])).loosened(self.margins[k]);
                self.bvh.update_partially_if_present(aabb, leaf as u32, 0.0);
            }
        }
        self.bvh.refit_without_opt();
        let mut found = std::mem::take(&mut self.candidates);
        found.clear();
        let leaves = &self.leaves;
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.bvh_workspace, &mut |i, j| {
                let (a, b) = (leaves[i as usize], leaves[j as usize]);
                found.push((a.min(b) as u32, a.max(b) as u32));
            });
        // A plane against the shapes whose box reaches it (within the shape's margin).
        for &p in &self.planes {
            let n = self.poses[p].rotation * parry3d_f64::math::Vector::Z;
            let offset = n.dot(self.poses[p].translation);
            for (leaf, &k) in self.leaves.iter().enumerate() {
                let b = self.bvh.leaf_node(leaf as u32).map(|node| node.aabb());
                let Some(b) = b else { continue };
                let (c, h) = (b.center(), b.half_extents());
                let lowest = n.dot(c) - n.abs().dot(h) - offset;
                if lowest <= 0.0 {
                    found.push((k.min(p) as u32, k.max(p) as u32));
                }
            }
        }
        found.retain(|&(a, b)| self.may_touch(model, a as usize, b as usize));
        self.candidates = found;
    }

    /// Places the shapes at `bodies`, finds the contacts and adds their forces to `acc`
    /// (module docs); the points are kept for the outputs.
    pub fn apply(&mut self, model: &Model, acc: &mut AppliedForces<'_>) {
        let bodies = acc.bodies;
        for (pose, s) in self.poses.iter_mut().zip(&self.shapes) {
            if let BodyId::Moving(_) = s.body {
                *pose = s.pose(bodies);
            }
        }
        self.stamp += 1;
        self.broad_phase(model);
        self.points.clear();
        self.slopes.clear();
        for c in 0..self.candidates.len() {
            let (a, b) = self.candidates[c];
            self.pair_forces(model, a as usize, b as usize, acc);
        }
        // Forget pairs whose boxes parted long ago (their memory is that of a new contact).
        if self.stamp.is_multiple_of(64) {
            let stamp = self.stamp;
            self.pairs
                .retain(|_, p| p.touching || !p.v0.is_nan() || stamp - p.seen < 64);
        }
    }

    /// The contact of shapes a < b: manifolds, then each penetrating point's force.
    fn pair_forces(&mut self, model: &Model, a: usize, b: usize, acc: &mut AppliedForces<'_>) {
        let stamp = self.stamp;
        let margins = &self.margins;
        let pair = self.pairs.entry((a as u32, b as u32)).or_insert_with(|| {
            let (sa, sb) = (&model.shapes()[a], &model.shapes()[b]);
            let m = model.materials();
            let law = match model.material_pair(sa.material, sb.material) {
                Some(p) => PairLaw::of_pair(&m[p]),
                None => PairLaw::new(&m[sa.material], &sa.geometry, &m[sb.material], &sb.geometry),
            };
            Pair {
                law,
                manifolds: Vec::new(),
                workspace: None,
                v0: f64::NAN,
                touching: false,
                rate: 0.0,
                approach: 0.0,
                pre: 0.0,
                margin: margins[a].min(margins[b]),
                seen: stamp,
                slips: [SlipMemory::default(); 4],
                run: 0,
            }
        });
        pair.run = if pair.seen + 1 == stamp {
            pair.run.saturating_add(1)
        } else {
            0
        };
        pair.seen = stamp;
        let mut ip = 0usize;
        let (p1, p2) = (&self.poses[a], &self.poses[b]);
        let pos12 = p1.inv_mul(p2);
        let (s1, s2) = (&self.shapes[a], &self.shapes[b]);
        let done = DefaultQueryDispatcher.contact_manifolds(
            &pos12,
            s1.shape.as_ref(),
            s2.shape.as_ref(),
            pair.margin,
            &mut pair.manifolds,
            &mut pair.workspace,
        );
        pair.touching = false;
        pair.approach = 0.0;
        if done.is_err() {
            return;
        }
        let bodies = acc.bodies;
        let velocity = |id: BodyId, p: &Vector3<f64>| match id {
            BodyId::Ground => Vector3::zeros(),
            BodyId::Moving(k) => point_velocity(&bodies[k], p),
        };
        let mut rate_max = 0.0_f64;
        let v0 = pair.v0;
        for m in &pair.manifolds {
            let pose1 = match &m.subshape_poses {
                Some(sp) => sp.pos1.map_or(*p1, |q| *p1 * q),
                None => *p1,
            };
            let pose2 = match &m.subshape_poses {
                Some(sp) => sp.pos2.map_or(*p2, |q| *p2 * q),
                None => *p2,
            };
            let n = from_parry(pose1.rotation * m.local_n1);
            for pt in &m.points {
                let w1 = from_parry(pose1 * pt.local_p1);
                let w2 = from_parry(pose2 * pt.local_p2);
                let at = 0.5 * (w1 + w2);
                let v_rel = velocity(s2.body, &at) - velocity(s1.body, &at);
                let rate = -n.dot(&v_rel);
                if pt.dist > 0.0 {
                    // Apart, within the margin: its approach, for the onset speed.
                    pair.approach = pair.approach.max(rate);
                    continue;
                }
                rate_max = rate_max.max(rate);
                let delta = -pt.dist;
                let onset = if v0.is_nan() { rate.max(pair.pre) } else { v0 };
                let fn_ = pair.law.normal_force(delta, rate, onset);
                let (k_n, c_n) = pair.law.normal_slopes(delta, rate, onset);
                let vt = v_rel + n * rate;
                let slip = vt.norm();
                let phi = pair.law.friction_factor(slip);
                // The tangent's slope along the slip, from this point's last slips (a pair's
                // fifth point on takes the secant).
                let along = match pair.slips.get_mut(ip) {
                    Some(memory) => slip::along_slope(&pair.law, &vt, phi, memory, pair.run),
                    None => phi,
                };
                ip += 1;
                let ft = -vt * (phi * fn_);
                let f = n * fn_ + ft;
                for (id, sign) in [(s2.body, 1.0), (s1.body, -1.0)] {
                    if let BodyId::Moving(k) = id {
                        let s_local = bodies[k].a.tr_mul(&(at - bodies[k].r));
                        acc.add_force_at(id, &s_local, &(f * sign));
                    }
                }
                pair.touching = true;
                self.slopes.push(Slopes {
                    k: k_n,
                    c: c_n,
                    phi,
                    along,
                });
                self.points.push(ContactPoint {
                    shapes: [a, b],
                    point: at,
                    normal: n,
                    penetration: delta,
                    penetration_rate: rate,
                    normal_force: fn_,
                    friction_force: ft,
                    slip_velocity: vt,
                });
            }
        }
        if pair.touching {
            if pair.v0.is_nan() {
                pair.rate = rate_max;
            }
            if let (BodyId::Moving(i), BodyId::Moving(j)) = (s1.body, s2.body) {
                let key = ordered(i, j);
                if self.coupled_set.insert(key) {
                    self.coupled.push(key);
                    self.new_pairs = true;
                }
            }
        }
    }

    /// At an accepted state (the last evaluation's): a pair touching keeps (or takes) its
    /// onset speed, a pair apart forgets it.
    pub fn accept(&mut self) {
        self.onsets.clear();
        for (key, p) in self.pairs.iter_mut() {
            if p.touching {
                if p.v0.is_nan() {
                    p.v0 = p.rate.max(p.pre).max(law::ONSET_SPEED_FLOOR);
                    self.onsets.push(*key);
                }
            } else {
                p.v0 = f64::NAN;
                p.rate = 0.0;
                p.pre = p.approach;
            }
        }
    }

    /// The contacts' power at `bodies` with the forces of the last evaluation (the same state
    /// but for a velocity projection since): Σ fᵀ v_rel over the points (W).
    pub fn power_at(&self, bodies: &[BodyState]) -> f64 {
        let velocity = |id: BodyId, p: &Vector3<f64>| match id {
            BodyId::Ground => Vector3::zeros(),
            BodyId::Moving(k) => point_velocity(&bodies[k], p),
        };
        self.points
            .iter()
            .map(|c| {
                let [a, b] = c.shapes;
                let v_rel = velocity(self.shapes[b].body, &c.point)
                    - velocity(self.shapes[a].body, &c.point);
                (c.normal * c.normal_force + c.friction_force).dot(&v_rel)
            })
            .sum()
    }

    /// The longest step in which no moving shape travels more than its margin, at `bodies`
    /// (∞ without moving shapes or at rest): within it two shapes cannot pass through each
    /// other unseen, since each moves less than a quarter of its thickness.
    pub(crate) fn step_cap(&self, bodies: &[BodyState]) -> f64 {
        let mut cap = f64::INFINITY;
        for (k, s) in self.shapes.iter().enumerate() {
            let BodyId::Moving(b) = s.body else { continue };
            let st = &bodies[b];
            let w = st.omega_local.norm();
            // The shape's centre moves at |ṙ + ω × c|; its boundary turns about it at |ω| times
            // its bounding radius, except a ball's, which turning does not move.
            let centre = (st.r_dot + st.a * st.omega_local.cross(&s.center)).norm();
            let speed = centre
                + if self.round[k] {
                    0.0
                } else {
                    w * self.reach[k]
                };
            if speed > 0.0 && self.margins[k] > 0.0 {
                cap = cap.min(self.margins[k] / speed);
            }
        }
        cap
    }

    /// Forgets the onset speeds the last [`Collisions::accept`] took (the step that took them
    /// went past the contacts' onset, which an event then located: the state there takes them
    /// again).
    pub fn forget_onsets(&mut self) {
        for key in &self.onsets {
            if let Some(p) = self.pairs.get_mut(key) {
                p.v0 = f64::NAN;
            }
        }
        self.onsets.clear();
    }

    /// The pairs that did not touch at the last accepted state (or took their onset speed at
    /// the last [`Collisions::accept`]) but touch at the last evaluation: the onsets of a
    /// step, before or after it was accepted.
    pub fn new_contacts(&self, out: &mut Vec<(usize, usize)>) {
        out.clear();
        for (&(a, b), p) in &self.pairs {
            if p.touching && (p.v0.is_nan() || self.onsets.contains(&(a, b))) {
                out.push((a as usize, b as usize));
            }
        }
        out.sort_unstable();
    }

    /// The distance between shapes a and b at `bodies` (0 when they touch or overlap; ∞ when
    /// the geometry library cannot tell).
    pub fn distance(&self, a: usize, b: usize, bodies: &[BodyState]) -> f64 {
        let (s1, s2) = (&self.shapes[a], &self.shapes[b]);
        let (p1, p2) = (s1.pose(bodies), s2.pose(bodies));
        parry3d_f64::query::distance(&p1, s1.shape.as_ref(), &p2, s2.shape.as_ref())
            .map_or(f64::INFINITY, |d| d.distance)
    }

    /// The contacts' force tangents at the last evaluation, block by block: for each point and
    /// each pair (j, k) of its moving bodies, `add(j, k, C, K)` with the 6×6 blocks (row-major)
    /// C = −∂h_j/∂v_k and K = −∂h_j/∂q_k. With the contact point's Jacobians J_k = [I, −A_k s̃'_k]
    /// (v_P = J_k v_k), the force f on body 2 (−f on body 1) and v_rel = J₂v₂ − J₁v₁:
    ///
    /// ```text
    /// ∂f/∂v_rel = D = −c_n n nᵀ − F_n (φ (I − n nᵀ − t tᵀ) + σ t tᵀ),
    /// ∂f/∂x_P₂ = S = −k_n (n − φ v_t) nᵀ
    /// ```
    ///
    /// (c_n = ∂F_n/∂δ̇, k_n = ∂F_n/∂δ, t = v_t/|v_t|; across the slip the friction's exact
    /// φ F_n; along it a slope σ of its magnitude ψ(s) = φ(s) s chosen from the point's last
    /// slips ([`slip`]: the derivative where the slip grows, a chord to the solution
    /// estimated from the last three where it shrinks steadily, else the secant φ). On the
    /// landing 343-sphere pile the secant alone took 13.6 Newton iterations a step, the
    /// choice 7.8, the derivative everywhere six times the secant's. The turning of n and of
    /// the lever arms is left out.) So the blocks are
    /// ∓J_jᵀ D J_k and ∓J_jᵀ S J_k with the sign of body j times that of body k.
    pub fn tangents(
        &self,
        bodies: &[BodyState],
        mut add: impl FnMut(usize, usize, &[f64; 36], &[f64; 36]),
    ) {
        use nalgebra::{Matrix3, Matrix3x6};
        for (c, sl) in self.points.iter().zip(&self.slopes) {
            let n = c.normal;
            let nn = n * n.transpose();
            let mut d = -sl.c * nn - sl.phi * c.normal_force * (Matrix3::identity() - nn);
            let slip = c.slip_velocity.norm();
            if sl.along != sl.phi && slip > 0.0 {
                let t = c.slip_velocity / slip;
                d += (sl.phi - sl.along) * c.normal_force * t * t.transpose();
            }
            let s = -sl.k * (n - sl.phi * c.slip_velocity) * n.transpose();
            let jac = |k: usize| {
                let b = &bodies[k];
                let arm = b.a.tr_mul(&(c.point - b.r));
                let mut j = Matrix3x6::zeros();
                j.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&Matrix3::identity());
                j.fixed_view_mut::<3, 3>(0, 3)
                    .copy_from(&(-b.a * arm.cross_matrix()));
                j
            };
            // Each moving side: its body, sign and Jacobian, once.
            let mut sides = [(0, 0.0, Matrix3x6::zeros()); 2];
            let mut n_sides = 0;
            for (id, sign) in [
                (self.shapes[c.shapes[1]].body, 1.0),
                (self.shapes[c.shapes[0]].body, -1.0),
            ] {
                if let BodyId::Moving(k) = id {
                    sides[n_sides] = (k, sign, jac(k));
                    n_sides += 1;
                }
            }
            for &(j, sj, ref jj) in &sides[..n_sides] {
                for &(k, sk, ref jk) in &sides[..n_sides] {
                    // h_j = s_j J_jᵀ f, f depending on v_rel (s_k J_k v_k) and x_P (s_k J_k q_k).
                    let cb = -(sj * sk) * (jj.transpose() * d * jk);
                    let kb = -(sj * sk) * (jj.transpose() * s * jk);
                    let mut cm = [0.0; 36];
                    let mut km = [0.0; 36];
                    for r in 0..6 {
                        for col in 0..6 {
                            cm[r * 6 + col] = cb[(r, col)];
                            km[r * 6 + col] = kb[(r, col)];
                        }
                    }
                    add(j, k, &cm, &km);
                }
            }
        }
    }

    /// Whether a moving pair touched for the first time since the last call.
    pub fn take_new_pairs(&mut self) -> bool {
        std::mem::take(&mut self.new_pairs)
    }
}
