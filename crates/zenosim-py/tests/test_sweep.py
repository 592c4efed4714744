"""zenosim.sweep: its table, against the closed form and against single runs."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

import zenosim
from conftest import MODELS, interrupt

BALL = MODELS / "bouncing-ball.toml"


def closed_form_zeno_time(g: float, e: float, h0: float) -> float:
    """The bouncing ball dropped from rest at h0: t1 = sqrt(2 h0/g), v1 = g t1, and the flights
    after the first impact sum to 2 e v1 / (g (1 - e))."""
    t1 = math.sqrt(2 * h0 / g)
    return t1 + 2 * e * g * t1 / (g * (1 - e))


def test_fifty_restitutions_against_the_closed_form():
    model = zenosim.Model.from_file(BALL)
    restitutions = np.linspace(0.05, 0.9, 50)
    # The file's t_end is 3 s; at e = 0.9 the Zeno time is 8.6 s.
    table = zenosim.sweep(model, {"e": restitutions}, t_end=10.0)
    assert isinstance(table, dict) and isinstance(table, zenosim.SweepTable)
    np.testing.assert_array_equal(table["e"], restitutions)
    assert list(table["status"]) == ["finished"] * 50
    g, h0 = model.parameters["g"], model.parameters["h0"]
    expected = np.array([closed_form_zeno_time(g, e, h0) for e in restitutions])
    np.testing.assert_allclose(table["t_zeno"], expected, rtol=1e-9)
    assert np.all(table["t_switch"] <= table["t_zeno"] + 1e-9)
    # More bounces before the switch as e grows.
    assert np.all(np.diff(table["impacts"]) >= 0) and table["impacts"][-1] > table["impacts"][0]
    # At rest on the floor at the end.
    np.testing.assert_allclose(table["final_y"], 0.0, atol=1e-9)
    np.testing.assert_allclose(table["final_y_dot"], 0.0, atol=1e-9)


def test_columns_and_a_row_equal_to_a_single_run():
    model = zenosim.Model.from_file(MODELS / "ball-on-sine.toml")
    values = {"e": [0.5, 0.6], "x1_dot": [0.0, 0.25, 0.5]}
    table = zenosim.sweep(model, values, t_end=4.0)
    assert list(table) == [
        "e", "x1_dot", "status", "impacts", "t_zeno", "t_switch", "t_final",
        "final_x1", "final_x2", "final_x3", "final_x1_dot", "final_x2_dot", "final_x3_dot",
        "message",
    ]  # fmt: skip
    assert table.rows == 6
    assert {len(column) for column in table.values()} == {6}
    # The product, the last name fastest.
    np.testing.assert_array_equal(table["e"], [0.5, 0.5, 0.5, 0.6, 0.6, 0.6])
    np.testing.assert_array_equal(table["x1_dot"], [0.0, 0.25, 0.5] * 2)
    for i in range(6):
        e, x1_dot = table["e"][i], table["x1_dot"][i]
        run = zenosim.run(model, t_end=4.0, set={"e": e, "x1_dot": x1_dot})
        assert table["status"][i] == run.status
        assert table["message"][i] == run.message
        assert table["impacts"][i] == sum(ev["kind"] == "impact" for ev in run.events)
        assert table["t_zeno"][i] == run.zeno[0]["t_zeno"]
        assert table["t_switch"][i] == run.zeno[0]["t_switch"]
        assert table["t_final"][i] == run.final["t"]
        for k, name in enumerate(model.coordinates):
            assert table[f"final_{name}"][i] == run.final["q"][k]
            assert table[f"final_{name}_dot"][i] == run.final["q_dot"][k]


def test_zipped_values_are_the_products_diagonal():
    values = {"e": [0.3, 0.5, 0.7], "h0": [0.5, 1.0, 2.0]}
    zipped = zenosim.sweep(BALL, values, product=False)
    full = zenosim.sweep(BALL, values)
    assert zipped.rows == 3 and full.rows == 9
    for column in zipped:
        np.testing.assert_array_equal(zipped[column], full[column][[0, 4, 8]])


def test_workers_do_not_change_the_rows():
    values = {"e": np.linspace(0.1, 0.9, 17)}
    one = zenosim.sweep(BALL, values, workers=1)
    two = zenosim.sweep(BALL, values, workers=2)
    for column in one:
        np.testing.assert_array_equal(one[column], two[column])


def test_no_zeno_point_is_nan_and_refused_points_are_rows():
    # zeno="off" stops at the Zeno point; a restitution of 1.5 is refused by the model.
    table = zenosim.sweep(BALL, {"e": [0.5, 1.5]}, zeno="off")
    assert list(table["status"]) == ["zeno_stalled", "invalid"]
    assert "restitution" in table["message"][1]
    assert math.isnan(table["t_switch"][1]) and math.isnan(table["t_zeno"][1])
    elastic = zenosim.sweep(BALL, {"e": [1.0]}, t_end=2.0)
    assert elastic["status"][0] == "finished" and math.isnan(elastic["t_zeno"][0])


def test_to_pandas():
    pandas = pytest.importorskip("pandas")
    table = zenosim.sweep(BALL, {"e": [0.5, 0.6]})
    frame = table.to_pandas()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == list(table)
    np.testing.assert_array_equal(frame["t_zeno"].to_numpy(), table["t_zeno"])


@pytest.mark.parametrize(
    "values, kwargs, error, words",
    [
        ([0.5], {}, TypeError, "dict"),
        ({"e": 0.5}, {}, TypeError, "sequence"),
        ({"e": "0.5"}, {}, TypeError, "sequence"),
        ({"e": ["0.5"]}, {}, TypeError, "number"),
        ({"e": [True]}, {}, TypeError, "number"),
        ({"e": []}, {}, ValueError, "no values"),
        ({"e": [float("inf")]}, {}, ValueError, "finite"),
        ({"mass": [1.0]}, {}, ValueError, "not a parameter or an initial value"),
        ({}, {}, ValueError, "at least one name"),
        ({"e": [0.5], "h0": [1, 2]}, dict(product=False), ValueError, "same number"),
        ({"e": [0.5]}, dict(workers=0), ValueError, "at least 1"),
        ({"e": [0.5]}, dict(zeno="never"), ValueError, "zeno="),
        ({"e": [0.5]}, dict(t_end=-1.0), ValueError, "t_end"),
    ],
)
def test_bad_arguments_are_clear_errors(values, kwargs, error, words):
    with pytest.raises(error, match=words):
        zenosim.sweep(BALL, values, **kwargs)


SCRIPT = textwrap.dedent(
    """
    import sys, time, numpy, zenosim
    print("started", flush=True)
    start = time.perf_counter()
    try:
        zenosim.sweep(sys.argv[1], {"e": numpy.linspace(0.1, 0.7, 400)},
                      t_end=2e4, rtol=1e-12, atol=1e-12, workers=2)
    except KeyboardInterrupt:
        print(f"interrupted after {time.perf_counter() - start:.3f}", flush=True)
        sys.exit(42)
    print("finished", flush=True)
    """
)


def test_ctrl_c_interrupts_a_sweep():
    code, out, _, latency = interrupt(SCRIPT, str(MODELS / "ball-on-sine.toml"), delay=0.5)
    assert code == 42, out
    # Loose (a loaded machine), yet far below the minutes the sweep would take.
    assert latency < 10.0, latency


def test_a_sweep_of_initial_values_alone_equals_single_runs():
    # Initial values only: the sweep may run the model read once, from each start.
    model = zenosim.Model.from_file(MODELS / "ball-on-sine.toml")
    values = {"x3": [1.0, 2.0, 3.0], "x2_dot": [-0.5, 0.5]}
    table = zenosim.sweep(model, values, t_end=3.0)
    for i in range(table.rows):
        run = zenosim.run(
            model, t_end=3.0, set={"x3": table["x3"][i], "x2_dot": table["x2_dot"][i]}
        )
        assert table["status"][i] == run.status and table["message"][i] == run.message
        if run.zeno:
            assert table["t_zeno"][i] == run.zeno[0]["t_zeno"]
        else:
            assert math.isnan(table["t_zeno"][i])
        for k, name in enumerate(model.coordinates):
            assert table[f"final_{name}"][i] == run.final["q"][k]
            assert table[f"final_{name}_dot"][i] == run.final["q_dot"][k]


def test_a_varied_name_that_is_also_a_result_column_is_refused(tmp_path):
    # A parameter named `status` was swept, and the table's results replaced its values.
    model = tmp_path / "ball.toml"
    model.write_text(BALL.read_text().replace("h0 = 1.0", "h0 = 1.0\nstatus = 2.0"))
    with pytest.raises(ValueError, match="`status` is varied, but the sweep's table also has"):
        zenosim.sweep(model, {"status": [1.0, 2.0]})


def test_a_million_workers_are_refused_at_once():
    # sweep(workers=10**6) spent 22 s starting threads before the system refused.
    with pytest.raises(ValueError, match="more than the 1024 threads a sweep starts"):
        zenosim.sweep(BALL, {"e": [0.5, 0.6]}, workers=10**6)
    # More workers than points start only as many threads as there are points.
    table = zenosim.sweep(BALL, {"e": [0.5, 0.6]}, workers=1000)
    assert list(table["status"]) == ["finished", "finished"]


@pytest.mark.parametrize("name", ["t_end", "rtol", "atol"])
def test_a_bool_is_not_a_number(name):
    # t_end=True was taken as 1.0.
    with pytest.raises(TypeError, match=f"{name} must be a number, not a bool"):
        zenosim.sweep(BALL, {"e": [0.5]}, **{name: True})
    with pytest.raises(TypeError, match=f"{name} must be a number, not a bool"):
        zenosim.run(BALL, **{name: True})
