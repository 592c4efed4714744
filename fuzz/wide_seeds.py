#!/usr/bin/env python3
"""Writes the wide-formula seeds of fuzz/seeds/load_model/ (issue 25): models whose loading
cost grew fastest with their size, each kept under the fuzzer's -max_len (4096 bytes), two of
them at -max_len.

    python3 fuzz/wide_seeds.py     # from the repository root
"""

import pathlib
import string

FUZZ = pathlib.Path(__file__).resolve().parent
SEEDS = FUZZ / "seeds" / "load_model"
MAX_LEN = 4096
# a … u but t (the time): 20 coordinates, as in the "a_dot+…+u_dot".
NAMES = [c for c in string.ascii_lowercase[:21] if c != "t"]


def coordinates(names):
    return "coordinates = [" + ", ".join(f'"{n}"' for n in names) + "]\n"


def initial(names, value):
    return "[initial]\n" + "".join(f"{n} = {value}\n" for n in names)


def wide_lagrangian(factors):
    """0.5*(a_dot^2+…) + 1e-6*(a_dot+…)^2 * a*b*c*… with `factors` factors of the product."""
    kinetic = " + ".join(f"{n}_dot^2" for n in NAMES)
    speeds = " + ".join(f"{n}_dot" for n in NAMES)
    product = "*".join(NAMES[i % len(NAMES)] for i in range(factors))
    return (
        'name = "wide-lagrangian"\n'
        + coordinates(NAMES)
        + f'lagrangian = "0.5*({kinetic}) + 1e-6*({speeds})^2 * {product}"\n\n'
        + "[parameters]\nz = 2\n\n"
        + '[[constraint]]\nname = "floor"\nh = "b + z"\nrestitution = 0.5\n\n'
        + initial(NAMES, 1.0)
        + "\n[simulation]\nt_end = 0.1\n"
    )


def many_constraints(count, factors):
    """A wide Lagrangian (fewer factors) under `count` constraints, each retracing it."""
    names = NAMES[:6]
    kinetic = " + ".join(f"{n}_dot^2" for n in names)
    speeds = " + ".join(f"{n}_dot" for n in names)
    product = "*".join(names[i % len(names)] for i in range(factors))
    text = (
        'name = "many-constraints"\n'
        + coordinates(names)
        + f'lagrangian = "0.5*({kinetic}) + 1e-6*({speeds})^2 * {product}"\n\n'
        + "[parameters]\nz = 2\n\n"
    )
    for i in range(count):
        n = names[i % len(names)]
        text += f'[[constraint]]\nname="c{i}"\nh="{n}+z"\nrestitution=0.5\n'
    return text + "\n" + initial(names, 1.0) + "\n[simulation]\nt_end = 0.1\n"


def parameter_chain(count):
    """p0 = 1, p1 = "p0 + 1", …: each parameter refers to the one before."""
    text = 'name = "parameter-chain"\ncoordinates = ["y"]\nlagrangian = "0.5*y_dot^2 - g*y"\n'
    text += "\n[parameters]\np0 = 1\n"
    text += "".join(f'p{i} = "p{i - 1} + 1"\n' for i in range(1, count))
    text += f'g = "p{count - 1} / {count}"\n'
    return text + '\n[[constraint]]\nname = "floor"\nh = "y"\nrestitution = 0.5\n\n[initial]\ny = 1\n'


def dense_mass():
    """A dense 20×20 mass matrix: every pair of velocities coupled, M_ii = 2, M_ij = 0.1."""
    terms = []
    for i, a in enumerate(NAMES):
        for b in NAMES[i:]:
            terms.append(f"{a}_dot^2" if a == b else f"0.1*{a}_dot*{b}_dot")
    return (
        'name = "dense-mass"\n'
        + coordinates(NAMES)
        + 'lagrangian = """\n'
        + " +\n".join(terms)
        + '\n- grav*a"""\n\n'
        + "[parameters]\ngrav = 9.81\n\n"
        + '[[constraint]]\nname = "stop"\nh = "a + 1"\nrestitution = 0.5\n\n'
        + initial(NAMES, 0.1)
        + "\n[simulation]\nt_end = 0.1\n"
    )


def largest(make, size):
    """The largest argument for which `make` writes at most `size` bytes."""
    k = 1
    while len(make(k * 2)) <= size:
        k *= 2
    step = k // 2
    while step:
        if len(make(k + step)) <= size:
            k += step
        step //= 2
    return k


def write(folder, seeds):
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in seeds.items():
        assert len(text.encode()) <= MAX_LEN, (name, len(text))
        (folder / name).write_text(text)
        print(f"{folder.name}/{name}: {len(text)} bytes")


def small(make, count):
    """`make()` with the first `count` coordinates only."""
    global NAMES
    names, NAMES = NAMES, NAMES[:count]
    try:
        return make()
    finally:
        NAMES = names


def main():
    # The shapes of issue 25: 20 coordinates, many factors, many constraints, a long chain, a
    # dense mass matrix. Before loading was linear, the first three of these took 1-1.6 s in
    # the fuzz build (0.07-0.14 s in release): timeouts at -timeout=1 from the start.
    wide = largest(wide_lagrangian, 1024)
    seeds = {
        "wide-lagrangian.toml": wide_lagrangian(wide),
        "many-constraints.toml": many_constraints(64, 10),
        "dense-mass.toml": dense_mass(),
        "parameter-chain.toml": parameter_chain(largest(parameter_chain, MAX_LEN)),
    }
    # The same shapes, smaller, each within a third of the time limit in the fuzz build today,
    # for the fuzzer to grow (up to -max_len) until a load is slow.
    seeds.update(
        {
            "wide-lagrangian-small.toml": small(lambda: wide_lagrangian(60), 6),
            "many-constraints-small.toml": many_constraints(4, 10),
            "dense-mass-small.toml": small(dense_mass, 8),
        }
    )
    # The first two at -max_len, which took 1-2 s to load in release (and 10-30 s in the fuzz
    # build) before loading was linear and bounded: 0.01-0.12 s in release now.
    seeds.update(
        {
            "wide-lagrangian-4k.toml": wide_lagrangian(largest(wide_lagrangian, MAX_LEN)),
            "many-constraints-4k.toml": many_constraints(
                64, largest(lambda f: many_constraints(64, f), MAX_LEN)
            ),
        }
    )
    write(SEEDS, seeds)

if __name__ == "__main__":
    main()
