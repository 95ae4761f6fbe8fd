"""Oracle for the drivers (rotation, translation, distance, coordinate) and their time functions.
Phi is written from CONTRACT.md; f(t) is built symbolically in t so AD gives f' and f''.

Usage: python gen_drivers.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C

GENERATOR = "gen_drivers.py"
FAMILY = "driver"

# ---------------------------------------------------------------------------------------------
# Time functions: f(t) as SX, given the numeric t of the case (which picks the spline segment or
# the ramp piece; the SX expression is the one valid in a neighbourhood of that t).
# ---------------------------------------------------------------------------------------------


def natural_spline_second_derivatives(ts, fs):
    """Second derivatives M_k of the natural cubic spline (M_0 = M_n = 0): the tridiagonal system
    h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (slope_k - slope_{k-1}),
    solved by the Thomas algorithm in plain Python floats (deterministic)."""
    n = len(ts) - 1
    m = [0.0] * (n + 1)
    if n < 2:
        return m
    h = [ts[k + 1] - ts[k] for k in range(n)]
    slope = [(fs[k + 1] - fs[k]) / h[k] for k in range(n)]
    # unknowns M_1 .. M_{n-1}
    a = [h[k - 1] for k in range(1, n)]
    b = [2.0 * (h[k - 1] + h[k]) for k in range(1, n)]
    c = [h[k] for k in range(1, n)]
    d = [6.0 * (slope[k] - slope[k - 1]) for k in range(1, n)]
    for k in range(1, n - 1):
        w = a[k] / b[k - 1]
        b[k] -= w * c[k - 1]
        d[k] -= w * d[k - 1]
    x = [0.0] * (n - 1)
    x[-1] = d[-1] / b[-1]
    for k in range(n - 3, -1, -1):
        x[k] = (d[k] - c[k] * x[k + 1]) / b[k]
    m[1:n] = x
    return m


def spline_segment(ts, fs, m, k, t):
    """The cubic of segment k (t_k <= t <= t_{k+1}) as an SX expression in t."""
    h = ts[k + 1] - ts[k]
    a = ts[k + 1] - t
    b = t - ts[k]
    return (m[k] * a**3 / (6 * h) + m[k + 1] * b**3 / (6 * h)
            + (fs[k] / h - m[k] * h / 6) * a + (fs[k + 1] / h - m[k + 1] * h / 6) * b)


def time_function(spec, t, t_num):
    """f(t) as SX for a contract time function; t_num is the numeric time of the case."""
    kind = spec["kind"]
    if kind == "constant":
        return ca.SX(spec["value"]) + 0 * t
    if kind == "polynomial":
        f = ca.SX(0)
        for k, c in enumerate(spec["coefficients"]):
            f += c * t**k
        return f
    if kind == "harmonic":
        return spec["offset"] + spec["amplitude"] * ca.sin(spec["frequency"] * t + spec["phase"])
    if kind == "ramp":
        t0, t1, f0, f1 = spec["t0"], spec["t1"], spec["f0"], spec["f1"]
        if t_num < t0:
            tau = ca.SX(0) + 0 * t
        elif t_num > t1:
            tau = ca.SX(1) + 0 * t
        else:
            tau = (t - t0) / (t1 - t0)
        return f0 + (f1 - f0) * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)
    if kind == "spline":
        ts, fs = spec["t"], spec["f"]
        m = natural_spline_second_derivatives(ts, fs)
        n = len(ts) - 1
        if ts[0] <= t_num <= ts[-1]:
            k = max(j for j in range(n) if ts[j] <= t_num)
            return spline_segment(ts, fs, m, k, t)
        # Linear extrapolation with the end slope, the slope taken by AD of the end segment.
        k, tk, fk = (0, ts[0], fs[0]) if t_num < ts[0] else (n - 1, ts[-1], fs[-1])
        u = ca.SX.sym("u")
        slope_fn = ca.Function("slope", [u], [ca.jacobian(spline_segment(ts, fs, m, k, u), u)])
        slope = float(slope_fn(tk))
        return fk + slope * (t - tk)
    if kind == "expression":
        return EXPRESSIONS[spec["text"]](t, t_num)
    raise KeyError(kind)


def eval_time_function(spec, t_num):
    """Numeric f(t_num)."""
    t = ca.SX.sym("t")
    return float(ca.Function("f", [t], [time_function(spec, t, t_num)])(t_num))


KINDS = ["constant", "polynomial", "harmonic", "ramp", "spline", "expression"]
# The first cases cycle through the other kinds (so their data do not depend on the expression
# cases); the cases from FIRST_EXPRESSION_CASE on are expressions.
FIRST_EXPRESSION_CASE = 60
# Expression text -> the same function built with CasADi operations (never by parsing the text),
# called with the symbol t and the numeric time of the case (which picks a spline's segment).
EXPRESSIONS = {}
RAMP_WHERE = ["before", "inside", "after", "inside", "at-t0", "at-t1"]
SPLINE_WHERE = ["inside", "before", "after", "at-knot", "inside-2-knots", "after-2-knots"]


def make_function(rng, index, scale):
    """The time function of case number `index` (kinds cycle) and the case's time t.
    `scale` multiplies the function values (lengths for translation and distance drivers)."""
    if index >= FIRST_EXPRESSION_CASE:
        return make_expression(rng, index - FIRST_EXPRESSION_CASE, scale)
    kinds = KINDS[:-1]
    kind = kinds[index % len(kinds)]
    sub = index // len(kinds)

    def val(lo=-2.0, hi=2.0):
        return float(scale * rng.uniform(lo, hi))

    t = float(rng.uniform(-1.0, 3.0))
    if kind == "constant":
        return {"kind": "constant", "value": val()}, t, "constant"
    if kind == "polynomial":
        ncoef = 1 + sub % 5
        coeffs = [val(-1.5, 1.5) for _ in range(ncoef)]
        return {"kind": "polynomial", "coefficients": coeffs}, t, f"polynomial-deg{ncoef - 1}"
    if kind == "harmonic":
        spec = {"kind": "harmonic", "amplitude": val(0.2, 2.0), "frequency": float(rng.uniform(0.5, 5.0)),
                "phase": float(rng.uniform(-math.pi, math.pi)), "offset": val(-1.0, 1.0)}
        return spec, t, "harmonic"
    if kind == "ramp":
        t0 = float(rng.uniform(0.0, 1.0))
        t1 = t0 + float(rng.uniform(0.3, 1.5))
        spec = {"kind": "ramp", "t0": t0, "t1": t1, "f0": val(), "f1": val()}
        where = RAMP_WHERE[sub % len(RAMP_WHERE)]
        t = {"before": t0 - float(rng.uniform(0.05, 1.0)),
             "inside": t0 + (t1 - t0) * float(rng.uniform(0.05, 0.95)),
             "after": t1 + float(rng.uniform(0.05, 1.0)),
             "at-t0": t0, "at-t1": t1}[where]
        return spec, t, f"ramp-{where}"
    where = SPLINE_WHERE[sub % len(SPLINE_WHERE)]
    nknots = 2 if where.endswith("2-knots") else int(rng.integers(3, 8))
    ts = np.cumsum(rng.uniform(0.2, 1.0, nknots)) - 0.5
    ts = [float(x) for x in ts]
    fs = [val() for _ in range(nknots)]
    if where.startswith("inside"):
        t = float(rng.uniform(ts[0], ts[-1]))
    elif where == "before":
        t = ts[0] - float(rng.uniform(0.05, 1.0))
    elif where.startswith("after"):
        t = ts[-1] + float(rng.uniform(0.05, 1.0))
    else:  # an interior knot
        t = ts[int(rng.integers(1, nknots - 1))]
    return {"kind": "spline", "t": ts, "f": fs}, t, f"spline-{where}"


def expression(text, build):
    """An expression spec: the text for cardan and its CasADi twin, registered by text."""
    EXPRESSIONS[text] = build
    return {"kind": "expression", "text": text}


EXPRESSION_FORMS = ["harmonic", "damped", "step", "piecewise", "spline"]


def make_expression(rng, sub, scale):
    """Expression number `sub`: a form (cycling) with random parameters, written as cardan text
    (floats by repr, which round-trips) and as the same CasADi expression."""
    form = EXPRESSION_FORMS[sub % len(EXPRESSION_FORMS)]
    a, b, c = (float(scale * rng.uniform(-2.0, 2.0)) for _ in range(3))
    w, k = float(rng.uniform(0.5, 5.0)), float(rng.uniform(0.1, 1.0))
    t = float(rng.uniform(-1.0, 3.0))
    if form == "harmonic":
        spec = expression(f"{b!r} + {a!r}*sin({w!r}*t + {k!r})",
                          lambda x, tn: b + a * ca.sin(w * x + k))
    elif form == "damped":
        spec = expression(f"{a!r}*exp(-{k!r}*t)*cos({w!r}*t) + {b!r}*t^2 - {c!r}*tanh(t)",
                          lambda x, tn: a * ca.exp(-(k * x)) * ca.cos(w * x) + b * x**2 - c * ca.tanh(x))
    elif form == "step":
        t0, t1 = k, k + float(rng.uniform(0.3, 1.5))
        spec = expression(f"step(t, {t0!r}, {a!r}, {t1!r}, {b!r}) + {c!r}*atan(t/{w!r})",
                          lambda x, tn: _step(x, t0, a, t1, b) + c * ca.atan(x / w))
    elif form == "piecewise":
        t1, t2 = k - 0.5, k + 1.0
        spec = expression(
            f"piecewise(t, {a!r}*t, {t1!r}, {b!r}*sqrt(1 + t^2), {t2!r}, {c!r}*cos({w!r}*t))",
            lambda x, tn: ca.if_else(x >= t2, c * ca.cos(w * x),
                                 ca.if_else(x >= t1, b * ca.sqrt(1 + x**2), a * x)))
    else:
        ts = [-1.0, -0.2, 0.5, 1.1, 2.0]
        fs = [float(scale * rng.uniform(-2.0, 2.0)) for _ in ts]
        knots = ", ".join(repr(x) for x in ts)
        values = ", ".join(repr(x) for x in fs)
        spec = expression(f"spline(t, [{knots}], [{values}]) + {a!r}*abs(t - 2.5)",
                          lambda x, tn: time_function({"kind": "spline", "t": ts, "f": fs}, x, tn)
                          + a * ca.fabs(x - 2.5))
    return spec, t, f"expression-{form}"


def _step(x, x0, f0, x1, f1):
    tau = ca.fmin(ca.fmax((x - x0) / (x1 - x0), 0), 1)
    return f0 + (f1 - f0) * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)


def shift_function(spec, delta):
    """Add a constant to a time function (used to place a case on the solution)."""
    kind = spec["kind"]
    if kind == "constant":
        spec["value"] += delta
    elif kind == "polynomial":
        spec["coefficients"][0] += delta
    elif kind == "harmonic":
        spec["offset"] += delta
    elif kind == "ramp":
        spec["f0"] += delta
        spec["f1"] += delta
    elif kind == "expression":
        old = EXPRESSIONS[spec["text"]]
        spec["text"] = f"({spec['text']}) + {delta!r}"
        EXPRESSIONS[spec["text"]] = lambda x, tn: old(x, tn) + delta
    else:
        spec["f"] = [x + delta for x in spec["f"]]


# ---------------------------------------------------------------------------------------------
# Phi of each driver
# ---------------------------------------------------------------------------------------------


def phi_rotation(bi, bj, t, P, t_num):
    mi, mj = P["marker_i"], P["marker_j"]
    xi, yi = bi.vector(mi["x"]), bi.vector(mi["y"])
    xj = bj.vector(mj["x"])
    f = time_function(P["function"], t, t_num)
    return ca.cos(f) * ca.dot(yi, xj) - ca.sin(f) * ca.dot(xi, xj)


def phi_translation(bi, bj, t, P, t_num):
    mi, mj = P["marker_i"], P["marker_j"]
    d = bj.point(mj["point"]) - bi.point(mi["point"])
    return ca.dot(bi.vector(mi["z"]), d) - time_function(P["function"], t, t_num)


def phi_distance(bi, bj, t, P, t_num):
    d = bj.point(P["point_j"]) - bi.point(P["point_i"])
    f = time_function(P["function"], t, t_num)
    return ca.dot(d, d) - f**2


def phi_coordinate(bi, bj, t, P, t_num):
    return bi.point(P["point_i"])[P["axis"]] - time_function(P["function"], t, t_num)


# Geometric value g of each driver at a case (numeric): the function value that makes Phi = 0.


def _globals(case):
    ai, aj = C.a_num(case["q_i"][3:]), C.a_num(case["q_j"][3:])
    return ai, aj, np.array(case["q_i"][:3]), np.array(case["q_j"][:3])


def target_rotation(case):
    P = case["params"]
    ai, aj, _, _ = _globals(case)
    xi, yi = ai @ np.array(P["marker_i"]["x"]), ai @ np.array(P["marker_i"]["y"])
    xj = aj @ np.array(P["marker_j"]["x"])
    return math.atan2(float(yi @ xj), float(xi @ xj))


def target_translation(case):
    P = case["params"]
    ai, aj, ri, rj = _globals(case)
    d = rj + aj @ np.array(P["marker_j"]["point"]) - ri - ai @ np.array(P["marker_i"]["point"])
    return float((ai @ np.array(P["marker_i"]["z"])) @ d)


def target_distance(case):
    P = case["params"]
    ai, aj, ri, rj = _globals(case)
    d = rj + aj @ np.array(P["point_j"]) - ri - ai @ np.array(P["point_i"])
    return float(np.linalg.norm(d))


def target_coordinate(case):
    P = case["params"]
    ai, _, ri, _ = _globals(case)
    return float((ri + ai @ np.array(P["point_i"]))[P["axis"]])


def pr_rotation(rng, entry):
    return {"marker_i": C.marker(rng, entry, 0), "marker_j": C.marker(rng, entry, 1)}


def pr_points(rng, entry):
    mi, mj = C.marker(rng, entry, 0), C.marker(rng, entry, 1)
    return {"point_i": mi["point"], "point_j": mj["point"]}


def pr_coordinate(rng, entry):
    axis = entry["axis"] if entry["axis"] is not None else int(rng.integers(0, 3))
    return {"point_i": C.marker(rng, entry, 0)["point"], "axis": axis}


# name: (Phi, params, target, grounds, function values scale with lengths)
ELEMENTS = {
    "rotation_driver": (phi_rotation, pr_rotation, target_rotation, ("none", "i", "j"), False),
    "translation_driver": (phi_translation, pr_rotation, target_translation, ("none", "i", "j"), True),
    "distance_driver": (phi_distance, pr_points, target_distance, ("none", "i", "j"), True),
    "coordinate_driver": (phi_coordinate, pr_coordinate, target_coordinate, ("j",), True),
}

# More cases than the minimum so that every kind, and every ramp and spline placement, recurs.
N_DRIVER_CASES = 72


def build_cases(name):
    phi, make_params, target, grounds, scaled = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    for index, entry in enumerate(C.case_plan(grounds=grounds, n_total=N_DRIVER_CASES)):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        params = make_params(rng, entry)
        spec, t, what = make_function(rng, index, entry["scale"] if scaled else 1.0)
        params["function"] = spec
        case = C.new_case(f"{entry['label']}.{what}", entry["ground"], t, params, si, sj)
        if entry["solve"]:
            shift_function(spec, target(case) - eval_time_function(spec, t))
        cases.append(C.evaluate(lambda bi, bj, tt: phi(bi, bj, tt, params, t), case))
    return 1, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
