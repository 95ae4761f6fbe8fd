//! `cargo xtask stress [--quick]`: the numerical stability stress suite (docs/stress.md).
//!
//! - `--quick`: the subset CI runs as part of `cargo test --workspace` — the stress suites of
//!   `cardan-mechanism` (`tests/stress_*.rs`) with their default case counts and the CLI's
//!   hostile-input tests.
//! - full: the same suites in a release build with `CARDAN_STRESS_CASES` (default 1000) proptest
//!   cases, the ignored long runs (10⁶ kinematic frames), and a 10⁵-step dynamic run of the
//!   spatial slider-crank through the `cardan` binary; the measured bounds are printed and
//!   written to `target/stress/report.md`.

use crate::workspace_root;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

const SUITES: &[&str] = &[
    "stress_random",
    "stress_singular",
    "stress_redundant",
    "stress_conditioning",
];

/// Runs the stress suite.
pub fn run(quick: bool) -> Result<(), String> {
    let root = workspace_root();
    let cases = std::env::var("CARDAN_STRESS_CASES").unwrap_or_else(|_| "1000".into());
    let mut report = String::from("# cardan stress report\n\n");
    let start = Instant::now();

    // The proptest and near-singular suites.
    let mut args: Vec<String> = vec!["test".into(), "-p".into(), "cardan-mechanism".into()];
    if !quick {
        args.push("--release".into());
    }
    for s in SUITES {
        args.push("--test".into());
        args.push((*s).into());
    }
    let t = Instant::now();
    let envs: Vec<(&str, &str)> = if quick {
        vec![]
    } else {
        vec![("CARDAN_STRESS_CASES", cases.as_str())]
    };
    cargo(&root, &args, &envs)?;
    let _ = writeln!(
        report,
        "- mechanism stress suites ({}): {} cases per property, {:.1} s",
        SUITES.join(", "),
        if quick {
            "default (12)".to_string()
        } else {
            cases.clone()
        },
        t.elapsed().as_secs_f64()
    );

    // Hostile input through the binary.
    let t = Instant::now();
    let mut args: Vec<String> = vec!["test".into(), "-p".into(), "cardan-cli".into()];
    if !quick {
        args.push("--release".into());
    }
    args.extend(["--test".into(), "hostile_input".into()]);
    cargo(&root, &args, &[])?;
    let _ = writeln!(
        report,
        "- hostile input (cardan-cli tests/hostile_input.rs): {:.1} s",
        t.elapsed().as_secs_f64()
    );

    if !quick {
        // 10⁶ kinematic frames.
        let t = Instant::now();
        let out = cargo_output(
            &root,
            &[
                "test",
                "--release",
                "-p",
                "cardan-mechanism",
                "--test",
                "stress_long",
                "--",
                "--ignored",
                "--nocapture",
            ],
        )?;
        let _ = writeln!(
            report,
            "\n## Long kinematic run ({:.1} s)\n",
            t.elapsed().as_secs_f64()
        );
        for line in out.lines().filter_map(|l| l.strip_prefix("STRESS ")) {
            let _ = writeln!(report, "- {line}");
        }
        // 10⁵ dynamic steps.
        let t = Instant::now();
        let dynamic = dynamic_run(&root)?;
        let _ = writeln!(
            report,
            "\n## Long dynamic run ({:.1} s)\n\n{dynamic}",
            t.elapsed().as_secs_f64()
        );
    }
    let _ = writeln!(report, "\ntotal: {:.1} s", start.elapsed().as_secs_f64());
    println!("\n{report}");
    let dir = root.join("target/stress");
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("report.md"), &report).map_err(|e| e.to_string())?;
    Ok(())
}

/// 10⁵ generalized-α steps (h = 1 ms, ρ∞ = 1, 100 s) of the free spatial slider-crank under
/// gravity (examples/slider_crank_dynamic.toml with its analysis replaced), through the binary.
fn dynamic_run(root: &Path) -> Result<String, String> {
    let src = std::fs::read_to_string(root.join("examples/slider_crank_dynamic.toml"))
        .map_err(|e| format!("examples/slider_crank_dynamic.toml: {e}"))?;
    let head = src
        .split("[analysis]")
        .next()
        .ok_or("no [analysis] in the example")?;
    let model = format!(
        "{head}[analysis]
kind = \"dynamic\"
integrator = \"generalized_alpha\"
rho_inf = 1.0
dt = 0.001
t_end = 100.0
output_dt = 0.01
plots = \"none\"

[analysis.outputs]
bodies = [\"crank\", \"conrod\", \"slider\"]
energy = true
"
    );
    let dir = root.join("target/stress");
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let file = dir.join("slider_crank_long.toml");
    std::fs::write(&file, model).map_err(|e| e.to_string())?;
    let out_dir = dir.join("slider_crank_long");
    let out = cargo_output(
        root,
        &[
            "run",
            "--release",
            "-q",
            "-p",
            "cardan-cli",
            "--",
            "run",
            file.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "--quiet",
        ],
    )?;
    let summary = out
        .lines()
        .find(|l| l.contains("constraint drift"))
        .unwrap_or("(no summary line)")
        .to_string();
    // Normalization from bodies.csv (columns *.p.e0..e3), energy from energy.csv.
    let bodies = std::fs::read_to_string(out_dir.join("bodies.csv")).map_err(|e| e.to_string())?;
    let mut lines = bodies.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let e0: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| h.contains(".p.e0"))
        .map(|(k, _)| k)
        .collect();
    let mut norm = 0.0f64;
    let mut rows = 0usize;
    for l in lines {
        let v: Vec<f64> = l.split(',').filter_map(|x| x.parse().ok()).collect();
        rows += 1;
        for &k in &e0 {
            if k + 3 < v.len() {
                let n =
                    (v[k] * v[k] + v[k + 1] * v[k + 1] + v[k + 2] * v[k + 2] + v[k + 3] * v[k + 3])
                        .sqrt();
                norm = norm.max((n - 1.0).abs());
            }
        }
    }
    let energy = std::fs::read_to_string(out_dir.join("energy.csv")).map_err(|e| e.to_string())?;
    let mut e_first = None;
    let (mut drift, mut e_scale) = (0.0f64, 0.0f64);
    for l in energy.lines().skip(1) {
        let v: Vec<f64> = l.split(',').filter_map(|x| x.parse().ok()).collect();
        if v.len() < 5 {
            continue;
        }
        let total = v[4];
        let e0 = *e_first.get_or_insert(total);
        drift = drift.max((total - e0).abs());
        e_scale = e_scale.max(v[1].abs()).max(v[2].abs());
    }
    Ok(format!(
        "- {summary}\n- outputs: {rows}\n- max |‖p‖ − 1| at the outputs: {norm:.3e}\n- max |E(t) − E(0)|: {drift:.3e} J (relative to max(|T|, |V|) = {e_scale:.3e} J: {:.3e})",
        drift / e_scale.max(f64::MIN_POSITIVE)
    ))
}

fn cargo(root: &Path, args: &[String], envs: &[(&str, &str)]) -> Result<(), String> {
    println!("$ cargo {}", args.join(" "));
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.args(args).envs(envs.iter().copied()).current_dir(root);
    crate::run_status(cmd, &format!("cargo {}", args.join(" ")))
}

fn cargo_output(root: &Path, args: &[&str]) -> Result<String, String> {
    println!("$ cargo {}", args.join(" "));
    let out = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "cargo {} failed:\n{stdout}\n{}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}
