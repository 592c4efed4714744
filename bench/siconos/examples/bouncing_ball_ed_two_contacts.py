"""BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp: a ball between floor and ceiling, e = 0.8."""

from examples import ball, one_body

EXAMPLE = "examples/mechanics/BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp"
SCHEME = {"kind": "ED", "h": 0.01}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.01")


def spec(model):
    return one_body(model, ball(model))


DISCUSSION = """Both tools agree on the two ceiling impacts; the floor's Zeno point at 6.2072372 is where they
part. zenosim passes it with its Zeno estimate to 1e-13 (80 to 140 impacts, depending on the
tolerance, then the switch) and rests on the floor. Siconos with its default TOL_ED throws at
t ≈ 6.204–6.207 at tolerances 1e-6 and 1e-8: the integration error drives the closed floor's
gap below −TOL_ED = −2.2e-12. With TOL_ED = tol it finishes and rests, but its bounces stop
early (its flights fall below its tolerances), so its estimate of the Zeno time, its last impact,
is off by about 3 √tol (3e-3 at 1e-6, 3e-6 at 1e-12). The reference sides with zenosim."""
