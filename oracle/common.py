"""Shared machinery of the cardan symbolic oracle.

Everything here is built from scratch with CasADi SX symbols; nothing is imported from the Rust
side. An element (primitive, joint or driver) is defined by its constraint function Phi alone;
`derive` obtains Phi_q, Phi_v, nu and gamma# (7- and 6-coordinate forms) by CasADi's automatic
differentiation. No derivative formula is typed by hand anywhere in the oracle.

Conventions (see /work/shared/notation.md and oracle/CONTRACT.md):
  q = [r; p], p = [e0, e1, e2, e3] scalar first;
  A(p) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~)  (body -> global; for unit p this is G L^T);
  p (x) q is the Hamilton product, so A(p (x) q) = A(p) A(q) for unit p, q and a
  body-frame virtual rotation pi' acts as p (x) [1, pi'/2].
"""

import json
import math
import os
import zlib

import casadi as ca
import numpy as np

# ---------------------------------------------------------------------------------------------
# Kinematic building blocks (SX)
# ---------------------------------------------------------------------------------------------


def skew(a):
    """3x3 skew matrix a~ with a~ b = a x b."""
    return ca.vertcat(
        ca.horzcat(0, -a[2], a[1]),
        ca.horzcat(a[2], 0, -a[0]),
        ca.horzcat(-a[1], a[0], 0),
    )


def rot_a(p):
    """A(p) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~), the project's definition (also for non-unit p)."""
    e0 = p[0]
    e = p[1:4]
    return (2 * e0 * e0 - 1) * ca.SX.eye(3) + 2 * (ca.mtimes(e, e.T) + e0 * skew(e))


def mat_g(p):
    """G(p) = [-e, e~ + e0 I] (3x4)."""
    e0 = p[0]
    e = p[1:4]
    return ca.horzcat(-e, skew(e) + e0 * ca.SX.eye(3))


def mat_l(p):
    """L(p) = [-e, -e~ + e0 I] (3x4)."""
    e0 = p[0]
    e = p[1:4]
    return ca.horzcat(-e, -skew(e) + e0 * ca.SX.eye(3))


def quat_mul(p, q):
    """Hamilton product p (x) q, scalar first: [p0 q0 - p.q, p0 q + q0 p + p x q]."""
    p0, pv = p[0], p[1:4]
    q0, qv = q[0], q[1:4]
    return ca.vertcat(p0 * q0 - ca.dot(pv, qv), p0 * qv + q0 * pv + ca.cross(pv, qv))


def const(v):
    """A numeric vector as an SX column constant."""
    return ca.SX(ca.DM([float(x) for x in v]))


class Body:
    """Symbolic body: position r, Euler parameters p and A(p)."""

    def __init__(self, q):
        self.r = q[0:3]
        self.p = q[3:7]
        self.a = rot_a(self.p)

    def vector(self, local):
        """s = A s' for a body-fixed direction s' (numeric, body coordinates)."""
        return ca.mtimes(self.a, const(local))

    def point(self, local):
        """r^P = r + A s'^P for a body-fixed point s'^P (numeric, body coordinates)."""
        return self.r + ca.mtimes(self.a, const(local))

    def to_local(self, v):
        """A^T v: a global vector in this body's frame."""
        return ca.mtimes(self.a.T, v)


# ---------------------------------------------------------------------------------------------
# Automatic differentiation of Phi
# ---------------------------------------------------------------------------------------------


def derive(phi_of, n_extra=0):
    """Build a CasADi function of the case inputs from Phi alone.

    phi_of(body_i, body_j, t) -> SX column Phi(q_i, q_j, t).
    Returns F(q_i, q_j, t, qdot_i, qdot_j, v_i, v_j) -> (phi, phi_q, phi_v, nu, gamma_q, gamma_v).

    With n_extra > 0 the element also depends on extra coordinates u (an SX column of n_extra,
    e.g. a curve parameter): phi_of(body_i, body_j, t, u), and
    F(q_i, q_j, t, qdot_i, qdot_j, v_i, v_j, u, udot) -> (..., gamma_v, phi_u); u moves as
    u + udot tau in both gamma# forms.
    """
    qi = ca.SX.sym("q_i", 7)
    qj = ca.SX.sym("q_j", 7)
    t = ca.SX.sym("t")
    qdi = ca.SX.sym("qdot_i", 7)
    qdj = ca.SX.sym("qdot_j", 7)
    vi = ca.SX.sym("v_i", 6)
    vj = ca.SX.sym("v_j", 6)
    tau = ca.SX.sym("tau")
    w = ca.SX.sym("w", 12)  # [dr_i, pi'_i, dr_j, pi'_j]

    if n_extra:
        u = ca.SX.sym("u", n_extra)
        ud = ca.SX.sym("udot", n_extra)

        def ev(q_i, q_j, time, uu):
            return ca.vec(phi_of(Body(q_i), Body(q_j), time, uu))
    else:
        u = ud = None

        def ev(q_i, q_j, time, uu):
            return ca.vec(phi_of(Body(q_i), Body(q_j), time))

    def moved_u():
        return u + ud * tau if n_extra else None

    # Phi and its Jacobian in the 7-coordinate form; nu = -Phi_t.
    phi = ev(qi, qj, t, u)
    phi_q = ca.jacobian(phi, ca.vertcat(qi, qj))
    nu = -ca.jacobian(phi, t)

    # 6-coordinate Jacobian: d/dpi' of Phi(r + dr, p (x) [1, pi'/2]) at dr = pi' = 0.
    def perturb(q, dr, pi):
        return ca.vertcat(q[0:3] + dr, quat_mul(q[3:7], ca.vertcat(1, pi / 2)))

    phi_w = ev(perturb(qi, w[0:3], w[3:6]), perturb(qj, w[6:9], w[9:12]), t, u)
    phi_v = ca.substitute(ca.jacobian(phi_w, w), w, ca.SX.zeros(12))

    # gamma# (7-coordinate form): -d2/dtau2 Phi(q + qdot tau, [u + udot tau,] t + tau) at tau = 0.
    phi_tq = ev(qi + qdi * tau, qj + qdj * tau, t + tau, moved_u())
    gamma_q = -ca.substitute(ca.jacobian(ca.jacobian(phi_tq, tau), tau), tau, ca.SX(0))

    # gamma# (6-coordinate form): -d2/dtau2 Phi(r + rdot tau, p (x) E(tau), [u + udot tau,]
    # t + tau) at tau = 0, E(tau) = [1 - |w'|^2 tau^2 / 8, w' tau / 2] = exp(w' tau / 2) to second
    # order in tau.
    def move(q, v):
        om = v[3:6]
        e = ca.vertcat(1 - ca.dot(om, om) * tau**2 / 8, om * tau / 2)
        return ca.vertcat(q[0:3] + v[0:3] * tau, quat_mul(q[3:7], e))

    phi_tv = ev(move(qi, vi), move(qj, vj), t + tau, moved_u())
    gamma_v = -ca.substitute(ca.jacobian(ca.jacobian(phi_tv, tau), tau), tau, ca.SX(0))

    if n_extra:
        # Phi_u: the same in the 7- and the 6-coordinate form.
        phi_u = ca.jacobian(phi, u)
        return ca.Function(
            "oracle",
            [qi, qj, t, qdi, qdj, vi, vj, u, ud],
            [phi, phi_q, phi_v, nu, gamma_q, gamma_v, phi_u],
        )
    return ca.Function(
        "oracle",
        [qi, qj, t, qdi, qdj, vi, vj],
        [phi, phi_q, phi_v, nu, gamma_q, gamma_v],
    )


def evaluate(phi_of, case):
    """Fill a case (inputs already set) with phi, phi_q, phi_v, nu, gamma_q, gamma_v.

    A case with extra coordinates (fields "u" and "udot") gets phi_of(bi, bj, t, u) and also
    phi_u; the others are evaluated exactly as before."""
    n_extra = len(case["u"]) if "u" in case else 0
    f = derive(phi_of, n_extra)
    norm = case["normalized"]
    vi = case["v_i"] if norm else [0.0] * 6
    vj = case["v_j"] if norm else [0.0] * 6
    args = [case["q_i"], case["q_j"], case["t"], case["qdot_i"], case["qdot_j"], vi, vj]
    if n_extra:
        args += [case["u"], case["udot"]]
    out = [np.array(o.full(), dtype=float) for o in f(*args)]
    phi, phi_q, phi_v, nu, gamma_q, gamma_v = out[:6]
    if n_extra:
        case["phi_u"] = out[6].tolist()
    case["phi"] = phi.ravel().tolist()
    case["phi_q"] = phi_q.tolist()
    case["phi_v"] = phi_v.tolist() if norm else None
    case["nu"] = nu.ravel().tolist()
    case["gamma_q"] = gamma_q.ravel().tolist()
    case["gamma_v"] = gamma_v.ravel().tolist() if norm else None
    return case


# ---------------------------------------------------------------------------------------------
# Numeric helpers for case generation (inputs only; never used for derivatives)
# ---------------------------------------------------------------------------------------------

_p_sym = ca.SX.sym("p", 4)
_A_NUM = ca.Function("A", [_p_sym], [rot_a(_p_sym)])
_LT_NUM = ca.Function("Lt", [_p_sym], [mat_l(_p_sym).T])


def a_num(p):
    """A(p) as a numpy 3x3 array."""
    return np.array(_A_NUM([float(x) for x in p]).full(), dtype=float)


def pdot_from_omega(p, omega_local):
    """qdot_p = 1/2 L(p)^T w' (valid for unit p)."""
    return (0.5 * np.array(_LT_NUM([float(x) for x in p]).full(), dtype=float) @ omega_local).tolist()


def quat_from_matrix(m):
    """Unit Euler parameters of a rotation matrix (Shepperd's method), e0 >= 0 when possible."""
    m = np.asarray(m, dtype=float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    cand = [tr, m[0, 0], m[1, 1], m[2, 2]]
    k = max(range(4), key=lambda i: cand[i])
    if k == 0:
        e0 = 0.5 * math.sqrt(1.0 + tr)
        e = [(m[2, 1] - m[1, 2]) / (4 * e0), (m[0, 2] - m[2, 0]) / (4 * e0), (m[1, 0] - m[0, 1]) / (4 * e0)]
        p = [e0] + e
    else:
        i = k - 1
        j, l = (i + 1) % 3, (i + 2) % 3
        ei = 0.5 * math.sqrt(1.0 + 2 * m[i, i] - tr)
        e = [0.0, 0.0, 0.0]
        e[i] = ei
        e[j] = (m[j, i] + m[i, j]) / (4 * ei)
        e[l] = (m[l, i] + m[i, l]) / (4 * ei)
        e0 = (m[l, j] - m[j, l]) / (4 * ei)
        p = [e0] + e
        if e0 < 0:
            p = [-x for x in p]
    n = math.sqrt(sum(x * x for x in p))
    return [x / n for x in p]


def unit(v):
    """v / |v| as a list of floats."""
    n = math.sqrt(sum(float(x) * float(x) for x in v))
    return [float(x) / n for x in v]


def random_quat(rng):
    """A random unit quaternion (uniform on S^3)."""
    return unit(rng.standard_normal(4))


def random_frame(rng):
    """A random orthonormal right-handed frame: (x, y, z) columns of A(random p)."""
    m = a_num(random_quat(rng))
    return m[:, 0].tolist(), m[:, 1].tolist(), m[:, 2].tolist()


# Right-handed signed permutation frames (columns x, y, z), used for axis-aligned cases.
AXIS_FRAMES = [
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
    ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
    ([0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]),
]

GROUND_Q = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]


def element_rng(element):
    """Deterministic generator with a fixed seed per element."""
    return np.random.default_rng(20261122 + zlib.crc32(element.encode()))


def body_state(rng, rot="random", scale=1.0):
    """A moving body's q, qdot, v.

    rot: "random" | "identity" | "e0-zero" | "unnormalized" | ("unnormalized", factor).
    scale multiplies lengths (r, rdot). Unnormalized bodies get an arbitrary qdot and v = None.
    """
    r = (scale * rng.uniform(-2.0, 2.0, 3)).tolist()
    rdot = (scale * rng.uniform(-1.5, 1.5, 3)).tolist()
    omega = rng.uniform(-3.0, 3.0, 3)
    if rot == "identity":
        p = [1.0, 0.0, 0.0, 0.0]
    elif rot == "e0-zero":
        p = [0.0] + unit(rng.standard_normal(3))
    elif rot == "random":
        p = random_quat(rng)
    else:
        factor = rot[1] if isinstance(rot, tuple) else float(rng.choice([0.6, 0.85, 1.2, 1.7]))
        p = [factor * x for x in random_quat(rng)]
        pdot = rng.uniform(-1.0, 1.0, 4).tolist()
        return {"q": r + p, "qdot": rdot + pdot, "v": None}
    pdot = pdot_from_omega(p, omega)
    return {"q": r + p, "qdot": rdot + pdot, "v": rdot + omega.tolist()}


def ground_state():
    """The ground body: r = 0, p = [1, 0, 0, 0], at rest."""
    return {"q": list(GROUND_Q), "qdot": [0.0] * 7, "v": [0.0] * 6}


def states(rng, ground, rot="random", scale=1.0, rot_j=None):
    """States of bodies i and j for a ground option ("none" | "i" | "j")."""
    si = ground_state() if ground == "i" else body_state(rng, rot, scale)
    sj = ground_state() if ground == "j" else body_state(rng, rot if rot_j is None else rot_j, scale)
    return si, sj


def new_case(label, ground, t, params, si, sj):
    """A case dict with the inputs in contract order (outputs are filled by `evaluate`)."""
    normalized = si["v"] is not None and sj["v"] is not None
    return {
        "label": label,
        "ground": ground,
        "normalized": normalized,
        "t": float(t),
        "params": params,
        "q_i": [float(x) for x in si["q"]],
        "q_j": [float(x) for x in sj["q"]],
        "qdot_i": [float(x) for x in si["qdot"]],
        "qdot_j": [float(x) for x in sj["qdot"]],
        "v_i": [float(x) for x in si["v"]] if normalized else None,
        "v_j": [float(x) for x in sj["v"]] if normalized else None,
    }


def with_state(case, si=None, sj=None):
    """Replace body states in a case (used to build configurations at a solution)."""
    if si is not None:
        case["q_i"], case["qdot_i"] = list(si["q"]), list(si["qdot"])
        if case["normalized"]:
            case["v_i"] = list(si["v"])
    if sj is not None:
        case["q_j"], case["qdot_j"] = list(sj["q"]), list(sj["qdot"])
        if case["normalized"]:
            case["v_j"] = list(sj["v"])
    return case


# ---------------------------------------------------------------------------------------------
# Diff-friendly JSON
# ---------------------------------------------------------------------------------------------


def _num(x):
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, int):
        return str(x)
    x = float(x)
    if not math.isfinite(x):
        raise ValueError("non-finite value in oracle output")
    return repr(x)


def _inline(v):
    """A value on one line: arrays, small objects, scalars."""
    if v is None:
        return "null"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + _inline(x) for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_inline(x) for x in v) + "]"
    return _num(v)


def _field(key, v, indent):
    pad = " " * indent
    if isinstance(v, list) and v and isinstance(v[0], list):
        rows = (",\n").join(pad + "  " + _inline(r) for r in v)
        return f"{pad}{json.dumps(key)}: [\n{rows}\n{pad}]"
    if isinstance(v, dict) and v:
        items = (",\n").join(f"{pad}  {json.dumps(k)}: {_inline(x)}" for k, x in v.items())
        return f"{pad}{json.dumps(key)}: {{\n{items}\n{pad}}}"
    return f"{pad}{json.dumps(key)}: {_inline(v)}"


CASE_FIELDS = [
    "label", "ground", "normalized", "t", "params", "q_i", "q_j", "qdot_i", "qdot_j", "v_i", "v_j",
    "u", "udot", "phi", "phi_q", "phi_v", "phi_u", "nu", "gamma_q", "gamma_v",
]
# Written only for the cases that have them (elements with extra coordinates, e.g. curves).
OPTIONAL_FIELDS = {"u", "udot", "phi_u"}


def write_element(outdir, element, family, generator, rows, cases):
    """Write oracle/data/<element>.json: one case per block, one array per line."""
    for c in cases:
        assert len(c["phi"]) == rows, (element, c["label"])
    labels = [c["label"] for c in cases]
    assert len(set(labels)) == len(labels), f"duplicate labels in {element}"
    blocks = []
    for c in cases:
        keys = [k for k in CASE_FIELDS if k not in OPTIONAL_FIELDS or k in c]
        fields = ",\n".join(_field(k, c[k], 6) for k in keys)
        blocks.append("    {\n" + fields + "\n    }")
    text = (
        "{\n"
        f'  "element": {json.dumps(element)},\n'
        f'  "family": {json.dumps(family)},\n'
        f'  "generator": {json.dumps(generator)},\n'
        f'  "rows": {rows},\n'
        '  "cases": [\n' + ",\n".join(blocks) + "\n  ]\n}\n"
    )
    json.loads(text)  # must parse
    os.makedirs(outdir, exist_ok=True)
    with open(os.path.join(outdir, element + ".json"), "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return len(cases)


# ---------------------------------------------------------------------------------------------
# Case plans (labels and the kind of configuration each one asks for)
# ---------------------------------------------------------------------------------------------

N_CASES = 56


def case_plan(grounds=("none", "i", "j"), n_total=N_CASES, unnormalized=True, extra=()):
    """The curated cases of the conformance suite followed by random ones, n_total in all.

    Each entry is a dict: label, ground, rot ("random" | "identity" | "e0-zero" | "unnormalized"),
    scale (1, 1e-3, 1e3), axis (None | 0 | 1 | 2: axis-aligned vectors and frames), solve (place the
    configuration on the constraint manifold) and tie (index of a tie pattern, `_select` forms).
    Grounds not in `grounds` are replaced by the first allowed one.
    """
    g0 = grounds[0]

    def g(x):
        return x if x in grounds else g0

    def e(label, ground="none", rot="random", scale=1.0, axis=None, solve=False, tie=None):
        return {"label": label, "ground": g(ground), "rot": rot, "scale": scale, "axis": axis,
                "solve": solve, "tie": tie}

    plan = [
        e("identity", rot="identity"),
        e("e0-zero", rot="e0-zero"),
        e("axis-aligned-x", axis=0),
        e("axis-aligned-y", axis=1),
        e("axis-aligned-z", axis=2),
        e("axis-aligned-identity", rot="identity", axis=0),
        e("small-1e-3", scale=1e-3),
        e("large-1e3", scale=1e3),
    ]
    for side in ("i", "j"):
        if side in grounds:
            plan += [e(f"ground-{side}-{k}", ground=side) for k in (1, 2, 3)]
            plan += [e(f"ground-{side}-axis-aligned", ground=side, axis=2)]
    if unnormalized:
        plan += [e("unnormalized-1", rot="unnormalized"), e("unnormalized-2", rot="unnormalized"),
                 e("unnormalized-3", ground="i", rot="unnormalized"),
                 e("unnormalized-4", ground="j", rot="unnormalized")]
    plan += [e("at-solution-1", solve=True), e("at-solution-2", solve=True),
             e("at-solution-3", ground="i", solve=True), e("at-solution-4", ground="j", solve=True),
             e("at-solution-axis-aligned", solve=True, axis=1)]
    plan += [e(**x) for x in extra]
    k = 0
    while len(plan) < n_total:
        k += 1
        ground = ("none", "none", "i", "none", "j")[k % 5]
        plan.append(e(f"random-{k:02d}", ground=ground))
    # Labels must be unique even when grounds were remapped.
    seen = set()
    for x in plan:
        assert x["label"] not in seen, x["label"]
        seen.add(x["label"])
    return plan


# ---------------------------------------------------------------------------------------------
# Markers (joints and drivers) and configurations placed on a solution
# ---------------------------------------------------------------------------------------------


def marker(rng, entry, which=0):
    """A marker {point, x, y, z}: orthonormal right-handed frame in body coordinates."""
    scale = entry["scale"]
    if entry["axis"] is not None:
        x, y, z = AXIS_FRAMES[(entry["axis"] + 3 * which) % len(AXIS_FRAMES)]
        e = [0.0, 0.0, 0.0]
        e[(entry["axis"] + which) % 3] = scale * 0.5 * (1 + which)
        point = e
    else:
        x, y, z = random_frame(rng)
        point = (scale * rng.uniform(-1.0, 1.0, 3)).tolist()
    return {"point": [float(v) for v in point], "x": list(x), "y": list(y), "z": list(z)}


def marker_matrix(m):
    """[x y z] of a marker as a 3x3 numpy array (body coordinates)."""
    return np.column_stack([m["x"], m["y"], m["z"]])


def rot_axis(axis, angle):
    """Rotation matrix about a coordinate axis (numeric, for case construction)."""
    c, s = math.cos(angle), math.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    m = np.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def reposition(case, side, a_new, r_new):
    """Move body `side` ("i" | "j") of a normalized case to rotation matrix a_new and position r_new,
    keeping its rdot and w' (qdot_p is recomputed as 1/2 L^T w')."""
    p = quat_from_matrix(a_new)
    v = case["v_" + side]
    case["q_" + side] = [float(x) for x in r_new] + p
    case["qdot_" + side] = list(v[0:3]) + pdot_from_omega(p, np.array(v[3:6]))


def assemble_markers(case, mi, mj, r_rel, offset):
    """Place the moving body so that marker j's global frame is (marker i's frame) . r_rel and
    P_j = P_i + (marker i's frame) . offset. Body j moves unless it is ground."""
    ai = a_num(case["q_i"][3:])
    aj = a_num(case["q_j"][3:])
    ri = np.array(case["q_i"][:3])
    rj = np.array(case["q_j"][:3])
    li, lj = marker_matrix(mi), marker_matrix(mj)
    if case["ground"] != "j":
        frame_i = ai @ li
        pi = ri + ai @ np.array(mi["point"])
        a_j = frame_i @ r_rel @ lj.T
        pj = pi + frame_i @ np.array(offset)
        reposition(case, "j", a_j, pj - a_j @ np.array(mj["point"]))
    else:
        frame_j = aj @ lj
        pj = rj + aj @ np.array(mj["point"])
        frame_i = frame_j @ r_rel.T
        a_i = frame_i @ li.T
        pi = pj - frame_i @ np.array(offset)
        reposition(case, "i", a_i, pi - a_i @ np.array(mi["point"]))
