//! # cardan-eulerparam: Euler parameters as coordinates
//!
//! The rotation maths of the absolute-coordinate formulation of Nikravesh (*Computer-Aided
//! Analysis of Mechanical Systems*, 1988, ch. 6) and Haug (*Computer-Aided Kinematics and
//! Dynamics of Mechanical Systems*, 1989, ch. 6 and 9). Symbols follow `shared/notation.md`.
//!
//! ## Theory
//! A body's orientation is described by four Euler parameters p = [e0, e1, e2, e3]ᵀ (scalar
//! first, e = [e1, e2, e3]ᵀ) subject to the normalization pᵀp = 1. For a unit axis u and angle χ,
//! e0 = cos(χ/2) and e = u sin(χ/2). The rotation (body → global) is
//!
//! ```text
//! A(p) = (2 e0² − 1) I + 2 (e eᵀ + e0 ẽ)            (Nikravesh 1988 ch. 6; Haug 1989 ch. 6)
//! ```
//!
//! and the two 3×4 matrices
//!
//! ```text
//! G(p) = [−e, ẽ + e0 I]      L(p) = [−e, −ẽ + e0 I]   (Haug calls them E and G)
//! ```
//!
//! factor it, A = G Lᵀ (for pᵀp = 1; in general G Lᵀ = A + (1 − pᵀp) I), and map parameter
//! rates to angular velocity: ω = 2 G ṗ (global), ω' = 2 L ṗ (body frame). A(p) as written is
//! quadratic in p for every p (normalized or not), so the derivative of a rotated body-fixed
//! vector, ∂(A a')/∂p = 2 (G ā' + a' pᵀ), is linear in p; the seed slides call it C_k for a
//! direction vector and B_k for a point vector ([`da_dp`]).
//!
//! p and −p describe the same rotation but are different *coordinates*: this crate never treats
//! them as equal and never flips a sign behind the caller's back. That is why [`EulerParams`] is a
//! type of its own and not nalgebra's `Quaternion` (which stores [i, j, k, w]).
//!
//! ## Layout
//! - [`params`]: the [`EulerParams`] coordinate type (normalization, norm check, composition).
//! - [`skew`](mod@skew): the tilde operator ã b = a × b.
//! - [`matrices`]: A, G, L, ā, ∂(A a')/∂p and their time derivatives.
//! - [`velocity`]: ω, ω', ṗ and p̈ maps.
//! - [`convert`]: rotation matrix, axis-angle, Euler angles (3-1-3, 1-2-3), frames from axes,
//!   and the `EulerParams` constructors that use them (`from_axis_angle`, ...): `convert`
//!   builds on `params`, never the other way round.
//!
//! Everything uses nalgebra's fixed-size types; nothing allocates except an error's payload.
//!
//! ## Example
//! ```
//! use cardan_eulerparam::{EulerParams, a};
//! use nalgebra::Vector3;
//! // A quarter turn about z.
//! let p = EulerParams::from_axis_angle(&Vector3::z(), std::f64::consts::FRAC_PI_2).unwrap();
//! let x = a(p.as_vector()) * Vector3::x();
//! assert!((x - Vector3::y()).norm() < 1e-15);
//! ```

pub mod convert;
pub mod error;
pub mod matrices;
pub mod params;
pub mod skew;
pub mod velocity;

pub use convert::{
    euler_123_from_p, euler_313_from_p, frame_from_axis, frame_from_two_axes, p_from_euler_123,
    p_from_euler_313, p_from_rotation_matrix,
};
pub use error::EulerParamError;
pub use matrices::{a, a_dot, bar, da_dp, da_dpi_local, g, g_dot, l, l_dot};
pub use params::EulerParams;
pub use skew::{skew, unskew};
pub use velocity::{
    omega_global, omega_local, p_ddot_from_local, p_dot_from_global, p_dot_from_local,
};

/// Re-exported so downstream crates name the same nalgebra types.
pub use nalgebra;
