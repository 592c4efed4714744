"""Reference of models/siconos/two-dofs-friction-oscillator.toml (Siconos
FrictionOscillator/TwoDofsFrictionOscillator.py).

Run: python3 bench/siconos/references/two-dofs-friction-oscillator.py (needs mpmath; about a
minute). Writes models/siconos/references/two-dofs-friction-oscillator.json.

An event-driven computation of our own in mpmath at 40 digits, on the exact solutions of each
mode. Two masses on springs (k1 to the wall, k2 between them); the first is driven by
f1 cos(w t), the second rests on a rough floor with the normal force N and Coulomb's
coefficient mu (one coefficient):
- slipping in the direction sigma, M x'' + K x = (f1 cos(w t), -sigma mu N): the sum of the
  particular solution K^-1 (0, -sigma mu N) + (K - w^2 M)^-1 (f1, 0) cos(w t) and the free
  oscillation in the two normal modes (K phi = W^2 M phi, phi mass-normalised; the modes'
  amplitudes from the state at the mode's start);
- sticking (x2 = X, x2' = 0): m1 x1'' + (k1 + k2) x1 = k2 X + f1 cos(w t), one harmonic
  oscillator with its particular solution; the floor holds x2 with r = -k2 (x1 - X).
Events: a slip stops where x2' reaches 0 (the mass then sticks if k2 |x1 - x2| <= mu N, else
its slip reverses); a stick ends where |k2 (x1 - X)| reaches mu N (it slips towards the
spring's pull). Each event function is sampled every 0.01 s (a period is 3.9 s at least), its
local minima checked too (a dip below 0 inside a sample), and its first root located by
bisection to 1e-35 s. Listed: every event (friction_events, "stick", "slip", "reversal"),
and the state at t_end. Accuracy: the events are located to 1e-35 s and the closed forms are
exact; 40 digits carry the state through them far below f64's rounding (checked: the same
run at 30 digits agrees to 1e-20).
"""

import sys

import mpmath

from common import check_parameters, write_reference

NAME = "two-dofs-friction-oscillator"
# The example's values (TwoDofsFrictionOscillator.py and plugins/OscillatorPlugin.cpp): the
# masses and springs, mu and N of RelayNSL(1, -mu N, mu N), d1 = d2 = 0, the forcing f1, f2 = 0,
# its frequency w; the initial state (1, 0, 0, 0); T = 500.
EXAMPLE = {"m1": 1, "m2": 1, "k1": 1, "k2": 1, "mu": mpmath.mpf("0.5"), "N": 1, "f1": 1,
           "w": mpmath.mpf("0.3")}
T_END = 500
SAMPLE = mpmath.mpf("0.01")


class Slip:
    """The slipping motion from (t0, x, v) in the direction sigma: x(t), v(t) exact."""

    def __init__(self, p, t0, x, v, sigma):
        self.p, self.t0, self.sigma = p, t0, sigma
        m1, m2, k1, k2 = p["m1"], p["m2"], p["k1"], p["k2"]
        K = mpmath.matrix([[k1 + k2, -k2], [-k2, k2]])
        Mh = mpmath.diag([1 / mpmath.sqrt(m1), 1 / mpmath.sqrt(m2)])
        E, Q = mpmath.eigsy(Mh * K * Mh)
        self.freq = [mpmath.sqrt(E[i]) for i in range(2)]
        self.phi = Mh * Q  # mass-normalised modes, columns
        self.M = mpmath.diag([m1, m2])
        self.const = mpmath.lu_solve(K, mpmath.matrix([0, -sigma * p["mu"] * p["N"]]))
        w = p["w"]
        self.harm = mpmath.lu_solve(K - w * w * self.M, mpmath.matrix([p["f1"], 0]))
        xp, vp = self.particular(t0)
        dx = mpmath.matrix(x) - xp
        dv = mpmath.matrix(v) - vp
        a = self.phi.T * self.M * dx
        b = self.phi.T * self.M * dv
        self.a = [a[i] for i in range(2)]
        self.b = [b[i] / self.freq[i] for i in range(2)]

    def particular(self, t):
        w = self.p["w"]
        return (self.const + self.harm * mpmath.cos(w * t),
                -self.harm * w * mpmath.sin(w * t))

    def state(self, t):
        xp, vp = self.particular(t)
        tau = t - self.t0
        x, v = xp, vp
        for i in range(2):
            c, s = mpmath.cos(self.freq[i] * tau), mpmath.sin(self.freq[i] * tau)
            col = self.phi[:, i]
            x = x + col * (self.a[i] * c + self.b[i] * s)
            v = v + col * (self.freq[i] * (-self.a[i] * s + self.b[i] * c))
        return [x[0], x[1]], [v[0], v[1]]

    def event(self, t):
        """sigma x2' (positive while it slips on)."""
        return self.sigma * self.state(t)[1][1]


class Stick:
    """The motion with x2 held at X from (t0, x1, v1): x1(t) exact."""

    def __init__(self, p, t0, x1, v1, X):
        self.p, self.t0, self.X = p, t0, X
        m1, k1, k2, w = p["m1"], p["k1"], p["k2"], p["w"]
        self.freq = mpmath.sqrt((k1 + k2) / m1)
        self.const = k2 * X / (k1 + k2)
        self.harm = p["f1"] / ((k1 + k2) - m1 * w * w)
        xp, vp = self.particular(t0)
        self.a = x1 - xp
        self.b = (v1 - vp) / self.freq

    def particular(self, t):
        w = self.p["w"]
        return self.const + self.harm * mpmath.cos(w * t), -self.harm * w * mpmath.sin(w * t)

    def state(self, t):
        xp, vp = self.particular(t)
        tau = t - self.t0
        c, s = mpmath.cos(self.freq * tau), mpmath.sin(self.freq * tau)
        x1 = xp + self.a * c + self.b * s
        v1 = vp + self.freq * (-self.a * s + self.b * c)
        return [x1, self.X], [v1, mpmath.mpf(0)]

    def event(self, t):
        """mu N - |k2 (x1 - X)| (positive while it sticks)."""
        x = self.state(t)[0]
        return self.p["mu"] * self.p["N"] - abs(self.p["k2"] * (x[0] - self.X))


def first_root(f, t0, t_end, eps):
    """The first t in (t0, t_end] with f(t) <= 0, f positive before: sampled every SAMPLE
    (with the minima between samples checked by a finer look where f dips), then bisected."""
    def bisect(a, b):
        while b - a > eps:
            mid = (a + b) / 2
            if f(mid) > 0:
                a = mid
            else:
                b = mid
        return b

    a = t0 + mpmath.mpf("1e-12")
    fa = f(a)
    if fa <= 0:
        raise SystemExit(f"an event at the start of a mode, t = {t0}")
    while a < t_end:
        b = min(a + SAMPLE, t_end)
        fb = f(b)
        if fb <= 0:
            return bisect(a, b)
        # a dip inside the sample: its minimum by golden-section search
        fm = f((a + b) / 2)
        if fm < min(fa, fb):
            lo, hi = a, b
            for _ in range(60):
                m1_, m2_ = lo + (hi - lo) / 3, hi - (hi - lo) / 3
                if f(m1_) < f(m2_):
                    hi = m2_
                else:
                    lo = m1_
            if f(lo) <= 0:
                return bisect(a, lo)
        a, fa = b, fb
    return None


def run(p, dps):
    mpmath.mp.dps = dps
    eps = mpmath.mpf(10) ** (-dps + 5)
    t = mpmath.mpf(0)
    x, v = [mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(0), mpmath.mpf(0)]
    force = lambda x: p["k2"] * (x[0] - x[1])  # the spring's pull on the second mass
    mu_n = p["mu"] * p["N"]
    if abs(force(x)) <= mu_n:
        raise SystemExit("the example starts slipping")
    sigma = mpmath.sign(force(x))
    mode = Slip(p, t, x, v, sigma)
    events = []
    while True:
        t_event = first_root(mode.event, t, mpmath.mpf(T_END), eps)
        if t_event is None:
            x, v = mode.state(mpmath.mpf(T_END))
            break
        t = t_event
        x, v = mode.state(t)
        if isinstance(mode, Slip):
            v[1] = mpmath.mpf(0)
            if abs(force(x)) <= mu_n:
                events.append({"t": t, "kind": "stick", "constraints": ["floor"]})
                mode = Stick(p, t, x[0], v[0], x[1])
            else:
                events.append({"t": t, "kind": "reversal", "constraints": ["floor"]})
                mode = Slip(p, t, x, v, mpmath.sign(force(x)))
        else:
            events.append({"t": t, "kind": "slip", "constraints": ["floor"]})
            mode = Slip(p, t, x, v, mpmath.sign(force(x)))
        print(f"{float(t):.12f} {events[-1]['kind']}", file=sys.stderr)
    return events, {"t": mpmath.mpf(T_END), "q": [x[0], x[1], 0], "q_dot": [v[0], v[1], 0]}


def main():
    p = check_parameters(NAME, EXAMPLE)
    check, check_final = run(p, 30)
    events, final = run(p, 40)
    assert len(check) == len(events)
    agree = max([abs(a["t"] - b["t"]) for a, b in zip(check, events)]
                + [abs(a - b) for a, b in zip(check_final["q"] + check_final["q_dot"],
                                              final["q"] + final["q_dot"])])
    assert agree < mpmath.mpf("1e-20"), agree
    counts = {}
    for ev in events:
        counts[ev["kind"]] = counts.get(ev["kind"], 0) + 1
    kinds = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
    write_reference(
        NAME,
        "examples/mechanics/FrictionOscillator/TwoDofsFrictionOscillator.py",
        "exact modal solutions of the slipping and sticking modes, events located by "
        "bisection to 1e-35 s, mpmath (40 digits)",
        1e-15,
        friction_events=events,
        final=final,
        notes=f"{len(events)} friction events ({kinds}) "
        f"before t_end, the first stick at t = {float(events[0]['t']):.10g}; at 30 digits the "
        f"same run agrees to {float(agree):.1e}.",
    )


if __name__ == "__main__":
    main()
