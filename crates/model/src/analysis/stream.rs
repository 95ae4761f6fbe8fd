//! A run's frames as they are computed: the [`Recorder`] is the
//! [`FrameSink`](cardan_mechanism::FrameSink) of `cardan run`'s kinematic analysis and the
//! [`DynamicSink`](cardan_dynamics::DynamicSink) of its dynamic and inverse dynamics analyses
//! (one [`Frame`] type each, written by its [`FrameLayout`]).
//!
//! Each frame's rows go straight to the CSV files (buffered writers in the output directory's
//! temporary sibling of the command's output directory, [`crate::files::OutputFiles::create`]), in the model's units, with the
//! same text as a table written whole ([`crate::table::Table::to_csv`]); a long run formats and
//! writes them on a second thread (`super::csv_files`). What is drawn from
//! the results afterwards (the SVG plots, the animation, the report, the Python package's
//! tables) reads a copy kept in memory: every frame when the run writes nothing (the Python
//! package), otherwise a decimated copy: every s-th frame, s chosen at the start so that at most
//! [`MAX_PLOTTED_FRAMES`] frames and about [`KEPT_VALUES_BUDGET`] values are kept, plus the last
//! frame, whichever it is (a run stopped by Ctrl-C or a failure included). A further file
//! written from every frame (the `*.solved.asmt` TimeSeries of an ASMT run) takes each frame
//! as it passes too, through a [`Tap`]. Peak memory is then bounded by the model's size, not
//! by the number of steps.
//!
//! The summary's numbers (steps, Newton iterations, the largest residual; for the dynamic runs
//! the constraint drift, the energy balance and its scale, the peak driver efforts: the
//! layout's [`FrameLayout::Tally`]) are taken over every frame as it passes, never from the
//! decimated copy: a residual spike between two kept frames is still the run's largest
//! residual.

use super::csv_files::{CsvFile, CsvFiles};
use super::layout::Layout;
use crate::diag::Error;
use crate::files::{OutputFiles, StreamWriter};
use crate::table::{csv_header, Table};
use crate::units::UnitSystem;
use cardan_dynamics::DynamicResults;
use cardan_mechanism::Results;
use std::io::Write as _;
use std::ops::ControlFlow;

/// A further file written from every frame (declared with the other output files,
/// [`crate::files`]; `cardan-cli` implements it here).
pub use crate::files::Tap;

/// At most this many frames are kept for the plots, the animation and the report (a plot is
/// about 1,000 pixels wide: the plots draw min/max per pixel column either way).
pub const MAX_PLOTTED_FRAMES: usize = 2_000;

/// About this many numbers (8 bytes each) are kept in memory for the plots of a large model:
/// fewer frames for more columns, at least 2 (the first and the last).
pub const KEPT_VALUES_BUDGET: usize = 4_000_000;

/// The CSV files a run wrote frame by frame and how its kept copy was decimated.
pub struct Streamed {
    /// Each streamed CSV file's name and its writer (flushed and closed by the command when
    /// the outputs are written).
    pub csv: Vec<(String, StreamWriter)>,
    /// Frames the run stored (every one is in the CSV files).
    pub frames: usize,
    /// Frames kept in memory (in the plots, the animation and the report).
    pub kept: usize,
    /// Every `stride`-th frame was kept (1: all), plus the last.
    pub stride: usize,
}

/// The frames to keep for the plots: every `stride`-th of `planned` (module docs).
fn stride(planned: usize, values_per_frame: usize) -> usize {
    let by_memory = KEPT_VALUES_BUDGET / values_per_frame.max(1);
    let keep = MAX_PLOTTED_FRAMES.min(by_memory).max(2);
    // Frames 0, s, 2s, … ≤ planned − 1, then the last: at most `keep` in all.
    planned.saturating_sub(2) / (keep - 1).max(1) + 1
}

/// "1st", "2nd", "3rd", "11th", "501st".
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// What a run streams: results holding one frame at a time, which a copy made by
/// [`Frame::empty_like`] can collect.
pub trait Frame: Default {
    /// The same layout without frames, with room for `capacity`.
    fn empty_like(&self, capacity: usize) -> Self;
    /// Appends the frames of `other` (same layout).
    fn extend_from(&mut self, other: &Self);
    /// Removes every frame, keeping the storage.
    fn clear_frames(&mut self);
    /// The frames' times.
    fn times(&self) -> &[f64];
}

impl Frame for Results {
    fn empty_like(&self, capacity: usize) -> Self {
        Results::empty_like(self, capacity)
    }
    fn extend_from(&mut self, other: &Self) {
        Results::extend_from(self, other);
    }
    fn clear_frames(&mut self) {
        Results::clear_frames(self);
    }
    fn times(&self) -> &[f64] {
        &self.times
    }
}

impl Frame for DynamicResults {
    fn empty_like(&self, capacity: usize) -> Self {
        DynamicResults::empty_like(self, capacity)
    }
    fn extend_from(&mut self, other: &Self) {
        DynamicResults::extend_from(self, other);
    }
    fn clear_frames(&mut self) {
        DynamicResults::clear_frames(self);
    }
    fn times(&self) -> &[f64] {
        DynamicResults::times(self)
    }
}

/// The output groups of a run's frames: each group's empty table and the row of any frame, so
/// that the streamed rows and the tables of the kept copy come from one code path; and what the
/// summary takes from every frame.
pub trait FrameLayout {
    /// What the run streams.
    type Frame: Frame;
    /// The summary's numbers over every frame.
    type Tally: Default;
    /// The number of groups.
    fn groups(&self) -> usize;
    /// Group `g`'s table without rows.
    fn empty_table(&self, g: usize) -> &Table;
    /// The tables without rows, in output order (the layout's own: no copy of the columns,
    /// which a model of 10⁴ bodies has 4 × 10⁵ of).
    fn into_empty_tables(self) -> Vec<Table>;
    /// Fills `row` with the row of group `g` at frame k of `r`: the time, then each column.
    fn row(&self, g: usize, r: &Self::Frame, k: usize, row: &mut Vec<f64>);
    /// Takes every frame of `frame` into `tally`.
    fn tally(tally: &mut Self::Tally, frame: &Self::Frame);

    /// Values per frame over all groups (time columns included).
    fn values_per_frame(&self) -> usize {
        (0..self.groups())
            .map(|g| self.empty_table(g).columns.len() + 1)
            .sum()
    }

    /// The groups with every frame of `r`.
    fn into_tables(self, r: &Self::Frame) -> Vec<Table>
    where
        Self: Sized,
    {
        let n = r.times().len();
        let rows: Vec<Vec<Vec<f64>>> = (0..self.groups())
            .map(|g| {
                let width = self.empty_table(g).columns.len() + 1;
                (0..n)
                    .map(|k| {
                        let mut row = Vec::with_capacity(width);
                        self.row(g, r, k, &mut row);
                        row
                    })
                    .collect()
            })
            .collect();
        let mut out = self.into_empty_tables();
        for (t, rows) in out.iter_mut().zip(rows) {
            t.rows = rows;
        }
        out
    }
}

/// The numbers a kinematic run's summary takes over every frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KinematicTally {
    /// Newton iterations.
    pub iterations: usize,
    /// The largest position residual.
    pub max_residual: f64,
}

impl FrameLayout for Layout {
    type Frame = Results;
    type Tally = KinematicTally;
    fn groups(&self) -> usize {
        Layout::groups(self)
    }
    fn empty_table(&self, g: usize) -> &Table {
        Layout::empty_table(self, g)
    }
    fn into_empty_tables(self) -> Vec<Table> {
        Layout::into_empty_tables(self)
    }
    fn row(&self, g: usize, r: &Results, k: usize, row: &mut Vec<f64>) {
        Layout::row(self, g, r, k, row);
    }
    fn tally(tally: &mut KinematicTally, frame: &Results) {
        tally.iterations += frame.iterations.iter().sum::<usize>();
        tally.max_residual = (frame.residual.iter()).fold(tally.max_residual, |a, &b| a.max(b));
    }
}

/// What [`Recorder::finish`] returns: the kept copy and the run's numbers over every frame.
pub struct Recorded<L: FrameLayout> {
    /// The kept frames (all, or the decimated copy).
    pub results: L::Frame,
    /// The output groups with the kept frames (in SI units), titled as decimated when they are.
    pub tables: Vec<Table>,
    /// The streamed files (`None` when nothing was written during the run).
    pub streamed: Option<Streamed>,
    /// Frames the run stored.
    pub frames: usize,
    /// The summary's numbers over every frame.
    pub tally: L::Tally,
    /// The time of the last frame.
    pub last_time: Option<f64>,
}

/// Built at the first frame, when the histories' names are known.
struct Started<L: FrameLayout> {
    layout: L,
    stride: usize,
    kept: L::Frame,
    /// The latest frame when it was not kept (appended at the end).
    last: L::Frame,
    last_kept: bool,
    /// The CSV files, one per group (`None`: nothing is written).
    csv: Option<CsvFiles>,
    /// One group's row.
    row: Vec<f64>,
    /// A frame's rows, every group's.
    rows: Vec<f64>,
}

/// Makes a run's layout from its first frame.
type MakeLayout<'a, L> = Box<dyn FnOnce(&<L as FrameLayout>::Frame) -> L + 'a>;

/// The sink of a streamed run (module docs).
pub struct Recorder<'a, L: FrameLayout> {
    make: Option<MakeLayout<'a, L>>,
    units: UnitSystem,
    /// Frames the run will store when it completes.
    planned: usize,
    /// Where the CSV files go; `None`: nothing is written, every frame is kept.
    dir: Option<&'a mut (dyn OutputFiles + 'static)>,
    /// A further file written from every frame.
    tap: Option<&'a mut (dyn Tap<L::Frame> + 'static)>,
    started: Option<Started<L>>,
    /// A write error that stopped the run.
    error: Option<Error>,
    frames: usize,
    tally: L::Tally,
    last_time: Option<f64>,
}

impl<'a, L: FrameLayout> Recorder<'a, L> {
    /// A recorder of a run of `planned` frames writing the groups of the layout `make` builds
    /// at the first frame into `dir` (in `units`), and every frame to `tap`. Every frame is
    /// kept without a directory.
    pub fn new(
        units: UnitSystem,
        planned: usize,
        dir: Option<&'a mut (dyn OutputFiles + 'static)>,
        tap: Option<&'a mut (dyn Tap<L::Frame> + 'static)>,
        make: impl FnOnce(&L::Frame) -> L + 'a,
    ) -> Self {
        Self {
            make: Some(Box::new(make)),
            units,
            planned,
            dir,
            tap,
            started: None,
            error: None,
            frames: 0,
            tally: L::Tally::default(),
            last_time: None,
        }
    }

    /// Takes one frame (results holding one time): the summary's numbers, the CSV rows, the
    /// kept copy. A write error stops the run ([`ControlFlow::Break`]; [`Recorder::finish`]
    /// returns it).
    pub fn frame(&mut self, frame: &L::Frame) -> ControlFlow<()> {
        if self.started.is_none() {
            match self.start(frame) {
                Ok(s) => self.started = Some(s),
                Err(e) => {
                    self.error = Some(e);
                    return ControlFlow::Break(());
                }
            }
        }
        let Some(s) = self.started.as_mut() else {
            return ControlFlow::Break(());
        };
        L::tally(&mut self.tally, frame);
        self.last_time = frame.times().last().copied().or(self.last_time);
        let keep = self.frames.is_multiple_of(s.stride);
        if keep {
            s.kept.extend_from(frame);
        } else {
            s.last.clear_frames();
            s.last.extend_from(frame);
        }
        s.last_kept = keep;
        self.frames += 1;
        let mut written = write_rows(s, frame);
        if let (true, Some(t)) = (written.is_ok(), self.tap.as_deref_mut()) {
            written = t.frame(frame).map_err(|e| (t.name().to_string(), e));
        }
        if let Err((name, e)) = written {
            self.error = Some(write_error(self.dir.as_deref(), &name, &e));
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// The layout, the decimation, the kept copy's storage and the CSV files with their headers.
    fn start(&mut self, frame: &L::Frame) -> Result<Started<L>, Error> {
        let make = self
            .make
            .take()
            .ok_or_else(|| Error::output("the run restarted"))?;
        let layout = make(frame);
        let stride = match self.dir {
            None => 1,
            Some(_) => stride(self.planned, layout.values_per_frame()),
        };
        let capacity = self.planned.div_ceil(stride) + 1;
        let mut csv = None;
        if let Some(dir) = self.dir.as_deref_mut() {
            let mut files = Vec::new();
            for g in 0..layout.groups() {
                let t = layout.empty_table(g);
                let name = format!("{}.csv", t.name);
                let (header, factors) = header_in(self.units, &t.columns);
                let mut writer = dir.create(&name)?;
                (writer.write_all(header.as_bytes())).map_err(|e| dir.write_error(&name, &e))?;
                dir.announce_plots_of(&t.name)?;
                files.push(CsvFile {
                    name,
                    writer,
                    factors,
                });
            }
            let threaded = CsvFiles::should_thread(self.planned, layout.values_per_frame());
            csv = Some(CsvFiles::new(files, self.units, threaded));
        }
        Ok(Started {
            kept: frame.empty_like(capacity),
            last: frame.empty_like(1),
            last_kept: true,
            layout,
            stride,
            csv,
            row: Vec::new(),
            rows: Vec::new(),
        })
    }

    /// The time of the last frame taken.
    pub fn last_time(&self) -> Option<f64> {
        self.last_time
    }

    /// The kept copy with the last frame, its tables, the streamed files and the numbers.
    ///
    /// # Errors
    /// A write error during the run.
    pub fn finish(self) -> Result<Recorded<L>, Error> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let Some(mut s) = self.started else {
            return Ok(Recorded {
                results: L::Frame::default(),
                tables: Vec::new(),
                streamed: None,
                frames: 0,
                tally: self.tally,
                last_time: None,
            });
        };
        if !s.last_kept {
            s.kept.extend_from(&s.last);
        }
        let mut tables = s.layout.into_tables(&s.kept);
        if s.stride > 1 {
            for t in &mut tables {
                t.title = format!(
                    "{} (every {} of {} frames)",
                    t.title,
                    ordinal(s.stride),
                    self.frames
                );
            }
        }
        let csv = (s.csv.map(CsvFiles::finish).transpose())
            .map_err(|(name, e)| write_error(self.dir.as_deref(), &name, &e))?;
        let streamed = csv.map(|csv| Streamed {
            csv,
            frames: self.frames,
            kept: s.kept.times().len(),
            stride: s.stride,
        });
        Ok(Recorded {
            results: s.kept,
            tables,
            streamed,
            frames: self.frames,
            tally: self.tally,
            last_time: self.last_time,
        })
    }
}

/// The error of a failed write of `name` (into `dir`, when the run writes one).
fn write_error(dir: Option<&dyn OutputFiles>, name: &str, e: &std::io::Error) -> Error {
    dir.map_or_else(
        || Error::output(format!("cannot write {name}: {e}")),
        |d| d.write_error(name, e),
    )
}

/// The CSV header of columns `columns` (SI) in `units`, and the columns' factors from SI.
fn header_in(units: UnitSystem, columns: &[String]) -> (String, Vec<f64>) {
    if units == UnitSystem::Si {
        return (csv_header(columns), vec![1.0; columns.len()]);
    }
    let mut columns = columns.to_vec();
    let factors = units.convert_columns(&mut columns);
    (csv_header(&columns), factors)
}

/// Hands the frame's rows (every group's, in SI) to the CSV files.
fn write_rows<L: FrameLayout>(
    s: &mut Started<L>,
    frame: &L::Frame,
) -> Result<(), (String, std::io::Error)> {
    let Some(csv) = s.csv.as_mut() else {
        return Ok(());
    };
    for k in 0..frame.times().len() {
        s.rows.clear();
        for g in 0..s.layout.groups() {
            s.layout.row(g, frame, k, &mut s.row);
            s.rows.extend_from_slice(&s.row);
        }
        csv.frame(&mut s.rows)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stride_keeps_at_most_the_limit_with_the_first_and_last_frame() {
        assert_eq!(stride(1, 10), 1);
        assert_eq!(stride(2, 10), 1);
        assert_eq!(stride(MAX_PLOTTED_FRAMES, 10), 1);
        for planned in [MAX_PLOTTED_FRAMES + 1, 10_001, 1_000_001] {
            let s = stride(planned, 10);
            // 0, s, 2s, … below the last, and the last.
            let kept = (planned - 2) / s + 2;
            assert!(
                kept <= MAX_PLOTTED_FRAMES,
                "{planned}: {kept} kept, stride {s}"
            );
            assert!(kept > MAX_PLOTTED_FRAMES / 2, "{planned}: only {kept} kept");
        }
        // A model of many columns keeps fewer frames, never fewer than the first and last.
        let s = stride(1_001, KEPT_VALUES_BUDGET / 10);
        assert_eq!((1_001 - 2) / s + 2, 10);
        assert_eq!(stride(1_001, usize::MAX), 1_000);
    }

    /// A one-body frame at time t with residual `res` and `it` Newton iterations.
    fn frame(t: f64, res: f64, it: usize) -> Results {
        let mut r = Results {
            times: vec![t],
            residual: vec![res],
            iterations: vec![it],
            ..Results::default()
        };
        r.bodies.push(cardan_mechanism::BodyResults {
            name: "b".into(),
            r: vec![nalgebra::Vector3::new(t, 0.0, 0.0)],
            p: vec![nalgebra::Vector4::new(1.0, 0.0, 0.0, 0.0)],
            ..Default::default()
        });
        r
    }

    /// Feeds `n` frames (residual 1e-12, a spike of 1e-3 at frame `spike`) to a recorder
    /// keeping a decimated copy.
    fn record(n: usize, spike: usize) -> Recorded<Layout> {
        let req = crate::build::Outputs {
            bodies: vec!["b".into()],
            ..crate::build::Outputs::default()
        };
        let mut dir = crate::files::Directory(std::env::temp_dir().join(format!(
            "cardan-stream-test-{}-{n}-{spike}",
            std::process::id()
        )));
        std::fs::create_dir_all(&dir.0).unwrap();
        let make = move |f: &Results| Layout::new(f, &req);
        let mut rec = Recorder::new(UnitSystem::Si, n, Some(&mut dir), None, make);
        for k in 0..n {
            let res = if k == spike { 1e-3 } else { 1e-12 };
            assert!(rec.frame(&frame(k as f64, res, 2)).is_continue());
        }
        rec.finish().unwrap()
    }

    #[test]
    fn the_summary_counts_every_frame_and_the_copy_keeps_the_first_and_last() {
        let n = 10 * MAX_PLOTTED_FRAMES + 7;
        let s = stride(n, 9);
        assert!(s > 1);
        // The spike falls between two kept frames.
        let spike = 3 * s + s / 2;
        let rec = record(n, spike);
        assert_eq!(rec.frames, n);
        assert_eq!(rec.tally.iterations, 2 * n);
        assert_eq!(
            rec.tally.max_residual, 1e-3,
            "the spike at frame {spike} is lost"
        );
        let kept = &rec.results;
        assert!(kept.len() <= MAX_PLOTTED_FRAMES);
        assert!(!kept.times.contains(&(spike as f64)));
        assert_eq!(kept.times.first(), Some(&0.0));
        assert_eq!(kept.times.last(), Some(&((n - 1) as f64)));
        assert_eq!(kept.bodies[0].r.last().unwrap().x, (n - 1) as f64);
        // The tables say so in their titles and hold the kept frames.
        let t = &rec.tables[0];
        assert_eq!(t.name, "bodies");
        assert_eq!(t.rows.len(), kept.len());
        let note = format!("(every {} of {n} frames)", ordinal(s));
        assert!(t.title.ends_with(&note), "{}", t.title);
        let streamed = rec.streamed.unwrap();
        assert_eq!(
            (streamed.frames, streamed.kept, streamed.stride),
            (n, kept.len(), s)
        );
    }

    #[test]
    fn ordinals() {
        let got: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 501, 512].map(ordinal).into();
        assert_eq!(
            got,
            ["1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "501st", "512th"]
        );
    }
}
