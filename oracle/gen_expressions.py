"""Oracle for expression time functions: f, f' and f'' of text expressions in cardan's grammar.

Each case is written twice, by hand: as the text cardan parses, and as a CasADi expression built
directly from CasADi operations (no parser: nothing reads the text here). AD gives f' and f''.
Every function and operator of the grammar appears in some case (the Rust gate checks that).

Usage: python gen_expressions.py OUTDIR      (writes OUTDIR/expressions.json)
"""

import json
import math
import os
import sys

import casadi as ca

import gen_drivers

GENERATOR = "gen_expressions.py"
TIMES = [0.15, 0.7, 1.3, 2.2, 2.8]


def spline(x, x_num, ts, fs):
    """The contract's natural cubic spline (gen_drivers' own construction) at the expression x;
    the segment is picked by the numeric x."""
    return gen_drivers.time_function({"kind": "spline", "t": ts, "f": fs}, x, x_num)


def step(x, x0, f0, x1, f1):
    """The C^2 quintic step: f0 + (f1 - f0) s(tau), tau = clamp((x - x0)/(x1 - x0), 0, 1)."""
    tau = ca.fmin(ca.fmax((x - x0) / (x1 - x0), 0), 1)
    return f0 + (f1 - f0) * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)


def piecewise(x, f0, breaks_values):
    """f0 for x < x1, f_k for x_k <= x < x_(k+1), ..."""
    out = f0
    for b, f in breaks_values:
        out = ca.if_else(x >= b, f, out)
    return out


# (label, cardan text, CasADi f(t, t_num)).
CASES = [
    ("harmonic", "0.5 + 0.3*sin(2*pi*t - pi/2)",
     lambda t, n: 0.5 + 0.3 * ca.sin(2 * math.pi * t - math.pi / 2)),
    ("polynomial", "t^3 - 2*t^2 + t - 7", lambda t, n: t**3 - 2 * t**2 + t - 7),
    ("unary-minus-power", "-t^2 + -2^2*t", lambda t, n: -(t**2) + (-(2**2)) * t),
    ("power-right-assoc", "2^3^(t/2)/100", lambda t, n: 2 ** (3 ** (t / 2)) / 100),
    ("power-time-exponent", "t^t + 2^t", lambda t, n: t**t + 2**t),
    ("power-negative", "(1 + t^2)^-0.5 + (t - 3)^3", lambda t, n: (1 + t**2) ** -0.5 + (t - 3) ** 3),
    ("division-left-assoc", "8/2/t - t/(1 + t)", lambda t, n: (8 / 2) / t - t / (1 + t)),
    ("exp-cos", "1.5e-3*exp(-t/2)*cos(3*t)", lambda t, n: 1.5e-3 * ca.exp(-t / 2) * ca.cos(3 * t)),
    ("tan", "tan(t/3)", lambda t, n: ca.tan(t / 3)),
    ("asin-acos", "asin(t/4) + acos(t/5)", lambda t, n: ca.asin(t / 4) + ca.acos(t / 5)),
    ("atan", "atan(2*t - 1)", lambda t, n: ca.atan(2 * t - 1)),
    ("atan2", "atan2(sin(t) + 2, cos(3*t) - 0.5)",
     lambda t, n: ca.atan2(ca.sin(t) + 2, ca.cos(3 * t) - 0.5)),
    ("hyperbolic", "sinh(t/2) + cosh(t/3) - tanh(t - 1)",
     lambda t, n: ca.sinh(t / 2) + ca.cosh(t / 3) - ca.tanh(t - 1)),
    ("log-sqrt", "log(1 + t^2) + sqrt(2 + sin(t))", lambda t, n: ca.log(1 + t**2) + ca.sqrt(2 + ca.sin(t))),
    ("abs", "abs(sin(2*t))*t", lambda t, n: ca.fabs(ca.sin(2 * t)) * t),
    ("sign", "sign(t - 1)*t^2 + sign(cos(t))", lambda t, n: ca.sign(t - 1) * t**2 + ca.sign(ca.cos(t))),
    ("min-max", "min(t, 2 - t) + max(t^2, 1)", lambda t, n: ca.fmin(t, 2 - t) + ca.fmax(t**2, 1)),
    ("step", "step(t, 0.5, -1, 1.5, 2)", lambda t, n: step(t, 0.5, -1, 1.5, 2)),
    ("step-of-expressions", "step(sin(t), -0.5, 0, 0.5, t^2)",
     lambda t, n: step(ca.sin(t), -0.5, 0, 0.5, t**2)),
    ("piecewise", "piecewise(t, 0, 0.5, t^2, 1.2, 2 - t, 2.5, sqrt(t))",
     lambda t, n: piecewise(t, 0, [(0.5, t**2), (1.2, 2 - t), (2.5, ca.sqrt(t))])),
    ("spline", "spline(t, [0, 0.4, 1, 2], [0, 1, -0.5, 0.3])",
     lambda t, n: spline(t, n, [0, 0.4, 1, 2], [0, 1, -0.5, 0.3])),
    ("spline-of-expression", "spline(2*t - 1, [-1, 0, 0.5, 1.5, 3], [1, 0, 2, -1, 0.5])",
     lambda t, n: spline(2 * t - 1, 2 * n - 1, [-1, 0, 0.5, 1.5, 3], [1, 0, 2, -1, 0.5])),
    ("time-and-e", "time/2 + e^(t/4) - +t", lambda t, n: t / 2 + math.e ** (t / 4) - t),
]


def derivatives(build, t_num):
    """[f, f', f''] at t_num by CasADi AD."""
    t = ca.SX.sym("t")
    f = build(t, t_num)
    d1 = ca.jacobian(f, t)
    d2 = ca.jacobian(d1, t)
    out = ca.Function("f", [t], [f, d1, d2])(t_num)
    return [float(v) for v in out]


def build_cases():
    cases = []
    for label, text, build in CASES:
        for k, t in enumerate(TIMES):
            cases.append({"label": f"{label}-{k}", "text": text, "t": t, "f": derivatives(build, t)})
    return cases


def main(outdir):
    cases = build_cases()
    blocks = [json.dumps(c) for c in cases]
    text = (
        "{\n"
        '  "family": "time_function",\n'
        '  "kind": "expression",\n'
        f'  "generator": {json.dumps(GENERATOR)},\n'
        '  "cases": [\n    ' + ",\n    ".join(blocks) + "\n  ]\n}\n"
    )
    json.loads(text)
    os.makedirs(outdir, exist_ok=True)
    with open(os.path.join(outdir, "expressions.json"), "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return len(cases)


if __name__ == "__main__":
    print(main(sys.argv[1]))
