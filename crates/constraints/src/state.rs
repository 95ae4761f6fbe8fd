//! What a constraint sees of its two bodies: pose, cached rotation matrix and velocities.

use cardan_eulerparam::{a, p_dot_from_local};
use nalgebra::{Matrix3, Vector3, Vector4};

/// Pose and velocity of one body, as every constraint evaluation reads it.
///
/// The rotation matrix `a` = A(p) is computed once when the pose is set, so a mechanism step that
/// evaluates many constraints on the same body does not recompute it. The velocity is held in both
/// forms: `p_dot` (7-coordinate form, q̇ = [ṙ; ṗ]) and `omega_local` (6-coordinate form,
/// v = [ṙ; ω']); [`BodyState::with_v`] fills both consistently, [`BodyState::with_q_dot`] only ṗ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Position of the body reference point, global frame.
    pub r: Vector3<f64>,
    /// Euler parameters [e0, e1, e2, e3].
    pub p: Vector4<f64>,
    /// A(p), body → global (cached; kept in step with `p` by the constructors).
    pub a: Matrix3<f64>,
    /// ṙ.
    pub r_dot: Vector3<f64>,
    /// ṗ (7-coordinate velocity).
    pub p_dot: Vector4<f64>,
    /// ω', the angular velocity in the body frame (6-coordinate velocity).
    pub omega_local: Vector3<f64>,
}

impl BodyState {
    /// A body at rest at position `r` with Euler parameters `p` (not normalized here).
    pub fn at(r: Vector3<f64>, p: Vector4<f64>) -> Self {
        Self {
            r,
            p,
            a: a(&p),
            r_dot: Vector3::zeros(),
            p_dot: Vector4::zeros(),
            omega_local: Vector3::zeros(),
        }
    }

    /// Ground: r = 0, p = [1, 0, 0, 0], at rest. Vectors "local" to ground are global.
    pub fn ground() -> Self {
        Self::at(Vector3::zeros(), Vector4::new(1.0, 0.0, 0.0, 0.0))
    }

    /// The same pose with 7-coordinate velocity q̇ = [ṙ; ṗ] (ω' is left unchanged).
    pub fn with_q_dot(mut self, r_dot: Vector3<f64>, p_dot: Vector4<f64>) -> Self {
        self.r_dot = r_dot;
        self.p_dot = p_dot;
        self
    }

    /// The same pose with 6-coordinate velocity v = [ṙ; ω']; also sets ṗ = ½ Lᵀ ω'.
    pub fn with_v(mut self, r_dot: Vector3<f64>, omega_local: Vector3<f64>) -> Self {
        self.r_dot = r_dot;
        self.omega_local = omega_local;
        self.p_dot = p_dot_from_local(&self.p, &omega_local);
        self
    }

    /// Global position of a body-fixed point s'^P: r + A s'^P.
    pub fn point(&self, s_local: &Vector3<f64>) -> Vector3<f64> {
        self.r + self.a * s_local
    }

    /// Global components of a body-fixed vector s': A s'.
    pub fn vector(&self, s_local: &Vector3<f64>) -> Vector3<f64> {
        self.a * s_local
    }
}

/// The two bodies of a constraint, i and j (either may be [`BodyState::ground`]), and the
/// element's extra coordinates u with their rates u̇ (the curve parameters of a higher pair;
/// empty for every other element).
#[derive(Debug, Clone, Copy)]
pub struct BodyPair<'a> {
    /// Body i.
    pub i: &'a BodyState,
    /// Body j.
    pub j: &'a BodyState,
    /// The element's extra coordinates u ([`crate::Constraint::extra`] of them).
    pub u: &'a [f64],
    /// Their rates u̇ (read by γ#).
    pub u_dot: &'a [f64],
}

impl<'a> BodyPair<'a> {
    /// The pair (i, j), without extra coordinates.
    pub fn new(i: &'a BodyState, j: &'a BodyState) -> Self {
        Self {
            i,
            j,
            u: &[],
            u_dot: &[],
        }
    }

    /// The pair (i, j) with an element's extra coordinates `u` and their rates `u_dot`.
    pub fn with_extra(i: &'a BodyState, j: &'a BodyState, u: &'a [f64], u_dot: &'a [f64]) -> Self {
        Self { i, j, u, u_dot }
    }
}

/// Which of a body's coordinates a constraint's rows can depend on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BlockUse {
    /// Depends on r (or ṙ).
    pub r: bool,
    /// Depends on p (or ω').
    pub p: bool,
}

impl BlockUse {
    /// Neither r nor p.
    pub const NONE: Self = Self { r: false, p: false };
    /// Only the orientation.
    pub const P: Self = Self { r: false, p: true };
    /// Both position and orientation.
    pub const RP: Self = Self { r: true, p: true };

    /// Whether any coordinate is used.
    pub fn any(self) -> bool {
        self.r || self.p
    }

    /// The union of two uses.
    pub fn or(self, o: Self) -> Self {
        Self {
            r: self.r || o.r,
            p: self.p || o.p,
        }
    }
}

/// The sparsity footprint of a constraint: which coordinate blocks of bodies i and j its rows
/// touch. Known from the element's definition alone, before any evaluation, so that a mechanism
/// can lay out the global Jacobian once. Every nonzero of Φ_q and Φ_v lies inside it (checked by
/// the conformance suite).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Footprint {
    /// Blocks of body i.
    pub i: BlockUse,
    /// Blocks of body j.
    pub j: BlockUse,
}

impl Footprint {
    /// The union of two footprints.
    pub fn or(self, o: Self) -> Self {
        Self {
            i: self.i.or(o.i),
            j: self.j.or(o.j),
        }
    }
}
