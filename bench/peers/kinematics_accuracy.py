"""OndselSolver's work-precision point on the spatial slider-crank (issue 25).

    python bench/peers/kinematics_accuracy.py FRAMES ERROR_TOL

Solves the slider-crank of peers.py (the model of examples/slider_crank.toml) over one crank
turn in FRAMES frames with OndselSolver's errorTol = ERROR_TOL and prints one line

    RESULT per_frame=... error=... frames=...

per_frame: (solve of FRAMES frames − solve of 1 frame) / (FRAMES − 1), the best of 3 solves
(assembly and setup excluded, as in peers.py); error: the largest distance [m] of the slider
point C and the crank's centre of mass from the closed form over all frames, at the times
OndselSolver reports (it sums its output steps: frame 30 of 50 is at t = 0.6000000000000002),

    B(θ) = (0, 0.1 − 0.08 sin θ, 0.12 + 0.08 cos θ),  x_C = √(0.09 − B_y² − B_z²),
    crank centre = (A + B) / 2,  θ = 2πt.
"""

import math
import sys
import time

from peers import _timed, result, slider_crank_asmt


def closed_form(t):
    th = 2.0 * math.pi * t
    by, bz = 0.1 - 0.08 * math.sin(th), 0.12 + 0.08 * math.cos(th)
    x = math.sqrt(0.09 - by * by - bz * bz)
    return (x, 0.0, 0.0), (0.0, (0.1 + by) / 2.0, (0.12 + bz) / 2.0)


def model_text(frames, tol):
    a = slider_crank_asmt(frames)
    a.simulation.error_tol = tol
    text = a.to_asmt()
    return text


def main():
    from pyondsel.asmt_solver import AsmtSolver
    from pyondsel.solve_raw import solve_asmt_raw

    frames, tol = int(sys.argv[1]), float(sys.argv[2])
    text = model_text(frames, tol)
    one = model_text(1, tol)
    solve_asmt_raw(one)  # warm-up
    t_one = min(_timed(lambda: solve_asmt_raw(one)) for _ in range(3))
    runs = []
    for _ in range(3):
        t0 = time.perf_counter()
        out = solve_asmt_raw(text)
        runs.append(time.perf_counter() - t0)
    traj = AsmtSolver()._parse(out)
    parts = {k.split("/")[-1]: v for k, v in traj.parts.items()}
    err = 0.0
    for k, t in enumerate(traj.times):
        c, m = closed_form(t)
        for name, want in (("slider", c), ("crank", m)):
            got = parts[name].positions[k]
            err = max(err, max(abs(float(g) - w) for g, w in zip(got, want)))
    result(per_frame=(min(runs) - t_one) / max(frames - 1, 1), error=err, frames=len(traj.times))


if __name__ == "__main__":
    main()
