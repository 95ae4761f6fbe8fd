//! Options of a dynamic simulation: time span, output times, integrator and its options,
//! constraint stabilization.

use cardan_mechanism::Outputs;

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

    /// (α, β), zero without Baumgarte.
    pub fn baumgarte(&self) -> (f64, f64) {
        match *self {
            Stabilization::Baumgarte { alpha, beta }
            | Stabilization::BaumgarteAndProjection { alpha, beta } => (alpha, beta),
            _ => (0.0, 0.0),
        }
    }
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
    /// Step h (s); steps are shortened to land on output times.
    pub h: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1] (default 0.8; 1 = no numerical
    /// damping, trapezoidal-like).
    pub rho_inf: f64,
    /// Newton tolerance on the scaled residual (default 1e-10).
    pub tolerance: f64,
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
            h: 1e-3,
            rho_inf: 0.8,
            tolerance: 1e-10,
            max_iterations: 20,
            max_halvings: 6,
            project_velocities: true,
            iteration_matrix: IterationMatrix::Tangent,
            reuse_factorization: true,
        }
    }
}

impl GeneralizedAlphaOptions {
    /// Step h, other options default.
    pub fn with_step(h: f64) -> Self {
        Self {
            h,
            ..Self::default()
        }
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
