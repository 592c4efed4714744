"""zenosim.run against the closed forms and against what `zenosim run` writes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import zenosim
from conftest import FAULTS, MODELS

SHIPPED = sorted(MODELS.glob("*.toml"))


def assert_same_as_cli(run: zenosim.Run, cli) -> None:
    """`run` holds exactly (bit for bit) what the command wrote for the same run."""
    summary = cli.summary
    assert run.status == summary["status"]
    assert run.message == summary["message"]
    assert run.coordinates == summary["coordinates"]
    assert run.constraints == summary["constraints"]
    np.testing.assert_array_equal(run.t, cli.numbers(["t"])[:, 0])
    np.testing.assert_array_equal(run.q, cli.numbers(summary["coordinates"]))
    np.testing.assert_array_equal(run.q_dot, cli.numbers(summary["velocities"]))
    np.testing.assert_array_equal(
        run.h, cli.numbers([f"h_{c}" for c in summary["constraints"]])
    )
    np.testing.assert_array_equal(run.energy, cli.numbers(["energy"])[:, 0])
    np.testing.assert_array_equal(
        run.multipliers, cli.numbers([f"lambda_{c}" for c in summary["constraints"]])
    )
    friction = summary.get("friction", [])
    assert run.friction_constraints == friction
    # A contact in space has a second column, f2_<name>, after its f_<name>.
    in_space = summary.get("friction_in_space", [])
    columns = [
        name
        for c in friction
        for name in ([f"f_{c}", f"f2_{c}"] if c in in_space else [f"f_{c}"])
    ]
    assert run.friction_columns == columns
    if friction:
        np.testing.assert_array_equal(run.friction, cli.numbers(columns))
    assert run.friction.shape == (len(run.t), len(columns))
    work = ["work_forces", "work_drive", "work_constraints", "impact_loss"]
    if "work_forces" in cli.columns:
        for name in work:
            np.testing.assert_array_equal(run.balance[name], cli.numbers([name])[:, 0])
    assert run.energy_balance == summary["energy_balance"]
    assert run.mode == cli.columns["mode"]
    assert run.events == summary["events"]
    assert run.zeno == summary["zeno"]
    assert run.final == summary["final"]
    assert len(run.t) == summary["trajectory"]["rows"]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_every_shipped_model_gives_what_the_command_writes(path, cli_run):
    assert_same_as_cli(zenosim.run(path), cli_run(path))


@pytest.mark.parametrize(
    "kwargs, args",
    [
        (dict(zeno="off"), ["--zeno", "off"]),
        (dict(zeno=1e-3), ["--zeno", "0.001"]),
        (dict(dt=0.01, t_end=4.0), ["--dt", "0.01", "--t-end", "4"]),
        (dict(rtol=1e-7, atol=1e-9), ["--rtol", "1e-7", "--atol", "1e-9"]),
        (
            dict(set={"e": 0.8, "x2_dot": "-pi/4", "x3": 1.5}),
            ["--set", "e=0.8", "--set", "x2_dot=-pi/4", "--set", "x3=1.5"],
        ),
    ],
    ids=["zeno-off", "epsilon", "dt", "tolerances", "set"],
)
def test_settings_and_overrides_act_as_the_command_line_flags(kwargs, args, cli_run):
    path = MODELS / "ball-on-sine.toml"
    model = zenosim.Model.from_file(path)
    run = zenosim.run(model, **kwargs)
    assert_same_as_cli(run, cli_run(path, *args))
    # The same from the path.
    np.testing.assert_array_equal(zenosim.run(str(path), **kwargs).q, run.q)


def test_the_bouncing_balls_zeno_time_is_its_closed_form():
    model = zenosim.Model.from_file(MODELS / "bouncing-ball.toml")
    p = model.parameters
    g, e, h0 = p["g"], p["e"], p["h0"]
    # Dropped from rest at h0: it reaches the floor at t1 = sqrt(2 h0 / g) with speed
    # v1 = g t1, and the flights after it, 2 e^k v1 / g, sum to 2 e v1 / (g (1 - e)).
    t1 = math.sqrt(2 * h0 / g)
    v1 = g * t1
    tau = t1 + 2 * e * v1 / (g * (1 - e))
    run = zenosim.run(model)
    assert run.status == "finished"
    (zeno,) = run.zeno
    assert zeno["kind"] == "genuine"
    assert abs(zeno["t_zeno"] - tau) < 1e-9 * tau
    assert zeno["t_switch"] <= zeno["t_zeno"] + 1e-9
    # At rest on the floor after it.
    assert run.final["mode"] == "constrained"
    assert abs(run.final["q"][0]) < 1e-9 and abs(run.final["q_dot"][0]) < 1e-9
    # The first impact, at t1 exactly.
    assert abs(run.events[0]["t"] - t1) < 1e-12


def test_arrays_have_one_row_per_sample():
    model = zenosim.Model.from_file(MODELS / "ball-on-sine.toml")
    run = zenosim.run(model, dt=0.5)
    rows = len(run.t)
    assert run.t.dtype == np.float64 and run.t.shape == (rows,)
    assert run.q.shape == (rows, 3) and run.q_dot.shape == (rows, 3)
    assert run.h.shape == (rows, 1) and run.energy.shape == (rows,)
    assert len(run.mode) == rows and {type(m) for m in run.mode} == {str}
    # The uniform grid, 13 times on [0, 6], and the rows around the events: two at each
    # impact's time, the states just before and after it.
    grid = set(np.arange(0, 6.5, 0.5))
    assert grid <= set(run.t)
    events = {e["t"] for e in run.events}
    assert set(run.t) - grid <= events
    for impact in (e for e in run.events if e["kind"] == "impact"):
        assert list(run.t).count(impact["t"]) >= 2
    assert run.mode[0] == "free" and run.mode[-1] == "constrained:surface"
    assert run.final["t"] == 6.0 and len(run.final["q"]) == 3 and len(run.final["q_dot"]) == 3


def test_overrides_change_the_model_and_accept_formulas():
    base = zenosim.Model.from_file(MODELS / "bouncing-ball.toml")
    low = zenosim.run(base, set={"h0": 0.25})
    quarter = zenosim.run(base, set={"h0": "g/9.81/4"})  # a formula of the parameters
    np.testing.assert_array_equal(low.q, quarter.q)
    # A quarter of the height: half the time.
    assert abs(low.zeno[0]["t_zeno"] - zenosim.run(base).zeno[0]["t_zeno"] / 2) < 1e-9
    # numpy numbers are numbers.
    np.testing.assert_array_equal(zenosim.run(base, set={"h0": np.float64(0.25)}).q, low.q)
    # The model itself is unchanged.
    assert base.parameters["h0"] == 1.0


@pytest.mark.parametrize("path", sorted(FAULTS.glob("*.toml")), ids=lambda p: p.stem)
def test_a_failed_run_is_a_status_with_what_was_computed(path, cli_run):
    run = zenosim.run(path)
    assert run.status == "failed"
    assert run.message.startswith("failed: ")
    assert len(run.t) >= 1
    assert_same_as_cli(run, cli_run(path, expect=(1,)))


def test_a_stalled_run_says_where():
    run = zenosim.run(MODELS / "bouncing-ball.toml", zeno="off")
    assert run.status == "zeno_stalled"
    assert "τ∞" in run.message
    assert run.final["t"] < 1.36


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        (dict(zeno="sometimes"), ValueError, "zeno="),
        (dict(zeno=-1e-3), ValueError, "zeno="),
        (dict(zeno=True), TypeError, "zeno="),
        (dict(zeno=[1]), TypeError, "zeno="),
        (dict(t_end=-1.0), ValueError, "t_end"),
        (dict(rtol=0.0), ValueError, "tol"),
        (dict(dt=-0.1), ValueError, "dt"),
        (dict(t_end="long"), TypeError, "t_end"),
        (dict(set=[("e", 0.5)]), TypeError, "set="),
        (dict(set={"e": True}), TypeError, "bool"),
        (dict(set={"e": None}), TypeError, "set= e"),
        (dict(set={"e": float("nan")}), ValueError, "finite"),
        (dict(set={1: 0.5}), TypeError, "names"),
    ],
)
def test_bad_arguments_are_clear_errors(kwargs, error, words):
    with pytest.raises(error, match=words):
        zenosim.run(MODELS / "bouncing-ball.toml", **kwargs)


def test_the_model_is_a_model_or_a_path():
    with pytest.raises(TypeError, match="zenosim.Model or the path"):
        zenosim.run(42)
    with pytest.raises(FileNotFoundError) as raised:
        zenosim.run("no/such/model.toml")
    assert raised.value.filename == "no/such/model.toml"


@pytest.mark.parametrize("name", ["belt-stick-slip", "ball-backspin", "dragged-ball"])
def test_the_energy_balance_closes_on_every_row(name):
    """energy − energy[0] = W_forces + W_drive + W_constraints + W_friction − impact loss, row by
    row, to the integration tolerance (docs/output.md); friction only takes energy out."""
    run = zenosim.run(MODELS / f"{name}.toml")
    b = run.balance
    right = (
        b["work_forces"] + b["work_drive"] + b["work_constraints"] + b["work_friction"]
        - b["impact_loss"]
    )
    size = np.abs(run.energy).max() + sum(np.abs(v).max() for v in b.values())
    assert np.abs(run.energy - run.energy[0] - right).max() < 1e-8 * size
    assert (b["work_friction"] <= 1e-12 * size).all()


def test_the_belts_friction_is_within_its_cones():
    """Sticking, |fₜ| ≤ μₛ fₙ; slipping, |fₜ| = μₖ fₙ (unit mass, fₙ = g): the forces Python
    returns are the engine's."""
    run = zenosim.run(MODELS / "belt-stick-slip.toml")
    assert run.friction_constraints == ["belt"]
    f = run.friction[:, 0]
    normal = -run.multipliers[:, 0]
    np.testing.assert_allclose(normal, 9.81, rtol=1e-12)
    stick = np.array([";stick:belt" in m for m in run.mode])
    slip = np.array([";slip:belt" in m for m in run.mode])
    assert stick.any() and slip.any()
    assert (np.abs(f[stick]) <= 0.6 * 9.81 * (1 + 1e-12)).all()
    np.testing.assert_allclose(np.abs(f[slip]), 0.4 * 9.81, rtol=1e-9)


def test_a_model_file_cannot_raise_the_limits_that_bound_memory(tmp_path):
    # Two walls 1e-9 apart, elastic, with max_events = max_steps = 10**8 in the file: the run
    # held every event until memory ran out and the interpreter died (SIGABRT). The file may
    # lower the limits, never raise them: the default 100 000 events stop it, as a failure.
    model = tmp_path / "walls.toml"
    model.write_text(
        'name = "walls"\ncoordinates = ["x"]\nlagrangian = "0.5*x_dot^2"\n'
        '[[constraint]]\nname = "left"\nh = "x"\nrestitution = 1.0\n'
        '[[constraint]]\nname = "right"\nh = "1e-9 - x"\nrestitution = 1.0\n'
        '[initial]\nx = 5e-10\nx_dot = 1.0\n'
        "[simulation]\nt_end = 1.0\nmax_events = 100000000\nmax_steps = 100000000\n"
    )
    run = zenosim.run(model)
    assert run.status == "failed"
    assert "100000 events" in run.message
    assert len(run.events) == 100000
    # The caller may lower them, and raise them.
    run = zenosim.run(model, max_events=50)
    assert run.status == "failed" and len(run.events) == 50


def test_max_output_bounds_the_record(tmp_path):
    model = tmp_path / "ball.toml"
    model.write_text(MODELS.joinpath("bouncing-ball.toml").read_text())
    run = zenosim.run(model, dt=1e-5, t_end=10.0, max_output=1_000_000)
    assert run.status == "failed"
    assert "max_output = 1000000 bytes" in run.message
    assert 0 < len(run.t) < 20_000
    assert run.t[-1] < 10.0
    whole = zenosim.run(model, dt=1e-3, t_end=1.0)
    assert whole.status == "finished"


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        (dict(max_events=0), ValueError, "max_events must be a whole number > 0"),
        (dict(max_steps=-3), ValueError, "max_steps must be a whole number > 0"),
        (dict(max_output=1.5), TypeError, "max_output must be a whole number"),
        (dict(max_events=True), TypeError, "max_events must be a whole number"),
    ],
)
def test_bad_limits_are_clear_errors(kwargs, error, words):
    with pytest.raises(error, match=words):
        zenosim.run(MODELS / "bouncing-ball.toml", **kwargs)
