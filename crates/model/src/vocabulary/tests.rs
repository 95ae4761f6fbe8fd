use super::*;

/// Every table is consistent: unique entry names (and aliases), unique keys within an entry,
/// no entry key that is also a common key, and every "taken by" list is derived.
#[test]
fn the_tables_are_consistent() {
    for (_, v) in GENERATED {
        let mut names: Vec<&str> = v
            .entries
            .iter()
            .flat_map(|e| std::iter::once(e.name).chain(e.aliases.iter().copied()))
            .collect();
        let n = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n, "{}: an entry name twice", v.what);
        for e in v.entries {
            let mut keys: Vec<&str> = e
                .keys
                .iter()
                .flat_map(|k| std::iter::once(k.name).chain(k.aliases.iter().copied()))
                .collect();
            let n = keys.len();
            keys.sort();
            keys.dedup();
            assert_eq!(keys.len(), n, "{} {}: a key twice", v.what, e.name);
            for k in e.keys {
                assert!(
                    !v.common(k.name),
                    "{} {}: {} is common",
                    v.what,
                    e.name,
                    k.name
                );
                assert!(
                    !k.doc.is_empty(),
                    "{} {}: {} has no doc",
                    v.what,
                    e.name,
                    k.name
                );
            }
        }
    }
}

/// The analysis kinds are the model file's, and each integrator key belongs to some integrator.
#[test]
fn the_analysis_kinds_and_integrators_agree() {
    let kinds: Vec<&str> = ANALYSES.names().collect();
    assert_eq!(
        kinds,
        [
            "kinematic",
            "dynamic",
            "inverse_dynamics",
            "static",
            "quasi_static",
            "modal"
        ]
    );
    assert_eq!(OUTPUTS.names().collect::<Vec<_>>(), kinds);
    let dynamic = ANALYSES.find("dynamic").unwrap();
    for i in INTEGRATORS.entries {
        for k in i.keys {
            assert!(dynamic.key(k.name).is_some(), "{}: {}", i.name, k.name);
        }
    }
    let functions: Vec<&str> = FUNCTIONS.names().collect();
    assert_eq!(functions, cardan_constraints::TimeFunction::KINDS);
}
