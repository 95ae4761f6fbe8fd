//! The output directory of `cardan run`: one rule for every analysis.
//!
//! 1. **Lock.** `DIR.lock` beside the target `DIR` is created with `create_new` and holds the
//!    process id. A second run into the same directory gets an error naming the directory, the
//!    other run's process id and the lock file. A lock whose process no longer exists (a run
//!    that was killed) is stale and taken over.
//! 2. **Temporary sibling.** The files are written into `DIR.tmp-<pid>` next to the target (the
//!    same file system, so the final rename is atomic), each one written and flushed before
//!    the next; a write error (a full disk) removes the temporary directory and leaves the
//!    previous run's directory as it was: no truncated file is ever in `DIR`. The files are
//!    not synced to disk: outputs can be computed again, and a sync per file cost about
//!    10 ms per run (half of a small model's whole run), so only a power failure right after
//!    a run can lose them. Files the run announces ([`OutputDir::announce`],
//!    [`OutputDir::announce_plots_of`]) are created on a second thread while the analysis runs
//!    ([`opener`]); one announced but never written is removed before the rename.
//! 3. **Rename into place.** The previous `DIR` is renamed aside, the temporary directory renamed
//!    to `DIR`, then the previous one removed: `DIR` always holds the files of one run, never a
//!    mix. A directory is only replaced if it holds nothing but what a run writes (`*.csv`,
//!    `*.svg`, `*.png`, `*.solved.asmt`, `run.json`, `animation.glb`, `index.html`); anything else there is refused, so `-o` cannot delete a
//!    user's files.
//!
//! A run that produced no result (an input error, an assembly failure) writes nothing: the
//! previous directory stays. Partial results (a failure mid-run, Ctrl-C) replace it, marked
//! `"partial"` in `run.json`.

pub mod opener;
pub mod single;

use cardan_model::diag::{describe_io, Error};
use cardan_model::files::{OutputFiles, StreamFile, StreamWriter};
use cardan_model::plot::PlotFiles;
use opener::{Opener, PendingFile};
use std::ffi::OsString;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// A locked output directory being written: files go to the temporary sibling until
/// [`OutputDir::commit`]. Dropping it without committing removes the temporary directory and
/// the lock, leaving the target as it was.
#[derive(Debug)]
pub struct OutputDir {
    /// The directory the run writes (as given).
    target: PathBuf,
    /// `target` with `.tmp-<pid>` appended.
    tmp: PathBuf,
    /// `target` with `.lock` appended.
    lock: PathBuf,
    /// Names of the files written so far, in order.
    files: Vec<String>,
    /// The temporary directory exists and is ours to remove.
    tmp_created: bool,
    committed: bool,
    /// Creates announced and streamed files on a second thread.
    opener: Opener,
    /// Files announced and not yet written: name and the file being created.
    announced: Vec<(String, PendingFile)>,
    /// The plots written beside each table.
    plots: PlotFiles,
}

/// `path` with `suffix` appended to its last component (`out` → `out.lock`).
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let mut name: OsString = path.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    path.with_file_name(name)
}

impl OutputDir {
    /// Locks `target` against other runs (module docs, rule 1) and checks that it may be
    /// replaced. Nothing is written yet.
    ///
    /// # Errors
    /// An output error: no usable name (`.`, `/`), another live run holds the lock, the target
    /// is not a directory or holds files a run does not write, the parent cannot be created.
    pub fn lock(target: &Path) -> Result<Self, Error> {
        let named = target.file_name().is_some_and(|n| n != "." && n != "..");
        if !named {
            return Err(Error::usage(format!(
                "the output directory {} has no name of its own to replace; give a directory \
                 such as out/run1",
                target.display()
            )));
        }
        if let Some(parent) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|e| {
                Error::output(format!(
                    "cannot create the output directory's parent {}: {}",
                    parent.display(),
                    describe_io(&e)
                ))
            })?;
        }
        let lock = sibling(target, ".lock");
        take_lock(&lock, target)?;
        // Ours from here on: Drop releases it on every path (never another run's lock).
        let dir = Self {
            target: target.to_path_buf(),
            tmp: sibling(target, &format!(".tmp-{}", std::process::id())),
            lock,
            files: Vec::new(),
            tmp_created: false,
            committed: false,
            opener: Opener::default(),
            announced: Vec::new(),
            plots: PlotFiles::default(),
        };
        check_replaceable(&dir.target)?;
        Ok(dir)
    }

    /// The target directory.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Names of the files written so far.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// Creates the temporary directory on the first file.
    fn ensure_tmp(&mut self) -> Result<(), Error> {
        if !self.tmp_created {
            if self.tmp.exists() {
                // Left by an earlier run with our process id (ids are reused): ours to clear.
                let _ = std::fs::remove_dir_all(&self.tmp);
            }
            std::fs::create_dir(&self.tmp).map_err(|e| {
                Error::output(format!(
                    "cannot create the output directory {}: {}",
                    self.tmp.display(),
                    describe_io(&e)
                ))
            })?;
            self.tmp_created = true;
        }
        Ok(())
    }

    /// Says which files the run will write, so that they are created on a second thread while
    /// it goes on ([`opener`]). A name announced twice is created once.
    ///
    /// # Errors
    /// The temporary directory cannot be created.
    pub fn announce<S: Into<String>>(
        &mut self,
        names: impl IntoIterator<Item = S>,
    ) -> Result<(), Error> {
        self.ensure_tmp()?;
        for name in names {
            let name = name.into();
            if !self.announced.iter().any(|(n, _)| *n == name) {
                let file = self.opener.open(self.tmp.join(&name));
                self.announced.push((name, file));
            }
        }
        Ok(())
    }

    /// The plots to be written beside each table ([`OutputDir::announce_plots_of`]).
    pub fn set_plots(&mut self, plots: PlotFiles) {
        self.plots = plots;
    }

    /// Announces the plot files of the table `name` ([`OutputDir::set_plots`]).
    ///
    /// # Errors
    /// As [`OutputDir::announce`].
    pub fn announce_plots_of(&mut self, name: &str) -> Result<(), Error> {
        self.announce(self.plots.of(name))
    }

    /// The file `name` in the temporary directory: the announced one, or one created on the
    /// second thread (`later`, for a file whose first bytes come later) or here.
    fn file(&mut self, name: &str, later: bool) -> Result<PendingFile, Error> {
        self.ensure_tmp()?;
        Ok(match self.announced.iter().position(|(n, _)| n == name) {
            Some(i) => self.announced.swap_remove(i).1,
            None if later => self.opener.open(self.tmp.join(name)),
            None => PendingFile::create_now(&self.tmp.join(name)),
        })
    }

    /// Writes `name` (text or bytes) into the temporary directory: write and flush.
    ///
    /// # Errors
    /// An output error naming the file and the cause (a full disk, permissions).
    pub fn write(&mut self, name: &str, data: impl AsRef<[u8]>) -> Result<(), Error> {
        self.write_parts(name, &[data.as_ref()])
    }

    /// Writes `name` from `parts`, one after the other (a text too large to copy into one, the
    /// report page around three.js): write and flush.
    ///
    /// # Errors
    /// As [`OutputDir::write`].
    pub fn write_parts(&mut self, name: &str, parts: &[&[u8]]) -> Result<(), Error> {
        let mut file = self.file(name, false)?;
        let written =
            (parts.iter().try_for_each(|p| file.write_all(p))).and_then(|()| file.flush());
        written.map_err(|e| self.write_error(name, &e))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// Opens `name` in the temporary directory for a file written piece by piece while the run
    /// goes on (a streamed CSV): a buffered writer, the file created on the second thread.
    /// Once complete, [`OutputDir::finish`] flushes it and counts it among the files written.
    ///
    /// # Errors
    /// An output error naming the file and the cause (the temporary directory cannot be
    /// created; a file that cannot be created is an error of its first write).
    pub fn create(&mut self, name: &str) -> Result<StreamWriter, Error> {
        let file: Box<dyn StreamFile> = Box::new(self.file(name, true)?);
        Ok(std::io::BufWriter::with_capacity(1 << 16, file))
    }

    /// The path of a scratch file `name` in the temporary directory: a file the run reads and
    /// writes while it goes on and removes before [`OutputDir::commit`] (the spill file of an
    /// ASMT run's TimeSeries, [`crate::commands::asmt::SolvedSeries`]). If the run fails, it
    /// goes with the temporary directory.
    ///
    /// # Errors
    /// The temporary directory cannot be created.
    pub fn scratch(&mut self, name: &str) -> Result<PathBuf, Error> {
        self.ensure_tmp()?;
        Ok(self.tmp.join(name))
    }

    /// Completes a file opened by [`OutputDir::create`]: flush and record it in
    /// [`OutputDir::files`].
    ///
    /// # Errors
    /// An output error naming the file and the cause.
    pub fn finish(&mut self, name: &str, writer: StreamWriter) -> Result<(), Error> {
        let done = writer
            .into_inner()
            .map_err(|e| std::io::Error::new(e.error().kind(), e.error().to_string()))
            // Created even if nothing was written: its creation error is this file's error.
            .and_then(StreamFile::close);
        done.map_err(|e| self.write_error(name, &e))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// The error of a failed write of `name`.
    pub fn write_error(&self, name: &str, e: &std::io::Error) -> Error {
        Error::output(format!(
            "cannot write {} (for {}): {}; the previous contents of {} are unchanged",
            name,
            self.target.display(),
            describe_io(e),
            self.target.display()
        ))
    }

    /// Renames the temporary directory into place, replacing the previous run's directory as a
    /// whole, and releases the lock.
    ///
    /// # Errors
    /// An output error if a rename fails (the previous directory is then put back).
    pub fn commit(mut self) -> Result<(), Error> {
        self.opener.stop();
        for (name, _) in std::mem::take(&mut self.announced) {
            let _ = std::fs::remove_file(self.tmp.join(name));
        }
        let old = sibling(&self.target, &format!(".old-{}", std::process::id()));
        let had_previous = std::fs::symlink_metadata(&self.target).is_ok();
        if had_previous {
            let _ = std::fs::remove_dir_all(&old);
            std::fs::rename(&self.target, &old).map_err(|e| self.rename_error(&e))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.target) {
            if had_previous {
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(self.rename_error(&e));
        }
        self.committed = true;
        if had_previous {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }

    fn rename_error(&self, e: &std::io::Error) -> Error {
        Error::output(format!(
            "cannot move the new results into {}: {}; the previous contents are unchanged",
            self.target.display(),
            describe_io(e)
        ))
    }
}

impl OutputFiles for OutputDir {
    fn create(&mut self, name: &str) -> Result<StreamWriter, Error> {
        OutputDir::create(self, name)
    }
    fn announce_plots_of(&mut self, name: &str) -> Result<(), Error> {
        OutputDir::announce_plots_of(self, name)
    }
    fn write_error(&self, name: &str, e: &std::io::Error) -> Error {
        OutputDir::write_error(self, name, e)
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        // No file is being created in the temporary directory while it is removed.
        self.opener.stop();
        if self.tmp_created && !self.committed {
            let _ = std::fs::remove_dir_all(&self.tmp);
        }
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Creates `lock` holding our process id, taking over a stale lock of a dead process.
fn take_lock(lock: &Path, target: &Path) -> Result<(), Error> {
    for attempt in 0..3 {
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut f) => {
                let _ = writeln!(f, "{}", std::process::id());
                return Ok(());
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let holder = std::fs::read_to_string(lock).unwrap_or_default();
                let pid = holder.trim().parse::<u32>().ok();
                match pid {
                    Some(pid) if process_alive(pid) => {
                        return Err(Error::output(format!(
                            "another run (process {pid}) is writing {}; wait for it to finish or \
                             write elsewhere with -o DIR (if no such run is active, delete the \
                             lock file {})",
                            target.display(),
                            lock.display()
                        )))
                    }
                    // Empty: the other run may have created it an instant ago and not yet
                    // written its id; look again before calling it stale.
                    None if attempt == 0 => {
                        std::thread::sleep(std::time::Duration::from_millis(100))
                    }
                    _ => take_over(lock, &holder),
                }
            }
            Err(e) => {
                return Err(Error::output(format!(
                    "cannot create the lock file {}: {}",
                    lock.display(),
                    describe_io(&e)
                )))
            }
        }
    }
    Err(Error::output(format!(
        "cannot lock {}: the lock file {} keeps changing (other runs starting?); try again",
        target.display(),
        lock.display()
    )))
}

/// Removes a stale lock whose contents were `seen`. It is first renamed to a name of our own
/// and checked: if another run took it over in between, its lock is put back.
fn take_over(lock: &Path, seen: &str) {
    let mine = sibling(lock, &format!(".stale-{}", std::process::id()));
    if std::fs::rename(lock, &mine).is_ok() {
        let now = std::fs::read_to_string(&mine).unwrap_or_default();
        if now == seen {
            let _ = std::fs::remove_file(&mine);
        } else {
            let _ = std::fs::rename(&mine, lock);
        }
    }
}

/// Whether process `pid` exists. Where this cannot be told (no `/proc`), assumed alive: the
/// error message then says which lock file to delete.
fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    if proc.join("self").exists() {
        proc.join(pid.to_string()).exists()
    } else {
        true
    }
}

/// The target may be replaced: it does not exist, or it is a directory (not a link) that holds
/// only files a run writes.
fn check_replaceable(target: &Path) -> Result<(), Error> {
    let Ok(meta) = std::fs::symlink_metadata(target) else {
        return Ok(());
    };
    if !meta.is_dir() {
        return Err(Error::usage(format!(
            "the output path {} exists and is not a directory (a file or a link); remove it or \
             write elsewhere with -o DIR",
            target.display()
        )));
    }
    let entries = std::fs::read_dir(target).map_err(|e| {
        Error::output(format!(
            "cannot read the output directory {}: {}",
            target.display(),
            describe_io(&e)
        ))
    })?;
    let foreign: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|e| !is_run_output(e))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .take(3)
        .collect();
    if !foreign.is_empty() {
        return Err(Error::usage(format!(
            "the output directory {} holds files a run does not write ({}); a run replaces its \
             directory as a whole, so it will not delete them: move them away or write elsewhere \
             with -o DIR",
            target.display(),
            foreign.join(", ")
        )));
    }
    Ok(())
}

/// A plain file named `*.csv`, `*.svg`, `*.png`, `*.solved.asmt` (a run of an ASMT file),
/// `*.mtx` and `state_space.txt` (linearized models), `run.json`, `animation.glb` or
/// `index.html`.
fn is_run_output(e: &std::fs::DirEntry) -> bool {
    let name = e.file_name();
    let name = name.to_string_lossy();
    let plain = e.file_type().is_ok_and(|t| t.is_file());
    plain
        && (name.ends_with(".csv")
            || name.ends_with(".svg")
            || name.ends_with(".png")
            || name.ends_with(".solved.asmt")
            || name.ends_with(".mtx")
            || name == "state_space.txt"
            || name == "run.json"
            || name == "animation.glb"
            || name == "index.html")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cardan-outdir-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    /// Announced files are created ahead (here with their plots) and hold what was written;
    /// one announced but never written (the animation of a run whose scene failed) is not left
    /// behind.
    #[test]
    fn announced_files_hold_what_was_written_and_unwritten_ones_go() {
        let t = target("announce");
        let mut dir = OutputDir::lock(&t).unwrap();
        dir.set_plots(PlotFiles {
            svg: true,
            png: false,
        });
        dir.announce(["animation.glb", "run.json"]).unwrap();
        let mut csv = dir.create("points.csv").unwrap();
        dir.announce_plots_of("points").unwrap();
        dir.announce_plots_of("residual").unwrap();
        csv.write_all(b"t,x\n0,1\n").unwrap();
        dir.finish("points.csv", csv).unwrap();
        dir.write("points.svg", "<svg/>").unwrap();
        dir.write("run.json", "{}").unwrap();
        dir.commit().unwrap();
        assert_eq!(names(&t), ["points.csv", "points.svg", "run.json"]);
        assert_eq!(
            std::fs::read_to_string(t.join("points.csv")).unwrap(),
            "t,x\n0,1\n"
        );
        assert_eq!(
            std::fs::read_to_string(t.join("points.svg")).unwrap(),
            "<svg/>"
        );
        let _ = std::fs::remove_dir_all(&t);
    }

    /// A streamed file that cannot be created (its name is taken by a directory) is an error
    /// naming it when it is completed, even if nothing was written into it; the previous
    /// directory stays.
    #[test]
    fn a_file_that_cannot_be_created_is_an_error_naming_it() {
        let t = target("uncreatable");
        let mut dir = OutputDir::lock(&t).unwrap();
        dir.scratch("x").unwrap();
        std::fs::create_dir(dir.tmp.join("points.csv")).unwrap();
        let csv = dir.create("points.csv").unwrap();
        let e = dir.finish("points.csv", csv).unwrap_err();
        assert!(
            e.message.contains("cannot write points.csv"),
            "{}",
            e.message
        );
        drop(dir);
        assert!(!t.exists());
        let _ = std::fs::remove_dir_all(&t);
    }
}
