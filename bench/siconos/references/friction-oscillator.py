"""Reference of models/siconos/friction-oscillator.toml (Siconos
FrictionOscillator/FrictionOscillator.py and .cpp).

Run: python3 bench/siconos/references/friction-oscillator.py (needs mpmath; under a second).
Writes models/siconos/references/friction-oscillator.json.

Closed form, evaluated in mpmath at 50 digits. While the mass slips in the direction
sigma = sign(x_dot), m x'' + k x = -sigma F with F = mu m g (= alpha, the example's relay bound):
a harmonic oscillation of frequency w = sqrt(k/m) about c = -sigma F/k,
x = c + A cos(w t + phi), A = sqrt((x - c)^2 + (x_dot/w)^2). Its velocity is 0 at the next
w t + phi = k pi, at x = c +- A. There the spring's force k |x| is compared with the static
friction bound F: above it, the mass slips back (a reversal of the slip), about the centre of
the other sign, and each half-swing lasts pi/w; at or below it, the mass sticks for good (no
other force acts). Listed: every reversal and the final stick (friction_events, kind
"reversal" or "stick", with the position there), and the state at t_end, at rest where it
stuck, the floor holding y at 0. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "friction-oscillator"
# The example's values (FrictionOscillator.py): m, the stiffness, the relay's bound alpha
# (RelayNSL(1, -1, 1) with B = [0, alpha]), the default initial state (xinit, vinit); T = 100.
EXAMPLE = {"m": 1, "k": 1, "alpha": 1, "x0": 12, "v0": 6}
T_END = mpmath.mpf(100)


def main():
    p = check_parameters(NAME, EXAMPLE)
    m, k, g, mu = p["m"], p["k"], p["g"], p["mu"]
    force = mu * m * g  # the kinetic (and static) friction bound, alpha
    assert abs(force - p["alpha"]) < mpmath.mpf("1e-40")
    w = mpmath.sqrt(k / m)
    t, x, v = mpmath.mpf(0), p["x0"], p["v0"]
    events = []
    while True:
        sigma = mpmath.sign(v)
        c = -sigma * force / k
        phi = mpmath.atan2(-v / w, x - c)  # x - c = A cos(phi), v/w = -A sin(phi)
        amplitude = mpmath.sqrt((x - c) ** 2 + (v / w) ** 2)
        # the next zero of v(tau) = -A w sin(w tau + phi), tau > 0
        tau = (-phi if sigma > 0 else mpmath.pi - phi) / w
        t += tau
        x = c + amplitude if sigma > 0 else c - amplitude
        v = mpmath.mpf(0)
        if k * abs(x) <= force:
            events.append({"t": t, "kind": "stick", "constraints": ["floor"], "x": x})
            break
        events.append({"t": t, "kind": "reversal", "constraints": ["floor"], "x": x})
        v = -mpmath.sign(x) * mpmath.mpf("1e-60")  # slips back, towards the spring's pull
    assert t < T_END
    write_reference(
        NAME,
        "examples/mechanics/FrictionOscillator/FrictionOscillator.py",
        "closed form: half-swings of the harmonic oscillation about -sign(x_dot) mu m g/k, each "
        "ending where x_dot = 0; it sticks where k |x| <= mu m g",
        1e-15,
        friction_events=events,
        final={"t": T_END, "q": [x, 0], "q_dot": [0, 0]},
        notes=f"{len(events) - 1} reversals, then the mass sticks at x = {float(x):.12g}, "
        f"t = {float(t):.12g}, and stays there to t_end.",
    )


if __name__ == "__main__":
    main()
