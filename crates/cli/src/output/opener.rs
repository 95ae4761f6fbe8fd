//! Creating a run's files on a second thread.
//!
//! Creating a file is kernel work: an inode allocated, a directory entry added. The 23 files
//! of a dynamic run cost it 1–5 ms on ext4, the more the more files were deleted in the last
//! half minute (without a journal, ext4 looks past recently deleted inodes one by one), which
//! is a quarter of a small model's whole run. A run knows most of its file names long before
//! it writes them: the report's files when it starts, the CSV files and their plots at its
//! first frame. [`Opener`] creates them on a second thread while the analysis runs; a file is
//! waited for only when its first bytes are written ([`PendingFile`]).
//!
//! The files are the same, created in the same directory; only the thread that asks the kernel
//! for them differs. Where no thread can be started, a file is created when it is asked for.

use std::fs::File;
use std::io::{ErrorKind, Write};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread::JoinHandle;

/// The outcome of creating one file.
type Created = std::io::Result<File>;

/// A file to create and where to send it.
struct Request {
    path: PathBuf,
    reply: Sender<Created>,
}

/// The thread creating files (module docs), started with the first request.
#[derive(Debug, Default)]
pub struct Opener {
    to: Option<Sender<Request>>,
    thread: Option<JoinHandle<()>>,
    /// No thread could be started: files are created when asked for.
    inline: bool,
}

impl Opener {
    /// Starts creating `path` (truncated if it exists) and returns it, to be waited for at its
    /// first write.
    pub fn open(&mut self, path: PathBuf) -> PendingFile {
        let (reply, created) = channel();
        let request = Request { path, reply };
        let sent = match self.sender() {
            Some(to) => to.send(request).map_err(|e| e.0),
            None => Err(request),
        };
        match sent {
            Ok(()) => PendingFile {
                state: State::Waiting(created),
            },
            // No thread (or it is gone): create it here.
            Err(r) => PendingFile::create_now(&r.path),
        }
    }

    /// The request channel, the thread started on first use.
    fn sender(&mut self) -> Option<&Sender<Request>> {
        if self.to.is_none() && !self.inline {
            let (to, requests) = channel::<Request>();
            let spawned = std::thread::Builder::new()
                .name("cardan-files".into())
                .spawn(move || {
                    for r in requests {
                        let _ = r.reply.send(File::create(&r.path));
                    }
                });
            match spawned {
                Ok(thread) => {
                    self.to = Some(to);
                    self.thread = Some(thread);
                }
                Err(_) => self.inline = true,
            }
        }
        self.to.as_ref()
    }

    /// Waits until every file asked for is created (or failed).
    pub fn stop(&mut self) {
        self.to = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Opener {
    fn drop(&mut self) {
        self.stop();
    }
}

/// A file being created by an [`Opener`]: writes wait for it, then go to it. A creation error
/// is the error of every write.
#[derive(Debug)]
pub struct PendingFile {
    state: State,
}

#[derive(Debug)]
enum State {
    Waiting(Receiver<Created>),
    Open(File),
    /// Creating it failed: the error's kind and message, for every write.
    Failed(ErrorKind, String),
}

impl PendingFile {
    /// A file created here and now.
    pub fn create_now(path: &std::path::Path) -> Self {
        let state = match File::create(path) {
            Ok(f) => State::Open(f),
            Err(e) => State::Failed(e.kind(), e.to_string()),
        };
        Self { state }
    }

    /// The file, once created.
    ///
    /// # Errors
    /// Creating it failed.
    pub fn file(&mut self) -> std::io::Result<&mut File> {
        if let State::Waiting(created) = &self.state {
            self.state = match created.recv() {
                Ok(Ok(f)) => State::Open(f),
                Ok(Err(e)) => State::Failed(e.kind(), e.to_string()),
                Err(_) => State::Failed(ErrorKind::Other, "the file was not created".into()),
            };
        }
        match &mut self.state {
            State::Open(f) => Ok(f),
            State::Failed(kind, message) => Err(std::io::Error::new(*kind, message.clone())),
            State::Waiting(_) => unreachable!("resolved above"),
        }
    }
}

impl From<File> for PendingFile {
    fn from(f: File) -> Self {
        Self {
            state: State::Open(f),
        }
    }
}

impl cardan_model::files::StreamFile for PendingFile {
    fn close(mut self: Box<Self>) -> std::io::Result<()> {
        self.file().map(drop)
    }
}

impl Write for PendingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file()?.write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        self.file()?.write_all(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file()?.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cardan-opener-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn files_are_created_and_written() {
        let d = scratch("ok");
        let mut o = Opener::default();
        let mut a = o.open(d.join("a.csv"));
        let mut b = o.open(d.join("b.svg"));
        b.write_all(b"bee").unwrap();
        a.write_all(b"ay").unwrap();
        o.stop();
        assert_eq!(std::fs::read_to_string(d.join("a.csv")).unwrap(), "ay");
        assert_eq!(std::fs::read_to_string(d.join("b.svg")).unwrap(), "bee");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_creation_error_is_every_writes_error() {
        let d = scratch("err");
        let mut o = Opener::default();
        let mut f = o.open(d.join("missing/x.csv"));
        for _ in 0..2 {
            let e = f.write_all(b"x").unwrap_err();
            assert_eq!(e.kind(), ErrorKind::NotFound, "{e}");
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}
