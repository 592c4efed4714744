"""SliderCrank/SliderCrankD1MinusLinearVelocityLevel.cpp: a slider-crank whose slider has a clearance in its
guide (four corner contacts), e = 0.4, TimeSteppingD1Minus + D1MinusLinearOSI
(halfexplicit_velocity_level), h = 1e-5, to T = 0.2."""

from examples import constraint, time_steps

EXAMPLE = "examples/mechanics/SliderCrank/SliderCrankD1MinusLinearVelocityLevel.cpp"
SCHEME = {"kind": "TS", "osi": "D1MinusLinearOSI", "type": "halfexplicit_velocity_level",
          "h": 1e-5}
SCHEME_TEXT = ("TimeSteppingD1Minus + D1MinusLinearOSI (halfexplicit_velocity_level), LCPs "
               "at velocity and acceleration level, h = 1e-5; LagrangianDS and "
               "LagrangianScleronomousR from C plugins (plugins/slider_crank.c), run through "
               "d1minus_runner.cpp")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.25))


def spec(model):
    p = model["params"]
    names = ("mass", "FGyr", "jacobianFGyrq", "jacobianFGyrqDot", "FInt", "jacobianFIntq",
             "jacobianFIntqDot")
    return {
        "t_end": model["t_end"],
        "ds": [{"kind": "plugin", "coords": ["q1", "q2", "q3"], "q0": model["q0"],
                "v0": model["v0"], "plugin": "crank", "functions": {k: k for k in names}}],
        "interactions": [
            {"name": f"g{k}", "e": constraint(model, f"g{k}")["e"], "ds": [0],
             "relation": {"kind": "scleronomous", "plugin": "crank", "h": f"g{k}",
                          "G0": f"W{k}", "dotG0": f"W{k}dot"}} for k in (1, 2, 3, 4)],
        "plugins": {"crank": {"source": "slider_crank.c",
                              "defines": {"L1": p["l1"], "L2": p["l2"], "A": p["a"],
                                          "B": p["b"], "D": p["d"], "M1": p["m1"],
                                          "M2": p["m2"], "M3": p["m3"], "J1": p["J1"],
                                          "J2": p["J2"], "J3": p["J3"], "G": p["g"]}}},
    }


DISCUSSION = """With the velocity-level scheme's parameters the slider has one Zeno point in the window
(the pair g1+g2, 13 impacts each, ratio 0.4) and lift-offs. zenosim matches the 34 corner
impacts in the window to 1.2e-8 s at 1e-6 and 8.2e-13 s at 1e-12, the Zeno time to 1.9e-9 and
4.9e-13, the lift-offs to 8.9e-10 and 3.1e-15, and the state at 0.03 to 2.5e-5 and 1.5e-11.
D1Minus at the velocity level (Siconos) keeps re-striking the pair (72 impacts in the window
at the example's h = 1e-5, 230 at h = 2.5e-6, against the reference's 24) before it holds it:
its last impact is 2.1e-4 s from the Zeno time at h = 1e-5, 3.8e-5 s at 2.5e-6, and its state
at 0.03 within 2.3e-2 and 8.1e-3. Time: 6–23 ms against 535 ms at the example's step."""
