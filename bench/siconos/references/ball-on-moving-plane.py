"""Reference of models/siconos/ball-on-moving-plane.toml (Siconos
BallOnMovingPlane/BallOnMovingPlane.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/ball-on-moving-plane.py (needs mpmath;
about 10 seconds). Writes models/siconos/references/ball-on-moving-plane.json.

Exact flights, event by event in mpmath at 120 digits. The plane is at z(t) = C t + (A/w)
sin(w t) (velocity C + A cos(w t), the example's prescribed velocity, from 0 at t = 0); the ball
flies the parabola y_k + v_k s - g s^2/2 from impact k. The gap h = y - z has h'' = -g + A w
sin(w t), between -(g + A w) and -(g - A w) < 0: it is concave, so after each rebound (h = 0,
h' > 0) it has exactly one root, bracketed by 2 h'/(g + A w) and 2 h'/(g - A w), found by the
Illinois method to 100 digits. The impact law acts on the relative velocity, h'+ = -e h'-.
The impacts accumulate at a Zeno point: iterated until the rebound's relative speed is below
1e-25, then the remaining flights, each e times the one before to O(h') relative, are summed as
a geometric series. That Zeno point, 10.2885, is after T = 10 (after it the ball would ride the
plane, whose deceleration A w < g never lets it go): the impacts before T are listed and the
state at T is on the parabola after the last one. Accuracy: the roots to 100 digits and the
series tail to about 1e-25 relative; rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 120

NAME = "ball-on-moving-plane"
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"), "e": mpmath.mpf("0.9"),
           "C": 2, "A": 1, "w": mpmath.pi / 2, "y0": 1}
T_END = mpmath.mpf(10)


def main():
    p = check_parameters(NAME, EXAMPLE)
    g, e, c, a, w = p["g"], p["e"], p["C"], p["A"], p["w"]

    def z(t):
        return c * t + a / w * mpmath.sin(w * t)

    def z_dot(t):
        return c + a * mpmath.cos(w * t)

    # The first impact: the ball falls from rest at y0 onto the rising plane.
    y0 = p["y0"]
    t = mpmath.findroot(lambda s: y0 - g * s**2 / 2 - z(s), (mpmath.mpf(0), mpmath.mpf(1)),
                        solver="illinois", tol=mpmath.mpf("1e-200"))
    v_ball = -g * t
    impacts = [t]
    states = [(z(t), z_dot(t) - e * (v_ball - z_dot(t)))]  # the ball leaving each impact
    rel = -e * (v_ball - z_dot(t))  # the rebound's relative speed
    while rel > mpmath.mpf("1e-25"):
        y, v = z(t), z_dot(t) + rel
        t0 = t

        def gap(s):
            return y + v * s - g * s**2 / 2 - z(t0 + s)

        lower, upper = 2 * rel / (g + a * w), 2 * rel / (g - a * w)
        s = mpmath.findroot(gap, (lower, upper), solver="illinois",
                            tol=(rel * mpmath.mpf("1e-100")) ** 2)
        t = t0 + s
        rel = e * (z_dot(t) - (v - g * s))
        impacts.append(t)
        states.append((z(t), z_dot(t) + rel))
    # The rest of the sequence: flights 2 rel/|h''| shrinking by e.
    h_ddot = -g + a * w * mpmath.sin(w * t)
    zeno = t + 2 * rel / (-h_ddot) / (1 - e)
    listed = [{"t": s, "contacts": ["plane"]} for s in impacts
              if zeno - s >= mpmath.mpf("1e-14") and s <= T_END]
    fields = {"impacts": listed}
    if zeno <= T_END:
        fields["zeno"] = [{"t": zeno, "constraints": ["plane"]}]
        final = ([z(T_END), 0, 0], [z_dot(T_END), 0, 0])
        notes = (f"{len(listed)} impacts listed, up to 1e-14 s before the Zeno point; then the "
                 "ball rides the plane to t_end.")
    else:
        # t_end comes first: the ball is on the parabola after the last impact before it.
        k = len(listed) - 1
        s = T_END - impacts[k]
        y, v = states[k]
        final = ([y + v * s - g * s**2 / 2, 0, 0], [v - g * s, 0, 0])
        notes = (f"{len(listed)} impacts before t_end = 10; the impacts accumulate at the Zeno "
                 f"time {mpmath.nstr(zeno, 17)}, after t_end, so no Zeno point is reached.")
    write_reference(
        NAME,
        "examples/mechanics/BallOnMovingPlane/BallOnMovingPlane.cpp",
        "bench/siconos/references/ball-on-moving-plane.py: exact parabolas against the plane's "
        "exact motion, each impact the one root of a concave gap (120-digit mpmath)",
        1e-15,
        final={"t": T_END, "q": final[0], "q_dot": final[1]},
        notes=notes,
        **fields,
    )


if __name__ == "__main__":
    main()
