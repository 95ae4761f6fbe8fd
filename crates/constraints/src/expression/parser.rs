//! Recursive descent from tokens to a syntax tree (see the grammar in the module above).

use super::functions::{Arity, Func};
use super::lexer::{tokens, Tok};
use super::ParseError;
use std::ops::Range;

/// Deepest nesting of parentheses, calls and operators accepted (a bound on recursion).
pub(crate) const MAX_DEPTH: usize = 64;

/// Deepest syntax tree accepted: a chain a + b + c + … is a tree as deep as it is long, and
/// every pass over the tree (compilation, the time dependence, dropping it) recurses through
/// it, so a 5,000-term chain overflowed the stack. 512 operations in a row are far beyond a
/// formula a person writes; a longer chain is split into parts (or a table into `spline`).
pub(crate) const MAX_TREE_DEPTH: usize = 512;

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// A node of the syntax tree with the span of the text it was read from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Node {
    pub kind: NodeKind,
    pub span: Range<usize>,
    /// The depth of the tree under it (a leaf 1), bounded by [`MAX_TREE_DEPTH`].
    pub depth: usize,
}

/// What a node is.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum NodeKind {
    Num(f64),
    Time,
    Neg(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    Call(Func, Vec<Node>),
    /// `[a, b, ...]`: only as a spline argument.
    List(Vec<Node>),
}

impl Node {
    /// A node of `kind` read from `span` (its depth one more than its deepest child's).
    fn new(kind: NodeKind, span: Range<usize>) -> Self {
        let depth = 1 + match &kind {
            NodeKind::Num(_) | NodeKind::Time => 0,
            NodeKind::Neg(a) => a.depth,
            NodeKind::Bin(_, a, b) => a.depth.max(b.depth),
            NodeKind::Call(_, args) | NodeKind::List(args) => {
                args.iter().map(|a| a.depth).max().unwrap_or(0)
            }
        };
        Self { kind, span, depth }
    }

    /// Whether the node depends on the time.
    pub(crate) fn has_time(&self) -> bool {
        match &self.kind {
            NodeKind::Num(_) => false,
            NodeKind::Time => true,
            NodeKind::Neg(a) => a.has_time(),
            NodeKind::Bin(_, a, b) => a.has_time() || b.has_time(),
            NodeKind::Call(_, args) | NodeKind::List(args) => args.iter().any(Node::has_time),
        }
    }
}

/// Names of constants an expression may use besides `pi` and `e` (a model's parameters), with
/// their values.
pub type Constants<'a> = &'a dyn Fn(&str) -> Option<f64>;

struct Parser<'a> {
    toks: Vec<(Tok, Range<usize>)>,
    at: usize,
    depth: usize,
    constants: Constants<'a>,
}

/// Parses a whole expression, names other than `t`, `pi`, `e` and the functions looked up in
/// `constants`.
pub(crate) fn parse(text: &str, constants: Constants<'_>) -> Result<Node, ParseError> {
    let mut p = Parser {
        toks: tokens(text)?,
        at: 0,
        depth: 0,
        constants,
    };
    if p.peek() == &Tok::End {
        return Err(ParseError::new(0..0, "the expression is empty"));
    }
    let n = p.expr()?;
    match p.peek() {
        Tok::End => Ok(n),
        Tok::RParen => Err(p.error_here("this \")\" has no matching \"(\"")),
        t => {
            let what = t.describe();
            Err(p.error_here(&format!(
                "expected an operator (+ - * / ^) or the end, found {what}"
            )))
        }
    }
}

impl Parser<'_> {
    fn peek(&self) -> &Tok {
        &self.toks[self.at].0
    }

    fn span(&self) -> Range<usize> {
        self.toks[self.at].1.clone()
    }

    fn bump(&mut self) -> (Tok, Range<usize>) {
        let t = self.toks[self.at].clone();
        if self.at + 1 < self.toks.len() {
            self.at += 1;
        }
        t
    }

    fn error_here(&self, m: &str) -> ParseError {
        ParseError::new(self.span(), m)
    }

    fn enter(&mut self) -> Result<(), ParseError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error_here(&format!(
                "the expression nests deeper than {MAX_DEPTH} levels"
            )));
        }
        Ok(())
    }

    /// `n`, or an error at it when its tree is deeper than [`MAX_TREE_DEPTH`].
    fn deep(&self, n: Node) -> Result<Node, ParseError> {
        if n.depth > MAX_TREE_DEPTH {
            return Err(ParseError::new(
                n.span.end.saturating_sub(1)..n.span.end,
                format!(
                    "the expression chains more than {MAX_TREE_DEPTH} operations in a row; \
                     split it into parts (a table of values is a spline)"
                ),
            ));
        }
        Ok(n)
    }

    /// expr := term { ("+" | "-") term }
    fn expr(&mut self) -> Result<Node, ParseError> {
        self.enter()?;
        let mut a = self.term()?;
        loop {
            let op = match self.peek() {
                Tok::Plus => BinOp::Add,
                Tok::Minus => BinOp::Sub,
                _ => break,
            };
            self.bump();
            let b = self.term()?;
            a = self.deep(bin(op, a, b))?;
        }
        self.depth -= 1;
        Ok(a)
    }

    /// term := unary { ("*" | "/") unary }
    fn term(&mut self) -> Result<Node, ParseError> {
        let mut a = self.unary()?;
        loop {
            let op = match self.peek() {
                Tok::Star => BinOp::Mul,
                Tok::Slash => BinOp::Div,
                _ => break,
            };
            self.bump();
            let b = self.unary()?;
            a = self.deep(bin(op, a, b))?;
        }
        Ok(a)
    }

    /// unary := ("+" | "-") unary | power
    fn unary(&mut self) -> Result<Node, ParseError> {
        self.enter()?;
        let n = match self.peek() {
            Tok::Minus | Tok::Plus => {
                let (t, s) = self.bump();
                let a = self.unary()?;
                if t == Tok::Plus {
                    a
                } else {
                    let span = s.start..a.span.end;
                    Node::new(NodeKind::Neg(Box::new(a)), span)
                }
            }
            _ => self.power()?,
        };
        self.depth -= 1;
        Ok(n)
    }

    /// power := primary [ "^" unary ]   (right-associative; -2^2 = −(2²), 2^-1 = 0.5)
    fn power(&mut self) -> Result<Node, ParseError> {
        let a = self.primary()?;
        if self.peek() == &Tok::Caret {
            self.bump();
            let b = self.unary()?;
            return Ok(bin(BinOp::Pow, a, b));
        }
        Ok(a)
    }

    /// primary := number | name | name "(" args ")" | "(" expr ")" | "[" args "]"
    fn primary(&mut self) -> Result<Node, ParseError> {
        let (tok, span) = self.bump();
        let kind = match tok {
            Tok::Num(x) => NodeKind::Num(x),
            Tok::Name(n) if self.peek() == &Tok::LParen => return self.call(&n, span),
            Tok::Name(n) => match n.as_str() {
                "t" | "time" => NodeKind::Time,
                "pi" => NodeKind::Num(std::f64::consts::PI),
                "e" => NodeKind::Num(std::f64::consts::E),
                _ if Func::from_name(&n).is_some() => {
                    return Err(ParseError::new(
                        span,
                        format!("the function \"{n}\" needs its arguments in parentheses"),
                    ))
                }
                _ => match (self.constants)(&n) {
                    Some(x) => NodeKind::Num(x),
                    None => return Err(ParseError::unknown(span, n)),
                },
            },
            Tok::LParen => {
                let inner = self.expr()?;
                let end = self.close(Tok::RParen, "\")\"", &span)?;
                return Ok(Node {
                    span: span.start..end,
                    ..inner
                });
            }
            Tok::LBracket => {
                let (items, end) = self.list(Tok::RBracket, "\"]\"", &span)?;
                return Ok(Node::new(NodeKind::List(items), span.start..end));
            }
            other => {
                let what = other.describe();
                return Err(ParseError::new(
                    span,
                    format!("expected a number, a name or \"(\", found {what}"),
                ));
            }
        };
        Ok(Node::new(kind, span))
    }

    /// `name(args)`, the name already read.
    fn call(&mut self, name: &str, name_span: Range<usize>) -> Result<Node, ParseError> {
        let Some(f) = Func::from_name(name) else {
            if matches!(name, "t" | "time" | "pi" | "e") {
                return Err(ParseError::new(
                    name_span,
                    format!("\"{name}\" is not a function; write * for a product"),
                ));
            }
            return Err(ParseError::unknown(name_span, name.to_string()));
        };
        let open = self.bump().1;
        let (args, end) = self.list(Tok::RParen, "\")\"", &open)?;
        let n = args.len();
        let ok = match f.arity() {
            Arity::Exactly(k) => n == k,
            Arity::Piecewise => n >= 4 && n % 2 == 0,
        };
        let span = name_span.start..end;
        if !ok {
            let expected = match f.arity() {
                Arity::Exactly(1) => "1 argument".to_string(),
                Arity::Exactly(k) => format!("{k} arguments"),
                Arity::Piecewise => "an even number of arguments, at least 4".to_string(),
            };
            return Err(ParseError::new(
                span,
                format!(
                    "{}() takes {expected}, {}, but is given {n}",
                    f.name(),
                    f.signature()
                ),
            ));
        }
        Ok(Node::new(NodeKind::Call(f, args), span))
    }

    /// Comma-separated expressions up to `close` (the opening token already read); returns
    /// them and the end of the closing token.
    fn list(
        &mut self,
        close: Tok,
        close_text: &str,
        open: &Range<usize>,
    ) -> Result<(Vec<Node>, usize), ParseError> {
        let mut items = Vec::new();
        if self.peek() == &close {
            return Ok((items, self.bump().1.end));
        }
        loop {
            items.push(self.expr()?);
            if self.peek() == &Tok::Comma {
                self.bump();
                continue;
            }
            let end = self.close(close.clone(), close_text, open)?;
            return Ok((items, end));
        }
    }

    /// Reads the closing token or explains which opening one it is missing.
    fn close(
        &mut self,
        close: Tok,
        close_text: &str,
        open: &Range<usize>,
    ) -> Result<usize, ParseError> {
        if self.peek() == &close {
            return Ok(self.bump().1.end);
        }
        let found = self.peek().describe();
        let mut e = self.error_here(&format!(
            "expected {close_text} or \",\", found {found} (the bracket opened at column {})",
            open.start + 1
        ));
        if self.peek() == &Tok::End {
            e = ParseError::new(
                open.clone(),
                format!("this bracket is never closed (expected {close_text})"),
            );
        }
        Err(e)
    }
}

fn bin(op: BinOp, a: Node, b: Node) -> Node {
    let span = a.span.start..b.span.end;
    Node::new(NodeKind::Bin(op, Box::new(a), Box::new(b)), span)
}

#[cfg(test)]
mod depth_tests {
    use super::*;

    /// A chain of thousands of terms was a tree thousands deep that overflowed the stack in the
    /// passes over it (issue 45); it is refused at the operation past the limit.
    #[test]
    fn long_chains_are_refused_not_overflowed() {
        let ok = format!("t{}", "+t".repeat(MAX_TREE_DEPTH - 1));
        assert!(parse(&ok, &|_| None).is_ok());
        for op in ["+", "*"] {
            let long = format!("t{}", format!("{op}t").repeat(4900));
            let e = parse(&long, &|_| None).unwrap_err();
            assert!(e.to_string().contains("more than 512 operations"), "{e}");
        }
        // Nesting is bounded separately; a table of 2000 negative numbers is a shallow list.
        let list = format!("[{}]", vec!["-1.5"; 2000].join(", "));
        assert!(parse(&list, &|_| None).is_ok());
    }
}
