//! The model file's vocabularies as data, the way the joint kinds are
//! (`cardan_constraints::KINDS`): analysis kinds, integrators, drivers, time functions, force
//! elements, curves, cams, couplers, limits, joint friction, collision shapes, contact materials and the output groups. Each [`Vocabulary`] is a list of [`Entry`]s (a
//! name, its aliases, a summary and the [`Key`]s it takes); each key has its value's
//! [`Value`] (a quantity with its SI unit, a count with its range, a name, a function...), its
//! default and what it means.
//!
//! Everything about keys is derived from these tables:
//! - which keys an element may have: a key of another entry is refused at its line, naming the
//!   entries it belongs to ([`check`]); a key of no entry is refused by the parser with the
//!   nearest valid key ([`crate::file::parse`]);
//! - which keys it must have ([`check`]), and what "unknown kind" lists ([`Vocabulary::find`]);
//! - a number's quantity, for the unit conversion and the magnitude limits
//!   ([`Entry::quantity`]);
//! - the key tables of docs/model-format.md (`cargo xtask docs`, [`markdown`]).
//!
//! Adding an option is one [`Key`] in the entries that take it (and its use in the loader);
//! adding a kind is one [`Entry`].

mod analyses;
mod cams;
mod check;
mod couplers;
mod curves;
mod drivers;
mod forces;
mod functions;
mod integrators;
mod limits;
mod markdown;
mod outputs;
mod shapes;
mod surfaces;

pub use analyses::ANALYSES;
pub use cams::CAMS;
pub use check::{check, KeySpans, Present};
pub use couplers::COUPLERS;
pub use curves::CURVES;
pub use drivers::DRIVERS;
pub use forces::FORCES;
pub use functions::FUNCTIONS;
pub use integrators::INTEGRATORS;
pub use limits::{FRICTIONS, LIMITS};
pub use markdown::{markdown, GENERATED};
pub use outputs::OUTPUTS;
pub use shapes::{MATERIALS, SHAPES};
pub use surfaces::SURFACES;

use cardan_mechanism::Quantity;

/// What a key's value is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A number of a quantity (its SI unit, the model's units converted, its magnitude limit).
    Number(Quantity),
    /// A three-vector of a quantity.
    Vector(Quantity),
    /// A whole number in `[min, max]`.
    Count {
        /// Smallest accepted.
        min: i64,
        /// Largest accepted.
        max: i64,
    },
    /// A tolerance (dimensionless, scaled residual) in `[min, max]`.
    Tolerance {
        /// Smallest accepted.
        min: f64,
        /// Largest accepted.
        max: f64,
    },
    /// A name of another element (a body, a point, a joint...).
    Name,
    /// A list of names.
    Names,
    /// One of the given words.
    Choice(&'static [&'static str]),
    /// A time function `{ kind = ..., ... }` whose value is of this quantity.
    Function(Quantity),
    /// A list of time functions (three components, or a pose's six).
    Functions(Quantity),
    /// A list of numbers (a polynomial's coefficients, a spline's knots).
    Numbers,
    /// A list of points `[[x, y, z], ...]` of a quantity (a spline's points).
    Points(Quantity),
    /// A text (an expression).
    Text,
    /// true or false.
    Flag,
    /// A table of its own (`[analysis.outputs]`).
    Table,
}

impl Value {
    /// The value as the docs describe it: "number, s", "whole number 1 – 1000", "name"...
    pub fn describe(&self) -> String {
        let unit = |q: &Quantity| match q.unit() {
            "" => String::new(),
            u => format!(", {u}"),
        };
        match self {
            Value::Number(q) => format!("number{}", unit(q)),
            Value::Vector(q) => format!("[x, y, z]{}", unit(q)),
            Value::Count { min, max } => format!("whole number {min} – {max}"),
            Value::Tolerance { min, max } => format!("number {min:e} – {max:e}"),
            Value::Name => "name".into(),
            Value::Names => "list of names".into(),
            Value::Choice(words) => words
                .iter()
                .map(|w| format!("\"{w}\""))
                .collect::<Vec<_>>()
                .join(" or "),
            Value::Function(q) => format!("function{}", unit(q)),
            Value::Functions(q) => format!("list of functions{}", unit(q)),
            Value::Numbers => "list of numbers".into(),
            Value::Points(q) => format!("[[x, y, z], ...]{}", unit(q)),
            Value::Text => "text".into(),
            Value::Flag => "true or false".into(),
            Value::Table => "table".into(),
        }
    }
}

/// Whether a key must be given, and what it is when not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Default {
    /// The element needs it.
    Required,
    /// Optional; the text says what holds without it ("0", "the drawn pose's value").
    Is(&'static str),
}

/// One key of an entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// The name in the file.
    pub name: &'static str,
    /// Older spellings still accepted (the same meaning in this entry).
    pub aliases: &'static [&'static str],
    /// What its value is.
    pub value: Value,
    /// Required, or its default.
    pub default: Default,
    /// What it means (one sentence for the docs).
    pub doc: &'static str,
    /// Said when the key is given to an entry that does not take it, after "… does not apply
    /// to …" (e.g. "a kinematic analysis's output step is dt or steps").
    pub elsewhere: &'static str,
}

impl Key {
    /// A key with no aliases and nothing to add when misplaced.
    pub const fn new(
        name: &'static str,
        value: Value,
        default: Default,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            aliases: &[],
            value,
            default,
            doc,
            elsewhere: "",
        }
    }

    /// The same key with older spellings.
    pub const fn aliases(mut self, aliases: &'static [&'static str]) -> Self {
        self.aliases = aliases;
        self
    }

    /// The same key with a sentence for when it is given where it does not apply.
    pub const fn elsewhere(mut self, note: &'static str) -> Self {
        self.elsewhere = note;
        self
    }

    /// The same key, optional with this default.
    pub const fn default_is(mut self, default: &'static str) -> Self {
        self.default = Default::Is(default);
        self
    }

    /// Whether `name` is this key or one of its aliases.
    pub fn is(&self, name: &str) -> bool {
        self.name == name || self.aliases.contains(&name)
    }
}

/// One entry of a vocabulary: an analysis kind, a driver type...
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// The name in the file.
    pub name: &'static str,
    /// Other accepted names.
    pub aliases: &'static [&'static str],
    /// What it is (one sentence for the docs).
    pub summary: &'static str,
    /// The keys it takes (besides its vocabulary's common keys).
    pub keys: &'static [Key],
}

impl Entry {
    /// The key `name` (or an alias of it).
    pub fn key(&self, name: &str) -> Option<&'static Key> {
        self.keys.iter().find(|k| k.is(name))
    }

    /// The quantity of the number (or vector, or function value) `name` takes, for its unit
    /// and magnitude limit; `Unbounded` for a key that is not a quantity.
    pub fn quantity(&self, name: &str) -> Quantity {
        match self.key(name).map(|k| k.value) {
            Some(
                Value::Number(q)
                | Value::Vector(q)
                | Value::Function(q)
                | Value::Functions(q)
                | Value::Points(q),
            ) => q,
            _ => Quantity::Unbounded,
        }
    }
}

/// A vocabulary: the entries one key selects (`kind` of `[analysis]`, `type` of a driver...).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vocabulary {
    /// What an entry is called in messages ("analysis kind", "driver type").
    pub what: &'static str,
    /// The table the entries describe, for messages and docs (`"[analysis]"`, `"[[driver]]"`).
    pub table: &'static str,
    /// The key that selects the entry ("kind", "type", "integrator").
    pub selector: &'static str,
    /// Keys every entry takes (the selector, `name`...).
    pub common: &'static [Key],
    /// The entries.
    pub entries: &'static [Entry],
}

impl Vocabulary {
    /// The entry named `name` (or by an alias).
    pub fn find(&self, name: &str) -> Option<&'static Entry> {
        self.entries
            .iter()
            .find(|e| e.name == name || e.aliases.contains(&name))
    }

    /// Every entry's name, in table order.
    pub fn names(&self) -> impl Iterator<Item = &'static str> + Clone {
        self.entries.iter().map(|e| e.name)
    }

    /// The entries that take key `name`.
    pub fn taking(&self, name: &str) -> Vec<&'static str> {
        self.entries
            .iter()
            .filter(|e| e.key(name).is_some())
            .map(|e| e.name)
            .collect()
    }

    /// Whether `name` is a common key.
    pub fn common(&self, name: &str) -> bool {
        self.common.iter().any(|k| k.is(name))
    }
}

#[cfg(test)]
mod tests;
