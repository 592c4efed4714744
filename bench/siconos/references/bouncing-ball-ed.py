"""Reference of models/siconos/bouncing-ball-ed.toml (Siconos
BouncingBallEventDriven/BouncingBallED.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/bouncing-ball-ed.py (needs mpmath; under
a second). Writes models/siconos/references/bouncing-ball-ed.json.

Closed form, evaluated in mpmath at 50 digits: dropped from rest at y0, the ball lands at
t1 = sqrt(2 y0/g) at speed v1 = g t1; the k-th rebound leaves at e^k v1 and flies 2 e^k v1/g:
impact k is at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)). The example ends at T = 8.5, before the Zeno
time t1 (1 + e)/(1 - e) = 8.5789: every impact before T is listed, and the state at T is on the
parabola after the last one. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "bouncing-ball-ed"
# The example's values (BouncingBallED.cpp).
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"), "e": mpmath.mpf("0.9"),
           "y0": 1}
T_END = mpmath.mpf("8.5")


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, e, y0 = p["g"], p["e"], p["y0"]
    t1 = mpmath.sqrt(2 * y0 / g)
    impacts = []
    k = 1
    while True:
        t = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        if t > T_END:
            break
        impacts.append({"t": t, "contacts": ["floor"]})
        k += 1
    last = impacts[-1]["t"]
    v = e ** len(impacts) * g * t1  # the speed after the last impact
    s = T_END - last
    y, y_dot = v * s - g * s**2 / 2, v - g * s
    zeno = t1 * (1 + e) / (1 - e)
    write_reference(
        NAME,
        "examples/mechanics/BouncingBallEventDriven/BouncingBallED.cpp",
        "closed form: impact k at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), t1 = sqrt(2 y0/g); "
        "the parabola after the last impact at t_end",
        1e-15,
        impacts=impacts,
        final={"t": T_END, "q": [y, 0, 0], "q_dot": [y_dot, 0, 0]},
        notes=f"{len(impacts)} impacts before t_end = 8.5; the Zeno time "
        f"{mpmath.nstr(zeno, 17)} is after t_end, so no Zeno point is reached.",
    )


if __name__ == "__main__":
    main()
