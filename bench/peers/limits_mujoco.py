"""Peer comparison with MuJoCo for joint limits (issue 48, "joint limits"): the three-link arm of
crates/dynamics/tests/limits.rs `arm` (three 1 kg, 0.5 m rods hanging from ground by revolute
joints about z, gravity -y, released at rest straight along +x) with a compliant stop at
+-0.6 rad on every joint and a viscous damper in every joint, run in cardan and in MuJoCo and
compared at common output times. Not part of any test suite.

  target/peers-venv/bin/python bench/peers/limits_mujoco.py [H [T_END [CONVERGENCE [UNDAMPED]]]]

  H            MuJoCo's fixed RK4 step (default 5e-5 s; it must divide the 1e-3 s output spacing)
  T_END        end time (default 3.0 s; at most the model file's t_end)
  CONVERGENCE  1 (default): also cardan with rtol/atol divided by 100 (its self-difference),
               MuJoCo at H/2 and H/4 (both variants below), each against that tight cardan run,
               and MuJoCo's impedance d swept from 0.9999 down to 1e-4 at H/4; 0: skip
  UNDAMPED     1: without the joint dampers (the library test's conservative arm, chaotic: see
               below); 0 (default): with them

Prints `RESULT key=value ...` lines (times: wall time of one uninstrumented mj_step(m, d, N) call
over the whole run, and of the whole `cardan run` process, start-up and writing its 26 output
files included). About 75 s with CONVERGENCE = 1 on a 2-core VM.

Why joint dampers (0.3 N m s/rad each, a rotational_spring_damper in cardan, the joint's
`damping` in MuJoCo, the same torque -c q' exactly): the undamped arm is chaotic. cardan against
itself (rtol 1e-10 against 1e-12) separates to 1.7e-3 rad by 3 s (agreeing to 1e-6 rad only
until 1.5 s), and MuJoCo with cardan's exact force law agrees with it to 1e-6 rad only until
0.3-0.7 s whatever its step: a pointwise comparison over 3 s would measure the amplification of
round-off, not either solver. With the dampers the arm still strikes its stops 29 times in 3 s
(the lower stops of all three joints: 11, 14 and 4 phases; the upper stops are struck only in
the undamped run), and cardan's two runs agree to 1.3e-8 rad.

The arm and its stops, the same on both sides (everything is read from the model file):
- cardan: bench/peers/arm_limits.toml, three [[limit]] tables lower = -0.6, upper = 0.6,
  law = "compliant", stiffness K = 2000 N m/rad, exponent 1, damping 0: the torque K delta
  pushing back past either bound (delta the penetration) and nothing inside the range (the
  penetration reaches 0.09 rad), and three [[force]] rotational_spring_damper, damping 0.3
  N m s/rad. DOPRI5 rtol 1e-10, atol 1e-12, outputs every 1e-3 s, 3 s. joints.csv and
  joint_velocities.csv give the angles and rates, stops.csv each stop's torque signed as a
  torque on the coordinate (lower >= 0, upper <= 0; their sum is the joint's stop torque),
  energy.csv the kinetic and gravity energies and the dampers' work (the stops' elastic energy
  is not in cardan's E: it is the limits' work channel, so `balance` closes; the script adds
  K delta^2 / 2 itself on both sides).
- MuJoCo (MJCF generated here from the same numbers): a chain of three bodies, each with a
  hinge about z at its proximal end (child frame 0.5 m along the parent's x), an explicit
  <inertial> (mass 1, centre at x = 0.25, diaginertia = the TOML's), a capsule geom with
  contype = conaffinity = 0 (and the contact flag disabled), compiler angle = radian (MJCF's
  default unit for `range` is degrees) and inertiafromgeom = false, gravity (0, -9.81, 0), no
  armature or friction loss, joint damping = the TOML's dampers. qpos of a hinge = cardan's
  revolute angle (both measure the child's x from the parent's x about +z, zero in the drawn
  pose). Integrator RK4
  (the explicit classical method: no implicit damping, 4 force evaluations a step, the
  constraint solver in each), fixed step H; Newton constraint solver, 100 iterations,
  tolerance 1e-15 (the problem has at most three rows; Newton solves its piecewise-quadratic
  cost in one or two iterations). Two variants of the stop:

  "limit" (MuJoCo's own joint limits, the subject of the comparison): limited = "true",
  range = "-0.6 0.6", solreflimit in MuJoCo's direct form (-k, -b), solimplimit = (d, d, ...)
  (dmin = dmax: a constant impedance, so width/midpoint/power do not act). What MuJoCo computes
  for an active limit row (engine_core_constraint.c, mj_makeImpedance / mj_referenceConstraint;
  checked numerically by this script, RESULT law_check): with r = the row's distance (q - lo or
  hi - q, < 0 in contact) and v = its rate,
      K_row = k / dmax^2,  B_row = b / dmax,  aref = -B_row v - K_row d r,
      R = (1 - d) / d * w0   (w0 = dof_invweight0: the diagonal of M^-1 at qpos0, a constant;
                              only with the 4.x flag mjENBL_DIAGEXACT is it the current A_ii),
  and the solver returns f = (A + R)^-1 (aref - J a0) over the active rows (A = J M^-1 J^T,
  a0 = the unconstrained acceleration). With d constant this is
      f = (d A + (1 - d) W0)^-1 (k delta + b delta' - d J a0)   (W0 = diag w0)
        = K delta + d (K delta - q''_row / w0) + O(d^2)     with k = K w0, b = 0,
  i.e. MuJoCo's limit force tends to the spring K delta as d -> 0, and the residual is d times
  (the spring force minus the row's inertia-at-qpos0 times its acceleration). So k = K * w0
  (per joint) and the smallest impedance MuJoCo allows, d = mjMINIMP = 1e-4 (solimp is clamped
  to [1e-4, 0.9999]), are the settings that represent cardan's force law most closely; the
  residual is of relative order 1e-4. The opposite choice, d -> 1 (impedance close to 1, the
  usual "hard" limit), makes f = A^-1 (aref - J a0): the row's acceleration becomes aref itself,
  delta'' = -k delta - b delta' with unit mass in constraint space, i.e. a stop whose force is
  m_eff(q) k delta minus whatever the other forces (gravity, the other links) put on the row:
  not a force law at all. The sweep below shows both ends. With damping: MuJoCo's damping is
  linear, b delta', while cardan's compliant law is Hunt-Crossley's c delta^n delta' (the
  damping grows with the penetration): no choice of solref/solimp makes them equal (a position
  dependent impedance d(delta) scales the stiffness term with d too), so this comparison uses
  damping = 0, the only compliant law MuJoCo's limits can carry.
  "exact" (a model check, not MuJoCo's limit machinery): limits disabled and cardan's force law
  max(0, K delta + c delta delta') applied through mjcb_passive (a Python callback, called in
  every RK4 stage). It separates the model and integrator agreement (masses, inertias,
  geometry, RK4 vs DOPRI5) from the limit law's modelling difference.

Compared at the common output times (every 1e-3 s): every joint angle, the stop torque on
every joint (cardan: lower + upper force of stops.csv; MuJoCo: qfrc_constraint of the dof, which
holds only the limit rows here, or the callback's torque), each side's torque against K delta of
its own angle (the law residual), the contact phases of each of the six stops (entry and exit
times where the penetration changes sign, located by cubic Hermite interpolation between
samples with the angles and rates of both sides), and the energy E = kinetic + gravity + the
stops' elastic energy sum K delta^2 / 2, with the balance E - E(0) + the dampers' dissipated
energy (cardan: minus the sum of the dampers' W columns of energy.csv; MuJoCo: the trapezoidal
rule on c q'^2 over every step h), 0 for the exact motion: each side's error.

Measured (mujoco 4.0.1, 2-core VM, defaults; cardan's tight run is the reference of the
convergence lines):
- "exact" (the model check): max |d angle| 3.3e-6, 6.4e-7, 9.8e-8 rad at h = 5e-5, 2.5e-5,
  1.25e-5 (ratios 5.1 and 6.6: RK4 is fourth order between the stops, but every step that
  straddles a contact entry or exit, where the force's derivative jumps, has an error that
  depends on where in the step the kink falls), stop torque 1.0e-4 N m, the 29 phases' entry
  and exit times within 4.4e-8 s, MuJoCo's energy balance 1.4e-6 J (the dissipation quadrature
  included). cardan's two runs: 1.3e-8 rad.
- "limit" (MuJoCo's own limits, d = 1e-4): 2.2e-4 rad (j2; j0 3.5e-5, j1 1.5e-4), stop torque
  0.16 N m of a 182.8 N m peak, phases within 4.0e-5 s, all 29 found, MuJoCo's energy balance
  7.6e-4 J of the 16.26 J dissipated: the same at every h (2.18e-4, 2.20e-4, 2.20e-4 rad), and
  10 times larger at d = 1e-3 (2.2e-3 rad, 7.6e-3 J), 100 times at d = 1e-2: the difference is
  the O(d) term of MuJoCo's limit law, not integration error. Its own torque differs from
  K delta of its own angle by 0.023 N m (1.2e-4 of the peak), as the formula above says.
  At d = 0.5 ... 0.9999 (the usual hard limit) the arm moves differently (0.6-1.2 rad, 53-68
  contact phases instead of 29, torques off by 180-1300 N m, the energy balance 3-68 J: the
  stop's reference acceleration is not a conservative force).

The rigid law (law = "impact", e = 0: an instantaneous plastic impact, then the stop held as an
equality until its reaction would pull) has no exact MuJoCo counterpart: MuJoCo's limit is
always soft (solref's time constant is clamped to >= 2 h unless refsafe is disabled, and d <=
0.9999), so its impacts take a finite time and give a rebound that depends on the damping ratio
and the step, and a held stop creeps. A comparison would measure MuJoCo's regularization, not
the law; it is not run here.
"""

import os
import sys
import time
import tomllib
import warnings

from cardan_run import col, on_grid, require_cardan, result, run_model

warnings.filterwarnings("ignore")

HERE = os.path.dirname(os.path.abspath(__file__))
TOML = os.path.join(HERE, "arm_limits.toml")
OUT_DT = 1e-3  # s, output spacing on both sides
D_IMP = 1e-4  # MuJoCo's impedance d (mjMINIMP: the smallest MuJoCo allows)
JOINTS = ["j0", "j1", "j2"]


def model_text(undamped=False):
    """The model file's text; undamped: without the joint dampers (the library test's arm)."""
    text = open(TOML).read()
    if undamped:
        a = text.index("# --- joint dampers")
        b = text.index("[analysis]\n")
        text = text[:a] + text[b:]
    return text


def model_spec(text):
    """The arm's numbers from the model text: bodies, gravity, stops (lower, upper, K, c), the
    joint dampers (cj)."""
    spec = tomllib.loads(text)
    bodies = {b["name"]: b for b in spec["body"]}
    limits = {lim["joint"]: lim for lim in spec["limit"]}
    links = []
    for k, j in enumerate(JOINTS):
        joint = next(x for x in spec["joint"] if x["name"] == j)
        b = bodies[joint["body_j"]]
        assert joint["type"] == "revolute" and joint["axis_i"] == joint["axis_j"] == "z"
        assert b["points"]["A"] == [-0.25, 0.0, 0.0] and b["points"]["B"] == [0.25, 0.0, 0.0]
        assert b["position"] == [0.25 + 0.5 * k, 0.0, 0.0]
        lim = limits[j]
        assert lim["law"] == "compliant" and lim.get("exponent", 1.0) == 1.0
        links.append(dict(name=b["name"], mass=b["mass"], inertia=b["inertia"]["diag"],
                          lower=lim["lower"], upper=lim["upper"], k=lim["stiffness"],
                          c=lim.get("damping", 0.0)))
    # Viscous joint dampers (rotational_spring_damper with stiffness 0): MuJoCo's joint damping.
    for f in spec.get("force", []):
        assert f["type"] == "rotational_spring_damper" and f.get("stiffness", 0.0) == 0.0
        links[JOINTS.index(f["joint"])]["cj"] = f.get("damping", 0.0)
    for link in links:
        link.setdefault("cj", 0.0)
    return dict(gravity=spec["model"]["gravity"], links=links, t_end=spec["analysis"]["t_end"])


# --------------------------------------------------------------------------------------------
# cardan

def run_cardan(text, t_end, tol_factor=1.0):
    """cardan on the arm model text (rtol/atol scaled by tol_factor, t_end replaced): columns at
    the output times and the process wall time."""
    import numpy as np

    for old, new in [("rtol = 1e-10", f"rtol = {1e-10 * tol_factor:.3e}"),
                     ("atol = 1e-12", f"atol = {1e-12 * tol_factor:.3e}"),
                     ("t_end = 3.0", f"t_end = {t_end!r}")]:
        assert old in text, old
        text = text.replace(old, new)
    wall, out, run = run_model(text, os.path.basename(TOML), [
        "joints.csv", "joint_velocities.csv", "stops.csv", "energy.csv", "points.csv"])
    hj, j = out["joints.csv"]
    hv, v = out["joint_velocities.csv"]
    hs, s = out["stops.csv"]
    he, e = out["energy.csv"]
    hp, p = out["points.csv"]
    limits = [f"range{k}" for k in range(3)]
    d = dict(
        t=np.array(col(hj, j, "t [s]")),
        q=np.array([col(hj, j, f"{n}.angle [rad]") for n in JOINTS]).T,
        qd=np.array([col(hv, v, f"{n}.angle [rad/s]") for n in JOINTS]).T,
        tau=np.array([np.array(col(hs, s, f"{n}.lower force [N m]"))
                      + np.array(col(hs, s, f"{n}.upper force [N m]")) for n in limits]).T,
        tip=np.array([col(hp, p, f"link2.B.{c} [m]") for c in "xy"]).T,
        kinetic=np.array(col(he, e, "kinetic [J]")),
        gravity=np.array(col(he, e, "potential_gravity [J]")),
        balance=np.array(col(he, e, "balance [J]")),
        # the dampers' work is negative: dissipated = -sum W
        dissipated=-sum((np.array(col(he, e, f"damper{k}.W [J]")) if f"damper{k}.W [J]" in he
                         else np.zeros(len(e))) for k in range(3)),
    )
    d.update(wall=wall, steps=run["integration_steps"], rejected=run["rejected_steps"])
    return d


# --------------------------------------------------------------------------------------------
# MuJoCo

def mjcf(spec, d_imp):
    """The arm in MJCF; the limit rows' solref is set after compiling (it needs dof_invweight0)."""
    g = " ".join(repr(float(x)) for x in spec["gravity"])
    bodies, close = "", ""
    for k, link in enumerate(spec["links"]):
        pos = "0 0 0" if k == 0 else "0.5 0 0"
        ine = " ".join(repr(float(x)) for x in link["inertia"])
        bodies += f"""
    <body name="{link['name']}" pos="{pos}">
      <joint name="{JOINTS[k]}" type="hinge" axis="0 0 1" pos="0 0 0" limited="true"
             range="{link['lower']!r} {link['upper']!r}" solreflimit="-1 -0"
             solimplimit="{d_imp!r} {d_imp!r} 0.001 0.5 2" armature="0" damping="{link['cj']!r}"
             frictionloss="0" margin="0"/>
      <inertial pos="0.25 0 0" mass="{link['mass']!r}" diaginertia="{ine}"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.02" contype="0" conaffinity="0"/>"""
        close += "\n    </body>"
    return f"""<mujoco model="arm_limits">
  <compiler angle="radian" inertiafromgeom="false" autolimits="false"/>
  <option gravity="{g}" integrator="RK4" timestep="1e-4" solver="Newton" iterations="100"
          tolerance="1e-15" ls_tolerance="1e-10" cone="pyramidal" jacobian="dense">
    <flag contact="disable" energy="enable" warmstart="enable"/>
  </option>
  <worldbody>{bodies}{close}
  </worldbody>
</mujoco>"""


def build_mujoco(spec, h, variant="limit", d_imp=D_IMP):
    import mujoco
    import numpy as np

    m = mujoco.MjModel.from_xml_string(mjcf(spec, d_imp))
    m.opt.timestep = h
    K = np.array([link["k"] for link in spec["links"]])
    C = np.array([link["c"] for link in spec["links"]])
    if variant == "limit":
        assert not (m.opt.enableflags & mujoco.mjtEnableBit.mjENBL_DIAGEXACT)
        assert np.all(C == 0.0), "MuJoCo's limit damping is linear (b delta'), cardan's c delta delta'"
        # Direct solref (-k, -b): k = K w0 makes the limit force K delta as d -> 0 (docstring).
        m.jnt_solref[:, 0] = -K * m.dof_invweight0
        m.jnt_solref[:, 1] = -0.0
    else:
        m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_LIMIT
    return m


def _stop_law(spec, q, qd):
    """cardan's compliant law as the torque on each coordinate: +F past lower, -F past upper."""
    import numpy as np
    tau = np.zeros_like(q)
    for k, link in enumerate(spec["links"]):
        lo, hi, K, c = link["lower"], link["upper"], link["k"], link["c"]
        dl = lo - q[..., k]
        du = q[..., k] - hi
        fl = np.where(dl > 0, np.maximum(0.0, K * dl + c * dl * (-qd[..., k])), 0.0)
        fu = np.where(du > 0, np.maximum(0.0, K * du + c * du * qd[..., k]), 0.0)
        tau[..., k] = fl - fu
    return tau


def run_mujoco(spec, h, t_end, variant="limit", d_imp=D_IMP):
    """The arm in MuJoCo (RK4, fixed step h): samples at the output times, the joint dampers'
    dissipated energy (trapezoidal rule over every step h), and the wall time of a separate,
    uninstrumented run of the same steps (one mj_step call with nstep)."""
    import mujoco
    import numpy as np

    h, t_end = float(h), float(t_end)
    m = build_mujoco(spec, h, variant, d_imp)
    d = mujoco.MjData(m)
    nsub = int(round(OUT_DT / h))
    assert abs(nsub * h - OUT_DT) < 1e-15, "H must divide the output spacing"
    n = int(round(t_end / OUT_DT)) + 1
    lo = np.array([x["lower"] for x in spec["links"]])
    hi = np.array([x["upper"] for x in spec["links"]])
    K = np.array([x["k"] for x in spec["links"]])
    C = np.array([x["c"] for x in spec["links"]])

    if variant == "exact":
        def passive(m_, d_):
            q, v = d_.qpos, d_.qvel
            for k in range(3):
                if q[k] < lo[k]:
                    dl = lo[k] - q[k]
                    d_.qfrc_passive[k] += max(0.0, K[k] * dl - C[k] * dl * v[k])
                elif q[k] > hi[k]:
                    du = q[k] - hi[k]
                    d_.qfrc_passive[k] -= max(0.0, K[k] * du + C[k] * du * v[k])
        mujoco.set_mjcb_passive(passive)
    try:
        out = dict(t=np.zeros(n), q=np.zeros((n, 3)), qd=np.zeros((n, 3)), tau=np.zeros((n, 3)),
                   tip=np.zeros((n, 2)), kinetic=np.zeros(n), gravity=np.zeros(n),
                   dissipated=np.zeros(n))
        cj = np.array([x["cj"] for x in spec["links"]])
        iters, work = 0, 0.0
        for i in range(n):
            mujoco.mj_forward(m, d)  # the efc_ and energy fields at this state
            out["t"][i] = d.time
            out["q"][i] = d.qpos
            out["qd"][i] = d.qvel
            if variant == "limit":
                out["tau"][i] = d.qfrc_constraint  # only limit rows exist
            else:
                out["tau"][i] = _stop_law(spec, d.qpos.copy(), d.qvel.copy())
            # link2's distal end B = its body origin + 0.5 along its x.
            out["tip"][i] = (d.xpos[3] + 0.5 * d.xmat[3].reshape(3, 3)[:, 0])[:2]
            out["gravity"][i] = d.energy[0]
            out["kinetic"][i] = d.energy[1]
            out["dissipated"][i] = work
            if i == n - 1:
                break
            for _ in range(nsub):
                p0 = float(np.dot(cj, d.qvel * d.qvel))
                mujoco.mj_step(m, d)
                work += 0.5 * h * (p0 + float(np.dot(cj, d.qvel * d.qvel)))
                iters = max(iters, int(d.solver_niter[0]))
        d2 = mujoco.MjData(m)
        t0 = time.perf_counter()
        mujoco.mj_step(m, d2, (n - 1) * nsub)
        wall = time.perf_counter() - t0
        assert np.allclose(d2.qpos, d.qpos, rtol=0, atol=1e-12)
    finally:
        if variant == "exact":
            mujoco.set_mjcb_passive(None)
    out.update(wall=wall, steps=(n - 1) * nsub, max_solver_iter=iters, w0=m.dof_invweight0.copy(),
               solref=m.jnt_solref.copy())
    return out


def law_check(spec):
    """MuJoCo's limit force at a few states in contact, against K delta (the d -> 0 law)."""
    import mujoco
    import numpy as np
    worst = 0.0
    rel = 0.0
    for d_imp in (D_IMP,):
        m = build_mujoco(spec, 1e-4, "limit", d_imp)
        d = mujoco.MjData(m)
        rng = np.random.default_rng(1)
        for _ in range(20):
            d.qpos[:] = rng.uniform(-0.7, 0.7, 3)
            d.qvel[:] = rng.uniform(-3, 3, 3)
            mujoco.mj_forward(m, d)
            law = _stop_law(spec, d.qpos.copy(), d.qvel.copy())
            err = np.abs(d.qfrc_constraint - law)
            worst = max(worst, float(err.max()))
            big = np.abs(law) > 1.0
            if big.any():
                rel = max(rel, float(np.max(err[big] / np.abs(law[big]))))
    return worst, rel


# --------------------------------------------------------------------------------------------
# comparison

def _hermite_root(t0, t1, g0, g1, r0, r1):
    """The root in [t0, t1] of the cubic Hermite interpolant of g (values g0, g1, rates r0, r1),
    g0 and g1 of opposite signs (bisection)."""
    dt = t1 - t0

    def p(s):
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        return h00 * g0 + h10 * dt * r0 + h01 * g1 + h11 * dt * r1

    a, b = 0.0, 1.0
    pa = p(a)
    for _ in range(60):
        c = 0.5 * (a + b)
        pc = p(c)
        if (pc > 0) == (pa > 0):
            a, pa = c, pc
        else:
            b = c
    return t0 + 0.5 * (a + b) * dt


def phases(spec, d):
    """Contact phases of every stop, {(joint, side): [(t_in, t_out or None)]}: the penetration
    delta (lo - q or q - hi) positive, its sign changes located on the Hermite interpolant."""
    res = {}
    t = d["t"]
    for k, link in enumerate(spec["links"]):
        for side, sgn, bound in (("lower", -1.0, link["lower"]), ("upper", 1.0, link["upper"])):
            g = sgn * (d["q"][:, k] - bound)  # penetration
            r = sgn * d["qd"][:, k]
            ph, t_in = [], None
            if g[0] > 0:
                t_in = t[0]
            for i in range(1, len(t)):
                if (g[i] > 0) != (g[i - 1] > 0):
                    tc = _hermite_root(t[i - 1], t[i], g[i - 1], g[i], r[i - 1], r[i])
                    if g[i] > 0:
                        t_in = tc
                    else:
                        ph.append((t_in, tc))
                        t_in = None
            if t_in is not None:
                ph.append((t_in, None))
            res[(JOINTS[k], side)] = ph
    return res


def compare_phases(pa, pb):
    """Counts per stop, the first stop and time where the lists differ, max entry/exit time
    differences over the matched phases (up to the first count mismatch of each stop)."""
    import numpy as np
    n_a = sum(len(v) for v in pa.values())
    n_b = sum(len(v) for v in pb.values())
    din, dout, mismatch = 0.0, 0.0, []
    for key in pa:
        a, b = pa[key], pb[key]
        if len(a) != len(b):
            mismatch.append(f"{key[0]}.{key[1]}:{len(a)}/{len(b)}")
        for (ai, ao), (bi, bo) in zip(a, b):
            din = max(din, abs(ai - bi))
            if ao is not None and bo is not None:
                dout = max(dout, abs(ao - bo))
    return dict(n_a=n_a, n_b=n_b, dt_in=din, dt_out=dout, mismatch=",".join(mismatch) or "none",
                first_in=float(np.min([p[0] for v in pa.values() for p in v])) if n_a else None)


def elastic(spec, q):
    import numpy as np
    e = np.zeros(len(q))
    for k, link in enumerate(spec["links"]):
        dl = np.maximum(link["lower"] - q[:, k], 0.0)
        du = np.maximum(q[:, k] - link["upper"], 0.0)
        e += 0.5 * link["k"] * (dl**2 + du**2)
    return e


def energy(spec, d):
    """E - E(0) + the dampers' dissipated energy: 0 for the exact motion (each side's error)."""
    e = d["kinetic"] + d["gravity"] + elastic(spec, d["q"])
    return e - e[0] + d["dissipated"]


def compare(spec, a, b):
    import numpy as np
    dq = np.abs(a["q"] - b["q"])
    dtau = np.abs(a["tau"] - b["tau"])
    k = int(np.argmax(dq.max(axis=1)))
    return dict(dq=dq.max(axis=0), dq_all=float(dq.max()), at=float(a["t"][k]),
                dtau=dtau.max(axis=0), dtau_all=float(dtau.max()),
                dtip=float(np.max(np.linalg.norm(a["tip"] - b["tip"], axis=1))),
                # the time up to which all angles agree to 1e-6 rad and 1e-3 rad
                t_1e6=_agree_until(a["t"], dq.max(axis=1), 1e-6),
                t_1e3=_agree_until(a["t"], dq.max(axis=1), 1e-3))


def _agree_until(t, err, tol):
    import numpy as np
    bad = np.nonzero(err > tol)[0]
    return float(t[bad[0]]) if len(bad) else float(t[-1])


def _f(x):
    return f"{x:.3e}"


def main(h=5e-5, t_end=3.0, convergence=1, undamped=0):
    import numpy as np
    h, t_end, convergence, undamped = float(h), float(t_end), int(convergence), int(undamped)
    from importlib.metadata import version

    require_cardan()
    text = model_text(undamped)
    spec = model_spec(text)
    assert t_end <= spec["t_end"] + 1e-12
    worst, rel = law_check(spec)
    result(law_check_max_abs=_f(worst), law_check_max_rel=_f(rel), d=D_IMP,
           note="MuJoCo_limit_force_vs_K_delta_at_20_random_states")

    car = on_grid(run_cardan(text, t_end), t_end, OUT_DT)
    mj = on_grid(run_mujoco(spec, h, t_end, "limit"), t_end, OUT_DT)
    ex = on_grid(run_mujoco(spec, h, t_end, "exact"), t_end, OUT_DT)
    result(mujoco=version("mujoco"), h=h, t_end=t_end, samples=len(car["t"]), d=D_IMP,
           joint_damping="/".join(f"{x['cj']:g}" for x in spec["links"]),
           w0="/".join(f"{x:.6g}" for x in mj["w0"]),
           solref_k="/".join(f"{-x:.6g}" for x in mj["solref"][:, 0]),
           cardan_wall=f"{car['wall']:.3f}", cardan_steps=car["steps"], cardan_rejected=car["rejected"],
           mujoco_limit_wall=f"{mj['wall']:.3f}", mujoco_exact_wall=f"{ex['wall']:.3f}",
           mujoco_steps=mj["steps"], mujoco_max_solver_iter=mj["max_solver_iter"])
    # Sanity: the same kinetic/gravity energy definitions (first samples, before any contact).
    result(check_kinetic_t0p1=_f(abs(car["kinetic"][100] - mj["kinetic"][100])),
           check_gravity_t0p1=_f(abs(car["gravity"][100] - mj["gravity"][100])),
           kinetic_t0p1=f"{car['kinetic'][100]:.6f}")

    pc = phases(spec, car)
    for name, other in (("limit", mj), ("exact", ex)):
        c = compare(spec, car, other)
        po = phases(spec, other)
        cp = compare_phases(pc, po)
        result(variant=name, max_dangle=_f(c["dq_all"]), at_t=f"{c['at']:.3f}",
               dangle_j0=_f(c["dq"][0]), dangle_j1=_f(c["dq"][1]), dangle_j2=_f(c["dq"][2]),
               dtip=_f(c["dtip"]), agree_1e6_until=f"{c['t_1e6']:.3f}",
               agree_1e3_until=f"{c['t_1e3']:.3f}")
        peak = np.abs(car["tau"]).max(axis=0)
        result(variant=name, max_dtorque=_f(c["dtau_all"]),
               dtorque_j0=_f(c["dtau"][0]), dtorque_j1=_f(c["dtau"][1]), dtorque_j2=_f(c["dtau"][2]),
               peak_j0=f"{peak[0]:.3f}", peak_j1=f"{peak[1]:.3f}", peak_j2=f"{peak[2]:.3f}",
               peak_mujoco="/".join(f"{x:.3f}" for x in np.abs(other["tau"]).max(axis=0)))
        law_c = np.abs(car["tau"] - _stop_law(spec, car["q"], car["qd"])).max()
        law_o = np.abs(other["tau"] - _stop_law(spec, other["q"], other["qd"])).max()
        result(variant=name, law_residual_cardan=_f(law_c), law_residual_mujoco=_f(law_o))
        result(variant=name, phases_cardan=cp["n_a"], phases_mujoco=cp["n_b"],
               count_mismatch=cp["mismatch"], max_dt_entry=_f(cp["dt_in"]),
               max_dt_exit=_f(cp["dt_out"]))
        ec, eo = energy(spec, car), energy(spec, other)
        tot_c = car["kinetic"] + car["gravity"] + elastic(spec, car["q"])
        tot_o = other["kinetic"] + other["gravity"] + elastic(spec, other["q"])
        result(variant=name, energy_balance_cardan=_f(np.abs(ec).max()),
               energy_balance_mujoco=_f(np.abs(eo).max()),
               balance_column_cardan=_f(np.abs(car["balance"]).max()),
               dissipated_cardan=f"{car['dissipated'][-1]:.6f}",
               dissipated_mujoco=f"{other['dissipated'][-1]:.6f}",
               max_dE=_f(np.abs(tot_c - tot_o).max()), E_range=f"{np.ptp(tot_c):.4f}",
               max_dkinetic=_f(np.abs(car["kinetic"] - other["kinetic"]).max()))
    for key, ph in pc.items():
        if ph:
            result(stop=f"{key[0]}.{key[1]}", phases=len(ph),
                   cardan=";".join(f"{a:.5f}-{b:.5f}" if b is not None else f"{a:.5f}-open"
                                   for a, b in ph[:4]) + (";..." if len(ph) > 4 else ""))
    pen = [max(float(np.max(link["lower"] - car["q"][:, k])), float(np.max(car["q"][:, k] - link["upper"])))
           for k, link in enumerate(spec["links"])]
    result(max_penetration_cardan="/".join(f"{x:.5f}" for x in pen))

    if not convergence:
        return
    car2 = on_grid(run_cardan(text, t_end, tol_factor=0.01), t_end, OUT_DT)
    c = compare(spec, car, car2)
    result(cardan_self_dangle=_f(c["dq_all"]), cardan_self_dtorque=_f(c["dtau_all"]),
           cardan_tight_wall=f"{car2['wall']:.3f}", cardan_tight_steps=car2["steps"])
    pc2 = phases(spec, car2)
    for name in ("limit", "exact"):
        prev = None
        for div in (1, 2, 4):
            e = mj if (div == 1 and name == "limit") else ex if div == 1 else \
                on_grid(run_mujoco(spec, h / div, t_end, name), t_end, OUT_DT)
            c = compare(spec, car2, e)
            cp = compare_phases(pc2, phases(spec, e))
            kw = {}
            if prev is not None:
                kw = dict(ratio=f"{prev / max(c['dq_all'], 1e-300):.2f}")
            result(variant=name, h=h / div, wall=f"{e['wall']:.3f}", vs_cardan_tight_dangle=_f(c["dq_all"]),
                   dtorque=_f(c["dtau_all"]), dt_entry=_f(cp["dt_in"]), dt_exit=_f(cp["dt_out"]),
                   phases=cp["n_b"], mismatch=cp["mismatch"],
                   energy_balance=_f(np.abs(energy(spec, e)).max()), **kw)
            prev = c["dq_all"]
    # The impedance: from the usual "hard" limit (d -> 1) to MuJoCo's smallest (1e-4), at h/4.
    for d_imp in (0.9999, 0.99, 0.9, 0.5, 0.1, 1e-2, 1e-3, 1e-4):
        e = on_grid(run_mujoco(spec, h / 4, t_end, "limit", d_imp), t_end, OUT_DT)
        c = compare(spec, car2, e)
        cp = compare_phases(pc2, phases(spec, e))
        law_o = np.abs(e["tau"] - _stop_law(spec, e["q"], e["qd"])).max()
        result(sweep_d=d_imp, h=h / 4, dangle=_f(c["dq_all"]), dtorque=_f(c["dtau_all"]),
               law_residual=_f(law_o), agree_1e6_until=f"{c['t_1e6']:.3f}",
               agree_1e3_until=f"{c['t_1e3']:.3f}", phases=cp["n_b"], mismatch=cp["mismatch"],
               dt_entry=_f(cp["dt_in"]), dt_exit=_f(cp["dt_out"]),
               energy_balance=_f(np.abs(energy(spec, e)).max()))


if __name__ == "__main__":
    main(*sys.argv[1:])
