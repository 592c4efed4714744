"""ColumnOfBeads/BeadColumnED_NewtonLaw.cpp: ten touching beads dropped on the floor, e = 1,
EventDriven + LsodarOSI with time events every 0.001, to T = 0.5."""

from examples import beads

EXAMPLE = "examples/mechanics/ColumnOfBeads/BeadColumnED_NewtonLaw.cpp"
SCHEME = {"kind": "ED", "h": 0.001}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.001")


def spec(model):
    return beads(model)


DISCUSSION = """The column falls as one body and both tools apply the generalized Newton law on all ten
contacts at once: the column bounces as a whole, with the two impacts of the closed form.
zenosim agrees with it to 5e-16, Siconos to about tol/10 (8e-10 at 1e-8). Both are right; the
time is 0.66 ms against 10–14 ms."""
