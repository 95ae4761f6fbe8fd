"""URDF joint damping (issue 51) against MuJoCo 4.0.1: MuJoCo's URDF reader makes a joint's
``<dynamics damping>`` the joint's damping, and its inverse dynamics (``mj_inverse``) includes it
(the passive force −c q̇). cardan reads the same file with ``damping = true`` (each revolute
joint's damping a rotational damper) and drives every joint along a smooth trajectory
(inverse dynamics); the joint torques are compared at every output time."""

import math
import re

import mujoco
import numpy as np
import pytest

import cardan
from conftest import EXAMPLES

ARM = EXAMPLES / "urdf" / "three_link_arm.urdf"
DAMPING = {"turret_joint": 0.4, "shoulder": 0.25, "elbow": 0.1}
# q = c + a sin(w t + φ) per joint, inside the shoulder's and elbow's limits.
LAW = {
    "turret_joint": (0.0, 0.6, 1.3, 0.2),
    "shoulder": (0.5, 0.3, 2.0, 1.0),
    "elbow": (0.4, 0.3, 2.7, 0.5),
}


def damped_arm(tmp_path):
    """The arm with damping on its joints; every <inertia> with all six entries (MuJoCo's reader
    requires them, cardan's takes a missing one as 0)."""
    text = re.sub(
        r"<inertia (?![^>]*ixy)",
        '<inertia ixy="0" ixz="0" iyz="0" ',
        ARM.read_text(),
    )
    for name, c in DAMPING.items():
        end = text.index("</joint>", text.index(f'<joint name="{name}"'))
        text = text[:end] + f'  <dynamics damping="{c}"/>\n  ' + text[end:]
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    return path


def driven(tmp_path, urdf: str, keys: list, law: dict, t_end: float, dt: float, slides=()):
    """The inverse dynamics of an overlay on ``urdf`` (in tmp_path) with ``keys`` in its
    ``[urdf]``, each joint of ``law`` driven along q = c + a sin(w t + φ) (a translation driver
    for the joints in ``slides``, a rotation driver otherwise)."""
    lines = ["[model]", 'name = "driven"', "[urdf]", f'file = "{urdf}"', "limits = false", *keys]
    for name, (c, a, w, phi) in law.items():
        lines += [
            "[[driver]]",
            f'name = "d_{name}"',
            f'type = "{"translation" if name in slides else "rotation"}"',
            f'joint = "{name}"',
            f'function = {{ kind = "expression", text = "{c!r} + {a!r} * sin({w!r} * t + {phi!r})" }}',
        ]
    lines += ["[analysis]", 'kind = "inverse_dynamics"', f"t_end = {t_end!r}", f"dt = {dt!r}", "position_tolerance = 1e-13"]
    model = cardan.Model.from_toml("\n".join(lines) + "\n", path=tmp_path / "overlay.toml")
    return model.inverse_dynamics()


def set_state(d, names: list, law: dict, t: float) -> None:
    """MuJoCo's q, q̇, q̈ of the joints ``names`` (dof i the i-th) along ``law`` at t."""
    for i, name in enumerate(names):
        c, a, w, phi = law[name]
        d.qpos[i] = c + a * math.sin(w * t + phi)
        d.qvel[i] = a * w * math.cos(w * t + phi)
        d.qacc[i] = -a * w * w * math.sin(w * t + phi)


def cardan_torques(tmp_path):
    return driven(tmp_path, "arm.urdf", ["damping = true"], LAW, t_end=2.0, dt=0.05)


def test_joint_damping_matches_mujoco_inverse_dynamics(tmp_path) -> None:
    path = damped_arm(tmp_path)
    m = mujoco.MjModel.from_xml_path(str(path))
    names = [m.joint(i).name for i in range(m.njnt)]
    assert names == list(LAW)
    assert np.allclose(m.dof_damping, [DAMPING[n] for n in names])
    d = mujoco.MjData(m)
    results = cardan_torques(tmp_path)
    efforts = results.driver_efforts
    worst = largest = damping_part = 0.0
    for k, t in enumerate(results.t):
        set_state(d, names, LAW, t)
        mujoco.mj_inverse(m, d)
        for i, name in enumerate(names):
            mine = efforts[f"d_{name}.torque"][k]
            worst = max(worst, abs(mine - d.qfrc_inverse[i]))
            largest = max(largest, abs(d.qfrc_inverse[i]))
            damping_part = max(damping_part, abs(DAMPING[name] * d.qvel[i]))
    print(f"|Δτ| {worst:.2e} N m of {largest:.2f} N m (the damping's part up to {damping_part:.3f} N m)")
    # The damping is a visible part of the torque, and the two agree far below it.
    assert damping_part > 0.01 * largest
    assert worst < 1e-9 * largest


# A cart on a rail (prismatic, x) carrying a pendulum arm (revolute about y), both joints with
# <dynamics damping friction>.
CART = """<?xml version="1.0"?>
<robot name="cart">
  <link name="rail"/>
  <link name="cart">
    <inertial><mass value="3.0"/><inertia ixx="0.05" ixy="0" ixz="0" iyy="0.06" iyz="0" izz="0.07"/></inertial>
  </link>
  <link name="arm">
    <inertial><origin xyz="0 0 -0.25"/><mass value="0.8"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.021" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="slide" type="prismatic">
    <parent link="rail"/><child link="cart"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="100" velocity="10"/>
    <dynamics damping="1.2" friction="0.7"/>
  </joint>
  <joint name="swing" type="continuous">
    <parent link="cart"/><child link="arm"/><origin xyz="0 0 -0.05"/><axis xyz="0 1 0"/>
    <dynamics damping="0.05" friction="0.03"/>
  </joint>
</robot>
"""
CART_LAW = {"slide": (0.1, 0.3, 1.7, 0.4), "swing": (0.2, 0.6, 2.3, 1.1)}
CART_DYNAMICS = {"slide": (1.2, 0.7), "swing": (0.05, 0.03)}


def test_joint_damping_and_friction_match_mujoco_inverse_dynamics(tmp_path) -> None:
    """``damping = true`` and ``friction = true``: a prismatic joint's damping a
    ``translational_spring_damper``, each joint's friction a ``[[friction]] law = "constant"``.
    MuJoCo reads the same ``<dynamics>`` as ``dof_damping`` and ``dof_frictionloss``; while a
    joint moves, ``mj_inverse`` gives its friction loss F_c sign(q̇) exactly. cardan's friction
    has the sign regularized, s(v) = v/√(v² + v_s²) (v_s = 1e-4 by default), so the comparison
    adds F_c (s(q̇) − sign(q̇)) to MuJoCo's efforts. MuJoCo's friction loss is a soft
    constraint, its force −(q̈ + b q̇)/R clamped to ±F_c: near a turning point, where the
    acceleration outweighs b q̇, it is not saturated against the motion (or even pushes along
    it); those samples, by MuJoCo's own constraint force (``efc_force``), are skipped, and
    so are |q̇| < 1e-3."""
    (tmp_path / "cart.urdf").write_text(CART)
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "cart.urdf"))
    names = [m.joint(i).name for i in range(m.njnt)]
    assert names == list(CART_LAW)
    assert np.allclose(m.dof_damping, [CART_DYNAMICS[n][0] for n in names])
    assert np.allclose(m.dof_frictionloss, [CART_DYNAMICS[n][1] for n in names])
    # cardan.load reads them the same way when asked.
    text = cardan.load(tmp_path / "cart.urdf", damping=True, friction=True).text
    assert 'type = "translational_spring_damper"\njoint = "slide"\ndamping = 1.2' in text
    assert 'law = "constant"\njoint = "swing"\ntorque = 0.03' in text
    with pytest.warns(UserWarning, match="damping or friction, which is not modelled"):
        assert "law = \"constant\"" not in cardan.load(tmp_path / "cart.urdf").text
    keys = ["damping = true", "friction = true"]
    results = driven(tmp_path, "cart.urdf", keys, CART_LAW, t_end=3.0, dt=0.01, slides=("slide",))
    efforts = results.driver_efforts
    d = mujoco.MjData(m)
    vs = 1e-4
    worst = largest = friction_part = 0.0
    compared = 0
    for k, t in enumerate(results.t):
        set_state(d, names, CART_LAW, t)
        mujoco.mj_inverse(m, d)
        # MuJoCo's friction row of each dof: saturated against the motion, or skipped.
        row = {int(d.efc_id[r]): d.efc_force[r] for r in range(d.nefc) if d.efc_type[r] == mujoco.mjtConstraint.mjCNSTR_FRICTION_DOF}
        for i, name in enumerate(names):
            v = d.qvel[i]
            fc = CART_DYNAMICS[name][1]
            if abs(v) < 1e-3 or not math.isclose(row[i], -math.copysign(fc, v), rel_tol=1e-12):
                continue
            theirs = d.qfrc_inverse[i] + fc * (v / math.hypot(v, vs) - math.copysign(1.0, v))
            col = f"d_{name}.force" if name == "slide" else f"d_{name}.torque"
            worst = max(worst, abs(efforts[col][k] - theirs))
            largest = max(largest, abs(theirs))
            friction_part = max(friction_part, fc)
            compared += 1
    print(f"{compared} samples: |Δ| {worst:.2e} of {largest:.2f} (friction up to {friction_part})")
    assert compared > 0.8 * 2 * len(results.t)
    assert friction_part > 0.05 * largest
    assert worst < 1e-9 * largest
