"""Peer models for `cargo xtask bench --peers`: the same mechanisms as cardan's benchmarks, built in
OndselSolver (pyondsel, kinematics) and Exudyn (dynamics). Each command prints one line
`RESULT key=value ...` (times exclude Python start-up and imports; they are measured around the
solver call only).

  python peers.py check
  python peers.py ondsel-slider-crank FRAMES        # spatial slider-crank, crank at 2*pi rad/s, t in [0, 1]
  python peers.py exudyn-chain N H T_END            # N spherical-joint links, generalized-alpha, step H

Models (see crates/bench/src/models.rs and examples/slider_crank.toml for cardan's side):
- slider-crank: Haug's spatial slider-crank (ground A = (0, 0.1, 0.12), crank AB along z of length
  0.08, ball joint at B = (0, 0.1, 0.2), universal joint at C = (0.2, 0, 0) with arms along
  (0, 2, -1)/sqrt(5) (conrod) and x (slider), slider on x).
- chain: rods of length 1 m, mass 1 kg, inertia diag(0.001, 1/12, 1/12) about the centre, along +x
  at rest, spherical joints (the first to the ground at the origin), gravity -z.
pyondsel needs plain Python floats in its model text (never numpy scalars).
"""

import math
import warnings

warnings.filterwarnings("ignore")
import sys
import time


def result(**kw):
    print("RESULT " + " ".join(f"{k}={v}" for k, v in kw.items()), flush=True)


def check():
    import exudyn  # noqa: F401
    import pyondsel  # noqa: F401
    from importlib.metadata import version
    result(exudyn=version("exudyn"), pyondsel=version("pyondsel"))


# --------------------------------------------------------------------------------------------
# OndselSolver

Z_ALONG_X = ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))


def _u_arm():
    s = 1.0 / math.sqrt(5.0)
    # Columns: marker x = (1,0,0), y = z cross x, z = (0, 2, -1)/sqrt(5).
    return ((1.0, 0.0, 0.0), (0.0, -s, 2.0 * s), (0.0, -2.0 * s, -s))


def slider_crank_asmt(frames, transpose=False):
    from pyondsel.model.asmt_model import AsmtModel
    from pyondsel.model.joint import Joint
    from pyondsel.model.marker import Marker
    from pyondsel.model.motion import Motion
    from pyondsel.model.part import Part
    from pyondsel.model.simulation import Simulation

    def rot(m):
        m = tuple(tuple(float(v) for v in r) for r in m)
        return tuple(zip(*m)) if transpose else m

    a = AsmtModel(name="Assembly")
    a.add_ground_marker(Marker("A", (0.0, 0.1, 0.12), rot(Z_ALONG_X)))
    a.add_ground_marker(Marker("O", (0.0, 0.0, 0.0), rot(Z_ALONG_X)))
    crank = Part("crank", position=(0.0, 0.1, 0.16), mass=0.12,
                 moments_of_inertia=(1e-4, 1e-4, 1e-5))
    crank.add_marker(Marker("A", (0.0, 0.0, -0.04), rot(Z_ALONG_X)))
    crank.add_marker(Marker("B", (0.0, 0.0, 0.04)))
    conrod = Part("conrod", position=(0.1, 0.05, 0.1), mass=0.5,
                  moments_of_inertia=(4e-4, 4e-3, 4e-3))
    conrod.add_marker(Marker("B", (-0.1, 0.05, 0.1)))
    conrod.add_marker(Marker("C", (0.1, -0.05, -0.1), rot(_u_arm())))
    slider = Part("slider", position=(0.2, 0.0, 0.0), mass=2.0,
                  moments_of_inertia=(1e-4, 1e-4, 1e-4))
    slider.add_marker(Marker("C", (0.0, 0.0, 0.0), rot(Z_ALONG_X)))
    for p in (crank, conrod, slider):
        a.add_part(p)
    a.add_joint(Joint("crank_pin", "revolute", a.ground_path("A"), a.part_path("crank", "A")))
    a.add_joint(Joint("ball", "spherical", a.part_path("crank", "B"), a.part_path("conrod", "B")))
    a.add_joint(Joint("cross", "universal", a.part_path("conrod", "C"), a.part_path("slider", "C")))
    a.add_joint(Joint("slide", "translational", a.ground_path("O"), a.part_path("slider", "C")))
    a.add_motion(Motion("motor", "crank_pin", "2.0*pi*time"))
    a.simulation = Simulation(t_start=0.0, t_end=1.0, frames=int(frames), error_tol=1e-10)
    return a


def ondsel_slider_crank(frames):
    from pyondsel.asmt_solver import AsmtSolver
    from pyondsel.solve_raw import solve_asmt_raw

    frames = int(frames)
    best = None
    for transpose in (False, True):
        text = slider_crank_asmt(frames, transpose).to_asmt()
        one = slider_crank_asmt(1, transpose).to_asmt()
        solve_asmt_raw(one)  # warm-up
        t_one = min(_timed(lambda: solve_asmt_raw(one)) for _ in range(3))
        runs = []
        for _ in range(3):
            t0 = time.perf_counter()
            out = solve_asmt_raw(text)
            runs.append(time.perf_counter() - t0)
        traj = AsmtSolver()._parse(out)
        slider = [v for k, v in traj.parts.items() if k.endswith("/slider") or k == "slider"]
        xs = [p[0] for p in slider[0].positions] if slider else []
        # Slider x at t = 0.25: the crank is then at 90 degrees.
        cand = dict(transpose=int(transpose), t_total=min(runs), t_one=t_one,
                    per_frame=(min(runs) - t_one) / max(frames - 1, 1),
                    frames=len(traj.times), x_quarter=xs[frames // 4] if len(xs) > frames // 4 else float("nan"),
                    x_half=xs[frames // 2] if len(xs) > frames // 2 else float("nan"))
        if best is None or (math.isfinite(cand["x_quarter"]) and not math.isfinite(best["x_quarter"])):
            best = cand
        if transpose is False and math.isfinite(cand["x_quarter"]):
            best = cand
            break
    result(**best)


def _timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


# --------------------------------------------------------------------------------------------
# Exudyn

def exudyn_chain(n, h, t_end):
    import exudyn as exu
    import numpy as np
    from exudyn.utilities import RigidBodyInertia

    n, h, t_end = int(n), float(h), float(t_end)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    inertia = RigidBodyInertia(mass=1.0, inertiaTensor=np.diag([0.001, 1.0 / 12.0, 1.0 / 12.0]))
    prev = ground
    last = None
    first_body = None
    for k in range(n):
        b = mbs.CreateRigidBody(inertia=inertia, referencePosition=[k + 0.5, 0.0, 0.0],
                                gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
        mbs.CreateSphericalJoint(itemNumbers=[prev, b], position=[float(k), 0.0, 0.0])
        if first_body is None:
            first_body = b
        prev = b
        last = b
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(t_end / h))
    s.timeIntegration.endTime = t_end
    s.timeIntegration.verboseMode = 0
    s.timeIntegration.generalizedAlpha.spectralRadius = 0.8
    s.solutionSettings.writeSolutionToFile = False
    s.solutionSettings.sensorsWritePeriod = t_end
    s.linearSolverType = exu.LinearSolverType.EigenSparse
    s.displayStatistics = False
    s.displayComputationTime = False
    t0 = time.perf_counter()
    mbs.SolveDynamic(s)
    wall = time.perf_counter() - t0
    tip = mbs.GetObjectOutputBody(last, exu.OutputVariableType.Position, localPosition=[0.5, 0.0, 0.0],
                                  configuration=exu.ConfigurationType.Current)
    first = mbs.GetObjectOutputBody(first_body, exu.OutputVariableType.Position,
                                    localPosition=[0.5, 0.0, 0.0], configuration=exu.ConfigurationType.Current)
    result(wall=wall, steps=s.timeIntegration.numberOfSteps,
           tip_x=float(tip[0]), tip_y=float(tip[1]), tip_z=float(tip[2]),
           b0_x=float(first[0]), b0_y=float(first[1]), b0_z=float(first[2]))


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"check": check, "ondsel-slider-crank": ondsel_slider_crank, "exudyn-chain": exudyn_chain}[cmd](*args)
