//! Running a compiled program: a loop over the tape with a fixed-size stack of jets on the
//! machine stack (no allocation), and the same loop with a check after every operation that
//! finds where a result first stops being finite ([`Program::diagnose`]).

use super::jet::Jet;
use super::{Op, Program, STACK};
use std::ops::Range;

/// Where and why an expression is not finite at some time.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainError {
    /// Byte span in the expression text of the operation whose result is not finite.
    pub span: Range<usize>,
    /// What it is and its arguments, e.g. "sqrt of -1 (value NaN, rate NaN, acceleration NaN)".
    pub message: String,
}

impl Program {
    /// (f, ḟ, f̈) at t.
    pub(crate) fn run(&self, t: f64) -> Jet {
        let mut stack = [Jet::default(); STACK];
        let mut sp = 0;
        let mut pc = 0;
        while pc < self.ops.len() {
            pc = self.step(pc, t, &mut stack, &mut sp);
        }
        stack[0]
    }

    /// The first operation whose result is not finite at t, if any.
    pub(crate) fn diagnose(&self, t: f64) -> Option<DomainError> {
        let mut stack = [Jet::default(); STACK];
        let mut sp = 0;
        let mut pc = 0;
        while pc < self.ops.len() {
            let op = self.ops[pc];
            let pops = op.pops().min(sp);
            let args: Vec<Jet> = stack[sp - pops..sp].to_vec();
            let next = self.step(pc, t, &mut stack, &mut sp);
            if op.pushes() && !stack[sp - 1].is_finite() {
                return Some(DomainError {
                    span: self.spans[pc].clone(),
                    message: describe(op, &args, &stack[sp - 1]),
                });
            }
            pc = next;
        }
        None
    }

    /// Executes the operation at `pc`; returns the next pc.
    #[inline(always)]
    fn step(&self, pc: usize, t: f64, s: &mut [Jet; STACK], sp: &mut usize) -> usize {
        // The top of the stack (a) and, for binary operations, the value under it.
        macro_rules! unary {
            ($f:ident) => {
                s[*sp - 1] = s[*sp - 1].$f()
            };
        }
        macro_rules! binary {
            (|$a:ident, $b:ident| $e:expr) => {{
                *sp -= 1;
                let ($a, $b) = (s[*sp - 1], s[*sp]);
                s[*sp - 1] = $e;
            }};
        }
        match self.ops[pc] {
            Op::Const(c) => {
                s[*sp] = Jet::constant(c);
                *sp += 1;
            }
            Op::Time => {
                s[*sp] = Jet::time(t);
                *sp += 1;
            }
            Op::Neg => s[*sp - 1] = -s[*sp - 1],
            Op::Add => binary!(|a, b| a + b),
            Op::Sub => binary!(|a, b| a - b),
            Op::Mul => binary!(|a, b| a * b),
            Op::Div => binary!(|a, b| a / b),
            Op::Pow => binary!(|a, b| a.pow(b)),
            Op::PowC(c) => s[*sp - 1] = s[*sp - 1].powc(c),
            Op::Sin => unary!(sin),
            Op::Cos => unary!(cos),
            Op::Tan => unary!(tan),
            Op::Asin => unary!(asin),
            Op::Acos => unary!(acos),
            Op::Atan => unary!(atan),
            Op::Atan2 => binary!(|a, b| a.atan2(b)),
            Op::Sinh => unary!(sinh),
            Op::Cosh => unary!(cosh),
            Op::Tanh => unary!(tanh),
            Op::Exp => unary!(exp),
            Op::Log => unary!(ln),
            Op::Sqrt => unary!(sqrt),
            Op::Abs => unary!(abs),
            Op::Sign => unary!(sign),
            Op::Min => binary!(|a, b| a.min(b)),
            Op::Max => binary!(|a, b| a.max(b)),
            Op::Step { x0, x1 } => {
                *sp -= 2;
                let (x, f0, f1) = (s[*sp - 1], s[*sp], s[*sp + 1]);
                s[*sp - 1] = f0 + (f1 - f0) * smooth_step(x, x0, x1);
            }
            Op::Spline(k) => {
                let x = s[*sp - 1];
                let (f, g1, g2) = self.splines[k].eval(x.v);
                s[*sp - 1] = x.chain(f, g1, g2);
            }
            Op::Select(k) => {
                *sp -= 1;
                let table = &self.tables[k];
                let x = s[*sp].v;
                if x.is_nan() {
                    // No branch is active: the result is NaN (the last branch, made NaN).
                    s[*sp] = Jet::constant(f64::NAN);
                    *sp += 1;
                    return self.ops.len();
                }
                let branch = table.breaks.partition_point(|&b| b <= x);
                return table.targets[branch];
            }
            Op::Jump(to) => return to,
        }
        pc + 1
    }
}

/// The C² quintic step from 0 at x0 to 1 at x1 applied to the jet x: s = 10τ³ − 15τ⁴ + 6τ⁵,
/// τ = (x − x0)/(x1 − x0), ds/dx = 30τ²(1 − τ)²/h, d²s/dx² = 60τ(1 − τ)(1 − 2τ)/h²; constant
/// (0 or 1) outside (x0, x1).
fn smooth_step(x: Jet, x0: f64, x1: f64) -> Jet {
    let h = x1 - x0;
    let tau = ((x.v - x0) / h).clamp(0.0, 1.0);
    let s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    if !(x.v > x0 && x.v < x1) {
        return Jet {
            v: if x.v.is_nan() { f64::NAN } else { s },
            d1: 0.0,
            d2: 0.0,
        };
    }
    let ds = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / h;
    let dds = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (h * h);
    x.chain(s, ds, dds)
}

/// "sqrt of -1 (value NaN, rate NaN, acceleration NaN)".
fn describe(op: Op, args: &[Jet], out: &Jet) -> String {
    let vals: Vec<String> = args.iter().map(|a| format!("{}", a.v)).collect();
    let what = match (op.name(), vals.len()) {
        ("division", _) => format!("division of {} by {}", vals[0], vals[1]),
        ("power", 2) => format!("power {}^{}", vals[0], vals[1]),
        ("power", _) => format!("power of {}", vals[0]),
        (name, 0) => name.to_string(),
        (name, _) => format!("{name} of {}", vals.join(", ")),
    };
    let rate = if out.v.is_finite() {
        " (its value is finite but its derivatives are not)"
    } else {
        ""
    };
    format!(
        "{what}{rate}: value {}, rate {}, acceleration {}",
        out.v, out.d1, out.d2
    )
}
