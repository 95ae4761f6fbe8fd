"""URDF robots in Python (issue 51): ``cardan.load("robot.urdf", base=, mimic=, limits=)`` and an
overlay from text; the URDF options are refused for other files, a bad URDF is a ModelError at
its line. (The comparison with Pinocchio is test_urdf_pinocchio.py.)"""

import pytest

import cardan
from conftest import EXAMPLES

ARM = EXAMPLES / "urdf" / "three_link_arm.urdf"


def test_a_urdf_loads_with_its_options() -> None:
    model = cardan.load(ARM)
    check = model.check()
    assert check.dof == 3
    assert check.bodies == ["turret", "upper_arm", "forearm"]
    assert "[[limit]]" in model.text
    assert "[[limit]]" not in cardan.load(ARM, limits=False).text
    # A floating base: the arm's root link has no mass, so its free body is refused by name.
    with pytest.raises(cardan.ModelError, match='link "base_link" moves and has no mass'):
        cardan.load(ARM, base="floating")


def test_joint_damping_is_a_damper_when_asked_for(tmp_path) -> None:
    damped = tmp_path / "damped.urdf"
    damped.write_text(ARM.read_text().replace("</joint>", '<dynamics damping="0.2"/></joint>', 1))
    with pytest.warns(UserWarning, match="not modelled"):
        plain = cardan.load(damped)
    assert "rotational_spring_damper" not in plain.text
    model = cardan.load(damped, damping=True)
    assert 'type = "rotational_spring_damper"\njoint = "turret_joint"\ndamping = 0.2' in model.text


def test_urdf_options_are_refused_elsewhere_and_checked() -> None:
    with pytest.raises(ValueError, match="apply to URDF files"):
        cardan.load(EXAMPLES / "slider_crank.toml", base="floating")
    with pytest.raises(ValueError, match="apply to URDF files"):
        cardan.load(EXAMPLES / "slider_crank.toml", damping=True)
    with pytest.raises(ValueError, match="ASMT"):
        cardan.load(ARM, units="mm")
    with pytest.raises(ValueError, match="fixed"):
        cardan.load(ARM, base="flying")


def test_a_bad_urdf_is_a_model_error_at_its_line(tmp_path) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r">\n<link name="a"/>\n<joint name="j" type="hinge"><parent link="a"/><child link="a"/></joint>\n</robot>\n')
    with pytest.raises(cardan.ModelError, match="unknown joint type") as e:
        cardan.load(bad)
    assert "bad.urdf:3" in str(e.value)


def test_an_overlay_from_text_drives_the_robot() -> None:
    text = f"""
[model]
name = "wave"
[urdf]
file = "{ARM}"
[[driver]]
name = "turn"
type = "rotation"
joint = "turret_joint"
function = {{ kind = "expression", text = "0.5 * t" }}
[[driver]]
name = "lift"
type = "rotation"
joint = "shoulder"
function = {{ kind = "expression", text = "0.3 * sin(t)" }}
[[driver]]
name = "bend"
type = "rotation"
joint = "elbow"
function = {{ kind = "constant", value = 0.5 }}
[analysis]
kind = "inverse_dynamics"
t_end = 1.0
dt = 0.1
"""
    results = cardan.Model.from_toml(text).inverse_dynamics()
    assert len(results.t) == 11
    # The elbow held at 0.5 rad against gravity: a torque.
    assert abs(results.driver_efforts["bend.torque"]).max() > 0.1
