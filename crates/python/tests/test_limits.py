"""Limits and joint friction from Python (issue 48): the builder's ``limit`` and ``friction``
write the model file's ``[[limit]]`` and ``[[friction]]`` tables; a run's ``stops`` table holds
each stop's state and force, its ``friction`` table each friction's torque and power; a bad limit is a ModelError at its key."""

import math

import pytest

import cardan


def _pendulum(friction=None, **limit):
    b = cardan.Builder("pendulum", gravity=[0, -9.81, 0])
    b.ground(points={"O": [0, 0, 0]}, vectors={"z": [0, 0, 1], "x": [1, 0, 0]})
    b.body("rod", mass=1.0, inertia={"diag": [1e-4, 1 / 12, 1 / 12]}, position=[0.5, 0, 0],
           points={"O": [-0.5, 0, 0]}, vectors={"z": [0, 0, 1], "x": [1, 0, 0]})
    b.joint("hinge", "revolute", body_i="ground", point_i="O", axis_i="z", x_axis_i="x",
            body_j="rod", point_j="O", axis_j="z", x_axis_j="x")
    b.limit("stop", "hinge", **limit)
    b.friction("pin", "hinge", **(friction or {"coefficient": 0.0, "radius": 0.01}))
    b.analysis("dynamic", integrator="dopri5", rtol=1e-10, atol=1e-12, t_end=1.0, output_dt=0.01)
    return b


def test_a_pendulum_rests_on_its_stop_with_the_closed_form_reaction():
    r = _pendulum(lower=-math.pi / 3).build().dynamics()
    stops = r["stops"]
    assert stops.names == ["stop.lower held", "stop.lower force"]
    assert stops.unit("stop.lower force") == "N m"
    # e = 0: held from the first impact on, carrying m g (L/2) cos 60°.
    assert stops["stop.lower held"][-1] == 1.0
    assert abs(stops["stop.lower force"][-1] - 9.81 * 0.5 * 0.5) < 1e-6
    assert r.warnings == []
    # The joint's friction (here μ = 0) has its own table: torque and power per element.
    friction = r["friction"]
    assert friction.names == ["pin torque", "pin power"]
    assert friction.unit("pin torque") == "N m"
    assert max(abs(x) for x in friction["pin torque"]) == 0.0


def test_a_bad_limit_is_a_model_error_at_its_key():
    b = _pendulum(lower=0.5, upper=0.2)
    with pytest.raises(cardan.ModelError) as e:
        b.build()
    line = b.to_toml().splitlines()[e.value.line - 1]
    assert line == "upper = 0.2"
    assert "range is empty" in str(e.value)


def test_a_constant_friction_torque_from_the_builder():
    """``friction(name, joint, torque=T_c)`` without a coefficient writes ``law = "constant"``:
    the pin's friction torque is T_c s(θ̇) against the swing, whatever the load."""
    b = _pendulum(friction={"torque": 0.05}, lower=-math.pi)
    assert 'joint = "hinge"\nlaw = "constant"\ntorque = 0.05' in b.to_toml()
    r = b.build().dynamics()
    torque = r["friction"]["pin torque"]
    assert max(abs(x) for x in torque) <= 0.05 + 1e-15
    assert max(abs(x) for x in torque) > 0.0499
