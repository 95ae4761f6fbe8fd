"""Oracle for the joints: each joint's Phi is written out here from its definition (CONTRACT.md) in
terms of the markers and the joint's numbers (length, offset, angle); derivatives come from
common.derive.

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
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n2(f.zi) - P["offset"])


def phi_perpendicular(bi, bj, t, P):
    """z_i . z_j = 0: the two joint axes perpendicular."""
    f = Frames(bi, bj, P)
    return f.n1(f.zi, f.zj)


def phi_point_in_line(bi, bj, t, P):
    """P_j on the line through P_i along z_i: no component of d across z_i."""
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n2(f.xi), f.n2(f.yi))


def phi_point_in_plane(bi, bj, t, P):
    """P_j in the plane normal to z_i at height `offset` above P_i."""
    f = Frames(bi, bj, P)
    return f.n2(f.zi) - P["offset"]


def phi_line_in_plane(bi, bj, t, P):
    """P_j in the plane (offset along z_i) and the line's direction z_j in it."""
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n2(f.zi) - P["offset"], f.n1(f.zi, f.zj))


def phi_parallel_axes(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj))


def phi_angle(bi, bj, t, P):
    """z_j in the plane spanned by x_i and R_x(angle) z_i, i.e. normal to R_x(angle) y_i."""
    f = Frames(bi, bj, P)
    a = P["angle"]
    return f.n1(math.cos(a) * f.yi + math.sin(a) * f.zi, f.zj)


def phi_cone(bi, bj, t, P):
    """z_i . z_j - cos(angle): z_j on the cone of half-angle `angle` about z_i."""
    f = Frames(bi, bj, P)
    return f.n1(f.zi, f.zj) - math.cos(P["angle"])


def phi_no_rotation(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n1(f.xi, f.yj))


def phi_constant_velocity(bi, bj, t, P):
    """Coincident points; R = A_i^T A_j symmetric in its x-y block: R12 - R21 = 0."""
    f = Frames(bi, bj, P)
    return ca.vertcat(f.s(), f.n1(f.xi, f.yj) - f.n1(f.yi, f.xj))


def _radial(f, P):
    """(x_i . d)^2 + (y_i . d)^2 - l^2: squared distance of P_j from the line through P_i along
    z_i (written with x_i, y_i: on unnormalized p, where A(p) is not orthogonal, the form with
    |d|^2 - (z_i . d)^2 is a different function of q)."""
    return f.n2(f.xi) ** 2 + f.n2(f.yi) ** 2 - P["length"] ** 2


def phi_rev_cyl(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), _radial(f, P))


def phi_cyl_sph(bi, bj, t, P):
    return _radial(Frames(bi, bj, P), P)


def phi_rev_rev(bi, bj, t, P):
    f = Frames(bi, bj, P)
    return ca.vertcat(f.n1(f.xi, f.zj), f.n1(f.yi, f.zj), f.n2(f.zi) - P["offset"], _radial(f, P))


# ---------------------------------------------------------------------------------------------

# The numbers each kind takes besides its markers.
NUMBERS = {
    "point_in_plane": ("offset",),
    "line_in_plane": ("offset",),
    "planar": ("offset",),
    "angle": ("angle",),
    "cone": ("cone_angle",),
    "rev_cyl": ("length",),
    "cyl_sph": ("length",),
    "rev_rev": ("length", "offset"),
}


def pr_markers(rng, entry):
    return {"marker_i": C.marker(rng, entry, 0), "marker_j": C.marker(rng, entry, 1)}


def pr_numbers(name):
    def make(rng, entry):
        P = pr_markers(rng, entry)
        for key in NUMBERS[name]:
            if key == "length":
                P[key] = float(entry["scale"] * rng.uniform(0.5, 2.0))
            elif key == "offset":
                P[key] = float(entry["scale"] * rng.uniform(-1.0, 1.0))
            elif key == "cone_angle":
                # Away from 0 and pi, where the row loses rank (refused at model build).
                P["angle"] = float(rng.uniform(0.1, math.pi - 0.1))
            else:
                P[key] = _angle(rng)
        return P
    return make


def pr_ss(rng, entry):
    mi, mj = C.marker(rng, entry, 0), C.marker(rng, entry, 1)
    return {"point_i": mi["point"], "point_j": mj["point"],
            "length": float(entry["scale"] * rng.uniform(0.5, 2.0))}


def _angle(rng):
    return float(rng.uniform(-math.pi, math.pi))


def _bend(rng):
    """A rotation about a random axis in the x-y plane (no twist about z)."""
    c, b = _angle(rng), float(rng.uniform(-1.2, 1.2))
    n = [math.cos(c), math.sin(c), 0.0]
    return C.a_num([math.cos(b / 2)] + [math.sin(b / 2) * x for x in n])


def _around(rng, radius, axial):
    """An offset at `radius` from the z axis, `axial` along it."""
    c = _angle(rng)
    return [radius * math.cos(c), radius * math.sin(c), axial]


def relative_motion(name, rng, scale, P=None):
    """A relative marker rotation and offset (marker-i frame) that the joint allows (with the
    joint's numbers P)."""
    free = lambda: scale * float(rng.uniform(-1, 1))  # noqa: E731
    if name == "point_in_line":
        return C.a_num(C.random_quat(rng)), [0.0, 0.0, free()]
    if name == "point_in_plane":
        return C.a_num(C.random_quat(rng)), [free(), free(), P["offset"]]
    if name == "line_in_plane":
        r = C.rot_axis(2, _angle(rng)) @ C.rot_axis(0, math.pi / 2) @ C.rot_axis(2, _angle(rng))
        return r, [free(), free(), P["offset"]]
    if name == "parallel_axes":
        return C.rot_axis(2, _angle(rng)), [free(), free(), free()]
    if name == "angle":
        r = C.rot_axis(0, P["angle"]) @ C.rot_axis(1, _angle(rng)) @ C.rot_axis(2, _angle(rng))
        return r, [free(), free(), free()]
    if name == "cone":
        r = C.rot_axis(2, _angle(rng)) @ C.rot_axis(0, P["angle"]) @ C.rot_axis(2, _angle(rng))
        return r, [free(), free(), free()]
    if name == "no_rotation":
        return np.eye(3), [free(), free(), free()]
    if name == "constant_velocity":
        return _bend(rng), [0.0, 0.0, 0.0]
    if name == "rev_cyl":
        return C.rot_axis(2, _angle(rng)), _around(rng, P["length"], free())
    if name == "cyl_sph":
        return C.a_num(C.random_quat(rng)), _around(rng, P["length"], free())
    if name == "rev_rev":
        return C.rot_axis(2, _angle(rng)), _around(rng, P["length"], P["offset"])
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
        return C.rot_axis(2, _angle(rng)), off + [P["offset"]]
    if name == "perpendicular":
        r = C.rot_axis(2, _angle(rng)) @ C.rot_axis(0, math.pi / 2) @ C.rot_axis(2, _angle(rng))
        return r, (scale * rng.uniform(-1, 1, 3)).tolist()
    raise KeyError(name)


def solve_markers(name):
    def solve(case, rng):
        r_rel, offset = relative_motion(name, rng, 1.0, case["params"])
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
    "planar": (phi_planar, 3, pr_numbers("planar"), solve_markers("planar")),
    "perpendicular": (phi_perpendicular, 1, pr_markers, solve_markers("perpendicular")),
    "point_in_line": (phi_point_in_line, 2, pr_markers, solve_markers("point_in_line")),
    "point_in_plane": (
        phi_point_in_plane, 1, pr_numbers("point_in_plane"), solve_markers("point_in_plane"),
    ),
    "line_in_plane": (
        phi_line_in_plane, 2, pr_numbers("line_in_plane"), solve_markers("line_in_plane"),
    ),
    "parallel_axes": (phi_parallel_axes, 2, pr_markers, solve_markers("parallel_axes")),
    "angle": (phi_angle, 1, pr_numbers("angle"), solve_markers("angle")),
    "cone": (phi_cone, 1, pr_numbers("cone"), solve_markers("cone")),
    "no_rotation": (phi_no_rotation, 3, pr_markers, solve_markers("no_rotation")),
    "constant_velocity": (
        phi_constant_velocity, 4, pr_markers, solve_markers("constant_velocity"),
    ),
    "rev_cyl": (phi_rev_cyl, 3, pr_numbers("rev_cyl"), solve_markers("rev_cyl")),
    "cyl_sph": (phi_cyl_sph, 1, pr_numbers("cyl_sph"), solve_markers("cyl_sph")),
    "rev_rev": (phi_rev_rev, 4, pr_numbers("rev_rev"), solve_markers("rev_rev")),
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
