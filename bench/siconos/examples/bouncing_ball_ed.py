"""BouncingBallEventDriven/BouncingBallED.cpp: a ball dropped on the floor, e = 0.9."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = """zenosim's impact times and final state agree with the closed form to 2e-14 at every
tolerance: a free flight is a parabola, which its integrator follows exactly, and each impact
is a root located to rounding. Siconos's event-driven scheme (LSODAR) is accurate to about the
tolerance: the first impacts to about 20 tol, the last ones before t_end to about 400 tol, as
the errors in each flight add up. At 1e-6 that drift gives it a 45th impact where the ball
should still be in flight (the reference has 44 before t_end), and its state at t_end is off by
0.08. TOL_ED does not matter here (no contact stays closed before t_end). Who is right: the
closed form sides with zenosim. Wall time: 0.055 ms against about 10 ms."""
