"""Oracle for the point-on-surface elements: a point of body j on a surface S(u, v) fixed in
body i, the surface parameters u and v two extra coordinates of the system (CONTRACT.md,
"Surfaces"):

    Phi(q_i, q_j, u, v, t) = r_j + A_j sp_j - (r_i + A_i S(u, v))      (3 rows, no time dependence)

One element per surface kind: point_on_surface_plane, _sphere, _cylinder, _torus, _bicubic.
S(u, v) is built as an SX expression of the symbolic (u, v); common.derive (with two extra
coordinates) differentiates Phi, so Phi_u, Phi_v and the parameter terms of gamma# come from AD.

Usage: python gen_surfaces.py OUTDIR
"""

import sys

import casadi as ca
import numpy as np

import common as C
import gen_curves as K

GENERATOR = "gen_surfaces.py"
FAMILY = "surface"

ELEMENTS = {f"point_on_surface_{k}": k for k in ("plane", "sphere", "cylinder", "torus", "bicubic")}
N_CASES = 60


def _bernstein(t):
    s = 1 - t
    return [s * s * s, 3 * t * s * s, 3 * t * t * s, t * t * t]


def surface_point(surf, u, v):
    """S(u, v) as an SX column (surface coordinates: body i's, or global for ground i)."""
    kind = surf["kind"]
    if kind == "bicubic":
        bu, bv = _bernstein(u), _bernstein(v)
        s = 0
        for i in range(4):
            for j in range(4):
                s = s + bu[i] * bv[j] * C.const(surf["points"][i][j])
        return s
    o, x, y, z = (C.const(surf[k]) for k in ("center", "x", "y", "z"))
    if kind == "plane":
        return o + u * x + v * y
    if kind == "sphere":
        r = surf["radius"]
        th, ph = u / r, v / r
        return o + r * (ca.cos(ph) * (ca.cos(th) * x + ca.sin(th) * y) + ca.sin(ph) * z)
    if kind == "cylinder":
        r = surf["radius"]
        th = u / r
        return o + r * (ca.cos(th) * x + ca.sin(th) * y) + v * z
    if kind == "torus":
        big, r = surf["major"], surf["minor"]
        th, ph = u / big, v / r
        return o + (big + r * ca.cos(ph)) * (ca.cos(th) * x + ca.sin(th) * y) + r * ca.sin(ph) * z
    raise KeyError(kind)


def make_surface(kind, rng, entry):
    s = entry["scale"]
    if kind == "bicubic":
        # A wavy net over a grid of step 1/3 (times the scale) in a random frame.
        x, y, z = K._frame(rng, entry)
        o = K._center(rng, entry)
        pts = []
        for i in range(4):
            row = []
            for j in range(4):
                h = float(s * rng.uniform(-0.3, 0.3))
                p = [o[c] + s * (i / 3.0) * x[c] + s * (j / 3.0) * y[c] + h * z[c]
                     for c in range(3)]
                row.append(p)
            pts.append(row)
        return {"kind": "bicubic", "points": pts}
    x, y, z = K._frame(rng, entry)
    surf = {"kind": kind, "center": K._center(rng, entry), "x": x, "y": y, "z": z}
    if kind in ("sphere", "cylinder"):
        surf["radius"] = float(s * rng.uniform(0.3, 2.0))
    if kind == "torus":
        big = float(s * rng.uniform(0.8, 2.0))
        surf["major"] = big
        surf["minor"] = float(big * rng.uniform(0.15, 0.7))
    return surf


def draw_uv(surf, rng, scale):
    """(u, v): anywhere for a plane and a cylinder; a sphere's v keeps |phi| below 1.2 rad (away
    from the singular poles); a torus' angles over several turns; a patch's inside [0, 1]^2 but
    about one case in five just outside (the polynomial continues)."""
    kind = surf["kind"]
    if kind == "plane":
        return [float(scale * rng.uniform(-3, 3)), float(scale * rng.uniform(-3, 3))]
    if kind == "sphere":
        r = surf["radius"]
        return [float(r * rng.uniform(-8.0, 8.0)), float(r * rng.uniform(-1.2, 1.2))]
    if kind == "cylinder":
        r = surf["radius"]
        return [float(r * rng.uniform(-8.0, 8.0)), float(scale * rng.uniform(-3, 3))]
    if kind == "torus":
        return [float(surf["major"] * rng.uniform(-8.0, 8.0)),
                float(surf["minor"] * rng.uniform(-8.0, 8.0))]
    if rng.uniform() < 0.2:
        return [float(rng.uniform(-0.3, 1.3)), float(rng.uniform(-0.3, 1.3))]
    return [float(rng.uniform(0.0, 1.0)), float(rng.uniform(0.0, 1.0))]


def phi_surface(bi, bj, t, uv, P):
    """Phi = r_j + A_j sp_j - (r_i + A_i S(u, v))."""
    s = surface_point(P["surface"], uv[0], uv[1])
    return bj.point(P["sp_j"]) - (bi.r + ca.mtimes(bi.a, s)) + 0 * t


def _phi_of(params):
    return lambda bi, bj, tt, uu: phi_surface(bi, bj, tt, uu, params)


def solve_sp_j(case):
    """Put P_j on the surface: sp_j = A_j^T (r_i + A_i S(u, v) - r_j) (normalized bodies)."""
    params = case["params"]
    params["sp_j"] = [0.0, 0.0, 0.0]
    off = C.evaluate(_phi_of(params), dict(case))["phi"]
    aj = C.a_num(case["q_j"][3:])
    params["sp_j"] = (-(aj.T @ np.array(off))).tolist()


def build_cases(name):
    """(rows, cases) of element `name` (generate.py calls this for each entry of ELEMENTS)."""
    kind = ELEMENTS[name]
    rng = C.element_rng(name)
    cases = []
    for entry in C.case_plan(n_total=N_CASES, extra=K.EXTRA_SOLVED):
        si, sj = C.states(rng, entry["ground"], entry["rot"], entry["scale"])
        t = float(rng.uniform(0.0, 2.0))
        surf = make_surface(kind, rng, entry)
        params = {"surface": surf, "sp_j": K.make_sp_j(rng, entry)}
        case = C.new_case(entry["label"], entry["ground"], t, params, si, sj)
        case["u"] = draw_uv(surf, rng, entry["scale"])
        case["udot"] = [float(entry["scale"] * rng.uniform(-2.0, 2.0)) for _ in range(2)]
        if entry["solve"]:
            assert case["normalized"], case["label"]
            solve_sp_j(case)
        cases.append(C.evaluate(_phi_of(params), case))
    return 3, cases


def main(outdir):
    counts = {}
    for name in ELEMENTS:
        rows, cases = build_cases(name)
        counts[name] = C.write_element(outdir, name, FAMILY, GENERATOR, rows, cases)
    return counts


if __name__ == "__main__":
    print(main(sys.argv[1]))
