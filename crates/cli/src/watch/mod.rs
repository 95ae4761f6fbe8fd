//! `cardan watch MODEL [--port N]`: the live preview. A page on the loopback interface shows
//! the model's report (3D view and plots, as `cardan run` writes it) and re-solves when the
//! file is saved or a parameter's slider moves.
//!
//! Three threads share one [`State`]: the watcher polls the file every
//! [`POLL`] (its modification time, length and kind: an editor that saves by renaming a new
//! file over the old one, a file deleted or replaced by a directory are all seen) and marks it
//! dirty; the solver solves whenever it is dirty ([`solve`]) and publishes a new version; the
//! server ([`server`]) answers the page: `/` the page, `/report` the latest report,
//! `/update` the same solve for the page's viewer to show in place (no page load: the view,
//! time and toggles stay), `/state?after=N` a long poll that returns when the version passes
//! N, `POST /set` the sliders' values, `POST /drag` the steps of a body dragged with the mouse
//! ([`drag`]). Polling rather than file-system notifications: one `stat` every 50 ms is
//! free, sees every way a file can change (including the atomic renames of editors, which
//! notification APIs report as a remove on the old inode) and needs no platform code.
//!
//! Ctrl-C ends it: the threads see the stop flag within a poll and the command returns.

pub mod drag;
pub mod server;
pub mod solve;

use std::path::{Path, PathBuf};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant, SystemTime};

/// How often the file is looked at.
pub const POLL: Duration = Duration::from_millis(50);

/// What the page sees.
#[derive(Debug, Default)]
pub struct State {
    /// Increases with every solve.
    pub version: u64,
    /// The latest solve.
    pub solved: solve::Solved,
    /// The sliders' values: `--set` pairs.
    pub set: Vec<(String, String)>,
    /// The slider ranges, fixed when a parameter first appears (model units).
    pub ranges: Vec<(String, f64, f64)>,
    /// The latest solve's wall time (s).
    pub seconds: f64,
    /// A solve is wanted.
    pub dirty: bool,
}

/// The state and the condition the solver and the long polls wait on.
#[derive(Debug, Default)]
pub struct Shared {
    /// The state.
    pub state: Mutex<State>,
    /// Signalled on every change.
    pub changed: Condvar,
    /// The drag in progress (the page's Ctrl-drag of a body), apart from the state: its steps
    /// do not hold up the long polls.
    pub drag: Mutex<Option<drag::Session>>,
}

impl Shared {
    /// Runs `f` on the state and wakes every waiter.
    pub fn update(&self, f: impl FnOnce(&mut State)) {
        if let Ok(mut s) = self.state.lock() {
            f(&mut s);
        }
        self.changed.notify_all();
    }
}

/// What the watcher compares: the modification time, length and whether it is a file.
fn stamp(path: &Path) -> Option<(SystemTime, u64, bool)> {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok()?, m.len(), m.is_file()))
}

fn stopped() -> bool {
    cardan_model::progress::stop_requested()
}

/// Polls `path` and marks the state dirty when it changes.
fn watcher(path: &Path, shared: &Shared) {
    let mut last = stamp(path);
    while !stopped() {
        std::thread::sleep(POLL);
        let now = stamp(path);
        if now != last {
            last = now;
            shared.update(|s| s.dirty = true);
        }
    }
    shared.update(|_| {});
}

/// How long the solver lets a change settle before it reads the file: an editor that saves in
/// place truncates the file and then writes it, and the watcher may see the file in between.
pub const SETTLE: Duration = Duration::from_millis(10);

/// The file's text, or why it cannot be read (a missing file and a directory differ).
type Text = Result<Vec<u8>, std::io::ErrorKind>;

/// Solves whenever the state is dirty and publishes each solve as a new version. It reads the
/// file [`SETTLE`] after a change; a change that leaves the file's text (or its read error) and
/// the sliders as they were last solved (a save without an edit, the second change event of an
/// in-place save) is not solved again, so the page does not reload the same solution.
fn solver(path: &Path, shared: &Shared) {
    let mut last: Option<(Text, Vec<(String, String)>)> = None;
    loop {
        let set = {
            let Ok(mut s) = shared.state.lock() else {
                return;
            };
            while !s.dirty && !stopped() {
                s = match shared.changed.wait_timeout(s, POLL) {
                    Ok((s, _)) => s,
                    Err(_) => return,
                };
            }
            if stopped() {
                return;
            }
            s.dirty = false;
            s.set.clone()
        };
        std::thread::sleep(SETTLE);
        let input = (std::fs::read(path).map_err(|e| e.kind()), set);
        if last.as_ref() == Some(&input) {
            continue;
        }
        let set = &input.1;
        let start = Instant::now();
        let solved = solve::solve(path, set);
        let seconds = start.elapsed().as_secs_f64();
        shared.update(|s| {
            for sl in &solved.sliders {
                if !s.ranges.iter().any(|r| r.0 == sl.name) {
                    let (lo, hi) = range(sl.value);
                    s.ranges.push((sl.name.clone(), lo, hi));
                }
            }
            s.version += 1;
            s.solved = solved;
            s.seconds = seconds;
        });
        last = Some(input);
    }
}

/// A slider's range about the file's value: ±50 %, or ±1 about zero.
fn range(v: f64) -> (f64, f64) {
    if v == 0.0 {
        (-1.0, 1.0)
    } else {
        let d = 0.5 * v.abs();
        (v - d, v + d)
    }
}

/// `cardan watch`: serves the preview of `model` on 127.0.0.1:`port` (0: a free port), prints
/// its address and runs until Ctrl-C.
///
/// # Errors
/// The port cannot be bound; the model file does not exist when the preview starts.
pub fn watch(
    model: &Path,
    port: u16,
    out: &mut dyn std::io::Write,
) -> Result<(), cardan_model::diag::Error> {
    use cardan_model::diag::Error;
    if !model.exists() {
        return Err(Error::input(format!(
            "the model file {} does not exist",
            model.display()
        )));
    }
    crate::progress::catch_ctrl_c();
    let server = tiny_http::Server::http(("127.0.0.1", port)).map_err(|e| {
        Error::usage(format!(
            "cannot serve on 127.0.0.1:{port}: {e} (give another --port, or 0 for a free one)"
        ))
    })?;
    let port = server.server_addr().to_ip().map_or(port, |a| a.port());
    let shared = Shared::default();
    shared.update(|s| s.dirty = true);
    let path: PathBuf = model.to_path_buf();
    writeln!(
        out,
        "cardan watch: http://127.0.0.1:{port}/ shows {} and re-solves on every save (Ctrl-C ends)",
        model.display()
    )
    .and_then(|()| out.flush())
    .map_err(|e| Error::output(format!("cannot print: {e}")))?;
    std::thread::scope(|s| {
        s.spawn(|| watcher(&path, &shared));
        s.spawn(|| solver(&path, &shared));
        server::serve(&server, port, &shared);
    });
    Ok(())
}
