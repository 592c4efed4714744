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


DISCUSSION = """zenosim finishes at every tolerance, the beads stacked at rest by t = 2 (final state
within 8e-16 of the rest state). At 1e-8 to 1e-12 it reproduces all 730 binary impacts of the
60-digit reference to 2e-12 s or better (the first ten to 2e-16), and the three runs agree on
what follows (1424 impacts, the same on each contact). At 1e-6 it follows the reference to
t ≈ 1.177, the 87th impact on gap_3_4, where gaps of about 1e-7 open and close within the
tolerance: from there its sequence is another one (722 impacts in all, 41 of the matched ones
off by up to 0.05 s), still ending at rest. Every contact problem on the way has a positive
definite matrix and is solved (the earlier solver, Lemke's method alone, ended on a ray at
t ≈ 1.18–1.20 at every tolerance). Moreau–Jean time-stepping (Siconos) has 480 impacts at the
example's h = 5e-4, the first ten within 1.6e-3 s (about 3 h) of the reference's, the beads
ending stacked at rest within 2.6e-5 of the rest state; at h = 5e-5, 886 impacts, the first ten
within 1.6e-4 s. Time: 40–160 ms against 200 ms at the example's step (5 s at h = 5e-5)."""
