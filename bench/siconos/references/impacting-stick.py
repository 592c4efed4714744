"""Reference of models/siconos/impacting-stick.toml (Siconos ImpactingStick/ImpactingStick.cpp).

Run: python3 bench/siconos/references/impacting-stick.py (needs mpmath; a few seconds). Writes
models/siconos/references/impacting-stick.json.

An event-driven computation of our own in mpmath at 50 digits. In flight the stick's centre
follows a parabola and its angle turns uniformly (exact); the lower end's height
h(t) = y(t) - l/2 cos(th(t)) is sampled every 1e-4 s (and at the minima of h, where its rate
changes sign) for its first crossing from above, which is then located to 1e-45 s by bisection
refined with the secant method. At an impact the frictional impact law is solved exactly: with
the normal row n = [0, 1, l/2 sin th], the slip row s = [1, 0, l/2 cos th] and
W = [n; s] M^-1 [n; s]^T, the normal impulse makes the normal velocity -e' times what it was
(the stick approaches, so its impulse is positive), and Coulomb's law holds on the slip after
the impact: it sticks (s+ = 0) if the tangential impulse that does so is within the cone
mu times the normal one, else it slips with the tangential impulse -mu sign(s+) times the
normal one; every case is tried and exactly one holds (checked).

Two laws, which differ only where the impact would create energy:
- "newton": e' = e, the example's NewtonImpactFrictionNSL as it is written (Siconos's law);
- "energy-consistent" (zenosim's, docs/friction.md): where the law with e would create kinetic
  energy (its loss -1/2 Ln (un+ + un-) - 1/2 Lt (s+ + s-) negative, which happens when the slip
  reverses through an eccentric impact), e' = c e with c the largest factor in [0, 1] for which
  the loss is not negative (found here by scanning c and refining the last sign change of the
  loss by bisection to 1e-45).
The first impact here reverses the slip: under "newton" it gains kinetic energy; the second
does not, and there both laws agree. The file's main lists (impacts, final) are the
energy-consistent law's; "alternatives" has the newton law's.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "impacting-stick"
# The example's values (ImpactingStick.cpp and its plugin): l, m, the inertia m l^2/12, g,
# the initial angle pi/4, e and mu of NewtonImpactFrictionNSL(e, 0, mu, 2); T = 0.2.
EXAMPLE = {"l": 1, "m": 1, "I": mpmath.mpf(1) / 12, "g": 10, "th0": mpmath.pi / 4, "e": 1,
           "mu": mpmath.mpf("0.01")}
T_END = mpmath.mpf("0.2")
SAMPLE = mpmath.mpf("1e-4")
EPS = mpmath.mpf("1e-45")


def flight(p, q, v, tau):
    """The state tau after (q, v) in free flight."""
    x, y, th = q
    vx, vy, w = v
    return ([x + vx * tau, y + vy * tau - p["g"] * tau * tau / 2, th + w * tau],
            [vx, vy - p["g"] * tau, w])


def gap(p, q):
    return q[1] - p["l"] / 2 * mpmath.cos(q[2])


def gap_rate(p, q, v):
    return v[1] + p["l"] / 2 * mpmath.sin(q[2]) * v[2]


def bisect(f, a, b):
    """A root of f in [a, b] where f(a) > 0 >= f(b), to EPS."""
    fa, fb = f(a), f(b)
    assert fa > 0 >= fb
    while b - a > EPS:
        # secant step, kept inside the bracket, else bisection
        c = b - fb * (b - a) / (fb - fa)
        if not a < c < b or (b - a) > mpmath.mpf("1e-20"):
            c = (a + b) / 2
        fc = f(c)
        if fc > 0:
            a, fa = c, fc
        else:
            b, fb = c, fc
        if fc == 0:
            return c
    return b


def next_landing(p, q, v, horizon):
    """The first time in (0, horizon] at which the end reaches the floor from above, or None."""
    h = lambda tau: gap(p, flight(p, q, v, tau)[0])
    rate = lambda tau: gap_rate(p, *flight(p, q, v, tau))
    a = mpmath.mpf("1e-30")
    while a < horizon:
        b = min(a + SAMPLE, horizon)
        if h(b) <= 0 < h(a):
            return bisect(h, a, b)
        if rate(a) < 0 < rate(b):  # a minimum inside: is it below the floor?
            lo, hi = a, b
            while hi - lo > EPS:
                mid = (lo + hi) / 2
                if rate(mid) < 0:
                    lo = mid
                else:
                    hi = mid
            if h(lo) <= 0:
                return bisect(h, a, lo)
        a = b
    return None


def rows(p, q):
    c = p["l"] / 2
    return [0, 1, c * mpmath.sin(q[2])], [1, 0, c * mpmath.cos(q[2])]


def impact_law(p, q, v, e):
    """The frictional Newton-Coulomb impact with restitution e: (v+, Ln, Lt, case)."""
    n, s = rows(p, q)
    minv = [1 / p["m"], 1 / p["m"], 1 / p["I"]]
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))
    wnn = sum(a * a * k for a, k in zip(n, minv))
    wnt = sum(a * b * k for a, b, k in zip(n, s, minv))
    wtt = sum(b * b * k for b, k in zip(s, minv))
    un, sl = dot(n, v), dot(s, v)
    assert un < 0
    target = -e * un - un  # the change of the normal velocity
    solutions = []
    det = wnn * wtt - wnt * wnt
    ln = (target * wtt + wnt * sl) / det
    lt = (-wnn * sl - wnt * target) / det
    if ln >= 0 and abs(lt) <= p["mu"] * ln:
        solutions.append((ln, lt, "stick"))
    for sigma in (1, -1):
        ln = target / (wnn - sigma * p["mu"] * wnt)
        lt = -sigma * p["mu"] * ln
        s_after = sl + wnt * ln + wtt * lt
        if ln >= 0 and sigma * s_after > 0:
            solutions.append((ln, lt, "slip forward" if sigma > 0 else "slip backward"))
    if len(solutions) != 1:
        raise SystemExit(f"the impact law has {len(solutions)} solutions at q = {q}")
    ln, lt, case = solutions[0]
    v_after = [vi + k * (ni * ln + si * lt) for vi, k, ni, si in zip(v, minv, n, s)]
    un_after, s_after = dot(n, v_after), dot(s, v_after)
    loss = -(ln * (un_after + un) + lt * (s_after + sl)) / 2
    return v_after, {"normal_impulse": ln, "tangential_impulse": lt, "case": case,
                     "normal_velocity_before": un, "normal_velocity_after": un_after,
                     "slip_before": sl, "slip_after": s_after, "loss": loss}


def energy_consistent(p, q, v):
    """The law with the restitution scaled by the largest c in [0, 1] whose loss is >= 0."""
    v_after, info = impact_law(p, q, v, p["e"])
    if info["loss"] >= 0:
        info["restitution_scale"] = mpmath.mpf(1)
        return v_after, info
    loss = lambda c: impact_law(p, q, v, c * p["e"])[1]["loss"]
    grid = [mpmath.mpf(k) / 1000 for k in range(1001)]
    last = max(k for k in range(1000) if loss(grid[k]) >= 0 > loss(grid[k + 1]))
    lo, hi = grid[last], grid[last + 1]
    while hi - lo > EPS:
        mid = (lo + hi) / 2
        if loss(mid) >= 0:
            lo = mid
        else:
            hi = mid
    v_after, info = impact_law(p, q, v, lo * p["e"])
    info["restitution_scale"] = lo
    return v_after, info


def run(p, law):
    q = [p["l"] / 2 * mpmath.sin(p["th0"]), p["l"] / 2 * mpmath.cos(p["th0"]) + mpmath.mpf("0.01"),
         p["th0"]]
    v = [mpmath.mpf("-0.5"), mpmath.mpf("0.1"), mpmath.mpf("0.1")]
    t = mpmath.mpf(0)
    impacts = []
    while True:
        tau = next_landing(p, q, v, T_END - t)
        if tau is None:
            break
        q, v = flight(p, q, v, tau)
        t += tau
        v_before = v
        if law == "newton":
            v, info = impact_law(p, q, v, p["e"])
            info["restitution_scale"] = mpmath.mpf(1)
        else:
            v, info = energy_consistent(p, q, v)
        impacts.append(dict({"t": t, "contacts": ["end"], "q": q, "q_dot_before": v_before,
                             "q_dot_after": v}, **info))
    q, v = flight(p, q, v, T_END - t)
    return impacts, {"t": T_END, "q": q, "q_dot": v}


def main():
    p = check_parameters(NAME, EXAMPLE)
    impacts, final = run(p, "energy-consistent")
    newton_impacts, newton_final = run(p, "newton")
    gain = -newton_impacts[0]["loss"]
    write_reference(
        NAME,
        "examples/mechanics/ImpactingStick/ImpactingStick.cpp",
        "exact flights and the frictional impact law solved exactly, mpmath (50 digits); "
        "Newton-Coulomb with e scaled where it would create energy (docs/friction.md)",
        1e-15,
        impacts=impacts,
        final=final,
        alternatives=[{
            "name": "newton",
            "description": "the example's NewtonImpactFrictionNSL(e, 0, mu, 2) as written: "
                           "Newton's law with e on every impact, Coulomb's on the slip after "
                           "it, even where that creates energy",
            "impacts": newton_impacts, "final": newton_final}],
        notes=f"{len(impacts)} impacts before t_end, both slipping (the cone is too narrow to "
        f"stop the slip). The first reverses the slip (s- = "
        f"{float(impacts[0]['slip_before']):.6g}, s+ = {float(impacts[0]['slip_after']):.6g}): "
        f"with e = 1 as written it would create {float(gain):.4g} J of kinetic energy, so the "
        f"energy-consistent law scales e by {float(impacts[0]['restitution_scale']):.10g}; the "
        "second loses energy under both laws.",
    )


if __name__ == "__main__":
    main()
