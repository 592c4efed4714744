"""Reference of models/siconos/column-of-beads-ts.toml (Siconos ColumnOfBeads/ColumnOfBeadsTS.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/column-of-beads-ts.py (needs mpmath;
about 20 seconds). Writes models/siconos/references/column-of-beads-ts.json.

The exact sequence of binary impacts, event by event in mpmath at 60 digits. All beads have the
same weight, so in free flight every gap between neighbours changes linearly in time and only the
floor's gap is a parabola: the next event is the earliest of the floor's root (quadratic
formula) and each closing gap's root -h/u (u < 0 its relative velocity), all exact. An impact
acts on the one contact that is reached, by Newton's law with e = 0.9: on the floor the lowest
bead's velocity is reversed times e; between two equal beads the relative velocity u becomes
-e u and the momentum is kept (each bead's velocity changes by -+(1 + e) u/2).

The binary sequence runs into an accumulation near t = 1.1813, where a group of beads closes up
and the impacts alternate between contacts that are all nearly closed: in exact arithmetic no two
contacts are ever closed at the same instant, but the gaps of the other contacts at an impact
fall towards 0. The sequence is kept while every other contact's gap at each impact is at least
1e-9 (ten times zenosim's default absolute tolerance, 1e-10: a smaller gap is within what a run
at that tolerance can tell from closed, and the order of the impacts there is no longer
resolved); it stops before the first impact where another contact is closer than that, and the
JSON says how many binary impacts precede it (and, in the notes, where other thresholds would
stop it). Each listed impact has its time, its contact, and the smallest gap of the other
contacts then.

The rest state ("rest" in the JSON): the beads end at rest stacked, heights R, 3 R, ..., 19 R
(every contact closed, held by the weight of the beads above). It is not a state at Siconos's
T = 2, which may come before the beads settle: the test runs the model longer for it.
Accuracy: the event times are exact formulas in 60 digits; rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 60

NAME = "column-of-beads-ts"
EXAMPLE = {"m": 1, "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"), "e": mpmath.mpf("0.9"),
           "y0": 1, "gap0": mpmath.mpf("0.25")}
BEADS = 10
THRESHOLD = mpmath.mpf("1e-9")
REPORTED = ["1e-6", "1e-8", "1e-9", "1e-10", "1e-12"]
MAX_IMPACTS = 2000


def contact_names():
    return ["floor"] + [f"gap_{i}_{i + 1}" for i in range(1, BEADS)]


def binary_sequence(p):
    g, r, e = p["g"], p["R"], p["e"]
    y = [p["y0"] + p["gap0"] * i for i in range(BEADS)]
    v = [mpmath.mpf(0)] * BEADS
    t = mpmath.mpf(0)
    impacts = []
    while len(impacts) < MAX_IMPACTS:
        # The floor: y1 - R + v1 s - g s^2/2 = 0, its positive root.
        h0 = y[0] - r
        best = ((v[0] + mpmath.sqrt(v[0] ** 2 + 2 * g * h0)) / g, 0)
        for i in range(BEADS - 1):
            u = v[i + 1] - v[i]
            if u < 0:
                s = -(y[i + 1] - y[i] - 2 * r) / u
                if s < best[0]:
                    best = (s, i + 1)
        s, contact = best
        t += s
        y = [y[i] + v[i] * s - g * s * s / 2 for i in range(BEADS)]
        v = [v[i] - g * s for i in range(BEADS)]
        gaps = [y[0] - r] + [y[i + 1] - y[i] - 2 * r for i in range(BEADS - 1)]
        closest = min(abs(gaps[j]) for j in range(BEADS) if j != contact)
        if contact == 0:
            y[0] = r
            v[0] = -e * v[0]
        else:
            i = contact - 1
            u = v[i + 1] - v[i]
            v[i] += (1 + e) * u / 2
            v[i + 1] -= (1 + e) * u / 2
        impacts.append((t, contact, closest))
    return impacts


def main():
    p = check_parameters(NAME, EXAMPLE)
    names = contact_names()
    sequence = binary_sequence(p)
    first_below = {}
    for threshold in REPORTED:
        first_below[threshold] = next(
            (k for k, (_, _, closest) in enumerate(sequence) if closest < mpmath.mpf(threshold)),
            None)
    stop = next(k for k, (_, _, closest) in enumerate(sequence) if closest < THRESHOLD)
    impacts = [{"t": t, "contacts": [names[c]], "closest_other_gap": closest}
               for t, c, closest in sequence[:stop]]
    r = p["R"]
    rest = [r * (2 * i + 1) for i in range(BEADS)]
    where = "; ".join(
        f"below {th}: impact {k + 1} (t = {mpmath.nstr(sequence[k][0], 10)})"
        for th, k in first_below.items())
    write_reference(
        NAME,
        "examples/mechanics/ColumnOfBeads/ColumnOfBeadsTS.cpp",
        "bench/siconos/references/column-of-beads-ts.py: the exact binary-impact sequence "
        "(free parabolas, Newton's law with e = 0.9 on one pair at a time) in 60-digit mpmath",
        1e-15,
        binary_impacts=stop,
        impacts=impacts,
        rest={"q": rest, "q_dot": [0] * BEADS},
        notes=f"{stop} binary impacts before the first impact (number {stop + 1}, "
        f"t = {mpmath.nstr(sequence[stop][0], 12)}) where another contact's gap is below 1e-9. "
        f"The binary sequence accumulates near t = {mpmath.nstr(sequence[-1][0], 10)} "
        f"({MAX_IMPACTS} impacts computed). First impact where another contact's gap is: "
        f"{where}. 'rest' is the state the beads end in, stacked at R, 3R, ..., 19R and at rest "
        "(not a state at t = 2: the test checks it after a longer run).",
    )


if __name__ == "__main__":
    main()
