"""Reference of models/siconos/bead-column-ed-newton.toml (Siconos
ColumnOfBeads/BeadColumnED_NewtonLaw.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/bead-column-ed-newton.py (needs mpmath;
under a second). Writes models/siconos/references/bead-column-ed-newton.json.

Closed form, in mpmath at 50 digits. The ten beads touch and fall together; the lowest lands
after falling the height h, at t1 = sqrt(2 h/g), every contact of the column closed. The impact
law on all ten contacts at once (0 <= impulse, complementary to the post-impact normal velocity
plus e times the pre-impact one) has a unique solution, its Delassus matrix being positive
definite: the column leaves as one body at the speed g t1 it arrived with (e = 1: every bead
gets the same velocity, every gap keeps its zero velocity, and every impulse is positive, being
the momentum change of the beads above that contact). So the column bounces as a rigid body:
impacts at t1, 3 t1, 5 t1, ..., each on all ten contacts, and at T = 0.5 every bead is on the
parabola of the last flight. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "bead-column-ed-newton"
PI_SICONOS = mpmath.mpf("3.14159265")  # the example's own value of pi
R = mpmath.mpf("0.005")
RHO = mpmath.mpf(7780)
EXAMPLE = {"g": mpmath.mpf("9.81"), "R": R, "rho": RHO, "e_wall": 1, "e_ball": 1,
           "height": mpmath.mpf("0.05"), "m": 4 * PI_SICONOS * R**3 * RHO / 3}
T_END = mpmath.mpf("0.5")
BEADS = 10


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, h, r = p["g"], p["height"], p["R"]
    contacts = ["floor"] + [f"gap_{i}_{i + 1}" for i in range(1, BEADS)]
    t1 = mpmath.sqrt(2 * h / g)
    impacts = []
    k = 0
    while (2 * k + 1) * t1 <= T_END:
        impacts.append({"t": (2 * k + 1) * t1, "contacts": contacts})
        k += 1
    s = T_END - impacts[-1]["t"]
    v = g * t1
    lift = v * s - g * s**2 / 2  # the lowest bead's height above y = R
    q = [r + lift + 2 * r * i for i in range(BEADS)]
    q_dot = [v - g * s] * BEADS
    write_reference(
        NAME,
        "examples/mechanics/ColumnOfBeads/BeadColumnED_NewtonLaw.cpp",
        "closed form: the column bounces as one body, impacts at (2k + 1) sqrt(2 h/g) on all ten "
        "contacts (the impact law on the ten at once); the parabola at t_end",
        1e-15,
        impacts=impacts,
        final={"t": T_END, "q": q, "q_dot": q_dot},
        notes="e = 1: no Zeno point; the gaps between beads stay closed throughout.",
    )


if __name__ == "__main__":
    main()
