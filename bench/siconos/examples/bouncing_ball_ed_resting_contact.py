"""BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp: e = 0, one impact, then rest."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = """One plastic impact, then the floor holds the ball: both tools get the impact time to
rounding (Siconos 5.5e-11 at 1e-6, exact at 1e-12) and the resting state exactly. Nothing to
choose between them but the time (0.007 ms against 16 ms)."""
