"""Oracle for the joint-coordinate limits: one unilateral row g = c - lo (lower) or hi - c (upper)
on a joint coordinate c of the two markers, one element per measure (limit_angle, limit_slide,
...). g is written from CONTRACT.md; CasADi differentiates it.

Angles of atan2 form are continued from a reference angle: atan2(s, c) + 2 pi n with the integer
n chosen numerically at the case (a constant of the case, as in gen_couplers.py). Bend (in
[0, pi]) and bryant_y (an asin) are not continued.

Cases where c is ill-defined or ill-conditioned (an atan2 of two nearly vanishing terms, an asin
near +-1, a point near the axis or a vanishing distance) are redrawn: the limit is undefined
there, as a coupler's angle is.

Usage: python gen_limits.py OUTDIR
"""

import math
import sys

import casadi as ca

import common as C
from gen_couplers import continued

GENERATOR = "gen_limits.py"
FAMILY = "limit"


def _frame(b, m):
    """Global x, y, z of marker m on body b (SX)."""
    return b.vector(m["x"]), b.vector(m["y"]), b.vector(m["z"])


def terms(bi, bj, P):
    """("atan2", s, c), ("asin", s) or ("plain", v) of the measure (CONTRACT.md)."""
    mi, mj = P["marker_i"], P["marker_j"]
    d = bj.point(mj["point"]) - bi.point(mi["point"])
    xi, yi, zi = _frame(bi, mi)
    xj, yj, zj = _frame(bj, mj)
    m = P["measure"]
    table = {
        "angle": ("atan2", ca.dot(yi, xj), ca.dot(xi, xj)),
        "slide": ("plain", ca.dot(zi, d)),
        "offset_x": ("plain", ca.dot(xi, d)),
        "offset_y": ("plain", ca.dot(yi, d)),
        "offset_z": ("plain", ca.dot(zi, d)),
        "distance": ("plain", ca.norm_2(d)),
        "cross_angle_i": ("atan2", ca.dot(yi, zj), ca.dot(xi, zj)),
        "cross_angle_j": ("atan2", ca.dot(yj, zi), ca.dot(xj, zi)),
        "bryant_x": ("atan2", -ca.dot(yi, zj), ca.dot(zi, zj)),
        "bryant_y": ("asin", ca.dot(xi, zj)),
        "bryant_z": ("atan2", -ca.dot(xi, yj), ca.dot(xi, xj)),
        "axis_angle": ("atan2", -ca.dot(yi, zj), ca.dot(zi, zj)),
        "bend": ("atan2", ca.norm_2(ca.cross(zi, zj)), ca.dot(zi, zj)),
        "azimuth": ("atan2", ca.dot(yi, d), ca.dot(xi, d)),
    }
    return table[m]


MEASURES = ["angle", "slide", "offset_x", "offset_y", "offset_z", "distance", "cross_angle_i",
            "cross_angle_j", "bryant_x", "bryant_y", "bryant_z", "axis_angle", "bend", "azimuth"]
LENGTHS = {"slide", "offset_x", "offset_y", "offset_z", "distance"}
NOT_CONTINUED = {"bend"}


def _numeric(case):
    return C.Body(C.const(case["q_i"])), C.Body(C.const(case["q_j"]))


def _num(x):
    return float(ca.evalf(x))


def coordinate(bi, bj, P, case):
    """c as SX, an atan2 angle continued from P["reference"] at the case's numbers."""
    t = terms(bi, bj, P)
    if t[0] == "plain":
        return t[1]
    if t[0] == "asin":
        return ca.asin(t[1])
    if P["measure"] in NOT_CONTINUED:
        return ca.atan2(t[1], t[2])
    num = terms(*_numeric(case), P)
    return continued(t[1], t[2], _num(num[1]), _num(num[2]), P["reference"])


def phi_limit(bi, bj, t, P, case):
    sign = 1.0 if P["bound"] == "lower" else -1.0
    return sign * (coordinate(bi, bj, P, case) - P["value"]) + 0 * t


def definition(case, P):
    """How well c is defined at the case (as JointLimit::definition, relative to the scale)."""
    t = terms(*_numeric(case), P)
    scale = max(case["_scale"], 1e-300)
    m = P["measure"]
    if t[0] == "asin":
        s = _num(t[1])
        return math.sqrt(max(0.0, 1.0 - s * s))
    if t[0] == "plain":
        return _num(t[1]) / scale if m == "distance" else 1.0
    s, c = _num(t[1]), _num(t[2])
    if m == "bend":
        return s
    return math.hypot(s, c) / (scale if m == "azimuth" else 1.0)


def pr_limit(measure):
    def make(rng, entry, k):
        e = dict(entry, axis=None) if k > 0 else entry
        scale = entry["scale"] if measure in LENGTHS else 1.0
        return {"marker_i": C.marker(rng, e, 0), "marker_j": C.marker(rng, e, 1),
                "measure": measure, "bound": str(rng.choice(["lower", "upper"])),
                "value": float(scale * rng.uniform(-2.0, 2.0)),
                "reference": float(rng.uniform(-40.0, 40.0))}
    return make


ELEMENTS = {f"limit_{m}": m for m in MEASURES}


def build_cases(name):
    make_params = pr_limit(ELEMENTS[name])
    rng = C.element_rng(name)
    cases = []
    for entry in C.case_plan():
        # Redraw until c is well defined (axis-aligned markers first, then general ones).
        for k in range(200):
            si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
            params = make_params(rng, entry, k)
            case = C.new_case(entry["label"], entry["ground"], float(rng.uniform(0.0, 2.0)),
                              params, si, sj)
            case["_scale"] = entry["scale"]
            if definition(case, params) >= 0.4:
                break
        else:
            raise RuntimeError(f"{name} {entry['label']}: no well-defined case")
        del case["_scale"]
        if entry["solve"]:
            # On the limit: the bound takes the coordinate's value (g = 0).
            params["value"] = 0.0
            value = C.evaluate(lambda bi, bj, tt: phi_limit(bi, bj, tt, params, case), dict(case))
            sign = 1.0 if params["bound"] == "lower" else -1.0
            params["value"] = sign * value["phi"][0]
        cases.append(C.evaluate(lambda bi, bj, tt: phi_limit(bi, bj, tt, params, case), case))
    return 1, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
