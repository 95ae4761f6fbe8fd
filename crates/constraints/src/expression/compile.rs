//! From the syntax tree to a flat program (a tape of stack operations).
//!
//! Subtrees without `t` are evaluated here, once ("constant folding"): the tape then holds only
//! time-dependent work, and the arguments that must be constants (the exponent of [`Op::PowC`],
//! step bounds, piecewise breakpoints, spline knots) are numbers. A constant that is not finite
//! (`sqrt(-1)`, `1/0`) is a parse error at its place.
//!
//! `piecewise` compiles to a selection that jumps to the active branch, so inactive branches are
//! not evaluated (a branch that is undefined where it is not used does no harm).

use super::functions::Func;
use super::jet::Jet;
use super::parser::{BinOp, Node, NodeKind};
use super::{Op, ParseError, Piecewise, Program, STACK};
use crate::spline::Spline;
use std::ops::Range;

struct Compiler {
    prog: Program,
    depth: usize,
}

/// Compiles a parsed expression.
pub(crate) fn compile(node: &Node) -> Result<Program, ParseError> {
    let mut c = Compiler::new();
    c.emit(node)?;
    Ok(c.prog)
}

impl Compiler {
    fn new() -> Self {
        Self {
            prog: Program::default(),
            depth: 0,
        }
    }

    /// Appends `op` (from the text `span`) that pops `pops` values and pushes one.
    fn push(&mut self, op: Op, span: &Range<usize>, pops: usize) -> Result<(), ParseError> {
        self.depth = self.depth + 1 - pops;
        if self.depth > STACK {
            return Err(ParseError::new(
                span.clone(),
                format!("the expression needs more than {STACK} intermediate values; simplify it"),
            ));
        }
        self.prog.ops.push(op);
        self.prog.spans.push(span.clone());
        Ok(())
    }

    fn emit(&mut self, n: &Node) -> Result<(), ParseError> {
        match n.kind {
            NodeKind::Num(x) => self.push(Op::Const(x), &n.span, 0),
            NodeKind::List(_) => Err(ParseError::new(
                n.span.clone(),
                "a list [...] is only accepted as the knots of spline(x, [x0, ...], [f0, ...])",
            )),
            _ if !n.has_time() => {
                let c = constant(n)?;
                self.push(Op::Const(c), &n.span, 0)
            }
            _ => self.emit_raw(n),
        }
    }

    fn emit_raw(&mut self, n: &Node) -> Result<(), ParseError> {
        match &n.kind {
            NodeKind::Num(x) => self.push(Op::Const(*x), &n.span, 0),
            NodeKind::Time => self.push(Op::Time, &n.span, 0),
            NodeKind::Neg(a) => {
                self.emit(a)?;
                self.push(Op::Neg, &n.span, 1)
            }
            NodeKind::Bin(BinOp::Pow, a, b) if !b.has_time() => {
                let c = constant(b)?;
                self.emit(a)?;
                self.push(Op::PowC(c), &n.span, 1)
            }
            NodeKind::Bin(op, a, b) => {
                self.emit(a)?;
                self.emit(b)?;
                let op = match op {
                    BinOp::Add => Op::Add,
                    BinOp::Sub => Op::Sub,
                    BinOp::Mul => Op::Mul,
                    BinOp::Div => Op::Div,
                    BinOp::Pow => Op::Pow,
                };
                self.push(op, &n.span, 2)
            }
            NodeKind::Call(f, args) => self.call(*f, args, &n.span),
            NodeKind::List(_) => self.emit(n),
        }
    }

    fn call(&mut self, f: Func, args: &[Node], span: &Range<usize>) -> Result<(), ParseError> {
        match f {
            Func::Step => return self.step(args, span),
            Func::Piecewise => return self.piecewise(args, span),
            Func::Spline => return self.spline(args, span),
            _ => {}
        }
        for a in args {
            self.emit(a)?;
        }
        let op = match f {
            Func::Sin => Op::Sin,
            Func::Cos => Op::Cos,
            Func::Tan => Op::Tan,
            Func::Asin => Op::Asin,
            Func::Acos => Op::Acos,
            Func::Atan => Op::Atan,
            Func::Atan2 => Op::Atan2,
            Func::Sinh => Op::Sinh,
            Func::Cosh => Op::Cosh,
            Func::Tanh => Op::Tanh,
            Func::Exp => Op::Exp,
            Func::Log => Op::Log,
            Func::Sqrt => Op::Sqrt,
            Func::Abs => Op::Abs,
            Func::Sign => Op::Sign,
            Func::Min => Op::Min,
            Func::Max => Op::Max,
            Func::Step | Func::Piecewise | Func::Spline => unreachable!("handled above"),
        };
        self.push(op, span, args.len())
    }

    /// step(x, x0, f0, x1, f1): x0 < x1 constants; x, f0, f1 any expressions.
    fn step(&mut self, a: &[Node], span: &Range<usize>) -> Result<(), ParseError> {
        let x0 = self.constant_arg(&a[1], "step", "x0")?;
        let x1 = self.constant_arg(&a[3], "step", "x1")?;
        if x1 <= x0 {
            return Err(ParseError::new(
                a[1].span.start..a[3].span.end,
                format!("step(x, x0, f0, x1, f1) needs x1 > x0, got x0 = {x0}, x1 = {x1}"),
            ));
        }
        self.emit(&a[0])?;
        self.emit(&a[2])?;
        self.emit(&a[4])?;
        self.push(Op::Step { x0, x1 }, span, 3)
    }

    /// piecewise(x, f0, x1, f1, ..., xn, fn): x, then a selection that jumps to the branch,
    /// each branch ending with a jump to the end.
    fn piecewise(&mut self, a: &[Node], span: &Range<usize>) -> Result<(), ParseError> {
        let mut breaks = Vec::new();
        for k in (2..a.len()).step_by(2) {
            let b = self.constant_arg(&a[k], "piecewise", "breakpoint")?;
            if let Some(&prev) = breaks.last() {
                if b <= prev {
                    return Err(ParseError::new(
                        a[k].span.clone(),
                        format!("piecewise breakpoints must increase: {b} follows {prev}"),
                    ));
                }
            }
            breaks.push(b);
        }
        self.emit(&a[0])?;
        let table = self.prog.tables.len();
        self.prog.tables.push(Piecewise {
            breaks,
            targets: Vec::new(),
        });
        // Select pops x and pushes nothing.
        self.push(Op::Select(table), span, 1)?;
        self.depth -= 1;
        let mut jumps = Vec::new();
        for k in (1..a.len()).step_by(2) {
            self.prog.tables[table].targets.push(self.prog.ops.len());
            self.emit(&a[k])?;
            if k + 1 < a.len() {
                jumps.push(self.prog.ops.len());
                // The branch's value stays on the stack; the next branch starts from the
                // same depth.
                self.push(Op::Jump(0), span, 0)?;
                self.depth -= 2;
            }
        }
        let end = self.prog.ops.len();
        for j in jumps {
            self.prog.ops[j] = Op::Jump(end);
        }
        Ok(())
    }

    /// spline(x, [x0, ...], [f0, ...]): the knots are constants.
    fn spline(&mut self, a: &[Node], span: &Range<usize>) -> Result<(), ParseError> {
        let knots = |n: &Node, what: &str| -> Result<Vec<f64>, ParseError> {
            match &n.kind {
                NodeKind::List(items) => items
                    .iter()
                    .map(|i| Compiler::new().constant_arg(i, "spline", what))
                    .collect(),
                _ => Err(ParseError::new(
                    n.span.clone(),
                    format!(
                        "spline(x, [x0, x1, ...], [f0, f1, ...]) needs the {what}s as a list [...]"
                    ),
                )),
            }
        };
        let xs = knots(&a[1], "knot")?;
        let fs = knots(&a[2], "value")?;
        let s = Spline::new(xs, fs)
            .map_err(|e| ParseError::new(a[1].span.start..a[2].span.end, format!("spline: {e}")))?;
        self.emit(&a[0])?;
        self.prog.splines.push(s);
        self.push(Op::Spline(self.prog.splines.len() - 1), span, 1)
    }

    /// The value of an argument that must not depend on t.
    fn constant_arg(&mut self, n: &Node, f: &str, what: &str) -> Result<f64, ParseError> {
        if n.has_time() {
            return Err(ParseError::new(
                n.span.clone(),
                format!("the {what} of {f}() must be a constant (it may not use t)"),
            ));
        }
        constant(n)
    }
}

/// The value of a subtree without t; a parse error where it is not finite.
fn constant(n: &Node) -> Result<f64, ParseError> {
    let mut c = Compiler::new();
    c.emit_raw(n)?;
    let j: Jet = c.prog.run(0.0);
    if !j.v.is_finite() {
        return Err(ParseError::new(
            n.span.clone(),
            format!(
                "this constant part evaluates to {}, not a finite number",
                j.v
            ),
        ));
    }
    Ok(j.v)
}
