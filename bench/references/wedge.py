#!/usr/bin/env python3
"""The exact execution of a point mass in a wedge, an independent reference for zenosim.

A point of unit mass in the wedge y >= k |x| (the walls 'right': h = y - k x >= 0 and 'left':
h = y + k x >= 0), under gravity g pointing to -y, with restitution e on both walls, dropped
from rest at (x0, y0). Everything is computed in closed form, in 60-digit arithmetic (mpmath),
independently of zenosim's code:

- free flight is a parabola; a wall is reached at the smaller positive root of the quadratic
  h(t) = 0 (a wall just left: at 2 h_dot / g, since h_ddot = -g for both walls);
- an impact on one wall is Newton's law, h_dot+ = -e h_dot-, along the wall's normal (the mass
  matrix is the identity, so the impulse acts along A^T); the velocity along the wall is kept;
- impacts on one wall accumulate when the other is not reached first: the sequence is then a
  bouncing ball along that wall's normal (normal gravity g, since h_ddot = -g), whose Zeno time
  is t + 2 h_dot+ / (g (1 - e)) after an impact, while the motion along the wall goes on under
  gravity's component along it, untouched by the impacts. After it the mass slides on the wall
  into the vertex;
- at the vertex both walls are closed: the impact acts on both at once, by the generalized
  Newton law (docs/contact-laws.md, law 2): 0 <= L _|_ W L + (1 + e) h_dot- >= 0 with
  W = A A^T, solved by enumeration of its four complementary bases; a wall left at rest
  (h_dot+ = 0) with gravity pressing on it holds the mass, which slides along it and comes
  back to the vertex.
The execution is followed until the speed is below 1e-40 (the Zeno point at the vertex, where
the mass rests). It records every impact (time, the walls of the impact), every Zeno point of
one wall, and the final Zeno time.

Usage:
    python3 bench/references/wedge.py K E X0 Y0 [--g G] [--listed N] [--out FILE]
    python3 bench/references/wedge.py --family --out crates/zenosim-model/tests/data/wedges.json
    python3 bench/references/wedge.py 2 0.7 0.3 1 --out models/references/v-groove.json
Needs mpmath (pip install mpmath); a wedge takes a second, the family about half a minute.
Each listed impact is {"t", "contacts"}; t_zeno is the time the mass comes to rest at the
vertex; "zeno" lists one wall's Zeno points before it; "horizon" is the number of impacts
whose walls a start perturbed by one part in 2^52 leaves unchanged (how far a computation in
f64 can follow the sequence: near the vertex it is chaotic).
"""

import argparse
import json
import sys

from mpmath import mp, mpf, sqrt

mp.dps = 60
STOP = mpf("1e-40")


def wedge(k, e, x0, y0, g="9.81", max_events=100000):
    k, e, g = mpf(k), mpf(e), mpf(g)
    # h = a x + b y, a row of A.
    rows = {"right": (-k, mpf(1)), "left": (k, mpf(1))}
    other = {"right": "left", "left": "right"}
    x, y, vx, vy, t = mpf(x0), mpf(y0), mpf(0), mpf(0), mpf(0)

    def h(w):
        a, b = rows[w]
        return a * x + b * y

    def h_dot(w):
        a, b = rows[w]
        return a * vx + b * vy

    impacts, zeno = [], []
    mode = "free"  # or the wall held
    last = None  # the wall of the last impact (h = 0 there exactly)
    for _ in range(max_events):
        speed = sqrt(vx * vx + vy * vy)
        at_vertex = mode == "vertex"
        if at_vertex or (mode != "free" and speed < STOP):
            break
        if mode == "free":
            # The first wall reached: h + h_dot s - g s^2/2 = 0 (h_ddot = -g on both).
            best = None
            for w in rows:
                h0, hd = h(w), h_dot(w)
                if w == last or (last == "both"):
                    s = 2 * hd / g
                else:
                    s = (hd + sqrt(hd * hd + 2 * g * h0)) / g
                if s > 0 and (best is None or s < best[0]):
                    best = (s, w)
            if best is None:
                raise RuntimeError(f"no wall ahead at t = {t}")
            s, w = best
            x += vx * s
            y += vy * s - g * s * s / 2
            vy -= g * s
            t += s
            # Reached at the vertex (both walls at once, to 50 digits): law 2 on both.
            if abs(h(other[w])) < mpf("1e-50") * (abs(x) + abs(y) + mpf("1e-300")):
                x = y = mpf(0)
                vx, vy, mode = vertex(rows, e, vx, vy, t, impacts, g)
                last = "both"
                if mode == "vertex":
                    break
                continue
            a, b = rows[w]
            hd = a * vx + b * vy
            lam = -(1 + e) * hd / (a * a + b * b)
            vx += lam * a
            vy += lam * b
            impacts.append((t, [w]))
            last = w
            # Impacts on one wall accumulate: the rest of its sequence, if the next flight
            # back to this wall stays clear of the other one, is below 1e-40 s.
            flight = 2 * h_dot(w) / g
            if flight < STOP:
                rest = flight * e / (1 - e) + flight
                # Along the wall the motion is free of the impacts.
                x += vx * rest
                y += vy * rest - g * rest * rest / 2
                vy -= g * rest
                t += rest
                # Onto the wall: drop the normal velocity (rest on it).
                a, b = rows[w]
                n2 = a * a + b * b
                hd = a * vx + b * vy
                vx -= hd * a / n2
                vy -= hd * b / n2
                hh = a * x + b * y
                x -= hh * a / n2
                y -= hh * b / n2
                zeno.append((t, [w]))
                mode = w
        else:
            # Sliding on wall `mode` (h = 0, h_dot = 0) towards or away from the vertex: the
            # acceleration along the wall is gravity's projection.
            w = mode
            a, b = rows[w]
            n2 = a * a + b * b
            # Gravity (0, -g) minus its normal part.
            ax = -(-g * b) * a / n2
            ay = -g - (-g * b) * b / n2
            # Reach the vertex: the position along the wall, s = x (the wall is y = k |x|),
            # obeys x + vx s + ax s^2/2 = 0; the root ahead.
            disc = vx * vx - 2 * ax * x
            roots = [(-vx - sqrt(disc)) / ax, (-vx + sqrt(disc)) / ax] if disc >= 0 else []
            ahead = [r for r in roots if r > 0]
            # None ahead: the completion put the mass at (or, by its last 1e-40 s, past) the
            # vertex already.
            s = min(ahead) if ahead else mpf(0)
            vx += ax * s
            vy += ay * s
            t += s
            x = y = mpf(0)
            vx, vy, mode = vertex(rows, e, vx, vy, t, impacts, g)
            last = "both"
            if mode == "vertex":
                break
    return {"impacts": impacts, "zeno": zeno, "t_zeno": t}


def vertex(rows, e, vx, vy, t, impacts, g):
    """An impact at the vertex on both walls (law 2), then which wall holds, if any."""
    names = list(rows)
    A = [rows[w] for w in names]
    hd = [a * vx + b * vy for a, b in A]
    W = [[A[i][0] * A[j][0] + A[i][1] * A[j][1] for j in range(2)] for i in range(2)]
    c = [(1 + e) * hd[i] for i in range(2)]
    best = None
    for support in ([], [0], [1], [0, 1]):
        lam = [mpf(0), mpf(0)]
        if len(support) == 1:
            i = support[0]
            lam[i] = -c[i] / W[i][i]
        elif len(support) == 2:
            det = W[0][0] * W[1][1] - W[0][1] * W[1][0]
            lam[0] = (-c[0] * W[1][1] + c[1] * W[0][1]) / det
            lam[1] = (-c[1] * W[0][0] + c[0] * W[1][0]) / det
        w_ = [W[i][0] * lam[0] + W[i][1] * lam[1] + c[i] for i in range(2)]
        tol = mpf("1e-45") * (1 + max(abs(v) for v in c))
        if all(l >= -tol for l in lam) and all(v >= -tol for v in w_):
            best = lam
            break
    if best is None:
        raise RuntimeError("the vertex LCP has no solution")
    vx += best[0] * A[0][0] + best[1] * A[1][0]
    vy += best[0] * A[0][1] + best[1] * A[1][1]
    impacts.append((t, [n for n, l in zip(names, best) if l > 0] or names))
    after = [a * vx + b * vy for a, b in A]
    scale = abs(hd[0]) + abs(hd[1])
    closed = [abs(v) <= mpf("1e-45") * scale for v in after]
    if all(closed) or (vx * vx + vy * vy) < STOP * STOP:
        return mpf(0), mpf(0), "vertex"
    for n, c_ in zip(names, closed):
        if c_:
            # Left at rest on it, gravity pressing on it: held, sliding along it.
            return vx, vy, n
    return vx, vy, "free"


# The wedges the engine's tests compare with (crates/zenosim-model/tests/data/wedges.json):
# (k, e, x0, y0). Steep and shallow, elastic and not; one wall's Zeno points before the vertex
# in most. Not k = 3, e = 0.9 from (0.2, 1.5): its sequence is chaotic, and in 20-digit
# arithmetic its Zeno time is already 3.5e-7 off the 60-digit one.
FAMILY = [
    ("2", "0.7", "0.3", "1"),
    ("0.5", "0.5", "0.2", "1.5"),
    ("1", "0.5", "0.2", "1.5"),
    ("3", "0.5", "0.2", "1.5"),
    ("1", "0.8", "0.2", "1.5"),
    ("3", "0.8", "0.2", "1.5"),
]

METHOD = (
    "bench/references/wedge.py: closed-form flights, Newton's law one wall at a time, one "
    "wall's Zeno points in closed form, law 2 at the vertex; mpmath, 60 digits"
)


def horizon(k, e, x0, y0, g, impacts):
    """How far the sequence of walls is determined by a start known to f64's precision: the
    first impact whose walls change when x0 or y0 moves by one part in 2^52 (a wedge's
    sequence near its vertex is chaotic; no computation in f64 can follow it further)."""
    first = len(impacts)
    for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        eps = mpf(2) ** -52
        other = wedge(k, e, mpf(x0) * (1 + dx * eps), mpf(y0) * (1 + dy * eps), g)["impacts"]
        same = 0
        while same < min(len(impacts), len(other)) and impacts[same][1] == other[same][1]:
            same += 1
        first = min(first, same)
    return first


def record(k, e, x0, y0, g, listed):
    r = wedge(k, e, x0, y0, g)
    return {
        "parameters": {"k": k, "e": e, "x0": x0, "y0": y0, "g": g},
        "impacts_in_all": len(r["impacts"]),
        "horizon": horizon(k, e, x0, y0, g, r["impacts"]),
        "impacts": [{"t": float(t), "contacts": w} for t, w in r["impacts"][:listed]],
        "zeno": [{"t": float(t), "constraints": w} for t, w in r["zeno"]],
        "t_zeno": float(r["t_zeno"]),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("k", nargs="?")
    parser.add_argument("e", nargs="?")
    parser.add_argument("x0", nargs="?")
    parser.add_argument("y0", nargs="?")
    parser.add_argument("--g", default="9.81")
    parser.add_argument("--family", action="store_true", help="every wedge of FAMILY, a list")
    parser.add_argument("--listed", type=int, default=400, help="impacts listed (default 400)")
    parser.add_argument("--out")
    args = parser.parse_args()
    if args.family:
        out = {
            "method": METHOD,
            "wedges": [record(*w, args.g, args.listed) for w in FAMILY],
        }
    else:
        if args.y0 is None:
            parser.error("give K E X0 Y0, or --family")
        out = {"method": METHOD, **record(args.k, args.e, args.x0, args.y0, args.g, args.listed)}
    text = json.dumps(out, separators=(",", ":"))
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    else:
        sys.stdout.write(text + "\n")


if __name__ == "__main__":
    main()
