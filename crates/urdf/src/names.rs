//! URDF names → cardan names (ASCII letters, digits and `_`, not starting with a digit, not
//! `ground`), unique within a namespace.

use std::collections::HashSet;

/// The cardan spelling of `name`: every other character becomes `_`, a leading digit (or an
/// empty name) gets a `_` before it.
pub fn sanitize(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

/// One namespace: names handed out once each.
#[derive(Debug, Default, Clone)]
pub struct Namespace {
    taken: HashSet<String>,
}

impl Namespace {
    /// A namespace with `reserved` names already taken.
    pub fn with_reserved(reserved: &[&str]) -> Self {
        Self {
            taken: reserved.iter().map(|s| s.to_string()).collect(),
        }
    }

    /// Whether `name` (already a cardan name) is taken.
    pub fn taken(&self, name: &str) -> bool {
        self.taken.contains(name)
    }

    /// `sanitize(name)`, or with `_2`, `_3`, … appended if that is taken.
    pub fn claim(&mut self, name: &str) -> String {
        let base = sanitize(name);
        let mut candidate = base.clone();
        let mut k = 2;
        while self.taken.contains(&candidate) {
            candidate = format!("{base}_{k}");
            k += 1;
        }
        self.taken.insert(candidate.clone());
        candidate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_cardan_names_and_unique() {
        assert_eq!(sanitize("l_arm/shoulder-1"), "l_arm_shoulder_1");
        assert_eq!(sanitize("3dof"), "_3dof");
        let mut ns = Namespace::with_reserved(&["ground"]);
        assert_eq!(ns.claim("ground"), "ground_2");
        assert_eq!(ns.claim("a-b"), "a_b");
        assert_eq!(ns.claim("a_b"), "a_b_2");
    }
}
