//! Storing results at output times: poses, velocities, accelerations, points, joint
//! coordinates, λ, reactions, driver efforts, energy and drift. Storage is reserved up front;
//! each record allocates only the λ vector of that time. A streamed recorder
//! ([`Recorder::streamed`]) holds one time, hands it to a [`DynamicSink`] and reuses its storage
//! (λ included) for the next: it allocates nothing per time.

mod histories;

use crate::kkt::{eval_rows, Rhs, SchurRefinement};
use crate::results::{DriverEfforts, DynamicResults, DynamicSink, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::work::{Multipliers, SampledWork};
use crate::DynamicsError;
use cardan_constraints::joints::{
    continue_angle, BodyAcceleration, CoordinateQuantity, MAX_COORDINATES,
};
use cardan_constraints::{BodyPair, BodyState, Driver};
use cardan_eulerparam::{p_ddot_from_local, p_dot_from_local};
use cardan_mechanism::{BodyId, Model, Outputs};
use histories::{driver_points, empty_results, BodyPoint};
use nalgebra::Vector3;

/// Records a run's output times (module docs).
pub(crate) struct Recorder<'s> {
    /// The stored times (streamed: the one being handed to the sink).
    res: DynamicResults,
    /// Where a streamed run's times go; `None`: every time stays in `res`.
    sink: Option<&'s mut dyn DynamicSink>,
    /// Times recorded.
    frames: usize,
    /// The time recorded last.
    last_t: Option<f64>,
    /// Per joint: its coordinates and their rates at the time recorded last (angles continue
    /// from them over turns).
    last_joint: Vec<JointCoordinates>,
    /// A streamed recorder's λ vector, reused from one time to the next.
    spare_lambda: Option<Vec<f64>>,
    outputs: Outputs,
    vdot: Vec<f64>,
    lambda: Vec<f64>,
    phi: Vec<f64>,
    /// Every named point of a moving body.
    points: Vec<BodyPoint>,
    /// The power of each work channel at the time being recorded ([`crate::work`]).
    power: Vec<f64>,
    /// The work of each channel, when the recorder integrates it itself (inverse dynamics).
    work: Vec<f64>,
    /// The work integrated from the recorded powers (inverse dynamics).
    sampled: SampledWork,
    /// Per row: the worst scaled residual while dropped as redundant and off by more than the
    /// kept rows explain ([`DROPPED_ROW_DRIFT_FACTOR`]).
    dropped: Vec<DroppedRow>,
}

/// A joint's coordinates and their rates at one time.
#[derive(Debug, Clone, Copy)]
struct JointCoordinates {
    values: [f64; MAX_COORDINATES],
    rates: [f64; MAX_COORDINATES],
}

/// The worst scaled residual of a row while dropped as redundant, its value and time (NaN:
/// never off).
#[derive(Debug, Clone, Copy)]
struct DroppedRow {
    worst: f64,
    value: f64,
    time: f64,
}

/// A row dropped as redundant is reported when its scaled residual at an output time exceeds
/// both the position tolerance and this multiple of the kept rows' largest scaled residual
/// there: it is then off by more than the drift the kept rows share (the model's redundant
/// joints disagree; `cardan_mechanism::analysis::dropped`).
pub const DROPPED_ROW_DRIFT_FACTOR: f64 = 10.0;

impl<'s> Recorder<'s> {
    /// A recorder keeping every time (room reserved for `capacity` times).
    pub fn new(d: &Dynamics, capacity: usize, outputs: Outputs) -> Self {
        Self::with_sink(d, capacity, outputs, None)
    }

    /// A recorder handing each time to `sink` as it is recorded, keeping none.
    pub fn streamed(d: &Dynamics, outputs: Outputs, sink: &'s mut dyn DynamicSink) -> Self {
        Self::with_sink(d, 1, outputs, Some(sink))
    }

    fn with_sink(
        d: &Dynamics,
        capacity: usize,
        outputs: Outputs,
        sink: Option<&'s mut dyn DynamicSink>,
    ) -> Self {
        let model = d.model;
        let (res, points) = empty_results(d, capacity, outputs);
        let n = 6 * model.num_bodies();
        let m = model.num_equations();
        let zero = JointCoordinates {
            values: [0.0; MAX_COORDINATES],
            rates: [0.0; MAX_COORDINATES],
        };
        let never = DroppedRow {
            worst: 0.0,
            value: 0.0,
            time: f64::NAN,
        };
        Self {
            res,
            sink,
            frames: 0,
            last_t: None,
            last_joint: vec![zero; model.joints().len()],
            spare_lambda: None,
            outputs,
            vdot: vec![0.0; n],
            lambda: vec![0.0; m],
            phi: vec![0.0; m],
            points,
            power: vec![0.0; d.num_work_channels()],
            work: vec![0.0; d.num_work_channels()],
            sampled: SampledWork::new(d.num_work_channels()),
            dropped: vec![never; m],
        }
    }

    /// Records `state` (solving the equations of motion there for v̇ and λ). `work`: the
    /// integrator's work of each channel at this time ([`crate::work`]); `None`: the recorder
    /// integrates the power over the stored times (inverse dynamics, [`SampledWork`]).
    /// `refine`: the Schur refinement of the solve (the integrator's).
    pub fn record(
        &mut self,
        d: &mut Dynamics,
        state: &State,
        iterations: usize,
        work: Option<&[f64]>,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        d.accelerations_refined(state, &mut self.vdot, &mut self.lambda, refine)?;
        d.record_stops(state.t);
        d.record_friction(state.t);
        self.begin();
        self.record_work(d, state.t, work);
        self.store(d, state, iterations, false);
        let solved = (&self.lambda[..], &self.vdot[..]);
        d.record_joint_space(state.t, solved, &mut self.res.joint_space)?;
        self.hand_over(state.t)
    }

    /// A streamed recorder empties its one time before the next (keeping λ's storage).
    fn begin(&mut self) {
        if self.sink.is_some() {
            self.spare_lambda = self.res.lambda.pop();
            self.res.clear_frames();
        }
    }

    /// Counts the time just stored and hands it to the sink, if any.
    ///
    /// # Errors
    /// [`DynamicsError::Stopped`] when the sink breaks.
    fn hand_over(&mut self, t: f64) -> Result<(), DynamicsError> {
        let k = self.frames;
        self.frames += 1;
        self.last_t = Some(t);
        let stop = (self.sink.as_mut()).is_some_and(|sink| sink.frame(k, &self.res).is_break());
        match stop {
            true => Err(DynamicsError::Stopped { time: t }),
            false => Ok(()),
        }
    }

    /// Records a static equilibrium `state` (velocities zero) with its multipliers `lambda`
    /// (full rows): accelerations zero, velocity drift 0 (no velocities in statics).
    pub fn record_static(
        &mut self,
        d: &mut Dynamics,
        state: &State,
        lambda: &[f64],
        iterations: usize,
    ) {
        d.sync(state);
        if d.collisions.is_some() {
            // The contacts at the equilibrium (the last evaluation may have been a trial).
            d.eval_static_forces(state.t, 1.0);
        }
        self.vdot.fill(0.0);
        self.lambda.copy_from_slice(lambda);
        self.begin();
        self.record_work(d, state.t, None);
        self.store(d, state, iterations, true);
        // Statics keeps every time: no sink to stop it.
        let _ = self.hand_over(state.t);
    }

    /// Stores `state` with `self.vdot` and `self.lambda` at the synced bodies.
    fn store(&mut self, d: &mut Dynamics, state: &State, iterations: usize, is_static: bool) {
        self.store_residual(d, state.t, iterations);
        self.store_motion(d);
        self.store_joints(d, state.t);
        let lambda = match self.spare_lambda.take() {
            Some(mut l) => {
                l.copy_from_slice(&self.lambda);
                l
            }
            None => self.lambda.clone(),
        };
        self.res.lambda.push(lambda);
        self.store_joint_reactions(d, state.t);
        self.store_driver_efforts(d, state.t);
        self.store_coupler_efforts(d, state.t);
        self.store_curves(d, state.t);
        if let Some(c) = &d.collisions {
            let t = state.t;
            (self.res.contacts.points).extend(c.points.iter().map(|p| (t, *p)));
        }
        let g = BodyState::ground();
        let st = |id: BodyId| match id {
            BodyId::Ground => &g,
            BodyId::Moving(k) => &d.bodies[k],
        };
        pose_torques(&mut self.res.drivers, d.model, st);
        let en = d.energy(state);
        self.res.energy.kinetic.push(en.kinetic);
        self.res.energy.gravity.push(en.gravity);
        self.res.energy.spring.push(en.spring);
        self.res.energy.total.push(en.total());
        let vd = if is_static {
            0.0
        } else {
            d.velocity_residual(state).0
        };
        self.res.velocity_drift.push(vd);
    }

    /// The time, the iterations, max |Φ| (the position drift) and the dropped rows' residuals.
    fn store_residual(&mut self, d: &Dynamics, t: f64, iterations: usize) {
        let model = d.model;
        let kin = &mut self.res.kinematics;
        kin.times.push(t);
        kin.iterations.push(iterations);
        eval_rows(
            model,
            &d.elements,
            &d.bodies,
            &d.turns,
            &d.curves,
            t,
            Rhs::Phi,
            &mut self.phi,
        );
        let res = self.phi.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        kin.residual.push(res);
        self.res.position_drift.push(res);
        if let Some(kkt) = d.kkt.as_ref() {
            record_dropped_rows(model, &kkt.active, &self.phi, t, &mut self.dropped);
        }
    }

    /// The bodies' poses (and rates and accelerations, when asked) and the named points'.
    fn store_motion(&mut self, d: &Dynamics) {
        let vel = self.outputs.needs_velocity();
        let acc = self.outputs.acceleration;
        let kin = &mut self.res.kinematics;
        for (k, b) in kin.bodies.iter_mut().enumerate() {
            let s = &d.bodies[k];
            let wd = Vector3::from_column_slice(&self.vdot[6 * k + 3..6 * k + 6]);
            b.r.push(s.r);
            b.p.push(s.p);
            if vel {
                b.r_dot.push(s.r_dot);
                b.p_dot.push(p_dot_from_local(&s.p, &s.omega_local));
                b.omega.push(s.a * s.omega_local);
                b.omega_local.push(s.omega_local);
            }
            if acc {
                b.r_ddot
                    .push(Vector3::from_column_slice(&self.vdot[6 * k..6 * k + 3]));
                b.p_ddot.push(p_ddot_from_local(&s.p, &s.omega_local, &wd));
                b.omega_dot.push(s.a * wd);
                b.omega_dot_local.push(wd);
            }
        }
        for (pr, pt) in kin.points.iter_mut().zip(&self.points) {
            let (k, sl) = (pt.body, &pt.local);
            let s = &d.bodies[k];
            pr.position.push(s.point(sl));
            let w = s.omega_local;
            if vel {
                pr.velocity.push(s.r_dot + s.a * w.cross(sl));
            }
            if acc {
                let rdd = Vector3::from_column_slice(&self.vdot[6 * k..6 * k + 3]);
                let wd = Vector3::from_column_slice(&self.vdot[6 * k + 3..6 * k + 6]);
                pr.acceleration
                    .push(rdd + s.a * (wd.cross(sl) + w.cross(&w.cross(sl))));
            }
        }
    }

    /// The joint coordinates at time `t` (rates and accelerations when asked), angles
    /// continued over turns along a dynamic run's steps, or from the time recorded last.
    fn store_joints(&mut self, d: &Dynamics, t: f64) {
        let vel = self.outputs.needs_velocity();
        let acc = self.outputs.acceleration;
        let g = BodyState::ground();
        let st = |id: BodyId| match id {
            BodyId::Ground => &g,
            BodyId::Moving(k) => &d.bodies[k],
        };
        let dt = self.last_t.map_or(0.0, |t0| t - t0);
        let vdot = &self.vdot;
        let body_acc = |id: BodyId| match id {
            BodyId::Moving(k) if acc => BodyAcceleration {
                r_ddot: Vector3::from_column_slice(&vdot[6 * k..6 * k + 3]),
                omega_dot_local: Vector3::from_column_slice(&vdot[6 * k + 3..6 * k + 6]),
            },
            _ => BodyAcceleration::default(),
        };
        let continued = self.last_t.is_some();
        for (index, ((jr, j), last)) in (self.res.kinematics.joints.iter_mut())
            .zip(d.model.joints())
            .zip(&mut self.last_joint)
            .enumerate()
        {
            let pair = BodyPair::new(st(j.body_i), st(j.body_j));
            let mut c = j.joint.coordinates(&pair);
            let rates = vel.then(|| {
                j.joint
                    .coordinate_rates(&pair, &body_acc(j.body_i), &body_acc(j.body_j))
            });
            let (prev, prev_rates) = (last.values, last.rates);
            for (i, coord) in c.coordinates.iter().enumerate() {
                if coord.measure.quantity() != CoordinateQuantity::Angle {
                    continue;
                }
                // Along a dynamic run's steps ([`crate::joint_angles`]); else (inverse
                // dynamics, statics) from the time recorded last.
                if let Some(v) = d.joint_angles.continued(index, i, c.values[i]) {
                    c.values[i] = v;
                } else if continued {
                    let w = rates.as_ref().map(|r| (prev_rates[i], r.rates[i]));
                    c.values[i] = continue_angle(prev[i], w, dt, c.values[i]);
                }
            }
            last.values = c.values;
            jr.values.push(c.values);
            if let Some(r) = rates {
                last.rates = r.rates;
                jr.rates.push(r.rates);
                if acc {
                    jr.accelerations.push(r.accelerations);
                }
            }
        }
    }

    /// Each joint's reactions on its two bodies from `self.lambda`.
    fn store_joint_reactions(&mut self, d: &Dynamics, t: f64) {
        for (ji, (jr, j)) in self
            .res
            .reactions
            .iter_mut()
            .zip(d.model.joints())
            .enumerate()
        {
            let e = &d.elements[ji];
            let (ri, rj) = d.element_reaction(
                e,
                t,
                &self.lambda,
                &j.joint.marker_i().point,
                &j.joint.marker_j().point,
            );
            jr.on_i.push(ri);
            jr.on_j.push(rj);
        }
    }

    /// Each driver's multiplier, effort along its driven coordinate, power and reactions
    /// (ν into `self.phi`).
    fn store_driver_efforts(&mut self, d: &Dynamics, t: f64) {
        let model = d.model;
        let nj = model.joints().len();
        eval_rows(
            model,
            &d.elements,
            &d.bodies,
            &d.turns,
            &d.curves,
            t,
            Rhs::Nu,
            &mut self.phi,
        );
        for (di, (de, dr)) in self.res.drivers.iter_mut().zip(model.drivers()).enumerate() {
            let e = &d.elements[nj + di];
            let (pi, pj) = driver_points(model, dr);
            let (ri, rj) = d.element_reaction(e, t, &self.lambda, &pi, &pj);
            let row = dr.rows.start;
            let l = self.lambda[row];
            de.lambda.push(l);
            // −λ ∂Φ/∂c: the force or torque along the driven coordinate (the distance
            // driver's row dᵀd − ℓ² grows by 2ℓ per metre). Its power −λ ν is effort × ċ.
            de.effort.push(-l * dr.driver.coordinate_slope(t));
            de.power.push(-l * self.phi[row]);
            de.reactions.on_i.push(ri);
            de.reactions.on_j.push(rj);
        }
    }

    /// Each coupler's multiplier, efforts on its two coordinates, tooth or thread force and
    /// reactions.
    fn store_coupler_efforts(&mut self, d: &Dynamics, t: f64) {
        let model = d.model;
        let nj = model.joints().len();
        let nd = model.drivers().len();
        for (k, (ce, c)) in self
            .res
            .couplers
            .iter_mut()
            .zip(model.couplers())
            .enumerate()
        {
            let (pi, pj) = c.coupler.points();
            let (ri, rj) = d.element_reaction(&d.elements[nj + nd + k], t, &self.lambda, &pi, &pj);
            ce.reactions.on_i.push(ri);
            ce.reactions.on_j.push(rj);
            let l = self.lambda[c.rows.start];
            let q = [-l * c.coefficients[0], -l * c.coefficients[1]];
            ce.lambda.push(l);
            ce.efforts.push(q);
            if let Some(f) = ce.force.as_mut() {
                f.push(match c.gear_radius_j {
                    Some(rj) => q[1] / rj,
                    None => q[0],
                });
            }
        }
    }

    /// Each curve element's parameters (rates and accelerations when asked), and each cam
    /// pair's contact point, pressure angle and contact force on its follower (from its reduced
    /// rows' multipliers in `self.lambda`).
    fn store_curves(&mut self, d: &Dynamics, t: f64) {
        let model = d.model;
        let vel = self.outputs.needs_velocity();
        let acc = self.outputs.acceleration;
        let g = BodyState::ground();
        let st = |id: BodyId| match id {
            BodyId::Ground => &g,
            BodyId::Moving(k) => &d.bodies[k],
        };
        let first = model.joints().len() + model.drivers().len() + model.couplers().len();
        let mut cams = self.res.cams.iter_mut();
        for (k, c) in model.curves().iter().enumerate() {
            let tr = &d.curves.elements[k];
            let udd = acc.then(|| d.curves.accelerations(model, k, &d.bodies, &self.vdot));
            for (e, x) in c.extras().enumerate() {
                let h = &mut self.res.kinematics.curves[x];
                h.u.push(tr.u[e]);
                if vel {
                    h.u_dot.push(tr.u_dot[e]);
                }
                if let Some(a) = udd {
                    h.u_ddot.push(a[e]);
                }
            }
            let (si, sj) = (st(c.body_i), st(c.body_j));
            let n = c.extras().len();
            let Some((point, normal, local)) = c.element.contact(si, sj, &tr.u[..n]) else {
                continue;
            };
            let h = &mut self.res.kinematics.curves[c.extra];
            h.contact.push(point);
            if vel {
                let (vj, aj) = point_motion(sj, c.body_j, &local, &self.vdot);
                let local_i = si.a.tr_mul(&(point - si.r));
                let vi = point_motion(si, c.body_i, &local_i, &self.vdot).0;
                let scale = vi.norm().max(vj.norm());
                let a = acc.then_some(&aj);
                let angle = cardan_mechanism::CurveElement::pressure_angle(&normal, &vj, a, scale)
                    .or_else(|| h.pressure_angle.last().copied())
                    .unwrap_or(0.0);
                h.pressure_angle.push(angle);
            }
            let e = &d.elements[first + k];
            let (_, on_j) = d.element_reaction(e, t, &self.lambda, &Vector3::zeros(), &local);
            let push = c.element.push_direction(si, sj, &tr.u[..n]);
            let cam = cams.next().expect("one history per cam pair");
            cam.force.push(on_j.force);
            cam.normal_force
                .push(push.map_or(f64::NAN, |p| on_j.force.dot(&p)));
        }
    }

    /// The power and work of each channel and the constraints' power at the synced bodies
    /// (after the solve of [`record`](Self::record), with its λ).
    fn record_work(&mut self, d: &mut Dynamics, t: f64, work: Option<&[f64]>) {
        d.powers(t, Multipliers::Full(&self.lambda), &mut self.power);
        let en = &mut self.res.energy;
        en.constraint_power
            .push(d.constraint_power(t, &self.lambda));
        match work {
            Some(w) => self.work.copy_from_slice(w),
            None => {
                let h = self.last_t.map_or(0.0, |t0| t - t0);
                self.sampled.add(h, &self.power, &mut self.work);
            }
        }
        for ((c, &p), &w) in en.elements.iter_mut().zip(&self.power).zip(&self.work) {
            c.power.push(p);
            c.work.push(w);
        }
        en.work.push(self.work.iter().sum());
    }

    /// The power of each work channel at `state` (its efforts solved there), for the midpoint of
    /// the first interval of an inverse dynamics run ([`SampledWork::set_first_midpoint`]).
    /// Syncs `d` to `state` without accepting its couplers' turns.
    ///
    /// # Errors
    /// The failure of the solve at `state`.
    pub(crate) fn first_midpoint(
        &mut self,
        d: &mut Dynamics,
        state: &State,
    ) -> Result<(), DynamicsError> {
        d.accelerations(state, &mut self.vdot, &mut self.lambda)?;
        d.powers(state.t, Multipliers::Full(&self.lambda), &mut self.power);
        self.sampled.set_first_midpoint(self.power.clone());
        Ok(())
    }

    /// Number of recorded times (streamed: handed to the sink).
    pub fn len(&self) -> usize {
        self.frames
    }

    /// The time recorded last.
    pub fn last_time(&self) -> Option<f64> {
        self.last_t
    }

    /// The results with the run's counters and dropped rows: every time, or none when
    /// streamed (they went to the sink).
    pub fn finish(mut self, d: &Dynamics, stats: IntegrationStats) -> DynamicResults {
        if self.sink.is_some() {
            self.res.clear_frames();
        }
        self.res.stats = stats;
        let rows = self
            .dropped
            .iter()
            .enumerate()
            .map(|(r, row)| (r, row.worst, row.value, row.time));
        self.res.kinematics.dropped_rows = d.model.worst_dropped_rows(rows, 0.0);
        self.res
    }
}

/// Updates each dropped row's worst scaled residual (see [`DROPPED_ROW_DRIFT_FACTOR`]) from Φ
/// = `phi` at time `t`, `active` the kept rows (increasing). No allocation.
fn record_dropped_rows(
    model: &Model,
    active: &[usize],
    phi: &[f64],
    t: f64,
    dropped: &mut [DroppedRow],
) {
    if active.len() == phi.len() {
        return;
    }
    let scales = model.equation_scales();
    let kept_max = active
        .iter()
        .map(|&r| (phi[r] / scales[r]).abs())
        .fold(0.0f64, f64::max);
    let bound = cardan_solver::Tolerances::default()
        .residual
        .max(DROPPED_ROW_DRIFT_FACTOR * kept_max);
    let mut kept = active.iter().peekable();
    for (r, slot) in dropped.iter_mut().enumerate() {
        if kept.peek() == Some(&&r) {
            kept.next();
            continue;
        }
        let v = (phi[r] / scales[r]).abs();
        // A NaN, once recorded, stays.
        let worse = !slot.worst.is_nan() && (v.is_nan() || v > slot.worst);
        if (v > bound || v.is_nan()) && worse {
            *slot = DroppedRow {
                worst: v,
                value: phi[r],
                time: t,
            };
        }
    }
}

/// The efforts of a pose driver's rotation rows (3–5) as the torque its three rows exert on body
/// j about P_j, in the components of frame i (x_I, y_I, z_I): the rows' multipliers alone are not
/// torques about axes (each row is a dot product of the frames), their combined reaction is.
/// The translation rows' efforts, −λ, are already the force along x_I, y_I, z_I.
fn pose_torques<'a>(
    drivers: &mut [DriverEfforts],
    model: &Model,
    st: impl Fn(BodyId) -> &'a BodyState,
) {
    for (k, dr) in model.drivers().iter().enumerate() {
        let Driver::Pose(p) = &dr.driver else {
            continue;
        };
        if p.row != 3 || k + 3 > drivers.len() {
            continue;
        }
        let torque: Vector3<f64> = drivers[k..k + 3]
            .iter()
            .map(|de| {
                de.reactions
                    .on_j
                    .last()
                    .map_or(Vector3::zeros(), |r| r.torque)
            })
            .sum();
        let frame = st(dr.body_i).a * p.marker_i.frame;
        for (m, de) in drivers[k..k + 3].iter_mut().enumerate() {
            if let Some(e) = de.effort.last_mut() {
                *e = frame.column(m).dot(&torque);
            }
        }
    }
}

/// The velocity and acceleration (global) of the point `local` of a body in state `s` whose
/// accelerations are in `vdot` (zero for the ground).
fn point_motion(
    s: &BodyState,
    id: BodyId,
    local: &Vector3<f64>,
    vdot: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let w = s.omega_local;
    let v = s.r_dot + s.a * w.cross(local);
    let a = match id {
        BodyId::Ground => Vector3::zeros(),
        BodyId::Moving(k) => {
            let rdd = Vector3::from_column_slice(&vdot[6 * k..6 * k + 3]);
            let wd = Vector3::from_column_slice(&vdot[6 * k + 3..6 * k + 6]);
            rdd + s.a * (wd.cross(local) + w.cross(&w.cross(local)))
        }
    };
    (v, a)
}
