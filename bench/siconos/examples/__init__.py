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
    "bouncing-ball-ts": "bouncing_ball_ts",
    "column-of-beads": "column_of_beads",
    "double-pendulum": "double_pendulum",
    "rocking-block": "rocking_block",
    "ball-on-moving-plane": "ball_on_moving_plane",
    "linear-oscillator": "linear_oscillator",
    "slider-crank": "slider_crank",
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
