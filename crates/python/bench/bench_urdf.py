"""URDF robots side by side with Pinocchio and MuJoCo (issue 51's performance section): a
7-DOF arm (Franka Panda, 9 joints with its fingers) and a humanoid (Unitree G1, 29 joints,
its root link fixed) of ``example-robot-data``, in one Python process.

- Inverse dynamics of a 10⁴-sample trajectory: every joint driven along
  q_i = c_i + a_i sin(w_i t + φ_i) (as ``crates/python/tests/test_urdf_pinocchio.py``),
  10 s at dt = 1 ms. cardan: the whole analysis (``Model.inverse_dynamics()``: kinematics,
  efforts, reactions, energy, every table in memory); Pinocchio: ``rnea`` in a Python loop;
  MuJoCo: ``mj_inverse`` in a Python loop. The efforts of the three are compared (the worst
  difference against Pinocchio, relative to the largest effort).
- Forward dynamics over 2 s: the robot released at rest in its zero configuration under
  gravity. cardan: its dynamic analysis (DOPRI5, the tolerances given); Pinocchio: ``aba``
  with classical RK4 (h = 1 ms) in a Python loop; MuJoCo: ``mj_step`` with its RK4 (h = 1 ms).
  Each one's joint positions at 0.5 s and 1 s (``MARKS``) against a Pinocchio RK4 reference
  with h = 0.1 ms.

MuJoCo reads the URDF with its own compiler, the visual and collision elements removed (it
reads no COLLADA mesh, and its contacts and joint limits are switched off: the three then
solve the same equations; its damping, friction loss and armature are zeroed).

Run by ``scripts/bench-urdf``; prints a markdown table for docs/performance.md. Times are the
best of three.
"""

import math
import pathlib
import re
import sys
import time

import mujoco
import numpy as np
import pinocchio as pin

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
import test_urdf_pinocchio as T  # noqa: E402

import cardan  # noqa: E402

ROBOTS = {"panda": "Panda (9 joints)", "g1_humanoid": "G1 humanoid (29 joints, fixed root)"}
# The humanoid with its root link fixed (the tests float it): the same joint space for all three.
T.ROBOTS = {**T.ROBOTS, "g1_humanoid": (T.ROBOTS["g1_humanoid"][0], "fixed")}
SAMPLES = 10_001
# The times at which the forward runs are compared with the reference: a falling arm is
# chaotic (the Panda's fingers slide off, its joints spin), so beyond about a second every
# method's difference to the reference is the divergence of nearby motions, not its error.
MARKS = (0.5, 1.0)
DT = 1e-3


def best(f, repeat=3):
    out, times = None, []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return min(times), out


def mujoco_model(name: str) -> mujoco.MjModel:
    text = (T.ROBOTS_DIR / T.ROBOTS[name][0]).read_text()
    text = re.sub(r"<(visual|collision)\b.*?</\1>", "", text, flags=re.S)
    m = mujoco.MjModel.from_xml_string(text)
    m.dof_damping[:] = 0.0
    m.dof_frictionloss[:] = 0.0
    m.dof_armature[:] = 0.0
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    return m


def inverse(name: str) -> dict:
    model = pin.buildModelFromUrdf(str(T.ROBOTS_DIR / T.ROBOTS[name][0]))
    data = model.createData()
    joints = T.moving_joints(model)
    law = T.trajectory(joints, seed=len(name))
    cm = T.overlay(name, joints, law, t_end=(SAMPLES - 1) * DT, dt=DT)
    t_cardan, results = best(cm.inverse_dynamics)
    assert len(results.t) == SAMPLES
    states = [T.pin_state(model, joints, law, t) for t in results.t]

    def rnea():
        return [pin.rnea(model, data, q, v, a).copy() for q, v, a in states]

    t_pin, taus = best(rnea)
    m = mujoco_model(name)
    d = mujoco.MjData(m)
    # MuJoCo's dofs by name, in Pinocchio's velocity order.
    order = [m.joint(jname).dofadr[0] for _, jname, _, _ in joints]
    qadr = [m.joint(jname).qposadr[0] for _, jname, _, _ in joints]
    pin_idx = [model.joints[jid].idx_v for jid, _, _, _ in joints]
    law_of = list(zip(qadr, order, law))

    def mj_inverse():
        out = []
        for t in results.t:
            for qa, va, (c, a, w, phi) in law_of:
                s, co = math.sin(w * t + phi), math.cos(w * t + phi)
                d.qpos[qa] = c + a * s
                d.qvel[va] = a * w * co
                d.qacc[va] = -a * w * w * s
            mujoco.mj_inverse(m, d)
            out.append(d.qfrc_inverse[order].copy())
        return out

    t_mj, mj_taus = best(mj_inverse)
    efforts = results.driver_efforts
    scale = max(np.abs(tau).max() for tau in taus)
    worst_c = worst_m = 0.0
    for k, tau in enumerate(taus):
        for col, (_, jname, prismatic, _) in enumerate(joints):
            ref = tau[pin_idx[col]]
            mine = efforts[f"d_{T.sanitize(jname)}.{'force' if prismatic else 'torque'}"][k]
            worst_c = max(worst_c, abs(mine - ref))
            worst_m = max(worst_m, abs(mj_taus[k][col] - ref))
    return {"cardan": t_cardan, "pin": t_pin, "mj": t_mj, "dc": worst_c / scale, "dm": worst_m / scale}


def rk4_pin(model, q0, t_end, h):
    """Pinocchio's ``aba`` with classical RK4 from rest to ``t_end`` (the tests' integration,
    ``test_urdf_pinocchio.aba_trajectory``): q at each of ``MARKS``."""
    qs = T.aba_trajectory(model, q0, np.array([*MARKS, t_end]), h)
    return dict(zip(MARKS, qs))


def forward(name: str, rtol: float) -> dict:
    path = T.ROBOTS_DIR / T.ROBOTS[name][0]
    model = pin.buildModelFromUrdf(str(path))
    joints = T.moving_joints(model)
    # Every robot here has 1-DOF joints with nq = nv (no continuous joint).
    assert model.nq == model.nv
    cm = cardan.load(path, limits=False, mimic="free")
    t_end = 2.0
    t_cardan, results = best(lambda: cm.dynamics(t_end=t_end, output_dt=0.5, rtol=rtol, atol=rtol * 1e-2))
    q0 = pin.neutral(model)
    for jid, jname, prismatic, _ in joints:
        q0[model.joints[jid].idx_q] = results.joints[f"{T.sanitize(jname)}.{'slide' if prismatic else 'angle'}"][0]
    reference = rk4_pin(model, q0, t_end, 1e-4)
    t_pin, mine_pin = best(lambda: rk4_pin(model, q0, t_end, 1e-3))
    m = mujoco_model(name)
    m.opt.integrator = int(mujoco.mjtIntegrator.mjINT_RK4)
    m.opt.timestep = 1e-3
    d = mujoco.MjData(m)
    qadr = [m.joint(jname).qposadr[0] for _, jname, _, _ in joints]
    idx = [model.joints[jid].idx_q for jid, _, _, _ in joints]

    def mj_run():
        mujoco.mj_resetData(m, d)
        d.qpos[qadr] = q0[idx]
        out = {}
        for step in range(1, int(round(t_end / 1e-3)) + 1):
            mujoco.mj_step(m, d)
            for mark in MARKS:
                if abs(step * 1e-3 - mark) < 1e-9:
                    out[mark] = d.qpos[qadr].copy()
        return out

    t_mj, mine_mj = best(mj_run)

    def cardan_q(k):
        return np.array([results.joints[f"{T.sanitize(j)}.{'slide' if p else 'angle'}"][k] for _, j, p, _ in joints])

    k_of = {mark: int(np.argmin(np.abs(results.t - mark))) for mark in MARKS}
    def off(q, mk):
        # cardan's angles are continued over turns along its steps, as Pinocchio's q is.
        return np.abs(q - reference[mk][idx]).max()

    err = {
        "cardan": [off(cardan_q(k_of[mk]), mk) for mk in MARKS],
        "pin": [off(mine_pin[mk][idx], mk) for mk in MARKS],
        "mj": [off(mine_mj[mk], mk) for mk in MARKS],
    }
    return {"cardan": t_cardan, "pin": t_pin, "mj": t_mj, "err": err}


def main() -> None:
    print("| robot | cardan inverse dynamics (10⁴ samples, whole analysis) | Pinocchio `rnea` loop | MuJoCo `mj_inverse` loop | cardan / Pinocchio | cardan / MuJoCo | efforts vs Pinocchio: cardan, MuJoCo |")
    print("|---|---|---|---|---|---|---|")
    for name, label in ROBOTS.items():
        r = inverse(name)
        print(
            f"| {label} | {r['cardan']:.2f} s ({r['cardan'] / SAMPLES * 1e6:.0f} µs) | {r['pin']:.3f} s ({r['pin'] / SAMPLES * 1e6:.1f} µs) "
            f"| {r['mj']:.3f} s ({r['mj'] / SAMPLES * 1e6:.1f} µs) | {r['cardan'] / r['pin']:.0f}× | {r['cardan'] / r['mj']:.0f}× | {r['dc']:.1e}, {r['dm']:.1e} |"
        )
    print()
    print("| robot | cardan DOPRI5 (rtol) | Pinocchio `aba` RK4 h = 1 ms | MuJoCo RK4 h = 1 ms | max \\|Δq\\| at 0.5 s / 1 s: cardan, Pinocchio, MuJoCo |")
    print("|---|---|---|---|---|")
    for name, label in ROBOTS.items():
        for rtol in (1e-6, 1e-9):
            r = forward(name, rtol)
            e = r["err"]
            print(
                f"| {label} | {r['cardan']:.3f} s ({rtol:.0e}) | {r['pin']:.3f} s | {r['mj']:.3f} s "
                f"| {e['cardan'][0]:.1e} / {e['cardan'][1]:.1e}, {e['pin'][0]:.1e} / {e['pin'][1]:.1e}, {e['mj'][0]:.1e} / {e['mj'][1]:.1e} |"
            )


if __name__ == "__main__":
    main()
