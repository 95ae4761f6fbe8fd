"""Oracle for the pose driver (general motion): one row of the prescription of marker frame j
relative to marker frame i by three translations in frame i and three angles in a rotation
sequence (CONTRACT.md). R(t) is built from SX rotation matrices of the sequence, the angles being
time functions in t, so AD gives every time derivative.

Usage: python gen_pose.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C
import gen_drivers as D

GENERATOR = "gen_pose.py"
FAMILY = "driver"

ORDERS = ["xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz"]


def rot(axis, a):
    """Rotation matrix by angle a (SX or float) about coordinate axis 0, 1 or 2."""
    c, s = ca.cos(a), ca.sin(a)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    m = ca.SX.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def rotation(order, angles):
    r = ca.SX.eye(3)
    for letter, a in zip(order, angles):
        r = ca.mtimes(r, rot("xyz".index(letter), a))
    return r


def phi_pose(bi, bj, t, P, t_num):
    """Rows 0-2: x_I . d - f_k; rows 3-5 with E = A_I R(t): x_E . z_J, y_E . z_J, x_E . y_J."""
    mi, mj = P["marker_i"], P["marker_j"]
    f = [D.time_function(spec, t, t_num) for spec in P["functions"]]
    row = P["row"]
    if row < 3:
        d = bj.point(mj["point"]) - bi.point(mi["point"])
        return ca.dot(bi.vector(mi["xyz"[row]]), d) - f[row]
    frame_i = ca.horzcat(*(bi.vector(mi[k]) for k in ("x", "y", "z")))
    e = ca.mtimes(frame_i, rotation(P["order"], f[3:]))
    pick = {3: (0, "z"), 4: (1, "z"), 5: (0, "y")}[row]
    return ca.dot(e[:, pick[0]], bj.vector(mj[pick[1]]))


def numeric_rotation(order, angles):
    r = np.eye(3)
    for letter, a in zip(order, angles):
        r = r @ C.rot_axis("xyz".index(letter), a)
    return r


def solve(case, rng):
    """Place the case on the solution: shift a translation row's function, or turn marker j's
    frame (body coordinates) so that A_J = A_I R(t)."""
    P = case["params"]
    ai, aj, ri, rj = D._globals(case)
    row, t = P["row"], case["t"]
    mi, mj = P["marker_i"], P["marker_j"]
    if row < 3:
        d = rj + aj @ np.array(mj["point"]) - ri - ai @ np.array(mi["point"])
        g = float((ai @ np.array(mi["xyz"[row]])) @ d)
        spec = P["functions"][row]
        D.shift_function(spec, g - D.eval_time_function(spec, t))
        return
    angles = [D.eval_time_function(spec, t) for spec in P["functions"][3:]]
    e = ai @ C.marker_matrix(mi) @ numeric_rotation(P["order"], angles)
    lj = aj.T @ e
    mj["x"], mj["y"], mj["z"] = (lj[:, k].tolist() for k in range(3))


ELEMENTS = {"pose_driver": None}
N_CASES = 72


def build_cases(name):
    rng = C.element_rng(name)
    cases = []
    for index, entry in enumerate(C.case_plan(n_total=N_CASES)):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        row, order = index % 6, ORDERS[index % len(ORDERS)]
        specs = []
        t = None
        for k in range(6):
            spec, tk, what = D.make_function(rng, 6 * index + k, entry["scale"] if k < 3 else 1.0)
            specs.append(spec)
            if k == row:
                t, label = tk, what
        params = {"marker_i": C.marker(rng, entry, 0), "marker_j": C.marker(rng, entry, 1),
                  "order": order, "row": row, "functions": specs}
        case = C.new_case(f"{entry['label']}.row{row}.{order}.{label}", entry["ground"], t,
                          params, si, sj)
        if entry["solve"]:
            solve(case, rng)
        cases.append(C.evaluate(lambda bi, bj, tt: phi_pose(bi, bj, tt, params, t), case))
    return 1, cases


def main(outdir):
    rows, cases = build_cases("pose_driver")
    return {"pose_driver": C.write_element(outdir, "pose_driver", FAMILY, GENERATOR, rows, cases)}


if __name__ == "__main__":
    print(main(sys.argv[1]))
