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
    "ball2d-friction": "ball2d_friction",
    "impacting-stick": "impacting_stick",
    "friction-oscillator": "friction_oscillator",
    "two-dofs-friction-oscillator": "two_dofs_friction_oscillator",
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


def friction_law(model, name):
    """The NewtonImpactFrictionNSL parameters of the file's constraint `name`: Coulomb's
    coefficient (one: Siconos has no static one) and no tangential restitution."""
    c = constraint(model, name)
    return {"mu": c["mu_kinetic"], "et": 0.0}


def frictional_relation(model, name, coords, t=0.0):
    """The file's constraint `name` with friction, linear in q with a constant slip row, as
    Siconos's two-row LagrangianLinearTIR: the normal row C q + offset as linear_relation reads
    it, then the slip row S (ds/dv, read off the file's slip formula) with no offset."""
    import suite
    normal = linear_relation(model, name, coords, t)
    n = len(model["coordinates"])
    rows, _ = suite.file_slip_row(model, t, [0.0] * n)
    slip = [rows[name][model["coordinates"].index(c)] for c in coords]
    return {"kind": "linear", "C": [normal["C"][0], slip], "offset": [normal["offset"][0], 0.0]}


def normal_force(model, name):
    """The normal force of the file's constraint `name` on a body at rest on it at the initial
    state, its coordinate decoupled from the others (a height held at 0 under a weight): minus
    the file's force along that coordinate."""
    import suite
    n = len(model["coordinates"])
    zero = [0.0] * n
    jac = suite.file_jac(model, 0.0, model["q0"])[name]
    (k,) = [i for i, a in enumerate(jac) if a != 0.0]
    _, force = suite.file_dynamics(model, 0.0, model["q0"], zero)
    return -force[k] / jac[k]


def check_first_order_relay(model, spec, plugins, states=6):
    """A first-order relay port (Siconos's M x' = A x + b(t) + B lambda, RelayNSL(1, lb, ub) on
    y = C x) against the file, whose slipping contact carries the normal force of a weight on
    a floor: at a few states (the floor's coordinate held at 0, the others random around the
    initial state, slipping either way) x' against the file's motion with the kinetic friction
    force -mu N sign(s) along its slip row (lambda = lb where s > 0, ub where s < 0, Siconos's
    relay), y = C x against the file's slip, the initial state, and no coupling between the held
    coordinate and the others in the mass matrix. The largest differences, relative."""
    import random

    import suite
    rng = random.Random(3)
    coords = model["coordinates"]
    n = len(coords)
    (d,) = spec["ds"]
    (it,) = spec["interactions"]
    c = constraint(model, it["name"])
    if c["mu_static"] != c["mu_kinetic"]:
        raise ValueError(f"{model['name']}: the relay has one bound")
    held = [k for k in range(n) if d["positions"][k] is None]
    free = [k for k in range(n) if d["positions"][k] is not None]
    size = len(d["x0"])
    A, C = d["A"], it["relation"]["C"][0]
    B = [row[0] for row in it["relation"]["B"]]
    M = d.get("M") or [[float(i == j) for j in range(size)] for i in range(size)]
    lb, ub = it["relay"]
    N = normal_force(model, it["name"])
    worst = {"dynamics": 0.0, "slip": 0.0, "initial": 0.0, "coupling": 0.0}
    for s in range(states):
        t = model["t_end"] * rng.random() if s else 0.0
        q, v = list(model["q0"]), list(model["v0"])
        for k in free:
            if s:
                q[k] += rng.uniform(-2, 2)
                v[k] += rng.uniform(-2, 2)
        for k in held:
            q[k], v[k] = 0.0, 0.0
        slip = suite.file_slip(model, t, q, v)[it["name"]]
        rows, _ = suite.file_slip_row(model, t, q)
        srow = rows[it["name"]]
        mass, force = suite.file_dynamics(model, t, q, v)
        for i in held:
            for j in free:
                worst["coupling"] = max(worst["coupling"],
                                        abs(mass[i][j]) / max(abs(mass[i][i]), 1e-300))
        ft = -c["mu_kinetic"] * N * (1.0 if slip > 0 else -1.0)
        gen = [force[k] + srow[k] * ft for k in range(n)]
        # the file's accelerations of the free coordinates: M_ff a = F_f + S_f ft
        mff = [[mass[i][j] for j in free] for i in free]
        acc = _solve(mff, [gen[k] for k in free])
        x = [0.0] * size
        for k in free:
            x[d["positions"][k]] = q[k]
            x[d["velocities"][k]] = v[k]
        lam = lb if slip > 0 else ub
        b = plugins.call(d["b"]["plugin"], d["b"]["function"], "b", t=t, out_size=size) \
            if d.get("b") else [0.0] * size
        rhs = [sum(A[i][j] * x[j] for j in range(size)) + b[i] + B[i] * lam for i in range(size)]
        xdot = _solve(M, rhs)
        scale = max([abs(a) for a in acc] + [abs(v[k]) for k in free] + [1.0])
        for u, k in enumerate(free):
            worst["dynamics"] = max(worst["dynamics"],
                                    abs(xdot[d["positions"][k]] - v[k]) / scale,
                                    abs(xdot[d["velocities"][k]] - acc[u]) / scale)
        worst["slip"] = max(worst["slip"], abs(slip - sum(a * b for a, b in zip(C, x)))
                            / max(abs(slip), 1.0))
    for k in free:
        worst["initial"] = max(worst["initial"], abs(d["x0"][d["positions"][k]] - model["q0"][k]),
                               abs(d["x0"][d["velocities"][k]] - model["v0"][k]))
    for k in held:
        worst["initial"] = max(worst["initial"], abs(model["q0"][k]), abs(model["v0"][k]))
    worst["initial"] = max(worst["initial"],
                           abs(suite.file_h(model, 0.0, model["q0"])[it["name"]]))
    return worst


def _solve(a, b):
    """a x = b for a small dense a (Gaussian elimination with partial pivoting)."""
    n = len(b)
    m = [list(map(float, row)) + [float(b[i])] for i, row in enumerate(a)]
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(m[r][col]))
        m[col], m[piv] = m[piv], m[col]
        for r in range(n):
            if r != col and m[r][col] != 0.0:
                f = m[r][col] / m[col][col]
                m[r] = [x - f * y for x, y in zip(m[r], m[col])]
    return [m[i][n] / m[i][i] for i in range(n)]
