//! Analysis settings given from Python: `model.kinematics(t_end=2.0, steps=400)` sets
//! `[analysis]` keys of the model text before it is read.
//!
//! The text is edited in place (toml_edit), so every line outside `[analysis]` stays where the
//! user wrote it and error messages keep pointing at the right line of the file. Switching the
//! analysis kind drops the keys the new kind does not take (a dynamic file's `rtol` in a
//! kinematic run; its `dt`, whose meaning differs between the kinds), unless given again.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use toml_edit::{Array, DocumentMut, Item, Table};

/// A setting's value: what a model file's `[analysis]` table holds.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// `true` / `false`.
    Bool(bool),
    /// An integer (`steps`).
    Int(i64),
    /// A number.
    Float(f64),
    /// A name (`integrator`).
    Str(String),
    /// A list (`outputs.points`).
    List(Vec<Value>),
    /// A table (`outputs`).
    Table(Vec<(String, Value)>),
}

/// Keys every analysis kind takes.
const COMMON: [&str; 6] = ["kind", "t_start", "t_end", "steps", "outputs", "plots"];
/// Keys of the kinematic and inverse dynamics analyses.
const KINEMATIC: [&str; 3] = ["dt", "tolerance", "position_tolerance"];
/// Keys of the dynamic analysis.
const DYNAMIC: [&str; 8] = [
    "dt",
    "output_dt",
    "integrator",
    "rtol",
    "atol",
    "h_max",
    "rho_inf",
    "newton_tolerance",
];
/// `[analysis.outputs]` keys of the dynamic analysis only.
const DYNAMIC_OUTPUTS: [&str; 2] = ["reactions", "energy"];

/// The settings of a Python dict, in its order.
///
/// # Errors
/// A key that is not a string, or a value that is not a bool, int, float, str, list or dict of
/// those (a `TypeError` naming the key).
pub fn options_from_dict(d: &Bound<'_, PyDict>) -> PyResult<Vec<(String, Value)>> {
    d.iter()
        .map(|(k, v)| {
            let key: String = k.extract()?;
            let value = value_of(&v).map_err(|what| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "analysis option {key}: {what}; give a bool, int, float, str, a list or a \
                     dict of those"
                ))
            })?;
            Ok((key, value))
        })
        .collect()
}

/// The [`Value`] of a Python object, or what it is instead.
fn value_of(v: &Bound<'_, PyAny>) -> Result<Value, String> {
    if let Ok(b) = v.extract::<bool>() {
        return Ok(Value::Bool(b));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(Value::Int(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(Value::Float(x));
    }
    if let Ok(s) = v.extract::<String>() {
        return Ok(Value::Str(s));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut items = Vec::new();
        for (k, x) in d.iter() {
            let key: String = k
                .extract()
                .map_err(|_| "a dict key is not a str".to_string())?;
            items.push((key, value_of(&x)?));
        }
        return Ok(Value::Table(items));
    }
    if let Ok(l) = v.cast::<PyList>() {
        return l
            .iter()
            .map(|x| value_of(&x))
            .collect::<Result<_, _>>()
            .map(Value::List);
    }
    if let Ok(items) = v.try_iter() {
        let mut list = Vec::new();
        for x in items {
            list.push(value_of(&x.map_err(|e| e.to_string())?)?);
        }
        return Ok(Value::List(list));
    }
    Err(format!(
        "{} is not a setting",
        v.get_type().name().map_or("this".into(), |n| n.to_string())
    ))
}

/// `text` with `[analysis] kind` set to `kind` (if given) and `options` set; the text itself
/// when there is nothing to set.
///
/// # Errors
/// A text that is not TOML (the model reader then reports it with its line), or an
/// `[analysis]` that is not a table.
pub fn set_analysis(
    text: &str,
    kind: Option<&str>,
    options: &[(String, Value)],
) -> Result<String, String> {
    if kind.is_none() && options.is_empty() {
        return Ok(text.to_string());
    }
    let Ok(mut doc) = text.parse::<DocumentMut>() else {
        // Leave the syntax error to the model reader, which locates it.
        return Ok(text.to_string());
    };
    let item = doc
        .as_table_mut()
        .entry("analysis")
        .or_insert(Item::Table(Table::new()));
    let Some(table) = item.as_table_like_mut() else {
        return Err("the model file's `analysis` is not a table".into());
    };
    if let Some(kind) = kind {
        let old = table
            .get("kind")
            .and_then(|k| k.as_str())
            .map(str::to_string);
        if old.as_deref() != Some(kind) {
            drop_foreign_keys(table, kind);
        }
        table.insert("kind", toml_edit::value(kind));
    }
    for (key, value) in options {
        // `tolerance` is the older name of `position_tolerance`: the one given replaces both.
        match key.as_str() {
            "tolerance" => {
                table.remove("position_tolerance");
            }
            "position_tolerance" => {
                table.remove("tolerance");
            }
            _ => {}
        }
        table.insert(key, Item::Value(to_toml(value)));
    }
    Ok(doc.to_string())
}

/// Removes the keys of `table` (an `[analysis]`) that an analysis of `kind` does not take.
fn drop_foreign_keys(table: &mut dyn toml_edit::TableLike, kind: &str) {
    let own: &[&str] = if kind == "dynamic" {
        &DYNAMIC
    } else {
        &KINEMATIC
    };
    let foreign: Vec<String> = table
        .iter()
        .map(|(k, _)| k.to_string())
        .filter(|k| !COMMON.contains(&k.as_str()) && !own.contains(&k.as_str()))
        .collect();
    for k in foreign {
        table.remove(&k);
    }
    // `dt` is the output step of a kinematic run but the integration step of a dynamic one.
    table.remove("dt");
    if !matches!(kind, "kinematic" | "inverse_dynamics") {
        table.remove("position_tolerance");
    }
    if kind != "dynamic" {
        if let Some(outputs) = table.get_mut("outputs").and_then(|o| o.as_table_like_mut()) {
            for k in DYNAMIC_OUTPUTS {
                outputs.remove(k);
            }
        }
    }
}

/// The TOML value of a setting.
fn to_toml(v: &Value) -> toml_edit::Value {
    match v {
        Value::Bool(b) => (*b).into(),
        Value::Int(i) => (*i).into(),
        Value::Float(x) => (*x).into(),
        Value::Str(s) => s.as_str().into(),
        Value::List(items) => {
            let mut a = Array::new();
            for x in items {
                a.push(to_toml(x));
            }
            toml_edit::Value::Array(a)
        }
        Value::Table(items) => {
            let mut t = toml_edit::InlineTable::new();
            for (k, x) in items {
                t.insert(k, to_toml(x));
            }
            toml_edit::Value::InlineTable(t)
        }
    }
}
