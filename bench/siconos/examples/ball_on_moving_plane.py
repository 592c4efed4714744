"""BallOnMovingPlane/BallOnMovingPlane.cpp: a ball dropped onto a plane that rises with the
prescribed velocity C + A cos(w t), e = 0.9, TimeStepping + MoreauJeanOSI (theta = 0.5),
h = 0.005, to T = 10."""

import math

from examples import ball, time_steps

EXAMPLE = "examples/mechanics/BallOnMovingPlane/BallOnMovingPlane.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.5, "h": 0.005}
SCHEME_TEXT = ("TimeStepping + MoreauJeanOSI(theta 0.5), LCP, h = 0.005; the plane a second "
               "LagrangianLinearTIDS whose velocity a BoundaryCondition prescribes (C plugin "
               "plugins/moving_plane.c)")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1))


def spec(model):
    """The plane is the example's: a body like the ball (same mass matrix and weight, which the
    prescribed velocity overrides) whose height is linked to the ball's by H = [1 0 0 -1 0 0].
    It starts at 0 with the prescribed velocity at t = 0, C + A (the example starts it at rest,
    so its position lags the prescribed motion by about h (C + A)/2 after the first step)."""
    p = model["params"]
    b = ball(model)
    plane = dict(b, kind="driven", coords=["plane_y", "plane_x", "plane_theta"],
                 q0=[0.0, 0.0, 0.0], v0=[p["C"] + p["A"], 0.0, 0.0],
                 boundary={"dofs": [0], "plugin": "plane", "function": "prescribedvelocity"})
    (c,) = model["constraints"]
    return {
        "t_end": model["t_end"], "ds": [b, plane],
        "interactions": [{"name": c["name"], "e": c["e"], "ds": [0, 1],
                          "relation": {"kind": "linear",
                                       "C": [[1.0, 0.0, 0.0, -1.0, 0.0, 0.0]],
                                       "offset": [0.0]}}],
        "plugins": {"plane": {"source": "moving_plane.c",
                              "defines": {"VC": p["C"], "VA": p["A"], "VW": p["w"]}}},
    }


def plane_height(model, t):
    """The file's plane: y - h(t, y) at y = 0."""
    import suite
    zero = [0.0] * len(model["coordinates"])
    return -suite.file_h(model, t, zero)[model["constraints"][0]["name"]]


def driven_value(model, spec, ds, dof, t, x):
    """The plane's state for the check: its height from the file at t (dof 0), else 0. Called
    with x the positions (then the height) or the velocities (then, for the check, the same
    call: the velocity does not enter the plane's force, which is overridden)."""
    return plane_height(model, t) if dof == 0 else 0.0


def check_extra(model, spec, plugins):
    """The plugin's prescribed velocity against the file's plane velocity (central
    differences of its height), at a few times."""
    worst = 0.0
    for k in range(7):
        t = model["t_end"] * k / 6
        d = 1e-5
        v_file = (plane_height(model, t + d) - plane_height(model, t - d)) / (2 * d)
        v_plugin = plugins.call("plane", "prescribedvelocity", "velocity", t=t, out_size=1)[0]
        worst = max(worst, abs(v_file - v_plugin) / max(abs(v_file), 1.0))
    # its start: the file's plane is at 0 at t = 0, and the spec starts it there
    worst = max(worst, abs(plane_height(model, 0.0) - spec["ds"][1]["q0"][0]))
    return {"plane_velocity": worst}


DISCUSSION = """The plane rises with a prescribed velocity. zenosim treats it as a moving surface h(t, y)
and gets the 34 impacts before t_end to 7e-13 and the state at t_end, in flight, to 7e-12.
Siconos's example moves the plane as a second body whose velocity a boundary condition
prescribes, and integrates by Moreau–Jean: at its h = 0.005 it has 32 of the 34 impacts, the
first ten within 0.03 s, and its state at t_end is off by 0.04; at h = 5e-4 it has all 34,
within 6e-3 s, but the state at t_end, just after an impact at 9.989, is still off by 0.05: it
carries that impact's time error. The
reference (exact parabolas against the plane's exact motion) sides with zenosim."""
