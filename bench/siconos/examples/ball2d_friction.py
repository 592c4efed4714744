"""2DRigidBodies/Ball2D_kernel_only_with_friction.cpp: a spinning disk dropped onto a rough
ground, e = 0.9, mu = 0.1, TimeStepping + MoreauJeanOSI (theta = 0.5) with a FrictionContact(2)
problem, h = 0.005, to T = 10."""

from examples import friction_law, frictional_relation, time_steps

EXAMPLE = "examples/mechanics/2DRigidBodies/Ball2D_kernel_only_with_friction.cpp"
SCHEME = {"kind": "TS", "osi": "MoreauJeanOSI", "theta": 0.5, "h": 0.005,
          "problem": "FrictionContact"}
SCHEME_TEXT = ("TimeStepping + MoreauJeanOSI(theta 0.5), FrictionContact(2) with its default "
               "solver, NewtonImpactFrictionNSL, h = 0.005")


def steps(base):
    return time_steps(base, (4.0, 1.0, 0.1, 0.01))


def spec(model):
    """The example's disk: a LagrangianLinearTIDS (x, y, theta), mass diag(m, m, I), its weight
    -m g along x. Its contact is the example's Lagrangian2d2DR (C++ only) written as the
    LagrangianLinearTIR with the same two rows: the normal (1, 0, 0) with offset -R, and the
    tangent (0, 1, -R) (the contact point's velocity along the ground, the file's slip)."""
    p = model["params"]
    ds = {"kind": "linear", "coords": ["x", "y", "theta"], "q0": model["q0"], "v0": model["v0"],
          "mass": [[p["m"], 0.0, 0.0], [0.0, p["m"], 0.0], [0.0, 0.0, p["I"]]],
          "fext": [-p["m"] * p["g"], 0.0, 0.0]}
    (c,) = model["constraints"]
    return {"t_end": model["t_end"], "ds": [ds],
            "interactions": [{"name": c["name"], "e": c["e"], "ds": [0],
                              "friction": friction_law(model, c["name"]),
                              "relation": frictional_relation(model, c["name"],
                                                              ds["coords"])}],
            "stick_velocity": 1e-9}


DISCUSSION = """The disk sticks at its first impact (the cone admits the tangential impulse 2/7 that stops
its slip), then bounces like a frictionless ball while it rolls. zenosim has that impulse to
rounding and no tangential impulse after it; its first ten impact times agree with the closed
form to 4e-15, but deep in the sequence they drift to 1.1e-9 s at its 128th impact and its Zeno
time is 2e-9 off, the same at every tolerance: the gap x - R is computed from x near R = 0.5,
whose rounding (1e-16) moves a landing at speed v by about 1e-16/v (v = 4.8e-6 there). It is
rounding, not the tolerance (the frictionless balls' gap, y near 0, has no such floor). Its
state at t_end, rolling at y_dot = 2/7, theta_dot = 4/7, is exact to 1e-14. Siconos's
Moreau-Jean run sticks at the first impact too and rolls at exactly 2/7 and 4/7; as for the
frictionless ball its impacts are O(h): 40 of the 323 at the example's h = 0.005 (the first ten
within 0.03 s), its Zeno estimate 0.051 s off, and its state at t_end 4.6e-3 off (the roll starts
at the end of the landing's step, 5.7e-3 s late, and the disk rests 4e-5 inside the ground); at
h = 5e-5, 86 impacts within 5e-4 s and 7e-5. The closed form sides with zenosim. Wall time:
0.6 ms against 15 ms at the example's step (3.9 s at 5e-5)."""
