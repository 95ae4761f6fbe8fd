//! [`Dynamics`]: a model with its mass data and force elements, and the equations of motion
//! M v̇ + Φ_vᵀ λ = h, Φ_v v̇ = γ# solved at a state.

use crate::forces::{AppliedForces, Force, Resolved, UserForces};
use crate::kkt::{
    element_blocks, elements, eval_rows, CurveTrack, Element, Kkt, Rhs, SchurRefinement,
};
use crate::options::Baumgarte;
use crate::results::Reaction;
use crate::state::State;
use crate::DynamicsError;
use cardan_constraints::BodyState;
use cardan_mechanism::{AnalysisError, AssemblyOptions, BodyId, EquationName, Model};
use cardan_solver::{RankAnalysis, RankOptions, SolverError, SparsityPattern};
use nalgebra::{Matrix3, Vector3};

/// Kinetic and potential energy at one state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    /// ½ m ṙᵀṙ + ½ ω'ᵀ J' ω', summed over the bodies.
    pub kinetic: f64,
    /// −Σ m gᵀ r.
    pub gravity: f64,
    /// Springs (translational and rotational).
    pub spring: f64,
}

impl Energy {
    /// kinetic + gravity + spring.
    pub fn total(&self) -> f64 {
        self.kinetic + self.gravity + self.spring
    }
}

/// The dynamics of a mechanism: the [`Model`] (bodies with mass and inertia about the centre of
/// mass, joints, drivers), its force elements ([`Model::forces`] plus any added with
/// [`add_force`](Self::add_force)) and an optional user callback.
///
/// The body reference point must be the centre of mass (the builder's convention: points are
/// given relative to it), so that M = diag(m I, J') is block diagonal.
pub struct Dynamics<'m> {
    pub(crate) model: &'m Model,
    pub(crate) mass: Vec<f64>,
    pub(crate) inertia: Vec<Matrix3<f64>>,
    pub(crate) forces: Vec<Resolved>,
    /// The name of each element of `forces` (for the work channels, [`crate::work`]).
    pub(crate) force_names: Vec<String>,
    pub(crate) user: Option<UserForces>,
    pub(crate) elements: Vec<Element>,
    pub(crate) kkt: Option<Kkt>,
    pub(crate) redundant: Vec<EquationName>,
    /// Times the independent rows were chosen again ([`Dynamics::row_reselections`]).
    pub(crate) reselections: usize,
    /// Body states of the last evaluation.
    pub(crate) bodies: Vec<BodyState>,
    /// Each coupler's angles at the last accepted state, which its angles are continued from
    /// ([`Model::accept_turns`]).
    pub(crate) turns: Vec<[f64; 2]>,
    /// The joints' angles continued along the accepted steps of a run recording them
    /// ([`crate::joint_angles`]).
    pub(crate) joint_angles: crate::joint_angles::JointAngles,
    /// The curve elements' parameters at the synced bodies, eliminated from the equations of
    /// motion ([`crate::kkt`]'s `curves`).
    pub(crate) curves: CurveTrack,
    /// Generalized forces h (n).
    pub(crate) h: Vec<f64>,
    /// The user callback's generalized forces alone (n), for its power ([`crate::work`]).
    pub(crate) h_user: Vec<f64>,
    /// The first force element whose force or torque exceeded its limit (or was not finite) in
    /// the last [`Dynamics::eval_forces`], and that magnitude ([`Dynamics::check_forces`]).
    pub(crate) force_excess: Option<(usize, f64)>,
    /// The stops of the model's limits: which are held closed, their multipliers, the
    /// impacts so far ([`crate::contacts`]).
    pub(crate) contacts: crate::contacts::state::Contacts,
    /// The joints' friction ([`crate::friction`]).
    pub(crate) friction: crate::friction::state::FrictionState,
    /// Contact between the bodies' collision shapes ([`crate::collision`]).
    pub(crate) collisions: Option<crate::collision::Collisions>,
    /// Leave the contacts out of [`Dynamics::eval_forces`] (the finite differences of the
    /// implicit tangents, which take the contacts' tangents in closed form).
    pub(crate) contacts_off: bool,
    /// The joint-space outputs an inverse dynamics run records ([`crate::joint_space`]).
    pub(crate) joint_space: Option<crate::joint_space::history::JointSpaceWork>,
}

impl std::fmt::Debug for Dynamics<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Dynamics")
            .field("bodies", &self.mass.len())
            .field("forces", &self.forces)
            .field("user_forces", &self.user.is_some())
            .finish()
    }
}

impl<'m> Dynamics<'m> {
    /// The dynamics of `model` with the model's force elements.
    ///
    /// # Errors
    /// [`DynamicsError::MissingInertia`] if a body lacks mass or inertia;
    /// [`DynamicsError::BadForce`] for an invalid force element.
    pub fn new(model: &'m Model) -> Result<Self, DynamicsError> {
        if let Some(p) = model.paths().first() {
            return Err(DynamicsError::PathDriver {
                driver: p.name.clone(),
            });
        }
        let mut mass = Vec::new();
        let mut inertia = Vec::new();
        for b in model.bodies() {
            match (b.mass, b.inertia) {
                (Some(m), Some(j)) => {
                    mass.push(m);
                    inertia.push(j);
                }
                _ => {
                    return Err(DynamicsError::MissingInertia {
                        body: b.name.clone(),
                    })
                }
            }
        }
        let nb = model.num_bodies();
        let mut d = Self {
            model,
            mass,
            inertia,
            forces: Vec::new(),
            force_names: Vec::new(),
            user: None,
            elements: elements(model),
            kkt: None,
            redundant: Vec::new(),
            reselections: 0,
            bodies: vec![BodyState::ground(); nb],
            turns: model.initial_turns(),
            joint_angles: crate::joint_angles::JointAngles::new(model),
            curves: CurveTrack::new(model),
            h: vec![0.0; 6 * nb],
            h_user: vec![0.0; 6 * nb],
            force_excess: None,
            contacts: crate::contacts::state::Contacts::new(model),
            friction: crate::friction::state::FrictionState::new(model),
            collisions: None,
            contacts_off: false,
            joint_space: None,
        };
        let rest: Vec<BodyState> = (0..nb)
            .map(|k| {
                let b = &model.bodies()[k];
                BodyState::at(b.initial_r, b.initial_p)
            })
            .collect();
        d.collisions = crate::collision::Collisions::new(model, &rest)
            .map_err(|(shape, reason)| DynamicsError::BadShape { shape, reason })?;
        for f in Force::from_model(model) {
            d.add_force(f)?;
        }
        Ok(d)
    }

    /// Element `e`'s Φ_v blocks at the synced bodies (its reduced rows for a curve element).
    pub(crate) fn element_blocks(
        &self,
        e: &Element,
        t: f64,
        bi: &mut [[f64; 6]; 6],
        bj: &mut [[f64; 6]; 6],
    ) {
        element_blocks(self.model, e, &self.bodies, &self.curves, t, bi, bj);
    }

    /// The linearization about a motion and the sparse linearization do not take curve
    /// elements yet (their tangents are assembled from the model's rows, not the reduced rows of
    /// [`crate::kkt`]'s `curves`).
    pub(crate) fn refuse_curves(&self) -> Result<(), DynamicsError> {
        match self.model.curves().first() {
            Some(c) => Err(DynamicsError::CurveElement {
                what: c.element.what(),
                element: c.name.clone(),
            }),
            None => Ok(()),
        }
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// Adds a force element.
    ///
    /// # Errors
    /// [`DynamicsError::BadForce`] naming the element (unknown body, point or joint, negative
    /// coefficients, non-finite values).
    pub fn add_force(&mut self, force: Force) -> Result<&mut Self, DynamicsError> {
        let r = Resolved::resolve(self.model, &force)?;
        self.forces.push(r);
        self.force_names.push(force.name().to_string());
        self.kkt = None;
        Ok(self)
    }

    /// Sets the user force callback (see [`UserForces`]).
    pub fn set_user_forces(
        &mut self,
        f: impl FnMut(f64, &mut AppliedForces<'_>) + Send + 'static,
    ) -> &mut Self {
        self.user = Some(Box::new(f));
        self
    }

    /// Mass of body k.
    pub fn mass(&self, k: usize) -> f64 {
        self.mass[k]
    }

    /// Inertia of body k about its centre of mass (body frame).
    pub fn inertia(&self, k: usize) -> &Matrix3<f64> {
        &self.inertia[k]
    }

    /// The model's initial poses (not assembled), at rest, at t = 0: a rough guess for
    /// [`consistent_state`](Self::consistent_state).
    pub fn initial_guess(&self) -> State {
        State::initial(self.model, 0.0)
    }

    /// Equations dropped as redundant by the last preparation.
    pub fn redundant_equations(&self) -> &[EquationName] {
        &self.redundant
    }

    /// Accepts the synced bodies' poses for the couplers' turn counts (at each accepted step
    /// and projection). No allocation.
    pub(crate) fn accept_turns(&mut self) {
        self.model.accept_turns(&self.bodies, &mut self.turns);
        for f in &mut self.forces {
            f.accept_angle(self.model, &self.bodies);
        }
        self.joint_angles.accept(self.model, &self.bodies);
        if let Some(c) = &mut self.collisions {
            c.accept();
        }
    }

    /// Sets the bodies to `state` (and the curve elements' parameters to follow them).
    pub(crate) fn sync(&mut self, state: &State) {
        for (k, b) in self.bodies.iter_mut().enumerate() {
            *b = state.body_state(k);
        }
        if !self.curves.elements.is_empty() {
            self.curves.track(self.model, &self.bodies);
        }
    }

    /// Consistent initial conditions from a rough guess: positions by the mechanism's assembly
    /// (minimum-norm Newton, drivers included at `guess.t`), velocities by the least-change
    /// projection in the kinetic-energy metric,
    ///
    /// ```text
    /// v ← v + Δv,   ⎡M  Φ_vᵀ⎤ ⎡Δv⎤   ⎡     0     ⎤
    ///               ⎣Φ_v  0 ⎦ ⎣μ ⎦ = ⎣ν − Φ_v v  ⎦
    /// ```
    ///
    /// i.e. the consistent velocity closest to the guess in ‖·‖_M. Also decides once which
    /// redundant equations are dropped (rank analysis at the assembled poses).
    ///
    /// # Errors
    /// [`DynamicsError::InconsistentPositions`] naming the open joints and drivers;
    /// [`DynamicsError::InconsistentVelocities`] naming the violated velocity equations.
    pub fn consistent_state(&mut self, guess: &State) -> Result<State, DynamicsError> {
        let mut ws = self.model.workspace();
        for k in 0..self.model.num_bodies() {
            ws.set_pose(k, guess.r(k), guess.p(k));
        }
        match self.model.assemble(&mut ws, &AssemblyOptions::at(guess.t)) {
            Ok(_) => {}
            Err(AnalysisError::AssemblyFailed { open, .. }) => {
                return Err(DynamicsError::InconsistentPositions { open })
            }
            Err(e) => return Err(e.into()),
        }
        let mut state = self.adopt_assembly(&ws, guess.t, guess.v.clone());
        self.prepare(&state)?;
        self.project_velocities(&mut state)?;
        let (res, worst) = self.velocity_residual(&state);
        let scale = 1.0 + state.v.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if res > 1e-8 * scale {
            let equations = worst
                .into_iter()
                .filter(|&(_, r)| r > 1e-8 * scale)
                .filter_map(|(row, _)| self.model.equation(row))
                .collect();
            return Err(DynamicsError::InconsistentVelocities {
                residual: res,
                equations,
            });
        }
        Ok(state)
    }

    /// The state of an assembled workspace `ws` at time `t` with velocities `v`: its body poses
    /// (the curve parameters after them start the curve elements' tracking), its couplers'
    /// turns.
    pub(crate) fn adopt_assembly(
        &mut self,
        ws: &cardan_mechanism::Workspace,
        t: f64,
        v: Vec<f64>,
    ) -> State {
        let nq = 7 * self.model.num_bodies();
        self.turns.copy_from_slice(ws.turns());
        self.curves
            .start_from(self.model, self.model.extras_of(ws.state()));
        State {
            t,
            q: ws.state()[..nq].to_vec(),
            v,
        }
    }

    /// Lays out the KKT system at `state` (assumed assembled): rank analysis of Φ_v (all
    /// equations), redundant rows dropped once. Allocates; called by the entry points.
    ///
    /// # Errors
    /// Solver errors (non-finite Jacobian).
    pub fn prepare(&mut self, state: &State) -> Result<(), DynamicsError> {
        self.sync(state);
        if self.prepare_full_rank_fast(state) {
            return Ok(());
        }
        self.select_rows(state.t)
    }

    /// Chooses the independent rows again at the synced bodies and time `t`, for a mechanism
    /// with redundant equations whose kept rows lost rank where the full set has not (Bennett's
    /// linkage: the rows kept at the drawn pose are singular at two crank angles). Called when a
    /// factorization of the augmented system fails; `true` when the choice changed (the
    /// caller then solves again). The new rows are the best conditioned at this pose and are
    /// kept until they fail in turn, so the choice does not chatter. Allocates; rare.
    pub(crate) fn reselect(&mut self, t: f64) -> bool {
        if self.redundant.is_empty() {
            return false;
        }
        let Ok(active) = self.independent_rows(t) else {
            return false;
        };
        let Some(old) = self.kkt.as_ref() else {
            return false;
        };
        if old.active == active {
            // The same choice: the layout, its factorization and its counters stay.
            return false;
        }
        // The run's counter carries over to the new layout.
        let factorizations = old.factorizations;
        if self.lay_out(t, active).is_err() {
            return false;
        }
        let kkt = self.kkt.as_mut().expect("laid out");
        kkt.factorizations = factorizations;
        self.reselections += 1;
        true
    }

    /// Lays the KKT matrix out again when bodies touched for the first time since the last
    /// call (their pair joins the coupled blocks, [`crate::collision`]): `true` when it did
    /// (the caller's factorization and tangents are then of the old layout). Allocates; once
    /// per new pair of bodies in contact.
    ///
    /// # Errors
    /// The layout's failure.
    pub(crate) fn lay_out_new_contacts(&mut self, t: f64) -> Result<bool, DynamicsError> {
        let new = self
            .collisions
            .as_mut()
            .is_some_and(crate::collision::Collisions::take_new_pairs);
        let Some(old) = self.kkt.as_ref().filter(|_| new) else {
            return Ok(false);
        };
        let (active, factorizations) = (old.active.clone(), old.factorizations);
        self.lay_out(t, active)?;
        self.kkt.as_mut().expect("laid out").factorizations = factorizations;
        Ok(true)
    }

    /// How many times the independent rows were chosen again during the runs of this
    /// [`Dynamics`] (see [`prepare`](Self::prepare)).
    pub fn row_reselections(&self) -> usize {
        self.reselections
    }

    /// The rank analysis of Φ_v (all equations) at the synced bodies and time `t`, and the KKT
    /// layout on the independent rows.
    fn select_rows(&mut self, t: f64) -> Result<(), DynamicsError> {
        let active = self.independent_rows(t)?;
        self.lay_out(t, active)
    }

    /// The rank analysis of Φ_v (all equations) at the synced bodies and time `t`: the
    /// independent rows (the redundant ones are recorded in `self.redundant`).
    pub(crate) fn independent_rows(&mut self, t: f64) -> Result<Vec<usize>, DynamicsError> {
        let model = self.model;
        let m = model.num_equations();
        let n = 6 * model.num_bodies();
        let active: Vec<usize> = if m == 0 {
            Vec::new()
        } else {
            // Φ_v on its block pattern (two 6-column blocks per element row).
            let mut entries = Vec::new();
            let mut slots = Vec::new();
            let mut bi = [[0.0; 6]; 6];
            let mut bj = [[0.0; 6]; 6];
            for e in &self.elements {
                self.element_blocks(e, t, &mut bi, &mut bj);
                for (lr, r) in e.live_rows().enumerate() {
                    for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                        if let BodyId::Moving(k) = id {
                            for c in 0..6 {
                                entries.push((r, 6 * k + c));
                                slots.push(blk[lr][c]);
                            }
                        }
                    }
                }
            }
            let pattern =
                SparsityPattern::new(m, n, &entries).map_err(|e| self.solver_error(t, e))?;
            let ra = RankAnalysis::compute_auto(&pattern, &slots, RankOptions::default())
                .map_err(|e| self.solver_error(t, e))?;
            let eliminated = |r: usize| {
                self.elements
                    .iter()
                    .any(|e| r >= e.live_rows().end && r < e.rows.end)
            };
            self.redundant = ra
                .dependent_rows()
                .iter()
                .filter(|&&r| !eliminated(r))
                .filter_map(|&r| model.equation(r))
                .collect();
            ra.independent_rows().to_vec()
        };
        Ok(active)
    }

    /// The KKT layout on the rows `active`.
    fn lay_out(&mut self, t: f64, active: Vec<usize>) -> Result<(), DynamicsError> {
        let pairs = self.coupled_pairs();
        let kkt = Kkt::new(self.model, &self.elements, active, &pairs)
            .map_err(|e| self.solver_error(t, e))?;
        self.kkt = Some(kkt);
        Ok(())
    }

    /// Body pairs coupled by force elements (off-diagonal blocks of the iteration matrix),
    /// those in contact included.
    pub(crate) fn coupled_pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs = self.differenced_pairs();
        // Bodies in contact (the pairs that have touched so far).
        if let Some(c) = &self.collisions {
            pairs.extend_from_slice(&c.coupled);
        }
        pairs
    }

    /// The coupled pairs whose tangents are finite differences (all but the contacts').
    pub(crate) fn differenced_pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        for f in &self.forces {
            if let Some((BodyId::Moving(i), BodyId::Moving(j))) = f.coupled(self.model) {
                pairs.push((i, j));
            }
        }
        // Joint friction couples the joint's two bodies (its tangent in an implicit step).
        for f in self.model.frictions() {
            let info = &self.model.joints()[f.joint];
            if let (BodyId::Moving(i), BodyId::Moving(j)) = (info.body_i, info.body_j) {
                pairs.push((i, j));
            }
        }
        pairs
    }

    /// The fast path of [`prepare`](Self::prepare) for large models (at least
    /// [`cardan_mechanism::FAST_RANK_MIN_UNKNOWNS`] unknowns): lay out the KKT matrix with every
    /// equation active and factor it at `state`. [M Φ_vᵀ; Φ_v 0] with M positive definite is
    /// nonsingular exactly when Φ_v has full row rank, so when the sparse LU succeeds with
    /// acceptable pivots no equation is redundant and the dense rank-revealing QR of Φ_v
    /// (O(m n²) time, m × n dense memory: 28 GB at 10,000 bodies) is not needed. `false` (nothing
    /// changed) otherwise: the caller runs the rank analysis.
    fn prepare_full_rank_fast(&mut self, state: &State) -> bool {
        let model = self.model;
        let mut live: Vec<usize> = self.elements.iter().flat_map(Element::live_rows).collect();
        live.sort_unstable();
        let (m, n) = (live.len(), 6 * model.num_bodies());
        if n < cardan_mechanism::FAST_RANK_MIN_UNKNOWNS || m == 0 || m > n {
            return false;
        }
        let pairs = self.coupled_pairs();
        let Ok(mut kkt) = Kkt::new(model, &self.elements, live, &pairs) else {
            return false;
        };
        kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, state.t);
        kkt.set_mass(&self.mass, &self.inertia);
        if kkt.factor().is_err() {
            return false;
        }
        kkt.factorizations = 0;
        self.redundant = Vec::new();
        self.kkt = Some(kkt);
        true
    }

    pub(crate) fn solver_error(&self, time: f64, e: SolverError) -> DynamicsError {
        match e {
            SolverError::Singular {
                dependent_equations,
            } => {
                let n = 6 * self.model.num_bodies();
                let dependent = match &self.kkt {
                    Some(k) => dependent_equations
                        .iter()
                        .filter(|&&r| r >= n)
                        .filter_map(|&r| k.active.get(r - n))
                        .filter_map(|&row| self.model.equation(row))
                        .collect(),
                    None => Vec::new(),
                };
                DynamicsError::Singular { time, dependent }
            }
            SolverError::NonFinite { .. } => DynamicsError::NonFinite {
                time,
                what: "the equations of motion",
            },
            other => DynamicsError::Singular {
                time,
                dependent: vec![EquationName {
                    row: 0,
                    element: other.to_string(),
                    kind: "solver",
                    primitive: "solver",
                    local_row: 0,
                }],
            },
        }
    }

    /// [`Self::eval_forces`] for an implicit step's iterate: with joint friction, the friction
    /// from the iterate's multipliers (`friction.frozen`) too.
    pub(crate) fn eval_implicit_forces(&mut self, t: f64) {
        self.eval_forces(t);
        if !self.friction.hf.is_empty() {
            self.add_friction_frozen(t);
        }
    }

    /// h = [f; n' − ω̃' J' ω'] at the synced bodies, time t, into `self.h`. No allocation
    /// (unless the user callback allocates).
    pub(crate) fn eval_forces(&mut self, t: f64) {
        let model = self.model;
        let h = &mut self.h;
        h.fill(0.0);
        let mut acc = AppliedForces {
            h,
            bodies: &self.bodies,
        };
        self.force_excess = None;
        for (k, f) in self.forces.iter().enumerate() {
            let magnitude = f.apply(model, &self.mass, t, &mut acc);
            let within = magnitude <= f.quantity().limit(); // false for NaN
            if !within && self.force_excess.is_none() {
                self.force_excess = Some((k, magnitude));
            }
        }
        if let Some(u) = &mut self.user {
            u(t, &mut acc);
        }
        if !self.contacts.compliant.is_empty() {
            self.add_compliant_stops(t);
        }
        if let Some(c) = self.collisions.as_mut().filter(|_| !self.contacts_off) {
            let mut acc = AppliedForces {
                h: &mut self.h,
                bodies: &self.bodies,
            };
            c.apply(model, &mut acc);
        }
        for (k, b) in self.bodies.iter().enumerate() {
            let w = b.omega_local;
            let g = w.cross(&(self.inertia[k] * w));
            for c in 0..3 {
                self.h[6 * k + 3 + c] -= g[c];
            }
        }
    }

    /// Stops a run whose last force evaluation ([`Dynamics::eval_forces`], at time `t`) found
    /// an element's force or torque beyond the magnitude limit of a constant one
    /// ([`cardan_mechanism::Quantity::limit`]: 1e12 N, 1e12 N m) or not finite: a runaway
    /// expression or spring would otherwise drive the step size to nothing over millions of
    /// steps.
    ///
    /// # Errors
    /// [`DynamicsError::ForceLimit`] naming the element, the time and the value;
    /// [`DynamicsError::NonFinite`] for a force that is not finite.
    pub(crate) fn check_forces(&self, t: f64) -> Result<(), DynamicsError> {
        match self.force_excess {
            None => Ok(()),
            // A function undefined there: the front end names it (NonFinite's cause).
            Some((_, value)) if !value.is_finite() => Err(DynamicsError::NonFinite {
                time: t,
                what: "the forces",
            }),
            Some((k, value)) => {
                let q = self.forces[k].quantity();
                Err(DynamicsError::ForceLimit {
                    time: t,
                    force: self.force_names[k].clone(),
                    value,
                    limit: q.limit(),
                    unit: q.unit(),
                })
            }
        }
    }

    /// [`DynamicsError::CurveLost`] when a curve element's parameters were not found at the
    /// synced bodies; [`DynamicsError::CurveEnd`] when one has left its open curve's data (within
    /// a relative 1e-9 of the curve's length the end still counts).
    pub(crate) fn check_curves(&self, t: f64) -> Result<(), DynamicsError> {
        let curves = self.model.curves();
        if let Some((k, residual)) = self.curves.failed {
            return Err(DynamicsError::CurveLost {
                what: curves[k].element.what(),
                element: curves[k].name.clone(),
                time: t,
                residual,
            });
        }
        for (c, tr) in curves.iter().zip(&self.curves.elements) {
            let names = c.element.parameters().iter();
            for (e, (domain, parameter)) in c.element.domains().into_iter().zip(names).enumerate() {
                let Some((a, b)) = domain else {
                    continue;
                };
                let (slack, u) = (1e-9 * (b - a), tr.u[e]);
                if u < a - slack || u > b + slack {
                    let cam = matches!(c.element, cardan_mechanism::CurveElement::Cam(_));
                    return Err(DynamicsError::CurveEnd {
                        what: c.element.what(),
                        element: c.name.clone(),
                        contact: if cam { "contact point" } else { "point" },
                        parameter,
                        time: t,
                        u,
                        start: a,
                        end: b,
                    });
                }
            }
        }
        Ok(())
    }

    /// The generalized forces h = [f_k; n'_k − ω̃'_k J'_k ω'_k] (6 per body) at `state`.
    pub fn generalized_forces(&mut self, state: &State, out: &mut [f64]) {
        self.sync(state);
        self.eval_forces(state.t);
        out.copy_from_slice(&self.h);
    }

    /// Solves the equations of motion at the synced bodies: fills `kkt.sol` = [v̇; λ_active].
    /// `baumgarte` (α, β) adds −2α(Φ_v v − ν) − β²Φ to γ#; `refine`: when a Schur solve is
    /// refined. No allocation.
    pub(crate) fn solve_eom(
        &mut self,
        t: f64,
        baumgarte: Baumgarte,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        self.eval_forces(t);
        self.check_forces(t)?;
        self.check_curves(t)?;
        let model = self.model;
        let kkt = self.kkt.as_mut().expect("prepared");
        kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, t);
        kkt.set_mass(&self.mass, &self.inertia);
        let n = kkt.n;
        eval_rows(
            model,
            &self.elements,
            &self.bodies,
            &self.turns,
            &self.curves,
            t,
            Rhs::Gamma,
            &mut kkt.full,
        );
        for (a, &r) in kkt.active.iter().enumerate() {
            kkt.rhs[n + a] = kkt.full[r];
        }
        let Baumgarte { alpha, beta } = baumgarte;
        if alpha != 0.0 || beta != 0.0 {
            let mut wn = std::mem::take(&mut kkt.work_n);
            let mut wa = std::mem::take(&mut kkt.work_a);
            for (k, b) in self.bodies.iter().enumerate() {
                for c in 0..3 {
                    wn[6 * k + c] = b.r_dot[c];
                    wn[6 * k + 3 + c] = b.omega_local[c];
                }
            }
            kkt.phi_v_mul(&wn, &mut wa);
            eval_rows(
                model,
                &self.elements,
                &self.bodies,
                &self.turns,
                &self.curves,
                t,
                Rhs::Nu,
                &mut kkt.full,
            );
            for (a, &r) in kkt.active.iter().enumerate() {
                kkt.rhs[n + a] -= 2.0 * alpha * (wa[a] - kkt.full[r]);
            }
            eval_rows(
                model,
                &self.elements,
                &self.bodies,
                &self.turns,
                &self.curves,
                t,
                Rhs::Phi,
                &mut kkt.full,
            );
            for (a, &r) in kkt.active.iter().enumerate() {
                kkt.rhs[n + a] -= beta * beta * kkt.full[r];
            }
            kkt.work_n = wn;
            kkt.work_a = wa;
        }
        kkt.rhs[..n].copy_from_slice(&self.h);
        let friction = !self.friction.hf.is_empty();
        if friction {
            self.friction.rhs0.clone_from(&kkt.rhs);
        }
        let r = kkt.factor().and_then(|_| kkt.solve(refine));
        match r {
            Err(SolverError::Singular { .. }) if self.reselect(t) => {
                self.solve_eom(t, baumgarte, refine)
            }
            Err(e) => Err(self.solver_error(t, e)),
            Ok(()) if self.contacts.any_held() || friction => {
                if self.contacts.any_held() {
                    self.add_held_stops(t, refine)?;
                }
                if friction {
                    self.solve_friction(t, refine)?;
                }
                Ok(())
            }
            Ok(()) => Ok(()),
        }
    }

    /// Accelerations v̇ (6 per body) and multipliers λ (one per model equation; 0 for rows
    /// dropped as redundant) at `state`: the augmented system
    /// [M Φ_vᵀ; Φ_v 0][v̇; λ] = [h; γ#]. Prepares the layout at the first call. No allocation
    /// after that.
    ///
    /// # Errors
    /// [`DynamicsError::Singular`] at a singular configuration.
    pub fn accelerations(
        &mut self,
        state: &State,
        vdot: &mut [f64],
        lambda: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.accelerations_refined(state, vdot, lambda, SchurRefinement::ONE_SHOT)
    }

    /// [`accelerations`](Self::accelerations) with the Schur refinement of the caller's
    /// configuration (an integrator's).
    pub(crate) fn accelerations_refined(
        &mut self,
        state: &State,
        vdot: &mut [f64],
        lambda: &mut [f64],
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        self.sync(state);
        self.solve_eom(state.t, Baumgarte::NONE, refine)?;
        self.read_solution(vdot, lambda);
        Ok(())
    }

    /// Copies v̇ and the full-row λ out of the last KKT solution.
    pub(crate) fn read_solution(&self, vdot: &mut [f64], lambda: &mut [f64]) {
        let kkt = self.kkt.as_ref().expect("prepared");
        let n = kkt.n;
        vdot.copy_from_slice(&kkt.sol[..n]);
        lambda.fill(0.0);
        for (a, &r) in kkt.active.iter().enumerate() {
            lambda[r] = kkt.sol[n + a];
        }
    }

    /// Least-change velocity projection onto Φ_v v = ν in the metric of M (module docs of
    /// [`consistent_state`](Self::consistent_state)). No allocation.
    ///
    /// # Errors
    /// [`DynamicsError::Singular`].
    pub fn project_velocities(&mut self, state: &mut State) -> Result<(), DynamicsError> {
        self.project_velocities_refined(state, SchurRefinement::ONE_SHOT)
    }

    /// [`project_velocities`](Self::project_velocities) with the Schur refinement of the
    /// caller's configuration (an integrator's).
    pub(crate) fn project_velocities_refined(
        &mut self,
        state: &mut State,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        self.sync(state);
        let model = self.model;
        let t = state.t;
        let kkt = self.kkt.as_mut().expect("prepared");
        kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, t);
        kkt.set_mass(&self.mass, &self.inertia);
        let n = kkt.n;
        let mut wa = std::mem::take(&mut kkt.work_a);
        kkt.phi_v_mul(&state.v, &mut wa);
        eval_rows(
            model,
            &self.elements,
            &self.bodies,
            &self.turns,
            &self.curves,
            t,
            Rhs::Nu,
            &mut kkt.full,
        );
        kkt.rhs[..n].fill(0.0);
        for (a, &r) in kkt.active.iter().enumerate() {
            kkt.rhs[n + a] = kkt.full[r] - wa[a];
        }
        kkt.work_a = wa;
        let r = kkt.factor().and_then(|_| kkt.solve(refine));
        match r {
            Err(SolverError::Singular { .. }) if self.reselect(t) => {
                return self.project_velocities_refined(state, refine)
            }
            Err(e) => return Err(self.solver_error(t, e)),
            Ok(()) => {}
        }
        let kkt = self.kkt.as_ref().expect("prepared");
        for c in 0..n {
            state.v[c] += kkt.sol[c];
        }
        Ok(())
    }

    /// Position projection onto Φ(q, t) = 0: Newton with the least-change step in the metric
    /// of M, [M Φ_vᵀ; Φ_v 0][Δ; μ] = [0; −Φ], applied as r += Δr, p ← p ⊗ exp(Δπ'/2).
    /// Returns the iterations. No allocation.
    ///
    /// # Errors
    /// [`DynamicsError::NotConverged`] after 20 iterations; [`DynamicsError::Singular`].
    pub fn project_positions(
        &mut self,
        state: &mut State,
        tol: f64,
    ) -> Result<usize, DynamicsError> {
        self.project_positions_refined(state, tol, SchurRefinement::ONE_SHOT)
    }

    /// [`project_positions`](Self::project_positions) with the Schur refinement of the caller's
    /// configuration (an integrator's).
    pub(crate) fn project_positions_refined(
        &mut self,
        state: &mut State,
        tol: f64,
        refine: SchurRefinement,
    ) -> Result<usize, DynamicsError> {
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        let model = self.model;
        let t = state.t;
        let scales = model.equation_scales();
        let mut last = 0.0;
        let mut polish = 0;
        for it in 0..20 {
            self.sync(state);
            let kkt = self.kkt.as_mut().expect("prepared");
            eval_rows(
                model,
                &self.elements,
                &self.bodies,
                &self.turns,
                &self.curves,
                t,
                Rhs::Phi,
                &mut kkt.full,
            );
            let res = kkt
                .active
                .iter()
                .map(|&r| (kkt.full[r] / scales[r]).abs())
                .fold(0.0f64, f64::max);
            last = res;
            if !res.is_finite() {
                return Err(DynamicsError::NonFinite {
                    time: t,
                    what: "the constraint residual",
                });
            }
            if res <= tol {
                // The kept rows are satisfied; the dropped ones must be too. On the full set's
                // manifold they follow the kept rows up to the kept rows' conditioning, so a
                // Newton step or two more brings them in. If they stay off, Newton has landed on
                // a branch of the kept rows' solution set that the full set does not have (it
                // branches where the kept rows lose rank: Bennett's linkage with fixed DOPRI5
                // steps through such a point): choose the rows again and go on projecting.
                let dropped = dropped_residual(&kkt.active, &kkt.full, scales);
                if dropped <= tol {
                    self.accept_turns();
                    return Ok(it);
                }
                if polish == POLISH_STEPS {
                    if dropped > DROPPED_ROW_FACTOR * tol && self.reselect(t) {
                        polish = 0;
                        continue;
                    }
                    self.accept_turns();
                    return Ok(it);
                }
                polish += 1;
            }
            kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, t);
            kkt.set_mass(&self.mass, &self.inertia);
            let n = kkt.n;
            kkt.rhs[..n].fill(0.0);
            for (a, &r) in kkt.active.iter().enumerate() {
                kkt.rhs[n + a] = -kkt.full[r];
            }
            let r = kkt.factor().and_then(|_| kkt.solve(refine));
            match r {
                Err(SolverError::Singular { .. }) if self.reselect(t) => continue,
                Err(e) => return Err(self.solver_error(t, e)),
                Ok(()) => {}
            }
            let kkt = self.kkt.as_ref().expect("prepared");
            cardan_mechanism::apply_rotation_step(&mut state.q, &kkt.sol[..n]);
        }
        Err(DynamicsError::NotConverged {
            time: t,
            what: "position projection",
            iterations: 20,
            residual: last,
        })
    }

    /// max |Φ_v v − ν| over all equations (redundant ones included) and the per-row values.
    pub(crate) fn velocity_residual(&mut self, state: &State) -> (f64, Vec<(usize, f64)>) {
        self.sync(state);
        let model = self.model;
        let m = model.num_equations();
        let mut nu = vec![0.0; m];
        eval_rows(
            model,
            &self.elements,
            &self.bodies,
            &self.turns,
            &self.curves,
            state.t,
            Rhs::Nu,
            &mut nu,
        );
        let mut res = vec![0.0; m];
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        for e in &self.elements {
            self.element_blocks(e, state.t, &mut bi, &mut bj);
            for (lr, r) in e.rows.clone().enumerate() {
                let mut s = -nu[r];
                for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                    if let BodyId::Moving(k) = id {
                        for c in 0..6 {
                            s += blk[lr][c] * state.v[6 * k + c];
                        }
                    }
                }
                res[r] = s;
            }
        }
        let max = res.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        (max, res.into_iter().map(f64::abs).enumerate().collect())
    }

    /// Energy at `state`.
    pub fn energy(&mut self, state: &State) -> Energy {
        self.sync(state);
        let mut e = Energy::default();
        for (k, b) in self.bodies.iter().enumerate() {
            let w = b.omega_local;
            e.kinetic +=
                0.5 * self.mass[k] * b.r_dot.norm_squared() + 0.5 * w.dot(&(self.inertia[k] * w));
        }
        for f in &self.forces {
            let (g, s) = f.potential(self.model, &self.mass, &self.bodies);
            e.gravity += g;
            e.spring += s;
        }
        e
    }

    /// Reactions of element `e` (joint index, or joints.len() + driver index) on its bodies i
    /// and j at the synced bodies, from the full-row λ, about the points `pi`, `pj` (body
    /// frames).
    pub(crate) fn element_reaction(
        &self,
        e: &Element,
        t: f64,
        lambda: &[f64],
        pi: &Vector3<f64>,
        pj: &Vector3<f64>,
    ) -> (Reaction, Reaction) {
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        self.element_blocks(e, t, &mut bi, &mut bj);
        let g = BodyState::ground();
        let one = |id: BodyId, blk: &[[f64; 6]; 6], s: &Vector3<f64>| {
            let mut f = Vector3::zeros();
            let mut nl = Vector3::zeros();
            for (lr, r) in e.rows.clone().enumerate() {
                for c in 0..3 {
                    f[c] -= blk[lr][c] * lambda[r];
                    nl[c] -= blk[lr][3 + c] * lambda[r];
                }
            }
            let a = match id {
                BodyId::Ground => g.a,
                BodyId::Moving(k) => self.bodies[k].a,
            };
            let fl = a.tr_mul(&f);
            let tl = nl - s.cross(&fl);
            Reaction {
                force: f,
                torque: a * tl,
                force_local: fl,
                torque_local: tl,
            }
        };
        (one(e.bi, &bi, pi), one(e.bj, &bj, pj))
    }

    /// The reactions of joint `joint` (index into [`Model::joints`]) at `state` with full-row
    /// multipliers `lambda`: (on body i at marker point P_i, on body j at P_j). The generalized
    /// reaction force is −Φ_vᵀλ; F = −(Φ_r)ᵀλ and the body-frame torque about the centre of
    /// mass n' = −(Φ_π')ᵀλ, shifted to the joint point: n'_P = n' − s̃'^P F'.
    pub fn joint_reaction(
        &mut self,
        state: &State,
        lambda: &[f64],
        joint: usize,
    ) -> (Reaction, Reaction) {
        self.sync(state);
        let j = &self.model.joints()[joint];
        let (pi, pj) = (j.joint.marker_i().point, j.joint.marker_j().point);
        let e = self.elements[joint].clone();
        self.element_reaction(&e, state.t, lambda, &pi, &pj)
    }
}

/// Newton steps a projection takes beyond the kept rows' convergence for dropped (redundant)
/// rows that are still off by more than the tolerance.
const POLISH_STEPS: usize = 2;

/// A projection whose dropped rows are still off by more than this multiple of the tolerance
/// after [`POLISH_STEPS`] has landed on a branch of the kept rows that the full set does not
/// have, or the kept rows are nearly singular there: reason enough to choose them again.
const DROPPED_ROW_FACTOR: f64 = 1e2;

/// max |Φ_r / scale_r| over the rows not in `active` (sorted); 0 without redundant rows.
fn dropped_residual(active: &[usize], phi: &[f64], scales: &[f64]) -> f64 {
    if active.len() == phi.len() {
        return 0.0;
    }
    let mut kept = active.iter().peekable();
    let mut worst = 0.0f64;
    for (r, (&v, &s)) in phi.iter().zip(scales).enumerate() {
        if kept.peek() == Some(&&r) {
            kept.next();
        } else {
            worst = worst.max((v / s).abs());
        }
    }
    worst
}
