#!/usr/bin/env python3
"""Writes the seeds of the lcp fuzz target (fuzz/checks/lcp.rs describes the format) into
fuzz/seeds/lcp/: the contact problems the solver met or is built for; and its dictionary,
fuzz/lcp.dict: numbers as the 8 bytes of an f64 (zeros, units, the ends of the range,
subnormal ones, NaN and the infinities, rounding-sized ones).

    python3 fuzz/lcp_seeds.py
"""

import struct
from pathlib import Path

FUZZ = Path(__file__).resolve().parent
SEEDS = FUZZ / "seeds" / "lcp"

# The dictionary's numbers, by name.
TOKENS = {
    "zero": 0.0,
    "minus_zero": -0.0,
    "one": 1.0,
    "minus_one": -1.0,
    "two": 2.0,
    "half": 0.5,
    "smallest_subnormal": 5e-324,
    "minus_smallest_subnormal": -5e-324,
    "smallest_normal": 2.2250738585072014e-308,
    "tiny": 1e-300,
    "huge": 1e300,
    "largest": 1.7976931348623157e308,
    "nan": float("nan"),
    "infinity": float("inf"),
    "minus_infinity": float("-inf"),
    "f32_subnormal": 2.6624670822171523e-45,
    "epsilon": 2.220446049250313e-16,
    "rounding": 1e-16,
    "small": -1.06e-10,
}

# Bit 0: with rounding bounds (lcp::solve_rounded); bit 1: m = A Aᵀ + δ I.
ROUNDED, GRAM = 1, 2


def chain(k, apart=()):
    """The Delassus matrix of a column of beads on a floor: floor, then gaps between unit
    masses; the contacts in `apart` not coupled to the one before them."""
    w = [[0.0] * k for _ in range(k)]
    for i in range(k):
        w[i][i] = 1.0 if i == 0 else 2.0
        if i > 0 and i not in apart:
            w[i][i - 1] = w[i - 1][i] = -1.0
    return [x for row in w for x in row]


def write(name, k, flags, values):
    data = bytes([k, flags]) + b"".join(struct.pack("<d", v) for v in values)
    (SEEDS / f"{name}.bin").write_bytes(data)


def dictionary():
    lines = ["# The lcp fuzz target's tokens: f64s, 8 bytes little-endian (lcp_seeds.py)."]
    for name, value in TOKENS.items():
        escaped = "".join(f"\\x{b:02x}" for b in struct.pack("<d", value))
        lines.append(f'{name}="{escaped}"')
    (FUZZ / "lcp.dict").write_text("\n".join(lines) + "\n")


def main():
    dictionary()
    SEEDS.mkdir(parents=True, exist_ok=True)
    # The column of beads' impact law where Lemke's method stopped (t = 1.187, rtol = 1e-10):
    # exact, then with the engine's rounding bounds.
    beads_q = [-2.6624670822171523e-45, 2.6624670822171523e-45, 0.0, 0.0, 0.0, 0.0, 0.0,
               -0.12268525544980818]
    beads_bounds = [2.235287196701547e-15] + [3.1611734693742643e-15] * 7
    write("column-of-beads", 8, 0, chain(8, (7,)) + beads_q)
    write("column-of-beads-rounded", 8, ROUNDED, chain(8, (7,)) + beads_q + beads_bounds)
    # W = I with a small entry that is data, not a tie.
    write("identity-small-entry", 2, 0, [1.0, 0.0, 0.0, 1.0, -1.06e-10, -5.46])
    # Newton's cradle of three: the impulses (4/3, 2/3).
    write("newtons-cradle", 2, 0, [2.0, -1.0, -1.0, 2.0, -2.0, 0.0])
    # A point pinched between y ≥ 0 and y ≤ −x²: no solution, proven.
    write("pinched", 2, 0, [1.0, -1.0, -1.0, 1.0, -9.81, 7.81])
    # A table on four legs: A's rows (1, x, y) at (±1, ±1), a column of zeros; gravity.
    legs = [1.0, 1.0, 1.0, 0.0, 1.0, 1.0, -1.0, 0.0, 1.0, -1.0, 1.0, 0.0, 1.0, -1.0, -1.0, 0.0]
    write("table-on-four-legs", 4, GRAM, legs + [-9.81] * 4 + [0.0])
    # A chain of twelve contacts struck at one end.
    write("chain-of-twelve", 12, 0, chain(12) + [-2.0] + [0.0] * 11)
    # A Gram matrix plus a small multiple of I, q with zeros, a tie and a subnormal entry.
    a = [0.5, -0.25, 1.0, 0.0, 0.5, -0.25, 0.75, 2.0, 0.125, -1.0, 0.5, 0.25, 0.0, 1.5, -0.5, 0.5]
    write("gram-degenerate", 4, GRAM | ROUNDED,
          a + [0.0, -1.0, -1.0, -5e-324] + [0.0, 0.0, 1e-17, 0.0] + [1e-3])


if __name__ == "__main__":
    main()
