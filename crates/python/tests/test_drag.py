"""Dragging from Python (issue 53, item 4): ``Model.drag`` pulls a point of a body toward a
target, the rest following by least change, and stops at a joint limit; the pose it returns
starts the next step, as a mouse drag in FreeCAD does."""

import math

import pytest

import cardan
from conftest import EXAMPLES



def _model():
    # examples/pendulum_stop.toml: a 1 m rod hinged at O about z, a stop at −60°.
    return cardan.load(EXAMPLES / "pendulum_stop.toml")


def _angle(pose):
    (x, y, _), _p = pose["rod"]
    return math.atan2(y, x)


def test_the_rod_follows_the_cursor_and_stops_at_its_limit():
    model = _model()
    pose = None
    # Round from 0 towards −90°, in 5° steps, each repeated so the soft pull closes its lag.
    for k in range(1, 19):
        theta = -math.radians(5 * k)
        target = [math.cos(theta), math.sin(theta), 0.0]
        for _ in range(4):
            step = model.drag("rod", target, point="tip", pose=pose)
            pose = step.pose
        if theta >= -math.pi / 3 - 1e-9:  # up to the stop itself
            assert step.stop is None
            assert step.distance < 1e-9
            assert _angle(pose) == pytest.approx(theta, abs=1e-9)
        else:
            assert step.stop == "stop"
            assert step.reached < 1.0
            assert _angle(pose) == pytest.approx(-math.pi / 3, abs=1e-9)
    # The centre of mass stays 0.5 m from the hinge: the joint holds while dragged.
    (x, y, z), p = pose["rod"]
    assert math.hypot(x, y) == pytest.approx(0.5, abs=1e-12) and z == pytest.approx(0.0, abs=1e-12)
    assert sum(c * c for c in p) == pytest.approx(1.0, abs=1e-12)


def test_a_bad_drag_is_an_analysis_error():
    model = _model()
    with pytest.raises(cardan.AnalysisError, match="no point"):
        model.drag("rod", [1, 0, 0], point="nowhere")
    with pytest.raises(cardan.AnalysisError, match="no body"):
        model.drag("arm", [1, 0, 0])
    with pytest.raises(cardan.AnalysisError, match="ground"):
        model.drag("ground", [1, 0, 0])
