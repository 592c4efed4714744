"""BouncingBallEventDriven/BouncingBallED.cpp: a ball dropped on the ground, e = 0.9,
EventDriven + LsodarOSI with time events every 0.005."""

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCP at impact and acceleration level, "
               "TimeDiscretisation step 0.005")


def spec(model):
    """The example's ball has three dofs (height, a horizontal one and a rotation), uncoupled
    and free; the file keeps the height, which is all the contact sees. Mass, gravity and e
    come from the file; the ground is LagrangianLinearTIR(C, offset) read off the file's
    constraint."""
    from examples import linear_relation, single
    p = model["params"]
    x = single(model, "x")
    (c,) = model["constraints"]
    return {
        "t_end": model["t_end"],
        "ds": [{"kind": "linear", "coords": [x], "q0": model["q0"], "v0": model["v0"],
                "mass": [[p["m"]]], "fext": [-p["m"] * p["g"]]}],
        "interactions": [{"name": c["name"], "e": c["e"], "ds": [0],
                          "relation": linear_relation(model, c["name"], [x])}],
    }


DISCUSSION = ""
