"""Reference of models/siconos/bouncing-ball-ed-two-contacts.toml (Siconos
BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/bouncing-ball-ed-two-contacts.py (needs
mpmath; under a second). Writes models/siconos/references/bouncing-ball-ed-two-contacts.json.

Exact, event by event in mpmath at 50 digits: between impacts the height is the parabola
y + v s - g s^2/2; the next impact is the ceiling's (the smaller root of y(s) = box) when the
apex y + v^2/(2 g) reaches the ceiling, else the floor's (the positive root of y(s) = 0); each
reverses the velocity times e. Once the ball no longer reaches the ceiling it is the bouncing
ball: a rebound at v flies 2 v/g and the impacts accumulate at t_k + 2 v_k/(g (1 - e)). Listed:
every impact up to the one where the time left to the Zeno point is below 1e-14 s; after it the
ball rests on the floor (y = 0 at T = 10). Accuracy: the roots are exact (quadratic formula) in
50 digits, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "bouncing-ball-ed-two-contacts"
EXAMPLE = {"m": 1, "g": 10, "R": mpmath.mpf("0.1"), "e": mpmath.mpf("0.8"),
           "box": mpmath.mpf("1.5"), "y0": 1, "v0": 10}
T_END = mpmath.mpf(10)


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, e, box = p["g"], p["e"], p["box"]
    t, y, v = mpmath.mpf(0), p["y0"], p["v0"]
    impacts = []
    zeno = None
    while True:
        apex = y + v * v / (2 * g) if v > 0 else y
        if v > 0 and apex >= box:
            # y + v s - g s^2/2 = box: the first root.
            s = (v - mpmath.sqrt(v * v - 2 * g * (box - y))) / g
            contact = "ceiling"
        else:
            # y + v s - g s^2/2 = 0: the positive root.
            s = (v + mpmath.sqrt(v * v + 2 * g * y)) / g
            contact = "floor"
        t += s
        v_hit = v - g * s
        y = box if contact == "ceiling" else mpmath.mpf(0)
        v = -e * v_hit
        if contact == "floor" and v * v / (2 * g) < box:
            # No more ceiling: the bouncing ball's Zeno time from this rebound.
            zeno = t + 2 * v / (g * (1 - e))
            if zeno - t < mpmath.mpf("1e-14"):
                break
        impacts.append({"t": t, "contacts": [contact]})
    last_ceiling = max(i for i, x in enumerate(impacts) if x["contacts"] == ["ceiling"])
    write_reference(
        NAME,
        "examples/mechanics/BouncingBallEventDriven/BouncingBallED-TwoContacts.cpp",
        "closed form: exact parabolas between floor and ceiling, each impact time by the "
        "quadratic formula in 50-digit mpmath; Zeno time t_k + 2 v_k/(g (1 - e)); then at rest",
        1e-15,
        impacts=impacts,
        zeno=[{"t": zeno, "constraints": ["floor"]}],
        final={"t": T_END, "q": [0, 0, 0], "q_dot": [0, 0, 0]},
        notes=f"{len(impacts)} impacts listed (the last on the ceiling is number "
        f"{last_ceiling + 1}), up to 1e-14 s before the Zeno point on the floor; then the ball "
        "rests on the floor.",
    )


if __name__ == "__main__":
    main()
