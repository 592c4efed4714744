"""BouncingBallEventDriven/LinearOscillatorED.cpp: a mass on springs (kx on the height, ky on
the horizontal) striking the wall y = 0, e = 0.9."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/LinearOscillatorED.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005")


def spec(model):
    p = model["params"]
    return one_body(model, ball(model, stiffness=(p["kx"], p["ky"])))


DISCUSSION = ""
