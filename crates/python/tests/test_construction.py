"""A model is validated when it is made (issue 46): from a file, a string or a builder, a bad
model raises ModelError at once, naming its source; paths may be pathlib.Path."""

import pathlib

import pytest

import cardan
from conftest import EXAMPLES

BROKEN = (EXAMPLES / "slider_crank.toml").read_text().replace('type = "spherical"', 'type = "sphrical"')
BROKEN_LINE = next(k for k, l in enumerate(BROKEN.splitlines(), 1) if "sphrical" in l)


def test_from_toml_validates_at_once_and_names_the_string():
    with pytest.raises(cardan.ModelError) as e:
        cardan.Model.from_toml(BROKEN)
    err = e.value
    assert (err.file, err.line) == ("<string>", BROKEN_LINE)
    assert err.printed.startswith(f"<string>:{BROKEN_LINE}:")
    assert cardan.Model.from_toml(BROKEN.replace("sphrical", "spherical")).path == "<string>"


def test_load_validates_a_file_and_takes_a_path(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(BROKEN)
    with pytest.raises(cardan.ModelError) as e:
        cardan.load(bad)
    assert e.value.file == str(bad) and e.value.line == BROKEN_LINE
    for path in (EXAMPLES / "slider_crank.toml", str(EXAMPLES / "slider_crank.toml")):
        m = cardan.Model.load(path)
        assert isinstance(m, cardan.Model) and m.path == str(EXAMPLES / "slider_crank.toml")
    text = (EXAMPLES / "slider_crank.toml").read_text()
    assert cardan.Model.from_toml(text, pathlib.Path("a.toml")).path == "a.toml"


def test_a_builder_is_validated_by_build():
    b = cardan.Builder("loose")
    b.body("rod", mass=1.0, inertia={"diag": [1, 1, 1]}, points={"O": [0, 0, 0]})
    b.joint("pin", "revolute", body_i="ground", point_i="O", body_j="rod", point_j="O")
    with pytest.raises(cardan.ModelError) as e:
        b.build()
    assert e.value.file == "<builder loose>" and e.value.line is not None
