"""Reference of models/siconos/slider-crank-d1minus-velocity.toml (Siconos
SliderCrank/SliderCrankD1MinusLinearVelocityLevel.cpp, SCConst.h, SliderCrankPlugin/SliderCrankPlugin.cpp), e = 0.4.

Run: /path/to/venv/bin/python bench/siconos/references/slider-crank-d1minus-velocity.py (needs mpmath; about
two minutes: it computes everything twice, at 30 digits scanning every 1e-4 s and at 36 digits
scanning every 5e-5 s, and compares). It covers t <= 0.03 (T_END in slider_crank.py), not the
example's 0.2. Writes models/siconos/references/slider-crank-d1minus-velocity.json.

The method (the reduction to a flat slider and the event-driven computation in mpmath) is
described in slider_crank.py. Accuracy: the JSON's 'accuracy' is the largest difference between
the two computations over the event times and the final state.
"""

import mpmath

from common import write_reference
from slider_crank import SliderCrank, T_END

NAME = "slider-crank-d1minus-velocity"
E = "0.4"
WALLS = {1: ["g1", "g2"], -1: ["g3", "g4"]}


def main():
    events, q, v = SliderCrank(NAME, E, 30, "1e-4").run()
    check, q2, v2 = SliderCrank(NAME, E, 36, "5e-5").run()
    assert [(k, s) for k, _, s in events] == [(k, s) for k, _, s in check], (events, check)
    differences = [abs(a - b) for (_, a, _), (_, b, _) in zip(events, check)]
    differences += [abs(a - b) for a, b in zip(list(q) + list(v), list(q2) + list(v2))]
    accuracy = max(float(max(differences)), 1e-25)
    impacts = [{"t": t, "contacts": WALLS[side]} for kind, t, side in events if kind == "impact"]
    zeno = [{"t": t, "constraints": WALLS[side]} for kind, t, side in events if kind == "zeno"]
    liftoffs = [{"t": t, "constraints": WALLS[side]} for kind, t, side in events
                if kind == "liftoff"]
    write_reference(
        NAME,
        "examples/mechanics/SliderCrank/SliderCrankD1MinusLinearVelocityLevel.cpp",
        "bench/siconos/references/slider-crank-d1minus-velocity.py: the flat slider's exact reduction, "
        "hand-derived equations integrated by mpmath's Taylor method, events by scan and "
        "bisection, Zeno tails summed (30 digits, checked against 36), to t = 0.03",
        accuracy,
        impacts=impacts,
        zeno=zeno,
        liftoffs=liftoffs,
        final={"t": T_END, "q": [q[0], q[1], 0], "q_dot": [v[0], v[1], 0]},
        notes=f"{len(impacts)} impacts (each on both corners of a side at once: the slider stays "
        f"flat), {len(zeno)} Zeno points, {len(liftoffs)} lift-offs to t = 0.03 (the example "
        "runs to 0.2; this reference stops at 0.03). Each Zeno "
        "sequence is followed until its rebound speed is below 1e-8 m/s (the impacts after "
        "that are not listed) and its time is the sum of the rest.",
    )


if __name__ == "__main__":
    main()
