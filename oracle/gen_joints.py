"""Oracle for the joints: each joint's Phi is the stack of its primitive rows (CONTRACT.md), written
out here from the markers; derivatives come from common.derive.

Usage: python gen_joints.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C

GENERATOR = "gen_joints.py"
FAMILY = "joint"


class Frames:
    """Global marker quantities of a joint: P_k = r_k + A_k point_k, x_k = A_k x'_k, ..."""

    def __init__(self, bi, bj, P):
        mi, mj = P["marker_i"], P["marker_j"]
        self.pi, self.pj = bi.point(mi["point"]), bj.point(mj["point"])
        self.xi, self.yi, self.zi = (bi.vector(mi[k]) for k in ("x", "y", "z"))
        self.xj, self.yj, self.zj = (bj.vector(mj[k]) for k in ("x", "y", "z"))

    def s(self):
        """s(P_i, P_j) = P_i - P_j (3 rows)."""
        return self.pi - self.pj

    @staticmethod
    def n1(a, b):
        return ca.dot(a, b)

    def n2(self, a):
        """n2(a; P_i, P_j) = a^T (P_j - P_i)."""
        return ca.dot(a, self.pj - self.pi)


def phi_spherical(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return f.s()


def phi_universal(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.s(), f.n1(f.zi, f.zj))


def phi_revolute(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.s(), f.n1(f.xi, f.zj), f.n1(f.yi, f.zj))


def _cyl(f):
    return [f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n2(f.xi), f.n2(f.yi)]


def phi_cylindrical(bi, bj, t, P):
    return ca.vertcat(*_cyl(Frames(bi, bj, P)))


def phi_prismatic(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(*_cyl(f), f.n1(f.xi, f.yj))


def phi_fixed(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.s(), f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n1(f.xi, f.yj))


def phi_spherical_spherical(bi, bj, t, P):
    d = bj.point(P["point_j"]) - bi.point(P["point_i"])
    return ca.dot(d, d) - P["length"] ** 2


def phi_planar(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n2(f.zi))


def phi_perpendicular(bi, bj, t, P):
    """z_i . z_j = 0: the two joint axes perpendicular."""
    f = Frames(bi, bj, P)
    return f.n1(f.zi, f.zj)


# ---------------------------------------------------------------------------------------------


def pr_markers(rng, entry):
    return {"marker_i": C.marker(rng, entry, 0), "marker_j": C.marker(rng, entry, 1)}


def pr_ss(rng, entry):
    mi, mj = C.marker(rng, entry, 0), C.marker(rng, entry, 1)
    return {"point_i": mi["point"], "point_j": mj["point"],
            "length": float(entry["scale"] * rng.uniform(0.5, 2.0))}


def _angle(rng):
    return float(rng.uniform(-math.pi, math.pi))


def relative_motion(name, rng, scale):
    """A relative marker rotation and offset (marker-i frame) that the joint allows."""
    if name == "spherical":
        return C.a_num(C.random_quat(rng)), [0.0, 0.0, 0.0]
    if name == "universal":
        r = C.rot_axis(2, _angle(rng)) @ C.rot_axis(0, math.pi / 2) @ C.rot_axis(2, _angle(rng))
        return r, [0.0, 0.0, 0.0]
    if name == "revolute":
        return C.rot_axis(2, _angle(rng)), [0.0, 0.0, 0.0]
    if name == "cylindrical":
        return C.rot_axis(2, _angle(rng)), [0.0, 0.0, scale * float(rng.uniform(-1, 1))]
    if name == "prismatic":
        return np.eye(3), [0.0, 0.0, scale * float(rng.uniform(-1, 1))]
    if name == "fixed":
        return np.eye(3), [0.0, 0.0, 0.0]
    if name == "planar":
        off = (scale * rng.uniform(-1, 1, 2)).tolist()
        return C.rot_axis(2, _angle(rng)), off + [0.0]
    if name == "perpendicular":
        r = C.rot_axis(2, _angle(rng)) @ C.rot_axis(0, math.pi / 2) @ C.rot_axis(2, _angle(rng))
        return r, (scale * rng.uniform(-1, 1, 3)).tolist()
    raise KeyError(name)


def solve_markers(name):
    def solve(case, rng):
        r_rel, offset = relative_motion(name, rng, 1.0)
        C.assemble_markers(case, case["params"]["marker_i"], case["params"]["marker_j"], r_rel, offset)
    return solve


def solve_ss(case, rng):
    P = case["params"]
    ai, aj = C.a_num(case["q_i"][3:]), C.a_num(case["q_j"][3:])
    d = (np.array(case["q_j"][:3]) + aj @ np.array(P["point_j"])
         - np.array(case["q_i"][:3]) - ai @ np.array(P["point_i"]))
    P["length"] = float(np.linalg.norm(d))


ELEMENTS = {
    "spherical": (phi_spherical, 3, pr_markers, solve_markers("spherical")),
    "universal": (phi_universal, 4, pr_markers, solve_markers("universal")),
    "revolute": (phi_revolute, 5, pr_markers, solve_markers("revolute")),
    "cylindrical": (phi_cylindrical, 4, pr_markers, solve_markers("cylindrical")),
    "prismatic": (phi_prismatic, 5, pr_markers, solve_markers("prismatic")),
    "fixed": (phi_fixed, 6, pr_markers, solve_markers("fixed")),
    "spherical_spherical": (phi_spherical_spherical, 1, pr_ss, solve_ss),
    "planar": (phi_planar, 3, pr_markers, solve_markers("planar")),
    "perpendicular": (phi_perpendicular, 1, pr_markers, solve_markers("perpendicular")),
}


def build_cases(name):
    phi, rows, make_params, solve = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    for entry in C.case_plan():
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        t = float(rng.uniform(0.0, 2.0))
        case = C.new_case(entry["label"], entry["ground"], t, make_params(rng, entry), si, sj)
        if entry["solve"]:
            solve(case, rng)
        cases.append(C.evaluate(lambda bi, bj, tt: phi(bi, bj, tt, case["params"]), case))
    return rows, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
