//! The command's side of long runs: the progress bar on the terminal (indicatif) and Ctrl-C.
//!
//! The analyses tick a [`cardan_model::progress::Progress`] every step; a run given
//! [`terminal_bar`] (stderr is a terminal and not `--quiet`) draws this bar once it has taken a
//! second. The first Ctrl-C sets the model library's stop flag (the run stops at its next step
//! and keeps its results: written, marked partial, exit code 130); a second one ends the
//! process at once.

use cardan_model::progress::{stop_flag, Bar};
use std::sync::{Arc, OnceLock};

/// Installs the SIGINT handler (once per process): the first Ctrl-C sets the stop flag, a
/// second one exits with code 130.
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

/// The bar on stderr: position, percentage, the time reached and the estimated time left.
struct Terminal(indicatif::ProgressBar);

impl Bar for Terminal {
    fn draw(&mut self, done: u64, t: f64) {
        self.0.set_position(done);
        self.0.set_message(format!("{t:.6}"));
    }
}

impl Drop for Terminal {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

/// The terminal bar of a run of `len` units ([`cardan_model::progress::MakeBar`]).
pub fn terminal_bar(len: u64) -> Box<dyn Bar> {
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{wide_bar} {percent:>3}% t = {msg} s, eta {eta} (Ctrl-C: stop, keep results)",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Box::new(Terminal(bar))
}
