//! Hostile and malformed URDF input (issue 51): every problem an error with its line and the
//! element's name, never a panic, a hang or unbounded memory.

use cardan_urdf::{import, Base, MimicMode, Options, UrdfError};

fn err(text: &str) -> UrdfError {
    import(text, Options::default()).expect_err("an error")
}

fn kinematic() -> Options {
    Options {
        needs_masses: false,
        ..Options::default()
    }
}

const INERTIAL: &str =
    r#"<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial>"#;

/// A chain world → l1 → … → ln of revolute joints about z.
fn chain(n: usize) -> String {
    let mut s = String::from("<robot name=\"chain\">\n<link name=\"world\"/>\n");
    for k in 1..=n {
        s += &format!("<link name=\"l{k}\">{INERTIAL}</link>\n");
        s += &format!(
            "<joint name=\"j{k}\" type=\"continuous\"><parent link=\"{}\"/><child link=\"l{k}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"0 0 1\"/></joint>\n",
            if k == 1 { "world".to_string() } else { format!("l{}", k - 1) }
        );
    }
    s + "</robot>\n"
}

#[test]
fn malformed_xml_is_an_error_at_its_line() {
    let e = err("<robot name=\"r\">\n<link name=\"a\">\n</robot>\n");
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("not well-formed XML"), "{e}");
    let e = err("");
    assert!(e.message.contains("XML"), "{e}");
    let e = err("<model name=\"x\"/>");
    assert!(e.message.contains("<robot>"), "{e}");
}

#[test]
fn entity_expansion_is_refused_before_it_starts() {
    let mut lol =
        String::from("<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [\n<!ENTITY lol \"lol\">\n");
    for k in 1..10 {
        let prev = if k == 1 {
            "lol".to_string()
        } else {
            format!("lol{}", k - 1)
        };
        lol += &format!("<!ENTITY lol{k} \"{}\">\n", format!("&{prev};").repeat(10));
    }
    lol += "]>\n<robot name=\"&lol9;\"><link name=\"a\"/></robot>\n";
    let e = err(&lol);
    assert!(e.message.contains("document type declaration"), "{e}");
    assert_eq!(e.line, 2);
}

#[test]
fn a_massless_link_is_fine_for_kinematics_and_named_for_dynamics() {
    let text = r#"<robot name="r"><link name="world"/>
<link name="arm"/>
<joint name="j" type="continuous"><parent link="world"/><child link="arm"/></joint></robot>"#;
    assert!(import(text, kinematic()).is_ok());
    let e = err(text);
    assert_eq!(e.line, 2);
    assert!(
        e.message.contains("link \"arm\" moves and has no mass"),
        "{e}"
    );
}

#[test]
fn a_negative_or_degenerate_inertia_is_refused_for_dynamics() {
    let bad = r#"<robot name="r"><link name="world"/>
<link name="arm"><inertial><mass value="1"/>
<inertia ixx="0.1" iyy="-0.1" izz="0.1"/></inertial></link>
<joint name="j" type="continuous"><parent link="world"/><child link="arm"/></joint></robot>"#;
    let e = err(bad);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("negative principal moment"), "{e}");
    assert!(import(bad, kinematic()).is_ok());
    // A point mass alone on a moving body: not a body cardan can integrate.
    let point = bad
        .replace("iyy=\"-0.1\"", "iyy=\"0\"")
        .replace("ixx=\"0.1\"", "ixx=\"0\"")
        .replace("izz=\"0.1\"", "izz=\"0\"");
    let e = err(&point);
    assert!(e.message.contains("not positive definite"), "{e}");
    // The triangle inequality.
    let flat = bad
        .replace("iyy=\"-0.1\"", "iyy=\"0.01\"")
        .replace("ixx=\"0.1\"", "ixx=\"0.01\"");
    let e = err(&flat);
    assert!(e.message.contains("triangle inequality"), "{e}");
}

#[test]
fn a_link_with_two_parents_or_a_cycle_is_refused() {
    let two = r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="fixed"><parent link="a"/><child link="c"/></joint>
<joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint></robot>"#;
    let e = err(two);
    assert_eq!(e.line, 3);
    assert!(e.message.contains("link \"c\" has two parents"), "{e}");
    let cycle = r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
<joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#;
    let e = err(cycle);
    assert!(e.message.contains("cycle"), "{e}");
    let missing = r#"<robot name="r"><link name="a"/>
<joint name="j1" type="fixed"><parent link="a"/><child link="ghost"/></joint></robot>"#;
    let e = err(missing);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("\"ghost\" is not a <link>"), "{e}");
}

#[test]
fn an_unknown_joint_type_names_the_known_ones() {
    let text = r#"<robot name="r"><link name="a"/><link name="b"/>
<joint name="j" type="revolut"><parent link="a"/><child link="b"/></joint></robot>"#;
    let e = err(text);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("unknown joint type \"revolut\""), "{e}");
    assert!(e.message.contains("revolute, continuous, prismatic"), "{e}");
}

#[test]
fn bad_mimic_joints_are_refused_in_couple_mode_and_ignored_when_free() {
    let text = |target: &str| {
        format!(
            r#"<robot name="r"><link name="world"/>
<link name="a">{INERTIAL}</link><link name="b">{INERTIAL}</link>
<joint name="ja" type="continuous"><parent link="world"/><child link="a"/></joint>
<joint name="jb" type="continuous"><parent link="world"/><child link="b"/>
<mimic joint="{target}" multiplier="2"/></joint></robot>"#
        )
    };
    let e = err(&text("jb"));
    assert_eq!(e.line, 5);
    assert!(e.message.contains("mimics itself"), "{e}");
    let e = err(&text("nowhere"));
    assert!(
        e.message.contains("\"nowhere\", which is not a <joint>"),
        "{e}"
    );
    let free = Options {
        mimic: MimicMode::Free,
        ..Options::default()
    };
    let i = import(&text("nowhere"), free).unwrap();
    assert!(i.warnings.iter().any(|w| w.message.contains("free joint")));
    // A good mimic between two joints on the ground: a gear coupler.
    let i = import(&text("ja"), Options::default()).unwrap();
    assert_eq!(i.couplers, vec![(0, 1)]);
}

#[test]
fn a_mimic_on_a_fixed_joint_is_ignored_with_a_warning() {
    // Talos's grippers: fixed joints carrying <mimic> for a simulator plugin.
    let text = format!(
        r#"<robot name="r"><link name="world"/>
<link name="a">{INERTIAL}</link><link name="b">{INERTIAL}</link><link name="c">{INERTIAL}</link>
<joint name="ja" type="revolute"><parent link="world"/><child link="a"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<joint name="jb" type="fixed"><parent link="a"/><child link="b"/>
<mimic joint="ja" multiplier="-1"/></joint>
<joint name="jc" type="fixed"><parent link="a"/><child link="c"/>
<mimic joint="ja"/></joint></robot>"#
    );
    let i = import(&text, Options::default()).unwrap();
    assert!(i.couplers.is_empty());
    let w: Vec<_> = i
        .warnings
        .iter()
        .filter(|w| w.message.contains("<mimic>"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", i.warnings);
    assert_eq!(w[0].line, 5);
    assert!(
        w[0].message
            .starts_with("2 fixed joints with <mimic> (\"jb\", \"jc\")"),
        "{}",
        w[0].message
    );
}

#[test]
fn bad_numbers_name_the_element_and_the_value() {
    let text = r#"<robot name="r"><link name="world"/>
<link name="a">
<inertial><mass value="one"/></inertial></link></robot>"#;
    let e = err(text);
    assert_eq!(e.line, 3);
    assert!(
        e.message.contains("link \"a\"") && e.message.contains("\"one\""),
        "{e}"
    );
    let nan = r#"<robot name="r"><link name="a"/><link name="b"/>
<joint name="j" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0 NaN 0"/></joint></robot>"#;
    let e = err(nan);
    assert!(e.message.contains("not finite"), "{e}");
    let axis = r#"<robot name="r"><link name="a"/><link name="b"/>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/></joint></robot>"#;
    let e = err(axis);
    assert!(e.message.contains("<axis xyz> is zero"), "{e}");
}

#[test]
fn ten_thousand_links_import_quickly() {
    let text = chain(10_000);
    let t = std::time::Instant::now();
    let i = import(&text, Options::default()).unwrap();
    assert_eq!(i.layout.groups.len(), 10_000);
    let toml = cardan_urdf::toml_out::to_toml(&i, "chain.urdf");
    assert!(toml.len() < 20 << 20);
    // Generous: a quadratic step would take minutes.
    assert!(t.elapsed().as_secs() < 30, "{:?}", t.elapsed());
    let _ = Base::Floating;
}

#[test]
fn joint_damping_is_one_warning_listing_the_joints() {
    let mut text = chain(8);
    text = text.replace(
        "</joint>",
        "<dynamics damping=\"0.5\" friction=\"0\"/></joint>",
    );
    let i = import(&text, Options::default()).unwrap();
    let damping: Vec<_> = i
        .warnings
        .iter()
        .filter(|w| w.message.contains("<dynamics>"))
        .collect();
    assert_eq!(damping.len(), 1, "{damping:?}");
    assert!(
        damping[0].message.starts_with("8 joints with <dynamics>"),
        "{}",
        damping[0]
    );
    assert!(
        damping[0].message.contains("\"j1\" (line 4)")
            && damping[0]
                .message
                .ends_with("…; add dampers or [[friction]] in an overlay"),
        "{}",
        damping[0]
    );
    // Zero damping and friction: nothing to say.
    let quiet = chain(2).replace("</joint>", "<dynamics damping=\"0\"/></joint>");
    assert!(import(&quiet, Options::default())
        .unwrap()
        .warnings
        .is_empty());
}

#[test]
fn joint_damping_asked_for_is_a_damper_per_joint_and_a_negative_one_an_error() {
    let text = chain(3).replace(
        "</joint>",
        "<dynamics damping=\"0.5\" friction=\"0\"/></joint>",
    );
    let options = Options {
        damping: true,
        ..Options::default()
    };
    let i = import(&text, options).unwrap();
    assert!(
        !i.warnings.iter().any(|w| w.message.contains("<dynamics>")),
        "{:?}",
        i.warnings
    );
    let toml = cardan_urdf::toml_out::to_toml(&i, "chain.urdf");
    assert_eq!(
        toml.matches("type = \"rotational_spring_damper\"").count(),
        3
    );
    assert!(toml.contains("joint = \"j2\"\ndamping = 0.5"), "{toml}");
    // Not asked for: no damper.
    let plain = import(&text, Options::default()).unwrap();
    let toml = cardan_urdf::toml_out::to_toml(&plain, "chain.urdf");
    assert!(!toml.contains("[[force]]"), "{toml}");
    // A negative damping or friction is refused at its line.
    let bad = chain(2).replace("</joint>", "<dynamics damping=\"-1\"/></joint>");
    let e = err(&bad);
    assert_eq!(e.line, 4, "{e}");
    assert!(
        e.message.contains("<dynamics> damping = -1 is negative"),
        "{e}"
    );
}
