"""Reference of models/siconos/bouncing-ball-ed-resting-contact.toml (Siconos
BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/bouncing-ball-ed-resting-contact.py
(needs mpmath; under a second). Writes models/siconos/references/bouncing-ball-ed-resting-contact.json.

Closed form: dropped from rest at y0 with e = 0, the ball lands once, at t1 = sqrt(2 y0/g), and
stays on the floor (the floor pushes with m g > 0 and never lets go): at T = 8.5, y = 0 and every
velocity 0. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "bouncing-ball-ed-resting-contact"
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"), "e": 0, "y0": 1}
T_END = mpmath.mpf("8.5")


def main():
    p = check_parameters(NAME, EXAMPLE)
    t1 = mpmath.sqrt(2 * p["y0"] / p["g"])
    write_reference(
        NAME,
        "examples/mechanics/BouncingBallEventDriven/BouncingBallED-withRestingContact.cpp",
        "closed form: one plastic impact at t1 = sqrt(2 y0/g), then at rest on the floor",
        1e-15,
        impacts=[{"t": t1, "contacts": ["floor"]}],
        final={"t": T_END, "q": [0, 0, 0], "q_dot": [0, 0, 0]},
        notes="e = 0: no rebound and no Zeno point; the floor holds the ball from t1 on.",
    )


if __name__ == "__main__":
    main()
