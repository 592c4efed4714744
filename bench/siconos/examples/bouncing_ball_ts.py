"""BouncingBall/BouncingBallTS.cpp: a ball dropped on the floor, e = 0.9, TimeStepping +
MoreauJeanOSI (theta = 0.5), h = 0.005, to T = 10."""

from examples import ball, one_body, time_steps

EXAMPLE = "examples/mechanics/BouncingBall/BouncingBallTS.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.5, "h": 0.005}
SCHEME_TEXT = "TimeStepping + MoreauJeanOSI(theta 0.5), LCP, h = 0.005"


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1, 0.01))


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = ""
