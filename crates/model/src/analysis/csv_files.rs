//! The CSV files of a streamed run ([`super::stream`]): each frame's rows, converted to the
//! model's units and formatted ([`push_csv_row`]), written as the frames come.
//!
//! A long run formats and writes them on a second thread: in a 10,000-step kinematic run of
//! the slider-crank the formatting is a fifth of the instructions, and the writes add kernel
//! time. The solver's thread then only copies each frame's rows (SI) into a batch; full batches
//! go through a bounded channel (so memory stays bounded when the disk is slower than the
//! solver) and come back empty for reuse. Rows reach each file in frame order either way, so the
//! files are the same byte for byte. A short run (fewer than [`THREAD_MIN_VALUES`] values in
//! all) or a one-core machine writes on the solver's thread: starting a thread would cost more
//! than it saves.

use crate::files::StreamWriter;
use crate::table::push_csv_row;
use crate::units::UnitSystem;
#[cfg(test)]
use std::io::BufWriter;
use std::io::Write as _;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

/// Values (over all files and frames) from which a run writes on a second thread.
pub const THREAD_MIN_VALUES: usize = 200_000;

/// Values per batch handed to the writing thread.
const BATCH_VALUES: usize = 1 << 16;

/// Batches in flight between the two threads.
const BATCHES_IN_FLIGHT: usize = 2;

/// A write error: the file's name and the cause.
pub type WriteError = (String, std::io::Error);

/// One CSV file being written.
pub struct CsvFile {
    /// Its name (`points.csv`).
    pub name: String,
    /// Its writer, header written.
    pub writer: StreamWriter,
    /// The columns' factors from SI to the model's units ([`UnitSystem::convert_columns`]).
    pub factors: Vec<f64>,
}

/// Formats and writes frames' rows into `files`.
struct Formatter {
    files: Vec<CsvFile>,
    units: UnitSystem,
    text: String,
}

impl Formatter {
    /// Writes the frames of `values`: per frame, each file's row (time, then its columns), in
    /// SI; converted in place.
    fn write(&mut self, values: &mut [f64]) -> Result<(), WriteError> {
        let width: usize = self.files.iter().map(|f| f.factors.len() + 1).sum();
        for frame in values.chunks_mut(width.max(1)) {
            let mut at = 0;
            for f in &mut self.files {
                let row = &mut frame[at..at + f.factors.len() + 1];
                at += row.len();
                self.units.convert_row(row, &f.factors);
                self.text.clear();
                push_csv_row(&mut self.text, row);
                let written = f.writer.write_all(self.text.as_bytes());
                written.map_err(|e| (f.name.clone(), e))?;
            }
        }
        Ok(())
    }
}

/// The second thread's side.
struct Writer {
    /// Full batches to it; `None` once it stopped.
    to: Option<SyncSender<Vec<f64>>>,
    /// Emptied batches back.
    back: Receiver<Vec<f64>>,
    thread: Option<JoinHandle<Result<Vec<CsvFile>, WriteError>>>,
    /// The batch being filled.
    batch: Vec<f64>,
}

/// Where the rows are written.
enum Mode {
    Here(Formatter),
    Thread(Writer),
}

/// The CSV files of a run (module docs).
pub struct CsvFiles {
    mode: Mode,
}

impl CsvFiles {
    /// Files `files`, rows in `units`: written on a second thread when `threaded` (see
    /// [`CsvFiles::should_thread`]).
    pub fn new(files: Vec<CsvFile>, units: UnitSystem, threaded: bool) -> Self {
        let formatter = Formatter {
            files,
            units,
            text: String::new(),
        };
        if !threaded {
            return Self {
                mode: Mode::Here(formatter),
            };
        }
        let (to, from) = sync_channel::<Vec<f64>>(BATCHES_IN_FLIGHT);
        let (back_to, back) = sync_channel::<Vec<f64>>(BATCHES_IN_FLIGHT + 2);
        let thread = std::thread::spawn(move || {
            let mut formatter = formatter;
            for mut batch in from {
                formatter.write(&mut batch)?;
                batch.clear();
                let _ = back_to.try_send(batch);
            }
            Ok(formatter.files)
        });
        Self {
            mode: Mode::Thread(Writer {
                to: Some(to),
                back,
                thread: Some(thread),
                batch: Vec::with_capacity(BATCH_VALUES),
            }),
        }
    }

    /// Whether a run of `planned` frames of `values_per_frame` values writes on a second thread:
    /// a long run, on a machine with two cores or more.
    pub fn should_thread(planned: usize, values_per_frame: usize) -> bool {
        planned.saturating_mul(values_per_frame) >= THREAD_MIN_VALUES
            && std::thread::available_parallelism().is_ok_and(|n| n.get() > 1)
    }

    /// Takes one frame: `rows` holds each file's row in file order (time, then its columns), in
    /// SI.
    ///
    /// # Errors
    /// A write error (on the second thread: the first one it met).
    pub fn frame(&mut self, rows: &mut [f64]) -> Result<(), WriteError> {
        match &mut self.mode {
            Mode::Here(f) => f.write(rows),
            Mode::Thread(w) => {
                w.batch.extend_from_slice(rows);
                // Sent when the next frame of the same size would not fit.
                if w.batch.len() + rows.len() > BATCH_VALUES {
                    w.send()?;
                }
                Ok(())
            }
        }
    }

    /// Writes what is left and returns the files (header and rows written, not yet flushed).
    ///
    /// # Errors
    /// A write error.
    pub fn finish(self) -> Result<Vec<(String, StreamWriter)>, WriteError> {
        let files = match self.mode {
            Mode::Here(f) => f.files,
            Mode::Thread(mut w) => {
                if !w.batch.is_empty() {
                    w.send()?;
                }
                w.to = None;
                w.join()?
            }
        };
        Ok(files.into_iter().map(|f| (f.name, f.writer)).collect())
    }
}

impl Writer {
    /// Hands the batch to the thread and takes an emptied one back (or a new one). If the
    /// thread stopped, its error.
    fn send(&mut self) -> Result<(), WriteError> {
        let next = self
            .back
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BATCH_VALUES));
        let full = std::mem::replace(&mut self.batch, next);
        let sent = self.to.as_ref().map(|to| to.send(full));
        if matches!(sent, Some(Ok(()))) {
            return Ok(());
        }
        // The thread stopped at a write error: its result says which.
        self.to = None;
        self.join().map(drop)
    }

    /// Waits for the thread: its files, or its write error.
    fn join(&mut self) -> Result<Vec<CsvFile>, WriteError> {
        let stopped = || {
            (
                "a CSV file".to_string(),
                std::io::Error::other("the writer stopped"),
            )
        };
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(panic)) => std::panic::resume_unwind(panic),
            None => Err(stopped()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two files (2 and 1 columns) in a scratch directory; `n` frames written, here or on the
    /// second thread; the files' texts.
    fn write(n: usize, threaded: bool, units: UnitSystem) -> Vec<String> {
        let dir = std::env::temp_dir().join(format!(
            "cardan-csv-files-{}-{threaded}-{units:?}",
            std::process::id()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let file = |name: &str, factors: Vec<f64>| CsvFile {
            name: name.into(),
            writer: BufWriter::new(Box::new(std::fs::File::create(dir.join(name)).unwrap())),
            factors,
        };
        let files = vec![file("a.csv", vec![1.0, 1e3]), file("b.csv", vec![1e3])];
        let mut csv = CsvFiles::new(files, units, threaded);
        for k in 0..n {
            let t = k as f64 * 1e-3;
            let mut rows = [t, 0.5 * t, 2.0 + t, t, -t];
            csv.frame(&mut rows).unwrap();
        }
        let texts = csv
            .finish()
            .unwrap()
            .into_iter()
            .map(|(name, w)| {
                drop(w.into_inner().map_err(|e| e.into_error()).unwrap());
                std::fs::read_to_string(dir.join(name)).unwrap()
            })
            .collect();
        let _ = std::fs::remove_dir_all(&dir);
        texts
    }

    /// A file the thread cannot write (opened read-only): its error, with the file's name,
    /// reaches the solver's thread, at a later frame or at the end; nothing is lost silently.
    #[test]
    fn a_write_error_on_the_second_thread_reaches_the_run() {
        let path = std::env::temp_dir().join(format!("cardan-csv-ro-{}", std::process::id()));
        std::fs::write(&path, "").unwrap();
        let file = CsvFile {
            name: "points.csv".into(),
            writer: BufWriter::new(Box::new(std::fs::File::open(&path).unwrap())),
            factors: vec![1.0],
        };
        let mut csv = CsvFiles::new(vec![file], UnitSystem::Si, true);
        let mut failed = None;
        for k in 0..200_000 {
            if let Err(e) = csv.frame(&mut [k as f64, 1.0]) {
                failed = Some(e);
                break;
            }
        }
        let (name, _) = match failed {
            Some(e) => e,
            None => csv.finish().map(drop).expect_err("a write error"),
        };
        assert_eq!(name, "points.csv");
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn the_second_thread_writes_the_same_files() {
        // Several batches (5 values a frame), in SI and converted.
        for units in [UnitSystem::Si, UnitSystem::Mm] {
            let here = write(40_000, false, units);
            assert_eq!(here[0].lines().count(), 40_000);
            assert_eq!(here, write(40_000, true, units), "{units:?}");
        }
    }
}
