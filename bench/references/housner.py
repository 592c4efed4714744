"""Housner's rocking block, independently of zenosim: the Zeno time where it comes to rest.

A rectangle 2b wide and 2c tall (mass m, I = m (b^2 + c^2)/3 about its centre) let go from
rest tilted by th0 on a corner, with plastic corner impacts that stick (G. W. Housner, "The
behavior of inverted pendulum structures during earthquakes", Bull. Seismol. Soc. Am. 53
(1963)). About a corner, phi its tilt, R = sqrt(b^2 + c^2), alpha = atan(b/c), I_O = 4/3 m R^2:
  1/2 I_O phi_dot^2 + m g R cos(alpha - phi) = const,
so a fall from phi_a to 0 takes T(phi_a) = int_0^phi_a dphi / sqrt(2 m g R (cos(alpha - phi_a)
- cos(alpha - phi)) / I_O). Each impact scales the angular velocity by r = 1 - 3/2 sin^2 alpha;
the block then rises on the other corner to phi_k with cos(alpha - phi_k) = cos alpha + I_O
omega^2 / (2 m g R), and falls back in the same time. The Zeno time is
T(th0) + sum_k 2 T(phi_k), summed here in 50-digit arithmetic (mpmath, tanh-sinh quadrature)
until the terms are below 1e-40. Prints the impact times and the Zeno time as JSON.

Run: python3 bench/references/housner.py [b c th0 g]   (defaults: models/housner-block.toml)
"""
import json
import sys

import mpmath as mp

mp.mp.dps = 50


def main():
    args = [mp.mpf(a) for a in sys.argv[1:]] or [mp.mpf("0.2"), mp.mpf("0.5"), mp.mpf("0.1"),
                                                 mp.mpf("9.81")]
    b, c, th0, g = args
    R = mp.sqrt(b * b + c * c)
    alpha = mp.atan(b / c)
    I_O = mp.mpf(4) / 3 * R * R  # per unit mass
    r = 1 - mp.mpf(3) / 2 * mp.sin(alpha) ** 2

    def fall(phi_a):
        # cos(alpha - phi_a) - cos(alpha - phi) without cancellation; phi = phi_a (1 - u^2)
        # takes the square-root singularity at phi_a out.
        k = 2 * g * R / I_O

        def f(u):
            if u == 0:
                return 2 * mp.sqrt(phi_a / (k * mp.sin(alpha - phi_a)))
            d = phi_a * u * u  # phi_a - phi
            gap = 2 * mp.sin(alpha - phi_a + d / 2) * mp.sin(d / 2)
            return 2 * phi_a * u / mp.sqrt(k * gap)

        return mp.quad(f, [0, 1])

    def amplitude(energy):
        # phi with cos(alpha - phi) - cos(alpha) = 2 sin(alpha - phi/2) sin(phi/2) = energy.
        phi = 2 * energy / mp.sin(alpha)
        for _ in range(200):
            value = 2 * mp.sin(alpha - phi / 2) * mp.sin(phi / 2) - energy
            slope = mp.cos(alpha - phi)
            step = value / slope
            phi -= step
            if abs(step) <= abs(phi) * mp.mpf("1e-45"):
                break
        return phi

    def speed(phi_a):
        return mp.sqrt(2 * g * R / I_O * (mp.cos(alpha - phi_a) - mp.cos(alpha)))

    t = fall(th0)
    impacts = [t]
    omega = r * speed(th0)
    while True:
        phi = amplitude(I_O * omega * omega / (2 * g * R))
        step = 2 * fall(phi)
        t += step
        impacts.append(t)
        omega = r * omega
        if step < mp.mpf("1e-40"):
            break
    print(json.dumps({
        "b": float(b), "c": float(c), "th0": float(th0), "g": float(g),
        "ratio": mp.nstr(r, 20),
        "impacts": [mp.nstr(x, 20) for x in impacts[:60]],
        "impact_count_summed": len(impacts),
        "t_zeno": mp.nstr(t, 20),
    }, indent=1))


if __name__ == "__main__":
    main()
