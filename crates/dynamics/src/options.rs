//! Options of a dynamic simulation: time span, output times, integrator and its options,
//! constraint stabilization.

use cardan_mechanism::Outputs;

/// An integrator option outside the range where it means something (from
/// [`Integrator::validate`]). `option` is the field name in the options struct (`rtol`, `atol`,
/// `h_max`, `h_min`, `step`, `projection_tolerance`, `alpha`, `beta`, `h`, `rho_inf`,
/// `tolerance`, `max_iterations`, `max_halvings`), so a caller that read the options from a
/// file can point at its own key ([`OptionError::describe`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", self.describe(self.option))]
pub struct OptionError {
    /// The field of the options struct.
    pub option: &'static str,
    /// The value given.
    pub value: f64,
    /// The accepted range, e.g. "[1e-14, 1e-2]".
    pub range: &'static str,
    /// Why values outside the range are refused.
    pub why: &'static str,
}

impl OptionError {
    /// The message with the option called `key` (a model file's key for the same option).
    pub fn describe(&self, key: &str) -> String {
        let v = self.value;
        let value = if v == 0.0 || (1e-3..1e6).contains(&v.abs()) || !v.is_finite() {
            format!("{v}")
        } else {
            format!("{v:e}")
        };
        format!(
            "{key} = {value} is outside its sensible range {}: {}",
            self.range, self.why
        )
    }
}

/// Relative tolerances (DOPRI5's rtol): [1e-14, 1e-2].
pub const RTOL_RANGE: (f64, f64) = (1e-14, 1e-2);
/// Newton tolerances on scaled residuals (generalized-α, the projection): [1e-14, 1e-6].
pub const NEWTON_TOLERANCE_RANGE: (f64, f64) = (1e-14, 1e-6);
/// Absolute tolerances (DOPRI5's atol, in m, rad, m/s, rad/s): (0, 1e-2].
pub const ATOL_MAX: f64 = 1e-2;

/// `Ok` when lo ≤ value ≤ hi (false for NaN).
fn within(
    option: &'static str,
    value: f64,
    (lo, hi): (f64, f64),
    range: &'static str,
    why: &'static str,
) -> Result<(), OptionError> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(OptionError {
            option,
            value,
            range,
            why,
        })
    }
}

/// A step size: positive and finite.
fn step_size(option: &'static str, h: f64) -> Result<(), OptionError> {
    within(
        option,
        h,
        (f64::MIN_POSITIVE, f64::MAX),
        "(0, ∞) s",
        "a step must be a positive finite time",
    )
}

/// A Newton tolerance on a scaled residual.
fn newton_tolerance(option: &'static str, t: f64) -> Result<(), OptionError> {
    within(
        option,
        t,
        NEWTON_TOLERANCE_RANGE,
        "[1e-14, 1e-6] (default 1e-10)",
        "below 1e-14 it asks for less than roundoff; above 1e-6 the constraints are left \
         visibly violated and the energy is wrong",
    )
}

/// When results are stored.
#[derive(Debug, Clone, PartialEq)]
pub enum OutputTimes {
    /// `steps + 1` equally spaced times from t0 to t_end.
    Grid {
        /// Number of intervals.
        steps: usize,
    },
    /// These times (increasing, within [t0, t_end]).
    Times(Vec<f64>),
}

/// How the explicit integrator keeps the state on the constraint manifolds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stabilization {
    /// Coordinate projection after every accepted step and at every output (default).
    Projection,
    /// Baumgarte: the acceleration equation becomes Φ_v v̇ = γ# − 2α(Φ_v v − ν) − β²Φ.
    Baumgarte {
        /// α (1/s).
        alpha: f64,
        /// β (1/s).
        beta: f64,
    },
    /// Baumgarte plus projection.
    BaumgarteAndProjection {
        /// α (1/s).
        alpha: f64,
        /// β (1/s).
        beta: f64,
    },
    /// Nothing (the constraints drift; for tests and comparison).
    None,
}

impl Stabilization {
    /// Whether projection is on.
    pub fn projects(&self) -> bool {
        matches!(
            self,
            Stabilization::Projection | Stabilization::BaumgarteAndProjection { .. }
        )
    }

    /// The Baumgarte factors, zero without Baumgarte.
    pub fn baumgarte(&self) -> Baumgarte {
        match *self {
            Stabilization::Baumgarte { alpha, beta }
            | Stabilization::BaumgarteAndProjection { alpha, beta } => Baumgarte { alpha, beta },
            _ => Baumgarte::NONE,
        }
    }
}

/// The factors of Baumgarte's stabilization: the acceleration equation becomes
/// Φ_v v̇ = γ# − 2α(Φ_v v − ν) − β²Φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Baumgarte {
    /// α (1/s).
    pub alpha: f64,
    /// β (1/s).
    pub beta: f64,
}

impl Baumgarte {
    /// No stabilization terms (α = β = 0).
    pub const NONE: Self = Self {
        alpha: 0.0,
        beta: 0.0,
    };
}

/// Step-size control.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepControl {
    /// Adaptive step with error control; the first step is estimated if `None`.
    Adaptive {
        /// First step (s).
        initial: Option<f64>,
    },
    /// Fixed step h (s), no error control; the last step lands on t_end, outputs inside a step
    /// come from the dense output.
    Fixed(f64),
}

/// Options of the Dormand-Prince 5(4) integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dopri5Options {
    /// Relative tolerance (default 1e-6).
    pub rtol: f64,
    /// Absolute tolerance (default 1e-8).
    pub atol: f64,
    /// Adaptive (default) or fixed steps.
    pub step: StepControl,
    /// Largest step (default: unlimited).
    pub h_max: f64,
    /// Smallest step before giving up (default 1e-12).
    pub h_min: f64,
    /// Constraint stabilization (default: projection).
    pub stabilization: Stabilization,
    /// Projection Newton tolerance on the scaled residual (default 1e-10).
    pub projection_tolerance: f64,
}

impl Default for Dopri5Options {
    fn default() -> Self {
        Self {
            rtol: 1e-6,
            atol: 1e-8,
            step: StepControl::Adaptive { initial: None },
            h_max: f64::INFINITY,
            h_min: 1e-12,
            stabilization: Stabilization::Projection,
            projection_tolerance: 1e-10,
        }
    }
}

impl Dopri5Options {
    /// Adaptive with tolerances rtol, atol.
    pub fn tolerances(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            ..Self::default()
        }
    }

    /// Fixed step h.
    pub fn fixed(h: f64) -> Self {
        Self {
            step: StepControl::Fixed(h),
            ..Self::default()
        }
    }

    /// Refuses options that cannot give a meaningful result: tolerances outside
    /// [`RTOL_RANGE`], (0, [`ATOL_MAX`]] and [`NEWTON_TOLERANCE_RANGE`], non-positive or
    /// non-finite steps, h_min > h_max, negative Baumgarte factors.
    ///
    /// # Errors
    /// The first option out of range.
    pub fn validate(&self) -> Result<(), OptionError> {
        within(
            "rtol",
            self.rtol,
            RTOL_RANGE,
            "[1e-14, 1e-2] (default 1e-6)",
            "below 1e-14 the error test asks for less than roundoff; above 1e-2 the result \
             has no correct digits",
        )?;
        within(
            "atol",
            self.atol,
            (f64::MIN_POSITIVE, ATOL_MAX),
            "(0, 1e-2] (default 1e-8; m, rad, m/s, rad/s)",
            "above 1e-2 the result has no correct digits",
        )?;
        match self.step {
            StepControl::Fixed(h) => step_size("dt", h)?,
            StepControl::Adaptive { initial: Some(h) } => step_size("initial", h)?,
            StepControl::Adaptive { initial: None } => {}
        }
        within(
            "h_max",
            self.h_max,
            (f64::MIN_POSITIVE, f64::INFINITY),
            "(0, ∞] s",
            "the largest step must be positive",
        )?;
        within(
            "h_min",
            self.h_min,
            (f64::MIN_POSITIVE, self.h_max.min(f64::MAX)),
            "(0, h_max] s",
            "the smallest step must be positive and not above the largest",
        )?;
        newton_tolerance("projection_tolerance", self.projection_tolerance)?;
        let Baumgarte { alpha, beta } = self.stabilization.baumgarte();
        for (option, v) in [("alpha", alpha), ("beta", beta)] {
            within(
                option,
                v,
                (0.0, f64::MAX),
                "[0, ∞) 1/s",
                "a Baumgarte factor must be finite and not negative",
            )?;
        }
        Ok(())
    }
}

/// Which iteration matrix the implicit Newton uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IterationMatrix {
    /// M + γ' C_t + β' K_t with the force tangents C_t = −∂h/∂v, K_t = −∂h/∂q by finite
    /// differences (body blocks and the blocks of two-body force elements), plus Φ_v (default).
    #[default]
    Tangent,
    /// M only (cheaper; converges only when β' K and γ' C are small against M).
    MassOnly,
    /// M only, and for a step whose Newton iteration fails, one retry with the full tangent
    /// before the step is halved: the mass-only cost where it converges (most steps of a
    /// gravity-driven model), the tangent's robustness near singular configurations.
    MassOnlyThenTangent,
}

/// Options of the generalized-α integrator (index 3, Newton on [v̇, λ]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeneralizedAlphaOptions {
    /// Time step dt (s), the file's `dt` (h in the books' formulas); steps are shortened to
    /// land on output times.
    pub dt: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1] (default 0.8; 1 = no numerical
    /// damping, trapezoidal-like).
    pub rho_inf: f64,
    /// Newton tolerance on the scaled residual (default 1e-10), the file's `newton_tolerance`.
    pub newton_tolerance: f64,
    /// Newton iteration cap per step (default 20).
    pub max_iterations: usize,
    /// Halve the step (down to h / 2^`max_halvings`) when Newton fails (default 6).
    pub max_halvings: u32,
    /// Project the velocities onto Φ_v v = ν after each step (default true).
    pub project_velocities: bool,
    /// The iteration matrix.
    pub iteration_matrix: IterationMatrix,
    /// Modified Newton (default true): keep the last factorization of the KKT matrix across
    /// iterations, steps and velocity projections while the iteration contracts fast enough
    /// (θ = ‖Δ_k‖/‖Δ_{k−1}‖ ≤ 0.25), refactor at the current iterate when it does not. The
    /// converged result satisfies the same residual tests either way; `false` refactors at every
    /// iteration (full Newton, for comparison and tests).
    pub reuse_factorization: bool,
}

impl Default for GeneralizedAlphaOptions {
    fn default() -> Self {
        Self {
            dt: 1e-3,
            rho_inf: 0.8,
            newton_tolerance: 1e-10,
            max_iterations: 20,
            max_halvings: 6,
            project_velocities: true,
            iteration_matrix: IterationMatrix::Tangent,
            reuse_factorization: true,
        }
    }
}

impl GeneralizedAlphaOptions {
    /// Time step `dt`, other options default.
    pub fn with_step(dt: f64) -> Self {
        Self {
            dt,
            ..Self::default()
        }
    }

    /// Refuses options that cannot give a meaningful result: a non-positive or non-finite
    /// step, ρ∞ outside [0, 1], a Newton tolerance outside [`NEWTON_TOLERANCE_RANGE`], no
    /// iterations, more halvings than a step can take.
    ///
    /// # Errors
    /// The first option out of range.
    pub fn validate(&self) -> Result<(), OptionError> {
        step_size("dt", self.dt)?;
        within(
            "rho_inf",
            self.rho_inf,
            (0.0, 1.0),
            "[0, 1] (default 0.8)",
            "the spectral radius at infinite frequency: 1 = no numerical damping, 0 = the most",
        )?;
        newton_tolerance("newton_tolerance", self.newton_tolerance)?;
        within(
            "max_iterations",
            self.max_iterations as f64,
            (1.0, 1000.0),
            "[1, 1000] (default 20)",
            "Newton needs at least one iteration",
        )?;
        within(
            "max_halvings",
            f64::from(self.max_halvings),
            (0.0, 52.0),
            "[0, 52] (default 6)",
            "a step halved more than 52 times is below the roundoff of the time",
        )
    }
}

/// The time integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// Explicit Dormand-Prince 5(4) with dense output and projection.
    Dopri5(Dopri5Options),
    /// Implicit index-3 generalized-α (stiff models).
    GeneralizedAlpha(GeneralizedAlphaOptions),
}

impl Integrator {
    /// Refuses options that cannot give a meaningful result
    /// ([`Dopri5Options::validate`], [`GeneralizedAlphaOptions::validate`]).
    ///
    /// # Errors
    /// The first option out of range.
    pub fn validate(&self) -> Result<(), OptionError> {
        match self {
            Integrator::Dopri5(o) => o.validate(),
            Integrator::GeneralizedAlpha(o) => o.validate(),
        }
    }
}

impl Default for Integrator {
    fn default() -> Self {
        Integrator::Dopri5(Dopri5Options::default())
    }
}

/// Options of [`crate::Dynamics::simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// End time (the start time is the initial state's).
    pub t_end: f64,
    /// Output times.
    pub output: OutputTimes,
    /// Integrator.
    pub integrator: Integrator,
    /// What to store (positions always; velocities, accelerations, points, joint coordinates).
    pub outputs: Outputs,
    /// Step limit (default 10 000 000).
    pub max_steps: usize,
}

impl SimulationOptions {
    /// Until `t_end`, `steps + 1` equally spaced outputs, DOPRI5 with default tolerances.
    pub fn new(t_end: f64, steps: usize) -> Self {
        Self {
            t_end,
            output: OutputTimes::Grid { steps },
            integrator: Integrator::default(),
            outputs: Outputs::default(),
            max_steps: 10_000_000,
        }
    }

    /// The same with another integrator.
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }

    /// The same with explicit output times.
    pub fn output_times(mut self, times: Vec<f64>) -> Self {
        self.output = OutputTimes::Times(times);
        self
    }

    /// The same with other stored outputs.
    pub fn outputs(mut self, outputs: Outputs) -> Self {
        self.outputs = outputs;
        self
    }

    /// The output times for a run starting at `t0`.
    pub fn times(&self, t0: f64) -> Vec<f64> {
        match &self.output {
            OutputTimes::Grid { steps } => {
                let n = (*steps).max(1);
                (0..=n)
                    .map(|k| t0 + (self.t_end - t0) * (k as f64 / n as f64))
                    .collect()
            }
            OutputTimes::Times(t) => t.clone(),
        }
    }
}
