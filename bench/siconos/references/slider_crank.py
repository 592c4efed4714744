"""The slider-crank reference shared by slider-crank-d1minus.py and
slider-crank-d1minus-velocity.py (Siconos SliderCrank/SliderCrankD1MinusLinear*.cpp, SCConst.h,
SliderCrankPlugin/SliderCrankPlugin.cpp).

The reduction. The slider starts flat (q3 = 0) and at rest in rotation, and nothing turns it:
q3 appears in no force and in the mass matrix only as J3, and the two upper corners (g1, g2)
differ only by the sign of their lever a about the slider's centre, as do the two lower ones
(g3, g4). So whenever the slider is flat both upper corners reach the top of the guide at once,
with the same approach velocity, and the impact law on the pair (a 2x2 problem whose matrix is
w + a^2/J3 on the diagonal and w - a^2/J3 off it, w = A M^-1 A' of the crank and rod) has the
symmetric solution: equal impulses, whose torques on the slider cancel, and each corner's
normal velocity becomes -e times what it was. The slider stays flat: q3 = 0 exactly, and the
four constraints reduce to two on the slider's centre y = l1 sin q1 + l2 sin q2: the top,
c - y >= 0 (g1 = g2 = d/2 - b - y), and the bottom, c + y >= 0 (g3 = g4), with restitution e.
Held against a wall, both of its corners hold it, with equal forces.

The equations, derived by hand for the crank and rod (coordinates q1, q2; k = (m2/2 + m3) l1 l2):
  M = [[J1 + (m1/4 + m2 + m3) l1^2, k cos(q2 - q1)], [k cos(q2 - q1), J2 + (m2/4 + m3) l2^2]],
  M q'' = [k sin(q2 - q1) q2'^2 - g (m1/2 + m2 + m3) l1 cos q1,
           -k sin(q2 - q1) q1'^2 - g (m2/2 + m3) l2 cos q2]  (+ A' f while a wall holds),
  y'' = A q'' - l1 sin q1 q1'^2 - l2 sin q2 q2'^2,  A = [l1 cos q1, l2 cos q2] = dy/dq.
A wall held: f from A M^-1 (F + A' f) - curvature terms = 0 (y'' = 0), the state kept on the wall;
it lets go where its pushing force falls through 0.

The computation, in mpmath: each phase integrated by mpmath's Taylor method (odefun) from the
event that began it. Free flight: the first wall reached (y - c or -c - y rising through 0),
found by scanning every `scan` seconds and bisection, or, after a slow rebound (predicted
flight 2 v/|y''| under 20 scan steps), by bracketing around the predicted flight. Impact:
Newton's law v+ = -e v- on the normal velocity (the pair's symmetric solution above). When a
rebound's normal speed v falls below 1e-8 (m/s) with the free motion pressing the slider back,
the rest of the geometric sequence is summed (its flights, 2 v/|y''| = 3e-12 s and less, shrink by
e, to O(v) relative): that is the Zeno time; from that impact on the wall holds the slider, its
normal velocity projected to 0 (the remaining impacts and the pressing force, which the held
motion replaces, differ from it by O(v) times those flights: below 1e-19 in position). Held:
until the force falls through 0 (then free), with the same scan and bisection.
"""

import mpmath

from common import check_parameters

EXAMPLE = {
    "l1": mpmath.mpf("0.1530"), "l2": mpmath.mpf("0.3060"), "a": mpmath.mpf("0.05"),
    "b": mpmath.mpf("0.025"), "c": mpmath.mpf("0.001"), "m1": mpmath.mpf("0.038"),
    "m2": mpmath.mpf("0.038"), "m3": mpmath.mpf("0.0760"), "J1": mpmath.mpf("7.4e-5"),
    "J2": mpmath.mpf("5.9e-4"), "J3": mpmath.mpf("2.7e-6"), "g": mpmath.mpf("9.81"),
}
# The reference's horizon: the examples run to 0.2 s, but this computation in mpmath costs
# minutes per hundredth of a second on a shared 2-core machine; it covers the first 0.03 s (the
# first Zeno point on the top of the guide, the lift-off, the landing on the bottom).
T_END = mpmath.mpf("0.03")
V0 = ("150", "-75")
ZENO_SPEED = mpmath.mpf("1e-8")


class SliderCrank:
    def __init__(self, name, e, digits, scan):
        mpmath.mp.dps = digits
        p = check_parameters(name, dict(EXAMPLE, e=mpmath.mpf(e)))
        self.p = p
        self.e = p["e"]
        self.scan = mpmath.mpf(scan)
        self.digits = digits
        l1, l2, m1, m2, m3 = p["l1"], p["l2"], p["m1"], p["m2"], p["m3"]
        self.k = (m2 / 2 + m3) * l1 * l2
        self.m11 = p["J1"] + (m1 / 4 + m2 + m3) * l1**2
        self.m22 = p["J2"] + (m2 / 4 + m3) * l2**2
        self.g1 = p["g"] * (m1 / 2 + m2 + m3) * l1
        self.g2 = p["g"] * (m2 / 2 + m3) * l2

    # The crank and rod.
    def mass(self, q):
        c = self.k * mpmath.cos(q[1] - q[0])
        return mpmath.matrix([[self.m11, c], [c, self.m22]])

    def forces(self, q, v):
        s = self.k * mpmath.sin(q[1] - q[0])
        return mpmath.matrix([s * v[1] ** 2 - self.g1 * mpmath.cos(q[0]),
                              -s * v[0] ** 2 - self.g2 * mpmath.cos(q[1])])

    def y(self, q):
        return self.p["l1"] * mpmath.sin(q[0]) + self.p["l2"] * mpmath.sin(q[1])

    def grad(self, q):
        return mpmath.matrix([[self.p["l1"] * mpmath.cos(q[0]), self.p["l2"] * mpmath.cos(q[1])]])

    def curvature(self, q, v):
        return -self.p["l1"] * mpmath.sin(q[0]) * v[0] ** 2 - self.p["l2"] * mpmath.sin(q[1]) * v[1] ** 2

    def y_dot(self, q, v):
        return (self.grad(q) * mpmath.matrix(v))[0]

    def y_ddot_free(self, q, v):
        a = mpmath.lu_solve(self.mass(q), self.forces(q, v))
        return (self.grad(q) * a)[0] + self.curvature(q, v)

    # Walls: side +1 is the top (h = c - y), -1 the bottom (h = c + y).
    def gap(self, side, q):
        return self.p["c"] - side * self.y(q)

    def free_rhs(self, _, state):
        q, v = state[:2], state[2:]
        a = mpmath.lu_solve(self.mass(q), self.forces(q, v))
        return [v[0], v[1], a[0], a[1]]

    def held_force(self, side, q, v):
        """The wall's force on the slider, f >= 0 pushing (generalized force -side A' f)."""
        mass, a = self.mass(q), self.grad(q)
        m_inv_a = mpmath.lu_solve(mass, a.T)
        free = (a * mpmath.lu_solve(mass, self.forces(q, v)))[0] + self.curvature(q, v)
        # y'' = free - side f (A M^-1 A') = 0.
        return side * free / (a * m_inv_a)[0]

    def held_rhs(self, side):
        def rhs(_, state):
            q, v = state[:2], state[2:]
            f = self.held_force(side, q, v)
            total = self.forces(q, v) - side * f * self.grad(q).T
            acc = mpmath.lu_solve(self.mass(q), total)
            return [v[0], v[1], acc[0], acc[1]]
        return rhs

    def impact(self, side, q, v):
        a = self.grad(q)
        m_inv_a = mpmath.lu_solve(self.mass(q), a.T)
        normal = -side * (a * mpmath.matrix(v))[0]  # the gap's rate, < 0 approaching
        # The gap's rate becomes -e normal: an impulse along side * M^-1 A'.
        change = -(1 + self.e) * normal / (a * m_inv_a)[0]
        new = mpmath.matrix(v) - side * change * m_inv_a
        return [new[0], new[1]]

    def first_fall(self, functions, horizon, guess=None):
        """The first s in (0, horizon] where one of `functions` falls through 0, as (s, index),
        or None."""
        if guess is not None and guess < 20 * self.scan:
            lo, hi = guess / 2, guess * 2
            for i, f in enumerate(functions):
                if hi <= horizon and f(lo) > 0 and f(hi) <= 0:
                    if all(g(lo) > 0 for g in functions):
                        return self.bisect(f, lo, hi), i
        s = min(self.scan, horizon) / 1000
        values = [f(s) for f in functions]
        while s < horizon:
            nxt = min(s + self.scan, horizon)
            new = [f(nxt) for f in functions]
            falls = [(self.bisect(f, s, nxt), i) for i, f in enumerate(functions)
                     if values[i] > 0 and new[i] <= 0]
            if falls:
                return min(falls)
            s, values = nxt, new
        return None

    def bisect(self, f, lo, hi):
        width = mpmath.mpf(10) ** (-self.digits + 3) * max(hi, mpmath.mpf("1e-30"))
        while hi - lo > width:
            mid = (lo + hi) / 2
            if f(mid) > 0:
                lo = mid
            else:
                hi = mid
        return hi

    def run(self):
        t = mpmath.mpf(0)
        q = [mpmath.mpf(0), mpmath.mpf(0)]
        v = [mpmath.mpf(V0[0]), mpmath.mpf(V0[1])]
        events = []
        held = None
        guess = None
        while True:
            horizon = T_END - t
            if held is None:
                flow = mpmath.odefun(self.free_rhs, 0, q + v)
                hit = self.first_fall([lambda s: self.gap(1, flow(s)[:2]),
                                       lambda s: self.gap(-1, flow(s)[:2])], horizon, guess)
                guess = None
                if hit is None:
                    state = flow(horizon)
                    return events, state[:2], state[2:]
                s, side = hit[0], (1, -1)[hit[1]]
                state = flow(s)
                t += s
                q, v = list(state[:2]), self.impact(side, state[:2], state[2:])
                events.append(("impact", t, side))
                rebound = side * -self.y_dot(q, v)  # the gap's rate after, >= 0
                pull = -side * self.y_ddot_free(q, v)  # the gap's free acceleration
                if rebound < ZENO_SPEED and pull < 0:
                    # The rest of the sequence: flights 2 v/|h''| shrinking by e.
                    flight = 2 * rebound / -pull
                    events.append(("zeno", t + flight / (1 - self.e), side))
                    # Onto the wall from this impact on: plastic projection of the normal
                    # velocity (what the remaining impacts and the wall's force do together,
                    # to second order in the rebound speed).
                    a = self.grad(q)
                    m_inv_a = mpmath.lu_solve(self.mass(q), a.T)
                    new = mpmath.matrix(v) - self.y_dot(q, v) / (a * m_inv_a)[0] * m_inv_a
                    v = [new[0], new[1]]
                    held = side
                elif pull < 0:
                    guess = 2 * rebound / -pull
            else:
                flow = mpmath.odefun(self.held_rhs(held), 0, q + v)
                hit = self.first_fall(
                    [lambda s: self.held_force(held, flow(s)[:2], flow(s)[2:])], horizon)
                if hit is None:
                    state = flow(horizon)
                    return events, state[:2], state[2:]
                s = hit[0]
                state = flow(s)
                t += s
                q, v = list(state[:2]), list(state[2:])
                events.append(("liftoff", t, held))
                held = None
