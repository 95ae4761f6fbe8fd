//! The language of a parameter's value and of a number written as text: numbers with units,
//! parameter names, `+ - * / ^`, parentheses and functions.
//!
//! ```text
//! expr    := term { ("+" | "-") term }
//! term    := unary { ("*" | "/") unary }
//! unary   := ("+" | "-") unary | power
//! power   := primary [ "^" unary ]
//! primary := number [ units ] | name | name "(" expr { "," expr } ")" | "(" expr ")"
//! units   := unit [ "^" int ] { [ "*" | "/" ] unit [ "^" int ] }
//! ```
//! A unit is a name of [`super::units::UNITS`] right after a number (`80 mm`, `9.81 m/s^2`,
//! `2 N m`); anywhere else a name is a parameter (or `pi`). So `2 * g` is twice the parameter
//! g while `2 g` is two grams; `(80 mm) / s` divides by a parameter s.
//!
//! Functions: sqrt abs sin cos tan asin acos atan atan2(y, x) exp log min(a, b) max(a, b).
//! Their arguments' dimensions follow [`super::quantity`]: + − min max atan2 need equal
//! dimensions (a plain number takes the other's), the trigonometric and exponential functions
//! a dimensionless argument, sqrt an even one.

use super::quantity::{Dim, Quantity};
use super::units::unit;
use std::ops::Range;

/// Deepest nesting of parentheses and operators.
const MAX_DEPTH: usize = 64;
/// Most binary operations in one expression (a chain `1+1+1+…` is a tree as deep as it is
/// long: evaluating a longer one could exhaust the stack).
pub const MAX_OPS: usize = 512;

/// A problem in an expression: the byte span within its text and a sentence.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    /// Bytes of the expression text.
    pub span: Range<usize>,
    /// What is wrong.
    pub message: String,
}

fn err<T>(span: Range<usize>, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError {
        span,
        message: message.into(),
    })
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
    End,
}

fn tokens(text: &str) -> Result<Vec<(Tok, Range<usize>)>, ExprError> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let c = b[k];
        let start = k;
        if c.is_ascii_whitespace() {
            k += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == b'.' && b.get(k + 1).is_some_and(u8::is_ascii_digit)) {
            while k < b.len() && (b[k].is_ascii_digit() || b[k] == b'.') {
                k += 1;
            }
            if k < b.len() && (b[k] == b'e' || b[k] == b'E') {
                let mut j = k + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    k = j;
                    while k < b.len() && b[k].is_ascii_digit() {
                        k += 1;
                    }
                }
            }
            let s = &text[start..k];
            let Ok(x) = s.parse::<f64>() else {
                return err(start..k, format!("\"{s}\" is not a number"));
            };
            out.push((Tok::Num(x), start..k));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while k < b.len() && (b[k].is_ascii_alphanumeric() || b[k] == b'_') {
                k += 1;
            }
            out.push((Tok::Name(text[start..k].to_string()), start..k));
        } else if b"+-*/^(),".contains(&c) {
            k += 1;
            out.push((Tok::Op(c as char), start..k));
        } else {
            let ch = text[k..].chars().next().unwrap_or('?');
            return err(
                k..k + ch.len_utf8(),
                format!("unexpected \"{ch}\" (numbers, units, parameter names, + - * / ^ and parentheses are understood)"),
            );
        }
    }
    out.push((Tok::End, text.len()..text.len()));
    Ok(out)
}

/// A function of the language.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Func {
    Sqrt,
    Abs,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Exp,
    Log,
    Min,
    Max,
}

/// Name, function, number of arguments.
const FUNCS: &[(&str, Func, usize)] = &[
    ("sqrt", Func::Sqrt, 1),
    ("abs", Func::Abs, 1),
    ("sin", Func::Sin, 1),
    ("cos", Func::Cos, 1),
    ("tan", Func::Tan, 1),
    ("asin", Func::Asin, 1),
    ("acos", Func::Acos, 1),
    ("atan", Func::Atan, 1),
    ("atan2", Func::Atan2, 2),
    ("exp", Func::Exp, 1),
    ("log", Func::Log, 1),
    ("min", Func::Min, 2),
    ("max", Func::Max, 2),
];

/// The names a parameter may not take: the functions' and `pi`.
pub fn reserved(name: &str) -> bool {
    name == "pi" || FUNCS.iter().any(|f| f.0 == name)
}

/// A parsed expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    kind: Kind,
    span: Range<usize>,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Value(Quantity),
    Name(String),
    Neg(Box<Expr>),
    Bin(char, Box<Expr>, Box<Expr>),
    Call(Func, Vec<Expr>),
}

struct Parser {
    toks: Vec<(Tok, Range<usize>)>,
    at: usize,
    depth: usize,
    ops: usize,
}

/// Parses `text`.
///
/// # Errors
/// The span of the first problem and what it is.
pub fn parse(text: &str) -> Result<Expr, ExprError> {
    let mut p = Parser {
        toks: tokens(text)?,
        at: 0,
        depth: 0,
        ops: 0,
    };
    if p.peek() == &Tok::End {
        return err(0..0, "the expression is empty");
    }
    let e = p.expr()?;
    match p.peek() {
        Tok::End => Ok(e),
        Tok::Name(n) if unit(n).is_some() => err(
            p.span(),
            format!("the unit \"{n}\" must follow a number directly (write \"(…) * 1 {n}\")"),
        ),
        _ => err(p.span(), "expected an operator (+ - * / ^) or the end"),
    }
}

impl Parser {
    fn peek(&self) -> &Tok {
        &self.toks[self.at].0
    }
    fn peek2(&self) -> &Tok {
        &self.toks[(self.at + 1).min(self.toks.len() - 1)].0
    }
    fn span(&self) -> Range<usize> {
        self.toks[self.at].1.clone()
    }
    fn bump(&mut self) -> (Tok, Range<usize>) {
        let t = self.toks[self.at].clone();
        self.at = (self.at + 1).min(self.toks.len() - 1);
        t
    }

    fn expr(&mut self) -> Result<Expr, ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return err(
                self.span(),
                format!("nested deeper than {MAX_DEPTH} levels"),
            );
        }
        let mut a = self.term()?;
        while let Tok::Op(c @ ('+' | '-')) = *self.peek() {
            self.bump();
            let b = self.term()?;
            a = self.bin(c, a, b)?;
        }
        self.depth -= 1;
        Ok(a)
    }

    fn term(&mut self) -> Result<Expr, ExprError> {
        let mut a = self.unary()?;
        while let Tok::Op(c @ ('*' | '/')) = *self.peek() {
            self.bump();
            let b = self.unary()?;
            a = self.bin(c, a, b)?;
        }
        Ok(a)
    }

    fn unary(&mut self) -> Result<Expr, ExprError> {
        if let Tok::Op(c @ ('+' | '-')) = *self.peek() {
            let s = self.bump().1;
            self.depth += 1;
            if self.depth > MAX_DEPTH {
                return err(s, format!("nested deeper than {MAX_DEPTH} levels"));
            }
            let a = self.unary()?;
            self.depth -= 1;
            let span = s.start..a.span.end;
            return Ok(if c == '-' {
                Expr {
                    kind: Kind::Neg(Box::new(a)),
                    span,
                }
            } else {
                a
            });
        }
        let a = self.primary()?;
        if self.peek() == &Tok::Op('^') {
            let s = self.bump().1;
            // A power's exponent nests (2^2^2 is 2^(2^2)).
            self.depth += 1;
            if self.depth > MAX_DEPTH {
                return err(s, format!("nested deeper than {MAX_DEPTH} levels"));
            }
            let b = self.unary()?;
            self.depth -= 1;
            return self.bin('^', a, b);
        }
        Ok(a)
    }

    fn primary(&mut self) -> Result<Expr, ExprError> {
        let (tok, span) = self.bump();
        match tok {
            Tok::Num(x) => self.units(x, span),
            Tok::Name(n) if self.peek() == &Tok::Op('(') => self.call(&n, span),
            Tok::Name(n) if n == "pi" => Ok(Expr {
                kind: Kind::Value(Quantity::plain(std::f64::consts::PI)),
                span,
            }),
            Tok::Name(n) => Ok(Expr {
                kind: Kind::Name(n),
                span,
            }),
            Tok::Op('(') => {
                let inner = self.expr()?;
                if self.peek() != &Tok::Op(')') {
                    return err(self.span(), "expected \")\"");
                }
                let end = self.bump().1.end;
                Ok(Expr {
                    span: span.start..end,
                    ..inner
                })
            }
            Tok::End => err(span, "the expression ends where a value is expected"),
            Tok::Op(c) => err(
                span,
                format!("expected a number, a name or \"(\", found \"{c}\""),
            ),
        }
    }

    /// The units after a number, if any: `80 mm`, `9.81 m/s^2`, `2 N m`, `50 N/m`.
    fn units(&mut self, x: f64, span: Range<usize>) -> Result<Expr, ExprError> {
        let mut q = Quantity::plain(x);
        let mut end = span.end;
        let mut first = true;
        loop {
            let (divide, name) = match (self.peek(), self.peek2()) {
                (Tok::Name(n), next) if unit(n).is_some() && next != &Tok::Op('(') => {
                    (false, n.clone())
                }
                (Tok::Op(c @ ('*' | '/')), Tok::Name(n)) if !first && unit(n).is_some() => {
                    let d = *c == '/';
                    let n = n.clone();
                    self.bump();
                    (d, n)
                }
                _ => break,
            };
            let u = unit(&name).expect("checked");
            end = self.bump().1.end;
            let mut factor = u.factor;
            let mut dim = u.dim;
            if self.peek() == &Tok::Op('^') {
                let neg = self.peek2() == &Tok::Op('-');
                let at = self.at + 1 + usize::from(neg);
                if let Some((Tok::Num(p), s)) = self.toks.get(at).cloned() {
                    if p.fract() != 0.0 || p > 9.0 {
                        return err(s, "a unit's power is a whole number from -9 to 9");
                    }
                    let p = if neg { -p } else { p };
                    self.at = at;
                    end = self.bump().1.end;
                    factor = factor.powf(p);
                    dim = dim.pow(p).expect("whole power");
                }
            }
            if divide {
                factor = 1.0 / factor;
                dim = Dim::NONE.over(dim);
            }
            let d = q.dim.unwrap_or(Dim::NONE);
            q = Quantity::si(q.value * factor, d.times(dim));
            first = false;
        }
        Ok(Expr {
            kind: Kind::Value(q),
            span: span.start..end,
        })
    }

    fn call(&mut self, name: &str, name_span: Range<usize>) -> Result<Expr, ExprError> {
        let Some(&(_, f, arity)) = FUNCS.iter().find(|f| f.0 == name) else {
            let names: Vec<&str> = FUNCS.iter().map(|f| f.0).collect();
            return err(
                name_span,
                format!(
                    "no function \"{name}\"{}",
                    crate::diag::did_you_mean(name, names.iter().copied())
                ),
            );
        };
        self.bump();
        let mut args = Vec::new();
        loop {
            args.push(self.expr()?);
            match self.bump() {
                (Tok::Op(','), _) => continue,
                (Tok::Op(')'), s) => {
                    if args.len() != arity {
                        return err(
                            name_span.start..s.end,
                            format!("{name} takes {arity} argument(s), not {}", args.len()),
                        );
                    }
                    return Ok(Expr {
                        kind: Kind::Call(f, args),
                        span: name_span.start..s.end,
                    });
                }
                (_, s) => return err(s, "expected \",\" or \")\""),
            }
        }
    }
}

impl Parser {
    /// `a op b`, counted against [`MAX_OPS`].
    fn bin(&mut self, op: char, a: Expr, b: Expr) -> Result<Expr, ExprError> {
        self.ops += 1;
        let span = a.span.start..b.span.end;
        if self.ops > MAX_OPS {
            return err(
                span,
                format!("more than {MAX_OPS} operations in one expression"),
            );
        }
        Ok(Expr {
            kind: Kind::Bin(op, Box::new(a), Box::new(b)),
            span,
        })
    }
}

impl Expr {
    /// The parameter names it uses, with their spans, in order.
    pub fn names(&self) -> Vec<(&str, Range<usize>)> {
        let mut out = Vec::new();
        self.collect(&mut out);
        out
    }

    fn collect<'a>(&'a self, out: &mut Vec<(&'a str, Range<usize>)>) {
        match &self.kind {
            Kind::Value(_) => {}
            Kind::Name(n) => out.push((n, self.span.clone())),
            Kind::Neg(a) => a.collect(out),
            Kind::Bin(_, a, b) => {
                a.collect(out);
                b.collect(out);
            }
            Kind::Call(_, args) => args.iter().for_each(|a| a.collect(out)),
        }
    }

    /// The value, names looked up by `lookup`, plain numbers meeting a dimension read in the
    /// model's units (length unit `ell` metres).
    ///
    /// # Errors
    /// An unknown name (`lookup` gives the message), a dimension mismatch, a value that is not
    /// finite.
    pub fn eval(
        &self,
        lookup: &dyn Fn(&str) -> Result<Quantity, String>,
        ell: f64,
    ) -> Result<Quantity, ExprError> {
        let here = |m: String| ExprError {
            span: self.span.clone(),
            message: m,
        };
        let q = match &self.kind {
            Kind::Value(q) => *q,
            Kind::Name(n) => lookup(n).map_err(here)?,
            Kind::Neg(a) => {
                let q = a.eval(lookup, ell)?;
                Quantity {
                    value: -q.value,
                    ..q
                }
            }
            Kind::Bin(op, a, b) => {
                let (x, y) = (a.eval(lookup, ell)?, b.eval(lookup, ell)?);
                binary(*op, x, y, ell).map_err(here)?
            }
            Kind::Call(f, args) => {
                let v: Vec<Quantity> = args
                    .iter()
                    .map(|a| a.eval(lookup, ell))
                    .collect::<Result<_, _>>()?;
                call(*f, &v, ell).map_err(here)?
            }
        };
        if !q.value.is_finite() {
            return Err(here(format!(
                "the value is {} (overflow, or a function outside its domain)",
                q.value
            )));
        }
        Ok(q)
    }
}

/// The dimension both operands of + − min max atan2 share (a plain number takes the other's),
/// and both values in SI (or plain when both are).
fn common(
    x: Quantity,
    y: Quantity,
    ell: f64,
    what: &str,
) -> Result<(f64, f64, Option<Dim>), String> {
    match (x.dim, y.dim) {
        (Some(a), Some(b)) if a != b => Err(format!(
            "cannot {what} {} and {}: their units differ ({a} and {b})",
            x.describe(),
            y.describe()
        )),
        (Some(d), _) | (_, Some(d)) => Ok((x.as_dim(d, ell), y.as_dim(d, ell), Some(d))),
        (None, None) => Ok((x.value, y.value, None)),
    }
}

fn binary(op: char, x: Quantity, y: Quantity, ell: f64) -> Result<Quantity, String> {
    let both = |v: f64, d: Option<Dim>| Quantity { value: v, dim: d };
    Ok(match op {
        '+' | '-' => {
            let (a, b, d) = common(x, y, ell, if op == '+' { "add" } else { "subtract" })?;
            both(if op == '+' { a + b } else { a - b }, d)
        }
        '*' | '/' => {
            let d = match (x.dim, y.dim) {
                (None, None) => None,
                (a, b) => {
                    let (a, b) = (a.unwrap_or(Dim::NONE), b.unwrap_or(Dim::NONE));
                    Some(if op == '*' { a.times(b) } else { a.over(b) })
                }
            };
            both(
                if op == '*' {
                    x.value * y.value
                } else {
                    x.value / y.value
                },
                d,
            )
        }
        _ => {
            if y.dim.is_some_and(|d| d != Dim::NONE) {
                return Err(format!("an exponent has no unit; {} has", y.describe()));
            }
            let d = match x.dim {
                None => None,
                Some(d) => Some(d.pow(y.value).ok_or_else(|| {
                    format!("{} to the power {} has no unit", x.describe(), y.value)
                })?),
            };
            both(x.value.powf(y.value), d)
        }
    })
}

fn call(f: Func, v: &[Quantity], ell: f64) -> Result<Quantity, String> {
    let x = v[0];
    let dimensionless = |name: &str| -> Result<f64, String> {
        match x.dim {
            Some(d) if d != Dim::NONE => Err(format!(
                "{name} takes a number without a unit (or an angle), not {}",
                x.describe()
            )),
            _ => Ok(x.value),
        }
    };
    let keep = |value: f64| Quantity { value, dim: x.dim };
    let unitless = |value: f64| Quantity {
        value,
        dim: x.dim.map(|_| Dim::NONE),
    };
    let domain = match f {
        Func::Sqrt => x.value < 0.0,
        Func::Log => x.value <= 0.0,
        Func::Asin | Func::Acos => x.value.abs() > 1.0,
        _ => false,
    };
    if domain {
        let name = FUNCS.iter().find(|g| g.1 == f).map_or("", |g| g.0);
        return Err(format!("{name} of {} is not defined", x.describe()));
    }
    Ok(match f {
        Func::Abs => keep(x.value.abs()),
        Func::Sqrt => Quantity {
            value: x.value.sqrt(),
            dim: match x.dim {
                None => None,
                Some(d) => Some(d.pow(0.5).ok_or_else(|| {
                    format!("sqrt of {}: its unit has no square root", x.describe())
                })?),
            },
        },
        Func::Min | Func::Max | Func::Atan2 => {
            let name = match f {
                Func::Min => "compare",
                Func::Max => "compare",
                _ => "take atan2 of",
            };
            let (a, b, d) = common(x, v[1], ell, name)?;
            match f {
                Func::Min => Quantity {
                    value: a.min(b),
                    dim: d,
                },
                Func::Max => Quantity {
                    value: a.max(b),
                    dim: d,
                },
                _ => Quantity {
                    value: a.atan2(b),
                    dim: d.map(|_| Dim::NONE),
                },
            }
        }
        Func::Sin => unitless(dimensionless("sin")?.sin()),
        Func::Cos => unitless(dimensionless("cos")?.cos()),
        Func::Tan => unitless(dimensionless("tan")?.tan()),
        Func::Asin => unitless(dimensionless("asin")?.asin()),
        Func::Acos => unitless(dimensionless("acos")?.acos()),
        Func::Atan => unitless(dimensionless("atan")?.atan()),
        Func::Exp => unitless(dimensionless("exp")?.exp()),
        Func::Log => unitless(dimensionless("log")?.ln()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(text: &str, ell: f64) -> Result<Quantity, ExprError> {
        let look = |n: &str| match n {
            "crank" => Ok(Quantity::si(0.08, Dim([1, 0, 0]))),
            "speed" => Ok(Quantity::plain(2.0)),
            _ => Err(format!("no parameter \"{n}\"")),
        };
        parse(text)?.eval(&look, ell)
    }

    #[test]
    fn units_after_numbers() {
        let q = value("80 mm", 1.0).unwrap();
        assert!((q.value - 0.08).abs() < 1e-15 && q.dim == Some(Dim([1, 0, 0])));
        let g = value("9.81 m/s^2", 1.0).unwrap();
        assert_eq!(g.dim, Some(Dim([1, 0, -2])));
        let k = value("50 N/m", 1.0).unwrap();
        assert_eq!(k.dim, Some(Dim([0, 1, -2])));
        let c = value("2 N s/m", 1.0).unwrap();
        assert_eq!(c.dim, Some(Dim([0, 1, -1])));
        let i = value("0.5 kg m^2", 1.0).unwrap();
        assert_eq!(i.dim, Some(Dim([2, 1, 0])));
        let a = value("90 deg", 1.0).unwrap();
        assert!((a.value - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let w = value("60 rpm", 1.0).unwrap();
        assert!((w.value - 2.0 * std::f64::consts::PI).abs() < 1e-12);
        // A unit group ends at an operator followed by a number.
        let h = value("80 mm / 2", 1.0).unwrap();
        assert!((h.value - 0.04).abs() < 1e-15);
    }

    #[test]
    fn plain_numbers_take_the_model_units_of_what_they_meet() {
        // In a model in mm, crank + 10 is 90 mm; 2 * crank is 160 mm.
        let q = value("crank + 10", 1e-3).unwrap();
        assert!((q.in_model_units(1e-3) - 90.0).abs() < 1e-12);
        let q = value("2 * crank", 1e-3).unwrap();
        assert!((q.in_model_units(1e-3) - 160.0).abs() < 1e-12);
        let q = value("2 * crank + 0.01", 1.0).unwrap();
        assert!((q.in_model_units(1.0) - 0.17).abs() < 1e-15);
        assert_eq!(value("speed * 3", 1.0).unwrap(), Quantity::plain(6.0));
        assert!((value("sqrt(crank^2)", 1.0).unwrap().value - 0.08).abs() < 1e-15);
        // A mm model writes N/mm, N mm, kg mm², N and kg (crate::units).
        let in_mm = |t: &str| value(t, 1e-3).unwrap().in_model_units(1e-3);
        assert!((in_mm("50 N/m") - 0.05).abs() < 1e-15);
        assert!((in_mm("2 N m") - 2000.0).abs() < 1e-9);
        assert!((in_mm("0.5 kg m^2") - 5e5).abs() < 1e-6);
        assert!((in_mm("3 N") - 3.0).abs() < 1e-15 && (in_mm("3 kg") - 3.0).abs() < 1e-15);
        assert!((in_mm("9.81 m/s^2") - 9810.0).abs() < 1e-9);
    }

    #[test]
    fn exact_texts_read_back_to_the_same_quantity() {
        for t in [
            "80 mm",
            "60 rpm",
            "50 N/m",
            "0.5 kg m^2",
            "2 N s/m",
            "0.1",
            "90 deg",
            "3 W",
        ] {
            let q = value(t, 1.0).unwrap();
            let back = value(&q.exact_text(), 1.0).unwrap();
            assert_eq!(q.value, back.value, "{t}");
            assert_eq!(
                q.dim.filter(|d| *d != Dim::NONE),
                back.dim.filter(|d| *d != Dim::NONE),
                "{t}"
            );
        }
    }

    #[test]
    fn mismatched_units_are_refused_with_both_values() {
        let e = value("80 mm + 2 s", 1.0).unwrap_err();
        assert!(e.message.contains("0.08 m and 2 s"), "{}", e.message);
        assert_eq!(e.span, 0..11);
        let e = value("sin(crank)", 1.0).unwrap_err();
        assert!(
            e.message.contains("sin takes a number without a unit"),
            "{}",
            e.message
        );
        let e = value("sqrt(crank)", 1.0).unwrap_err();
        assert!(e.message.contains("no square root"), "{}", e.message);
    }

    #[test]
    fn problems_are_located() {
        let e = value("2 * crnak", 1.0).unwrap_err();
        assert_eq!(e.span, 4..9);
        let e = value("2 +", 1.0).unwrap_err();
        assert!(e.message.contains("ends"), "{}", e.message);
        let e = value("cos(1, 2)", 1.0).unwrap_err();
        assert!(e.message.contains("1 argument"), "{}", e.message);
        let e = value("sine(1)", 1.0).unwrap_err();
        assert!(e.message.contains("did you mean \"sin\""), "{}", e.message);
        let e = value("1 / 0", 1.0).unwrap_err();
        assert!(e.message.contains("inf"), "{}", e.message);
        let deep = format!("{}1{}", "(".repeat(200), ")".repeat(200));
        assert!(value(&deep, 1.0).unwrap_err().message.contains("nested"));
        // A long chain is refused before it is a tree too deep to evaluate.
        let chain = "1+".repeat(100_000) + "1";
        assert!(value(&chain, 1.0)
            .unwrap_err()
            .message
            .contains("more than 512 operations"));
        let pow = "2^".repeat(10_000) + "1";
        assert!(value(&pow, 1.0).is_err());
        let e = value("crank mm", 1.0).unwrap_err();
        assert!(e.message.contains("must follow a number"), "{}", e.message);
    }
}
