//! The linearized equations about an equilibrium as a state-space model for control design:
//! [`Dynamics::state_space`] and the MatrixMarket writer [`matrix_market`].
//!
//! With the independent coordinates z of the [`Linearization`] (δ = N z) and the state
//! x = [z; ż]:
//!
//! ```text
//! ẋ = A x + B u,   y = C x + D u
//! A = ⎡    0          I     ⎤     B = ⎡     0      ⎤     C = [C_y N, 0],   D = 0
//!     ⎣−M_r⁻¹K_r  −M_r⁻¹C_r ⎦         ⎣M_r⁻¹NᵀQ_u ⎦
//! ```
//!
//! Q_u (n × inputs) holds the generalized forces of unit inputs: a force along the global
//! direction d at the body point s' of body k contributes d to the force rows of k and
//! s' × Aᵀd to its body-frame torque rows; a torque about the global axis a contributes Aᵀa
//! to the torque rows. The effort e of a released one-coordinate driver Φ_d = c(q) − f(t) (or
//! the distance driver's dᵀd − ℓ², ∂Φ_d/∂c = 2ℓ) acts along its coordinate: its generalized
//! force is −Φ_d,vᵀλ_d = Φ_d,vᵀ e / (∂Φ_d/∂c) (the sign convention of the crate docs, e =
//! −λ ∂Φ_d/∂c), so its column is Φ_d,vᵀ / (∂Φ_d/∂c). C_y (outputs × n) holds the gradients of the outputs: the coordinate
//! dᵀr_P of a body point P along d has the gradient [dᵀ, (s' × Aᵀd)ᵀ] (the same row as the
//! force: reciprocity), a joint coordinate the rates of that coordinate for the velocities
//! δ = N e_i (the joint's own exact rate formula). D = 0: no input reaches an output
//! directly in a mechanical model.

use crate::modal::Linearization;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_constraints::{BodyPair, BodyState};
use cardan_mechanism::BodyId;
use nalgebra::{DMatrix, Vector3};
use std::fmt::Write as _;

/// An input u of the state-space model.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A force (N) along the global `direction` (unit) at the body point `point` (body frame).
    Force {
        /// The body.
        body: String,
        /// The point, body frame, relative to the centre of mass.
        point: Vector3<f64>,
        /// The direction, global (normalized here).
        direction: Vector3<f64>,
    },
    /// A torque (N m) about the global `axis` (normalized here).
    Torque {
        /// The body.
        body: String,
        /// The axis, global.
        axis: Vector3<f64>,
    },
    /// The effort (N or N m) of a one-coordinate driver along its coordinate, the driver
    /// released ([`Dynamics::linearize_released`]): the change of the effort that held the
    /// equilibrium.
    Driver {
        /// The driver.
        driver: String,
    },
}

/// An output y of the state-space model.
#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    /// The coordinate along the global `direction` (normalized here) of a body point (m).
    Point {
        /// The body.
        body: String,
        /// The point, body frame.
        point: Vector3<f64>,
        /// The direction, global.
        direction: Vector3<f64>,
    },
    /// Coordinate `index` of joint `joint` (as in the joint coordinate tables: rad or m).
    Joint {
        /// The joint.
        joint: String,
        /// The coordinate's index among the joint's coordinates.
        index: usize,
    },
}

/// ẋ = A x + B u, y = C x + D u with x = [z; ż] (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct StateSpace {
    /// A (2d × 2d).
    pub a: DMatrix<f64>,
    /// B (2d × inputs).
    pub b: DMatrix<f64>,
    /// C (outputs × 2d).
    pub c: DMatrix<f64>,
    /// D (outputs × inputs), zero.
    pub d: DMatrix<f64>,
}

impl Dynamics<'_> {
    /// The state-space model of `lin` (the linearization about the equilibrium pose `state`)
    /// with `inputs` and `outputs`.
    ///
    /// # Errors
    /// [`DynamicsError::BadForce`] naming an unknown body or joint, a zero direction or a
    /// coordinate index out of range; [`DynamicsError::NonFinite`] when M_r is singular.
    pub fn state_space(
        &mut self,
        state: &State,
        lin: &Linearization,
        inputs: &[Input],
        outputs: &[Output],
    ) -> Result<StateSpace, DynamicsError> {
        let dof = lin.dof();
        let n = lin.basis.nrows();
        let bad = |what: &str, reason: String| DynamicsError::BadForce {
            key: None,
            force: what.to_string(),
            reason,
        };
        let body = |name: &str| match self.model.body_id(name) {
            Some(BodyId::Moving(k)) => Ok(k),
            _ => Err(bad(name, format!("unknown moving body \"{name}\""))),
        };
        let unit = |v: &Vector3<f64>, what: &str| {
            let l = v.norm();
            if l > 0.0 && l.is_finite() {
                Ok(v / l)
            } else {
                Err(bad(what, "the direction must be finite and nonzero".into()))
            }
        };
        let mut q = DMatrix::zeros(n, inputs.len());
        for (c, u) in inputs.iter().enumerate() {
            match u {
                Input::Force {
                    body: b,
                    point,
                    direction,
                } => {
                    let k = body(b)?;
                    let d = unit(direction, b)?;
                    let a = state.body_state(k).a;
                    let t = point.cross(&(a.transpose() * d));
                    for i in 0..3 {
                        q[(6 * k + i, c)] = d[i];
                        q[(6 * k + 3 + i, c)] = t[i];
                    }
                }
                Input::Torque { body: b, axis } => {
                    let k = body(b)?;
                    let ax = unit(axis, b)?;
                    let t = state.body_state(k).a.transpose() * ax;
                    for i in 0..3 {
                        q[(6 * k + 3 + i, c)] = t[i];
                    }
                }
                Input::Driver { .. } => {}
            }
        }
        for (c, u) in inputs.iter().enumerate() {
            if let Input::Driver { driver } = u {
                let row = self.driver_row(driver)?;
                let slope = self
                    .model
                    .drivers()
                    .iter()
                    .find(|d| &d.name == driver)
                    .map_or(1.0, |d| d.driver.coordinate_slope(state.t));
                self.sync(state);
                let j = self.phi_v_dense(state.t, &[row]);
                for i in 0..n {
                    q[(i, c)] = j[(0, i)] / slope;
                }
            }
        }
        let mut cy = DMatrix::zeros(outputs.len(), dof);
        for (r, y) in outputs.iter().enumerate() {
            match y {
                Output::Point {
                    body: b,
                    point,
                    direction,
                } => {
                    let k = body(b)?;
                    let d = unit(direction, b)?;
                    let a = state.body_state(k).a;
                    let t = point.cross(&(a.transpose() * d));
                    for i in 0..dof {
                        let col = lin.basis.column(i);
                        let mut s = 0.0;
                        for j in 0..3 {
                            s += d[j] * col[6 * k + j] + t[j] * col[6 * k + 3 + j];
                        }
                        cy[(r, i)] = s;
                    }
                }
                Output::Joint { joint, index } => {
                    let ji = self
                        .model
                        .joint_index(joint)
                        .ok_or_else(|| bad(joint, format!("unknown joint \"{joint}\"")))?;
                    let jn = &self.model.joints()[ji];
                    if *index >= jn.joint.kind().info().coordinates.len() {
                        return Err(bad(
                            joint,
                            format!("joint \"{joint}\" has no coordinate {index}"),
                        ));
                    }
                    for i in 0..dof {
                        let mut moving = state.clone();
                        moving.v.copy_from_slice(lin.basis.column(i).as_slice());
                        let g = BodyState::ground();
                        let st = |id: BodyId| match id {
                            BodyId::Ground => g,
                            BodyId::Moving(k) => moving.body_state(k),
                        };
                        let (si, sj) = (st(jn.body_i), st(jn.body_j));
                        let zero = Default::default();
                        let rates =
                            jn.joint
                                .coordinate_rates(&BodyPair::new(&si, &sj), &zero, &zero);
                        cy[(r, i)] = rates.rates[*index];
                    }
                }
            }
        }
        let chol = lin.mass_cholesky(state.t)?;
        let mut a = DMatrix::zeros(2 * dof, 2 * dof);
        for i in 0..dof {
            a[(i, dof + i)] = 1.0;
        }
        a.view_mut((dof, 0), (dof, dof))
            .copy_from(&(-chol.solve(&lin.stiffness)));
        a.view_mut((dof, dof), (dof, dof))
            .copy_from(&(-chol.solve(&lin.damping)));
        let mut b = DMatrix::zeros(2 * dof, inputs.len());
        b.view_mut((dof, 0), (dof, inputs.len()))
            .copy_from(&chol.solve(&(lin.basis.transpose() * q)));
        let mut c = DMatrix::zeros(outputs.len(), 2 * dof);
        c.view_mut((0, 0), (outputs.len(), dof)).copy_from(&cy);
        Ok(StateSpace {
            a,
            b,
            c,
            d: DMatrix::zeros(outputs.len(), inputs.len()),
        })
    }
}

/// `m` in the MatrixMarket coordinate format (`%%MatrixMarket matrix coordinate real
/// general`, 1-based indices, every nonzero, 17 significant digits), readable by
/// `scipy.io.mmread` and MATLAB's `mmread`.
pub fn matrix_market(m: &DMatrix<f64>) -> String {
    let nz: Vec<(usize, usize, f64)> = (0..m.ncols())
        .flat_map(|c| (0..m.nrows()).map(move |r| (r, c)))
        .map(|(r, c)| (r, c, m[(r, c)]))
        .filter(|&(_, _, v)| v != 0.0)
        .collect();
    let mut s = String::from("%%MatrixMarket matrix coordinate real general\n");
    let _ = writeln!(s, "{} {} {}", m.nrows(), m.ncols(), nz.len());
    for (r, c, v) in nz {
        let _ = writeln!(s, "{} {} {:.17e}", r + 1, c + 1, v);
    }
    s
}

/// The sparse `rows` × `cols` matrix of the triplets `entries` (no duplicates) in the format of
/// [`matrix_market`] (the same text as the dense matrix would give: nonzeros by column, then
/// row).
pub fn matrix_market_sparse(rows: usize, cols: usize, entries: &[(usize, usize, f64)]) -> String {
    let mut nz: Vec<(usize, usize, f64)> = entries.iter().copied().filter(|e| e.2 != 0.0).collect();
    nz.sort_by_key(|e| (e.1, e.0));
    let mut s = String::from("%%MatrixMarket matrix coordinate real general\n");
    let _ = writeln!(s, "{rows} {cols} {}", nz.len());
    for (r, c, v) in nz {
        let _ = writeln!(s, "{} {} {:.17e}", r + 1, c + 1, v);
    }
    s
}
