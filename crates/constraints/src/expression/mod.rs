//! Expression time functions: f(t) written as text, with exact ḟ and f̈.
//!
//! ```
//! use cardan_constraints::expression::Expression;
//! let f = Expression::parse("0.5 + 0.3*sin(2*pi*t - pi/2)").unwrap();
//! let (v, d1, d2) = f.eval(0.25);
//! assert!((v - 0.5).abs() < 1e-15 && (d1 - 0.6 * std::f64::consts::PI).abs() < 1e-14);
//! # let _ = d2;
//! ```
//!
//! ## Grammar
//! ```text
//! expr    := term { ("+" | "-") term }
//! term    := unary { ("*" | "/") unary }
//! unary   := ("+" | "-") unary | power
//! power   := primary [ "^" unary ]                 (right-associative)
//! primary := number | "t" | "time" | "pi" | "e" | name "(" expr { "," expr } ")"
//!          | "(" expr ")" | "[" expr { "," expr } "]"    (a list: spline knots only)
//! number  := digits [ "." digits ] [ ("e" | "E") [ "+" | "-" ] digits ]     (or ".5")
//! ```
//! Precedence, loosest first: `+ -`, `* /`, unary `-`, `^`. So `-2^2` = −(2²) = −4 (as in
//! mathematics), `2^-1` = 0.5, `2^3^2` = 2^(3^2) = 512, `a/b*c` = (a/b)·c.
//!
//! Functions: sin cos tan asin acos atan atan2(y, x) sinh cosh tanh exp log (natural) sqrt
//! abs sign min(a, b) max(a, b), and
//! - `step(x, x0, f0, x1, f1)`: the C² quintic step of the `ramp` time function with argument
//!   x (any expression): f0 + (f1 − f0)(10τ³ − 15τ⁴ + 6τ⁵), τ = clamp((x − x0)/(x1 − x0), 0, 1);
//!   x0 < x1 constants, f0 and f1 any expressions;
//! - `piecewise(x, f0, x1, f1, ..., xn, fn)`: f0 for x < x1, f_k for x_k ≤ x < x_{k+1}, fn for
//!   x ≥ xn (constant, strictly increasing breakpoints; only the active branch is evaluated);
//! - `spline(x, [x0, x1, ...], [f0, f1, ...])`: the natural cubic spline of the `spline` time
//!   function through constant knots, linear beyond them.
//!
//! ## Derivatives
//! The text is parsed once (`parser`), compiled to a flat tape of stack operations with the
//! constant parts evaluated (`compile`), and run over [`jet::Jet`]s (u, u̇, ü) on a fixed-size
//! stack (`eval`): second-order forward-mode differentiation, exact up to rounding. For g(u),
//! (g(u))˙ = g′ u̇ and (g(u))¨ = g″ u̇² + g′ ü; products and quotients by their rules. abs, sign,
//! min, max, step and piecewise take the derivatives of the active branch (sign: zero).
//! Evaluation does not allocate.
//!
//! ## Errors
//! A [`ParseError`] carries the byte span of the problem in the text. Where a function is not
//! defined (sqrt of a negative, log of ≤ 0, asin beyond ±1, division by zero, overflow) the
//! result is not finite: [`Expression::diagnose`] names the first operation that fails.

mod compile;
mod eval;
mod functions;
mod jet;
mod lexer;
mod parser;

pub use eval::DomainError;
pub use functions::names;
pub use jet::Jet;
pub use parser::Constants;

use crate::spline::Spline;
use std::fmt;
use std::ops::Range;

/// Most intermediate values an expression may need at once (the evaluation stack).
pub const STACK: usize = 32;

/// A parsed, compiled expression f(t).
#[derive(Debug, Clone)]
pub struct Expression {
    text: String,
    prog: Program,
    /// A number no other compiled expression of the process has (clones share it: the same
    /// program gives the same values), the key of the evaluation memo ([`Expression::eval`]).
    id: u64,
}

impl PartialEq for Expression {
    fn eq(&self, other: &Self) -> bool {
        self.text == other.text && self.prog == other.prog
    }
}

/// The source of [`Expression`] ids (0 marks an empty memo slot).
static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// Slots of the evaluation memo, per thread: direct-mapped on the id, so up to this many
/// expressions evaluated in turn at one time each keep their values.
const MEMO_SLOTS: usize = 64;

/// One memo slot: an expression's id, the bits of t and (f, ḟ, f̈) there.
#[derive(Clone, Copy)]
struct Memo {
    id: u64,
    t: u64,
    value: (f64, f64, f64),
}

thread_local! {
    /// The last values of the expressions this thread evaluated (see [`Expression::eval`]).
    static MEMO: std::cell::RefCell<[Memo; MEMO_SLOTS]> = const {
        std::cell::RefCell::new([Memo { id: 0, t: 0, value: (0.0, 0.0, 0.0) }; MEMO_SLOTS])
    };
}

/// Longest expression text quoted in a message ([`quoted`]).
pub const QUOTE_MAX: usize = 80;

/// An expression's text for a message: whole up to [`QUOTE_MAX`] characters, else its first
/// [`QUOTE_MAX`] characters and "…" (a 10,000-character expression is not echoed; the message
/// gives the column of the problem).
pub fn quoted(text: &str) -> std::borrow::Cow<'_, str> {
    match text.char_indices().nth(QUOTE_MAX) {
        None => text.into(),
        Some((end, _)) => format!("{}…", &text[..end]).into(),
    }
}

impl Expression {
    /// Parses and compiles `text`.
    ///
    /// # Errors
    /// A [`ParseError`] with the span of the problem.
    pub fn parse(text: &str) -> Result<Self, ParseError> {
        Self::parse_with(text, &|_| None)
    }

    /// Parses and compiles `text`, a name that is neither `t`, `pi`, `e` nor a function
    /// standing for the constant `constants` gives it (a model's parameters).
    ///
    /// # Errors
    /// As [`Expression::parse`]; a name `constants` does not know is unknown.
    pub fn parse_with(text: &str, constants: parser::Constants<'_>) -> Result<Self, ParseError> {
        let tree = parser::parse(text, constants)?;
        let prog = compile::compile(&tree)?;
        Ok(Self {
            text: text.to_string(),
            prog,
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        })
    }

    /// The text it was parsed from.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Whether the expression reads t anywhere (`false`: a constant, whatever its form).
    pub fn uses_time(&self) -> bool {
        self.prog.ops.iter().any(|op| matches!(op, Op::Time))
    }

    /// (f, ḟ, f̈) at t (not finite where the expression is not defined).
    #[inline]
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        // A driver's f(t) is asked for about ten times at each time of a run (Φ in each Newton
        // iteration, ν, γ#, the dynamics' rows, the power), at the same t: the last value of
        // each expression is kept per thread (an expression is a pure function of t).
        let key = t.to_bits();
        MEMO.with(|memo| {
            let mut memo = memo.borrow_mut();
            let slot = &mut memo[(self.id % MEMO_SLOTS as u64) as usize];
            if slot.id == self.id && slot.t == key {
                return slot.value;
            }
            let j = self.prog.run(t);
            let value = (j.v, j.d1, j.d2);
            *slot = Memo {
                id: self.id,
                t: key,
                value,
            };
            value
        })
    }

    /// Where the expression first stops being finite at t (`None` if f, ḟ, f̈ are finite).
    pub fn diagnose(&self, t: f64) -> Option<DomainError> {
        self.prog.diagnose(t)
    }

    /// A one-line description of [`Expression::diagnose`]'s finding at t, quoting the failing
    /// part of the text when it is not the whole, e.g.
    /// `at "sqrt(1 - t)" (column 7): sqrt of -1: value NaN, rate NaN, acceleration NaN`.
    pub fn domain_message(&self, t: f64) -> Option<String> {
        self.diagnose(t).map(|d| {
            let part = &self.text[d.span.clone()];
            if part.trim() == self.text.trim() {
                d.message
            } else {
                format!("at \"{part}\" (column {}): {}", d.span.start + 1, d.message)
            }
        })
    }
}

/// A syntax or definition error in an expression's text.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    /// Byte span in the text (empty at the end of the text).
    pub span: Range<usize>,
    /// What is wrong.
    pub message: String,
    /// An unknown name, for suggestions among [`names`].
    pub unknown: Option<String>,
}

impl ParseError {
    pub(crate) fn new(span: Range<usize>, message: impl Into<String>) -> Self {
        Self {
            span,
            message: message.into(),
            unknown: None,
        }
    }

    pub(crate) fn unknown(span: Range<usize>, name: String) -> Self {
        Self {
            span,
            message: format!("unknown name \"{name}\""),
            unknown: Some(name),
        }
    }

    /// 1-based column of the start of the span, counted in characters of `text`.
    pub fn column(&self, text: &str) -> usize {
        let mut at = self.span.start.min(text.len());
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        text[..at].chars().count() + 1
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at column {}: {}", self.span.start + 1, self.message)
    }
}

impl std::error::Error for ParseError {}

/// One operation of the tape. Values are popped from and pushed to the jet stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Op {
    Const(f64),
    Time,
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// u^v with v depending on t.
    Pow,
    /// u^c with a constant c.
    PowC(f64),
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Log,
    Sqrt,
    Abs,
    Sign,
    Min,
    Max,
    /// Pops x, f0, f1; pushes the smooth step.
    Step {
        x0: f64,
        x1: f64,
    },
    /// Spline k of the program applied to the top.
    Spline(usize),
    /// Pops x and jumps to the branch of piecewise table k.
    Select(usize),
    /// Jumps to the operation at the index.
    Jump(usize),
}

impl Op {
    /// Values it pops.
    fn pops(self) -> usize {
        match self {
            Op::Const(_) | Op::Time | Op::Jump(_) => 0,
            Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Pow | Op::Atan2 | Op::Min | Op::Max => 2,
            Op::Step { .. } => 3,
            _ => 1,
        }
    }

    /// Whether it pushes a value.
    fn pushes(self) -> bool {
        !matches!(self, Op::Select(_) | Op::Jump(_))
    }

    /// Its name in messages.
    fn name(self) -> &'static str {
        match self {
            Op::Const(_) => "constant",
            Op::Time => "t",
            Op::Neg => "negation",
            Op::Add => "sum",
            Op::Sub => "difference",
            Op::Mul => "product",
            Op::Div => "division",
            Op::Pow | Op::PowC(_) => "power",
            Op::Sin => "sin",
            Op::Cos => "cos",
            Op::Tan => "tan",
            Op::Asin => "asin",
            Op::Acos => "acos",
            Op::Atan => "atan",
            Op::Atan2 => "atan2",
            Op::Sinh => "sinh",
            Op::Cosh => "cosh",
            Op::Tanh => "tanh",
            Op::Exp => "exp",
            Op::Log => "log",
            Op::Sqrt => "sqrt",
            Op::Abs => "abs",
            Op::Sign => "sign",
            Op::Min => "min",
            Op::Max => "max",
            Op::Step { .. } => "step",
            Op::Spline(_) => "spline",
            Op::Select(_) | Op::Jump(_) => "piecewise",
        }
    }
}

/// The compiled form: the tape, the text span of each operation, and the tables it refers to.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Program {
    ops: Vec<Op>,
    spans: Vec<Range<usize>>,
    splines: Vec<Spline>,
    tables: Vec<Piecewise>,
}

/// A piecewise selection: branch k starts at targets[k]; breaks are x1 < ... < xn.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Piecewise {
    breaks: Vec<f64>,
    targets: Vec<usize>,
}
