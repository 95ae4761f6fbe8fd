//! `cargo xtask compare-outputs <rev>`: the outputs of every bundled example and of every ASMT
//! assembly in `../shared/asmt/files`, written by the `cardan` CLI of commit `<rev>` and by the
//! working tree, compared byte for byte. A refactoring that promises "no change in behaviour"
//! proves it with this (issues 20 and 47).
//!
//! The base commit is checked out as a git worktree under `target/compare/` and built there in
//! release mode with its own target directory (a full build the first time); both binaries run
//! every `examples/*.toml` and `examples/asmt/*.asmt` that exists in both trees, and the shared
//! ASMT files, writing to `target/compare/out-base/` and `out-head/`. Compared: every CSV file,
//! every `.solved.asmt`, and `run.json` with its `wall_time_s` line left out (the one number
//! that differs between two runs).

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
    let mut cases = model_files(root, "examples", "toml")?;
    cases.extend(model_files(root, "examples/asmt", "asmt")?);
    let shared = root.join("../shared/asmt/files");
    let shared_cases = match std::fs::canonicalize(&shared) {
        Ok(s) => model_files(&s, "", "asmt")?,
        Err(_) => Vec::new(),
    };
    let (mut same, mut differ, mut skipped) = (0, Vec::new(), Vec::new());
    let all = (cases.iter().map(|c| (c, true))).chain(shared_cases.iter().map(|c| (c, false)));
    for (rel, in_tree) in all {
        let name = rel.to_string_lossy().replace(['/', '.'], "_");
        let input = |tree: &Path| {
            if in_tree {
                tree.join(rel)
            } else {
                shared.join(rel)
            }
        };
        if !input(base).exists() {
            skipped.push(name);
            continue;
        }
        for (label, bin, tree) in &bins {
            let out = dir.join(format!("out-{label}")).join(&name);
            let _ = std::fs::remove_dir_all(&out);
            // Run from the tree with a relative path, so that run.json names the model alike.
            let arg = if in_tree {
                rel.clone()
            } else {
                shared.join(rel)
            };
            let status = Command::new(bin)
                .current_dir(tree)
                .arg("run")
                .arg(arg)
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
        let files = compared_files(&dir.join("out-head").join(&name))?;
        for f in files {
            let a = comparable(&dir.join("out-base").join(&name).join(&f));
            let b = comparable(&dir.join("out-head").join(&name).join(&f));
            if a == b {
                same += 1;
            } else {
                differ.push(format!("{name}/{f}"));
            }
        }
    }
    println!(
        "{same} files identical (CSV, run.json, .solved.asmt); {} differ; \
         models only in the working tree: {skipped:?}",
        differ.len()
    );
    if differ.is_empty() {
        Ok(())
    } else {
        Err(format!("outputs differ: {differ:?}"))
    }
}

/// The files `*.ext` in `root/sub`, as paths relative to `root`, sorted.
fn model_files(root: &Path, sub: &str, ext: &str) -> Result<Vec<PathBuf>, String> {
    let d = root.join(sub);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&d)
        .map_err(|e| format!("{}: {e}", d.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .filter_map(|p| p.file_name().map(|f| Path::new(sub).join(f)))
        .collect();
    v.sort();
    Ok(v)
}

/// The compared file names in `dir` (CSV files, `run.json`, `.solved.asmt`), sorted.
fn compared_files(dir: &Path) -> Result<Vec<String>, String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.ends_with(".csv") || n.ends_with(".solved.asmt") || n == "run.json")
        .collect();
    v.sort();
    Ok(v)
}

/// The bytes of `path` that two runs must share: `run.json` without its `wall_time_s` line.
fn comparable(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap_or_default();
    if path.file_name().is_some_and(|n| n == "run.json") {
        let text = String::from_utf8_lossy(&bytes);
        let kept: Vec<&str> = (text.lines())
            .filter(|l| !l.trim_start().starts_with("\"wall_time_s\""))
            .collect();
        return kept.join("\n").into_bytes();
    }
    bytes
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
