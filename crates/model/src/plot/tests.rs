//! Tests of the table figures: units per panel, legends, colours, odd tables.

use super::*;

fn table(cols: &[&str], rows: usize) -> Table {
    let mut t = Table::new("g", "G", cols.iter().map(|c| c.to_string()).collect());
    for k in 0..rows {
        let time = k as f64 * 0.01;
        let mut row = vec![time];
        row.extend((0..cols.len()).map(|c| (time * (c + 1) as f64).sin()));
        t.rows.push(row);
    }
    t
}

#[test]
fn joint_coordinates_do_not_share_an_axis() {
    let fig = figure(&table(&["crank_pin.angle [rad]", "slide.slide [m]"], 10));
    let labels: Vec<&str> = fig.panels.iter().map(|p| p.y_label.as_str()).collect();
    assert_eq!(labels, ["angle [rad]", "length [m]"]);
}

/// The reaction headers of a joint between two bodies (as in reactions.csv).
fn reaction(joint: &str, bodies: [&str; 2]) -> Vec<String> {
    let mut v = Vec::new();
    for b in bodies {
        for (q, u) in [("F", "N"), ("T", "N m")] {
            v.extend(["x", "y", "z"].map(|c| format!("{joint}.{b}.{q}.{c} [{u}]")));
        }
    }
    v
}

#[test]
fn a_body_keeps_its_colour_across_panels() {
    let mut cols = reaction("j1", ["ground", "crank"]);
    cols.extend(reaction("j2", ["crank", "rod"]));
    let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
    let fig = figure(&table(&refs, 5));
    assert_eq!(fig.panels.len(), 4);
    let colour_of = |label: &str| -> Vec<usize> {
        let all = fig.panels.iter().flat_map(|p| p.series.iter());
        all.filter(|s| s.label == label)
            .map(|s| s.style.colour)
            .collect()
    };
    let crank: Vec<usize> = ["crank.F.x", "crank.T.y"]
        .iter()
        .flat_map(|l| colour_of(l))
        .collect();
    assert_eq!(crank.len(), 4);
    assert!(crank.iter().all(|c| *c == crank[0]));
    assert_ne!(colour_of("ground.F.x"), colour_of("rod.F.x"));
}

#[test]
fn points_of_one_body_are_told_apart() {
    let fig = figure(&table(&["b.P.x [m]", "b.Q.x [m]"], 3));
    let s = &fig.panels[0].series;
    assert_ne!(s[0].style, s[1].style);
}

#[test]
fn odd_tables_give_figures() {
    let empty = table(&[], 0);
    assert!(figure(&empty).panels.is_empty());
    let mut t = table(&["a [m]", "b [m]"], 1);
    t.rows.push(vec![f64::NAN]);
    t.rows.push(vec![0.5, f64::INFINITY, 2.0]);
    let svg = t.to_svg();
    assert!(svg.ends_with("</svg>\n"));
}

#[test]
fn long_tables_are_reduced_while_collected() {
    let t = table(&["a [m]"], 20_000);
    let fig = figure(&t);
    assert!(fig.panels[0].series[0].points.len() <= 2 * PRE_COLUMNS);
}

/// A deterministic noisy value in [-1, 1] (the worst case for a path: every column spans its
/// full height).
fn noise(k: usize, c: usize) -> f64 {
    let h = (k as u64 ^ ((c as u64) << 40)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// A reactions table of `joints` joints (12 columns each) with `rows` noisy samples.
fn noisy_reactions(joints: usize, rows: usize) -> Table {
    let mut cols = Vec::new();
    for j in 0..joints {
        cols.extend(reaction(&format!("j{j}"), ["a", "b"]));
    }
    let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
    let mut t = table(&refs, 0);
    t.rows = (0..rows)
        .map(|k| {
            let mut row = Vec::with_capacity(cols.len() + 1);
            row.push(k as f64 * 1e-5);
            row.extend((0..cols.len()).map(|c| noise(k, c) * (1.0 + c as f64)));
            row
        })
        .collect();
    t
}

#[test]
fn plot_size_is_bounded_for_long_runs() {
    // 10⁶ samples of 12 noisy columns; the slider crank's reactions table has 36 columns, and a
    // plot's size grows with the columns, not the samples: 3 × this must stay under 300 KB.
    let long = noisy_reactions(1, 1_000_000).to_svg();
    let short = noisy_reactions(1, 20_000).to_svg();
    assert!(3 * long.len() < 300_000, "{} bytes", long.len());
    assert!(
        long.len() < short.len() * 11 / 10,
        "{} vs {}",
        long.len(),
        short.len()
    );
}

#[test]
fn a_panel_of_round_off_is_drawn_flat_on_its_siblings_scale() {
    let mut cols = reaction("pin", ["ground", "crank"]);
    cols.extend(reaction("ball", ["crank", "rod"]));
    let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
    let mut t = table(&refs, 20);
    // The ball's torques (row entries 16..19 and 22..25; entry 0 is t) are round-off.
    for (k, row) in t.rows.iter_mut().enumerate() {
        for c in (16..19).chain(22..25) {
            row[c] = 1e-16 * ((k % 3) as f64 - 1.0);
        }
    }
    let fig = figure(&t);
    let ball_torque = fig
        .panels
        .iter()
        .find(|p| p.title.starts_with("ball") && p.y_label.contains("N m"))
        .unwrap();
    assert!(
        ball_torque.title.contains("round-off only"),
        "{}",
        ball_torque.title
    );
    assert!(ball_torque.y_extent.unwrap() > 0.5);
    let normal = fig.panels.iter().filter(|p| p.y_extent.is_some()).count();
    assert_eq!(normal, 1, "only the round-off panel is flattened");
}

/// A table of a large model (here 2,000 bodies, two to a panel) draws the `MAX_PANELS` panels
/// that change most, in table order, and its title says how many there were; a small table is
/// drawn whole under its own title.
#[test]
fn a_large_table_draws_the_panels_that_change_most() {
    let n = 2_000;
    let cols: Vec<String> = (0..n)
        .flat_map(|b| ["x", "y", "z"].map(|c| format!("b{b}.r.{c} [m]")))
        .collect();
    let mut t = Table::new("bodies", "Bodies", cols);
    for k in 0..4 {
        let time = k as f64 * 0.1;
        let mut row = vec![time];
        // Body b moves by (b mod 100) · t: the panels of bodies 99, 199, …, 1999 most (20
        // panels, each with the body before), then those of 97, 197, … (the first 4 of them).
        row.extend((0..3 * n).map(|c| time * ((c / 3) % 100) as f64));
        t.rows.push(row);
    }
    let fig = figure(&t);
    assert_eq!(fig.panels.len(), MAX_PANELS);
    assert!(
        fig.title.starts_with("Bodies (24 of 1000 panels"),
        "{}",
        fig.title
    );
    let titles: Vec<&str> = fig.panels.iter().map(|p| p.title.as_str()).collect();
    let pair = |b: usize| (b, format!("b{}, b{}", b - 1, b));
    let mut want: Vec<(usize, String)> = (0..20).map(|k| pair(100 * k + 99)).collect();
    want.extend((0..4).map(|k| pair(100 * k + 97)));
    want.sort();
    assert_eq!(
        titles,
        want.iter().map(|w| w.1.as_str()).collect::<Vec<_>>()
    );
    let small = figure(&table(&["b.r.x [m]"], 3));
    assert_eq!(small.title, "G");
}
