"""ColumnOfBeads/ColumnOfBeadsTS.cpp: ten beads dropped onto the floor and onto each other,
e = 0.9, TimeStepping + MoreauJeanOSI (theta = 0.5), h = 5e-4, to T = 2."""

from examples import beads, time_steps

EXAMPLE = "examples/mechanics/ColumnOfBeads/ColumnOfBeadsTS.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.5, "h": 5e-4}
SCHEME_TEXT = ("TimeStepping + MoreauJeanOSI(theta 0.5), LCP, h = 5e-4; every contact linked "
               "from the start (the example links a pair once its gap is below 0.02, which "
               "changes nothing while the gap is open)")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1))


def spec(model):
    return beads(model)


DISCUSSION = ""
