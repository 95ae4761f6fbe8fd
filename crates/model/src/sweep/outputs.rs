//! The outputs of a sweep: a scalar of each case's run, written `NAME=EXPR` with `EXPR` an
//! expression over the run's tables.
//!
//! ```text
//! peak_torque=max(abs(motor.torque))      the largest |motor torque| over the run
//! stroke=max(slider.C.x) - min(slider.C.x)
//! top_speed=max(abs(slider.C.x'))         ' is the velocity table's column, '' the acceleration's
//! work=integral(motor.P)                  trapezoidal, over the output times
//! angle_half=at(crank_pin.angle, 0.5)     the value at t = 0.5 s (linear between outputs)
//! ```
//! A column is named as in the CSV header without its unit (`motor.torque`, `crank_pin.angle`,
//! `kinetic`); a name two tables share is qualified with the table, `reactions:ball.conrod.F.x`.
//! `t` is the time. Series combine element by element with `+ - * / ^`, `abs sqrt sin cos exp
//! log` and two-argument `min(a, b)`, `max(a, b)`; a reduction makes a number of a series:
//! `max min mean rms integral first last` and `at(series, t)`. The expression's value must be
//! a number. Values are in the model's units, as the tables.

use crate::table::Table;
use std::ops::Range;

/// One output: its name and expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// The column of sweep.csv.
    pub name: String,
    /// The expression as written.
    pub text: String,
    tree: Node,
}

#[derive(Debug, Clone, PartialEq)]
enum Node {
    Num(f64),
    Column(String, usize, Range<usize>),
    Time,
    Neg(Box<Node>),
    Bin(char, Box<Node>, Box<Node>),
    Call(String, Vec<Node>, Range<usize>),
}

/// A function of one number.
type Unary = fn(f64) -> f64;

/// Element-wise functions of one argument.
const MAP: &[(&str, Unary)] = &[
    ("abs", f64::abs),
    ("sqrt", f64::sqrt),
    ("sin", f64::sin),
    ("cos", f64::cos),
    ("exp", f64::exp),
    ("log", f64::ln),
];
/// Reductions of a series to a number.
const REDUCE: &[&str] = &[
    "max", "min", "mean", "rms", "integral", "first", "last", "at",
];

/// A value: a number or a series over the output times.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Num(f64),
    Series(Vec<f64>),
}

impl Output {
    /// Parses `NAME=EXPR`.
    ///
    /// # Errors
    /// A message naming the output and the column of the problem.
    pub fn parse(spec: &str) -> Result<Self, String> {
        let Some((name, text)) = spec.split_once('=') else {
            return Err(format!(
                "--output {spec}: not NAME=EXPR (e.g. peak=max(abs(motor.torque)))"
            ));
        };
        let (name, text) = (name.trim(), text.trim());
        let valid = name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid {
            return Err(format!(
                "--output {spec}: the name \"{name}\" is not a name (letters, digits, _)"
            ));
        }
        let mut p = Parser {
            text,
            at: 0,
            depth: 0,
            ops: 0,
        };
        let tree = p.expr().and_then(|t| {
            p.skip();
            if p.at < text.len() {
                Err((p.at, "expected an operator or the end".to_string()))
            } else {
                Ok(t)
            }
        });
        let tree =
            tree.map_err(|(at, m)| format!("--output {name}: \"{text}\", column {}: {m}", at + 1))?;
        Ok(Self {
            name: name.to_string(),
            text: text.to_string(),
            tree,
        })
    }

    /// The output's value over `tables` (the time is each table's first column).
    ///
    /// # Errors
    /// A column no table has (with the nearest), a name in several tables, series of
    /// different lengths, a value that is still a series, not finite.
    pub fn eval(&self, tables: &[Table]) -> Result<f64, String> {
        let what = |m: String| format!("output {} (\"{}\"): {m}", self.name, self.text);
        match eval(&self.tree, tables).map_err(what)? {
            Value::Num(x) if x.is_finite() => Ok(x),
            Value::Num(x) => Err(what(format!("the value is {x}"))),
            Value::Series(_) => Err(what(
                "the value is a series; reduce it with max, min, mean, rms, integral, first, last or at(…, t)".into(),
            )),
        }
    }
}

struct Parser<'a> {
    text: &'a str,
    at: usize,
    depth: usize,
    ops: usize,
}

type Parsed = Result<Node, (usize, String)>;

impl Parser<'_> {
    fn skip(&mut self) {
        while self.text[self.at..].starts_with(char::is_whitespace) {
            self.at += self.text[self.at..]
                .chars()
                .next()
                .map_or(1, char::len_utf8);
        }
    }
    fn peek(&mut self) -> Option<char> {
        self.skip();
        self.text[self.at..].chars().next()
    }
    /// `a op b`, at most [`crate::parameters::expr::MAX_OPS`] of them (a chain is a tree as
    /// deep as it is long).
    fn bin(&mut self, op: char, a: Node, b: Node) -> Parsed {
        self.ops += 1;
        if self.ops > crate::parameters::expr::MAX_OPS {
            let max = crate::parameters::expr::MAX_OPS;
            return Err((self.at, format!("more than {max} operations in one output")));
        }
        Ok(Node::Bin(op, Box::new(a), Box::new(b)))
    }

    fn expr(&mut self) -> Parsed {
        self.depth += 1;
        if self.depth > 64 {
            return Err((self.at, "nested too deeply".into()));
        }
        let mut a = self.term()?;
        while let Some(c @ ('+' | '-')) = self.peek() {
            self.at += 1;
            let b = self.term()?;
            a = self.bin(c, a, b)?;
        }
        self.depth -= 1;
        Ok(a)
    }
    fn term(&mut self) -> Parsed {
        let mut a = self.unary()?;
        while let Some(c @ ('*' | '/')) = self.peek() {
            self.at += 1;
            let b = self.unary()?;
            a = self.bin(c, a, b)?;
        }
        Ok(a)
    }
    fn unary(&mut self) -> Parsed {
        if self.peek() == Some('-') {
            self.at += 1;
            self.depth += 1;
            if self.depth > 64 {
                return Err((self.at, "nested too deeply".into()));
            }
            let a = self.unary()?;
            self.depth -= 1;
            return Ok(Node::Neg(Box::new(a)));
        }
        let a = self.primary()?;
        if self.peek() == Some('^') {
            self.at += 1;
            self.depth += 1;
            if self.depth > 64 {
                return Err((self.at, "nested too deeply".into()));
            }
            let b = self.unary()?;
            self.depth -= 1;
            return self.bin('^', a, b);
        }
        Ok(a)
    }
    fn primary(&mut self) -> Parsed {
        let start = self.at;
        match self.peek() {
            Some('(') => {
                self.at += 1;
                let e = self.expr()?;
                if self.peek() != Some(')') {
                    return Err((self.at, "expected \")\"".into()));
                }
                self.at += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => {
                let s = self.at;
                let rest = &self.text[s..];
                let mut end = rest
                    .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                    .unwrap_or(rest.len());
                let tail = &rest[end..];
                if tail.starts_with(['e', 'E']) {
                    let digits = tail[1..].trim_start_matches(['+', '-']);
                    if digits.starts_with(|c: char| c.is_ascii_digit()) {
                        let sign = tail.len() - 1 - digits.len();
                        let n = digits
                            .find(|c: char| !c.is_ascii_digit())
                            .unwrap_or(digits.len());
                        end += 1 + sign + n;
                    }
                }
                self.at = s + end;
                rest[..end]
                    .parse()
                    .map(Node::Num)
                    .map_err(|_| (s, format!("\"{}\" is not a number", &rest[..end])))
            }
            Some(c) if c.is_ascii_alphabetic() || c == '_' => {
                let s = self.at;
                let rest = &self.text[s..];
                let end = rest
                    .find(|c: char| !(c.is_ascii_alphanumeric() || "_.@:".contains(c)))
                    .unwrap_or(rest.len());
                let name = rest[..end].to_string();
                self.at = s + end;
                if self.peek() == Some('(') {
                    self.at += 1;
                    let mut args = vec![self.expr()?];
                    while self.peek() == Some(',') {
                        self.at += 1;
                        args.push(self.expr()?);
                    }
                    if self.peek() != Some(')') {
                        return Err((self.at, "expected \",\" or \")\"".into()));
                    }
                    self.at += 1;
                    let known = MAP.iter().any(|m| m.0 == name) || REDUCE.contains(&name.as_str());
                    if !known {
                        let names = MAP.iter().map(|m| m.0).chain(REDUCE.iter().copied());
                        return Err((
                            s,
                            format!(
                                "no function \"{name}\"{}",
                                crate::diag::did_you_mean(&name, names)
                            ),
                        ));
                    }
                    return Ok(Node::Call(name, args, s..self.at));
                }
                let primes = self.text[self.at..]
                    .chars()
                    .take_while(|&c| c == '\'')
                    .count();
                self.at += primes;
                match name.as_str() {
                    "t" if primes == 0 => Ok(Node::Time),
                    "pi" if primes == 0 => Ok(Node::Num(std::f64::consts::PI)),
                    _ if primes > 2 => Err((
                        s,
                        "a column takes at most two primes (velocity ', acceleration '')".into(),
                    )),
                    _ => Ok(Node::Column(name, primes, s..self.at)),
                }
            }
            None => Err((
                start,
                "the expression ends where a value is expected".into(),
            )),
            Some(c) => Err((self.at, format!("unexpected \"{c}\""))),
        }
    }
}

/// The tables a column with `primes` primes is looked for in.
fn family(table: &str, primes: usize) -> bool {
    let vel = table.ends_with("_velocities");
    let acc = table.ends_with("_accelerations");
    match primes {
        0 => !vel && !acc,
        1 => vel,
        _ => acc,
    }
}

/// The column `name` (`table:column` qualified or not) with its table's times.
fn column<'a>(
    tables: &'a [Table],
    name: &str,
    primes: usize,
) -> Result<(&'a Table, usize), String> {
    let (only, col) = match name.split_once(':') {
        Some((t, c)) => (Some(t), c),
        None => (None, name),
    };
    let mut found = Vec::new();
    for t in tables
        .iter()
        .filter(|t| only.is_none_or(|o| o == t.name) && family(&t.name, primes))
    {
        if let Some(k) = t
            .columns
            .iter()
            .position(|h| h.split(" [").next() == Some(col))
        {
            found.push((t, k));
        }
    }
    let ticks = "'".repeat(primes);
    match found.as_slice() {
        [one] => Ok(*one),
        [] if only.is_some() => Err(format!(
            "no column \"{col}{ticks}\" in the table {}",
            only.unwrap_or_default()
        )),
        [] => {
            let all = tables
                .iter()
                .filter(|t| family(&t.name, primes))
                .flat_map(|t| t.columns.iter().map(|h| h.split(" [").next().unwrap_or("")));
            Err(format!(
                "no column \"{col}{ticks}\" in the run's tables{}",
                crate::diag::did_you_mean(col, all)
            ))
        }
        many => Err(format!(
            "\"{col}{ticks}\" is a column of {}: write TABLE:{col}",
            many.iter()
                .map(|(t, _)| t.name.as_str())
                .collect::<Vec<_>>()
                .join(" and ")
        )),
    }
}

fn eval(n: &Node, tables: &[Table]) -> Result<Value, String> {
    let times = || -> Result<Vec<f64>, String> {
        let t = tables.first().ok_or("the run has no tables")?;
        Ok(t.rows.iter().map(|r| r[0]).collect())
    };
    Ok(match n {
        Node::Num(x) => Value::Num(*x),
        Node::Time => Value::Series(times()?),
        Node::Column(name, primes, _) => {
            let (t, k) = column(tables, name, *primes)?;
            Value::Series(t.rows.iter().map(|r| r[k + 1]).collect())
        }
        Node::Neg(a) => map(eval(a, tables)?, |x| -x),
        Node::Bin(op, a, b) => {
            let f = |x: f64, y: f64| match op {
                '+' => x + y,
                '-' => x - y,
                '*' => x * y,
                '/' => x / y,
                _ => x.powf(y),
            };
            zip(eval(a, tables)?, eval(b, tables)?, f)?
        }
        Node::Call(name, args, _) => call(name, args, tables, &times)?,
    })
}

fn map(v: Value, f: impl Fn(f64) -> f64) -> Value {
    match v {
        Value::Num(x) => Value::Num(f(x)),
        Value::Series(s) => Value::Series(s.into_iter().map(f).collect()),
    }
}

fn zip(a: Value, b: Value, f: impl Fn(f64, f64) -> f64) -> Result<Value, String> {
    Ok(match (a, b) {
        (Value::Num(x), Value::Num(y)) => Value::Num(f(x, y)),
        (Value::Series(s), Value::Num(y)) => {
            Value::Series(s.into_iter().map(|x| f(x, y)).collect())
        }
        (Value::Num(x), Value::Series(s)) => {
            Value::Series(s.into_iter().map(|y| f(x, y)).collect())
        }
        (Value::Series(s), Value::Series(r)) => {
            if s.len() != r.len() {
                return Err(format!(
                    "series of {} and {} values do not combine",
                    s.len(),
                    r.len()
                ));
            }
            Value::Series(s.into_iter().zip(r).map(|(x, y)| f(x, y)).collect())
        }
    })
}

fn call(
    name: &str,
    args: &[Node],
    tables: &[Table],
    times: &dyn Fn() -> Result<Vec<f64>, String>,
) -> Result<Value, String> {
    let arity = |n: usize| -> Result<(), String> {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!("{name} takes {n} argument(s), not {}", args.len()))
        }
    };
    if let Some((_, f)) = MAP.iter().find(|m| m.0 == name) {
        arity(1)?;
        return Ok(map(eval(&args[0], tables)?, f));
    }
    if args.len() == 2 && (name == "max" || name == "min") {
        let (a, b) = (eval(&args[0], tables)?, eval(&args[1], tables)?);
        return zip(a, b, if name == "max" { f64::max } else { f64::min });
    }
    arity(if name == "at" { 2 } else { 1 })?;
    let series = match eval(&args[0], tables)? {
        Value::Series(s) => s,
        Value::Num(x) => vec![x],
    };
    if series.is_empty() {
        return Err(format!("{name} of an empty series"));
    }
    let n = series.len() as f64;
    let t = times()?;
    Ok(Value::Num(match name {
        "max" => series.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        "min" => series.iter().copied().fold(f64::INFINITY, f64::min),
        "mean" => series.iter().sum::<f64>() / n,
        "rms" => (series.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
        "first" => series[0],
        "last" => series[series.len() - 1],
        "integral" => {
            if t.len() != series.len() {
                return Err("integral of a number".into());
            }
            (1..t.len())
                .map(|k| 0.5 * (series[k] + series[k - 1]) * (t[k] - t[k - 1]))
                .sum()
        }
        _ => {
            let Value::Num(at) = eval(&args[1], tables)? else {
                return Err("at(series, t): t is a number".into());
            };
            interpolate(&t, &series, at)?
        }
    }))
}

/// The series' value at `at`, linear between output times.
fn interpolate(t: &[f64], s: &[f64], at: f64) -> Result<f64, String> {
    if t.len() != s.len() || t.is_empty() {
        return Err("at(series, t) needs a series".into());
    }
    let (t0, t1) = (t[0], t[t.len() - 1]);
    if !(t0..=t1).contains(&at) {
        return Err(format!(
            "at(…, {at}): the run's outputs span t = {t0} … {t1} s"
        ));
    }
    let k = t.partition_point(|&x| x <= at).clamp(1, t.len() - 1);
    let (a, b) = (t[k - 1], t[k]);
    let f = if b > a { (at - a) / (b - a) } else { 0.0 };
    Ok(s[k - 1] + f * (s[k] - s[k - 1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tables() -> Vec<Table> {
        let mut a = Table::new("driver_efforts", "", vec!["motor.torque [N m]".into()]);
        a.rows = vec![vec![0.0, 1.0], vec![0.5, -3.0], vec![1.0, 2.0]];
        let mut b = Table::new("point_velocities", "", vec!["slider.C.x [m/s]".into()]);
        b.rows = vec![vec![0.0, 0.0], vec![0.5, 4.0], vec![1.0, -5.0]];
        let mut c = Table::new("points", "", vec!["slider.C.x [m]".into()]);
        c.rows = vec![vec![0.0, 0.1], vec![0.5, 0.2], vec![1.0, 0.3]];
        vec![a, b, c]
    }

    fn value(spec: &str) -> Result<f64, String> {
        Output::parse(spec)?.eval(&tables())
    }

    #[test]
    fn reductions_and_primes() {
        assert_eq!(value("p=max(abs(motor.torque))"), Ok(3.0));
        assert_eq!(value("v=max(abs(slider.C.x'))"), Ok(5.0));
        assert_eq!(
            value("s=max(slider.C.x) - min(slider.C.x)"),
            Ok(0.19999999999999998)
        );
        assert_eq!(value("r=rms(motor.torque)"), Ok((14.0f64 / 3.0).sqrt()));
        assert_eq!(
            value("i=integral(motor.torque)"),
            Ok(0.25 * (1.0 - 3.0) + 0.25 * (-3.0 + 2.0))
        );
        assert_eq!(value("a=at(motor.torque, 0.25)"), Ok(-1.0));
        assert_eq!(value("l=last(t) * 2"), Ok(2.0));
        assert_eq!(
            value("q=points:slider.C.x'"),
            Err(
                "output q (\"points:slider.C.x'\"): no column \"slider.C.x'\" in the table points"
                    .into()
            )
        );
    }

    #[test]
    fn mistakes_are_named() {
        assert!(value("p=max(abs(motor.torqe))")
            .unwrap_err()
            .contains("did you mean \"motor.torque\""));
        assert!(value("p=abs(motor.torque)")
            .unwrap_err()
            .contains("is a series"));
        assert!(value("p=maxx(motor.torque)")
            .unwrap_err()
            .contains("did you mean \"max\""));
        assert!(value("p=at(motor.torque, 2)")
            .unwrap_err()
            .contains("span t = 0 … 1 s"));
        assert!(Output::parse("max(x)").unwrap_err().contains("NAME=EXPR"));
        assert!(Output::parse("p=max(x").unwrap_err().contains("column 6"));
        let chain = format!("p={}1", "1+".repeat(100_000));
        assert!(Output::parse(&chain)
            .unwrap_err()
            .contains("more than 512 operations"));
    }
}
