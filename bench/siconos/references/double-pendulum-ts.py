"""Reference of models/siconos/double-pendulum-ts.toml (Siconos Pendulum/DoublePendulumTS.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/double-pendulum-ts.py (needs mpmath;
about two minutes: it computes everything twice, at 25 and at 35 digits, and compares).
Writes models/siconos/references/double-pendulum-ts.json.

The equations, derived by hand from the Lagrangian of two point masses on massless rods
(angles a, b from the downward vertical):
  M = [[(m1 + m2) l1^2, m2 l1 l2 cos(a - b)], [m2 l1 l2 cos(a - b), m2 l2^2]],
  M [a'', b''] = [-m2 l1 l2 sin(a - b) b'^2 - (m1 + m2) g l1 sin a,
                   m2 l1 l2 sin(a - b) a'^2 - m2 g l2 sin b],
integrated by mpmath's Taylor-series method (odefun) at 25 digits, restarted after each impact.
Constraints h1 = l1 sin a (e1 = 1) and h2 = l1 sin a + l2 sin b (e2 = 0), gradients
A1 = [l1 cos a, 0], A2 = [l1 cos a, l2 cos b]. Events: a constraint falling through 0, found
by scanning its h along the solution every 1e-3 s and refined by bisection to 1e-22 s. Each
impact (one contact here) applies Newton's law: q' <- q' - (1 + e) (A q')/(A M^-1 A') M^-1 A'.
After an impact with e = 0 the contact is closed (h = 0, h' = 0); if its free acceleration
pulled it further in, the mass would be held there, which this script does not treat: it checks
that the free acceleration is positive (the mass leaves the wall at once) and stops otherwise.
Accuracy: the whole computation is repeated at 35 digits with a scan every 5e-4 s; the JSON
gives the larger of the differences between the two (times and final state) as the accuracy.
"""

import mpmath

from common import check_parameters, write_reference

NAME = "double-pendulum-ts"
EXAMPLE = {"g": 10, "m1": 1, "m2": 1, "l1": 1, "l2": 1, "e1": 1, "e2": 0}
T_END = 5
START = ("0.1", "0.2")


def simulate(p, digits, scan):
    mpmath.mp.dps = digits
    g, m1, m2, l1, l2 = p["g"], p["m1"], p["m2"], p["l1"], p["l2"]
    restitution = [p["e1"], p["e2"]]

    def mass(q):
        c = mpmath.cos(q[0] - q[1])
        return mpmath.matrix([[(m1 + m2) * l1**2, m2 * l1 * l2 * c], [m2 * l1 * l2 * c, m2 * l2**2]])

    def accel(q, v):
        s = mpmath.sin(q[0] - q[1])
        f = mpmath.matrix([-m2 * l1 * l2 * s * v[1] ** 2 - (m1 + m2) * g * l1 * mpmath.sin(q[0]),
                           m2 * l1 * l2 * s * v[0] ** 2 - m2 * g * l2 * mpmath.sin(q[1])])
        return mpmath.lu_solve(mass(q), f)

    def rhs(_, y):
        a = accel(y[:2], y[2:])
        return [y[2], y[3], a[0], a[1]]

    def h(i, q):
        return l1 * mpmath.sin(q[0]) + (l2 * mpmath.sin(q[1]) if i == 1 else 0)

    def grad(i, q):
        return mpmath.matrix([[l1 * mpmath.cos(q[0]), l2 * mpmath.cos(q[1]) if i == 1 else 0]])

    def h_ddot_free(i, q, v):
        # d2/dt2 of h along the free motion: A q'' + the curvature terms.
        a = accel(q, v)
        curvature = -l1 * mpmath.sin(q[0]) * v[0] ** 2
        if i == 1:
            curvature -= l2 * mpmath.sin(q[1]) * v[1] ** 2
        return (grad(i, q) * a)[0] + curvature

    t = mpmath.mpf(0)
    q = [mpmath.mpf(START[0]), mpmath.mpf(START[1])]
    v = [mpmath.mpf(0), mpmath.mpf(0)]
    step = mpmath.mpf(scan)
    impacts = []
    while True:
        flow = mpmath.odefun(rhs, 0, q + v)
        found = None
        s = step / 1000
        values = [h(i, flow(s)[:2]) for i in range(2)]
        while s < T_END - t and found is None:
            s_next = min(s + step, T_END - t)
            nxt = [h(i, flow(s_next)[:2]) for i in range(2)]
            falling = [i for i in range(2) if values[i] > 0 and nxt[i] <= 0]
            if falling:
                roots = []
                for i in falling:
                    lo, hi = s, s_next
                    while hi - lo > mpmath.mpf(10) ** (-digits + 3):
                        mid = (lo + hi) / 2
                        if h(i, flow(mid)[:2]) > 0:
                            lo = mid
                        else:
                            hi = mid
                    roots.append((hi, i))
                found = min(roots)
            s, values = s_next, nxt
        if found is None:
            y = flow(T_END - t)
            return impacts, y[:2], y[2:]
        s, i = found
        y = flow(s)
        t += s
        q, v = list(y[:2]), mpmath.matrix(y[2:])
        a = grad(i, q)
        m_inv_at = mpmath.lu_solve(mass(q), a.T)
        normal = (a * v)[0]
        v = v - (1 + restitution[i]) * normal / (a * m_inv_at)[0] * m_inv_at
        v = [v[0], v[1]]
        impacts.append((t, i))
        for j in range(2):
            closed = abs(h(j, q)) < mpmath.mpf(10) ** (-digits + 5)
            if closed and abs((grad(j, q) * mpmath.matrix(v))[0]) < mpmath.mpf(10) ** (-digits + 5):
                if h_ddot_free(j, q, v) <= 0:
                    raise SystemExit(f"t = {t}: constraint {j} would be held; not treated")


def main():
    p = check_parameters(NAME, EXAMPLE)
    names = ["mass1", "mass2"]
    impacts, q, v = simulate(p, 25, "1e-3")
    check, q2, v2 = simulate(p, 35, "5e-4")
    assert [i for _, i in impacts] == [i for _, i in check], (impacts, check)
    differences = [abs(a - b) for (a, _), (b, _) in zip(impacts, check)]
    differences += [abs(a - b) for a, b in zip(q + v, q2 + v2)]
    accuracy = max(float(max(differences)), 1e-20)
    write_reference(
        NAME,
        "examples/mechanics/Pendulum/DoublePendulumTS.cpp",
        "bench/siconos/references/double-pendulum-ts.py: hand-derived equations integrated by "
        "mpmath's Taylor method (odefun) at 25 digits, events by scan and bisection; checked "
        "against a 35-digit run",
        accuracy,
        impacts=[{"t": t, "contacts": [names[i]]} for t, i in impacts],
        final={"t": T_END, "q": q, "q_dot": v},
        notes=f"{len(impacts)} impacts, each on one mass; no contact is held (after each e = 0 "
        "impact the second mass leaves the wall at once). 'accuracy' is the largest difference "
        "between the 25- and 35-digit computations.",
    )


if __name__ == "__main__":
    main()
