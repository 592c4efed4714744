"""Reference of models/siconos/impacting-bar.toml (Siconos
FEM/ImpactingBar/ImpactingBarD1minusLinear.cpp with UserDefinedParameter.hpp, 10 nodes).

Run: /path/to/venv/bin/python bench/siconos/references/impacting-bar.py (needs mpmath; about a
minute). Writes models/siconos/references/impacting-bar.json.

Exact linear flows by modal decomposition, in mpmath at 40 digits. The bar's equations are
M u'' + K u = r e1 (r >= 0 the ground's force on the lowest node while it is held), with the
example's consistent mass matrix M = rho S l tridiag(1/6 | 1/3, 2/3, ..., 1/3 | 1/6) and
stiffness K = (E S/l) tridiag(-1 | 1, 2, ..., 1 | -1), l = L/nDof, built here from the
example's parameters (and checked against the model file's):
- free flight: with M = C C' (Cholesky) and C^-1 K C^-T = Q diag(w^2) Q', the modal coordinates
  z = Q' C' u move as z0 cos(w t) + z0' t sinc(w t) (the rigid mode, w = 0, included);
- held (u1 = 0): the other nine coordinates by the same method on the reduced M_rr, K_rr, and
  the ground's force r = (K_1r - M_1r M_rr^-1 K_rr) u_r, linear in the state;
- an impact on the lowest node with e = 0: u1' becomes 0 and the other velocities change by
  the impulse along M^-1 e1 (u' - (1 + e) u1'/(M^-1)_11 M^-1 e1).
Events: in free flight the lowest node reaching u1 = 0 moving down; while held, r falling
through 0 (lift-off). Each is found by scanning a grid of 1/200 of the shortest period, then
refined by bisection to 1e-30 s; the scan is repeated at 1/400 of the period to check that no
event was missed (the script stops if the two disagree beyond 1e-25 s).
The bar starts as a rigid body moving down (K u = 0 for equal u), so the first impact is at
u0/|v0| = 5e-4 exactly; the run then holds, lifts off, and flies to t_end.
Times are zenosim's (from 0): Siconos's clock reads 1e-8 more.
Accuracy: 40-digit arithmetic; events to 1e-30 s; rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 40

NAME = "impacting-bar"
EXAMPLE = {"E": mpmath.mpf("210e9"), "rho": 7800, "S": mpmath.mpf("0.000314"), "L": 1,
           "nDof": 10, "e": 0, "u0": mpmath.mpf("0.00005"), "v0": mpmath.mpf("-0.1")}
T0_SICONOS = mpmath.mpf("1e-8")
T_SICONOS = mpmath.mpf("0.0015")


def matrices(p):
    n = int(p["nDof"])
    l = p["L"] / n
    mass = mpmath.zeros(n, n)
    stiff = mpmath.zeros(n, n)
    for i in range(n):
        end = i in (0, n - 1)
        mass[i, i] = mpmath.mpf(1) / 3 if end else mpmath.mpf(2) / 3
        stiff[i, i] = 1 if end else 2
        if i + 1 < n:
            mass[i, i + 1] = mass[i + 1, i] = mpmath.mpf(1) / 6
            stiff[i, i + 1] = stiff[i + 1, i] = -1
    return mass * (p["rho"] * p["S"] * l), stiff * (p["E"] * p["S"] / l)


class Modal:
    """The flow of M u'' + K u = 0 for symmetric M > 0, K >= 0."""

    def __init__(self, mass, stiff):
        self.c = mpmath.cholesky(mass)
        c_inv = mpmath.inverse(self.c)
        s = c_inv * stiff * c_inv.T
        s = (s + s.T) / 2
        d, self.q = mpmath.eigsy(s)
        self.w = [mpmath.sqrt(max(x, 0)) for x in d]
        self.to_modal = self.q.T * self.c.T
        self.from_modal = c_inv.T * self.q

    def state(self, u, v, t):
        z0 = self.to_modal * u
        zd0 = self.to_modal * v
        n = len(self.w)
        z = mpmath.matrix(n, 1)
        zd = mpmath.matrix(n, 1)
        for j, w in enumerate(self.w):
            c, s = mpmath.cos(w * t), mpmath.sin(w * t)
            z[j] = z0[j] * c + zd0[j] * t * mpmath.sinc(w * t)
            zd[j] = -z0[j] * w * s + zd0[j] * c
        return self.from_modal * z, self.from_modal * zd

    def shortest_period(self):
        return 2 * mpmath.pi / max(self.w)


def first_fall(f, t0, t_end, step):
    """The first t in (t0, t_end] where f falls through 0 (f > 0 just before), or None."""
    a = t0 + step / 1000
    fa = f(a)
    while a < t_end:
        b = min(a + step, t_end)
        fb = f(b)
        if fa > 0 and fb <= 0:
            lo, hi = a, b
            while hi - lo > mpmath.mpf("1e-32"):
                mid = (lo + hi) / 2
                if f(mid) > 0:
                    lo = mid
                else:
                    hi = mid
            return hi
        a, fa = b, fb
    return None


def simulate(p, mass, stiff, t_end, fraction):
    n = mass.rows
    free = Modal(mass, stiff)
    rest = list(range(1, n))
    m_rr = mpmath.matrix([[mass[i, j] for j in rest] for i in rest])
    k_rr = mpmath.matrix([[stiff[i, j] for j in rest] for i in rest])
    held = Modal(m_rr, k_rr)
    force_row = (mpmath.matrix([[stiff[0, j] for j in rest]])
                 - mpmath.matrix([[mass[0, j] for j in rest]]) * mpmath.inverse(m_rr) * k_rr)
    m_inv = mpmath.inverse(mass)
    step = min(free.shortest_period(), held.shortest_period()) * fraction
    t = mpmath.mpf(0)
    u = mpmath.matrix([p["u0"]] * n)
    v = mpmath.matrix([p["v0"]] * n)
    events = []
    mode = "free"
    while True:
        if mode == "free":
            hit = first_fall(lambda s: free.state(u, v, s)[0][0], 0, t_end - t, step)
            if hit is None:
                u, v = free.state(u, v, t_end - t)
                return events, u, v
            u, v = free.state(u, v, hit)
            t += hit
            u[0] = 0  # on the ground (the root, to 1e-32 s)
            v = v - (1 + p["e"]) * v[0] / m_inv[0, 0] * (m_inv * mpmath.matrix([1] + [0] * (n - 1)))
            events.append(("impact", t))
            mode = "held"
        else:
            ur = mpmath.matrix([u[i] for i in rest])
            vr = mpmath.matrix([v[i] for i in rest])

            def force(s):
                return (force_row * held.state(ur, vr, s)[0])[0]

            off = first_fall(force, 0, t_end - t, step)
            s = t_end - t if off is None else off
            ur, vr = held.state(ur, vr, s)
            u = mpmath.matrix([0] + [ur[i] for i in range(n - 1)])
            v = mpmath.matrix([0] + [vr[i] for i in range(n - 1)])
            t += s
            if off is None:
                return events, u, v
            events.append(("liftoff", t))
            mode = "free"


def main():
    p = check_parameters(NAME, EXAMPLE)
    mass, stiff = matrices(p)
    t_end = T_SICONOS - T0_SICONOS
    events, u, v = simulate(p, mass, stiff, t_end, mpmath.mpf(1) / 200)
    check, u2, v2 = simulate(p, mass, stiff, t_end, mpmath.mpf(1) / 400)
    assert [k for k, _ in events] == [k for k, _ in check], (events, check)
    assert all(abs(a - b) < mpmath.mpf("1e-25") for (_, a), (_, b) in zip(events, check))
    assert max(abs(x) for x in list(u - u2) + list(v - v2)) < mpmath.mpf("1e-25")
    impacts = [{"t": t, "contacts": ["ground"]} for kind, t in events if kind == "impact"]
    liftoffs = [{"t": t, "constraints": ["ground"]} for kind, t in events if kind == "liftoff"]
    write_reference(
        NAME,
        "examples/mechanics/FEM/ImpactingBar/ImpactingBarD1minusLinear.cpp",
        "bench/siconos/references/impacting-bar.py: exact modal flows (free, and with the lowest "
        "node held), events on a 1/200-period grid refined by bisection (40-digit mpmath)",
        1e-15,
        impacts=impacts,
        liftoffs=liftoffs,
        final={"t": t_end, "q": list(u), "q_dot": list(v)},
        notes="Times from 0 (Siconos's minus 1e-8). Events: "
        + ", ".join(f"{k} at {mpmath.nstr(t, 17)}" for k, t in events)
        + "; the scan at 1/400 of a period finds the same events and final state to 1e-25.",
    )


if __name__ == "__main__":
    main()
