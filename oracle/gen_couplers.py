"""Oracle for the couplers (gear, rack_pinion, screw): one equation between two bodies relating
two joint coordinates, with angles continued over turns from a reference angle.
Phi is written from CONTRACT.md; CasADi differentiates it.

An angle atan2(s, c) continued from a reference theta_ref is atan2(s, c) + 2 pi n, with the
integer n chosen numerically at the case so that the value is the one nearest to theta_ref (the
integer is a constant of the case: it does not enter any derivative).

Usage: python gen_couplers.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C

GENERATOR = "gen_couplers.py"
FAMILY = "coupler"

TWO_PI = 2.0 * math.pi


def continued(s, c, s_num, c_num, reference):
    """atan2(s, c) as SX plus the multiple of 2 pi that puts the case's value nearest to
    `reference` (s_num, c_num: the numeric s and c at the case)."""
    principal = math.atan2(s_num, c_num)
    n = round((reference - principal) / TWO_PI)
    return ca.atan2(s, c) + TWO_PI * n


def _frame(b, m):
    """Global x, y, z of marker m on body b (SX)."""
    return b.vector(m["x"]), b.vector(m["y"]), b.vector(m["z"])


def _numeric(case):
    """The two bodies of a case as numeric Body objects (for the turn count)."""
    return C.Body(C.const(case["q_i"])), C.Body(C.const(case["q_j"]))


def _num(x):
    return float(ca.evalf(x))


def gear_terms(bi, bj, P):
    """(s, c) of the two orbit angles: psi_i = atan2(y_i.d, x_i.d) (P_j seen from marker i),
    psi_j = atan2(-y_j.d, -x_j.d) (P_i seen from marker j), d = P_j - P_i."""
    mi, mj = P["marker_i"], P["marker_j"]
    d = bj.point(mj["point"]) - bi.point(mi["point"])
    xi, yi, _ = _frame(bi, mi)
    xj, yj, _ = _frame(bj, mj)
    return [(ca.dot(yi, d), ca.dot(xi, d)), (-ca.dot(yj, d), -ca.dot(xj, d))]


def slide_angle_terms(bi, bj, P, axis):
    """Slide e_i.d along marker i's `axis` ("x" or "z") and (s, c) of the angle of x_j from x_i
    about z_i."""
    mi, mj = P["marker_i"], P["marker_j"]
    d = bj.point(mj["point"]) - bi.point(mi["point"])
    xi, yi, _ = _frame(bi, mi)
    xj = bj.vector(mj["x"])
    return ca.dot(bi.vector(mi[axis]), d), (ca.dot(yi, xj), ca.dot(xi, xj))


def phi_gear(bi, bj, t, P, case):
    ni, nj = _numeric(case)
    num = gear_terms(ni, nj, P)
    sym = gear_terms(bi, bj, P)
    psi = [continued(s, c, _num(sn), _num(cn), ref)
           for (s, c), (sn, cn), ref in zip(sym, num, P["reference"])]
    return P["k_i"] * psi[0] + P["k_j"] * psi[1] - P["constant"] + 0 * t


def phi_slide_angle(axis):
    def phi(bi, bj, t, P, case):
        ni, nj = _numeric(case)
        _, (sn, cn) = slide_angle_terms(ni, nj, P, axis)
        u, (s, c) = slide_angle_terms(bi, bj, P, axis)
        theta = continued(s, c, _num(sn), _num(cn), P["reference"])
        return P["k_slide"] * u + P["k_angle"] * theta - P["constant"] + 0 * t
    return phi


def general(entry):
    """Markers of a coupler are general frames and points: its angles are undefined where
    d is along z_i (gear) or x_j along z_i (rack, screw), which axis-aligned frames on bodies
    turned by multiples of 90 degrees hit exactly."""
    return dict(entry, axis=None)


def pr_gear(rng, entry):
    e = general(entry)
    return {"marker_i": C.marker(rng, e, 0), "marker_j": C.marker(rng, e, 1),
            "k_i": float(rng.uniform(-2.0, 2.0)), "k_j": float(rng.uniform(-2.0, 2.0)),
            "constant": float(rng.uniform(-3.0, 3.0)),
            "reference": [float(rng.uniform(-40.0, 40.0)), float(rng.uniform(-40.0, 40.0))]}


def pr_slide_angle(rng, entry):
    e = general(entry)
    return {"marker_i": C.marker(rng, e, 0), "marker_j": C.marker(rng, e, 1),
            "k_slide": float(rng.choice([-1.0, 1.0])),
            "k_angle": float(entry["scale"] * rng.uniform(-2.0, 2.0)),
            "constant": float(entry["scale"] * rng.uniform(-1.0, 1.0)),
            "reference": float(rng.uniform(-40.0, 40.0))}


# name: (Phi, params)
ELEMENTS = {
    "gear": (phi_gear, pr_gear),
    "rack_pinion": (phi_slide_angle("x"), pr_slide_angle),
    "screw": (phi_slide_angle("z"), pr_slide_angle),
}


def build_cases(name):
    phi, make_params = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    for entry in C.case_plan():
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        params = make_params(rng, entry)
        case = C.new_case(entry["label"], entry["ground"], float(rng.uniform(0.0, 2.0)), params, si, sj)
        if entry["solve"]:
            # Place the case on the solution: the constant takes the value of the other terms.
            params["constant"] = 0.0
            value = C.evaluate(lambda bi, bj, tt: phi(bi, bj, tt, params, case), dict(case))
            params["constant"] = value["phi"][0]
        cases.append(C.evaluate(lambda bi, bj, tt: phi(bi, bj, tt, params, case), case))
    return 1, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
