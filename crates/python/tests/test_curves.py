"""Curves from Python (issue 49): the builder's ``curve`` writes the model file's ``[[curve]]``
table and a driver of ``type="path"`` prescribes its parameter; the joint tables carry the
curve parameter u; a bad curve is a ModelError at its key."""

import math
import pathlib

import numpy as np

import pytest

import cardan

ROOT = pathlib.Path(__file__).resolve().parents[3]


def _arm(radius=0.1, speed=0.2):
    """A two-link planar arm whose tool point runs around a circle at constant speed."""
    b = cardan.Builder("arm_path")
    b.ground(points={"O": [0, 0, 0], "C": [0.3, 0.3, 0]}, vectors={"x": [1, 0, 0], "z": [0, 0, 1]})
    b.body("upper", mass=2.0, inertia={"diag": [1e-3, 3e-2, 3e-2]}, position=[0.2, 0, 0],
           points={"O": [-0.2, 0, 0], "E": [0.2, 0, 0]}, vectors={"x": [1, 0, 0], "z": [0, 0, 1]})
    b.body("fore", mass=1.0, inertia={"diag": [1e-3, 8e-3, 8e-3]}, position=[0.4, 0.15, 0],
           orientation={"axis": [0, 0, 1], "angle": math.pi / 2},
           points={"E": [-0.15, 0, 0], "tool": [0.15, 0, 0]}, vectors={"x": [1, 0, 0], "z": [0, 0, 1]})
    for name, (bi, pi, bj) in {"shoulder": ("ground", "O", "upper"), "elbow": ("upper", "E", "fore")}.items():
        b.joint(name, "revolute", body_i=bi, point_i=pi, axis_i="z", x_axis_i="x",
                body_j=bj, point_j=pi, axis_j="z", x_axis_j="x")
    b.curve("path", "circle", body_i="ground", point_i="C", axis_i="z", x_axis_i="x",
            radius=radius, body_j="fore", point_j="tool")
    b.driver("feed", type="path", curve="path", function=cardan.polynomial([0.0, speed]))
    b.analysis("kinematic", t_end=1.0, steps=50,
               outputs={"points": ["fore.tool"], "joints": ["elbow", "path"]})
    return b


def test_a_tool_point_runs_around_its_circle_at_the_path_speed():
    r = _arm().build().kinematics()
    joints = r.joints
    assert joints.names[-1] == "path.u"
    assert joints.unit("path.u") == "m"
    for t, u in zip(joints.t, joints["path.u"]):
        assert abs(u - 0.2 * t) < 1e-12
    rates = r.joint_velocities
    assert max(abs(v - 0.2) for v in rates["path.u"]) < 1e-12
    points = r.points
    for t, x, y in zip(points.t, points["fore.tool.x"], points["fore.tool.y"]):
        a = 0.2 * t / 0.1
        assert abs(x - (0.3 + 0.1 * math.cos(a))) < 1e-10
        assert abs(y - (0.3 + 0.1 * math.sin(a))) < 1e-10


def test_a_bad_curve_is_a_model_error_at_its_key():
    b = _arm(radius=-0.1)
    with pytest.raises(cardan.ModelError) as e:
        b.build()
    line = b.to_toml().splitlines()[e.value.line - 1]
    assert line == "radius = -0.1"
    assert 'curve "path"' in str(e.value)


def test_a_harmonic_cam_lifts_its_flat_faced_tappet_by_e_one_minus_cos():
    e, radius, w = 0.005, 0.02, 2 * math.pi
    b = cardan.Builder("valve")
    b.ground(points={"O": [0, 0, 0]}, vectors={"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]})
    b.body("camshaft", mass=0.5, inertia={"diag": [1e-4] * 3},
           points={"O": [0, 0, 0], "C": [0, -e, 0]}, vectors={"x": [1, 0, 0], "z": [0, 0, 1]})
    b.body("tappet", mass=0.1, inertia={"diag": [1e-5] * 3}, position=[0, radius - e, 0],
           points={"F": [0, 0, 0]}, vectors={"x": [1, 0, 0], "y": [0, 1, 0]})
    b.joint("bearing", "revolute", body_i="ground", point_i="O", axis_i="z", x_axis_i="x",
            body_j="camshaft", point_j="O", axis_j="z", x_axis_j="x")
    b.joint("guide", "prismatic", body_i="ground", point_i="O", axis_i="y",
            body_j="tappet", point_j="F", axis_j="y")
    b.cam("lobe", "flat", body_i="camshaft", axis_i="z", profile="disc", point_i="C",
          radius=radius, body_j="tappet", point_j="F", axis_j="x")
    b.driver("motor", type="rotation", joint="bearing", function=cardan.polynomial([0.0, w]))
    b.analysis("kinematic", t_end=1.0, steps=40, outputs={"joints": ["guide", "lobe"]})
    results = b.build().kinematics()
    joints = results.joints
    assert joints.names == ["guide.slide", "lobe.u", "lobe.w"]
    for t, s, face in zip(joints.t, joints["guide.slide"], joints["lobe.w"]):
        assert abs(s - (radius - e) - e * (1 - math.cos(w * t))) < 1e-12
        assert abs(face - e * math.sin(w * t)) < 1e-12
    # The cam's contact point (on the face above the disc's centre) and pressure angle (0).
    cams = results["cams"]
    assert cams.names == ["lobe.contact.x", "lobe.contact.y", "lobe.contact.z", "lobe.pressure_angle"]
    assert cams.unit("lobe.pressure_angle") == "rad"
    for t, x, angle in zip(cams.t, cams["lobe.contact.x"], cams["lobe.pressure_angle"]):
        assert abs(x - e * math.sin(w * t)) < 1e-12
        assert abs(angle) < 1e-12


def test_an_arm_tip_on_a_torus_sets_the_shaft_height():
    """The builder's ``surface`` writes ``[[surface]]``: an arm on a sliding shaft whose tip
    (0.3 m out) rides a torus about x (R = 1, r = 0.4), z(θ) = √((R + √(r² − x²))² − y²)."""
    b = cardan.Builder("torus_follower")
    b.ground(points={"O": [0, 0, 0]}, vectors={"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]})
    z0 = 1.0 + math.sqrt(0.16 - 0.09)
    b.body("arm", mass=1.0, inertia={"diag": [0.01, 0.01, 0.01]}, position=[0, 0, z0],
           points={"O": [0, 0, 0], "T": [0.3, 0, 0]}, vectors={"x": [1, 0, 0], "z": [0, 0, 1]})
    b.joint("shaft", "cylindrical", body_i="ground", point_i="O", axis_i="z", x_axis_i="x",
            body_j="arm", point_j="O", axis_j="z", x_axis_j="x")
    b.surface("ring", "torus", body_i="ground", point_i="O", axis_i="x", x_axis_i="y",
              radius=1.0, tube_radius=0.4, body_j="arm", point_j="T")
    b.driver("motor", type="rotation", joint="shaft",
             function=cardan.polynomial([0.0, 2 * math.pi]))
    b.analysis("kinematic", t_end=1.0, steps=40, outputs={"joints": ["shaft", "ring"]})
    joints = b.build().kinematics().joints
    assert joints.names[-2:] == ["ring.u", "ring.v"]
    for t, z in zip(joints.t, joints["shaft.slide"]):
        x, y = 0.3 * math.cos(2 * math.pi * t), 0.3 * math.sin(2 * math.pi * t)
        assert abs(z - math.sqrt((1.0 + math.sqrt(0.16 - x * x)) ** 2 - y * y)) < 1e-12


def test_a_billiard_ball_built_in_python_rolls_at_five_sevenths():
    """The builder's ``material`` and ``shape`` write ``[[material]]`` and ``[[shape]]``: a
    ball launched sliding at v0 on a table rolls at v0 / (1 + J/(m ρ²)) (5/7 v0 for a rigid
    contact; ρ = r − δ/2 the rolling radius, δ the static penetration)."""
    m, r, k, v0 = 0.17, 0.028575, 1e8, 2.0
    delta = (m * 9.81 / k) ** (2 / 3)
    j = 0.4 * m * r * r
    b = cardan.Builder("billiard", gravity=[0, 0, -9.81])
    b.ground(points={"O": [0, 0, 0]})
    b.body("ball", mass=m, inertia={"diag": [j, j, j]}, position=[0, 0, r - delta],
           velocity=[v0, 0, 0])
    b.material("cloth", stiffness=2 * k, restitution=0.8, friction=0.2, slip_velocity=1e-4)
    b.shape("ball", "sphere", "ball", "cloth", radius=r)
    b.shape("table", "plane", "ground", "cloth", point="O")
    b.analysis("dynamic", integrator="dopri5", rtol=1e-9, atol=1e-11, t_end=0.6, output_dt=0.3,
               outputs={"bodies": ["ball"]})
    v = b.build().dynamics().body_velocities
    rho = r - delta / 2
    assert abs(v["ball.r_dot.x"][-1] - v0 / (1 + j / (m * rho * rho))) < 1e-8


def test_the_contacts_of_a_run_are_arrays_with_the_closed_form_forces():
    """``Results.contacts()`` reads ``contacts.csv``: the billiard ball's one contact point per
    output time carries m g normally and, while it slides (t < 2 v0 / (7 μ g) = 0.29 s), the
    friction μ m g against its motion; the penetration is (m g / K)^(2/3) with the pair's K (once
    settled from its drawn height)."""
    r = cardan.load(ROOT / "examples/billiard.toml").run()
    c = r.contacts()
    m, g, mu = 0.17, 9.81, 0.2
    assert len(c) == len(r.t) and c.columns[:3] == ["point.x", "point.y", "point.z"]
    assert c.units["normal_force"] == "N" and c.units["penetration"] == "m"
    assert set(c.shape_1) | set(c.shape_2) == {"ball", "table"} and c.between("table", "ball").all()
    settled = c.t > 0.05  # the ball is drawn at a rounded height: it settles in a few ms
    assert np.allclose(c["normal_force"][settled], m * g, rtol=1e-6)
    assert np.allclose(c["penetration"][settled], (m * g / 1e8) ** (2 / 3), rtol=1e-6)
    sliding = settled & (c.t < 0.25)
    # friction.x is the force on shape 2: on the ball, against its motion.
    on_ball = np.where([s == "ball" for s in c.shape_2], c["friction.x"], -c["friction.x"])
    assert np.allclose(on_ball[sliding], -mu * m * g, rtol=1e-3)
    assert list(c.to_pandas().columns[:5]) == ["t", "shape_1", "body_1", "shape_2", "body_2"]
    with pytest.raises(AttributeError, match="no contacts"):
        cardan.load(ROOT / "examples/a01_pendulum.toml").run().contacts()
