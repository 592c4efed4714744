"""ColumnOfBeads/BeadColumnED_NewtonLaw.cpp: ten touching beads dropped on the floor, e = 1,
EventDriven + LsodarOSI with time events every 0.001, to T = 0.5."""

from examples import beads

EXAMPLE = "examples/mechanics/ColumnOfBeads/BeadColumnED_NewtonLaw.cpp"
SCHEME = {"kind": "ED", "h": 0.001}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.001")


def spec(model):
    return beads(model)


DISCUSSION = ""
