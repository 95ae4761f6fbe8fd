//! ASMT motion expressions → cardan's expression grammar
//! ([`cardan_constraints::expression`]).
//!
//! OndselSolver's grammar (`SymbolicParser`, notes §1.7) is a subset of cardan's with a few
//! spellings of its own; translating the text (rather than teaching cardan's parser ASMT) keeps
//! one expression language in cardan, and the translated text is what `cardan import` writes.
//!
//! | ASMT | cardan |
//! |---|---|
//! | `2.0d`, `1.0d-3` (Smalltalk double suffix) | `2.0`, `0.001` |
//! | `time` | `t` |
//! | `arctan(x)`, `arcsin(x)`, `asin(x)` | `atan(x)`, `asin(x)`, `asin(x)` |
//! | `rampstep(x, x0, y0, x1, y1)` (linear ramp, `RampStepFunction`) | `piecewise(x, y0, x0, y0 + (y1 − y0)/(x1 − x0)·(x − x0), x1, y1)` |
//! | `piecewise(x, functions(f1, …, fn), transitions(t1, …, tn−1))` | `piecewise(x, f1, t1, f2, …, fn)` |
//! | `"…"` comments, `<n>` line tags | removed |
//! | empty text | `0` |
//!
//! `spline(x, order, …)` (OndselSolver's general spline of any order) and `integral` have no
//! exact counterpart and are refused. The output is fully parenthesised, so precedence cannot
//! change in translation; breakpoints are folded to numbers (cardan needs constants there).

use std::fmt::Write as _;

/// A syntax tree of an ASMT expression.
#[derive(Debug, Clone, PartialEq)]
enum Ast {
    Num(f64),
    Time,
    Pi,
    Neg(Box<Ast>),
    Bin(char, Box<Ast>, Box<Ast>),
    Call(String, Vec<Ast>),
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
}

/// Translates ASMT expression `text`; the error is a one-sentence reason.
pub fn translate(text: &str) -> Result<String, String> {
    let toks = lex(text)?;
    if toks.is_empty() {
        return Ok("0".into());
    }
    let mut p = Parser { toks, k: 0 };
    let ast = p.expression()?;
    if p.k != p.toks.len() {
        return Err(format!("unexpected {} after the expression", p.show()));
    }
    let mut out = String::new();
    print(&ast, &mut out)?;
    Ok(out)
}

fn lex(text: &str) -> Result<Vec<Tok>, String> {
    let b = text.as_bytes();
    let mut toks = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let c = b[k] as char;
        if c.is_whitespace() {
            k += 1;
        } else if c == '"' {
            // A comment: up to the closing quote.
            match text[k + 1..].find('"') {
                Some(e) => k += e + 2,
                None => return Err("a comment opened with \" is not closed".into()),
            }
        } else if c == '<' {
            // A line tag <n>.
            match text[k + 1..].find('>') {
                Some(e)
                    if text[k + 1..k + 1 + e]
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric()) =>
                {
                    k += e + 2
                }
                _ => return Err("'<' is neither a line tag <n> nor an operator".into()),
            }
        } else if c.is_ascii_digit() || (c == '.' && b.get(k + 1).is_some_and(u8::is_ascii_digit)) {
            let s = k;
            while k < b.len() && (b[k].is_ascii_digit() || b[k] == b'.') {
                k += 1;
            }
            let mantissa = &text[s..k];
            let mut exponent = String::new();
            if k < b.len() && matches!(b[k], b'd' | b'D' | b'e' | b'E') {
                let mut j = k + 1;
                if j < b.len() && matches!(b[j], b'+' | b'-') {
                    j += 1;
                }
                let ds = j;
                while j < b.len() && b[j].is_ascii_digit() {
                    j += 1;
                }
                // "2.0d" alone is 2.0; "2.0d-3" is 2.0e-3; a sign without digits is not part
                // of the number.
                if j > ds {
                    exponent = format!("e{}", &text[k + 1..j]);
                    k = j;
                } else if ds == k + 1 && !b.get(k + 1).is_some_and(u8::is_ascii_alphabetic) {
                    k += 1;
                }
            }
            let v: f64 = format!("{mantissa}{exponent}")
                .parse()
                .map_err(|_| format!("\"{mantissa}{exponent}\" is not a number"))?;
            if !v.is_finite() {
                return Err(format!("\"{mantissa}{exponent}\" is not a finite number"));
            }
            toks.push(Tok::Num(v));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let s = k;
            while k < b.len() && (b[k].is_ascii_alphanumeric() || b[k] == b'_') {
                k += 1;
            }
            toks.push(Tok::Name(text[s..k].to_string()));
        } else if "+-*/^(),".contains(c) {
            toks.push(Tok::Op(c));
            k += 1;
        } else {
            let ch = text[k..].chars().next().unwrap_or('?');
            return Err(format!("unexpected character '{ch}'"));
        }
    }
    Ok(toks)
}

struct Parser {
    toks: Vec<Tok>,
    k: usize,
}

/// Deepest nesting accepted (a hostile file must not overflow the stack).
const MAX_DEPTH: usize = 64;

impl Parser {
    fn peek_op(&self, c: char) -> bool {
        self.toks.get(self.k) == Some(&Tok::Op(c))
    }

    fn show(&self) -> String {
        match self.toks.get(self.k) {
            None => "the end of the text".into(),
            Some(Tok::Num(v)) => format!("the number {v}"),
            Some(Tok::Name(n)) => format!("\"{n}\""),
            Some(Tok::Op(c)) => format!("'{c}'"),
        }
    }

    fn expect(&mut self, c: char) -> Result<(), String> {
        if self.peek_op(c) {
            self.k += 1;
            Ok(())
        } else {
            Err(format!("expected '{c}', found {}", self.show()))
        }
    }

    fn expression(&mut self) -> Result<Ast, String> {
        self.expr_at(0)
    }

    fn expr_at(&mut self, depth: usize) -> Result<Ast, String> {
        if depth > MAX_DEPTH {
            return Err(format!("nested more than {MAX_DEPTH} levels deep"));
        }
        let neg = if self.peek_op('-') {
            self.k += 1;
            true
        } else {
            if self.peek_op('+') {
                self.k += 1;
            }
            false
        };
        let mut a = self.term(depth)?;
        if neg {
            a = Ast::Neg(Box::new(a));
        }
        while self.peek_op('+') || self.peek_op('-') {
            let Tok::Op(op) = self.toks[self.k] else {
                unreachable!()
            };
            self.k += 1;
            let b = self.term(depth)?;
            a = Ast::Bin(op, Box::new(a), Box::new(b));
        }
        Ok(a)
    }

    fn term(&mut self, depth: usize) -> Result<Ast, String> {
        let mut a = self.factor(depth)?;
        while self.peek_op('*') || self.peek_op('/') {
            let Tok::Op(op) = self.toks[self.k] else {
                unreachable!()
            };
            self.k += 1;
            let b = self.factor(depth)?;
            a = Ast::Bin(op, Box::new(a), Box::new(b));
        }
        Ok(a)
    }

    fn factor(&mut self, depth: usize) -> Result<Ast, String> {
        let a = self.primary(depth)?;
        if self.peek_op('^') {
            self.k += 1;
            if depth > MAX_DEPTH {
                return Err(format!("nested more than {MAX_DEPTH} levels deep"));
            }
            // Right-associative; a signed exponent (2^-1) is accepted as cardan does.
            let b = if self.peek_op('-') {
                self.k += 1;
                Ast::Neg(Box::new(self.factor(depth + 1)?))
            } else {
                self.factor(depth + 1)?
            };
            return Ok(Ast::Bin('^', Box::new(a), Box::new(b)));
        }
        Ok(a)
    }

    fn primary(&mut self, depth: usize) -> Result<Ast, String> {
        match self.toks.get(self.k).cloned() {
            Some(Tok::Num(v)) => {
                self.k += 1;
                Ok(Ast::Num(v))
            }
            Some(Tok::Op('(')) => {
                self.k += 1;
                let e = self.expr_at(depth + 1)?;
                self.expect(')')?;
                Ok(e)
            }
            Some(Tok::Name(n)) => {
                self.k += 1;
                match n.as_str() {
                    "time" => Ok(Ast::Time),
                    "pi" => Ok(Ast::Pi),
                    _ if self.peek_op('(') => {
                        self.k += 1;
                        let mut args = vec![self.expr_at(depth + 1)?];
                        while self.peek_op(',') {
                            self.k += 1;
                            args.push(self.expr_at(depth + 1)?);
                        }
                        self.expect(')')?;
                        Ok(Ast::Call(n, args))
                    }
                    _ => Err(format!(
                        "unknown name \"{n}\" (ASMT motions know only time and pi)"
                    )),
                }
            }
            _ => Err(format!(
                "expected a number, time, pi, a function or '(', found {}",
                self.show()
            )),
        }
    }
}

/// The value of a constant subtree (no `time`), for breakpoints.
fn constant(a: &Ast) -> Option<f64> {
    Some(match a {
        Ast::Num(v) => *v,
        Ast::Pi => std::f64::consts::PI,
        Ast::Time | Ast::Call(..) => return None,
        Ast::Neg(x) => -constant(x)?,
        Ast::Bin(op, x, y) => {
            let (x, y) = (constant(x)?, constant(y)?);
            match op {
                '+' => x + y,
                '-' => x - y,
                '*' => x * y,
                '/' => x / y,
                _ => x.powf(y),
            }
        }
    })
}

fn breakpoint(a: &Ast, what: &str) -> Result<f64, String> {
    match constant(a) {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{what} must be a constant")),
    }
}

fn print(a: &Ast, out: &mut String) -> Result<(), String> {
    match a {
        Ast::Num(v) => {
            let _ = write!(out, "{v:?}");
        }
        Ast::Time => out.push('t'),
        Ast::Pi => out.push_str("pi"),
        Ast::Neg(x) => {
            out.push_str("(-");
            print(x, out)?;
            out.push(')');
        }
        Ast::Bin(op, x, y) => {
            out.push('(');
            print(x, out)?;
            out.push(*op);
            print(y, out)?;
            out.push(')');
        }
        Ast::Call(name, args) => call(name, args, out)?,
    }
    Ok(())
}

fn list(args: &[Ast], out: &mut String) -> Result<(), String> {
    for (k, a) in args.iter().enumerate() {
        if k > 0 {
            out.push_str(", ");
        }
        print(a, out)?;
    }
    Ok(())
}

fn call(name: &str, args: &[Ast], out: &mut String) -> Result<(), String> {
    let unary = |cardan: &str, out: &mut String| -> Result<(), String> {
        if args.len() != 1 {
            return Err(format!("{name} takes 1 argument, {} given", args.len()));
        }
        out.push_str(cardan);
        out.push('(');
        print(&args[0], out)?;
        out.push(')');
        Ok(())
    };
    match name {
        "sin" | "cos" | "abs" => unary(name, out),
        "asin" | "arcsin" => unary("asin", out),
        "arctan" => unary("atan", out),
        "rampstep" => {
            let [x, x0, y0, x1, y1] = args else {
                return Err(format!(
                    "rampstep takes 5 arguments (x, x0, y0, x1, y1), {} given",
                    args.len()
                ));
            };
            let (a0, a1) = (
                breakpoint(x0, "rampstep's x0")?,
                breakpoint(x1, "rampstep's x1")?,
            );
            if a1 <= a0 {
                return Err(format!("rampstep needs x0 < x1 (x0 = {a0}, x1 = {a1})"));
            }
            let ramp = Ast::Bin(
                '+',
                Box::new(y0.clone()),
                Box::new(Ast::Bin(
                    '*',
                    Box::new(Ast::Bin(
                        '/',
                        Box::new(Ast::Bin('-', Box::new(y1.clone()), Box::new(y0.clone()))),
                        Box::new(Ast::Num(a1 - a0)),
                    )),
                    Box::new(Ast::Bin('-', Box::new(x.clone()), Box::new(Ast::Num(a0)))),
                )),
            );
            out.push_str("piecewise(");
            list(
                &[x.clone(), y0.clone(), Ast::Num(a0), ramp, Ast::Num(a1), y1.clone()],
                out,
            )?;
            out.push(')');
            Ok(())
        }
        "piecewise" => {
            let [x, Ast::Call(f, fs), Ast::Call(t, ts)] = args else {
                return Err("piecewise takes (x, functions(f1, …), transitions(t1, …))".into());
            };
            if f != "functions" || t != "transitions" || fs.len() != ts.len() + 1 {
                return Err("piecewise takes (x, functions(f1, …, fn), transitions(t1, …, tn−1)), n functions and n − 1 transitions".into());
            }
            let mut flat = vec![x.clone(), fs[0].clone()];
            let mut last = f64::NEG_INFINITY;
            for (tk, fk) in ts.iter().zip(&fs[1..]) {
                let v = breakpoint(tk, "a piecewise transition")?;
                if v <= last {
                    return Err("piecewise transitions must increase".into());
                }
                last = v;
                flat.push(Ast::Num(v));
                flat.push(fk.clone());
            }
            out.push_str("piecewise(");
            list(&flat, out)?;
            out.push(')');
            Ok(())
        }
        "spline" | "integral" => Err(format!(
            "{name}(…) has no exact counterpart in cardan (OndselSolver's general spline of any order, integrals); rewrite the motion with polynomials, piecewise or cardan's spline time function"
        )),
        "functions" | "transitions" => Err(format!("{name}(…) may only appear inside piecewise(…)")),
        other => Err(format!(
            "unknown function \"{other}\" (ASMT knows abs, sin, cos, asin, arcsin, arctan, rampstep, piecewise)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cardan_constraints::expression::Expression;

    fn value(asmt: &str, t: f64) -> f64 {
        let text = translate(asmt).unwrap();
        Expression::parse(&text).unwrap().eval(t).0
    }

    #[test]
    fn testapp_expressions() {
        let pi = std::f64::consts::PI;
        assert_eq!(value("2.0d*pi*time", 0.25), 2.0 * pi * 0.25);
        let t = 0.3;
        let want = (45.0 + 45.0 * ((360.0 * t - 90.0) * pi / 180.0).sin()) * pi / 180.0;
        let got = value(
            "(45.0d + 45.0d*sin((360.0d*time - 90.0d)*pi/180.0d))*pi/180.0d",
            t,
        );
        assert!((got - want).abs() < 1e-15);
        assert_eq!(value("-0.05 + 0.05*sin(2*pi*time - 0)", 0.0), -0.05);
        assert_eq!(value("1.0d-3*time", 2.0), 2e-3);
        assert_eq!(value("", 1.0), 0.0);
        assert_eq!(value("-2^2", 0.0), -4.0);
        assert_eq!(value("2^3^2", 0.0), 512.0);
        assert_eq!(value("8/2*2", 0.0), 8.0);
    }

    #[test]
    fn comments_tags_and_aliases() {
        let v = value("\"template\"<n>arctan(time)<n>+<n>arcsin(0.5)", 1.0);
        assert!((v - (1f64.atan() + 0.5f64.asin())).abs() < 1e-15);
    }

    #[test]
    fn rampstep_is_linear_between_its_breakpoints() {
        let f = "rampstep(time, 1.0, 2.0, 3.0, 6.0)";
        assert_eq!(value(f, 0.0), 2.0);
        assert_eq!(value(f, 2.0), 4.0);
        assert_eq!(value(f, 5.0), 6.0);
        let text = translate(f).unwrap();
        let (_, rate, _) = Expression::parse(&text).unwrap().eval(2.0);
        assert_eq!(rate, 2.0);
    }

    #[test]
    fn piecewise_form() {
        let f = "piecewise(time, functions(0, 2*time, 4), transitions(0.5d, 2))";
        assert_eq!(value(f, 0.1), 0.0);
        assert_eq!(value(f, 1.0), 2.0);
        assert_eq!(value(f, 3.0), 4.0);
    }

    #[test]
    fn refusals_say_why() {
        assert!(translate("spline(time, 3, 0, 0, 1, 1)")
            .unwrap_err()
            .contains("spline"));
        assert!(translate("exp(time)").unwrap_err().contains("exp"));
        assert!(translate("x*time").unwrap_err().contains("\"x\""));
        assert!(translate("sin(time").unwrap_err().contains("')'"));
        assert!(translate("\"open").is_err());
        let deep = "(".repeat(200) + "1" + &")".repeat(200);
        assert!(translate(&deep).is_err());
    }
}
