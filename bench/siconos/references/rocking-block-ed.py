"""Reference of models/siconos/rocking-block-ed.toml (Siconos RockingBlock/RockingBlockED.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/rocking-block-ed.py (needs mpmath; under a
second). Writes models/siconos/references/rocking-block-ed.json.

Closed form, in mpmath at 50 digits. The example starts the block flat (theta = 0) at rest with
its centre at y0, its lower corners H/2 below: it falls as a ball from y0 - H/2, both corners
land together, and the impact on both (equal impulses, the corners being symmetric about the
centre) reverses the vertical velocity times e and leaves theta_dot = 0. So the block bounces
flat like a ball: impact k at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), t1 = sqrt(2 (y0 - H/2)/g), each
on both corners; its Zeno time t1 (1 + e)/(1 - e) is after T = 2, and the state at T is on the
parabola after the last impact (x = x0, theta = 0). Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "rocking-block-ed"
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "L": mpmath.mpf("0.2"), "H": mpmath.mpf("0.1"),
           "e": mpmath.mpf("0.9"), "x0": mpmath.mpf("0.5"), "y0": mpmath.mpf("0.5")}
T_END = mpmath.mpf(2)


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, e, drop = p["g"], p["e"], p["y0"] - p["H"] / 2
    t1 = mpmath.sqrt(2 * drop / g)
    impacts = []
    k = 1
    while True:
        t = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        if t > T_END:
            break
        impacts.append({"t": t, "contacts": ["corner1", "corner2"]})
        k += 1
    v = e ** len(impacts) * g * t1
    s = T_END - impacts[-1]["t"]
    y = p["H"] / 2 + v * s - g * s**2 / 2
    zeno = t1 * (1 + e) / (1 - e)
    write_reference(
        NAME,
        "examples/mechanics/RockingBlock/RockingBlockED.cpp",
        "closed form: the block bounces flat, impact k at t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), "
        "t1 = sqrt(2 (y0 - H/2)/g), on both corners; the parabola at t_end",
        1e-15,
        impacts=impacts,
        final={"t": T_END, "q": [p["x0"], y, 0], "q_dot": [0, v - g * s, 0]},
        notes=f"{len(impacts)} impacts before t_end = 2; the Zeno time {mpmath.nstr(zeno, 17)} "
        "is after t_end.",
    )


if __name__ == "__main__":
    main()
