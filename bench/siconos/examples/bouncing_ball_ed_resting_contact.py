"""BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp: e = 0, one impact, then rest."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = ""
