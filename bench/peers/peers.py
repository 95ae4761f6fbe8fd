"""Peer models for `cargo xtask bench --peers`: the same mechanisms as cardan's benchmarks, built in
OndselSolver (pyondsel, kinematics) and Exudyn (dynamics). Each command prints one line
`RESULT key=value ...` (times exclude Python start-up and imports; they are measured around the
solver call only).

  python peers.py check
  python peers.py ondsel-slider-crank FRAMES        # spatial slider-crank, crank at 2*pi rad/s, t in [0, 1]
  python peers.py exudyn-chain N H T_END            # N spherical-joint links, generalized-alpha, step H
  python peers.py exudyn-slider-crank H T_END [CSV] # IFToMM spatial slider-crank, generalized-alpha, step H

Models (see crates/bench/src/models.rs and examples/slider_crank.toml for cardan's side):
- slider-crank: Haug's spatial slider-crank (ground A = (0, 0.1, 0.12), crank AB along z of length
  0.08, ball joint at B = (0, 0.1, 0.2), universal joint at C = (0.2, 0, 0) with arms along
  (0, 2, -1)/sqrt(5) (conrod) and x (slider), slider on x).
- IFToMM spatial rigid slider-crank (examples/slider_crank_dynamic.toml; problem definition in
  shared/benchmarks/README.md section 2.6): the same geometry, free motion under gravity -z from
  crank omega = 6 rad/s, crank centre of mass at its midpoint, U-joint cross = slider x and the
  conrod's y axis (0, 2, -1)/sqrt(5). Error: max over the reference samples (every 0.05 s of
  tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv) of |C - (x_ref, 0, 0)| (slider) and
  |B - B_ref(theta_ref)| (crank tip), exactly as tests/tests/benchmark_slider_crank.rs.
- chain: rods of length 1 m, mass 1 kg, inertia diag(0.001, 1/12, 1/12) about the centre, along +x
  at rest, spherical joints (the first to the ground at the origin), gravity -z.
pyondsel needs plain Python floats in its model text (never numpy scalars).
Exudyn is imported as its "fast" build (sys.exudynFast: the same solver without range checks, about
10 % faster here), so the peer runs in its quickest stock configuration.
"""

import math
import warnings

warnings.filterwarnings("ignore")
import sys
import time


def result(**kw):
    print("RESULT " + " ".join(f"{k}={v}" for k, v in kw.items()), flush=True)


def _exudyn():
    sys.exudynFast = True  # read by exudyn/__init__.py: the build without range checks
    import exudyn
    return exudyn


def check():
    _exudyn()
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
    exu = _exudyn()
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


SLIDER_CRANK_CSV = "tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv"
G = 9.81  # m/s^2, gravity along -z
SLIDER_X0 = 0.2  # m, the slider's reference (initial) x: the U-joint C = (0.2, 0, 0)
# The slider-crank's bodies: name, mass [kg], inertia about the centre of mass in body axes
# [kg m^2] (the bodies' reference points are their centres of mass).
SLIDER_CRANK_BODIES = [("crank", 0.12, (1e-4, 1e-4, 1e-5)), ("conrod", 0.5, (4e-4, 4e-3, 4e-3)),
                       ("slider", 2.0, (1e-4, 1e-4, 1e-4))]


def exudyn_slider_crank_model(mbs):
    """Adds the IFToMM spatial slider-crank to mbs: the ground, three rigid bodies
    (Euler-parameter nodes, the default) with their initial velocities and gravity as body loads,
    CreateRevoluteJoint (crank, axis x at A), CreateSphericalJoint (B), CreateGenericJoint with
    the rotation about the joint z axis locked (universal joint at C: free about the slider's x
    and the conrod's y), CreatePrismaticJoint (slider along x). Returns the body numbers
    (crank, rod, slider)."""
    import numpy as np
    from exudyn.utilities import RigidBodyInertia

    (_, m_crank, j_crank), (_, m_rod, j_rod), (_, m_slider, j_slider) = SLIDER_CRANK_BODIES
    g = [0.0, 0.0, -G]
    ground = mbs.CreateGround()
    # Crank: body frame = global at t = 0 (x = rotation axis, z along the crank), CoM mid A-B.
    crank = mbs.CreateRigidBody(inertia=RigidBodyInertia(m_crank, np.diag(j_crank)),
                                referencePosition=[0.0, 0.1, 0.16], initialVelocity=[0.0, -0.24, 0.0],
                                initialAngularVelocity=[6.0, 0.0, 0.0], gravity=g)
    # Conrod: body x along B -> C, y = the U-joint arm (0, 2, -1)/sqrt(5), z = x cross y.
    ex = np.array([2.0, -1.0, -2.0]) / 3.0
    ey = np.array([0.0, 2.0, -1.0]) / math.sqrt(5.0)
    rod = mbs.CreateRigidBody(inertia=RigidBodyInertia(m_rod, np.diag(j_rod)),
                              referencePosition=[0.1, 0.05, 0.1],
                              referenceRotationMatrix=np.column_stack([ex, ey, np.cross(ex, ey)]),
                              initialVelocity=[0.12, -0.24, 0.0],
                              initialAngularVelocity=[1.92, -0.96, 0.48], gravity=g)
    slider = mbs.CreateRigidBody(inertia=RigidBodyInertia(m_slider, np.diag(j_slider)),
                                 referencePosition=[SLIDER_X0, 0.0, 0.0],
                                 initialVelocity=[0.24, 0.0, 0.0], gravity=g)
    mbs.CreateRevoluteJoint(itemNumbers=[ground, crank], position=[0.0, 0.1, 0.12],
                            axis=[1.0, 0.0, 0.0])
    mbs.CreateSphericalJoint(itemNumbers=[crank, rod], position=[0.0, 0.1, 0.2])
    # Universal joint: joint frame x = slider x (free), y = conrod arm (free), z locked, i.e.
    # x_slider . y_rod = 0 (Haug's DP1), plus coincident points.
    ux = np.array([1.0, 0.0, 0.0])
    mbs.CreateGenericJoint(itemNumbers=[slider, rod], position=[SLIDER_X0, 0.0, 0.0],
                           rotationMatrixAxes=np.column_stack([ux, ey, np.cross(ux, ey)]),
                           constrainedAxes=[1, 1, 1, 0, 0, 1])
    mbs.CreatePrismaticJoint(itemNumbers=[ground, slider], position=[SLIDER_X0, 0.0, 0.0],
                             axis=[1.0, 0.0, 0.0])
    return crank, rod, slider


def exudyn_slider_crank_sensors(mbs, crank, rod, slider):
    """Position sensors stored in memory (C++ sensors, no Python per step) on the slider-crank of
    exudyn_slider_crank_model: the crank tip B, the slider's C, and for the energy each body's
    centre-of-mass position and velocity and its body-frame angular velocity. Returns
    (sensor B, sensor C, [(mass, inertia diagonal, (position, velocity, angular velocity
    sensors)) for each body])."""
    exu = _exudyn()
    import numpy as np
    from exudyn.itemInterface import SensorBody

    pos = exu.OutputVariableType.Position
    s_b = mbs.AddSensor(SensorBody(bodyNumber=crank, localPosition=[0.0, 0.0, 0.04],
                                   storeInternal=True, outputVariableType=pos))
    s_c = mbs.AddSensor(SensorBody(bodyNumber=slider, localPosition=[0.0, 0.0, 0.0],
                                   storeInternal=True, outputVariableType=pos))
    energy_sensors = []
    for body, (_, m, j) in zip([crank, rod, slider], SLIDER_CRANK_BODIES):
        kinds = [pos, exu.OutputVariableType.Velocity,
                 exu.OutputVariableType.AngularVelocityLocal]
        energy_sensors.append((m, np.array(j), [mbs.AddSensor(SensorBody(
            bodyNumber=body, storeInternal=True, outputVariableType=k)) for k in kinds]))
    return s_b, s_c, energy_sensors


def exudyn_fixed_step_settings(h, t_end, write_period):
    """Exudyn's dynamic solver settings (otherwise its defaults) for a fixed step h to t_end,
    quiet, no solution file, the sensors stored every write_period. Returns (settings, steps)."""
    exu = _exudyn()

    s = exu.SimulationSettings()
    steps = int(round(t_end / h))
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.endTime = t_end
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = write_period
    s.displayStatistics = False
    s.displayComputationTime = False
    return s, steps


def exudyn_solve(mbs, s):
    """mbs.SolveDynamic(s): the wall time of the solver call and the solver's iteration counters
    (newtonStepsCount, newtonJacobiCount, ...)."""
    t0 = time.perf_counter()
    mbs.SolveDynamic(s, storeSolver=True)
    wall = time.perf_counter() - t0
    return wall, mbs.sys["dynamicSolver"].it


def exudyn_slider_crank(h, t_end, csv=None):
    """The IFToMM spatial slider-crank in Exudyn (exudyn_slider_crank_model). Generalized-alpha
    (Exudyn's default dynamic solver and settings: rho_inf 0.9, modified Newton, relative
    tolerance 1e-8, dense linear solver), fixed step h."""
    exu = _exudyn()
    import numpy as np

    h, t_end = float(h), float(t_end)
    if csv is None:
        import os
        csv = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", SLIDER_CRANK_CSV)
    with open(csv) as f:
        rows = [[float(x) for x in line.split(",")] for line in f
                if line.strip() and not line.startswith("#")]
    rows = [r for r in rows if r[0] <= t_end + 1e-9]
    spacing = rows[1][0] - rows[0][0]

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    crank, rod, slider = exudyn_slider_crank_model(mbs)
    # Positions stored at the reference spacing.
    s_b, s_c, energy_sensors = exudyn_slider_crank_sensors(mbs, crank, rod, slider)
    mbs.Assemble()

    s, steps = exudyn_fixed_step_settings(h, t_end, spacing)
    wall, it = exudyn_solve(mbs, s)

    b = mbs.GetSensorStoredData(s_b)
    c = mbs.GetSensorStoredData(s_c)
    err = 0.0
    for r in rows:
        k = int(np.argmin(np.abs(b[:, 0] - r[0])))
        if abs(b[k, 0] - r[0]) > 1e-9:
            raise SystemExit(f"no sample at t = {r[0]} (h = {h} must divide {spacing})")
        x, th = r[1], r[2]
        b_ref = np.array([0.0, 0.1 - 0.08 * math.sin(th), 0.12 + 0.08 * math.cos(th)])
        err = max(err, float(np.linalg.norm(b[k, 1:4] - b_ref)),
                  float(np.linalg.norm(c[k, 1:4] - np.array([x, 0.0, 0.0]))))
    energy = 0.0
    for m, j, (sp, sv, sw) in energy_sensors:
        p, v, w = (mbs.GetSensorStoredData(x) for x in (sp, sv, sw))
        energy = energy + 0.5 * m * np.sum(v[:, 1:4] ** 2, axis=1) \
            + 0.5 * np.sum(j * w[:, 1:4] ** 2, axis=1) + m * G * p[:, 3]
    times = b[:, 0]
    at_rows = [int(np.argmin(np.abs(times - r[0]))) for r in rows]
    energy_err = float(np.max(np.abs(energy[at_rows] - energy[0])))
    energy_end = float(energy[at_rows[-1]] - energy[0])
    result(wall=wall, steps=steps, err=err, energy_err=energy_err, energy_end=energy_end,
           samples=len(rows),
           newton=it.newtonStepsCount,
           jacobians=it.newtonJacobiCount, x_end=float(c[-1, 1]))


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"check": check, "ondsel-slider-crank": ondsel_slider_crank, "exudyn-chain": exudyn_chain,
     "exudyn-slider-crank": exudyn_slider_crank}[cmd](*args)
