"""BouncingBallEventDriven/BouncingBallED.cpp: a ball dropped on the floor, e = 0.9."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = ""
