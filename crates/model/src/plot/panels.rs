//! Which columns share a panel: one unit per panel, the columns of one element together, at most
//! [`MAX_SERIES`] per panel.
//!
//! Columns are grouped by (unit, element) (a reaction's element is its joint, so forces and
//! torques of a joint get one panel each); groups of one unit are packed in column order into
//! panels of at most [`MAX_SERIES`] series, a group larger than that is split. Panels are
//! ordered by their first column, so a joint's force and torque panels sit side by side.

use super::header::Header;
use std::collections::HashMap;

/// The most series drawn in one panel.
pub const MAX_SERIES: usize = 8;

/// One panel: its unit, the elements it shows and the indices of its columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PanelSpec {
    /// The unit of every column of the panel.
    pub unit: String,
    /// The elements shown, in column order.
    pub elements: Vec<String>,
    /// Column indices (into the table's columns, time excluded).
    pub columns: Vec<usize>,
    /// Part k of n when one element's columns were split (1-based), else `None`.
    pub part: Option<(usize, usize)>,
}

/// The panels of a table with these headers; every column is in exactly one panel.
pub fn panels(headers: &[Header]) -> Vec<PanelSpec> {
    // Column groups by unit, then by element, each in order of first appearance (one pass:
    // tables of 10⁴ bodies have 10⁵ columns).
    let mut units: Vec<(&str, Vec<Group>)> = Vec::new();
    let mut unit_at: HashMap<&str, usize> = HashMap::new();
    let mut group_at: HashMap<(&str, &str), usize> = HashMap::new();
    for (k, h) in headers.iter().enumerate() {
        let u = *unit_at.entry(h.unit).or_insert_with(|| {
            units.push((h.unit, Vec::new()));
            units.len() - 1
        });
        let groups = &mut units[u].1;
        let g = *group_at.entry((h.unit, h.element)).or_insert_with(|| {
            groups.push((h.element, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(k);
    }
    let mut out = Vec::new();
    for (unit, groups) in units {
        pack(unit, groups, &mut out);
    }
    out.sort_by_key(|p| p.columns.first().copied());
    out
}

/// One element's columns of one unit: (element, column indices).
type Group<'a> = (&'a str, Vec<usize>);

/// Packs the element groups of `unit` (in order) into panels appended to `out`.
fn pack(unit: &str, groups: Vec<Group>, out: &mut Vec<PanelSpec>) {
    let mut current: Option<PanelSpec> = None;
    for (element, cols) in groups {
        let fits = current
            .as_ref()
            .is_some_and(|p| p.columns.len() + cols.len() <= MAX_SERIES);
        if fits {
            if let Some(p) = current.as_mut() {
                p.elements.push(element.to_string());
                p.columns.extend(cols);
            }
            continue;
        }
        out.extend(current.take());
        let parts = cols.len().div_ceil(MAX_SERIES);
        for (k, chunk) in cols.chunks(MAX_SERIES).enumerate() {
            let spec = PanelSpec {
                unit: unit.to_string(),
                elements: vec![element.to_string()],
                columns: chunk.to_vec(),
                part: (parts > 1).then_some((k + 1, parts)),
            };
            if parts > 1 {
                out.push(spec);
            } else {
                current = Some(spec);
            }
        }
    }
    out.extend(current);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn specs(cols: &[&str]) -> Vec<PanelSpec> {
        let headers: Vec<Header> = cols.iter().map(|c| Header::parse(c)).collect();
        let p = panels(&headers);
        let mut all: Vec<usize> = p.iter().flat_map(|s| s.columns.clone()).collect();
        all.sort_unstable();
        assert_eq!(all, (0..cols.len()).collect::<Vec<_>>(), "each column once");
        for s in &p {
            assert!(s.columns.len() <= MAX_SERIES && !s.columns.is_empty());
            assert!(
                s.columns.iter().all(|&c| headers[c].unit == s.unit),
                "{s:?}"
            );
        }
        p
    }

    /// The reaction headers of a joint between two bodies.
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
    fn reactions_get_a_force_and_a_torque_panel_per_joint() {
        let mut cols = reaction("crank_pin", ["ground", "crank"]);
        cols.extend(reaction("ball", ["crank", "conrod"]));
        cols.extend(reaction("slide", ["conrod", "slider"]));
        let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
        let p = specs(&refs);
        let names: Vec<(String, &str)> = p
            .iter()
            .map(|s| (s.elements.join(","), s.unit.as_str()))
            .collect();
        let want = [
            ("crank_pin", "N"),
            ("crank_pin", "N m"),
            ("ball", "N"),
            ("ball", "N m"),
        ];
        for (k, (e, u)) in want.iter().enumerate() {
            assert_eq!((names[k].0.as_str(), names[k].1), (*e, *u));
        }
        assert_eq!(p.len(), 6);
    }

    #[test]
    fn units_never_share_a_panel_and_small_elements_pack() {
        let p = specs(&[
            "crank_pin.angle [rad]",
            "slide.slide [m]",
            "other.angle [rad]",
        ]);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].columns, [0, 2]);
        let body = |b: &str| ["x", "y", "z"].map(|c| format!("{b}.r.{c} [m]"));
        let cols: Vec<String> = ["a", "b", "c"].iter().flat_map(|b| body(b)).collect();
        let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
        let p = specs(&refs);
        assert_eq!(
            p.iter().map(|s| s.columns.len()).collect::<Vec<_>>(),
            [6, 3]
        );
    }

    #[test]
    fn a_large_element_is_split_and_odd_tables_work() {
        let cols: Vec<String> = (0..20).map(|k| format!("e.q{k} [m]")).collect();
        let refs: Vec<&str> = cols.iter().map(String::as_str).collect();
        let p = specs(&refs);
        assert_eq!(
            p.iter().map(|s| s.part).collect::<Vec<_>>(),
            [Some((1, 3)), Some((2, 3)), Some((3, 3))]
        );
        assert!(specs(&[]).is_empty());
        assert_eq!(specs(&["a", "b [m]", "c"]).len(), 2);
    }
}
