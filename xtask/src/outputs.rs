//! `cargo xtask compare-outputs <rev>`: the CSV files of every bundled example, written by the
//! `cardan` CLI of commit `<rev>` and by the working tree, compared byte for byte. A refactoring
//! that promises "no change in behaviour" proves it with this (issue 20).
//!
//! The base commit is checked out as a git worktree under `target/compare/` and built there in
//! release mode with its own target directory (a full build the first time); both binaries run
//! every `examples/*.toml` that exists in both trees.

use crate::{run_status, workspace_root};
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn run(rev: &str) -> Result<(), String> {
    let root = workspace_root();
    let dir = root.join("target/compare");
    let base = dir.join("base");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if base.exists() {
        git(
            &root,
            &["worktree", "remove", "--force", &base.to_string_lossy()],
        )?;
    }
    git(
        &root,
        &["worktree", "add", "--detach", &base.to_string_lossy(), rev],
    )?;
    let result = compare(&root, &base, &dir);
    git(
        &root,
        &["worktree", "remove", "--force", &base.to_string_lossy()],
    )?;
    result
}

fn compare(root: &Path, base: &Path, dir: &Path) -> Result<(), String> {
    let base_target = dir.join("target");
    build(base, &base_target)?;
    build(root, &root.join("target"))?;
    let bins = [
        ("base", base_target.join("release/cardan"), base),
        ("head", root.join("target/release/cardan"), root),
    ];
    let mut examples: Vec<PathBuf> = std::fs::read_dir(root.join("examples"))
        .map_err(|e| e.to_string())?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    examples.sort();
    let (mut same, mut differ, mut skipped) = (0, Vec::new(), Vec::new());
    for ex in &examples {
        let name = ex
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        if !base
            .join("examples")
            .join(ex.file_name().unwrap_or_default())
            .exists()
        {
            skipped.push(name);
            continue;
        }
        for (label, bin, tree) in &bins {
            let out = dir.join(label).join(&name);
            let _ = std::fs::remove_dir_all(&out);
            let status = Command::new(bin)
                .arg("run")
                .arg(
                    tree.join("examples")
                        .join(ex.file_name().unwrap_or_default()),
                )
                .arg("-o")
                .arg(&out)
                .output()
                .map_err(|e| format!("{}: {e}", bin.display()))?;
            if !status.status.success() {
                return Err(format!(
                    "{label} {name}: {}",
                    String::from_utf8_lossy(&status.stderr)
                ));
            }
        }
        let files = csv_files(&dir.join("head").join(&name))?;
        for f in files {
            let a = std::fs::read(dir.join("base").join(&name).join(&f)).unwrap_or_default();
            let b = std::fs::read(dir.join("head").join(&name).join(&f)).unwrap_or_default();
            if a == b {
                same += 1;
            } else {
                differ.push(format!("{name}/{f}"));
            }
        }
    }
    println!(
        "{same} CSV files identical; {} differ; examples only in the working tree: {skipped:?}",
        differ.len()
    );
    if differ.is_empty() {
        Ok(())
    } else {
        Err(format!("CSV outputs differ: {differ:?}"))
    }
}

/// The CSV file names in `dir`, sorted.
fn csv_files(dir: &Path) -> Result<Vec<String>, String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    v.sort();
    Ok(v)
}

fn build(tree: &Path, target: &Path) -> Result<(), String> {
    println!(
        "$ cargo build --release -p cardan-cli  (in {})",
        tree.display()
    );
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.args(["build", "--release", "-q", "-p", "cardan-cli"])
        .env("CARGO_TARGET_DIR", target)
        .current_dir(tree);
    run_status(cmd, &format!("the build in {}", tree.display()))
}

fn git(root: &Path, args: &[&str]) -> Result<(), String> {
    let mut cmd = Command::new("git");
    cmd.args(args).current_dir(root);
    run_status(cmd, &format!("git {}", args.join(" ")))
}
