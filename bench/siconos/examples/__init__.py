"""One module per Siconos example: how Siconos runs it (the example's scheme) and the Siconos
model written from the model file models/siconos/<name>.toml. Each module has

  EXAMPLE      the example's file in siconos-tutorials (examples/mechanics/...)
  SCHEME       the example's scheme: {"kind": "ED", "h"} (EventDriven + LsodarOSI, the step of
               its TimeDiscretisation) or {"kind": "TS", "osi", "theta", "h", ...}
  SCHEME_TEXT  the same in words, for the table
  steps(base)  (time-stepping) the step sizes run: the example's and others
  spec(model)  the Siconos model (siconos_side.py's spec) with every number from the file
  DISCUSSION   the paragraph under the example's table: where the tools differ and why

and, for a model with a body whose motion is prescribed (not a coordinate of the file),
driven_value(model, spec, ds, dof, t, x) and check_extra(model, spec, plugins).
"""

# model name (models/siconos/<name>.toml) -> module
EXAMPLES = {
    "bouncing-ball-ed": "bouncing_ball_ed",
    "bouncing-ball-ed-two-contacts": "bouncing_ball_ed_two_contacts",
    "bouncing-ball-ed-resting-contact": "bouncing_ball_ed_resting_contact",
    "bouncing-ball-ts": "bouncing_ball_ts",
    "column-of-beads-ts": "column_of_beads_ts",
    "bead-column-ed-newton": "bead_column_ed_newton",
    "double-pendulum-ts": "double_pendulum_ts",
    "rocking-block-ed": "rocking_block_ed",
    "ball-on-moving-plane": "ball_on_moving_plane",
    "linear-oscillator-ed": "linear_oscillator_ed",
    "slider-crank-d1minus": "slider_crank_d1minus",
    "slider-crank-d1minus-velocity": "slider_crank_d1minus_velocity",
    "impacting-bar": "impacting_bar",
}


def time_steps(base, factors=(4.0, 1.0, 0.25)):
    """The example's step times each factor."""
    return [base["h"] * f for f in factors]


def single(model, name):
    """The one coordinate called name, or the file's only coordinate."""
    cs = model["coordinates"]
    if name in cs:
        return name
    if len(cs) == 1:
        return cs[0]
    raise ValueError(f"{model['name']}: no coordinate {name!r} in {cs}")


def linear_relation(model, name, coords, t=0.0):
    """The file's constraint `name`, linear in q, as Siconos's LagrangianLinearTIR(C, offset)
    over the dofs coords (file coordinates, in the order of the Siconos DSs): offset = h(0),
    C_j = h(e_j) - h(0), read off the file's formula (suite.py then checks h and dh/dq at
    other states, which catches a constraint that is not linear)."""
    import suite
    n = len(model["coordinates"])
    zero = [0.0] * n
    h0 = suite.file_h(model, t, zero)[name]
    row = []
    for c in coords:
        q = list(zero)
        q[model["coordinates"].index(c)] = 1.0
        row.append(suite.file_h(model, t, q)[name] - h0)
    return {"kind": "linear", "C": [row], "offset": [h0]}


def constraint(model, name):
    for c in model["constraints"]:
        if c["name"] == name:
            return c
    raise ValueError(f"{model['name']}: no constraint {name!r}")


def ball(model, stiffness=None):
    """The examples' ball as Siconos writes it: a LagrangianLinearTIDS with three dofs (height
    y, horizontal x, rotation theta), mass diag(m, m, I), weight -m g on y, and, for the linear
    oscillator, springs diag(kx, ky, 0): every number from the file's parameters."""
    p = model["params"]
    d = {"kind": "linear", "coords": ["y", "x", "theta"],
         "q0": [model["q0"][model["coordinates"].index(c)] for c in ("y", "x", "theta")],
         "v0": [model["v0"][model["coordinates"].index(c)] for c in ("y", "x", "theta")],
         "mass": [[p["m"], 0.0, 0.0], [0.0, p["m"], 0.0], [0.0, 0.0, p["I"]]],
         "fext": [-p["m"] * p["g"], 0.0, 0.0]}
    if stiffness is not None:
        d["K"] = [[stiffness[0], 0.0, 0.0], [0.0, stiffness[1], 0.0], [0.0, 0.0, 0.0]]
    return d


def one_body(model, ds):
    """A spec with one DS and a LagrangianLinearTIR per constraint of the file."""
    return {"t_end": model["t_end"], "ds": [ds],
            "interactions": [{"name": c["name"], "e": c["e"], "ds": [0],
                              "relation": linear_relation(model, c["name"], ds["coords"])}
                             for c in model["constraints"]]}


def beads(model):
    """The columns of beads as the examples write them: one LagrangianLinearTIDS per bead (its
    height; mass m and weight -m g from the file), and per constraint a LagrangianLinearTIR
    between the one or two beads it involves (a bead and the floor, or two neighbours)."""
    p = model["params"]
    coords = model["coordinates"]
    ds = [{"kind": "linear", "coords": [c], "q0": [model["q0"][i]], "v0": [model["v0"][i]],
           "mass": [[p["m"]]], "fext": [-p["m"] * p["g"]]} for i, c in enumerate(coords)]
    inters = []
    for c in model["constraints"]:
        full = linear_relation(model, c["name"], coords)
        involved = [i for i, a in enumerate(full["C"][0]) if a != 0.0]
        if not 1 <= len(involved) <= 2:
            raise ValueError(f"{model['name']}: {c['name']} involves {len(involved)} beads")
        inters.append({"name": c["name"], "e": c["e"], "ds": involved,
                       "relation": linear_relation(model, c["name"],
                                                   [coords[i] for i in involved])})
    return {"t_end": model["t_end"], "ds": ds, "interactions": inters}
