"""Oracle for the primitives: n1, n2, p1 (+ _select, _perp), p2 (+ _select, _perp), s, distance,
normalization, radial_distance, homokinetic. Each is defined by Phi alone (see CONTRACT.md); derivatives come from common.derive.

Usage: python gen_primitives.py OUTDIR
"""

import math
import sys

import casadi as ca
import numpy as np

import common as C

GENERATOR = "gen_primitives.py"
FAMILY = "primitive"

# ---------------------------------------------------------------------------------------------
# Phi of each primitive: phi(body_i, body_j, t, params) -> SX
# ---------------------------------------------------------------------------------------------


def d_vec(bi, bj, P):
    """d = r^P_j - r^P_i."""
    return bj.point(P["sp_j"]) - bi.point(P["sp_i"])


def dropped_row(s_local):
    """The `_select` rule: drop k = argmax_k |s'_i[k]| (the first on ties)."""
    a = [abs(float(x)) for x in s_local]
    return max(range(3), key=lambda k: a[k])


def kept_rows(s_local):
    """The two kept rows of the `_select` forms, in increasing order."""
    k = dropped_row(s_local)
    return [r for r in range(3) if r != k]


def phi_n1(bi, bj, t, P):
    return ca.dot(bi.vector(P["s_i"]), bj.vector(P["s_j"]))


def phi_n2(bi, bj, t, P):
    return ca.dot(bi.vector(P["s_i"]), d_vec(bi, bj, P))


def phi_p1(bi, bj, t, P):
    return ca.mtimes(C.skew(bi.vector(P["s_i"])), bj.vector(P["s_j"]))


def phi_p1_select(bi, bj, t, P):
    full = ca.mtimes(C.skew(C.const(P["s_i"])), bi.to_local(bj.vector(P["s_j"])))
    return ca.vertcat(*[full[r] for r in kept_rows(P["s_i"])])


def phi_p1_perp(bi, bj, t, P):
    sj = bj.vector(P["s_j"])
    return ca.vertcat(ca.dot(bi.vector(P["f_i"]), sj), ca.dot(bi.vector(P["g_i"]), sj))


def phi_p2(bi, bj, t, P):
    return ca.mtimes(C.skew(bi.vector(P["s_i"])), d_vec(bi, bj, P))


def phi_p2_select(bi, bj, t, P):
    full = ca.mtimes(C.skew(C.const(P["s_i"])), bi.to_local(d_vec(bi, bj, P)))
    return ca.vertcat(*[full[r] for r in kept_rows(P["s_i"])])


def phi_p2_perp(bi, bj, t, P):
    d = d_vec(bi, bj, P)
    return ca.vertcat(ca.dot(bi.vector(P["f_i"]), d), ca.dot(bi.vector(P["g_i"]), d))


def phi_s(bi, bj, t, P):
    return bi.point(P["sp_i"]) - bj.point(P["sp_j"])


def phi_distance(bi, bj, t, P):
    d = d_vec(bi, bj, P)
    return ca.dot(d, d) - P["length"] ** 2


def phi_radial_distance(bi, bj, t, P):
    """(f_i . d)^2 + (g_i . d)^2 - l^2: P_j at distance l from the line through P_i across f_i, g_i."""
    d = d_vec(bi, bj, P)
    u, w = ca.dot(bi.vector(P["f_i"]), d), ca.dot(bi.vector(P["g_i"]), d)
    return u**2 + w**2 - P["length"] ** 2


def phi_homokinetic(bi, bj, t, P):
    """x_i . y_j - y_i . x_j: no relative twist about z."""
    xi, yi = bi.vector(P["x_i"]), bi.vector(P["y_i"])
    xj, yj = bj.vector(P["x_j"]), bj.vector(P["y_j"])
    return ca.dot(xi, yj) - ca.dot(yi, xj)


def phi_normalization(bi, bj, t, P):
    return ca.dot(bi.p, bi.p) - 1


# ---------------------------------------------------------------------------------------------
# Parameters of each case
# ---------------------------------------------------------------------------------------------

E = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
TIES = ([1.0, -1.0, 0.5], [0.3, 2.0, -2.0], [1.0, 1.0, 1.0], [-0.5, 0.5, 0.5])


def direction(rng, entry, which=0):
    """A body-fixed direction: random (any length), along an axis, or a tie pattern."""
    if entry["tie"] is not None and which == 0:
        return [entry["scale"] * x for x in TIES[entry["tie"]]]
    if entry["axis"] is not None:
        sign = 1.0 if which % 2 == 0 else -1.0
        return [entry["scale"] * sign * x for x in E[(entry["axis"] + which) % 3]]
    return (entry["scale"] * rng.uniform(-1.5, 1.5, 3)).tolist()


def point(rng, entry, which=0):
    """A body-fixed point: random, or on a coordinate axis."""
    if entry["axis"] is not None:
        return [entry["scale"] * 0.75 * (which + 1) * x for x in E[(entry["axis"] + which) % 3]]
    return (entry["scale"] * rng.uniform(-1.0, 1.0, 3)).tolist()


def perp_pair(rng, entry):
    """Two orthonormal body-fixed vectors f, g (perpendicular to the frame's z)."""
    x, y, _ = C.AXIS_FRAMES[entry["axis"]] if entry["axis"] is not None else C.random_frame(rng)
    return list(x), list(y)


def pr_dirs(rng, entry):
    return {"s_i": direction(rng, entry, 0), "s_j": direction(rng, entry, 1)}


def pr_dir_points(rng, entry):
    return {"s_i": direction(rng, entry, 0), "sp_i": point(rng, entry, 0), "sp_j": point(rng, entry, 1)}


def pr_perp1(rng, entry):
    f, g = perp_pair(rng, entry)
    return {"f_i": f, "g_i": g, "s_j": direction(rng, entry, 1)}


def pr_perp2(rng, entry):
    f, g = perp_pair(rng, entry)
    return {"f_i": f, "g_i": g, "sp_i": point(rng, entry, 0), "sp_j": point(rng, entry, 1)}


def pr_points(rng, entry):
    return {"sp_i": point(rng, entry, 0), "sp_j": point(rng, entry, 1)}


def pr_distance(rng, entry):
    P = pr_points(rng, entry)
    P["length"] = float(entry["scale"] * rng.uniform(0.5, 2.0))
    return P


def pr_radial(rng, entry):
    P = pr_perp2(rng, entry)
    P["length"] = float(entry["scale"] * rng.uniform(0.5, 2.0))
    return P


def pr_frames(rng, entry):
    xi, yi = perp_pair(rng, entry)
    x, y, _ = C.random_frame(rng)
    return {"x_i": xi, "y_i": yi, "x_j": list(x), "y_j": list(y)}


# ---------------------------------------------------------------------------------------------
# Configurations at a solution: adjust a parameter of body j so that Phi = 0
# ---------------------------------------------------------------------------------------------


def _geo(case):
    ai = C.a_num(case["q_i"][3:])
    aj = C.a_num(case["q_j"][3:])
    ri = np.array(case["q_i"][:3])
    rj = np.array(case["q_j"][:3])
    return ai, aj, ri, rj


def _set_d(case, d_new):
    """Choose sp_j so that d = r^P_j - r^P_i equals d_new."""
    ai, aj, ri, rj = _geo(case)
    P = case["params"]
    rpi = ri + ai @ np.array(P["sp_i"])
    P["sp_j"] = (aj.T @ (rpi + d_new - rj)).tolist()


def _sg(case, key="s_i"):
    ai, _, _, _ = _geo(case)
    return ai @ np.array(case["params"][key])


def _d(case):
    ai, aj, ri, rj = _geo(case)
    P = case["params"]
    return rj + aj @ np.array(P["sp_j"]) - ri - ai @ np.array(P["sp_i"])


def solve_n1(case, rng):
    _, aj, _, _ = _geo(case)
    si = _sg(case)
    case["params"]["s_j"] = (aj.T @ np.cross(si, rng.standard_normal(3))).tolist()


def solve_n2(case, rng):
    si = _sg(case)
    d = _d(case)
    _set_d(case, d - (si @ d) / (si @ si) * si)


def solve_p1(case, rng):
    _, aj, _, _ = _geo(case)
    case["params"]["s_j"] = (aj.T @ (_sg(case) * rng.uniform(-2.0, 2.0))).tolist()


def _perp_axis(case):
    ai, _, _, _ = _geo(case)
    P = case["params"]
    return ai @ np.cross(np.array(P["f_i"]), np.array(P["g_i"]))


def solve_p1_perp(case, rng):
    _, aj, _, _ = _geo(case)
    case["params"]["s_j"] = (aj.T @ (_perp_axis(case) * rng.uniform(-2.0, 2.0))).tolist()


def solve_p2(case, rng):
    _set_d(case, _sg(case) * rng.uniform(-2.0, 2.0))


def solve_p2_perp(case, rng):
    _set_d(case, _perp_axis(case) * rng.uniform(-2.0, 2.0))


def solve_s(case, rng):
    _set_d(case, np.zeros(3))


def solve_distance(case, rng):
    case["params"]["length"] = float(np.linalg.norm(_d(case)))


def solve_radial_distance(case, rng):
    ai, _, _, _ = _geo(case)
    P = case["params"]
    d = _d(case)
    u, w = (ai @ np.array(P["f_i"])) @ d, (ai @ np.array(P["g_i"])) @ d
    P["length"] = float(math.hypot(u, w))


def solve_homokinetic(case, rng):
    """Frame j = frame i bent about a random axis in frame i's x-y plane (a pure bend)."""
    ai, aj, _, _ = _geo(case)
    P = case["params"]
    xg, yg = ai @ np.array(P["x_i"]), ai @ np.array(P["y_i"])
    c = float(rng.uniform(-math.pi, math.pi))
    n = math.cos(c) * xg + math.sin(c) * yg
    bend = C.a_num(C.unit(np.concatenate(([math.cos(0.6)], math.sin(0.6) * n))))
    P["x_j"] = (aj.T @ bend @ xg).tolist()
    P["y_j"] = (aj.T @ bend @ yg).tolist()


def solve_normalization(case, rng):
    pass  # every normalized case is at the solution


# ---------------------------------------------------------------------------------------------

SELECT_EXTRA = [
    {"label": f"tie-{k + 1}", "tie": k} for k in range(len(TIES))
] + [{"label": "tie-ground-i", "ground": "i", "tie": 0}, {"label": "tie-ground-j", "ground": "j", "tie": 2}]

NORMALIZATION_EXTRA = [
    {"label": "unnormalized-small-1e-3", "rot": ("unnormalized", 1e-3)},
    {"label": "unnormalized-large-1e3", "rot": ("unnormalized", 1e3)},
] + [{"label": f"unnormalized-{k}", "rot": "unnormalized"} for k in range(5, 13)]

# name: (Phi, rows, params, solve, plan options)
ELEMENTS = {
    "n1": (phi_n1, 1, pr_dirs, solve_n1, {}),
    "n2": (phi_n2, 1, pr_dir_points, solve_n2, {}),
    "p1": (phi_p1, 3, pr_dirs, solve_p1, {}),
    "p1_select": (phi_p1_select, 2, pr_dirs, solve_p1, {"extra": SELECT_EXTRA}),
    "p1_perp": (phi_p1_perp, 2, pr_perp1, solve_p1_perp, {}),
    "p2": (phi_p2, 3, pr_dir_points, solve_p2, {}),
    "p2_select": (phi_p2_select, 2, pr_dir_points, solve_p2, {"extra": SELECT_EXTRA}),
    "p2_perp": (phi_p2_perp, 2, pr_perp2, solve_p2_perp, {}),
    "s": (phi_s, 3, pr_points, solve_s, {}),
    "distance": (phi_distance, 1, pr_distance, solve_distance, {}),
    "radial_distance": (phi_radial_distance, 1, pr_radial, solve_radial_distance, {}),
    "homokinetic": (phi_homokinetic, 1, pr_frames, solve_homokinetic, {}),
    "normalization": (
        phi_normalization, 1, lambda rng, entry: {}, solve_normalization,
        {"grounds": ("j",), "extra": NORMALIZATION_EXTRA},
    ),
}


def build_cases(name):
    phi, rows, make_params, solve, opts = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    for entry in C.case_plan(**opts):
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
