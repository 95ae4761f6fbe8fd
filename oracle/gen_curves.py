"""Oracle for the curve elements: a point of body j that follows a curve c(u) fixed in body i,
the curve parameter u being an extra coordinate of the system (CONTRACT.md, "Curves"):

    Phi(q_i, q_j, u, t) = r_j + A_j sp_j - (r_i + A_i c(u))      (3 rows, no time dependence)

One element per curve kind: point_on_curve_line, _circle, _helix, _cubic, _cubic_closed.
c(u) is built as an SX expression of the symbolic u; common.derive (with one extra coordinate)
differentiates Phi, so phi_u and the u-terms of gamma# come from AD as everything else.

The cubic spline's knot second derivatives M_k are solved here with numpy (a dense solve: the
oracle's own implementation). The segment (or the linear extension of an open spline, or the
period count of a closed one) is picked numerically at the case's u, a constant of the case as
the continued angles of gen_couplers.py are; c is then the SX polynomial of that segment.

Usage: python gen_curves.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C
import gen_drivers as D

GENERATOR = "gen_curves.py"
FAMILY = "curve"

TWO_PI = 2.0 * math.pi

# ---------------------------------------------------------------------------------------------
# Curves: c(u) as SX (u symbolic, u_num the case's value, which picks the piece)
# ---------------------------------------------------------------------------------------------


def cubic_knots(points):
    """Chord-length knots u_0 = 0, u_k = u_{k-1} + |P_k - P_{k-1}|."""
    pts = np.array(points, dtype=float)
    knots = [0.0]
    for k in range(1, len(pts)):
        knots.append(knots[-1] + float(np.linalg.norm(pts[k] - pts[k - 1])))
    return knots


def cubic_second_derivatives(points, knots, closed):
    """Knot second derivatives M_k (rows, 3-vectors) of the interpolating cubic spline:
    h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (D_k - D_{k-1}),
    D_k = (P_{k+1} - P_k) / h_k, at the interior knots with M_0 = M_n = 0 (open, natural), or at
    every k = 0..n-1 taken cyclically with M_n = M_0 (closed, periodic). Dense numpy solve."""
    pts = np.array(points, dtype=float)
    n = len(pts) - 1
    h = [knots[k + 1] - knots[k] for k in range(n)]
    delta = [(pts[k + 1] - pts[k]) / h[k] for k in range(n)]
    m = np.zeros((n + 1, 3))
    if not closed:
        if n < 2:
            return m
        a = np.zeros((n - 1, n - 1))
        b = np.zeros((n - 1, 3))
        for k in range(1, n):
            r = k - 1
            a[r, r] = 2.0 * (h[k - 1] + h[k])
            if k - 1 >= 1:
                a[r, r - 1] = h[k - 1]
            if k + 1 <= n - 1:
                a[r, r + 1] = h[k]
            b[r] = 6.0 * (delta[k] - delta[k - 1])
        m[1:n] = np.linalg.solve(a, b)
        return m
    a = np.zeros((n, n))
    b = np.zeros((n, 3))
    for k in range(n):
        km, kp = (k - 1) % n, (k + 1) % n
        a[k, km] += h[km]
        a[k, k] += 2.0 * (h[km] + h[k])
        a[k, kp] += h[k]
        b[k] = 6.0 * (delta[k] - delta[km])
    sol = np.linalg.solve(a, b)
    m[0:n] = sol
    m[n] = sol[0]
    return m


def cubic_segment(pts, m, knots, k, u):
    """The contract's cubic of segment k (u_k <= u <= u_{k+1}) as an SX column in u."""
    h = knots[k + 1] - knots[k]
    a = knots[k + 1] - u
    b = u - knots[k]
    rows = []
    for d in range(3):
        rows.append(m[k][d] * a**3 / (6 * h) + m[k + 1][d] * b**3 / (6 * h)
                    + (pts[k][d] - m[k][d] * h * h / 6) * a / h
                    + (pts[k + 1][d] - m[k + 1][d] * h * h / 6) * b / h)
    return ca.vertcat(*rows)


def _segment_at(knots, n, w):
    """Index k of the segment holding w (the last one starting at or before w; 0 below u_0)."""
    ks = [j for j in range(n) if knots[j] <= w]
    return max(ks) if ks else 0


def _end_tangent(pts, m, knots, k, at):
    """c'(at) of segment k, by AD of its cubic (numeric 3-vector)."""
    s = ca.SX.sym("s")
    f = ca.Function("tangent", [s], [ca.jacobian(cubic_segment(pts, m, knots, k, s), s)])
    return np.array(f(at).full(), dtype=float).ravel()


def quintic_coefficients(pts, knots, closed):
    """The quintic spline's power-basis coefficients per segment, c(t) = sum_j C[k][j] t^j
    (t = u - u_k), solved here as one dense system on all 6n coefficients (our own formulation,
    not the Rust side's knot derivatives): interpolation at both ends of every segment,
    continuity of the first to fourth derivatives at the interior knots (every knot of a closed
    curve, cyclically), and the natural ends (third and fourth derivatives 0) of an open one."""
    n = len(pts) - 1
    h = [knots[k + 1] - knots[k] for k in range(n)]
    dim = 6 * n
    a = np.zeros((dim, dim))
    b = np.zeros((dim, 3))

    def deriv_row(k, t, d):
        """The coefficients' weights in the d-th derivative of segment k at local t."""
        row = np.zeros(dim)
        for j in range(d, 6):
            row[6 * k + j] = math.factorial(j) / math.factorial(j - d) * t ** (j - d)
        return row

    r = 0
    for k in range(n):
        a[r] = deriv_row(k, 0.0, 0)
        b[r] = pts[k]
        a[r + 1] = deriv_row(k, h[k], 0)
        b[r + 1] = pts[k + 1]
        r += 2
    joins = [(k - 1, k) for k in range(1, n)] + ([(n - 1, 0)] if closed else [])
    for left, right in joins:
        for d in range(1, 5):
            a[r] = deriv_row(left, h[left], d) - deriv_row(right, 0.0, d)
            r += 1
    if not closed:
        for k, t in ((0, 0.0), (n - 1, h[n - 1])):
            for d in (3, 4):
                a[r] = deriv_row(k, t, d)
                r += 1
    assert r == dim
    x = np.linalg.solve(a, b)
    return [x[6 * k:6 * k + 6].tolist() for k in range(n)]


def quintic_segment(coef, t):
    """sum_j coef[j] t^j as SX (t symbolic)."""
    c = 0
    for j in range(6):
        c = c + (t ** j) * C.const(coef[j])
    return c


def quintic_point(curve, u, u_num):
    """c(u) of a quintic spline as SX: the segment holding the case's u (a closed curve's period
    count a constant of the case), beyond an open one's ends the end's quadratic Taylor
    polynomial (CONTRACT.md, "Curves")."""
    pts = [list(map(float, p)) for p in curve["points"]]
    closed = bool(curve["closed"])
    knots = cubic_knots(pts)
    coef = quintic_coefficients(pts, knots, closed)
    n = len(pts) - 1
    if closed:
        period = knots[n]
        turns = math.floor(u_num / period)
        w_num = u_num - period * turns
        k = _segment_at(knots, n, w_num)
        return quintic_segment(coef[k], u - period * turns - knots[k])
    if u_num < knots[0] or u_num > knots[n]:
        before = u_num < knots[0]
        k, at = (0, 0.0) if before else (n - 1, knots[n] - knots[n - 1])
        cf = np.array(coef[k])
        value = sum(cf[j] * at ** j for j in range(6))
        slope = sum(j * cf[j] * at ** (j - 1) for j in range(1, 6))
        curv = sum(j * (j - 1) * cf[j] * at ** (j - 2) for j in range(2, 6))
        d = u - (knots[0] if before else knots[n])
        return (C.const(value.tolist()) + d * C.const(slope.tolist())
                + 0.5 * d * d * C.const(curv.tolist()))
    k = _segment_at(knots, n, u_num)
    return quintic_segment(coef[k], u - knots[k])


def curve_point(curve, u, u_num):
    """c(u) as an SX column (curve coordinates: body i's, or global for ground i)."""
    kind = curve["kind"]
    if kind == "line":
        return C.const(curve["origin"]) + u * C.const(curve["direction"])
    if kind == "circle":
        r = curve["radius"]
        th = u / r
        return C.const(curve["center"]) + r * (ca.cos(th) * C.const(curve["x"])
                                               + ca.sin(th) * C.const(curve["y"]))
    if kind == "helix":
        r, pitch = curve["radius"], curve["pitch"]
        k = math.sqrt(r * r + (pitch / TWO_PI) ** 2)
        ph = u / k
        return (C.const(curve["center"]) + r * ca.cos(ph) * C.const(curve["x"])
                + r * ca.sin(ph) * C.const(curve["y"])
                + (pitch * ph / TWO_PI) * C.const(curve["z"]))
    if kind == "quintic":
        return quintic_point(curve, u, u_num)
    if kind == "cubic":
        pts = [list(map(float, p)) for p in curve["points"]]
        closed = bool(curve["closed"])
        knots = cubic_knots(pts)
        m = cubic_second_derivatives(pts, knots, closed).tolist()
        n = len(pts) - 1
        if closed:
            # c(u) = c(u - L floor(u / L)): the period count is a constant of the case.
            period = knots[n]
            turns = math.floor(u_num / period)
            w_num = u_num - period * turns
            return cubic_segment(pts, m, knots, _segment_at(knots, n, w_num), u - period * turns)
        if u_num < knots[0]:
            return C.const(pts[0]) + u * C.const(_end_tangent(pts, m, knots, 0, knots[0]))
        if u_num > knots[n]:
            slope = _end_tangent(pts, m, knots, n - 1, knots[n])
            return C.const(pts[n]) + (u - knots[n]) * C.const(slope)
        return cubic_segment(pts, m, knots, _segment_at(knots, n, u_num), u)
    raise KeyError(kind)


def phi_curve(bi, bj, t, u, P, u_num):
    """Phi = r_j + A_j sp_j - (r_i + A_i c(u))."""
    c = curve_point(P["curve"], u[0], u_num)
    return bj.point(P["sp_j"]) - (bi.r + ca.mtimes(bi.a, c)) + 0 * t


# ---------------------------------------------------------------------------------------------
# Parameters and the placement of u
# ---------------------------------------------------------------------------------------------


def _axis_vec(axis, length):
    e = [0.0, 0.0, 0.0]
    e[axis % 3] = float(length)
    return e


def _frame(rng, entry):
    if entry["axis"] is not None:
        x, y, z = C.AXIS_FRAMES[entry["axis"] % len(C.AXIS_FRAMES)]
        return list(x), list(y), list(z)
    return C.random_frame(rng)


def _center(rng, entry):
    s = entry["scale"]
    if entry["axis"] is not None:
        return _axis_vec(entry["axis"] + 1, 0.5 * s)
    return (s * rng.uniform(-1.0, 1.0, 3)).tolist()


def _points(rng, entry, closed):
    """4 to 8 points in a box of size 2 (times the scale), consecutive ones (and, closed, the last
    and the first) at least 0.2 apart; axis-aligned cases use a grid of step 0.5."""
    s = entry["scale"]
    n = int(rng.integers(4, 9))

    def draw():
        if entry["axis"] is not None:
            return 0.5 * s * rng.integers(-2, 3, 3).astype(float)
        return s * rng.uniform(-1.0, 1.0, 3)

    def far(a, b):
        return float(np.linalg.norm(a - b)) >= 0.2 * s

    pts = [draw()]
    while len(pts) < n:
        p = draw()
        last = len(pts) == n - 1
        if far(p, pts[-1]) and (not (closed and last) or far(p, pts[0])):
            pts.append(p)
    pts = [[float(x) for x in p] for p in pts]
    if closed:
        pts.append(list(pts[0]))  # P_n = P_0 exactly
    return pts


def make_curve(kind, closed, rng, entry):
    s = entry["scale"]
    if kind == "line":
        if entry["axis"] is not None:
            direction = _axis_vec(entry["axis"], 1.0)
        else:
            direction = C.unit(rng.standard_normal(3))
        return {"kind": "line", "origin": _center(rng, entry), "direction": direction}
    if kind == "circle":
        x, y, _ = _frame(rng, entry)
        return {"kind": "circle", "center": _center(rng, entry), "x": x, "y": y,
                "radius": float(s * rng.uniform(0.3, 2.0))}
    if kind == "helix":
        x, y, z = _frame(rng, entry)
        pitch = float(s * rng.uniform(0.2, 2.0) * rng.choice([-1.0, 1.0]))
        return {"kind": "helix", "center": _center(rng, entry), "x": x, "y": y, "z": z,
                "radius": float(s * rng.uniform(0.3, 2.0)), "pitch": pitch}
    if kind == "quintic":
        return {"kind": "quintic", "points": _points(rng, entry, closed), "closed": closed}
    return {"kind": "cubic", "points": _points(rng, entry, closed), "closed": closed}


def make_sp_j(rng, entry):
    s = entry["scale"]
    if entry["axis"] is not None:
        return _axis_vec(entry["axis"] + 2, 0.5 * s)
    return (s * rng.uniform(-1.0, 1.0, 3)).tolist()


# Where u is put, cycled over the cases of an element (the label ends with it).
PLACEMENTS = {
    "line": ["near", "far-plus", "far-minus"],
    "circle": ["near", "far-plus", "far-minus"],
    "helix": ["near", "far-plus", "far-minus"],
    "cubic": ["inside", "knot", "before", "after"],
    "cubic_closed": ["inside", "knot", "beyond", "negative", "seam"],
}


def draw_u(curve, placement, rng, scale):
    """u for a placement: line, circle, helix: |u| within about half a turn (3 for a line)
    ("near") or well beyond a turn, |u| > 2 pi R for a circle ("far-*"); open cubic: inside
    [0, u_n], exactly at an interior knot, or on the linear extensions; closed cubic: inside the
    first period, at an interior knot, beyond the period, negative, or exactly at a multiple of
    the period (the seam P_0)."""
    kind = curve["kind"]
    if kind in ("line", "circle", "helix"):
        if kind == "line":
            unit = scale
        elif kind == "circle":
            unit = curve["radius"]
        else:
            unit = math.sqrt(curve["radius"] ** 2 + (curve["pitch"] / TWO_PI) ** 2)
        if placement == "near":
            return float(unit * rng.uniform(-3.0, 3.0))
        sign = 1.0 if placement == "far-plus" else -1.0
        return float(sign * unit * rng.uniform(TWO_PI + 0.1, 25.0))
    knots = cubic_knots(curve["points"])
    n = len(knots) - 1
    length = knots[n]
    if placement == "inside":
        return float(rng.uniform(0.0, length))
    if placement == "knot":
        return float(knots[int(rng.integers(1, n))])
    if placement == "before":
        return float(-length * rng.uniform(0.02, 0.5))
    if placement == "after":
        return float(length * (1.0 + rng.uniform(0.02, 0.5)))
    if placement == "beyond":
        return float(length * rng.uniform(1.02, 4.0))
    if placement == "negative":
        return float(-length * rng.uniform(0.02, 3.0))
    if placement == "seam":
        return float(length * int(rng.choice([-1, 0, 1, 2])))
    raise KeyError(placement)


# ---------------------------------------------------------------------------------------------
# Elements and cases
# ---------------------------------------------------------------------------------------------

# name: (curve kind, closed, placement set)
ELEMENTS = {
    "point_on_curve_line": ("line", False, "line"),
    "point_on_curve_circle": ("circle", False, "circle"),
    "point_on_curve_helix": ("helix", False, "helix"),
    "point_on_curve_cubic": ("cubic", False, "cubic"),
    "point_on_curve_cubic_closed": ("cubic", True, "cubic_closed"),
    "point_on_curve_quintic": ("quintic", False, "cubic"),
    "point_on_curve_quintic_closed": ("quintic", True, "cubic_closed"),
    # Phi = u - f(t): build_path_driver_cases.
    "path_driver": None,
}
PATH_DRIVER = "path_driver"

N_CASES = 60  # every placement cycle (3, 4, 5) recurs evenly

# Cam pairs (CONTRACT.md, "Curves"): curve_on_curve_<i>_<j> for every pair of planar kinds,
# u on curve i and w on curve j the two extra coordinates.
PLANAR = {"line": ("line", False), "circle": ("circle", False), "cubic": ("cubic", False),
          "cubic_closed": ("cubic", True), "quintic": ("quintic", False),
          "quintic_closed": ("quintic", True)}
CAMS = {f"curve_on_curve_{a}_{b}": (a, b) for a in PLANAR for b in PLANAR}
N_CAM_CASES = 50

# Path drivers along a spline's arc length (CONTRACT.md, "Curves"): Phi = S(u) - f(t).
ARC_DRIVERS = {"path_driver_arc_cubic": False, "path_driver_arc_cubic_closed": True}
ELEMENTS.update(dict.fromkeys(ARC_DRIVERS))  # built by build_arc_driver_cases
# Gauss-Legendre rules: 20 points for the reference lengths (on 64 pieces of every knot span),
# 8 for the symbolic stretch from the case's u.
GL20 = np.polynomial.legendre.leggauss(20)
GL8 = np.polynomial.legendre.leggauss(8)
# Not at a spline's knots or seam: the tangency row's gamma# holds c''' (the third
# derivative), which jumps there, so a knot computed one ulp apart on either side picks another
# one-sided value (point_on_curve_* covers the evaluation at knots).
CAM_PLACEMENTS = {"line": PLACEMENTS["line"], "circle": PLACEMENTS["circle"],
                  "cubic": ["inside", "before", "after"],
                  "cubic_closed": ["inside", "beyond", "negative"],
                  "quintic": ["inside", "before", "after"],
                  "quintic_closed": ["inside", "beyond", "negative"]}
ELEMENTS.update(dict.fromkeys(CAMS))  # built by build_cam_cases

# Extra configurations on the solution (with the plan's five, about a third of the cases).
EXTRA_SOLVED = [
    {"label": f"at-solution-{k}", "ground": ("none", "none", "i", "none", "j")[k % 5],
     "solve": True}
    for k in range(5, 20)
]


def _phi_of(params, u_num):
    return lambda bi, bj, tt, uu: phi_curve(bi, bj, tt, uu, params, u_num)


def solve_sp_j(case):
    """Put P_j on the curve: sp_j = A_j^T (r_i + A_i c(u) - r_j) (normalized bodies)."""
    params = case["params"]
    params["sp_j"] = [0.0, 0.0, 0.0]
    off = C.evaluate(_phi_of(params, case["u"][0]), dict(case))["phi"]  # r_j - r_i - A_i c(u)
    aj = C.a_num(case["q_j"][3:])
    params["sp_j"] = (-(aj.T @ np.array(off))).tolist()


def build_cases(name):
    """(rows, cases) of element `name` (generate.py calls this for each entry of ELEMENTS)."""
    if name == PATH_DRIVER:
        return build_path_driver_cases()
    if name in ARC_DRIVERS:
        return build_arc_driver_cases(name)
    if name in CAMS:
        return build_cam_cases(name)
    return build_curve_cases(name)


def curve_tangent(curve, u, u_num):
    """c'(u) = dc/du by AD on a symbol of its own, then evaluated at the expression u (which
    derive moves in time, so it is not a symbol)."""
    s = ca.SX.sym("s")
    return ca.substitute(ca.jacobian(curve_point(curve, s, u_num), s), s, u)


def phi_cam(bi, bj, t, u, P, u_num, w_num):
    """Phi = [r_j + A_j c_j(w) - r_i - A_i c_i(u); (A_i (k x c_i'(u)))^T (A_j c_j'(w))]."""
    ci = curve_point(P["curve_i"], u[0], u_num)
    cj = curve_point(P["curve_j"], u[1], w_num)
    ti = curve_tangent(P["curve_i"], u[0], u_num)
    tj = curve_tangent(P["curve_j"], u[1], w_num)
    d = (bj.r + ca.mtimes(bj.a, cj)) - (bi.r + ca.mtimes(bi.a, ci))
    n = ca.mtimes(bi.a, ca.cross(C.const(P["normal_i"]), ti))
    return ca.vertcat(d, ca.dot(n, ca.mtimes(bj.a, tj))) + 0 * t


def build_cam_cases(name):
    """Two planar curves in tangent contact, u and w random on each (the placements of its kind
    but a spline's knots and seam, CAM_PLACEMENTS, cycled), the plane normal a random unit vector (the equations do not need the curves in
    its plane), u-dot and w-dot random. Not put on the solution: the gate compares derivatives,
    which hold anywhere."""
    kind_i, kind_j = CAMS[name]
    rng = C.element_rng(name)
    cases = []
    for index, entry in enumerate(C.case_plan(n_total=N_CAM_CASES)):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        t = float(rng.uniform(0.0, 2.0))
        ci = make_curve(PLANAR[kind_i][0], PLANAR[kind_i][1], rng, entry)
        cj = make_curve(PLANAR[kind_j][0], PLANAR[kind_j][1], rng, entry)
        pi, pj = CAM_PLACEMENTS[kind_i], CAM_PLACEMENTS[kind_j]
        u = draw_u(ci, pi[index % len(pi)], rng, entry["scale"])
        w = draw_u(cj, pj[(index // len(pi)) % len(pj)], rng, entry["scale"])
        params = {"curve_i": ci, "normal_i": C.unit(rng.standard_normal(3)), "curve_j": cj}
        label = f"{entry['label']}.u-{pi[index % len(pi)]}.w-{pj[(index // len(pi)) % len(pj)]}"
        case = C.new_case(label, entry["ground"], t, params, si, sj)
        case["u"] = [u, w]
        case["udot"] = [float(entry["scale"] * rng.uniform(-2.0, 2.0)) for _ in range(2)]

        def phi(bi, bj, tt, uu, params=params, u=u, w=w):
            return phi_cam(bi, bj, tt, uu, params, u, w)

        cases.append(C.evaluate(phi, case))
    return 4, cases


def build_curve_cases(name):
    kind, closed, pset = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    plan = C.case_plan(n_total=N_CASES, extra=EXTRA_SOLVED)
    for index, entry in enumerate(plan):
        placement = PLACEMENTS[pset][index % len(PLACEMENTS[pset])]
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        t = float(rng.uniform(0.0, 2.0))
        curve = make_curve(kind, closed, rng, entry)
        params = {"curve": curve, "sp_j": make_sp_j(rng, entry)}
        u = draw_u(curve, placement, rng, entry["scale"])
        udot = float(entry["scale"] * rng.uniform(-2.0, 2.0))
        case = C.new_case(f"{entry['label']}.u-{placement}", entry["ground"], t, params, si, sj)
        case["u"] = [u]
        case["udot"] = [udot]
        if entry["solve"]:
            assert case["normalized"], case["label"]
            solve_sp_j(case)
        cases.append(C.evaluate(_phi_of(params, u), case))
    return 3, cases


def _reference_length(curve, a, b):
    """Integral of |c'| over [a, b] (inside one knot span, or on one extension): 20-point
    Gauss-Legendre on 64 equal pieces (|c'| on the piece of the curve holding the middle)."""
    s = ca.SX.sym("s")
    speed = ca.Function("speed", [s], [ca.norm_2(curve_tangent(curve, s, 0.5 * (a + b)))])
    x, w = GL20
    edges = np.linspace(a, b, 65)
    mids, halves = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
    nodes = (mids[:, None] + halves[:, None] * x[None, :]).ravel()
    values = np.array(speed.map(nodes.size)(nodes.reshape(1, -1))).ravel()
    return float(np.sum(values.reshape(64, 20) * w[None, :] * halves[:, None]))


def arc_length_at(curve, u):
    """S(u) = integral of |c'| from 0 to u: knot span by knot span; a closed spline's turns
    (S(u + L) = S(u) + Lambda); an open one's straight extensions beyond its ends."""
    knots = cubic_knots(curve["points"])
    n = len(knots) - 1
    total = [0.0]
    for k in range(n):
        total.append(total[-1] + _reference_length(curve, knots[k], knots[k + 1]))
    if curve["closed"]:
        turns = math.floor(u / knots[n])
        w = u - knots[n] * turns
        return turns * total[n] + _inside_length(curve, knots, total, w)
    if u < 0.0:
        return -_reference_length(curve, u, 0.0)
    if u > knots[n]:
        return total[n] + _reference_length(curve, knots[n], u)
    return _inside_length(curve, knots, total, u)


def _inside_length(curve, knots, total, u):
    k = _segment_at(knots, len(knots) - 1, u)
    return total[k] + _reference_length(curve, knots[k], u)


def phi_arc(curve, u, u_num, f):
    """S(u) - f: S(u_num) numerically plus the integral of |c'| from u_num to the symbolic u by
    8-point Gauss-Legendre (its first two derivatives in u at u_num are |c'| and its
    derivative exactly)."""
    x, w = GL8
    mid, half = 0.5 * (u + u_num), 0.5 * (u - u_num)
    stretch = 0
    for xi, wi in zip(x, w):
        stretch = stretch + wi * ca.norm_2(curve_tangent(curve, mid + half * xi, u_num))
    return arc_length_at(curve, u_num) + half * stretch - f


def build_arc_driver_cases(name):
    """The path driver along a spline's arc length: a random spline per case (as the
    point-on-curve cases draw them), u at the spline's placements, the time functions of
    gen_drivers' plan (every kind but expressions)."""
    closed = ARC_DRIVERS[name]
    pset = "cubic_closed" if closed else "cubic"
    rng = C.element_rng(name)
    cases = []
    for index, entry in enumerate(C.case_plan(n_total=N_CAM_CASES)):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        spec, t, what = D.make_function(rng, index, entry["scale"])
        curve = make_curve("cubic", closed, rng, entry)
        placement = PLACEMENTS[pset][index % len(PLACEMENTS[pset])]
        u = draw_u(curve, placement, rng, entry["scale"])
        params = {"function": spec, "curve": curve}
        case = C.new_case(f"{entry['label']}.{what}.u-{placement}", entry["ground"], t, params,
                          si, sj)
        case["u"] = [u]
        case["udot"] = [float(entry["scale"] * rng.uniform(-2.0, 2.0))]

        def phi(bi, bj, tt, uu, spec=spec, t_num=t, curve=curve, u=u):
            return phi_arc(curve, uu[0], u, D.time_function(spec, tt, t_num))

        cases.append(C.evaluate(phi, case))
    return 1, cases


def build_path_driver_cases():
    """The path driver Phi = u - f(t) (CONTRACT.md, "Curves"): the time function of each case
    from gen_drivers' plan (every kind but expressions), u and udot random; the bodies' states
    are drawn as elsewhere (the element does not depend on them)."""
    rng = C.element_rng(PATH_DRIVER)
    cases = []
    for index, entry in enumerate(C.case_plan(n_total=N_CASES)):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        spec, t, what = D.make_function(rng, index, entry["scale"])
        params = {"function": spec}
        case = C.new_case(f"{entry['label']}.{what}", entry["ground"], t, params, si, sj)
        case["u"] = [float(entry["scale"] * rng.uniform(-3.0, 3.0))]
        case["udot"] = [float(entry["scale"] * rng.uniform(-2.0, 2.0))]
        t_num = t

        def phi(bi, bj, tt, u, spec=spec, t_num=t_num):
            return u[0] - D.time_function(spec, tt, t_num)

        cases.append(C.evaluate(phi, case))
    return 1, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
