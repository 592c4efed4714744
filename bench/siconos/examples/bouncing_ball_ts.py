"""BouncingBall/BouncingBallTS.cpp: the same ball, e = 0.9, TimeStepping + MoreauJeanOSI
(theta = 0.5) with h = 0.005, to T = 10."""

from examples import bouncing_ball_ed, time_steps

EXAMPLE = "examples/mechanics/BouncingBall/BouncingBallTS.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.5, "h": 0.005}
SCHEME_TEXT = "TimeStepping + MoreauJeanOSI(theta 0.5), LCP, h = 0.005"


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1, 0.01))


spec = bouncing_ball_ed.spec

DISCUSSION = ""
