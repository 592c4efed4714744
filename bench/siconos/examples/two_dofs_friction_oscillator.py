"""FrictionOscillator/TwoDofsFrictionOscillator.py: two masses on springs, the first driven by
f1 cos(w t), the second on a rough floor, as Siconos writes it: a first-order linear system
(x1, x1', x2, x2') with its mass matrix and forcing, and a relay on x2', TimeStepping +
EulerMoreauOSI (theta = 0.5), a Relay problem solved by Lemke (tolerance 1e-8), h = 0.05, to
T = 500."""

import suite
from examples import check_first_order_relay, constraint, normal_force, time_steps

EXAMPLE = "examples/mechanics/FrictionOscillator/TwoDofsFrictionOscillator.py"
SCHEME = {"kind": "TS", "osi": "EulerMoreauOSI", "theta": 0.5, "h": 0.05, "problem": "Relay",
          "solver": "SICONOS_RELAY_LEMKE", "solver_tol": 1e-8}
SCHEME_TEXT = ("TimeStepping + EulerMoreauOSI(theta 0.5), Relay (Lemke, tolerance 1e-8), "
               "h = 0.05; FirstOrderLinearDS (x1, x1', x2, x2') with M and its forcing b(t) "
               "(plugins/two_dofs_oscillator.c), FirstOrderLinearR and RelayNSL(1, -mu N, mu N)")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1, 0.01))


def spec(model):
    """The example's system from the file: x = (x1, x1', x2, x2'), M = diag(1, m1, 1, m2),
    A the file's linear forces (-K read off the file's forces at unit displacements), b(t) its
    forcing along x1 (f1 cos(w t), a C plugin with f1 and w from the file's parameters), the
    relay's output H x = x2' (the file's slip), r = H^T lambda with RelayNSL(1, -mu N, mu N),
    N the floor's normal force. The file's height y2 is held at 0 by its floor, which Siconos
    does not have."""
    p = model["params"]
    coords = model["coordinates"]
    n = len(coords)
    free = [coords.index("x1"), coords.index("x2")]
    zero = [0.0] * n
    mass, f0 = suite.file_dynamics(model, 0.0, zero, zero)
    # the forces' linear part -K, column by column (the forcing is f0 at t = 0: left out)
    cols = {}
    for k in free:
        unit = list(zero)
        unit[k] = 1.0
        _, f1 = suite.file_dynamics(model, 0.0, unit, zero)
        cols[k] = [f1[i] - f0[i] for i in range(n)]
    A = [[0.0] * 4 for _ in range(4)]
    for a, i in enumerate(free):
        A[2 * a][2 * a + 1] = 1.0
        for b, j in enumerate(free):
            A[2 * a + 1][2 * b] = cols[j][i]
    M = [[0.0] * 4 for _ in range(4)]
    for a, i in enumerate(free):
        M[2 * a][2 * a] = 1.0
        M[2 * a + 1][2 * a + 1] = mass[i][i]
    bound = constraint(model, "floor")["mu_kinetic"] * normal_force(model, "floor")
    positions = [None] * n
    velocities = [None] * n
    for a, i in enumerate(free):
        positions[i], velocities[i] = 2 * a, 2 * a + 1
    x0 = [0.0] * 4
    for a, i in enumerate(free):
        x0[2 * a], x0[2 * a + 1] = model["q0"][i], model["v0"][i]
    H = [0.0, 0.0, 0.0, 1.0]
    return {
        "t_end": model["t_end"],
        "ds": [{"kind": "first_order", "coords": coords, "positions": positions,
                "velocities": velocities, "x0": x0, "A": A, "M": M,
                "b": {"plugin": "forcing", "function": "TwoDofsOscillatorB"}}],
        "interactions": [{"name": "floor", "ds": [0], "relay": [-bound, bound],
                          "relation": {"kind": "first_order_linear", "C": [H],
                                       "B": [[x] for x in H]}}],
        "plugins": {"forcing": {"source": "two_dofs_oscillator.c",
                                "defines": {"F1": p["f1"], "OMEGA": p["w"]}}},
        "stick_velocity": 1e-9,
    }


def check_spec(model, spec, plugins):
    return check_first_order_relay(model, spec, plugins)


DISCUSSION = """The forced chain's second mass sticks 54 times and slips 53 times before t = 500, never
reversing. zenosim has every event, in the reference's order, to 8.4e-9 s at 1e-10 (the largest
on the three short, slow slips near t = 127.5, 137.9 and 148.4, which start where the spring's
pull barely exceeds mu N and end 0.26-0.33 s later: their roots are flat), and the state at
t = 500 to 3.5e-10; its errors scale with the tolerance. At the example's h = 0.05 Siconos keeps
the mass stuck through those three short slips (its velocity stays below 1e-14 there): 101
events, so each later one is matched with the reference's next (the 3.2e1 s in the table), and
its state at t = 500 is 5.8e-3 off. At h = 0.005 it has all 107 within 8.2e-3 s (its state, on
its grid at 499.995, 1.9e-3 off), at 5e-4 within 7.5e-4 s and 5.7e-7. The reference sides with
zenosim. Wall time: 142 ms at 1e-10 against 87 ms at the example's h = 0.05, which is cheaper
and misses events, and 0.87 s at 0.005."""
