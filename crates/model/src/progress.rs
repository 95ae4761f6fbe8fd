//! Long runs: a progress bar, and a stop request (Ctrl-C).
//!
//! Every analysis loop (the kinematic grid, the integrators, the two passes of inverse
//! dynamics) calls [`Progress::tick`] once per step. A bar ([`Bar`], drawn by the command on
//! its terminal) is made only once a run has taken [`SHOW_AFTER`] (a run expected to be quick
//! never flickers a bar), and only when the run was given a [`MakeBar`]. [`Progress::tick`]
//! also reads the stop flag ([`request_stop`]: the command's Ctrl-C handler, a host's
//! interrupt): the loop then stops and the run keeps its results so far (written, marked
//! partial, exit code 130).

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// A run that has taken this long shows its progress bar.
pub const SHOW_AFTER: Duration = Duration::from_secs(1);

/// Redraws of the bar per run (at most).
const REDRAWS: u64 = 1000;

/// A progress bar: drawn at most `REDRAWS` times a run, removed when dropped.
pub trait Bar {
    /// `done` units of the run's length done, at time `t`.
    fn draw(&mut self, done: u64, t: f64);
}

/// Makes the bar of a run of `len` units (`RunFlags::progress`; the command's terminal bar).
pub type MakeBar = fn(u64) -> Box<dyn Bar>;

/// The stop flag (set by a signal handler or a host, read by every step).
pub fn stop_flag() -> &'static Arc<AtomicBool> {
    static STOP: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    STOP.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// Whether Ctrl-C was pressed.
pub fn stop_requested() -> bool {
    stop_flag().load(Ordering::Relaxed)
}

/// Asks the running analyses to stop at their next step and keep their results, as Ctrl-C
/// does (for hosts with their own interrupt handling, such as the Python bindings).
pub fn request_stop() {
    stop_flag().store(true, Ordering::Relaxed);
}

/// Clears a stop request, so that the next analysis runs (hosts that handled the interrupt).
pub fn clear_stop() {
    stop_flag().store(false, Ordering::Relaxed);
}

/// The progress of one run: `len` units of work (steps, or parts of the time span).
pub struct Progress {
    make: Option<MakeBar>,
    start: Instant,
    len: u64,
    bar: Option<Box<dyn Bar>>,
    /// The next position at which the bar is redrawn.
    next_draw: u64,
    /// Set when a tick saw the stop flag.
    stopped: bool,
}

impl Progress {
    /// A run of `len` units; a bar is made (after [`SHOW_AFTER`]) only with `make`.
    pub fn new(make: Option<MakeBar>, len: u64) -> Self {
        Self {
            make,
            start: Instant::now(),
            len: len.max(1),
            bar: None,
            next_draw: 0,
            stopped: false,
        }
    }

    /// One step done: `done` units of `len`, at time `t`. Breaks when Ctrl-C was pressed. No
    /// allocation, except when the bar is created or redrawn (at most 1000 times a run).
    pub fn tick(&mut self, done: u64, t: f64) -> ControlFlow<()> {
        if stop_requested() {
            self.stopped = true;
            return ControlFlow::Break(());
        }
        let Some(make) = self.make else {
            return ControlFlow::Continue(());
        };
        if done < self.next_draw {
            return ControlFlow::Continue(());
        }
        if self.bar.is_none() {
            if self.start.elapsed() < SHOW_AFTER {
                return ControlFlow::Continue(());
            }
            self.bar = Some(make(self.len));
        }
        if let Some(bar) = &mut self.bar {
            bar.draw(done.min(self.len), t);
        }
        self.next_draw = done + self.len.div_ceil(REDRAWS);
        ControlFlow::Continue(())
    }

    /// Whether the run was stopped by Ctrl-C.
    pub fn stopped(&self) -> bool {
        self.stopped
    }
}

/// The error of a run stopped by Ctrl-C after storing the results at `times` (exit code 130;
/// the results are written and marked partial).
pub fn interrupted(times: &[f64]) -> crate::diag::Error {
    crate::diag::Error {
        kind: crate::diag::ErrorKind::Interrupted,
        location: None,
        message: format!(
            "stopped by Ctrl-C at t = {} s",
            times.last().copied().unwrap_or(f64::NAN)
        ),
    }
}
