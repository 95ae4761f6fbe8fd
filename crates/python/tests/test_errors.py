"""Failures are exceptions with the fields a program needs."""

import pytest

import cardan
from conftest import EXAMPLES


def test_a_broken_model_raises_model_error_with_its_place():
    text = (EXAMPLES / "slider_crank.toml").read_text().replace('type = "spherical"', 'type = "sphrical"')
    with pytest.raises(cardan.ModelError) as e:
        cardan.Model.from_toml(text, "broken.toml").check()
    err = e.value
    line = next(k for k, l in enumerate(text.splitlines(), 1) if "sphrical" in l)
    assert err.file == "broken.toml" and err.line == line and err.column is not None
    assert "spherical" in err.message  # the nearest valid kind is suggested
    assert err.printed.startswith(f"broken.toml:{line}:")


def test_a_syntax_error_is_located():
    with pytest.raises(cardan.ModelError) as e:
        cardan.Model.from_toml("[model]\nname = \n", "s.toml").check()
    assert e.value.line == 2


def test_an_unknown_body_names_the_element():
    text = (EXAMPLES / "slider_crank.toml").read_text().replace('body_j = "conrod"', 'body_j = "conrad"', 1)
    with pytest.raises(cardan.ModelError) as e:
        cardan.Model.from_toml(text, "m.toml").run()
    assert e.value.element is not None and "conrad" in e.value.message


def pushed_crank(t_end: float) -> cardan.Model:
    """A crank of length 1 on a pivot, its tip pushed to x = t: stretched (singular) at t = 1,
    no position after that."""
    b = cardan.Builder("pushed")
    b.ground(points={"O": [0, 0, 0]}, vectors={"z": [0, 0, 1], "x": [1, 0, 0]})
    b.body("crank", mass=1.0, inertia={"diag": [0.01, 0.1, 0.1]}, position=[0.0, 0.5, 0.0],
           orientation={"axis": [0.0, 0.0, 1.0], "angle": 1.5707963267948966},
           points={"O": [-0.5, 0, 0], "tip": [0.5, 0, 0]}, vectors={"z": [0, 0, 1], "x": [1, 0, 0]})
    b.joint("pivot", "revolute", body_i="ground", point_i="O", axis_i="z", body_j="crank",
            point_j="O", axis_j="z", x_axis_i="x", x_axis_j="x")
    b.driver("push", type="coordinate", body="crank", point="tip", coordinate="x",
             function=cardan.polynomial([0.0, 1.0]))
    b.analysis("kinematic", t_end=t_end, steps=int(round(50 * t_end)))
    return b.build()


def test_a_singular_run_raises_analysis_error_with_time_and_partial_results():
    with pytest.raises(cardan.AnalysisError) as e:
        pushed_crank(2.0).run()
    err = e.value
    # The solver's failure is a SolverError, an AnalysisError; it names the element.
    assert isinstance(err, cardan.SolverError) and err.element in ("push", "pivot")
    # The failed step is subdivided down to 1/1024 of it: the run stops just past t = 1 s.
    assert err.time == pytest.approx(1.0 + 0.02 / 1024)
    assert "push" in err.equations and "pivot" in err.equations
    assert err.partial is not None and err.partial.status == "partial"
    assert len(err.partial.t) == 51 and err.partial.t[-1] == pytest.approx(1.0)
    # The tip reached x = 1 (stretched), within the accuracy of a singular root.
    assert err.partial.points["crank.tip.x"][-1] == pytest.approx(1.0, abs=1e-6)
    assert pushed_crank(0.9).run().status == "complete"
    import pickle

    again = pickle.loads(pickle.dumps(err))
    assert type(again) is cardan.SolverError
    assert again.time == err.time and again.equations == err.equations
    assert len(again.partial.t) == 51


def test_errors_pickle():
    import pickle

    e = cardan.ModelError("bad", "f:1:2: error: bad", "f", 1, 2)
    e2 = pickle.loads(pickle.dumps(e))
    assert (e2.file, e2.line, e2.column, e2.message) == ("f", 1, 2, "bad")


def test_strict_warnings_are_an_analysis_error_not_a_solver_error():
    # The A01 pendulum on fixed DOPRI5 steps of 0.25 s: its energy grows, a warning
    # (crates/cli/tests/doubtful_results.rs).
    text = (EXAMPLES / "a01_pendulum.toml").read_text()
    adaptive = "rtol = 1e-10\natol = 1e-12\nt_end = 10.0\noutput_dt = 0.05"
    assert adaptive in text
    m = cardan.Model.from_toml(text.replace(adaptive, "dt = 0.25\nt_end = 20.0\noutput_dt = 0.5"))
    assert m.dynamics().warnings
    with pytest.raises(cardan.AnalysisError) as e:
        m.dynamics(strict=True)
    assert not isinstance(e.value, cardan.SolverError) and "--strict" in e.value.message


def test_every_error_has_file_line_column_and_element():
    text = (EXAMPLES / "slider_crank.toml").read_text().replace('joint = "crank_pin"', 'joint = "crank_pn"', 1)
    with pytest.raises(cardan.ModelError) as e:
        cardan.Model.from_toml(text, "m.toml")
    err = e.value
    assert err.file == "m.toml" and err.line is not None and err.column is not None
    assert err.element is not None
