//! `cargo xtask oracle [--check]`: run the CasADi oracle (`oracle/*.py`).
//!
//! 1. Find Python (`$CARDAN_PYTHON`, else `python3`, else `python`), at least 3.11.
//! 2. Create the virtual environment `target/oracle-venv` if needed and install the pinned
//!    `oracle/requirements.txt`; a stamp file skips the install while the requirements (and the
//!    interpreter version) are unchanged.
//! 3. Without `--check`: regenerate `oracle/data/`.
//!    With `--check`: regenerate into `target/oracle-check/` and compare with `oracle/data/`
//!    (`oracle/compare.py`: same files and structure, numbers to relative 1e-12); stale data are an
//!    error with a summary of the differences.
//!
//! Missing Python, a failing venv creation or a failing pip are errors that say what to install;
//! the task never skips silently.

use crate::workspace_root;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// What `cargo xtask oracle` does with the regenerated data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Regenerate `oracle/data/` in place.
    Write,
    /// Regenerate into `target/` and fail if `oracle/data/` differs.
    Check,
}

/// Minimum Python version (the pinned numpy needs 3.11).
const MIN_PYTHON: (u32, u32) = (3, 11);

/// Runs the oracle task.
pub fn run(mode: Mode) -> Result<(), String> {
    let root = workspace_root();
    let oracle = root.join("oracle");
    let requirements = oracle.join("requirements.txt");
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let venv = target.join("oracle-venv");

    let start = Instant::now();
    let python = venv_python(&venv, &requirements)?;
    let env_time = start.elapsed();

    match mode {
        Mode::Write => {
            let data = oracle.join("data");
            run_python(&python, &oracle.join("generate.py"), &[&data], "generate")?;
            println!(
                "oracle: regenerated {} (venv ready in {:.1} s, total {:.1} s); review and commit it",
                data.display(),
                env_time.as_secs_f64(),
                start.elapsed().as_secs_f64()
            );
            Ok(())
        }
        Mode::Check => {
            let fresh = target.join("oracle-check");
            if fresh.exists() {
                fs::remove_dir_all(&fresh)
                    .map_err(|e| format!("cannot clear {}: {e}", fresh.display()))?;
            }
            run_python(&python, &oracle.join("generate.py"), &[&fresh], "generate")?;
            let compare = oracle.join("compare.py");
            let status = Command::new(&python)
                .arg(&compare)
                .arg(oracle.join("data"))
                .arg(&fresh)
                .env("PYTHONDONTWRITEBYTECODE", "1")
                .status()
                .map_err(|e| format!("cannot run {}: {e}", compare.display()))?;
            match status.code() {
                Some(0) => Ok(()),
                Some(1) => Err(
                    "oracle/data/ is stale (see the differences above); run `cargo xtask oracle` \
                     and commit oracle/data/"
                        .to_string(),
                ),
                _ => Err(format!("{} failed ({status})", compare.display())),
            }
        }
    }
}

/// Python inside the venv (`bin/python`, or `Scripts\python.exe` on Windows).
fn venv_bin(venv: &Path) -> PathBuf {
    if cfg!(windows) {
        venv.join("Scripts").join("python.exe")
    } else {
        venv.join("bin").join("python")
    }
}

/// Finds the system Python and its version, or explains what to install.
fn system_python() -> Result<(String, String), String> {
    let candidates: Vec<String> = match std::env::var("CARDAN_PYTHON") {
        Ok(p) if !p.is_empty() => vec![p],
        _ => vec!["python3".to_string(), "python".to_string()],
    };
    let mut tried = Vec::new();
    for cand in candidates {
        let out = Command::new(&cand)
            .args(["-c", "import sys; print('%d.%d.%d' % sys.version_info[:3])"])
            .output();
        match out {
            Ok(out) if out.status.success() => {
                let version = String::from_utf8_lossy(&out.stdout).trim().to_string();
                let mut parts = version.split('.').map(|x| x.parse::<u32>().unwrap_or(0));
                let (major, minor) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0));
                if (major, minor) < MIN_PYTHON {
                    return Err(format!(
                        "`{cand}` is Python {version}, the oracle needs Python >= {}.{} \
                         (install a newer python3, or point CARDAN_PYTHON at one)",
                        MIN_PYTHON.0, MIN_PYTHON.1
                    ));
                }
                return Ok((cand, version));
            }
            Ok(out) => tried.push(format!("`{cand}` exited with {}", out.status)),
            Err(e) => tried.push(format!("`{cand}`: {e}")),
        }
    }
    Err(format!(
        "no usable Python found ({}).\n\
         The oracle needs Python >= {}.{} with the venv module and pip: install it (Debian/Ubuntu: \
         `apt-get install python3 python3-venv python3-pip`; macOS: `brew install python`), \
         or set CARDAN_PYTHON to the interpreter to use",
        tried.join("; "),
        MIN_PYTHON.0,
        MIN_PYTHON.1
    ))
}

/// Creates or updates the venv and returns its Python.
fn venv_python(venv: &Path, requirements: &Path) -> Result<PathBuf, String> {
    let (python, version) = system_python()?;
    let reqs = fs::read_to_string(requirements)
        .map_err(|e| format!("cannot read {}: {e}", requirements.display()))?;
    let stamp_path = venv.join("cardan-requirements.stamp");
    let stamp = format!("python {version}\n{reqs}");
    let bin = venv_bin(venv);

    if bin.exists() && fs::read_to_string(&stamp_path).ok().as_deref() == Some(stamp.as_str()) {
        return Ok(bin);
    }

    if !bin.exists() || venv_version(&bin).as_deref() != Some(version.as_str()) {
        println!(
            "oracle: creating {} with {python} {version}",
            venv.display()
        );
        let status = Command::new(&python)
            .args(["-m", "venv", "--clear"])
            .arg(venv)
            .status()
            .map_err(|e| format!("cannot run `{python} -m venv`: {e}"))?;
        if !status.success() || !bin.exists() {
            return Err(format!(
                "`{python} -m venv {}` failed ({status}). The venv module (with ensurepip) is \
                 missing: install it (Debian/Ubuntu: `apt-get install python3-venv`), or set \
                 CARDAN_PYTHON to a Python that has it",
                venv.display()
            ));
        }
    }

    println!(
        "oracle: installing {} into {}",
        requirements.display(),
        venv.display()
    );
    let _ = fs::remove_file(&stamp_path);
    let status = Command::new(&bin)
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "-r",
        ])
        .arg(requirements)
        .status()
        .map_err(|e| format!("cannot run pip in {}: {e}", venv.display()))?;
    if !status.success() {
        return Err(format!(
            "`pip install -r {}` failed ({status}). pip needs network access to PyPI (or a \
             configured index) and a Python for which the pinned wheels exist; if pip itself is \
             missing, install it (Debian/Ubuntu: `apt-get install python3-pip python3-venv`) and \
             delete {}",
            requirements.display(),
            venv.display()
        ));
    }
    fs::write(&stamp_path, stamp)
        .map_err(|e| format!("cannot write {}: {e}", stamp_path.display()))?;
    Ok(bin)
}

/// Version of the venv's Python, if it runs.
fn venv_version(bin: &Path) -> Option<String> {
    let out = Command::new(bin)
        .args(["-c", "import sys; print('%d.%d.%d' % sys.version_info[:3])"])
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Runs an oracle script with the venv's Python.
fn run_python(python: &Path, script: &Path, args: &[&Path], what: &str) -> Result<(), String> {
    let status = Command::new(python)
        .arg(script)
        .args(args)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .status()
        .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!(
            "oracle {what} step `{}` failed ({status})",
            script.display()
        ))
    }
}
