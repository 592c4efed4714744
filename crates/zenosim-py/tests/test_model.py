"""zenosim.Model and zenosim.ModelError."""

from __future__ import annotations

import pickle
import subprocess

import pytest

import zenosim
from conftest import MODELS

BALL = """\
name = "ball"
coordinates = ["y"]
lagrangian = "0.5*m*y_dot^2 - m*g*y"

[parameters]
m = 1.0
g = 9.81

[[constraint]]
name = "floor"
h = "y"
restitution = 1.5

[initial]
y = 1.0
"""


def test_a_model_file_is_read_with_its_names_and_values():
    model = zenosim.Model.from_file(MODELS / "ball-on-sine.toml")
    assert model.name == "ball-on-sine"
    assert model.coordinates == ["x1", "x2", "x3"]
    assert model.velocities == ["x1_dot", "x2_dot", "x3_dot"]
    assert model.parameters == {"m": 1.0, "g": 9.81, "e": 0.6}
    assert list(model.parameters) == ["m", "g", "e"]  # the file's order
    assert model.constraints == ["surface"]
    assert model.initial["x3"] == 2.0 and model.initial["x1_dot"] == 0.5
    assert model.file.endswith("ball-on-sine.toml")
    assert "ball-on-sine" in repr(model)


def test_a_model_from_text_equals_the_model_from_its_file():
    path = MODELS / "bouncing-ball.toml"
    from_text = zenosim.Model.from_toml(path.read_text())
    assert from_text.file == "<string>"
    assert from_text.parameters == zenosim.Model.from_file(path).parameters
    assert zenosim.run(from_text).final == zenosim.run(path).final


def test_models_pickle_for_other_processes():
    model = zenosim.Model.from_file(MODELS / "corner.toml")
    again = pickle.loads(pickle.dumps(model))
    assert (again.file, again.parameters) == (model.file, model.parameters)
    assert zenosim.run(again).final == zenosim.run(model).final


def test_a_bad_value_is_a_model_error_with_its_place(cli, tmp_path):
    path = tmp_path / "ball.toml"
    path.write_text(BALL)
    with pytest.raises(zenosim.ModelError) as raised:
        zenosim.Model.from_file(path)
    error = raised.value
    # `restitution = 1.5` is line 12; the value starts in column 15.
    assert (error.file, error.line, error.column) == (str(path), 12, 15)
    assert error.key == "constraint[1].restitution"
    assert isinstance(error, Exception)
    # The command line's message, word for word.
    done = subprocess.run([str(cli), "check", str(path)], capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr == f"error: {error}\n"


def test_a_syntax_error_is_placed():
    text = BALL.replace('coordinates = ["y"]', 'coordinates = ["y" "z"]')
    with pytest.raises(zenosim.ModelError) as raised:
        zenosim.Model.from_toml(text)
    error = raised.value
    # Line 2, at the second string, where a comma is missing.
    assert (error.file, error.line, error.column, error.key) == ("<string>", 2, 20, None)
    assert str(error).startswith("<string>:2:20: invalid TOML: missing comma")


def test_a_missing_key_is_named_without_a_place():
    text = BALL.replace('lagrangian = "0.5*m*y_dot^2 - m*g*y"\n', "")
    with pytest.raises(zenosim.ModelError) as raised:
        zenosim.Model.from_toml(text)
    error = raised.value
    assert (error.line, error.column, error.key) == (None, None, "lagrangian")
    assert "missing key `lagrangian`" in str(error)


def test_a_bad_override_names_it():
    with pytest.raises(zenosim.ModelError) as raised:
        zenosim.run(MODELS / "bouncing-ball.toml", set={"mass": 2.0})
    error = raised.value
    assert error.key == "mass"
    assert "--set mass=2" in str(error)


def test_a_file_that_is_not_utf8_is_placed(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(zenosim.ModelError) as raised:
        zenosim.Model.from_file(path)
    assert (raised.value.line, raised.value.column) == (1, 12)
    assert "UTF-8" in str(raised.value)


def test_model_error_can_be_raised_by_hand():
    error = zenosim.ModelError("made up")
    assert (error.file, error.line, error.column, error.key) == (None, None, None, None)


def test_bad_arguments():
    with pytest.raises(TypeError, match="from_file"):
        zenosim.Model.from_toml(b"name = 'x'")
    with pytest.raises(TypeError, match="not bytes"):
        zenosim.Model.from_file(b"models/ball-on-sine.toml")
    with pytest.raises(IsADirectoryError):
        zenosim.Model.from_file(MODELS)
