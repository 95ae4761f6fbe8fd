"""Peer comparison with Exudyn for end stops (issue 48, "joint limits"): the IFToMM spatial
slider-crank of examples/slider_crank_dynamic.toml (free motion under gravity from crank
omega = 6 rad/s) with a compliant stroke stop on the slider's travel, run in cardan and in
Exudyn at equal settings and compared at common output times. Not part of any test suite.

  target/peers-venv/bin/python bench/peers/limits_exudyn.py [H [T_END [CONVERGENCE]]]

  H            Exudyn's fixed step (default 1e-5 s; it must divide the 1e-4 s output spacing)
  T_END        end time (default 2.0 s; at most the model file's t_end)
  CONVERGENCE  1 (default): also run cardan with rtol/atol divided by 100 (its self-difference)
               and Exudyn at H/2 and H/4, each compared with that tight cardan run; 0: skip

Prints `RESULT key=value ...` lines (times are wall times of the solver call for Exudyn and of
the whole `cardan run` process for cardan, start-up and CSV writing included).

The stop, the same on both sides:
- cardan: bench/peers/slider_crank_stroke.toml = examples/slider_crank_dynamic.toml plus
  [[limit]] name = "stroke", joint = "slide", upper = 0.25 m, law = "compliant",
  stiffness = 1e5 N/m, exponent = 1, damping = 0, i.e. the force k (x - 0.25) pushing back past
  x = 0.25 and nothing inside the range. DOPRI5 rtol 1e-10, atol 1e-12, outputs every 1e-4 s.
  The run is `target/release/cardan run <toml> -o <tmpdir> --quiet`; joints.csv gives the slide
  and the crank angle, points.csv the crank tip B and slider C, stops.csv the stop's force (signed
  as a force on the coordinate: negative = pushing the slider back), energy.csv the energies.
  cardan's slide is measured between the joint points, ground O = origin and slider O = the
  slider's origin, along x: slide = the slider's x (checked below on the first row and at every
  output time against points.csv's slider.C.x).
- Exudyn: the same slider-crank as bench/peers/peers.py `exudyn_slider_crank`, built by the same
  function (peers.py `exudyn_slider_crank_model`: rigid bodies with Euler-parameter nodes,
  redundant coordinates, CreateRevoluteJoint / CreateSphericalJoint / CreateGenericJoint
  (universal) / CreatePrismaticJoint; generalized-alpha with a fixed step),
  plus ObjectConnectorCoordinateSpringDamperExt between a ground coordinate (NodePointGround,
  coordinate 0) and coordinate 0 of the slider's node, with stiffness = damping = 0, no friction
  (fDynamicFriction = fStaticFrictionOffset = fViscousFriction = 0) and useLimitStops: the
  contact force is limitStopsStiffness (q - limitStopsUpper) + limitStopsDamping v past the
  upper limit, with q = the node's displacement coordinate, which does NOT include the reference
  position 0.2: limitStopsUpper = 0.25 - 0.2 = 0.05, limitStopsLower = -1e3 (the default 0 would
  be a lower stop at x = 0.2, inside the motion), limitStopsStiffness = 1e5,
  limitStopsDamping = 0. The contact state lives in a NodeGenericData (3 data coordinates) and is
  switched in Exudyn's PostNewton step (discontinuous iteration): the step is repeated with the
  new state when the switching error k |delta| exceeds discontinuous.iterationTolerance, set here
  to 1e-9 N so every switch is resolved within its step (the default 1 N would let a switch
  lag by one step). Spectral radius 0.9 (Exudyn's default, as peers.py), full Newton
  (useModifiedNewton = False) with relativeTolerance 1e-12. Why these:
  * Not spectral radius 1 (no numerical damping): with it the Newton iterations of the index-3
    constraint equations degrade over the run (25 iterations and failing by 1.2 s at h = 1e-4,
    the step cut down to 1e-8 s, the run stopped; also without any contact). 0.9 damps only
    the unresolved high frequencies: at the stop's (about 190 rad/s, the contact lasts
    0.0167 s) omega h = 2e-3 at h = 1e-5.
  * Exudyn's default Newton (modified, relative tolerance 1e-8) leaves an error floor of a few
    1e-8 m in the slider's x that does not shrink with h (the differences to cardan at h = 2e-5
    and 1e-5 were 1.7e-7 and 2.0e-7 m); with full Newton at 1e-12 (2.5 to 3 iterations a step)
    the difference to cardan is 1.3e-7 m at h = 1e-5 and 2.1e-8 m at 5e-6 (the mechanism
    amplifies errors between the contacts, about 30 times a cycle, so the ratio is 6, not
    the asymptotic 4). At h = 2.5e-6 it is 3.7e-8 m again: that run picks up an erratic
    error of about 1e-9 m in the free phase 0.19 - 0.3 s (x - x_cardan at 0.5 s: +1.2e-8,
    +2.4e-9, -2.9e-9, +2.2e-10 m for h = 1e-5, 5e-6, 2.5e-6, 1.25e-6), which the mechanism
    then amplifies; cardan's own run is converged to 4e-10 m (rtol 1e-12 against 1e-13).
    Modified Newton at 1e-10 stalls at a relative error of 1.0001e-10 and cuts the step.
  Exudyn's explicit integrators do not take the joints' algebraic constraints, so
  generalized-alpha (implicit) is the solver.

Compared at the common output times (every 1e-4 s): the slider's x, the crank tip B, the crank
angle (cardan's crank_pivot.angle; Exudyn's from B: theta = atan2(-(B_y - 0.1), B_z - 0.12),
unwrapped), the stop force, and the contact phases (the times x crosses 0.25, by linear
interpolation between output samples, so to about 1e-6 s at these speeds). Energy: on both
sides E = kinetic + gravity potential + the stop's elastic energy k delta^2 / 2, whose drift
from E(0) is reported (the stop is conservative).
"""

import os
import sys
import warnings

from cardan_run import col, on_grid, require_cardan, result, run_model
from peers import (G, SLIDER_X0, _exudyn, exudyn_fixed_step_settings, exudyn_slider_crank_model,
                   exudyn_slider_crank_sensors, exudyn_solve)

warnings.filterwarnings("ignore")

HERE = os.path.dirname(os.path.abspath(__file__))
TOML = os.path.join(HERE, "slider_crank_stroke.toml")

UPPER = 0.25  # m, the stop on the slider's x
K_STOP = 1e5  # N/m
X0 = SLIDER_X0  # m, the slider's reference (initial) x in Exudyn
OUT_DT = 1e-4  # s, output spacing on both sides
# Exudyn solver settings applied last (dotted paths below SimulationSettings).
EXUDYN_SETTINGS = {}


# --------------------------------------------------------------------------------------------
# cardan

def run_cardan(t_end, tol_factor=1.0):
    """Runs cardan on the stroke model (rtol/atol scaled by tol_factor, t_end replaced) and
    returns a dict of columns at the output times and the process wall time."""
    import numpy as np

    text = open(TOML).read()
    text = text.replace("rtol = 1e-10", f"rtol = {1e-10 * tol_factor:.3e}")
    text = text.replace("atol = 1e-12", f"atol = {1e-12 * tol_factor:.3e}")
    text = text.replace("t_end = 2.0", f"t_end = {t_end!r}")
    wall, out, run = run_model(text, os.path.basename(TOML),
                               ["joints.csv", "points.csv", "stops.csv", "energy.csv"])
    hj, j = out["joints.csv"]
    hp, p = out["points.csv"]
    hs, s = out["stops.csv"]
    he, e = out["energy.csv"]
    d = dict(
        t=np.array(col(hj, j, "t [s]")),
        x=np.array(col(hj, j, "slide.slide [m]")),
        angle=np.array(col(hj, j, "crank_pivot.angle [rad]")),
        B=np.array([col(hp, p, f"crank.B.{c} [m]") for c in "xyz"]).T,
        C=np.array([col(hp, p, f"slider.C.{c} [m]") for c in "xyz"]).T,
        force=np.array(col(hs, s, "stroke.upper force [N]")),
        kinetic=np.array(col(he, e, "kinetic [J]")),
        gravity=np.array(col(he, e, "potential_gravity [J]")),
        balance=np.array(col(he, e, "balance [J]")),
    )
    d["wall"] = wall
    d["steps"] = run["integration_steps"]
    d["rejected"] = run["rejected_steps"]
    return d


# --------------------------------------------------------------------------------------------
# Exudyn

def run_exudyn(h, t_end):
    """The stroke model in Exudyn (module docs), generalized-alpha with the fixed step h; returns
    a dict of the sensor histories at the output times and the solver's wall time."""
    exu = _exudyn()
    import numpy as np
    from exudyn.itemInterface import (CoordinateSpringDamperExt, MarkerNodeCoordinate,
                                      NodeGenericData, NodePointGround, SensorObject)

    h, t_end = float(h), float(t_end)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    crank, rod, slider = exudyn_slider_crank_model(mbs)

    # The stroke stop: a one-sided linear spring on the slider node's x displacement.
    n_ground = mbs.AddNode(NodePointGround(referenceCoordinates=[0.0, 0.0, 0.0]))
    n_slider = mbs.GetObject(slider)["nodeNumber"]
    m_ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n_ground, coordinate=0))
    m_slider = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n_slider, coordinate=0))
    n_data = mbs.AddNode(NodeGenericData(numberOfDataCoordinates=3, initialCoordinates=[0.0, 0.0, 0.0]))
    stop = mbs.AddObject(CoordinateSpringDamperExt(
        markerNumbers=[m_ground, m_slider], nodeNumber=n_data,
        stiffness=0.0, damping=0.0, offset=0.0,
        fDynamicFriction=0.0, fStaticFrictionOffset=0.0, fViscousFriction=0.0,
        frictionProportionalZone=0.0, stickingStiffness=0.0, stickingDamping=0.0,
        useLimitStops=True, limitStopsUpper=UPPER - X0, limitStopsLower=-1e3,
        limitStopsStiffness=K_STOP, limitStopsDamping=0.0))

    s_b, s_c, energy_sensors = exudyn_slider_crank_sensors(mbs, crank, rod, slider)
    s_f = mbs.AddSensor(SensorObject(objectNumber=stop, storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Force))
    s_q = mbs.AddSensor(SensorObject(objectNumber=stop, storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Displacement))
    mbs.Assemble()

    s, steps = exudyn_fixed_step_settings(h, t_end, OUT_DT)
    s.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    s.timeIntegration.newton.useModifiedNewton = False
    s.timeIntegration.newton.relativeTolerance = 1e-12
    s.timeIntegration.discontinuous.iterationTolerance = 1e-9
    s.timeIntegration.discontinuous.maxIterations = 20
    for path, value in EXUDYN_SETTINGS.items():
        obj = s
        *head, last = path.split(".")
        for name in head:
            obj = getattr(obj, name)
        setattr(obj, last, value)
    wall, it = exudyn_solve(mbs, s)

    b = mbs.GetSensorStoredData(s_b)
    c = mbs.GetSensorStoredData(s_c)
    f = mbs.GetSensorStoredData(s_f)
    q = mbs.GetSensorStoredData(s_q)
    kin = 0.0
    grav = 0.0
    for m, j, (sp, sv, sw) in energy_sensors:
        p, v, w = (mbs.GetSensorStoredData(x) for x in (sp, sv, sw))
        kin = kin + 0.5 * m * np.sum(v[:, 1:4] ** 2, axis=1) + 0.5 * np.sum(j * w[:, 1:4] ** 2, axis=1)
        grav = grav + m * G * p[:, 3]
    angle = np.unwrap(np.arctan2(-(b[:, 2] - 0.1), b[:, 3] - 0.12))
    return dict(t=b[:, 0], x=c[:, 1], C=c[:, 1:4], B=b[:, 1:4], angle=angle, force=f[:, 1],
                q=q[:, 1], kinetic=kin, gravity=grav, wall=wall, steps=steps,
                newton=it.newtonStepsCount, jacobians=it.newtonJacobiCount,
                discontinuous=getattr(it, "discontinuousIterationsCount", -1))


# --------------------------------------------------------------------------------------------
# comparison

def contacts(t, x):
    """The contact phases [(t_in, t_out)]: x above UPPER, crossing times by linear
    interpolation between samples."""
    phases = []
    inside = x[0] > UPPER
    t_in = t[0] if inside else None
    for k in range(1, len(t)):
        now = x[k] > UPPER
        if now != inside:
            tc = t[k - 1] + (UPPER - x[k - 1]) / (x[k] - x[k - 1]) * (t[k] - t[k - 1])
            if now:
                t_in = tc
            else:
                phases.append((t_in, tc))
            inside = now
    if inside:
        phases.append((t_in, None))
    return phases


def energy(d):
    import numpy as np
    stored = 0.5 * K_STOP * np.maximum(d["x"] - UPPER, 0.0) ** 2
    e = d["kinetic"] + d["gravity"] + stored
    return e - e[0]


def fmt_phases(ph):
    return ";".join(f"{a:.6f}-{b:.6f}" if b is not None else f"{a:.6f}-open" for a, b in ph)


def compare(a, b):
    """Max differences between two runs on the common grid."""
    import numpy as np
    return dict(dx=float(np.max(np.abs(a["x"] - b["x"]))),
                dangle=float(np.max(np.abs(a["angle"] - b["angle"]))),
                dB=float(np.max(np.linalg.norm(a["B"] - b["B"], axis=1))))


def main(h=1e-5, t_end=2.0, convergence=1):
    import numpy as np
    h, t_end, convergence = float(h), float(t_end), int(convergence)
    from importlib.metadata import version

    require_cardan()
    car = on_grid(run_cardan(t_end), t_end, OUT_DT)
    exu = on_grid(run_exudyn(h, t_end), t_end, OUT_DT)
    result(exudyn=version("exudyn"), h=h, t_end=t_end, samples=len(car["t"]),
           cardan_wall=f"{car['wall']:.3f}", cardan_steps=car["steps"], cardan_rejected=car["rejected"],
           exudyn_wall=f"{exu['wall']:.3f}", exudyn_steps=exu["steps"], exudyn_newton=exu["newton"],
           exudyn_jacobians=exu["jacobians"])

    # The coordinates are the same thing: cardan's slide = its slider.C.x; Exudyn's stop
    # coordinate q = its slider x - 0.2.
    result(check_cardan_slide_vs_Cx=float(np.max(np.abs(car["x"] - car["C"][:, 0]))),
           check_cardan_x0=car["x"][0], check_exudyn_q_vs_x=float(np.max(np.abs(exu["q"] + X0 - exu["x"]))),
           check_exudyn_x0=exu["x"][0],
           check_angle_vs_B=float(np.max(np.abs(car["angle"] - np.unwrap(np.arctan2(
               -(car["B"][:, 1] - 0.1), car["B"][:, 2] - 0.12))))))

    d = compare(car, exu)
    k = int(np.argmax(np.abs(car["x"] - exu["x"])))
    # cardan's stops.csv force is the force on the coordinate (negative pushes back); Exudyn's
    # connector force is the spring force k (q - upper) (positive in contact).
    df = float(np.max(np.abs(-car["force"] - exu["force"])))
    result(max_dx_slider=d["dx"], at_t=f"{car['t'][k]:.4f}", max_dangle_crank=d["dangle"],
           max_dB_tip=d["dB"], max_dC_slider=float(np.max(np.linalg.norm(car["C"] - exu["C"], axis=1))),
           max_dforce=df, max_force_cardan=float(np.max(-car["force"])),
           max_force_exudyn=float(np.max(exu["force"])),
           x_end_cardan=car["x"][-1], x_end_exudyn=exu["x"][-1],
           angle_end_cardan=car["angle"][-1], angle_end_exudyn=exu["angle"][-1])
    # The force law itself: both sides' force against k delta of their own x.
    result(cardan_force_law=float(np.max(np.abs(-car["force"] - K_STOP * np.maximum(car["x"] - UPPER, 0)))),
           exudyn_force_law=float(np.max(np.abs(exu["force"] - K_STOP * np.maximum(exu["x"] - UPPER, 0)))))

    pc, pe = contacts(car["t"], car["x"]), contacts(exu["t"], exu["x"])
    dt_contact = max((abs(a - c) for (a, b), (c, e) in zip(pc, pe)), default=float("nan"))
    dt_release = max((abs(b - e) for (a, b), (c, e) in zip(pc, pe) if b is not None and e is not None),
                     default=float("nan"))
    result(contacts_cardan=len(pc), contacts_exudyn=len(pe), phases_cardan=fmt_phases(pc),
           phases_exudyn=fmt_phases(pe), max_dt_contact=dt_contact, max_dt_release=dt_release,
           max_penetration_cardan=float(np.max(car["x"]) - UPPER),
           max_penetration_exudyn=float(np.max(exu["x"]) - UPPER))
    ec, ee = energy(car), energy(exu)
    result(energy_drift_cardan=float(np.max(np.abs(ec))), energy_drift_exudyn=float(np.max(np.abs(ee))),
           energy_balance_cardan=float(np.max(np.abs(car["balance"]))),
           max_dkinetic=float(np.max(np.abs(car["kinetic"] - exu["kinetic"]))))

    if convergence:
        car2 = on_grid(run_cardan(t_end, tol_factor=0.01), t_end, OUT_DT)
        c1 = compare(car, car2)
        result(cardan_self_dx=c1["dx"], cardan_self_dangle=c1["dangle"], cardan_self_dB=c1["dB"],
               cardan_tight_wall=f"{car2['wall']:.3f}", cardan_tight_steps=car2["steps"])
        # Exudyn at h/2 and h/4, each against the tight cardan run and the previous step.
        prev, prev_d = exu, compare(car2, exu)
        result(h=h, vs_cardan_tight_dx=prev_d["dx"], dangle=prev_d["dangle"], dB=prev_d["dB"])
        for div in (2, 4):
            e = on_grid(run_exudyn(h / div, t_end), t_end, OUT_DT)
            d, self_d = compare(car2, e), compare(prev, e)
            pe = contacts(e["t"], e["x"])
            result(h=h / div, exudyn_wall=f"{e['wall']:.3f}", steps=e["steps"],
                   vs_cardan_tight_dx=d["dx"], dangle=d["dangle"], dB=d["dB"],
                   ratio_dx=prev_d["dx"] / d["dx"],
                   dforce=float(np.max(np.abs(-car2["force"] - e["force"]))),
                   self_dx=self_d["dx"], self_dangle=self_d["dangle"],
                   max_dt_contact=max(abs(a - c) for (a, b), (c, f) in zip(contacts(car2["t"], car2["x"]), pe)),
                   contacts=len(pe),
                   energy_drift=float(np.max(np.abs(energy(e)))))
            prev, prev_d = e, d

if __name__ == "__main__":
    main(*sys.argv[1:])
