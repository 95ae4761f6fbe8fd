"""Peer comparison with Exudyn for contact between bodies (issue 50): the billiard ball of
examples/billiard.toml (a solid ball, m = 0.17 kg, r = 28.575 mm, J = 2/5 m r^2, launched sliding
at v0 = 2 m/s without spin on a table, mu = 0.2), run in Exudyn at a ladder of accuracies, each
run's error against Routh's closed form and its wall time. The Exudyn side only: cardan's runs of
the same ball are in bench/peers/contact_mujoco.py. Not part of any test suite.

  target/peers-venv/bin/python bench/peers/contact_exudyn.py

Closed form (a rigid contact): sliding v(t) = v0 - mu g t until t_r = 2 v0 / (7 mu g) =
0.2913 s, then rolling at 5 v0 / 7. Error of a run = max(|v(t_r/2) - (v0 - mu g t_r/2)|,
|v(2 t_r) - 5 v0/7|), v the x-velocity of the ball's centre, T_END = 2 t_r; v(t_r/2) linearly
interpolated between the stored steps (v is linear there, while it slides).

Exudyn 1.13.6 (its "fast" build, sys.exudynFast, as bench/peers/peers.py), one thread:
- Contact: GeneralContact (mbs.AddGeneralContact()), the ball a sphere on a rigid marker at its
  centre (gContact.AddSphereWithMarker(marker, radius=r, contactStiffness=2e7,
  contactDamping=184.75, frictionMaterialIndex=0)), the table two static triangles of a 4 m x 4 m
  square at z = 0 with normals +z on a ground marker (gContact.AddTrianglesRigidBodyBased(marker,
  contactStiffness=2e7, contactDamping=0, frictionMaterialIndex=0, pointList, triangleList,
  staticTriangles=True)), search tree box [-2, 2] x [-2, 2] x [-0.1, 0.1] with 4 x 4 x 1 cells.
  Exudyn puts the two stiffnesses in series and the dampers in parallel (the same convention as
  billiard.toml's "each"), so the pair is a linear penalty k = 1e7 N/m, d = 184.75 N s/m:
  damping ratio 0.0709 of 2 sqrt(k m), restitution 0.8 for this spring-dashpot (billiard.toml's
  value); keepContactWhilePenetrating = False (the default: the damper never pulls). The ball
  starts at its static equilibrium z = r - m g / k (penetration 0.167 um; it stays there to
  1e-15 m with generalized-alpha, 5e-9 m with DOPRI5 at rtol 1e-4: no bounce).
- Friction: gContact.SetFrictionPairings(0.2 * np.eye(1)) (Coulomb, static = dynamic), regularized
  linearly below frictionProportionalZone = 1e-3 m/s (Exudyn's default, 10 times billiard.toml's
  slip_velocity 1e-4): force mu N v_t / 1e-3 below it. The regularization hardly changes the
  errors: at 1e-2, 1e-3 and 1e-4 m/s they agree to 5 % (to 3 digits at h = 0.25 ms), since
  v(t_r/2) is taken with 1 m/s of slip and the rolling speed is set by the angular momentum
  about the contact point, whatever the friction law in between. The zone changes the cost:
  1e-4 makes DOPRI5 take 4 times as many steps (a stiff stick phase); 1e-2 lets
  generalized-alpha keep every fixed step at h = 4 and 2 ms (1e-3 needs step reductions there,
  below).
- The ball: mbs.CreateRigidBody(inertia=RigidBodyInertia(m, J I), referencePosition=[0, 0, z0],
  initialVelocity=[2, 0, 0], initialAngularVelocity=[0, 0, 0], gravity=[0, 0, -9.81], nodeType).
- Generalized-alpha (mbs.SolveDynamic, DynamicSolverType.GeneralizedAlpha) with Exudyn's
  defaults (spectral radius 0.9, modified Newton, relative tolerance 1e-8, discontinuous
  iteration tolerance 1 N, adaptiveStep = True), Euler-parameter node (Exudyn's default for
  rigid bodies; explicit solvers refuse it), numberOfSteps = round(T_END / h), endTime = T_END,
  h = 4 ... 0.25 ms. At h = 4 and 2 ms the fixed step fails (Newton diverges at the slip-stick
  transition, t = 0.29 s, relative error 2 after 25 iterations, also with full Newton), and
  Exudyn's adaptive step reduction takes over: 247 and 346 steps instead of 146 and 291 (the
  steps stay reduced, recovering slowly, through the rolling phase; 1173 instead of 1165 at
  0.5 ms); the NOTE steps line gives the steps taken. About 7 to 9 Newton iterations a step
  (modified Newton: a Jacobian every 1 to 5 steps); full Newton gives the same errors.
- DOPRI5 (DynamicSolverType.DOPRI5, automaticStepSize, relativeTolerance rtol = 1e-4 ... 1e-10,
  absoluteTolerance rtol / 100, maximum step T_END / 58 = 10 ms): with a RotationRotationVector
  node and explicit.useLieGroupIntegration = True (Exudyn's explicit solvers refuse the
  Euler-parameter node: "node 0 contains algebraic variables"). Its step is limited by stability
  (the contact's sqrt(k / m) = 7700 rad/s), not by rtol: about 1750 - 1800 accepted steps and
  650 rejected ones at every rtol.
Time = the wall time of the mbs.SolveDynamic call (time.perf_counter around it; the system is
built and assembled before), best of 3; no solution file, no console output, one velocity sensor
(SensorBody, OutputVariableType.Velocity) stored in memory every step.

Observed (exudyn 1.13.6, the machine shared with another benchmark):
  genalpha h = 4, 2, 1, 0.5, 0.25 ms: error 1.02e-3, 2.73e-4, 6.95e-5, 1.90e-5, 8.8e-6 (about
    h^2 down to the floor 4.76e-6 below), in 4.7, 5.3, 6.8, 13, 26 ms; all from v(2 t_r),
    v(t_r/2) is right to 1e-9. The error is the Euler parameters' rotation kinematics: the
    angular momentum about the contact point, m v r + J w, which the contact conserves, drifts
    while the ball spins up (-4.7e-5 relative at h = 1 ms, -4.5e-6 at 0.25 ms; v stays linear
    in t to 1e-10, w lags). The same solver with a RotationRotationVector node (linear
    kinematics for a rotation about a fixed axis, so not a fair general setting; not printed)
    gives 4.76e-6 at every h, in 3.3 to 20 ms.
  dopri5 rtol 1e-4 ... 1e-10: error 4.73e-6, then 4.76e-6 at every rtol, 0.03 s.
  4.76e-6 is the compliant contact's own floor against the rigid closed form: Exudyn's contact
  point, and so the rolling radius and the friction's lever arm, is r - delta below the centre,
  delta = m g / k = 0.167 um, so the rolling speed is 5 v0 / 7 (1 - (4/7) delta / r), 4.76e-6 m/s
  below 5 v0/7 (cardan's Hertz contact at K = 1e8: delta = 6.5 um, 6.6e-5 m/s).

Every run is checked: the sliding deceleration (a least-squares line over 0.1 ... 0.9 t_r) must
be mu g to 2 % and the final speed 5 v0/7 to 1 % (met to 6e-8 and 7e-4 relative).

Prints `RESULT code=... setting=... error=... time=...` lines, `NOTE ...` lines for the model and
its parameters, the steps taken and the checks.
"""
import sys
import time
import warnings

import numpy as np

sys.exudynFast = True  # read by exudyn/__init__.py: the build without range checks (peers.py)
import exudyn as exu  # noqa: E402
from exudyn.utilities import MarkerBodyRigid, RigidBodyInertia, SensorBody  # noqa: E402

warnings.filterwarnings("ignore")

V0, MU, G, R, M = 2.0, 0.2, 9.81, 0.028575, 0.17
J = 0.4 * M * R * R
T_ROLL = 2 * V0 / (7 * MU * G)
T_END = 2 * T_ROLL
K = 1e7  # N/m, the pair's linear penalty stiffness: 2K on the sphere and 2K on the triangles, in series
RESTITUTION = 0.8
ZETA = -np.log(RESTITUTION) / np.sqrt(np.pi ** 2 + np.log(RESTITUTION) ** 2)
D = 2 * ZETA * np.sqrt(K * M)  # N s/m, on the sphere only (dampers add in parallel)
DELTA = M * G / K  # static penetration
ZONE = 1e-3  # m/s, frictionProportionalZone
L = 2.0  # half-size of the table square
EULER = exu.NodeType.RotationEulerParameters
ROTVEC = exu.NodeType.RotationRotationVector


def error(v_half, v_end):
    return max(abs(v_half - (V0 - MU * G * T_ROLL / 2)), abs(v_end - 5 * V0 / 7))


def build(node_type):
    """The ball on the table with a GeneralContact; returns (system container, mbs, the ball's
    velocity sensor)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    ball = mbs.CreateRigidBody(inertia=RigidBodyInertia(M, np.diag([J, J, J])),
                               referencePosition=[0.0, 0.0, R - DELTA],
                               initialVelocity=[V0, 0.0, 0.0], initialAngularVelocity=[0.0, 0.0, 0.0],
                               gravity=[0.0, 0.0, -G], nodeType=node_type)
    m_ball = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ball))
    m_ground = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground))
    gc = mbs.AddGeneralContact()
    gc.verboseMode = 0
    gc.SetFrictionPairings(MU * np.eye(1))
    gc.frictionProportionalZone = ZONE
    points = [[-L, -L, 0.0], [L, -L, 0.0], [L, L, 0.0], [-L, L, 0.0]]
    gc.AddTrianglesRigidBodyBased(rigidBodyMarkerIndex=m_ground, contactStiffness=2 * K, contactDamping=0.0,
                                  frictionMaterialIndex=0, pointList=points,
                                  triangleList=[[0, 1, 2], [0, 2, 3]], staticTriangles=True)
    gc.AddSphereWithMarker(m_ball, radius=R, contactStiffness=2 * K, contactDamping=D, frictionMaterialIndex=0)
    gc.SetSearchTreeCellSize([4, 4, 1])
    gc.SetSearchTreeBox([-L, -L, -0.1], [L, L, 0.1])
    sensor = mbs.AddSensor(SensorBody(bodyNumber=ball, storeInternal=True, writeToFile=False,
                                      outputVariableType=exu.OutputVariableType.Velocity))
    mbs.Assemble()
    return sc, mbs, sensor


def settings(h, rtol=None):
    """Quiet settings, no files, sensors every step; a fixed step h, or with rtol DOPRI5's
    automatic step with maximum h."""
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(T_END / h))
    s.timeIntegration.endTime = T_END
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = 0.0
    s.show.statistics = False
    s.show.computationTime = False
    if rtol is not None:
        s.timeIntegration.automaticStepSize = True
        s.timeIntegration.relativeTolerance = rtol
        s.timeIntegration.absoluteTolerance = rtol / 100
        s.timeIntegration.explicit.useLieGroupIntegration = True
    return s


def check(t, v):
    """Sliding deceleration and final rolling speed against the closed form (relative)."""
    sliding = (t > 0.1 * T_ROLL) & (t < 0.9 * T_ROLL)
    decel = -np.polyfit(t[sliding], v[sliding], 1)[0]
    d_decel = decel / (MU * G) - 1
    d_roll = v[-1] / (5 * V0 / 7) - 1
    if abs(d_decel) > 0.02 or abs(d_roll) > 0.01:
        raise RuntimeError(f"Exudyn's ball is off: deceleration {decel} (mu g = {MU * G}), "
                           f"final speed {v[-1]} (5 v0/7 = {5 * V0 / 7})")
    return d_decel, d_roll


def exudyn_run(solver, node_type, h, rtol=None):
    """Best-of-3 wall time of SolveDynamic; returns (error, time, steps taken, check)."""
    best = float("inf")
    for _ in range(3):
        sc, mbs, sensor = build(node_type)
        s = settings(h, rtol)
        start = time.perf_counter()
        mbs.SolveDynamic(s, solverType=solver)
        best = min(best, time.perf_counter() - start)
        data = mbs.GetSensorStoredData(sensor)
    t, v = data[:, 0], data[:, 1]
    if abs(t[-1] - T_END) > 1e-9:
        raise RuntimeError(f"Exudyn stopped at t = {t[-1]}, not {T_END}")
    v_half = np.interp(T_ROLL / 2, t, v)
    return error(v_half, v[-1]), best, len(t) - 1, check(t, v)


def main():
    print(f"NOTE exudyn {exu.__version__} GeneralContact: AddSphereWithMarker(r={R}) + "
          f"AddTrianglesRigidBodyBased(2 static triangles, plane z=0), linear penalty k={K:g} N/m "
          f"(contactStiffness {2 * K:g} on each, in series), damping d={D:.2f} N s/m on the sphere "
          f"(zeta={ZETA:.4f}, restitution {RESTITUTION}), SetFrictionPairings({MU}*eye(1)), "
          f"frictionProportionalZone={ZONE:g} m/s, start at z=r-mg/k (delta={DELTA:.3e} m); "
          f"genalpha: Euler-parameter node, Exudyn defaults (rho_inf 0.9, modified Newton, "
          f"adaptiveStep); dopri5: rotation-vector node + Lie group integration, atol=rtol/100")
    steps, checks = [], []
    for h in [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]:
        e, t, n, c = exudyn_run(exu.DynamicSolverType.GeneralizedAlpha, EULER, h)
        print(f"RESULT code=exudyn setting=genalpha_h_{h:g} error={e:.3e} time={t:.4e}", flush=True)
        steps.append(f"genalpha_h_{h:g}={n}/{int(round(T_END / h))}")
        checks.append(c)
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10]:
        e, t, n, c = exudyn_run(exu.DynamicSolverType.DOPRI5, ROTVEC, 1e-2, rtol)
        print(f"RESULT code=exudyn setting=dopri5_rtol_{rtol:g} error={e:.3e} time={t:.4e}", flush=True)
        steps.append(f"dopri5_rtol_{rtol:g}={n}")
        checks.append(c)
    print("NOTE steps taken (genalpha: taken/nominal, more when Exudyn's adaptive step reduces it): "
          + " ".join(steps))
    checks = np.array(checks)
    print(f"NOTE check: sliding deceleration / (mu g) - 1 within {np.abs(checks[:, 0]).max():.1e}, "
          f"final speed / (5 v0/7) - 1 within {np.abs(checks[:, 1]).max():.1e} over all runs")


if __name__ == "__main__":
    main()
