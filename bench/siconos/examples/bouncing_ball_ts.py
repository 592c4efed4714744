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


DISCUSSION = """Moreau–Jean time-stepping does not locate impacts: an impact falls in the step where the
contact closes, so its time is good to O(h) (the first ten to about 8 h: 0.04 s at the
example's h = 0.005) and a flight shorter than a few steps is not resolved at all: Siconos
has 42 impacts at h = 0.005, 91 at h = 5e-5, of the 326 before the Zeno point. Where its ball
stops bouncing (its Zeno estimate) is 0.094 s early at the example's step and converges as
O(h) (7e-4 at 5e-5). Its state at t = 10, at rest, is off by 2.3e-5 at the example's step and 6e-9 at
5e-5. zenosim follows the impacts one by one through
the Zeno time (3e-13) to rest. The closed form sides with zenosim; time-stepping was not built
for impact times, and its cost grows as 1/h (10 ms at h = 0.005, 2.2 s at 5e-5, in a Python
loop)."""
