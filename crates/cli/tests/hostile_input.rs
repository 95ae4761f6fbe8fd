//! Hostile input: huge files, 10⁶ bodies declared, deep nesting, enormous arrays, 1e308 and
//! subnormal numbers, self-referencing definitions. Each is run through the real binary and
//! must end with a non-zero exit code and a one-paragraph message, in bounded time (< 5 s, debug
//! build) and without a panic or a stack overflow. The files are generated here, never
//! committed. The limits are `cardan_model::file::{MAX_FILE_BYTES, MAX_BODIES, MAX_ELEMENTS,
//! MAX_ARRAY_LEN, MAX_NESTING}` (docs/model-format.md, "Limits").

use cardan_model::file::{MAX_BODIES, MAX_FILE_BYTES};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

mod common;
use common::{edited, BASE};

fn scratch() -> PathBuf {
    common::scratch("hostile")
}

/// Writes `text` to a fresh directory, runs `cardan check` on it and checks the common contract:
/// failure, one paragraph naming every needle, no panic, under `limit`. Returns stderr.
fn rejected(text: &[u8], needles: &[&str]) -> String {
    let dir = scratch();
    let path = dir.join("model.toml");
    std::fs::write(&path, text).unwrap();
    let out = rejected_path(&dir, &path, needles);
    let _ = std::fs::remove_dir_all(&dir);
    out
}

fn rejected_path(dir: &Path, path: &Path, needles: &[&str]) -> String {
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_cardan"))
        .args(["check", path.to_str().unwrap()])
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the binary runs");
    let took = start.elapsed();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !stderr.contains("panicked") && !stderr.contains("stack overflow"),
        "panic: {stderr}"
    );
    assert_eq!(out.status.code(), Some(1), "input error expected: {stderr}");
    assert_eq!(
        cardan_model::diag::message_paragraph(&stderr)
            .lines()
            .count(),
        1,
        "one paragraph: {stderr}"
    );
    assert!(
        cardan_model::diag::message_paragraph(&stderr).len() < 600,
        "a short message: {stderr}"
    );
    for n in needles {
        assert!(stderr.contains(n), "missing {n:?} in: {stderr}");
    }
    assert!(took < Duration::from_secs(5), "took {took:?}: {stderr}");
    stderr
}

#[test]
fn file_over_the_size_limit_is_refused_before_reading() {
    // A sparse file (a hole, no data written) just over the limit: refused from its metadata.
    let dir = scratch();
    let path = dir.join("model.toml");
    let f = std::fs::File::create(&path).unwrap();
    f.set_len(MAX_FILE_BYTES as u64 + 1).unwrap();
    drop(f);
    rejected_path(&dir, &path, &["bytes long", &MAX_FILE_BYTES.to_string()]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn million_body_tables_are_refused_before_parsing() {
    // 10⁶ [[body]] tables fit in the size limit (about 18 MB); the header count stops them
    // before the parser.
    let mut text = String::from("[model]\nname = \"many\"\n");
    for k in 0..1_000_000 {
        text.push_str(&format!("[[body]]\nname=\"{k}\"\n"));
    }
    assert!(text.len() < MAX_FILE_BYTES);
    rejected(
        text.as_bytes(),
        &["[[...]] tables", &format!("at most {MAX_BODIES} bodies")],
    );
}

#[test]
fn too_many_bodies_as_an_inline_array_are_refused_after_parsing() {
    let many = MAX_BODIES + 1;
    let bodies: Vec<String> = (0..many).map(|k| format!("{{name=\"{k}\"}}")).collect();
    let text = format!("body = [{}]\n[model]\nname = \"many\"\n", bodies.join(","));
    rejected(
        text.as_bytes(),
        &[&format!("{many} bodies"), &format!("at most {MAX_BODIES}")],
    );
}

#[test]
fn deeply_nested_arrays_do_not_overflow_the_stack() {
    for depth in [100, 100_000] {
        let text = format!(
            "{}\nextra = {}{}\n",
            BASE,
            "[".repeat(depth),
            "]".repeat(depth)
        );
        rejected(text.as_bytes(), &["nested more than 32 levels"]);
    }
}

#[test]
fn deeply_nested_inline_tables_do_not_overflow_the_stack() {
    let depth = 100_000;
    let text = format!(
        "extra = {}1{}\n{BASE}",
        "{ a = ".repeat(depth),
        " }".repeat(depth)
    );
    rejected(text.as_bytes(), &["nested more than 32 levels"]);
}

#[test]
fn brackets_inside_strings_and_comments_do_not_count_as_nesting() {
    // 40 '[' in a string and in a comment: not nesting; the file is valid, check succeeds.
    let text = edited(
        "name = \"crank\"\n",
        &format!(
            "name = \"crank\"\ndescription = \"{}\" # {}\n",
            "[".repeat(40),
            "{".repeat(40)
        ),
    );
    let o = common::run_text("check", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let _ = std::fs::remove_dir_all(&o.dir);
}

#[test]
fn enormous_arrays_are_refused() {
    let coefficients = vec!["0.5"; 20_000].join(", ");
    let text = edited(
        "coefficients = [0.0, 1.0]",
        &format!("coefficients = [{coefficients}]"),
    );
    rejected(text.as_bytes(), &["20000 entries", "at most 10000"]);
    let times: Vec<String> = (0..20_001).map(|k| format!("{k}.0")).collect();
    let text = edited(
        "function = { kind = \"polynomial\", coefficients = [0.0, 1.0] }",
        &format!(
            "function = {{ kind = \"spline\", times = [{0}], values = [{0}] }}",
            times.join(",")
        ),
    );
    rejected(text.as_bytes(), &["spline times", "at most 10000"]);
}

#[test]
fn huge_numbers_are_refused() {
    rejected(
        edited("mass = 1.0", "mass = 1e308").as_bytes(),
        &["mass", "1e308", "beyond the limit of"],
    );
    rejected(
        edited("tip = [0.5, 0.0, 0.0]", "tip = [1e308, 0.0, 0.0]").as_bytes(),
        &["tip", "beyond the limit of"],
    );
    rejected(
        edited("t_end = 1.0", "t_end = 1e308").as_bytes(),
        &["t_end", "beyond the limit of"],
    );
    // Beyond f64: TOML parses it as infinity.
    rejected(
        edited("mass = 1.0", "mass = 1e999").as_bytes(),
        &["model.toml:10:8", "overflowed"],
    );
}

#[test]
fn subnormal_numbers_are_refused() {
    rejected(
        edited("mass = 1.0", "mass = 5e-324").as_bytes(),
        &["mass", "5e-324", "subnormal"],
    );
    rejected(
        edited("tip = [0.5, 0.0, 0.0]", "tip = [0.5, 5e-324, 0.0]").as_bytes(),
        &["tip", "subnormal"],
    );
    rejected(
        edited(
            "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n[[body]]",
            "vectors = { z = [0.0, 0.0, 2.2e-308], x = [1.0, 0.0, 0.0] }\n\n[[body]]",
        )
        .as_bytes(),
        &["ground vector", "subnormal"],
    );
    rejected(
        edited("coefficients = [0.0, 1.0]", "coefficients = [0.0, 1e-310]").as_bytes(),
        &["coefficients[1]", "subnormal"],
    );
}

#[test]
fn tiny_but_normal_numbers_give_a_readable_message() {
    // A direction of length 1e-300 is refused as zero; the message prints it compactly.
    let e = rejected(
        edited(
            "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n[[body]]",
            "vectors = { z = [0.0, 0.0, 1e-300], x = [1.0, 0.0, 0.0] }\n\n[[body]]",
        )
        .as_bytes(),
        &["zero length", "1e-300"],
    );
    assert!(!e.contains("0.000000000"), "{e}");
}

#[test]
fn self_referencing_definitions_are_refused() {
    // A joint from a body to itself.
    rejected(
        edited(
            "body_i = \"ground\"\npoint_i = \"O\"",
            "body_i = \"crank\"\npoint_i = \"tip\"",
        )
        .as_bytes(),
        &["to itself"],
    );
    // A driver that drives itself.
    rejected(
        edited("joint = \"pivot\"\nfunction", "joint = \"motor\"\nfunction").as_bytes(),
        &["motor", "unknown joint"],
    );
    // A second driver that drives the first driver.
    let text = format!(
        "{}\n[[driver]]\nname = \"meta\"\ntype = \"rotation\"\njoint = \"motor\"\nfunction = {{ kind = \"constant\", value = 0.0 }}\n",
        BASE.replace("[analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 10\n", "")
    );
    rejected(text.as_bytes(), &["meta", "unknown joint \"motor\""]);
    // A body whose name is also a joint's name, and a joint named like a driver.
    rejected(
        edited("name = \"pivot\"", "name = \"motor\"").as_bytes(),
        &["motor"],
    );
    // An output that names the body as its own point.
    rejected(
        format!("{BASE}[analysis.outputs]\npoints = [\"crank.crank\"]\n").as_bytes(),
        &["crank"],
    );
}

#[test]
fn binary_garbage_is_refused() {
    let mut bytes: Vec<u8> = (0..1_000_000u32)
        .map(|k| (k.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    bytes[0] = 0xff;
    rejected(&bytes, &["UTF-8"]);
}

#[test]
fn runs_that_would_store_too_much_are_refused() {
    // 10⁷ steps of one body with two points would store 3·10⁷ frames (≈ 8 GB): refused before
    // anything is allocated.
    let text = edited("steps = 10", "steps = 10000000");
    let dir = scratch();
    std::fs::write(dir.join("model.toml"), &text).unwrap();
    rejected_path(
        &dir,
        &dir.join("model.toml"),
        &["stored frames", "use fewer steps"],
    );
    // The same through dt.
    let text = edited("steps = 10", "dt = 1e-7");
    rejected(text.as_bytes(), &["stored frames"]);
}
