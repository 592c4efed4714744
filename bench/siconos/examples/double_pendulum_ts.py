"""Pendulum/DoublePendulumTS.cpp: a double pendulum against the wall x = 0 (e = 1 for the first
mass, e = 0 for the second), TimeStepping + MoreauJeanOSI (theta = 0.500001), h = 5e-4, Newton
tolerance 0.05, at most 20000 Newton iterations, to T = 5."""

from examples import constraint, time_steps

EXAMPLE = "examples/mechanics/Pendulum/DoublePendulumTS.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.500001, "h": 5e-4,
          "newton_tol": 0.05, "newton_max_iter": 20000}
SCHEME_TEXT = ("TimeStepping + MoreauJeanOSI(theta 0.500001), LCP, h = 5e-4, Newton tolerance "
               "0.05; LagrangianDS and LagrangianScleronomousR from C plugins "
               "(plugins/double_pendulum.c)")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1))


def spec(model):
    """The example's plugin writes each equation divided by its length ((m1 + m2) l1 where the
    Lagrangian has (m1 + m2) l1^2): the same motion, but not the same impact law unless
    l1 = l2 = 1, and not the file's mass matrix; the plugin here is the Lagrangian's."""
    p = model["params"]
    return {
        "t_end": model["t_end"],
        "ds": [{"kind": "plugin", "coords": ["theta1", "theta2"], "q0": model["q0"],
                "v0": model["v0"], "plugin": "pendulum",
                "functions": {k: k for k in ("mass", "FGyr", "jacobianFGyrq", "jacobianFGyrqDot",
                                             "FInt", "jacobianFIntq", "jacobianFIntqDot")}}],
        "interactions": [
            {"name": "mass1", "e": constraint(model, "mass1")["e"], "ds": [0],
             "relation": {"kind": "scleronomous", "plugin": "pendulum", "h": "h0", "G0": "G0"}},
            {"name": "mass2", "e": constraint(model, "mass2")["e"], "ds": [0],
             "relation": {"kind": "scleronomous", "plugin": "pendulum", "h": "h1", "G0": "G1"}}],
        "plugins": {"pendulum": {"source": "double_pendulum.c",
                                 "defines": {"M1": p["m1"], "M2": p["m2"], "L1": p["l1"],
                                             "L2": p["l2"], "G": p["g"]}}},
    }


DISCUSSION = """Both tools see the same ten impacts (seven of the first mass on the wall, e = 1, three of the
second, e = 0). zenosim's impact times and final state follow its tolerance (2.6e-6 and 1.6e-6
at 1e-6, 4.6e-12 and 1.7e-12 at 1e-12: the motion is nonlinear, so the integration error
shows). Siconos's Moreau-Jean runs, with the example's loose Newton tolerance 0.05, have the
impacts within 1.1e-2 s at its h = 5e-4 and within 4e-4 s at 5e-5, and the state at t_end
within 6e-3 and 6e-4: first order in h. The Taylor-method reference sides with zenosim."""
