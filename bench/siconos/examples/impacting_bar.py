"""FEM/ImpactingBar/ImpactingBarD1minusLinear.cpp: an elastic bar of nDof = 10 linear elements
dropped on the ground, e = 0, TimeSteppingD1Minus + D1MinusLinearOSI (its default type), h = 1e-7,
from t0 = 1e-8 to T = 0.0015."""

from examples import constraint, linear_relation, time_steps

EXAMPLE = "examples/mechanics/FEM/ImpactingBar/ImpactingBarD1minusLinear.cpp"
SCHEME = {"kind": "TS", "osi": "D1MinusLinearOSI", "type": "halfexplicit_acceleration_level",
          "h": 1e-7}
SCHEME_TEXT = ("TimeSteppingD1Minus + D1MinusLinearOSI (halfexplicit_acceleration_level), LCPs "
               "at velocity and acceleration level, h = 1e-7; LagrangianLinearTIDS (the "
               "example's assembled mass and stiffness) and LagrangianLinearTIR; run through "
               "d1minus_runner.cpp; time from 0 as in the file (the example's t0 = 1e-8)")


def steps(base):
    return time_steps(base, (10.0, 1.0, 0.25))


def spec(model):
    """The example's assembly, with the file's rho, S, E, L and nDof: the consistent mass
    rho S l tridiag(1/6 | 1/3, 2/3, ..., 2/3, 1/3 | 1/6) and the stiffness E S / l
    tridiag(-1 | 1, 2, ..., 2, 1 | -1), l = L / nDof as the example has it; no weight."""
    p = model["params"]
    n = int(round(p["nDof"]))
    if len(model["coordinates"]) != n:
        raise ValueError(f"{model['name']}: {len(model['coordinates'])} coordinates, nDof {n}")
    length = p["L"] / n
    mass = [[0.0] * n for _ in range(n)]
    stiff = [[0.0] * n for _ in range(n)]
    for i in range(n):
        end = i in (0, n - 1)
        mass[i][i] = (1.0 / 3.0 if end else 2.0 / 3.0) * p["rho"] * p["S"] * length
        stiff[i][i] = (1.0 if end else 2.0) * p["E"] * p["S"] / length
        for j in (i - 1, i + 1):
            if 0 <= j < n:
                mass[i][j] = 1.0 / 6.0 * p["rho"] * p["S"] * length
                stiff[i][j] = -1.0 * p["E"] * p["S"] / length
    coords = model["coordinates"]
    (c,) = model["constraints"]
    return {"t_end": model["t_end"],
            "ds": [{"kind": "linear", "coords": coords, "q0": model["q0"], "v0": model["v0"],
                    "mass": mass, "K": stiff, "fext": [0.0] * n}],
            "interactions": [{"name": c["name"], "e": constraint(model, c["name"])["e"],
                              "ds": [0], "relation": linear_relation(model, c["name"], coords)}]}


DISCUSSION = """The bar lands at t = 5e-4 (one plastic impact), a compression wave runs up and back, and the
lowest node lifts off at 8.36e-4. zenosim gets the impact to 4e-19 and the state at t_end to
about the tolerance (1.7e-5 at 1e-6, 1.3e-11 at 1e-12: ten coupled modes up to about 1e5 rad/s,
integrated, not solved in closed form). D1Minus (Siconos, in C++) puts the impact in the step
where the node reaches the ground (error at most h) and ends on its grid, up to one step before
t_end (0.001499 at h = 1e-6): its last state is compared with the reference's at t_end, so its
final error mixes that offset with the scheme's; its positions are within 1.3e-7, 1.2e-8 and
1.6e-8 at h = 1e-6, 1e-7 and 2.5e-8, its velocities (which the fast modes change by about 1e-3
per 1e-7 s) within 2.4e-3, 6.7e-5 and 2.7e-4. The modal reference sides with zenosim; zenosim
takes 0.7-3 ms, Siconos 235 ms at the example's step."""
