//! The keys written in the file's tables, with their spans ([`KeySpans`], taken from the
//! parsed document before it is deserialized), and the generic check of a table against its
//! vocabulary entry ([`check`]): the entry exists, every key it is given is one it takes, every
//! key it needs is there.

use super::{Default, Entry, Vocabulary};
use crate::diag::{did_you_mean, list, Error, Source};
use std::collections::HashMap;
use std::ops::Range;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// The keys written in each table of the sections that have vocabularies (`[analysis]`,
/// `[[driver]]`, `[[force]]`, `[[coupler]]` and the function tables inside them), found by the
/// start of the table's span (the span the deserialized `Spanned` section or inline table has).
#[derive(Debug, Default, Clone)]
pub struct KeySpans {
    tables: HashMap<usize, Present>,
    texts: HashMap<usize, Texts>,
}

/// The keys of one table, in the order written, with their spans.
pub type Present = Vec<(String, Range<usize>)>;

/// The text values of one table's keys whose value is a string, with the value's span.
type Texts = HashMap<String, (String, Range<usize>)>;

/// The top-level sections whose tables are checked against a vocabulary.
const SECTIONS: [&str; 11] = [
    "analysis", "driver", "force", "coupler", "limit", "friction", "curve", "cam", "surface",
    "shape", "material",
];

impl KeySpans {
    /// Adds the keys of another part of the same text (an overlay's robot, [`crate::overlay`]).
    pub fn extend(&mut self, other: KeySpans) {
        self.tables.extend(other.tables);
        self.texts.extend(other.texts);
    }

    /// The keys of the vocabulary sections of `doc` (the parsed file).
    pub fn collect(doc: &DeTable<'_>) -> Self {
        let mut spans = Self::default();
        for (key, value) in doc.iter() {
            if SECTIONS.contains(&key.get_ref().as_ref()) {
                spans.walk(value);
            }
        }
        spans
    }

    fn walk(&mut self, value: &Spanned<DeValue<'_>>) {
        match value.get_ref() {
            DeValue::Table(t) => {
                let mut keys: Present = t
                    .iter()
                    .map(|(k, _)| (k.get_ref().to_string(), k.span()))
                    .collect();
                keys.sort_by_key(|(_, s)| s.start);
                let texts: Texts = t
                    .iter()
                    .filter_map(|(k, v)| match v.get_ref() {
                        DeValue::String(text) => {
                            Some((k.get_ref().to_string(), (text.to_string(), v.span())))
                        }
                        _ => None,
                    })
                    .collect();
                self.tables.insert(value.span().start, keys);
                self.texts.insert(value.span().start, texts);
                for (_, v) in t.iter() {
                    self.walk(v);
                }
            }
            DeValue::Array(a) => {
                for v in a.iter() {
                    self.walk(v);
                }
            }
            _ => {}
        }
    }

    /// The keys of the table whose span starts at `start` (none for a table not collected).
    pub fn of(&self, start: usize) -> &[(String, Range<usize>)] {
        self.tables.get(&start).map_or(&[], Vec::as_slice)
    }

    /// The text value of `key` in the table whose span starts at `start`, with its span.
    pub fn text(&self, start: usize, key: &str) -> Option<&(String, Range<usize>)> {
        self.texts.get(&start)?.get(key)
    }
}

/// Checks a table against `vocab`: its entry `selected` (the value of the vocabulary's selector,
/// with its span) exists; the keys of the table at `table` that `keep` keeps are the entry's or
/// the vocabulary's common ones, each once (not under its name and an older one), with a value
/// of its choices where it has some; every required key of the entry is there. `owner` starts
/// the messages ("driver \"motor\""; empty: none); `element` is where a missing key is reported.
///
/// # Errors
/// An input error at the unknown name, at the misplaced key or value, or at the element for a
/// missing key.
pub fn check(
    src: &Source,
    vocab: &Vocabulary,
    owner: &str,
    selected: &Spanned<String>,
    (keys, table): (&KeySpans, usize),
    keep: impl Fn(&str) -> bool,
    element: Range<usize>,
) -> Result<&'static Entry, Error> {
    let prefix = if owner.is_empty() {
        String::new()
    } else {
        format!("{owner}: ")
    };
    let name = selected.get_ref().as_str();
    let Some(entry) = vocab.find(name) else {
        let plural = vocab.what.rsplit(' ').next().unwrap_or(vocab.what);
        return Err(src.error_at(
            selected.span(),
            format!(
                "{prefix}unknown {} \"{name}\"{} ({plural}s: {})",
                vocab.what,
                did_you_mean(name, vocab.names()),
                list(vocab.names())
            ),
        ));
    };
    let present: Vec<&(String, Range<usize>)> =
        keys.of(table).iter().filter(|(k, _)| keep(k)).collect();
    for (i, (key, span)) in present.iter().enumerate() {
        let spec = vocab
            .common
            .iter()
            .find(|k| k.is(key))
            .or_else(|| entry.key(key));
        let Some(spec) = spec else {
            return Err(src.error_at(span.clone(), misplaced(vocab, entry, key, &prefix)));
        };
        if let Some((other, _)) = present[..i].iter().find(|(k, _)| spec.is(k)) {
            return Err(src.error_at(
                span.clone(),
                format!(
                    "{prefix}give {} or {}, not both (the same key: {} is its older name)",
                    spec.name,
                    if other == spec.name { key } else { other },
                    if other == spec.name { key } else { other },
                ),
            ));
        }
        if let (super::Value::Choice(words), Some((text, at))) = (spec.value, keys.text(table, key))
        {
            if !words.contains(&text.as_str()) && key != vocab.selector {
                return Err(src.error_at(
                    at.clone(),
                    format!(
                        "{prefix}{key} = \"{text}\" is not supported: use {}{}",
                        words
                            .iter()
                            .map(|w| format!("\"{w}\""))
                            .collect::<Vec<_>>()
                            .join(" or "),
                        did_you_mean(text, words.iter().copied())
                    ),
                ));
            }
        }
    }
    for key in entry.keys {
        let given = present.iter().any(|(k, _)| key.is(k));
        if key.default == Default::Required && !given {
            return Err(src.error_at(
                element,
                format!("{prefix}missing key \"{}\" ({})", key.name, key.doc),
            ));
        }
    }
    Ok(entry)
}
/// The message for `key`, given to `entry`, which does not take it.
fn misplaced(vocab: &Vocabulary, entry: &Entry, key: &str, prefix: &str) -> String {
    let sel = vocab.selector;
    let owners = vocab.taking(key);
    let elsewhere = vocab
        .entries
        .iter()
        .find_map(|e| e.key(key))
        .map_or("", |k| k.elsewhere);
    let applies = match owners.as_slice() {
        [] => String::new(),
        some => {
            let names: Vec<String> = some.iter().map(|n| format!("{sel} = \"{n}\"")).collect();
            let note = if elsewhere.is_empty() {
                String::new()
            } else {
                format!(": {elsewhere}")
            };
            format!(" (it applies to {}{note})", names.join(", "))
        }
    };
    format!(
        "{prefix}{sel} = \"{}\" does not take \"{key}\"{applies}; it takes {}",
        entry.name,
        list(entry.keys.iter().map(|k| k.name))
    )
}
