"""BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp: a ball between floor and ceiling, e = 0.8."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp"
SCHEME = {"kind": "ED", "h": 0.01}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.01")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = ""
