"""Peer comparison with MuJoCo for contact between bodies (issue 50): the billiard ball of
examples/billiard.toml (a solid ball, m = 0.17 kg, r = 28.575 mm, launched sliding at
v0 = 2 m/s without spin on a table, mu = 0.2), run in cardan and in MuJoCo at a ladder of
accuracies, each run's error against Routh's closed form and its wall time. Not part of any
test suite.

  target/peers-venv/bin/python bench/peers/contact_mujoco.py [CARDAN]

  CARDAN  the cardan binary (default target/release/cardan)

Closed form (a rigid contact): sliding v(t) = v0 - mu g t until t_r = 2 v0 / (7 mu g) =
0.2913 s, then rolling at 5 v0 / 7. Error of a run = max(|v(t_r/2) - (v0 - mu g t_r/2)|,
|v(2 t_r) - 5 v0/7|). (cardan's compliant contact rolls on r - delta/2, delta = 6.5 um for
K = 1e8: 6.6e-5 m/s below 5 v0/7, which sets its error floor against this rigid closed form;
MuJoCo's soft contact has its own.)

cardan: the example with DOPRI5 at rtol 1e-4 ... 1e-10 (atol = rtol / 100) and generalized-alpha
at h = 32 ... 0.5 ms; time = run.json's wall_time_s (the analysis: assembly, integration and
its tables; reading the file and writing the output files excluded), best of 3. MuJoCo 4.0.1: the same ball (a sphere geom with
a free joint, mass 0.17 kg, friction 0.2) on a plane, integrator implicitfast, elliptic cones,
its default soft contact (solref 0.02 1), timestep 4 ... 0.125 ms; time = one mj_step(m, d, N)
call over 2 t_r, best of 3.

Prints `RESULT code=... setting=... error=... time=...` lines.
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import mujoco
import numpy as np

V0, MU, G, R, M = 2.0, 0.2, 9.81, 0.028575, 0.17
T_ROLL = 2 * V0 / (7 * MU * G)
T_END = 2 * T_ROLL
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")


def error(v_half, v_end):
    return max(abs(v_half - (V0 - MU * G * T_ROLL / 2)), abs(v_end - 5 * V0 / 7))


def mujoco_run(h):
    xml = f"""<mujoco>
  <option timestep="{h}" gravity="0 0 -{G}" integrator="implicitfast" cone="elliptic"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1" friction="{MU} 0 0"/>
    <body pos="0 0 {R}"><freejoint/><geom type="sphere" size="{R}" mass="{M}" friction="{MU} 0 0"/></body>
  </worldbody>
</mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    best = float("inf")
    for _ in range(3):
        d = mujoco.MjData(m)
        d.qvel[0] = V0
        n_half = round(T_ROLL / 2 / h)
        mujoco.mj_step(m, d, n_half)
        # The speed at the step nearest t_r/2, corrected to t_r/2 by the sliding deceleration.
        v_half = d.qvel[0] + MU * G * (n_half * h - T_ROLL / 2)
        d = mujoco.MjData(m)
        d.qvel[0] = V0
        n = round(T_END / h)
        start = time.perf_counter()
        mujoco.mj_step(m, d, n)
        best = min(best, time.perf_counter() - start)
        v_end = d.qvel[0]
    return error(v_half, v_end), best


def cardan_run(cardan, analysis, k_material=2e8):
    """The example's ball with each material's stiffness `k_material` (the pair's K is half),
    drawn at its static penetration (m g / K)^(2/3)."""
    text = open(os.path.join(ROOT, "examples", "billiard.toml")).read()
    head = text[: text.index("[analysis]")]
    delta = (M * G / (k_material / 2)) ** (2 / 3)
    head = head.replace("stiffness = 2e8", f"stiffness = {k_material:g}")
    head = re.sub(r"position = \[0.0, 0.0, [0-9.e-]+\]", f"position = [0.0, 0.0, {R - delta!r}]", head)
    model = head + analysis + f"\noutput_dt = {T_ROLL / 2}\nt_end = {T_END}\n\n[analysis.outputs]\nbodies = [\"ball\"]\n"
    best, err = float("inf"), None
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "billiard.toml")
        open(path, "w").write(model)
        for _ in range(3):
            subprocess.run([cardan, "run", path, "-o", os.path.join(tmp, "out"), "--quiet"],
                           capture_output=True, text=True, check=True)
            wall = json.load(open(os.path.join(tmp, "out", "run.json")))["wall_time_s"]
            best = min(best, wall)
            rows = open(os.path.join(tmp, "out", "body_velocities.csv")).read().splitlines()[1:]
            v = [float(r.split(",")[1]) for r in rows]
            err = error(v[1], v[-1])
    return err, best


def main():
    cardan = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "release", "cardan")
    # The example's contact (K = 1e8 N/m^1.5 for the pair: the ball sinks 6.5 um) and a stiff one
    # sinking as little as Exudyn's penalty contact in contact_exudyn.py (0.17 um).
    for k in [2e8, 4.8e10]:
        for rtol in [1e-4, 1e-6, 1e-8, 1e-10]:
            analysis = f'[analysis]\nkind = "dynamic"\nintegrator = "dopri5"\nrtol = {rtol}\natol = {rtol / 100}\n'
            e, t = cardan_run(cardan, analysis, k)
            print(f"RESULT code=cardan setting=K_{k / 2:g}_dopri5_rtol_{rtol:g} error={e:.3e} time={t:.4e}")
        for h in [3.2e-2, 1.6e-2, 8e-3, 4e-3, 2e-3, 1e-3, 5e-4]:
            analysis = f'[analysis]\nkind = "dynamic"\nintegrator = "generalized_alpha"\ndt = {h}\n'
            e, t = cardan_run(cardan, analysis, k)
            print(f"RESULT code=cardan setting=K_{k / 2:g}_genalpha_h_{h:g} error={e:.3e} time={t:.4e}")
    for h in [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4]:
        e, t = mujoco_run(h)
        print(f"RESULT code=mujoco setting=h_{h:g} error={e:.3e} time={t:.4e}")


if __name__ == "__main__":
    main()
