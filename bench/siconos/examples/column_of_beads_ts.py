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


DISCUSSION = """zenosim fails at every tolerance at t ≈ 1.18–1.20: the contact problem on eight contacts has
no solution by Lemke's method (the LCP defect being fixed; reported as the table shows it).
Before that it reproduces the reference's binary impacts: the first ten to 2e-16. Its largest
error, 0.32, is not a drift: at t ≈ 1.1177 it has an impact on the floor that the binary
reference does not have (3.6e-5 s before the reference's 41st floor impact, in the stretch
where, the reference notes, other gaps are already below 1e-6), and from there the matching of
the k-th floor impact with the k-th is off by one. Moreau–Jean time-stepping (Siconos) needs
no contact problem at the acceleration level and always finishes: at the example's h = 5e-4 it
has 480 impacts, the first ten within 1.6e-3 s (about 3 h) of the reference's; the beads end
stacked at rest. The reference stops at the first impact where two contacts are closed at once,
and has no state at t = 2 (its rest state is reached later), so no final error is given."""
