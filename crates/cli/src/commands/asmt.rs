//! ASMT files on the command line: `cardan import` (the imported model written whole or not at
//! all) and an ASMT run's `<stem>.solved.asmt`, streamed with the run's other outputs
//! ([`SolvedSeries`]). Reading and importing is the model library's
//! ([`cardan_model::asmt`]).

use crate::output::OutputDir;
use cardan_asmt::series::write_block;
use cardan_asmt::solved::SeriesPlan;
use cardan_asmt::transpose::Transposer;
use cardan_model::analysis::stream::Tap;
use cardan_model::asmt::{import_source, AsmtOptions, Units};
use cardan_model::diag::{Error, Source};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `cardan import MODEL.asmt|MODEL.urdf [-o MODEL.toml] [--units si|mm] [--base …]`: writes the
/// equivalent cardan model (to stdout without `-o`).
///
/// # Errors
/// Unreadable or bad ASMT or URDF file, unwritable output.
pub fn import(
    path: &Path,
    output: Option<&Path>,
    options: AsmtOptions,
    out: &mut dyn Write,
) -> Result<(), Error> {
    let src = Source::read(path)?;
    let (model, warnings) = if cardan_model::urdf::is_urdf(path) {
        cardan_model::urdf::import_source(&src, options.urdf, true)?
    } else {
        import_source(&src, options.units, options.analysis)?
    };
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    match output {
        Some(o) => {
            if crate::output::single::same_file(path, o) {
                return Err(Error::usage(format!(
                    "the output {} is the input file {}: importing would overwrite the \
                     file with its cardan model; write to another file (e.g. -o {})",
                    o.display(),
                    path.display(),
                    path.with_extension("toml").display()
                )));
            }
            crate::output::single::write_atomically(o, |w| w.write_all(model.text.as_bytes()))?;
            writeln!(out, "wrote {} ({} warnings)", o.display(), warnings.len())
                .map_err(|e| Error::output(e.to_string()))?;
        }
        None => out
            .write_all(model.text.as_bytes())
            .map_err(|e| Error::output(e.to_string()))?,
    }
    Ok(())
}

/// Values of the solved TimeSeries held in memory (8 bytes each) before its frames spill to a
/// scratch file ([`cardan_asmt::transpose`]): a few megabytes, whatever the run's length.
const SERIES_BUDGET: usize = 1 << 19;

/// The file `<stem>.solved.asmt` of a run of an ASMT file, written as the run goes: the input
/// with a TimeSeries of the run's frames in OndselSolver's conventions
/// ([`cardan_asmt::solved`]: part-frame origins, exact Bryant angles, velocities and
/// accelerations) and, when the run computes reactions (inverse dynamics or dynamics), the
/// reaction series of every joint and motion, in the file's units. The TimeSeries is written a
/// quantity per row, a run computes a time per frame: the frames go through a
/// [`Transposer`] that spills them to a scratch file in the
/// output directory, so memory is bounded whatever the run's length. `cardan run` takes every
/// frame into it (`cardan_model::analysis::stream::Tap`) and writes it with the other outputs,
/// inside the output directory's atomic commit ([`crate::output`]).
pub struct SolvedSeries {
    /// `<stem>.solved.asmt`.
    name: String,
    /// The input up to its TimeSeries (if any).
    prefix: String,
    doc: cardan_asmt::Document,
    import: cardan_asmt::Import,
    /// Lengths from the analysis's SI to the file's units.
    length_factor: f64,
    /// Where the frames spill.
    spill: PathBuf,
    /// The plan and the frames, from the first frame on.
    started: Option<(SeriesPlan, Transposer)>,
    values: Vec<f64>,
}

impl SolvedSeries {
    /// The solved file of a run of the ASMT file `path` read in `units`, spilling into `dir`.
    ///
    /// # Errors
    /// Unreadable or bad input, or the output directory cannot be created.
    pub fn new(path: &Path, units: Units, dir: &mut OutputDir) -> Result<Self, Error> {
        let src = Source::read(path)?;
        let doc = cardan_asmt::read_model(&src.text).map_err(|e| Error::input(e.to_string()))?;
        let (doc, length_factor) = match units {
            Units::Si => (doc, 1.0),
            Units::Mm => (doc.scaled(1e-3), 1e3),
        };
        let import = cardan_asmt::import(&doc).map_err(|e| Error::input(e.to_string()))?;
        let stem = path
            .file_stem()
            .map_or_else(|| "model".into(), |s| s.to_string_lossy().into_owned());
        let name = format!("{stem}.solved.asmt");
        Ok(Self {
            spill: dir.scratch(&format!("{name}.spill"))?,
            prefix: cardan_asmt::solved::before_time_series(&src.text),
            name,
            doc,
            import,
            length_factor,
            started: None,
            values: Vec::new(),
        })
    }

    /// Takes every time of `results` (with `dynamics`, its reactions too).
    fn take(
        &mut self,
        results: &cardan_mechanism::Results,
        dynamics: Option<&cardan_dynamics::DynamicResults>,
    ) -> std::io::Result<()> {
        let (plan, frames) = self.started.get_or_insert_with(|| {
            let plan = SeriesPlan::new(
                &self.doc,
                &self.import,
                results,
                dynamics,
                self.length_factor,
            );
            let rows = 1 + plan.rows();
            (
                plan,
                Transposer::new(rows, SERIES_BUDGET, self.spill.clone()),
            )
        });
        for (k, &t) in results.times.iter().enumerate() {
            self.values.clear();
            self.values.push(t);
            plan.frame(results, dynamics, k, &mut self.values);
            frames.push(&self.values)?;
        }
        Ok(())
    }

    /// Writes the file into `dir` (the spill file is removed).
    ///
    /// # Errors
    /// A write error.
    pub fn write(self, dir: &mut OutputDir) -> Result<(), Error> {
        let mut w = dir.create(&self.name)?;
        let written = w.write_all(self.prefix.as_bytes()).and_then(|()| {
            let Some((plan, mut frames)) = self.started else {
                return Ok(());
            };
            let n = frames.frames();
            write_block(&mut w, n, plan.items(), &mut |i, emit| frames.row(i, emit))
        });
        written.map_err(|e| dir.write_error(&self.name, &e))?;
        dir.finish(&self.name, w)
    }
}

impl Tap<cardan_mechanism::Results> for SolvedSeries {
    fn name(&self) -> &str {
        &self.name
    }
    fn frame(&mut self, frame: &cardan_mechanism::Results) -> std::io::Result<()> {
        self.take(frame, None)
    }
}

impl Tap<cardan_dynamics::DynamicResults> for SolvedSeries {
    fn name(&self) -> &str {
        &self.name
    }
    fn frame(&mut self, frame: &cardan_dynamics::DynamicResults) -> std::io::Result<()> {
        self.take(&frame.kinematics, Some(frame))
    }
}
