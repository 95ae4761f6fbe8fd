"""URDF robots of ``example-robot-data`` read by cardan and checked against Pinocchio (issue 51).

For each robot, cardan reads the URDF (``cardan.load``, or an overlay naming it) and Pinocchio
builds its model from the same file (``pin.buildModelFromUrdf``; fixed joints become frames,
mimic joints free: Pinocchio's default reading, and cardan's ``mimic="free"``).

- Forward kinematics and inverse dynamics along smooth random trajectories: an overlay drives
  every joint by q_i(t) = c_i + a_i sin(w_i t + φ_i); cardan's inverse dynamics gives the link
  origins (points), the first link of each body's orientation (the body's) and the driver
  efforts, Pinocchio ``framesForwardKinematics`` and ``rnea`` at the same q, q̇, q̈.
- Forward dynamics: the robot released at rest in cardan's drawn configuration, 2 s under
  gravity without limits, against Pinocchio's ``aba`` integrated by classical Runge–Kutta with a
  step of 0.25 ms (on the configuration manifold through ``pin.integrate`` for a floating base):
  every link origin at every output time.
"""

import math
import pathlib
import sysconfig
import tomllib

import numpy as np
import pinocchio as pin
import pytest

import cardan

ROBOTS_DIR = pathlib.Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix/share/example-robot-data/robots"

# name: (URDF under ROBOTS_DIR, base)
ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "fixed"),
    "panda": ("panda_description/urdf/panda.urdf", "fixed"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", "fixed"),
    "z1": ("z1_description/urdf/z1.urdf", "fixed"),
    "so100": ("so_arm_description/urdf/so100.urdf", "fixed"),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", "fixed"),
    "allegro_hand": ("allegro_hand_description/urdf/allegro_right_hand.urdf", "fixed"),
    "solo12": ("solo_description/robots/solo12.urdf", "floating"),
    "go2": ("go2_description/urdf/go2.urdf", "floating"),
    "g1_humanoid": ("g1_description/urdf/g1_29dof_rev_1_0.urdf", "floating"),
}
FIXED = [n for n, (_, b) in ROBOTS.items() if b == "fixed"]


def sanitize(name: str) -> str:
    """cardan's spelling of a URDF name (crates/urdf/src/names.rs)."""
    s = "".join(c if (c.isascii() and c.isalnum()) or c == "_" else "_" for c in name)
    return "_" + s if not s or s[0].isdigit() else s


def pinocchio_model(name: str) -> pin.Model:
    path, base = ROBOTS[name]
    urdf = str(ROBOTS_DIR / path)
    if base == "floating":
        return pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    return pin.buildModelFromUrdf(urdf)


def moving_joints(model: pin.Model) -> list:
    """(joint id, name, is_prismatic, is_unbounded) of the 1-DOF joints."""
    out = []
    for jid in range(1, model.njoints):
        j = model.joints[jid]
        if j.nv != 1:
            continue
        out.append((jid, model.names[jid], j.shortname().startswith("JointModelP"), j.nq == 2))
    return out


def set_q(model: pin.Model, q: np.ndarray, jid: int, value: float) -> None:
    j = model.joints[jid]
    if j.nq == 2:  # continuous: cos, sin
        q[j.idx_q], q[j.idx_q + 1] = math.cos(value), math.sin(value)
    else:
        q[j.idx_q] = value


def link_points(imported_text: str) -> dict:
    """Each URDF link → the points-table column prefix of its origin (``body.point``), and the
    bodies whose frame is a link's (the first link of each body)."""
    doc = tomllib.loads(imported_text)
    out = {}
    for body in doc.get("body", []):
        for point in body.get("global_points", {}):
            out.setdefault(point, []).append(f"{body['name']}.{point}")
    return out


def link_columns(model: pin.Model, imported_text: str) -> dict:
    """URDF link name → (Pinocchio frame id, ``body.point`` of its origin)."""
    points = link_points(imported_text)
    out = {}
    for fid, f in enumerate(model.frames):
        if f.type != pin.FrameType.BODY:
            continue
        cands = points.get(sanitize(f.name), [])
        if len(cands) == 1:
            out[f.name] = (fid, cands[0])
    return out


def quat_matrix(e: np.ndarray) -> np.ndarray:
    """The rotation matrix of Euler parameters (e0, e1, e2, e3)."""
    e0, e1, e2, e3 = e
    return np.array(
        [
            [1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
            [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
            [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)],
        ]
    )


def trajectory(joints: list, seed: int) -> list:
    """(c, a, w, φ) per joint: q = c + a sin(w t + φ), within ±0.4 rad (±1 cm) of the drawn 0."""
    rng = np.random.default_rng(seed)
    out = []
    for _, _, prismatic, _ in joints:
        a = 0.01 if prismatic else 0.4
        out.append((rng.uniform(-0.5, 0.5) * a, a, rng.uniform(1.0, 3.0), rng.uniform(0, 2 * math.pi)))
    return out


def overlay(name: str, joints: list, law: list, t_end: float, dt: float, outputs: tuple = ()) -> cardan.Model:
    path, base = ROBOTS[name]
    lines = [
        "[model]",
        f'name = "{name}_wave"',
        "[urdf]",
        f'file = "{ROBOTS_DIR / path}"',
        f'base = "{base}"',
        'mimic = "free"',
        "limits = false",
    ]
    for (_, jname, prismatic, _), (c, a, w, phi) in zip(joints, law):
        lines += [
            "[[driver]]",
            f'name = "d_{sanitize(jname)}"',
            f'type = "{"translation" if prismatic else "rotation"}"',
            f'joint = "{sanitize(jname)}"',
            f'function = {{ kind = "expression", text = "{c!r} + {a!r} * sin({w!r} * t + {phi!r})" }}',
        ]
    lines += [
        "[analysis]",
        'kind = "inverse_dynamics"',
        f"t_end = {t_end!r}",
        f"dt = {dt!r}",
        "position_tolerance = 1e-13",
        *outputs,
    ]
    return cardan.Model.from_toml("\n".join(lines) + "\n", path=ROBOTS_DIR / path.replace(".urdf", ".overlay.toml"))


def imported(name: str, **keys) -> cardan.Model:
    path, base = ROBOTS[name]
    return cardan.load(ROBOTS_DIR / path, base=base, mimic="free", **keys)


@pytest.mark.parametrize("name", FIXED)
def test_kinematics_and_inverse_dynamics_match_pinocchio(name: str) -> None:
    model = pinocchio_model(name)
    data = model.createData()
    joints = moving_joints(model)
    law = trajectory(joints, seed=len(name))
    results = overlay(name, joints, law, t_end=1.0, dt=0.05).inverse_dynamics()
    text = imported(name, limits=False).text
    columns = link_columns(model, text)
    assert len(columns) >= len(joints), f"{name}: {len(columns)} link origins for {len(joints)} joints"
    points, efforts, bodies = results.points, results.driver_efforts, results.bodies
    body_names = [b["name"] for b in tomllib.loads(text)["body"]]
    worst_x = worst_r = worst_tau = 0.0
    for k, t in enumerate(results.t):
        q, v, a = pin_state(model, joints, law, t)
        pin.framesForwardKinematics(model, data, q)
        for link, (fid, col) in columns.items():
            oMf = data.oMf[fid]
            mine = np.array([points[f"{col}.{c}"][k] for c in "xyz"])
            worst_x = max(worst_x, np.abs(mine - oMf.translation).max())
            body = col.split(".")[0]
            if sanitize(link) == body or (body in body_names and col.endswith("." + body)):
                e = np.array([bodies[f"{body}.p.e{i}"][k] for i in range(4)])
                worst_r = max(worst_r, np.abs(quat_matrix(e) - oMf.rotation).max())
        tau = pin.rnea(model, data, q, v, a)
        scale = np.abs(tau).max()
        for jid, jname, prismatic, _ in joints:
            col = f"d_{sanitize(jname)}.{'force' if prismatic else 'torque'}"
            worst_tau = max(worst_tau, abs(efforts[col][k] - tau[model.joints[jid].idx_v]) / scale)
    print(f"{name}: |Δx| {worst_x:.2e} m, |ΔR| {worst_r:.2e}, |Δτ|/max|τ| {worst_tau:.2e}")
    assert worst_x < 1e-12
    assert worst_r < 1e-12
    assert worst_tau < 1e-10


def pin_state(model: pin.Model, joints: list, law: list, t: float) -> tuple:
    """Pinocchio's q, v, a of the overlay's law at t."""
    q, v, a = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
    for (jid, _, _, _), (c, amp, w, phi) in zip(joints, law):
        set_q(model, q, jid, c + amp * math.sin(w * t + phi))
        iv = model.joints[jid].idx_v
        v[iv] = amp * w * math.cos(w * t + phi)
        a[iv] = -amp * w * w * math.sin(w * t + phi)
    return q, v, a


@pytest.mark.parametrize("name", FIXED)
def test_joint_space_matches_pinocchio_crba_nle_and_frame_jacobians(name: str) -> None:
    """M(θ) against ``crba``, h(θ, θ̇) against ``nonLinearEffects`` and every link frame's
    Jacobian against ``computeFrameJacobian`` (``LOCAL_WORLD_ALIGNED``), along the same
    trajectories; cardan's coordinates are the overlay's drivers, one per joint."""
    model = pinocchio_model(name)
    data = model.createData()
    joints = moving_joints(model)
    law = trajectory(joints, seed=len(name) + 1)
    columns = link_columns(model, imported(name, limits=False).text)
    points = ", ".join(f'"{col}"' for _, col in columns.values())
    outputs = ("[analysis.outputs]", "joint_space = true", f"jacobians = [{points}]")
    results = overlay(name, joints, law, t_end=0.5, dt=0.05, outputs=outputs).inverse_dynamics()
    js = results.joint_space()
    assert js.coordinates == [f"d_{sanitize(j[1])}" for j in joints]
    iv = [model.joints[jid].idx_v for jid, _, _, _ in joints]
    worst_m = worst_h = worst_j = 0.0
    for k, t in enumerate(js.t):
        q, v, _ = pin_state(model, joints, law, t)
        m = pin.crba(model, data, q)
        m = np.triu(m) + np.triu(m, 1).T
        m = m[np.ix_(iv, iv)]
        worst_m = max(worst_m, np.abs(js.M[k] - m).max() / np.abs(m).max())
        h = pin.nonLinearEffects(model, data, q, v)[iv]
        worst_h = max(worst_h, np.abs(js.h[k] - h).max() / max(np.abs(h).max(), 1e-300))
        for fid, col in columns.values():
            jf = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[:, iv]
            worst_j = max(worst_j, np.abs(js.jacobians[col][k] - jf).max())
    print(f"{name}: n = {len(iv)}, |ΔM|/max|M| {worst_m:.2e}, |Δh|/max|h| {worst_h:.2e}, "
          f"|ΔJ| {worst_j:.2e} (m, rad)")
    assert worst_m < 1e-10
    assert worst_h < 1e-10
    assert worst_j < 1e-12


FLOATING = [n for n, (_, b) in ROBOTS.items() if b == "floating"]


def rot(axis: int, a: float) -> np.ndarray:
    """The rotation by a about the x, y or z axis."""
    c, s = math.cos(a), math.sin(a)
    m = np.eye(3)
    i, j = [(1, 2), (0, 2), (0, 1)][axis]
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    if axis == 1:
        m[i, j], m[j, i] = s, -s
    return m


def skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def base_state(law: list, t: float) -> tuple:
    """The base's position, R = R_x(a₁) R_y(a₂) R_z(a₃), ṗ and Ṙ of the general motion law
    (six (c, a, w, φ): x, y, z, a₁, a₂, a₃)."""
    val = [c + a * math.sin(w * t + ph) for c, a, w, ph in law]
    rate = [a * w * math.cos(w * t + ph) for c, a, w, ph in law]
    f = [rot(k, val[3 + k]) for k in range(3)]
    df = [f[k] @ skew(np.eye(3)[k]) * rate[3 + k] for k in range(3)]
    r = f[0] @ f[1] @ f[2]
    r_dot = df[0] @ f[1] @ f[2] + f[0] @ df[1] @ f[2] + f[0] @ f[1] @ df[2]
    return np.array(val[:3]), r, np.array(rate[:3]), r_dot


@pytest.mark.parametrize("name", FLOATING)
def test_floating_base_joint_space_matches_pinocchio(name: str) -> None:
    """A floating robot's base driven by a general motion from the ground, its joints by their
    own laws: M(θ) against ``crba`` and h against ``nonLinearEffects`` with Pinocchio's
    free-flyer velocity v with u = T v (cardan's six base rows u: the base link origin's velocity
    in ground axes, then ω·y, −ω·x, −ω·z; T = diag(R, P); ``cardan_dynamics::joint_space``), so
    M_pin = Tᵀ M T, h_pin = Tᵀ (h + M Ṫ v) (the two bases' accelerations differ by Ṫ v) and
    every link frame's Jacobian J_pin = J T."""
    model = pinocchio_model(name)
    data = model.createData()
    joints = moving_joints(model)
    law = trajectory(joints, seed=len(name) + 2)
    rng = np.random.default_rng(7)
    base = [(rng.uniform(-0.05, 0.05), 0.05, rng.uniform(1, 3), rng.uniform(0, 6)) for _ in range(3)]
    base += [(rng.uniform(-0.1, 0.1), 0.2, rng.uniform(1, 3), rng.uniform(0, 6)) for _ in range(3)]
    text = imported(name, limits=False).text
    columns = link_columns(model, text)
    root = next(f for f in model.frames if f.parentJoint == 1 and f.type == pin.FrameType.BODY)
    body, point = columns[root.name][1].split(".")
    fn = lambda c, a, w, ph: f'{{ kind = "expression", text = "{c!r} + {a!r} * sin({w!r} * t + {ph!r})" }}'
    path, _ = ROBOTS[name]
    lines = ["[model]", f'name = "{name}_float"', "[urdf]", f'file = "{ROBOTS_DIR / path}"', 'base = "floating"',
             'mimic = "free"', "limits = false", "[ground]", "points = { world_o = [0.0, 0.0, 0.0] }",
             "[[driver]]", 'name = "base"', 'type = "general_motion"', 'body_i = "ground"', 'point_i = "world_o"',
             f'body_j = "{body}"', f'point_j = "{point}"', 'order = "xyz"',
             "translation = [" + ", ".join(fn(*b) for b in base[:3]) + "]",
             "rotation = [" + ", ".join(fn(*b) for b in base[3:]) + "]"]
    for (_, jname, prismatic, _), (c, a, w, phi) in zip(joints, law):
        lines += ["[[driver]]", f'name = "d_{sanitize(jname)}"', f'type = "{"translation" if prismatic else "rotation"}"',
                  f'joint = "{sanitize(jname)}"', f"function = {fn(c, a, w, phi)}"]
    points = ", ".join(f'"{col}"' for _, col in columns.values())
    lines += ["[analysis]", 'kind = "inverse_dynamics"', "t_end = 0.5", "dt = 0.05", "position_tolerance = 1e-13",
              "[analysis.outputs]", "joint_space = true", f"jacobians = [{points}]"]
    overlay_model = cardan.Model.from_toml("\n".join(lines) + "\n", path=ROBOTS_DIR / path.replace(".urdf", ".float.toml"))
    js = overlay_model.inverse_dynamics().joint_space()
    assert js.coordinates[:6] == ["base.x", "base.y", "base.z", "base.angle_1", "base.angle_2", "base.angle_3"]
    iv = list(range(6)) + [model.joints[jid].idx_v for jid, _, _, _ in joints]
    p_ang = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    worst_m = worst_h = worst_j = 0.0
    for k, t in enumerate(js.t):
        pos, r, p_dot, r_dot = base_state(base, t)
        q, v, _ = pin_state(model, joints, law, t)
        q[:3], q[3:7] = pos, pin.Quaternion(r).coeffs()
        omega = r.T @ r_dot
        v[:3], v[3:6] = r.T @ p_dot, np.array([omega[2, 1], omega[0, 2], omega[1, 0]])
        tt = np.eye(len(iv))
        tt[:3, :3], tt[3:6, 3:6] = r, p_ang
        m = pin.crba(model, data, q)
        m = (np.triu(m) + np.triu(m, 1).T)[np.ix_(iv, iv)]
        mine = tt.T @ js.M[k] @ tt
        worst_m = max(worst_m, np.abs(mine - m).max() / np.abs(m).max())
        # Pinocchio's base acceleration is d/dt (Rᵀ ṗ), cardan's d/dt ṗ: with u = T v,
        # u̇ = T v̇ + Ṫ v, so h_pin = Tᵀ (h + M Ṫ v), Ṫ v = [R (ω × v_lin); 0].
        t_dot_v = np.zeros(len(iv))
        t_dot_v[:3] = r @ np.cross(v[3:6], v[:3])
        h = pin.nonLinearEffects(model, data, q, v)[iv]
        mine_h = tt.T @ (js.h[k] + js.M[k] @ t_dot_v)
        worst_h = max(worst_h, np.abs(mine_h - h).max() / np.abs(h).max())
        for fid, col in columns.values():
            jf = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[:, iv]
            worst_j = max(worst_j, np.abs(js.jacobians[col][k] @ tt - jf).max())
    print(f"{name}: n = {len(iv)}, |ΔM|/max|M| {worst_m:.2e}, |Δh|/max|h| {worst_h:.2e}, |ΔJ| {worst_j:.2e}")
    assert worst_m < 1e-10
    assert worst_h < 1e-10
    assert worst_j < 1e-11


def aba_trajectory(model: pin.Model, q0: np.ndarray, times: np.ndarray, h: float) -> list:
    """Pinocchio's ABA from rest, classical RK4 with step h (pin.integrate on the manifold)."""
    data = model.createData()
    zero = np.zeros(model.nv)

    def f(q, v):
        return pin.aba(model, data, q, v, zero)

    out, q, v, t = [], q0.copy(), np.zeros(model.nv), 0.0
    for target in times:
        while t < target - 1e-12:
            step = min(h, target - t)
            k1v, k1a = v, f(q, v)
            q2, v2 = pin.integrate(model, q, 0.5 * step * k1v), v + 0.5 * step * k1a
            k2v, k2a = v2, f(q2, v2)
            q3, v3 = pin.integrate(model, q, 0.5 * step * k2v), v + 0.5 * step * k2a
            k3v, k3a = v3, f(q3, v3)
            q4, v4 = pin.integrate(model, q, step * k3v), v + step * k3a
            k4v, k4a = v4, f(q4, v4)
            q = pin.integrate(model, q, step / 6 * (k1v + 2 * k2v + 2 * k3v + k4v))
            v = v + step / 6 * (k1a + 2 * k2a + 2 * k3a + k4a)
            t += step
        out.append(q.copy())
    return out


@pytest.mark.parametrize("name", FIXED)
def test_accelerations_match_pinocchio_aba_along_a_fall(name: str) -> None:
    """At every output time of a free fall, cardan's joint accelerations against ``aba`` at
    cardan's own joint positions and rates: the forward dynamics pointwise, chaos or not."""
    model = pinocchio_model(name)
    data = model.createData()
    results = imported(name, limits=False).dynamics(t_end=1.0, output_dt=0.05, rtol=1e-10, atol=1e-12)
    joints = moving_joints(model)
    worst = 0.0
    for k in range(len(results.t)):
        q, v = pin.neutral(model), np.zeros(model.nv)
        mine = np.zeros(model.nv)
        for jid, jname, prismatic, _ in joints:
            col = f"{sanitize(jname)}.{'slide' if prismatic else 'angle'}"
            set_q(model, q, jid, results.joints[col][k])
            iv = model.joints[jid].idx_v
            v[iv] = results.joint_velocities[col][k]
            mine[iv] = results.joint_accelerations[col][k]
        ddq = pin.aba(model, data, q, v, np.zeros(model.nv))
        worst = max(worst, np.abs(mine - ddq).max() / np.abs(ddq).max())
    print(f"{name}: {len(results.t)} states, |Δq̈|/max|q̈| {worst:.2e}")
    assert worst < 1e-9


# Forward-dynamics horizons: a passive arm whips chaotically, so two integrations part at a rate
# set by the motion; each horizon is where both integrations (tightened tenfold) still agree to
# the tolerance.
HORIZON = {"panda": 1.0, "so100": 1.0, "xarm7": 1.5}


@pytest.mark.parametrize("name", list(ROBOTS))
def test_forward_dynamics_matches_pinocchio_aba(name: str) -> None:
    model = pinocchio_model(name)
    data = model.createData()
    cm = imported(name, limits=False)
    t_end = HORIZON.get(name, 2.0)
    results = cm.dynamics(t_end=t_end, output_dt=t_end / 8, rtol=1e-12, atol=1e-14)
    columns = link_columns(model, cm.text)
    joints = moving_joints(model)
    # The drawn configuration: cardan's joint coordinates at t = 0, the base at the identity.
    q0 = pin.neutral(model)
    for jid, jname, prismatic, _ in joints:
        col = f"{sanitize(jname)}.{'slide' if prismatic else 'angle'}"
        set_q(model, q0, jid, results.joints[col][0])
    qs = aba_trajectory(model, q0, results.t, h=1e-4)
    worst, travel = 0.0, 0.0
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(model, data, q)
        for link, (fid, col) in columns.items():
            p = data.oMf[fid].translation
            mine = np.array([results.points[f"{col}.{c}"][k] for c in "xyz"])
            worst = max(worst, np.abs(mine - p).max())
            travel = max(travel, np.abs(mine - np.array([results.points[f"{col}.{c}"][0] for c in "xyz"])).max())
    print(f"{name}: {len(columns)} links over {t_end} s, travel {travel:.3f} m, |Δx| {worst:.2e} m")
    assert travel > 0.01
    assert worst < 1e-6
