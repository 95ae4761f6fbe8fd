//! A vocabulary as the key tables of docs/model-format.md (written by `cargo xtask docs`,
//! checked by the model crate's `docs_tables` test).

use super::{Default, Vocabulary};

/// The vocabularies written into docs/model-format.md, with the name of their generated block.
pub const GENERATED: [(&str, &Vocabulary); 14] = [
    ("analysis-kinds", &super::ANALYSES),
    ("integrators", &super::INTEGRATORS),
    ("drivers", &super::DRIVERS),
    ("functions", &super::FUNCTIONS),
    ("curves", &super::CURVES),
    ("cams", &super::CAMS),
    ("surfaces", &super::SURFACES),
    ("couplers", &super::COUPLERS),
    ("forces", &super::FORCES),
    ("limits", &super::LIMITS),
    ("frictions", &super::FRICTIONS),
    ("shapes", &super::SHAPES),
    ("materials", &super::MATERIALS),
    ("outputs", &super::OUTPUTS),
];

/// The entries of `vocab` (name, what it is, its keys), then its keys (value, default, meaning,
/// the entries that take it), as Markdown tables.
pub fn markdown(vocab: &Vocabulary) -> String {
    let mut out = String::new();
    if !vocab.entries.is_empty() && !vocab.selector.is_empty() {
        out.push_str(&format!(
            "| `{}` | what it is | keys |\n|---|---|---|\n",
            vocab.selector
        ));
        for e in vocab.entries {
            let mut name = format!("`{}`", e.name);
            if !e.aliases.is_empty() {
                let aliases: Vec<String> = e.aliases.iter().map(|a| format!("`{a}`")).collect();
                name.push_str(&format!(" (alias {})", aliases.join(", ")));
            }
            let keys: Vec<String> = e
                .keys
                .iter()
                .map(|k| match k.default {
                    Default::Required => format!("`{}`", k.name),
                    Default::Is(_) => format!("optional `{}`", k.name),
                })
                .collect();
            out.push_str(&format!(
                "| {name} | {} | {} |\n",
                e.summary,
                keys.join(", ")
            ));
        }
        out.push('\n');
    }
    out.push_str("| key | value | default | meaning | in |\n|---|---|---|---|---|\n");
    let mut seen: Vec<(&str, &str)> = Vec::new();
    let common = vocab.common.iter().map(|k| (k, "every one"));
    let owned = vocab
        .entries
        .iter()
        .flat_map(|e| e.keys.iter().map(move |k| (k, e.name)));
    for (k, _) in common.chain(owned) {
        // The same name with the same meaning once; a name with another meaning in another
        // entry (a driver's `function` is an angle or a length) once per meaning.
        if seen.contains(&(k.name, k.doc)) {
            continue;
        }
        seen.push((k.name, k.doc));
        let taken_by = if vocab.common(k.name) {
            "every one".to_string()
        } else {
            let names: Vec<String> = vocab
                .entries
                .iter()
                .filter(|e| e.keys.iter().any(|o| o.name == k.name && o.doc == k.doc))
                .map(|e| format!("`{}`", e.name))
                .collect();
            names.join(", ")
        };
        let mut name = format!("`{}`", k.name);
        if !k.aliases.is_empty() {
            let aliases: Vec<String> = k.aliases.iter().map(|a| format!("`{a}`")).collect();
            name.push_str(&format!(" (or {})", aliases.join(", ")));
        }
        let default = match k.default {
            Default::Required => "required".to_string(),
            Default::Is(d) => d.to_string(),
        };
        out.push_str(&format!(
            "| {name} | {} | {default} | {} | {taken_by} |\n",
            k.value.describe(),
            k.doc
        ));
    }
    out
}
