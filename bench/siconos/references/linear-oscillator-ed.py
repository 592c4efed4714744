"""Reference of models/siconos/linear-oscillator-ed.toml (Siconos
BouncingBallEventDriven/LinearOscillatorED.cpp).

Run: /path/to/venv/bin/python bench/siconos/references/linear-oscillator-ed.py (needs mpmath;
about a second). Writes models/siconos/references/linear-oscillator-ed.json.

Exact, in mpmath at 50 digits. With w = sqrt(kx/m) and d = m g/kx (the spring's rest point
y = -d is behind the wall), a free flight is y(s) = -d + (y + d) cos(w s) + (v/w) sin(w s):
- from rest at y0 the mass reaches the wall after s1 = acos(d/(y0 + d))/w, at the speed
  w sqrt((y0 + d)^2 - d^2);
- from the wall at speed v it returns after s = (2/w) atan(v/(w d)) (y(s) = 0 factors as
  sin(w s/2) ((v/w) cos(w s/2) - d sin(w s/2))), at the same speed (energy), and rebounds at e v.
So impact k + 1 comes (2/w) atan(e^k v1/(w d)) after impact k; the Zeno time is the sum of the
series, summed term by term until a term is below 1e-45 and the rest bounded by its geometric
tail (the terms fall faster than e^k there). Listed: every impact up to 1e-14 s before the Zeno
point; after it the wall holds the mass (its force m g > 0 never vanishes): y = 0 at T = 8.5.
The second coordinate oscillates freely, x = x0 cos(sqrt(ky/m) t); theta never moves.
Accuracy: exact formulas in 50 digits, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "linear-oscillator-ed"
EXAMPLE = {"m": mpmath.mpf("1e-3"), "g": mpmath.mpf("9.81"), "R": mpmath.mpf("0.1"),
           "kx": 100, "ky": 100, "e": mpmath.mpf("0.9"), "y0": 1, "x0": mpmath.mpf("0.001")}
T_END = mpmath.mpf("8.5")


def main():
    p = check_parameters(NAME, EXAMPLE)
    m, g, e, y0 = p["m"], p["g"], p["e"], p["y0"]
    w = mpmath.sqrt(p["kx"] / m)
    d = m * g / p["kx"]
    t = mpmath.acos(d / (y0 + d)) / w
    v = w * mpmath.sqrt((y0 + d) ** 2 - d**2)  # the speed at the first impact
    times = [t]
    # The whole series for the Zeno time.
    total = t
    k = 0
    while True:
        v *= e
        flight = 2 / w * mpmath.atan(v / (w * d))
        total += flight
        k += 1
        if flight < mpmath.mpf("1e-45"):
            total += flight * e / (1 - e)  # the tail, each term below e times the one before
            break
        times.append(total)
    zeno = total
    impacts = [{"t": s, "contacts": ["wall"]} for s in times if zeno - s >= mpmath.mpf("1e-14")]
    wx = mpmath.sqrt(p["ky"] / m)
    x = p["x0"] * mpmath.cos(wx * T_END)
    x_dot = -p["x0"] * wx * mpmath.sin(wx * T_END)
    write_reference(
        NAME,
        "examples/mechanics/BouncingBallEventDriven/LinearOscillatorED.cpp",
        "bench/siconos/references/linear-oscillator-ed.py: exact harmonic flights, impact k+1 "
        "at t_k + (2/w) atan(e^k v1/(w d)); the Zeno time as the series' sum (50-digit mpmath)",
        1e-15,
        impacts=impacts,
        zeno=[{"t": zeno, "constraints": ["wall"]}],
        final={"t": T_END, "q": [0, x, 0], "q_dot": [0, x_dot, 0]},
        notes=f"{len(impacts)} impacts listed, up to 1e-14 s before the Zeno point; then the "
        "wall holds the mass while x oscillates freely.",
    )


if __name__ == "__main__":
    main()
