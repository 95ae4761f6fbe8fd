//! When generalized-α's modified Newton factors its iteration matrix ([`FactorPolicy`]).
//!
//! The KKT solver holds one factorization at a time, of one layout: an iteration matrix
//! [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0], or [M Φ_vᵀ; Φ_v 0] of a velocity projection or an
//! acceleration solve at an accepted state. With
//! [`GeneralizedAlphaOptions::reuse_factorization`](crate::GeneralizedAlphaOptions::reuse_factorization)
//! an attempt starts from the held one ([`Factor::Stale`]) and factors again
//!
//! * when there is none, or when the iteration is a tangent one and the held matrix is not a
//!   tangent matrix for this h (unless the tangent terms are small, [`TANGENT_SMALL`]);
//! * at the predictor, before the first update, when the held matrix has aged so far that the
//!   chord iteration needs a third update ("refresh", [`THETA_REFRESH`]: the chord rate of the
//!   last measured step above it and at least twice that of the last refreshed matrix — the
//!   hold-back rule —, and the refreshed matrix mass-only);
//! * at the current iterate when the residual contracts by less than 4× per iteration
//!   ([`THETA_REFACTOR`]).
//!
//! The chord rate θ is measured at the third iteration of a step that kept its matrix over
//! its first two updates (the ratio of the second update to the first); a factorization of an
//! iteration that is not a refresh forgets the refreshed matrix's rate.

/// Size of the tangent terms γ' C_t + β' K_t relative to M
/// ([`Tangents::relative_size`](super::tangents::Tangents::relative_size)) up to which the
/// modified Newton of a tangent iteration uses M instead: a held mass-only factorization (of a
/// velocity projection or an output's acceleration solve) serves, and a refactorization
/// factors M alone. The chord iteration with M then contracts at about this rate, well within
/// the modified Newton's refactoring bound [`THETA_REFACTOR`]. A chain under gravity
/// (gyroscopic terms only, γ'|ω| ≈ 1e-3) is far below; a stiff spring is above and keeps its
/// tangent matrix. The tangents are evaluated again at every refactorization but a refresh
/// ([`THETA_REFRESH`]), so a motion that makes them grow (the chord iteration with M then
/// fails the bound) brings them back.
pub(super) const TANGENT_SMALL: f64 = 0.05;

/// Contraction rate above which modified Newton refactors at the current iterate.
pub(super) const THETA_REFACTOR: f64 = 0.25;

/// Contraction rate of the chord iteration above which the next step refactors its matrix at
/// the predictor, before its first update ("refresh"), when that rate is also at least twice
/// the rate of the last refreshed matrix (so that refreshing pays) and the refreshed matrix is
/// mass-only (M, or small tangents: a tangent matrix of a stiff force may be an LU of the
/// full system, dearer than the updates it saves).
///
/// The chord test accepts after two updates while θ²/(1 − θ) ≤
/// [`NEWTON_FRACTION`](super::newton::NEWTON_FRACTION), θ ≲ 0.01. A held matrix ages: the
/// iteration matrix misses the Jacobian of the rotation update p ⊗ exp(Δπ'/2) (about h|ω|/2
/// relative) and the gyroscopic terms (γ'|ω|) even when fresh, and Φ_v moves by about h|ω| per
/// step after it. On the slider-crank at h = 1 ms θ is about 3e-3 for a fresh matrix and grows
/// by 2.8e-3 per step, so a matrix kept until it failed the contraction bound
/// [`THETA_REFACTOR`] made most steps take a third update (3.3 per step). A refresh is one
/// factorization of M (small tangents are not evaluated again) and saves a Newton update in
/// each of the next steps: 2.2 updates and 0.44 factorizations per step, −17 % instructions of
/// the 5 s run; h = 0.5 ms −20 %, the error within 4 %. 0.004 and 0.008 did as well within
/// 3 %. The factor 2 keeps a matrix that cannot be refreshed to below the bound (a fast spin,
/// h|ω| ≫ 0.01, when the matrix ages slowly) from being refactored at every step for nothing;
/// the fresh rate is forgotten at every other factorization of an iteration (the bound's), so
/// a motion that slows down brings the refresh back. It holds refreshes back where a small
/// tangent left out of M decides the rate: a crank falling against a light damper
/// (γ'c/m ≈ 0.01) took 0.26 factorizations per step without it, 0.05 with it, at the same 1.4
/// updates (`tests/step_policy.rs`). On the slider-crank at h = 2, 4, 8 ms and the 5-link
/// chain up to 16 ms the matrix ages too fast for it to act.
pub(super) const THETA_REFRESH: f64 = 0.006;

/// Whether the KKT solver holds a factorization that may serve as the (approximate) iteration
/// matrix: one of the same layout at a nearby state ([M Φ_vᵀ; Φ_v 0] from a projection or an
/// acceleration solve, or an earlier iteration matrix). Modified Newton only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Factor {
    /// Nothing usable (start, or the last factorization failed).
    None,
    /// Usable, computed before the current step attempt.
    Stale,
    /// Computed in the current step attempt, at one of its iterates.
    Fresh,
}

/// The factorization held across steps and what is known of its quality.
#[derive(Debug, Clone)]
pub(super) struct FactorPolicy {
    /// State of the solver's factorization.
    pub factor: Factor,
    /// The step size of the tangent iteration matrix the solver holds, 0 when it holds
    /// another matrix.
    tangent_h: f64,
    /// The tangent terms of the last tangent evaluation were small against M
    /// ([`TANGENT_SMALL`]), so a held mass-only matrix serves the iteration as well.
    pub tangent_small: bool,
    /// Contraction of the chord iteration in the last step that measured it (the ratio of its
    /// second update to its first, both with the matrix held at its start), and in the last
    /// step whose matrix was refreshed at its start (0 after any other factorization of an
    /// iteration; see [`THETA_REFRESH`]).
    chord_theta: f64,
    fresh_theta: f64,
}

/// One attempt's factorization plan: what to do before the next update and what the held
/// matrix is to this attempt.
#[derive(Debug, Clone, Copy)]
pub(super) struct Plan {
    /// Factor at the current iterate before the next update.
    pub refactor: bool,
    /// That factorization is a refresh at the predictor.
    pub refresh: bool,
    /// The iteration of this attempt at which the held matrix was factored (MAX: before it).
    factored_at: usize,
    /// Whether that factorization was a refresh.
    pub refreshed: bool,
}

impl Plan {
    /// After the residual of iteration `it` contracted at `theta`: full Newton refactors at
    /// every iteration, modified Newton when the contraction is slower than [`THETA_REFACTOR`].
    pub fn after_residual(&mut self, reuse: bool, it: usize, theta: f64) {
        if !reuse || (it >= 1 && theta > THETA_REFACTOR) {
            self.refactor = true;
        }
    }
}

impl FactorPolicy {
    /// Nothing held.
    pub fn new() -> Self {
        Self {
            factor: Factor::None,
            tangent_h: 0.0,
            tangent_small: false,
            chord_theta: 0.0,
            fresh_theta: 0.0,
        }
    }

    /// The solver holds [M Φ_vᵀ; Φ_v 0] factored at the accepted state (by a velocity
    /// projection or an acceleration solve): a mass-only matrix, with no chord rate measured.
    pub fn hold_mass_matrix(&mut self, factor: Factor) {
        self.factor = factor;
        self.tangent_h = 0.0;
        self.chord_theta = 0.0;
    }

    /// A factorization or a solve failed: nothing usable is held.
    pub fn lost(&mut self) {
        self.factor = Factor::None;
        self.tangent_h = 0.0;
    }

    /// The plan of an attempt of size `h` (`reuse`: modified Newton; `tangent`: a tangent
    /// iteration matrix). The held factorization becomes stale.
    pub fn plan(&mut self, reuse: bool, tangent: bool, h: f64) -> Plan {
        // A tangent iteration matrix is kept across steps like the mass-only one, as long as
        // it is one (not the mass-only matrix of a projection or an output solve) for this h
        // (γ' and β' depend on h).
        let mut refactor = !reuse
            || self.factor == Factor::None
            || (tangent && self.tangent_h.to_bits() != h.to_bits() && !self.tangent_small);
        // A held matrix that has aged (see `THETA_REFRESH`) is refreshed at the predictor, when
        // the refreshed matrix is mass-only (a tangent one may be an LU of the full system).
        let refresh = reuse
            && !refactor
            && (!tangent || self.tangent_small)
            && self.chord_theta > THETA_REFRESH.max(2.0 * self.fresh_theta);
        refactor |= refresh;
        if refresh {
            // Measured again with the refreshed matrix.
            self.chord_theta = 0.0;
        }
        if self.factor == Factor::Fresh {
            self.factor = Factor::Stale;
        }
        Plan {
            refactor,
            refresh,
            factored_at: usize::MAX,
            refreshed: false,
        }
    }

    /// At iteration `it`, with `theta_dv` the ratio of the last two updates of v̇: the chord
    /// rate of a matrix held over the attempt's first two updates (and of a refreshed one).
    pub fn measure_chord(&mut self, plan: &Plan, it: usize, theta_dv: f64) {
        if it == 2 && plan.factored_at != 1 {
            self.chord_theta = theta_dv;
            if plan.refreshed {
                self.fresh_theta = theta_dv;
            }
        }
    }

    /// Whether the tangents are evaluated again for a factorization at iteration `it`: at
    /// every factorization of modified Newton (full Newton: at the predictor, once per
    /// attempt), but a refresh keeps tangents found small.
    pub fn evaluates_tangents(&self, plan: &Plan, reuse: bool, it: usize) -> bool {
        (reuse || it == 0) && !(plan.refresh && self.tangent_small)
    }

    /// Notes the size of the tangent terms relative to M just evaluated.
    pub fn tangents_evaluated(&mut self, relative_size: f64) {
        self.tangent_small = relative_size <= TANGENT_SMALL;
    }

    /// Whether a factorization includes the tangent terms: modified Newton factors M alone
    /// when they are small against it.
    pub fn with_tangents(&self, reuse: bool) -> bool {
        !(reuse && self.tangent_small)
    }

    /// The iteration matrix was factored at iteration `it` of the attempt (with the tangent
    /// terms for the step size `tangent_h`, or 0).
    pub fn factored(&mut self, plan: &mut Plan, it: usize, tangent_h: f64) {
        self.factor = Factor::Fresh;
        self.tangent_h = tangent_h;
        plan.factored_at = it;
        plan.refreshed = plan.refresh;
        if !plan.refresh {
            self.fresh_theta = 0.0;
        }
        plan.refactor = false;
        plan.refresh = false;
    }
}
