//! Where a run's files go while it runs: the seam between the analyses (this crate) and the
//! command's output directory (`cardan-cli`'s `OutputDir`, which writes into a temporary
//! sibling renamed into place). A library caller passes none and keeps every frame in memory
//! (the Python package).
//!
//! - [`OutputFiles`]: the streamed CSV files a run creates at its first frame and writes row by
//!   row ([`crate::analysis::stream`]), and the plot files announced beside them.
//! - [`Tap`] and [`FrameTap`]: a further file written from every frame (an ASMT run's
//!   `*.solved.asmt`), taken as the frames pass ([`crate::analysis::stream`]).

use crate::diag::Error;
use cardan_dynamics::DynamicResults;
use cardan_mechanism::Results;
use std::io::{BufWriter, Write};

/// A file written piece by piece while a run goes on (a streamed CSV table).
pub trait StreamFile: Write + Send {
    /// After the last write: the file's own error, if it could not be made at all (a file
    /// created on another thread reports its creation error here even if nothing was written).
    ///
    /// # Errors
    /// The creation or write error of the file.
    fn close(self: Box<Self>) -> std::io::Result<()>;
}

impl StreamFile for std::fs::File {
    fn close(self: Box<Self>) -> std::io::Result<()> {
        Ok(())
    }
}

/// A streamed file with its buffer.
pub type StreamWriter = BufWriter<Box<dyn StreamFile>>;

/// Where a run's streamed files are created (the command's output directory).
pub trait OutputFiles {
    /// Opens `name` for a file written row by row while the run goes on.
    ///
    /// # Errors
    /// An output error naming the file and the cause.
    fn create(&mut self, name: &str) -> Result<StreamWriter, Error>;

    /// Says that the plot files of the table `name` will be written (so they can be created
    /// while the run goes on).
    ///
    /// # Errors
    /// An output error naming the directory and the cause.
    fn announce_plots_of(&mut self, name: &str) -> Result<(), Error>;

    /// The error of a failed write of `name`, as the command says it.
    fn write_error(&self, name: &str, e: &std::io::Error) -> Error;
}

/// A file written from every frame besides the CSV files: the `TimeSeries` of an ASMT run's
/// `*.solved.asmt` (`cardan-cli`'s `SolvedSeries`).
pub trait Tap<F> {
    /// The file's name (for a write error).
    fn name(&self) -> &str;
    /// Takes one frame (results holding one time).
    ///
    /// # Errors
    /// A write error.
    fn frame(&mut self, frame: &F) -> std::io::Result<()>;
}

/// A file written from every frame of a kinematic, inverse dynamics or dynamic run.
pub trait FrameTap: Tap<Results> + Tap<DynamicResults> {}

impl<T: Tap<Results> + Tap<DynamicResults>> FrameTap for T {}

/// Streamed files written straight into an existing directory: no lock and no atomic
/// replacement (the command's output directory does both), for a library caller that manages
/// its own directory, and for tests.
#[derive(Debug, Clone)]
pub struct Directory(pub std::path::PathBuf);

impl OutputFiles for Directory {
    fn create(&mut self, name: &str) -> Result<StreamWriter, Error> {
        let path = self.0.join(name);
        let file = std::fs::File::create(&path).map_err(|e| self.write_error(name, &e))?;
        Ok(BufWriter::new(Box::new(file)))
    }
    fn announce_plots_of(&mut self, _name: &str) -> Result<(), Error> {
        Ok(())
    }
    fn write_error(&self, name: &str, e: &std::io::Error) -> Error {
        Error::output(format!(
            "cannot write {}: {}",
            self.0.join(name).display(),
            crate::diag::describe_io(e)
        ))
    }
}
