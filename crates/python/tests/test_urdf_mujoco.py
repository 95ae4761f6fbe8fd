"""URDF joint damping (issue 51) against MuJoCo 4.0.1: MuJoCo's URDF reader makes a joint's
``<dynamics damping>`` the joint's damping, and its inverse dynamics (``mj_inverse``) includes it
(the passive force −c q̇). cardan reads the same file with ``damping = true`` (each revolute
joint's damping a rotational damper) and drives every joint along a smooth trajectory
(inverse dynamics); the joint torques are compared at every output time."""

import math
import re

import mujoco
import numpy as np

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


def cardan_torques(tmp_path):
    lines = ["[model]", 'name = "damped"', "[urdf]", 'file = "arm.urdf"', "limits = false", "damping = true"]
    for name, (c, a, w, phi) in LAW.items():
        lines += [
            "[[driver]]",
            f'name = "d_{name}"',
            'type = "rotation"',
            f'joint = "{name}"',
            f'function = {{ kind = "expression", text = "{c!r} + {a!r} * sin({w!r} * t + {phi!r})" }}',
        ]
    lines += ["[analysis]", 'kind = "inverse_dynamics"', "t_end = 2.0", "dt = 0.05", "position_tolerance = 1e-13"]
    model = cardan.Model.from_toml("\n".join(lines) + "\n", path=tmp_path / "overlay.toml")
    return model.inverse_dynamics()


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
        for i, name in enumerate(names):
            c, a, w, phi = LAW[name]
            d.qpos[i] = c + a * math.sin(w * t + phi)
            d.qvel[i] = a * w * math.cos(w * t + phi)
            d.qacc[i] = -a * w * w * math.sin(w * t + phi)
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
