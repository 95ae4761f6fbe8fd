//! Analyses on a [`crate::Model`] and its [`crate::Workspace`]: assembly, position, velocity and
//! acceleration at one time, and runs over a time grid.
//!
//! - [`assembly`]: consistent initial poses from a rough guess (minimum-norm Newton).
//! - [`dof`](mod@dof): the degrees-of-freedom count and the redundant equations at a pose.
//! - [`drag`]: a point of a body dragged toward a target, the rest following by least change,
//!   stopped at joint limits.
//! - [`dropped`]: the residuals of the rows dropped as redundant, checked at the solution.
//! - [`position`]: the square kinematic Newton (redundant rows dropped once) at one time.
//! - [`velocity`]: Φ_v v = ν with the position factorization.
//! - [`acceleration`]: Φ_v v̇ = γ#_v with the same factorization.
//! - [`grid`]: the three over a time grid, with a predicted Newton start, into [`crate::Results`].
//! - [`least_change`]: the pose nearest a previous one (weighted) on the constraints: the free
//!   degrees of freedom of an under-driven mechanism held still.
//! - [`limits`]: a prescribed motion that drives a joint past a limit stops at the crossing.
//! - `predictor`: that Newton start, predicted relative to a parent along a spanning tree of the
//!   joints.

pub mod acceleration;
pub mod assembly;
pub(crate) mod best_fit;
pub mod dof;
pub mod drag;
pub mod dropped;
pub mod grid;
pub(crate) mod held;
pub mod least_change;
pub mod limits;
pub mod position;
pub(crate) mod predictor;
pub mod velocity;
