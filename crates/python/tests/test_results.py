"""The Python results are the command's: same tables, CSV byte for byte; numpy access."""

import pathlib
import subprocess

import numpy as np
import pytest

import cardan
from conftest import EXAMPLES, run_cli

# One of each analysis kind, and the joint vocabulary's larger examples.
CASES = [
    "slider_crank.toml",
    "slider_crank_inverse.toml",
    "a01_pendulum.toml",
    "wobble_plate_pump.toml",
    "gear_train.toml",
    "expression_driver.toml",
]


@pytest.mark.parametrize("name", CASES)
def test_csv_files_equal_the_commands_byte_for_byte(name, cardan_bin, tmp_path):
    model = EXAMPLES / name
    cli = run_cli(cardan_bin, model, tmp_path / "cli")
    assert cli.returncode == 0, cli.stderr
    results = cardan.load(model).run()
    results.to_csv(tmp_path / "py")
    cli_csv = sorted(p.name for p in (tmp_path / "cli").glob("*.csv"))
    py_csv = sorted(p.name for p in (tmp_path / "py").glob("*.csv"))
    assert cli_csv == py_csv
    for f in cli_csv:
        assert (tmp_path / "cli" / f).read_bytes() == (tmp_path / "py" / f).read_bytes(), f


def test_tables_are_float64_arrays_with_names_and_units():
    r = cardan.load(EXAMPLES / "slider_crank.toml").kinematics()
    pts = r.points
    assert pts.values.dtype == np.float64 and pts.values.shape == (len(r.t), len(pts.columns))
    assert r.t[0] == 0.0 and np.all(np.diff(r.t) > 0)
    x = pts["slider.C.x"]
    assert pts.unit("slider.C.x") == "m"
    # Haug's closed form of the slider position (examples/slider_crank.toml's header).
    th = 2 * np.pi * r.t
    by, bz = 0.1 - 0.08 * np.sin(th), 0.12 + 0.08 * np.cos(th)
    np.testing.assert_allclose(x, np.sqrt(0.3**2 - by**2 - bz**2), atol=1e-9)
    with pytest.raises(KeyError, match="no column"):
        pts["nothing"]
    with pytest.raises(AttributeError, match="no table"):
        r.reactions
    assert r.status == "complete" and r.warnings == []


def test_options_override_the_file_and_switch_the_kind():
    m = cardan.load(EXAMPLES / "slider_crank_inverse.toml")
    r = m.kinematics(t_end=0.5, steps=50)
    assert r.kind == "kinematic" and len(r.t) == 51 and r.t[-1] == 0.5
    assert "driver_efforts" not in r.tables
    r = m.inverse_dynamics(t_end=0.5, steps=50, outputs={"points": ["slider.C"]})
    assert "driver_efforts" in r.tables and list(r.points.names) == ["slider.C.x", "slider.C.y", "slider.C.z"]


def test_position_tolerance_and_its_older_name(tmp_path):
    """`position_tolerance` (and `tolerance`, its older name) set the kinematic position
    tolerance; the one given replaces the file's other one instead of clashing with it."""
    text = (EXAMPLES / "slider_crank.toml").read_text()
    file = tmp_path / "tolerance.toml"
    file.write_text(text.replace("[analysis]", "[analysis]\ntolerance = 1e-12"))
    m = cardan.load(file)
    tight = m.kinematics(steps=20, position_tolerance=1e-14)
    old = m.kinematics(steps=20, tolerance=1e-14)
    np.testing.assert_array_equal(tight.points.values, old.points.values)
    with pytest.raises(cardan.ModelError, match="tolerance = 0.001 is outside"):
        m.kinematics(steps=20, position_tolerance=1e-3)


def test_pandas_frames():
    r = cardan.load(EXAMPLES / "slider_crank.toml").kinematics(steps=20)
    df = r.to_pandas("points")
    assert df.index.name == "t [s]" and list(df.columns) == r.points.columns
    np.testing.assert_array_equal(df.to_numpy(), r.points.values)


def test_dataframe_columns_are_the_csv_headers():
    r = cardan.load(EXAMPLES / "slider_crank_inverse.toml").inverse_dynamics(steps=20)
    for name, table in r.tables.items():
        header = table.to_csv().splitlines()[0].split(",")
        assert list(r.to_pandas(name).reset_index().columns) == header, name


def test_plot_puts_each_unit_on_its_own_axis():
    import matplotlib

    matplotlib.use("Agg")
    r = cardan.load(EXAMPLES / "slider_crank.toml").kinematics(steps=20)
    fig = r.plot("joints")
    units = {a.get_ylabel() for a in fig.axes}
    assert len(fig.axes) == len(units) >= 2


def test_builder_gives_the_same_results_as_the_file(tmp_path):
    b = cardan.Builder("pendulum", gravity=np.array([0.0, 0.0, -9.81]))
    b.ground(points={"O": [0.0, 0.0, 0.0]}, vectors={"x": [1.0, 0.0, 0.0]})
    b.body("rod", mass=1.0, inertia={"diag": [0.1, 0.1, 0.01]}, position=np.array([0.0, 0.0, -0.5]),
           points={"O": [0.0, 0.0, 0.5]}, vectors={"x": [1.0, 0.0, 0.0]})
    b.joint("pin", "revolute", body_i="ground", point_i="O", axis_i="x", body_j="rod", point_j="O", axis_j="x")
    b.analysis("dynamic", t_end=0.5, output_dt=0.01, outputs={"bodies": ["rod"]})
    model = b.build()
    assert model.check().dof == 1
    r = model.dynamics()
    file = tmp_path / "pendulum.toml"
    file.write_text(b.to_toml())
    r2 = cardan.load(file).run()
    np.testing.assert_array_equal(r.bodies.values, r2.bodies.values)
    # It hangs at rest, so it stays there.
    np.testing.assert_allclose(r.bodies["rod.r.z"], -0.5, atol=1e-9)


def test_check_reports_dof_and_redundant_equations():
    c = cardan.load(EXAMPLES / "slider_crank.toml").check()
    assert c.dof == 1 and c.fully_driven and c.redundant == []
    assert c.bodies == ["crank", "conrod", "slider"]


ASMT = EXAMPLES.parent / "crates" / "asmt" / "tests" / "data"


def test_asmt_assemblies_load_and_equal_the_commands_run(cardan_bin, tmp_path):
    model = ASMT / "fourbar.asmt"
    r = cardan.load(model).run()
    cli = run_cli(cardan_bin, model, tmp_path / "cli")
    assert cli.returncode == 0, cli.stderr
    r.to_csv(tmp_path / "py")
    for f in (tmp_path / "cli").glob("*.csv"):
        assert f.read_bytes() == (tmp_path / "py" / f.name).read_bytes(), f.name


def test_asmt_in_millimetres_equals_the_commands_run(cardan_bin, tmp_path):
    model = ASMT / "crank_slider.asmt"
    r = cardan.load(model, units="mm").run()
    assert any(u == "mm" for t in r.tables.values() for u in t.units)
    cli = subprocess.run(
        [cardan_bin, "run", str(model), "-o", str(tmp_path / "cli"), "--quiet", "--units", "mm"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert cli.returncode == 0, cli.stderr
    r.to_csv(tmp_path / "py")
    for f in (tmp_path / "cli").glob("*.csv"):
        assert f.read_bytes() == (tmp_path / "py" / f.name).read_bytes(), f.name
    with pytest.raises(ValueError, match="ASMT files"):
        cardan.load(EXAMPLES / "slider_crank.toml", units="mm")


def test_a_bad_asmt_file_is_a_model_error_at_its_line(tmp_path):
    text = (ASMT / "fourbar.asmt").read_text().replace("\t", "    ", 1)
    bad = tmp_path / "bad.asmt"
    bad.write_text(text)
    with pytest.raises(cardan.ModelError) as e:
        cardan.load(bad)
    assert e.value.line is not None and e.value.file.endswith("bad.asmt")


def test_a_report_run_gives_the_commands_animation_and_page(tmp_path):
    r = cardan.load(EXAMPLES / "slider_crank.toml").kinematics(report=True)
    assert r.glb[:4] == b"glTF"
    assert r.html.startswith("<!DOCTYPE html>") and "window.THREE" in r.html
    assert r._repr_html_().startswith("<iframe srcdoc=")
    paths = r.save_report(tmp_path)
    assert [pathlib.Path(p).name for p in paths] == ["animation.glb", "index.html"]
    plain = cardan.load(EXAMPLES / "slider_crank.toml").kinematics()
    assert plain.glb is None and plain._repr_html_() is None
    with pytest.raises(ValueError, match="report=True"):
        plain.save_report(tmp_path)


def test_static_and_modal_runs():
    m = cardan.load(EXAMPLES / "fourbar_spring_modal.toml")
    r = m.modal()
    assert "modes" in r.tables and any(n.endswith(".mtx") for n in r.files)
    s = m.statics()
    assert "stability" in s.tables
