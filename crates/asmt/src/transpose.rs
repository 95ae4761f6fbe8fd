//! A table that arrives a column at a time and leaves a row at a time, in bounded memory.
//!
//! An OndselSolver `TimeSeries` is written row by row (one row per quantity, one value per
//! time, [`crate::series`]), but a run computes it column by column (every quantity at one
//! time). [`Transposer`] takes the columns (frames) as they come and holds them in a block of
//! at most `budget` values. When the block is full it goes to a spill file, row by row:
//! row r of block b is the `frames_per_block` values at byte offset
//! 8·(b·rows·frames_per_block + r·frames_per_block). Reading a row back then takes one read
//! per block, and rows are read in groups of as many as `budget` values hold, so that the whole
//! file is read once with about (values / budget)² reads: the two-pass external transpose.
//! Memory is about three budgets (the block being filled, the group being read, and one byte
//! buffer), whatever the number of frames; a run that fits in one block never touches the disk.
//! The block being filled starts at 16 frames (`FIRST_FRAMES`) and doubles up to the budget: a
//! short run does not touch a page of a budget-sized block per row (on a 26-frame ASMT file that
//! was a hundred page faults, about a tenth of the run).

use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::path::PathBuf;

/// Frames the block being filled holds at first (module docs).
const FIRST_FRAMES: usize = 16;

/// Frames in, rows out (module docs).
pub struct Transposer {
    rows: usize,
    /// Frames per block.
    block: usize,
    /// Frames `current` has room for (at most `block`).
    room: usize,
    /// The block being filled: row r's values at `r * room ..`.
    current: Vec<f64>,
    /// Frames in `current`.
    filled: usize,
    /// Full blocks in the spill file.
    spilled: usize,
    budget: usize,
    /// Where full blocks go, created at the first full block and removed on drop.
    path: PathBuf,
    file: Option<File>,
    /// The rows `group.0 ..` of every spilled frame (row i at `i * spilled_frames ..`).
    group: (usize, Vec<f64>),
    /// The values of one read.
    piece: Vec<f64>,
    bytes: Vec<u8>,
}

impl Transposer {
    /// A transposer of `rows` values per frame holding about `budget` values in memory,
    /// spilling full blocks to a new file at `path` (removed when the transposer is dropped).
    pub fn new(rows: usize, budget: usize, path: PathBuf) -> Self {
        let block = (budget / rows.max(1)).max(1);
        let room = block.min(FIRST_FRAMES);
        Self {
            rows,
            block,
            room,
            current: vec![0.0; rows * room],
            filled: 0,
            spilled: 0,
            budget,
            path,
            file: None,
            group: (0, Vec::new()),
            piece: Vec::new(),
            bytes: Vec::new(),
        }
    }

    /// Values per frame.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Frames taken.
    pub fn frames(&self) -> usize {
        self.spilled * self.block + self.filled
    }

    /// Takes one frame: `rows` values.
    ///
    /// # Errors
    /// The spill file cannot be created or written.
    ///
    /// # Panics
    /// If `frame` does not hold `rows` values.
    pub fn push(&mut self, frame: &[f64]) -> io::Result<()> {
        assert_eq!(frame.len(), self.rows, "a frame of the wrong length");
        // A full block spills when the next frame comes: a run that just fills one stays in
        // memory.
        if self.filled == self.block {
            self.spill()?;
        }
        if self.filled == self.room {
            self.grow();
        }
        for (r, &v) in frame.iter().enumerate() {
            self.current[r * self.room + self.filled] = v;
        }
        self.filled += 1;
        Ok(())
    }

    /// Doubles the room of the block being filled (at most a whole block), keeping its frames.
    fn grow(&mut self) {
        let room = (2 * self.room).min(self.block);
        let mut wider = vec![0.0; self.rows * room];
        for r in 0..self.rows {
            let old = &self.current[r * self.room..r * self.room + self.filled];
            wider[r * room..r * room + self.filled].copy_from_slice(old);
        }
        (self.current, self.room) = (wider, room);
    }

    /// Appends the full block to the spill file (a full block has room for a block).
    fn spill(&mut self) -> io::Result<()> {
        let file = match &mut self.file {
            Some(f) => f,
            None => {
                let f = File::options()
                    .read(true)
                    .write(true)
                    .create_new(true)
                    .open(&self.path)?;
                self.file.insert(f)
            }
        };
        self.bytes.clear();
        self.bytes
            .extend(self.current.iter().flat_map(|v| v.to_le_bytes()));
        file.seek(SeekFrom::End(0))?;
        file.write_all(&self.bytes)?;
        self.spilled += 1;
        self.filled = 0;
        self.group = (0, Vec::new());
        Ok(())
    }

    /// Passes row `r`'s values, in frame order, to `emit` (in one or more pieces). Rows are
    /// read fastest in order 0, 1, 2, ….
    ///
    /// # Errors
    /// A read of the spill file failed, or `emit` failed.
    pub fn row(
        &mut self,
        r: usize,
        emit: &mut dyn FnMut(&[f64]) -> io::Result<()>,
    ) -> io::Result<()> {
        let on_disk = self.spilled * self.block;
        match self.budget.checked_div(on_disk) {
            // Nothing spilled.
            None => {}
            // A row's spilled values exceed the budget: one read per block, emitted as read.
            Some(per_group) if per_group < 2 => {
                for b in 0..self.spilled {
                    self.read(b, r, 1)?;
                    emit(&self.piece)?;
                }
            }
            Some(per_group) => {
                let (first, held) = (self.group.0, self.group.1.len() / on_disk);
                if r < first || r >= first + held {
                    self.load_group(r, per_group)?;
                }
                let i = r - self.group.0;
                emit(&self.group.1[i * on_disk..(i + 1) * on_disk])?;
            }
        }
        let start = r * self.room;
        emit(&self.current[start..start + self.filled])
    }

    /// Reads rows `first .. first + n` of every spilled block into `group`.
    fn load_group(&mut self, first: usize, n: usize) -> io::Result<()> {
        let n = n.min(self.rows - first);
        let on_disk = self.spilled * self.block;
        let mut group = std::mem::take(&mut self.group.1);
        group.clear();
        group.resize(n * on_disk, 0.0);
        for b in 0..self.spilled {
            self.read(b, first, n)?;
            for (i, values) in self.piece.chunks_exact(self.block).enumerate() {
                let at = i * on_disk + b * self.block;
                group[at..at + self.block].copy_from_slice(values);
            }
        }
        self.group = (first, group);
        Ok(())
    }

    /// Reads rows `first .. first + n` of spilled block `b` into `piece`.
    fn read(&mut self, b: usize, first: usize, n: usize) -> io::Result<()> {
        let Some(file) = self.file.as_mut() else {
            return Err(io::Error::other("no spill file"));
        };
        let offset = 8 * (b * self.rows * self.block + first * self.block);
        file.seek(SeekFrom::Start(offset as u64))?;
        self.bytes.resize(8 * n * self.block, 0);
        file.read_exact(&mut self.bytes)?;
        self.piece.clear();
        let values = self.bytes.chunks_exact(8).map(|c| {
            let mut le = [0; 8];
            le.copy_from_slice(c);
            f64::from_le_bytes(le)
        });
        self.piece.extend(values);
        Ok(())
    }
}

impl Drop for Transposer {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every row read back, as one vector per row.
    fn read_rows(t: &mut Transposer) -> Vec<Vec<f64>> {
        (0..t.rows())
            .map(|r| {
                let mut row = Vec::new();
                t.row(r, &mut |piece| {
                    row.extend_from_slice(piece);
                    Ok(())
                })
                .unwrap();
                row
            })
            .collect()
    }

    fn spill_path(tag: &str) -> PathBuf {
        std::env::temp_dir().join(format!("cardan-transpose-{}-{tag}", std::process::id()))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Any shape and budget, in memory or spilled: row r holds every frame's r-th value in
        /// frame order, and the spill file is gone afterwards.
        #[test]
        fn rows_are_the_frames_transposed(
            rows in 1usize..12,
            frames in 0usize..60,
            budget in 1usize..80,
            case in 0u64..u64::MAX,
        ) {
            let path = spill_path(&case.to_string());
            let value = |k: usize, r: usize| (k * 100 + r) as f64 + 0.25;
            let mut t = Transposer::new(rows, budget, path.clone());
            for k in 0..frames {
                let frame: Vec<f64> = (0..rows).map(|r| value(k, r)).collect();
                t.push(&frame).unwrap();
            }
            prop_assert_eq!(t.frames(), frames);
            let got = read_rows(&mut t);
            for (r, row) in got.iter().enumerate() {
                let want: Vec<f64> = (0..frames).map(|k| value(k, r)).collect();
                prop_assert_eq!(row, &want);
            }
            // Rows can be read again, in any order.
            prop_assert_eq!(read_rows(&mut t), got);
            drop(t);
            prop_assert!(!path.exists());
        }
    }

    #[test]
    fn a_run_within_the_budget_writes_no_file() {
        let path = spill_path("small");
        let mut t = Transposer::new(3, 100, path.clone());
        for k in 0..33 {
            t.push(&[k as f64; 3]).unwrap();
        }
        assert!(!path.exists());
        assert_eq!(read_rows(&mut t)[2].len(), 33);
    }
}
