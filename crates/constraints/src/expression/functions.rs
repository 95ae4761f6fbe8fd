//! The names an expression may use: variables, constants and functions with their arities.

/// A built-in function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Func {
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
    Step,
    Piecewise,
    Spline,
}

/// How many arguments a function takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Arity {
    /// Exactly n.
    Exactly(usize),
    /// piecewise: x, f0, then (breakpoint, value) pairs: an even count ≥ 4.
    Piecewise,
}

/// (name, function, arity, signature shown in messages).
const FUNCTIONS: [(&str, Func, Arity, &str); 20] = [
    ("sin", Func::Sin, Arity::Exactly(1), "sin(x)"),
    ("cos", Func::Cos, Arity::Exactly(1), "cos(x)"),
    ("tan", Func::Tan, Arity::Exactly(1), "tan(x)"),
    ("asin", Func::Asin, Arity::Exactly(1), "asin(x)"),
    ("acos", Func::Acos, Arity::Exactly(1), "acos(x)"),
    ("atan", Func::Atan, Arity::Exactly(1), "atan(x)"),
    ("atan2", Func::Atan2, Arity::Exactly(2), "atan2(y, x)"),
    ("sinh", Func::Sinh, Arity::Exactly(1), "sinh(x)"),
    ("cosh", Func::Cosh, Arity::Exactly(1), "cosh(x)"),
    ("tanh", Func::Tanh, Arity::Exactly(1), "tanh(x)"),
    ("exp", Func::Exp, Arity::Exactly(1), "exp(x)"),
    ("log", Func::Log, Arity::Exactly(1), "log(x)"),
    ("sqrt", Func::Sqrt, Arity::Exactly(1), "sqrt(x)"),
    ("abs", Func::Abs, Arity::Exactly(1), "abs(x)"),
    ("sign", Func::Sign, Arity::Exactly(1), "sign(x)"),
    ("min", Func::Min, Arity::Exactly(2), "min(a, b)"),
    ("max", Func::Max, Arity::Exactly(2), "max(a, b)"),
    (
        "step",
        Func::Step,
        Arity::Exactly(5),
        "step(x, x0, f0, x1, f1)",
    ),
    (
        "piecewise",
        Func::Piecewise,
        Arity::Piecewise,
        "piecewise(x, f0, x1, f1, ..., xn, fn)",
    ),
    (
        "spline",
        Func::Spline,
        Arity::Exactly(3),
        "spline(x, [x0, x1, ...], [f0, f1, ...])",
    ),
];

/// Names that are not functions: the time and the constants.
pub(crate) const VARIABLES: [&str; 4] = ["t", "time", "pi", "e"];

impl Func {
    /// The function called `name`.
    pub(crate) fn from_name(name: &str) -> Option<Func> {
        FUNCTIONS.iter().find(|f| f.0 == name).map(|f| f.1)
    }

    fn entry(self) -> &'static (&'static str, Func, Arity, &'static str) {
        FUNCTIONS
            .iter()
            .find(|f| f.1 == self)
            .expect("every Func has an entry")
    }

    /// Its name.
    pub(crate) fn name(self) -> &'static str {
        self.entry().0
    }

    /// Its arity.
    pub(crate) fn arity(self) -> Arity {
        self.entry().2
    }

    /// Its signature, e.g. "atan2(y, x)".
    pub(crate) fn signature(self) -> &'static str {
        self.entry().3
    }
}

/// Every name an expression accepts (for suggestions): variables, constants, functions.
pub fn names() -> impl Iterator<Item = &'static str> + Clone {
    VARIABLES
        .iter()
        .copied()
        .chain(FUNCTIONS.iter().map(|f| f.0))
}
