//! The threads analyses run on, kept for the next run.
//!
//! A run goes to another thread so that the calling thread can watch for Ctrl-C (the module
//! docs of the crate). Starting a thread for each run cost about a tenth of a millisecond here,
//! a tenth of a small ASMT file's whole `cardan.load(f).run()`; a thread that finished a run
//! now waits for the next one instead (at most [`MAX_IDLE`] wait; one more is started when all
//! are busy, so runs from several Python threads still run side by side).
//!
//! A process forked from this one (multiprocessing's `fork`) has none of its threads: the
//! waiting list is keyed by the process id and starts empty in the child.

use std::sync::{mpsc, Mutex};

/// A run, with everything it needs moved in (it sends its own result).
type Job = Box<dyn FnOnce() + Send>;

/// Threads kept waiting at most.
const MAX_IDLE: usize = 8;

/// The waiting threads (a sender to each one's queue) and the process they belong to.
static IDLE: Mutex<(u32, Vec<mpsc::Sender<Job>>)> = Mutex::new((0, Vec::new()));

/// A waiting thread of this process, if any.
fn take_idle() -> Option<mpsc::Sender<Job>> {
    let mut idle = IDLE.lock().ok()?;
    let pid = std::process::id();
    if idle.0 != pid {
        *idle = (pid, Vec::new());
    }
    idle.1.pop()
}

/// Puts a thread that finished its job back on the waiting list; `false` when the list is full
/// (the thread then ends).
fn wait_again(me: &mpsc::Sender<Job>) -> bool {
    let Ok(mut idle) = IDLE.lock() else {
        return false;
    };
    if idle.0 != std::process::id() || idle.1.len() >= MAX_IDLE {
        return false;
    }
    idle.1.push(me.clone());
    true
}

/// Runs `job` on a waiting thread, or on a new one.
///
/// # Errors
/// The operating system refused a new thread.
pub fn run(job: impl FnOnce() + Send + 'static) -> std::io::Result<()> {
    let mut job: Job = Box::new(job);
    while let Some(worker) = take_idle() {
        match worker.send(job) {
            Ok(()) => return Ok(()),
            // Its thread has ended (a run panicked): try the next.
            Err(mpsc::SendError(back)) => job = back,
        }
    }
    let (me, jobs) = mpsc::channel::<Job>();
    me.send(job)
        .map_err(|_| std::io::Error::other("a new thread's queue closed"))?;
    std::thread::Builder::new()
        .name("cardan-run".into())
        .spawn(move || {
            while let Ok(job) = jobs.recv() {
                job();
                if !wait_again(&me) {
                    return;
                }
            }
        })
        .map(drop)
}
