"""Reference of models/siconos/bouncing-ball-ts.toml (Siconos BouncingBall/BouncingBallTS.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/bouncing-ball-ts.py (needs mpmath;
under a second). Writes models/siconos/references/bouncing-ball-ts.json.

Closed form, evaluated in mpmath at 50 digits: dropped from rest at y0, the ball lands at
t1 = sqrt(2 y0/g) at speed v1 = g t1; the k-th rebound leaves at e^k v1 and flies 2 e^k v1/g, so
impact k is at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)) and the impacts accumulate at the Zeno time
t1 (1 + e)/(1 - e). Listed: every impact up to the one where the time left to the Zeno point is
below 1e-14 s (zenosim switches to the constrained motion long before: its impacts are compared
with the first ones of this list). After the Zeno point the ball rests on the floor: at t_end,
y = 0, every velocity 0; x and theta never move. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "bouncing-ball-ts"
# The example's values (BouncingBallTS.cpp): m, g, R, e, the height, the end time T.
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"), "e": mpmath.mpf("0.9"),
           "y0": 1}
T_END = mpmath.mpf(10)


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, e, y0 = p["g"], p["e"], p["y0"]
    t1 = mpmath.sqrt(2 * y0 / g)
    zeno = t1 * (1 + e) / (1 - e)
    impacts = []
    k = 1
    while True:
        t = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        if zeno - t < mpmath.mpf("1e-14"):
            break
        impacts.append({"t": t, "contacts": ["floor"]})
        k += 1
    write_reference(
        NAME,
        "examples/mechanics/BouncingBall/BouncingBallTS.cpp",
        "closed form: impact k at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), t1 = sqrt(2 y0/g); "
        "Zeno time t1 (1 + e)/(1 - e); then at rest on the floor",
        1e-15,
        impacts=impacts,
        zeno=[{"t": zeno, "constraints": ["floor"]}],
        final={"t": T_END, "q": [0, 0, 0], "q_dot": [0, 0, 0]},
        notes=f"{len(impacts)} impacts listed, up to 1e-14 s before the Zeno point; "
        "after it the ball rests on the floor (x and theta never move).",
    )


if __name__ == "__main__":
    main()
