//! The numbers a dynamic or inverse dynamics run's summary and warnings take from its frames
//! ([`DynamicTally`]): running maxima over every frame as it is streamed
//! ([`super::stream::FrameLayout::Tally`]), never from the decimated copy kept for the plots.

use super::energy::EnergyBalance;
use crate::output_tables::fold_peak_efforts;
use cardan_dynamics::DynamicResults;

/// The numbers a dynamic or inverse dynamics run's summary and warnings take over every
/// frame, as running maxima (the same folds as over the whole histories, so the same numbers).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DynamicTally {
    /// Times taken.
    pub frames: usize,
    /// Newton iterations of the kinematics (inverse dynamics).
    pub iterations: usize,
    /// The largest max |Φ| (the constraint drift of a dynamic run, the residual of an inverse
    /// one).
    pub max_drift: f64,
    /// The total energy at the first time, E(t₀).
    pub e0: f64,
    /// max |E − E(t₀)|.
    pub max_energy_drift: f64,
    /// max |E − E(t₀) − W_nc|.
    pub max_balance: f64,
    /// The largest kinetic energy.
    pub max_kinetic: f64,
    /// The least and the largest potential energy (gravity and springs).
    pub potential: (f64, f64),
    /// Per work channel, the largest |W|.
    pub max_work: Vec<f64>,
    /// Per driver, the largest |effort|.
    pub peak_efforts: Vec<f64>,
    /// Per cam pair, where its contact pulls ([`CamPull`]).
    pub cam_pulls: Vec<CamPull>,
    /// The contacts between collision shapes at every time (`contacts.csv`).
    pub contacts: Vec<(f64, cardan_dynamics::collision::ContactPoint)>,
}

/// Where a cam pair's contact pulls the follower on (its normal force below −1e-9 of the
/// largest |normal force| so far): the follower would lift off there.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CamPull {
    /// The cam pair.
    pub name: String,
    /// The largest |normal force| so far (N).
    pub scale: f64,
    /// The first time it pulled, with the force then.
    pub first: Option<(f64, f64)>,
    /// The least normal force and its time.
    pub least: Option<(f64, f64)>,
}

impl CamPull {
    fn take(&mut self, times: &[f64], normal: &[f64]) {
        for (&t, &n) in times.iter().zip(normal) {
            if n.is_nan() {
                continue;
            }
            self.scale = self.scale.max(n.abs());
            if n < -1e-9 * self.scale {
                self.first.get_or_insert((t, n));
                if self.least.is_none_or(|(_, l)| n < l) {
                    self.least = Some((t, n));
                }
            }
        }
    }
}

impl DynamicTally {
    /// The tally over every time of `r`.
    pub fn of(r: &DynamicResults) -> Self {
        let mut t = Self::default();
        t.take(r);
        t
    }

    /// Takes the times of `r` (the first ever taken sets E(t₀) and the per-element storage).
    pub fn take(&mut self, r: &DynamicResults) {
        let e = &r.energy;
        if self.frames == 0 {
            self.e0 = e.total.first().copied().unwrap_or(0.0);
            self.potential = (f64::INFINITY, f64::NEG_INFINITY);
            self.max_work = vec![0.0; e.elements.len()];
            self.peak_efforts = vec![0.0; r.drivers.len()];
            self.cam_pulls = (r.cams.iter())
                .map(|c| CamPull {
                    name: c.name.clone(),
                    ..CamPull::default()
                })
                .collect();
        }
        for (pull, c) in self.cam_pulls.iter_mut().zip(&r.cams) {
            pull.take(r.times(), &c.normal_force);
        }
        self.frames += r.len();
        self.iterations += r.kinematics.iterations.iter().sum::<usize>();
        self.max_drift = (r.position_drift.iter()).fold(self.max_drift, |a, &b| a.max(b));
        let e0 = self.e0;
        for &t in &e.total {
            self.max_energy_drift = self.max_energy_drift.max((t - e0).abs());
        }
        for (&t, &w) in e.total.iter().zip(&e.work) {
            self.max_balance = self.max_balance.max((t - e0 - w).abs());
        }
        self.max_kinetic = e.kinetic.iter().fold(self.max_kinetic, |a, &t| a.max(t));
        for (g, s) in e.gravity.iter().zip(&e.spring) {
            let v = g + s;
            self.potential = (self.potential.0.min(v), self.potential.1.max(v));
        }
        for (m, w) in self.max_work.iter_mut().zip(&e.elements) {
            *m = w.work.iter().fold(*m, |a, x| a.max(x.abs()));
        }
        fold_peak_efforts(r, &mut self.peak_efforts);
        self.contacts.extend_from_slice(&r.contacts.points);
    }

    /// The energy scale ([`super::energy::energy_scale`]) over the times taken.
    pub fn energy_scale(&self) -> f64 {
        let (lo, hi) = self.potential;
        let range = if hi >= lo { hi - lo } else { 0.0 };
        self.max_kinetic + range + self.max_work.iter().sum::<f64>()
    }

    /// The energy balance of the summary.
    pub fn energy_balance(&self) -> EnergyBalance {
        EnergyBalance {
            max_abs: self.max_balance,
            scale: self.energy_scale(),
        }
    }
}
