//! Parameters: named values of a model file, used wherever a number is.
//!
//! ```toml
//! [parameters]
//! crank = "80 mm"            # a value with its unit
//! rod = "3.5 * crank"        # from other parameters
//! speed = 2.0                # a plain number
//!
//! [[body]]
//! name = "crank"
//! points = { A = [0, 0, 0], B = ["crank", 0, 0] }
//! ```
//!
//! A number of the file may be written as text: an expression of numbers with units, parameter
//! names, `+ - * / ^`, parentheses and functions ([`expr`]). Its value is written in the model's
//! units (`[model] units`: SI or mm): `"80 mm"` is 0.08 in an SI model and 80 in a mm model; a
//! plain number meeting a quantity is in the model's units of it ([`quantity`]). Time-function
//! expressions (`kind = "expression"`) see the parameters as constants in the model's units.
//!
//! Parameters are evaluated in the order their uses need (any order in the file), once; a
//! cycle, an unknown name, a unit mismatch or a value that is not finite is an error at the
//! definition, naming the parameters involved. Values given from outside (`cardan run --set
//! crank=0.1`, Python's `with_parameters`) replace a definition before evaluation; a plain
//! number replacing a quantity is read in the model's units of it, a quantity of another unit
//! is refused.

pub mod expr;
pub mod quantity;
pub mod units;

use crate::diag::{did_you_mean, Error, Source};
use quantity::Quantity;
use std::cell::RefCell;
use std::ops::Range;
use std::sync::Arc;
use toml::de::{DeTable, DeValue};

/// Most parameters a file may define.
pub const MAX_PARAMETERS: usize = 1000;

/// One parameter.
#[derive(Debug, Clone)]
pub struct Parameter {
    /// Its name.
    pub name: String,
    /// Its value as written in the file (a number's digits or the text).
    pub written: String,
    /// The text given with `--set` (or `with_parameters`), which replaced `written`.
    pub set: Option<String>,
    /// The bytes of its value in the file.
    pub span: Range<usize>,
    /// The line of its definition.
    pub line: usize,
    /// Its value.
    pub value: Quantity,
}

/// A file's parameters, evaluated.
#[derive(Debug, Clone)]
pub struct Parameters {
    /// In the file's order.
    pub list: Vec<Parameter>,
    /// The model's length unit in metres (1 or 0.001).
    pub ell: f64,
}

impl Default for Parameters {
    fn default() -> Self {
        Self {
            list: Vec::new(),
            ell: 1.0,
        }
    }
}

/// A definition before evaluation.
struct Definition {
    name: String,
    key: Range<usize>,
    span: Range<usize>,
    written: String,
    set: Option<(String, expr::Expr)>,
    expr: expr::Expr,
    /// Where the expression's text starts in the file (None for `--set` text and for texts
    /// with escapes, located at the whole value).
    text_at: Option<usize>,
}

impl Parameters {
    /// The parameter called `name`.
    pub fn get(&self, name: &str) -> Option<&Parameter> {
        self.list.iter().find(|p| p.name == name)
    }

    /// `name`'s value in the model's units (for time-function expressions).
    pub fn constant(&self, name: &str) -> Option<f64> {
        self.get(name).map(|p| p.value.in_model_units(self.ell))
    }

    /// A number written as `text` where the file wants a number, in the model's units.
    ///
    /// # Errors
    /// The expression's problem, quoting it, with the definitions of the parameters it uses.
    pub fn number(&self, text: &str) -> Result<f64, String> {
        let quoted = cardan_constraints::expression::quoted(text);
        let e = expr::parse(text)
            .map_err(|e| format!("\"{quoted}\" (column {}): {}", e.span.start + 1, e.message))?;
        let lookup = |n: &str| self.lookup(n);
        let q = e.eval(&lookup, self.ell).map_err(|err| {
            // A lone name needs no quoting before the sentence that names it.
            let lone = e.names().first().is_some_and(|(n, _)| *n == text.trim());
            let mut m = if lone {
                err.message.clone()
            } else {
                format!("\"{quoted}\": {}", err.message)
            };
            let used: Vec<String> = e
                .names()
                .iter()
                .filter_map(|(n, _)| self.get(n))
                .map(|p| format!("{} = {} (line {})", p.name, p.value.describe(), p.line))
                .collect();
            if !used.is_empty() {
                m += &format!(" [{}]", used.join(", "));
            }
            m
        })?;
        Ok(q.in_model_units(self.ell))
    }

    fn lookup(&self, n: &str) -> Result<Quantity, String> {
        match self.get(n) {
            Some(p) => Ok(p.value),
            None if self.list.is_empty() => Err(format!(
                "\"{n}\" is not a number, nor a parameter: the file has no [parameters] table"
            )),
            None => Err(format!(
                "no parameter \"{n}\"{}",
                did_you_mean(n, self.list.iter().map(|p| p.name.as_str()))
            )),
        }
    }

    /// Reads `[parameters]` off the parsed document, applies the values `set` from outside
    /// and evaluates every parameter.
    ///
    /// # Errors
    /// A malformed table, name or value at its place in the file; a `set` name the file does
    /// not define (with the nearest one) as a usage error; a cycle, unknown name or unit
    /// mismatch at the definition.
    pub fn read(src: &Source, doc: &DeTable<'_>, set: &[(String, String)]) -> Result<Self, Error> {
        let ell = model_length_unit(doc);
        let mut defs = definitions(src, doc)?;
        apply_set(src, &mut defs, set)?;
        let mut state = vec![State::Pending; defs.len()];
        let mut values = vec![Quantity::plain(0.0); defs.len()];
        for k in 0..defs.len() {
            evaluate(src, &defs, k, ell, &mut state, &mut values, &mut Vec::new())?;
        }
        let list = defs
            .into_iter()
            .zip(values)
            .map(|(d, value)| Parameter {
                line: src.location(d.key.start).line,
                name: d.name,
                written: d.written,
                set: d.set.map(|s| s.0),
                span: d.span,
                value,
            })
            .collect();
        Ok(Self { list, ell })
    }
}

fn model_length_unit(doc: &DeTable<'_>) -> f64 {
    let units = doc
        .get("model")
        .and_then(|m| match m.get_ref() {
            DeValue::Table(t) => t.get("units"),
            _ => None,
        })
        .and_then(|u| u.get_ref().as_str().map(str::to_string));
    units
        .as_deref()
        .and_then(crate::units::UnitSystem::parse)
        .map_or(1.0, crate::units::UnitSystem::length)
}

/// A valid parameter name: a letter or `_`, then letters, digits, `_`.
fn valid_name(n: &str) -> bool {
    let mut c = n.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn definitions(src: &Source, doc: &DeTable<'_>) -> Result<Vec<Definition>, Error> {
    let Some(table) = doc.get("parameters") else {
        return Ok(Vec::new());
    };
    let DeValue::Table(t) = table.get_ref() else {
        return Err(src.error_at(
            table.span(),
            "[parameters] is a table of name = value (e.g. crank = \"80 mm\")",
        ));
    };
    if t.len() > MAX_PARAMETERS {
        return Err(src.error_at(
            table.span(),
            format!(
                "{} parameters are defined; at most {MAX_PARAMETERS} are accepted",
                t.len()
            ),
        ));
    }
    let mut defs = Vec::new();
    for (k, v) in t.iter() {
        let name = k.get_ref().to_string();
        if !valid_name(&name) {
            return Err(src.error_at(
                k.span(),
                format!("the parameter name \"{name}\" is not a name: a letter or _, then letters, digits or _ (it is used in expressions)"),
            ));
        }
        if expr::reserved(&name) {
            return Err(src.error_at(
                k.span(),
                format!("\"{name}\" is a function or constant of expressions; call the parameter otherwise"),
            ));
        }
        // Expression time functions see the parameters as constants, after their own names.
        if cardan_constraints::expression::names().any(|n| n == name) {
            return Err(src.error_at(
                k.span(),
                format!("\"{name}\" is the time, a constant or a function in expression functions (kind = \"expression\"), where the parameter would not be seen; call the parameter otherwise"),
            ));
        }
        let (written, text_at) = match v.get_ref() {
            DeValue::Integer(i) if i.radix() == 10 => (i.as_str().to_string(), None),
            DeValue::Float(f) => (f.as_str().to_string(), None),
            DeValue::String(s) => {
                let raw = &src.text[v.span()];
                let plain = raw.len() == s.len() + 2;
                (s.to_string(), plain.then_some(v.span().start + 1))
            }
            _ => {
                return Err(src.error_at(
                    v.span(),
                    format!(
                    "the parameter {name} is a number or a text such as \"80 mm\" or \"2 * crank\""
                ),
                ))
            }
        };
        if written.len() > crate::limits::MAX_EXPRESSION_LEN {
            return Err(src.error_at(
                v.span(),
                format!(
                    "the value of {name} is {} bytes long; at most {} are accepted",
                    written.len(),
                    crate::limits::MAX_EXPRESSION_LEN
                ),
            ));
        }
        let expr = expr::parse(&written).map_err(|e| {
            let span = text_at.map_or(v.span(), |a| a + e.span.start..a + e.span.end);
            src.error_at(span, format!("the parameter {name}: {}", e.message))
        })?;
        defs.push(Definition {
            name,
            key: k.span(),
            span: v.span(),
            written,
            set: None,
            expr,
            text_at,
        });
    }
    defs.sort_by_key(|d| d.key.start);
    Ok(defs)
}

/// Replaces the definitions named by `set` with the given texts.
fn apply_set(src: &Source, defs: &mut [Definition], set: &[(String, String)]) -> Result<(), Error> {
    for (name, text) in set {
        let Some(d) = defs.iter_mut().find(|d| &d.name == name) else {
            let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
            let known = if names.is_empty() {
                format!("{} has no [parameters] table", src.path.display())
            } else {
                format!(
                    "{} defines {}",
                    src.path.display(),
                    crate::diag::list(names.iter().copied())
                )
            };
            return Err(Error::usage(format!(
                "--set {name}=…: no parameter \"{name}\"{} ({known})",
                did_you_mean(name, names.iter().copied())
            )));
        };
        let e = expr::parse(text).map_err(|e| {
            Error::usage(format!(
                "--set {name}={text}: column {}: {}",
                e.span.start + 1,
                e.message
            ))
        })?;
        d.set = Some((text.clone(), e));
    }
    Ok(())
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum State {
    Pending,
    Active,
    Done,
}

/// Evaluates definition `k` after the ones it uses (depth first; `path` is the chain being
/// evaluated, for the cycle message).
fn evaluate(
    src: &Source,
    defs: &[Definition],
    k: usize,
    ell: f64,
    state: &mut [State],
    values: &mut [Quantity],
    path: &mut Vec<usize>,
) -> Result<(), Error> {
    match state[k] {
        State::Done => return Ok(()),
        State::Active => {
            let from = path.iter().position(|&j| j == k).unwrap_or(0);
            let chain: Vec<&str> = path[from..]
                .iter()
                .chain(std::iter::once(&k))
                .map(|&j| defs[j].name.as_str())
                .collect();
            return Err(src.error_at(
                defs[k].key.clone(),
                format!("the parameters form a cycle: {}", chain.join(" → ")),
            ));
        }
        State::Pending => {}
    }
    state[k] = State::Active;
    path.push(k);
    let d = &defs[k];
    let set_names = d.set.iter().flat_map(|(_, e)| e.names());
    for (n, span) in d
        .expr
        .names()
        .into_iter()
        .map(|n| (n, false))
        .chain(set_names.map(|n| (n, true)))
        .map(|((n, s), set)| (n, (s, set)))
    {
        let (span, set) = span;
        let at = match (set, d.text_at) {
            (false, Some(a)) => a + span.start..a + span.end,
            _ => d.span.clone(),
        };
        let Some(j) = defs.iter().position(|x| x.name == n) else {
            let names = defs.iter().map(|x| x.name.as_str());
            let via = if set { " (as given with --set)" } else { "" };
            let err = format!(
                "the parameter {}{via} uses \"{n}\", which is no parameter{}",
                d.name,
                did_you_mean(n, names)
            );
            return Err(if set {
                Error::usage(err)
            } else {
                src.error_at(at, err)
            });
        };
        evaluate(src, defs, j, ell, state, values, path)?;
    }
    let lookup = |n: &str| -> Result<Quantity, String> {
        let j = defs
            .iter()
            .position(|x| x.name == n)
            .expect("checked above");
        Ok(values[j])
    };
    let used = |e: &expr::Expr| -> String {
        let mut seen: Vec<&str> = Vec::new();
        let parts: Vec<String> = (e.names().into_iter())
            .filter(|(n, _)| {
                !seen.contains(n) && {
                    seen.push(n);
                    true
                }
            })
            .filter_map(|(n, _)| defs.iter().position(|x| x.name == n))
            .map(|j| {
                let from = match &defs[j].set {
                    Some((t, _)) => format!("--set {}={t}", defs[j].name),
                    None => format!("line {}", src.location(defs[j].key.start).line),
                };
                format!("{} = {} ({from})", defs[j].name, values[j].describe())
            })
            .collect();
        if parts.is_empty() {
            String::new()
        } else {
            format!(" [{}]", parts.join(", "))
        }
    };
    let mut q = d.expr.eval(&lookup, ell).map_err(|e| {
        let at = d
            .text_at
            .map_or(d.span.clone(), |a| a + e.span.start..a + e.span.end);
        src.error_at(
            at,
            format!("the parameter {}: {}{}", d.name, e.message, used(&d.expr)),
        )
    })?;
    if let Some((text, e)) = &d.set {
        let given = e
            .eval(&lookup, ell)
            .map_err(|e| Error::usage(format!("--set {}={text}: {}", d.name, e.message)))?;
        q = converted_setting(d, text, q, given, ell)?;
    }
    values[k] = q;
    state[k] = State::Done;
    path.pop();
    Ok(())
}

/// A value given with `--set` in the unit of the file's definition (`file`): a plain number
/// is read in the model's units of it; another unit is refused.
fn converted_setting(
    d: &Definition,
    text: &str,
    file: Quantity,
    given: Quantity,
    ell: f64,
) -> Result<Quantity, Error> {
    match (file.dim, given.dim) {
        (None, _) => Ok(given),
        (Some(dim), None) => Ok(Quantity::si(given.as_dim(dim, ell), dim)),
        (Some(a), Some(b)) if a == b => Ok(given),
        (Some(a), Some(b)) => Err(Error::usage(format!(
            "--set {}={text}: the file gives {} in {a} (\"{}\"), the value given is in {b}",
            d.name, d.name, d.written
        ))),
    }
}

/// The model file's text with the parameters named in `src.set` given those values: each
/// one's definition replaced by its value as a quantity (`crank = "0.1 m"`), read as `--set`
/// reads it (a plain number in the model's units of the parameter). What Python's
/// `Model.with_parameters` makes: a model of its own, as if the file had been edited.
///
/// # Errors
/// As [`Parameters::read`]; TOML syntax.
pub fn rewrite(src: &Source) -> Result<String, Error> {
    let doc = toml::de::DeTable::parse(&src.text)
        .map_err(|e| src.error_at(e.span().unwrap_or(0..0), e.message().to_string()))?;
    let p = Parameters::read(src, doc.get_ref(), &src.set)?;
    let mut edits: Vec<(Range<usize>, String)> = (p.list.iter())
        .filter(|q| q.set.is_some())
        .map(|q| (q.span.clone(), format!("\"{}\"", q.value.exact_text())))
        .collect();
    edits.sort_by_key(|(s, _)| std::cmp::Reverse(s.start));
    let mut text = src.text.clone();
    for (span, value) in edits {
        text.replace_range(span, &value);
    }
    Ok(text)
}

thread_local! {
    /// The parameters of the file being deserialized ([`with_scope`]).
    static SCOPE: RefCell<Option<Arc<Parameters>>> = const { RefCell::new(None) };
}

/// Runs `f` (the file's deserialization) with `p` as the parameters numbers written as text
/// refer to.
pub(crate) fn with_scope<R>(p: Arc<Parameters>, f: impl FnOnce() -> R) -> R {
    let before = SCOPE.with(|s| s.replace(Some(p)));
    let out = f();
    SCOPE.with(|s| *s.borrow_mut() = before);
    out
}

/// A number written as text, in the parameters of the file being deserialized (none outside
/// [`with_scope`]).
pub(crate) fn number_in_scope(text: &str) -> Result<f64, String> {
    SCOPE.with(|s| match s.borrow().as_ref() {
        Some(p) => p.number(text),
        None => Parameters::default().number(text),
    })
}
