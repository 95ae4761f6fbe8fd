//! Long runs: a progress bar with an estimate of the time left, and Ctrl-C.
//!
//! Every analysis loop (the kinematic grid, the integrators, the two passes of inverse
//! dynamics) calls [`Progress::tick`] once per step. The bar appears on stderr only once a run
//! has taken [`SHOW_AFTER`] (a run expected to be quick never flickers a bar), and only when
//! asked (stderr is a terminal and not `--quiet`). [`Progress::tick`] also reads the Ctrl-C flag
//! set by [`catch_ctrl_c`]: the loop then stops and the run keeps its results so far (written,
//! marked partial, exit code 130). A second Ctrl-C ends the process at once.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// A run that has taken this long shows its progress bar.
pub const SHOW_AFTER: Duration = Duration::from_secs(1);

/// Redraws of the bar per run (at most; indicatif rate-limits the terminal writes too).
const REDRAWS: u64 = 1000;

/// The Ctrl-C flag (set by the signal handler, read by every step).
fn stop_flag() -> &'static Arc<AtomicBool> {
    static STOP: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    STOP.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// Installs the SIGINT handler (once per process): the first Ctrl-C sets the stop flag, a
/// second one exits with code 130. Without the handler (library use, tests) nothing stops.
pub fn catch_ctrl_c() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let flag = Arc::clone(stop_flag());
        // Order matters: the conditional exit sees the flag as it was before this signal.
        let _ = signal_hook::flag::register_conditional_shutdown(
            signal_hook::consts::SIGINT,
            130,
            Arc::clone(&flag),
        );
        let _ = signal_hook::flag::register(signal_hook::consts::SIGINT, flag);
    });
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
    show: bool,
    start: Instant,
    len: u64,
    bar: Option<indicatif::ProgressBar>,
    /// The next position at which the bar is redrawn.
    next_draw: u64,
    /// Set when a tick saw the stop flag.
    stopped: bool,
}

impl Progress {
    /// A run of `len` units; the bar is shown (after [`SHOW_AFTER`]) only when `show`.
    pub fn new(show: bool, len: u64) -> Self {
        Self {
            show,
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
        if !self.show || done < self.next_draw {
            return ControlFlow::Continue(());
        }
        if self.bar.is_none() {
            if self.start.elapsed() < SHOW_AFTER {
                return ControlFlow::Continue(());
            }
            self.bar = Some(self.new_bar());
        }
        if let Some(bar) = &self.bar {
            bar.set_position(done.min(self.len));
            bar.set_message(format!("{t:.6}"));
        }
        self.next_draw = done + self.len.div_ceil(REDRAWS);
        ControlFlow::Continue(())
    }

    /// Whether the run was stopped by Ctrl-C.
    pub fn stopped(&self) -> bool {
        self.stopped
    }

    fn new_bar(&self) -> indicatif::ProgressBar {
        let bar = indicatif::ProgressBar::new(self.len);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{wide_bar} {percent:>3}% t = {msg} s, eta {eta} (Ctrl-C: stop, keep results)",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
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
