//! Bad ASMT files: a clear error at the right line, never a panic.

use std::path::PathBuf;

fn piston() -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/rackscrew.asmt");
    std::fs::read_to_string(p).unwrap()
}

/// The 1-based line of the first line equal to `line` (tabs included).
fn line_of(text: &str, line: &str) -> usize {
    text.lines().position(|l| l == line).unwrap() + 1
}

fn error(text: &str) -> cardan_asmt::AsmtError {
    match cardan_asmt::load(text) {
        Ok(_) => panic!("accepted"),
        Err(e) => e,
    }
}

#[test]
fn the_good_file_loads_with_no_warnings() {
    let (doc, import) = cardan_asmt::load(&piston()).unwrap();
    assert_eq!(doc.parts.len(), 3);
    assert_eq!(import.joints.len(), 3);
    assert_eq!(import.couplers.len(), 2);
    assert_eq!(import.drivers.len(), 1);
    // Only the massless part is reported.
    assert_eq!(import.warnings.len(), 1, "{:?}", import.warnings);
    assert!(import.warnings[0].message.contains("no mass"));
    import.builder().build().unwrap();
}

#[test]
fn truncated_file() {
    let text = piston();
    for cut in [3, 40, 200, 330, 372] {
        let short: String = text.lines().take(cut).map(|l| format!("{l}\n")).collect();
        let e = error(&short);
        assert!(e.line >= 1 && e.line <= cut, "cut {cut}: {e}");
    }
}

#[test]
fn spaces_instead_of_tabs() {
    let text = piston().replacen("\t\t\tRevoluteJoint", "      RevoluteJoint", 1);
    let e = error(&text);
    assert_eq!(e.line, line_of(&piston(), "\t\t\tRevoluteJoint"));
    assert!(e.message.contains("spaces"), "{e}");
}

#[test]
fn unknown_joint_kind() {
    let text = piston().replacen("\t\t\tScrewJoint", "\t\t\tWormJoint", 1);
    let e = error(&text);
    assert_eq!(e.line, line_of(&piston(), "\t\t\tScrewJoint"));
    assert!(e.message.contains("WormJoint"), "{e}");
}

#[test]
fn missing_marker_path() {
    let text = piston().replacen(
        "\t\t\t\t\t/Assembly1/Assembly1Part2/Assembly1Part2Marker2",
        "\t\t\t\t\t/Assembly1/Assembly1Part2/NoSuchMarker",
        1,
    );
    let e = error(&text);
    assert_eq!(
        e.line,
        line_of(
            &piston(),
            "\t\t\t\t\t/Assembly1/Assembly1Part2/Assembly1Part2Marker2"
        )
    );
    assert!(e.message.contains("NoSuchMarker"), "{e}");
    assert!(e.message.contains("Assembly1Joint1"), "{e}");
}

#[test]
fn nan_and_infinity() {
    for bad in ["NaN", "inf", "1e999"] {
        for (field, value) in [
            ("\t\t\t\tpitch\n", "\t\t\t\t\t1.0 \n"),
            ("\tConstantGravity\n", "\t\t0.0 \t-9.81 \t0.0 \n"),
        ] {
            let good = format!("{field}{value}");
            let broken = format!(
                "{field}{}",
                value.replacen("1.0", bad, 1).replacen("-9.81", bad, 1)
            );
            let text = piston().replacen(&good, &broken, 1);
            assert_ne!(text, piston());
            let e = error(&text);
            assert!(e.message.contains("finite"), "{bad}: {e}");
        }
    }
}

#[test]
fn motion_on_a_missing_joint() {
    let text = piston().replacen(
        "\t\t\t\t\t/Assembly1/Assembly1Joint1\n",
        "\t\t\t\t\t/Assembly1/Gone\n",
        1,
    );
    let e = error(&text);
    assert_eq!(
        e.line,
        line_of(&piston(), "\t\t\t\t\t/Assembly1/Assembly1Joint1")
    );
    assert!(e.message.contains("/Assembly1/Gone"), "{e}");
}

#[test]
fn bad_expression() {
    let text = piston().replacen("2*pi*time", "2*pi*tim", 1);
    let e = error(&text);
    assert_eq!(e.line, line_of(&piston(), "\t\t\t\t\t2*pi*time"));
    assert!(e.message.contains("tim"), "{e}");
}

#[test]
fn force_elements_are_warnings_and_limits_are_read() {
    let with_force = piston().replacen(
        "\tForceTorques\n",
        "\tForceTorques\n\t\tForceTorque\n\t\t\tName\n\t\t\t\tSpring\n",
        1,
    );
    let (_, import) = cardan_asmt::load(&with_force).unwrap();
    let w: Vec<String> = import.warnings[1..].iter().map(|w| w.to_string()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("ForceTorque \"Spring\""), "{w:?}");
    // A limit is a bound on a joint's coordinate (tests of crates/cli/tests/asmt_limits.rs): one
    // without its Limit is an error at its line, naming it.
    let text = with_force.replacen(
        "\t\tGeneralConstraintSets\n",
        "\t\tLimits\n\t\t\tRotationLimit\n\t\t\t\tName\n\t\t\t\t\tStop\n\t\tGeneralConstraintSets\n",
        1,
    );
    let e = cardan_asmt::load(&text).unwrap_err().to_string();
    assert!(
        e.contains("RotationLimit \"Stop\"") && e.contains("Limit"),
        "{e}"
    );
}

#[test]
fn arbitrary_edits_never_panic() {
    let text = piston();
    let lines: Vec<&str> = text.lines().collect();
    // Drop each line in turn (every 7th, to stay quick) and duplicate it: errors or models,
    // never panics.
    for k in (0..lines.len()).step_by(7) {
        let mut dropped = lines.clone();
        dropped.remove(k);
        let _ = cardan_asmt::load(&dropped.join("\n"));
        let mut doubled = lines.clone();
        doubled.insert(k, lines[k]);
        if let Ok((_, i)) = cardan_asmt::load(&doubled.join("\n")) {
            let _ = i.builder().build();
        }
    }
}

/// A rack and pinion whose joints share no body (the pinion's revolute moved from the ground to
/// another part): cardan's couplers relate two joints on a common body, so the file is refused
/// at the coupler's line, naming it.
#[test]
fn coupler_whose_joints_share_no_body() {
    let text = piston().replacen(
        "\t\t\t\t\t/Assembly1/Assembly1Marker2\n",
        "\t\t\t\t\t/Assembly1/Assembly1Part1/Assembly1Part1Marker1\n",
        1,
    );
    assert_ne!(text, piston());
    let e = error(&text);
    assert_eq!(e.line, line_of(&piston(), "\t\t\tRackPinionJoint"));
    assert!(
        e.message
            .contains("RackPinionJoint /Assembly1/Assembly1Joint3")
            && e.message.contains("common body"),
        "{e}"
    );
}

/// An AngleJoint at θ = 0 (or near π): its row z_I·z_J − cos θ loses rank, refused at its
/// theIzJz line.
#[test]
fn angle_joint_near_parallel_axes() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/small/angle.asmt");
    let text = std::fs::read_to_string(p).unwrap();
    for theta in ["0.0", "3.1412", "-0.3"] {
        let bad = text.replacen(
            "\t\t\t\t\t1.0471975511965976",
            &format!("\t\t\t\t\t{theta}"),
            1,
        );
        let e = error(&bad);
        assert_eq!(e.line, line_of(&bad, &format!("\t\t\t\t\t{theta}")), "{e}");
        assert!(e.to_string().contains("loses rank"), "{e}");
    }
}
