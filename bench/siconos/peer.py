#!/usr/bin/env python3
"""zenosim against Siconos's event-driven scheme on three multi-contact models.

Run it through bench/siconos/run (which installs Debian's python3-siconos if it is missing and
builds zenosim), or directly with the system python (Siconos is a Debian package for it):

    /usr/bin/python3 bench/siconos/peer.py --zenosim target/release/zenosim
    /usr/bin/python3 bench/siconos/peer.py --help

The models (read from models/*.toml with tomllib; every number comes from the file):
  corner          a point mass in a right-angled corner: two independent bouncing balls,
                  two Zeno points, then at rest in the corner (closed forms for every impact);
  floor-and-wall  a point mass sliding on a floor into a wall: one impact while the floor holds;
  rocking-block   a block rocking on its two corners (nonlinear constraints), e = 0: every
                  impact multiplies theta_dot by (I - m b^2)/(I + m b^2); it comes to rest flat.

Siconos: written by hand from the model file, as a careful Siconos user would, and checked
against the file's formulas before any run (mass matrix, forces, constraints, Jacobians):
  * LagrangianLinearTIDS (corner, floor-and-wall) or LagrangianDS with constant mass (the
    block), external force = gravity;
  * one Interaction per constraint: NewtonImpactNSL(e of that constraint) with a
    LagrangianLinearTIR (straight walls) or a LagrangianScleronomousR whose h, dh/dq and
    d/dt(dh/dq) are C plugins (the block's corners, rocking_block_plugin.c);
  * EventDriven + LsodarOSI (setTol(1, tol, tol)), impact problem LCP
    (SICONOS_OSNSP_ED_IMPACT), acceleration problem LCP (SICONOS_OSNSP_ED_SMOOTH_ACC);
  * Siconos's event tolerance TOL_ED (EventDriven.setToleranceED): its default (1e4 machine
    epsilons), and, as a second variant, scaled with the integration tolerance.
Each Siconos run is a subprocess with a wall-time limit (--timeout): a run that does not reach
t_end in time is recorded as stalled, with the time it had reached.

zenosim: `zenosim run MODEL --out DIR --rtol tol --atol tol` for the events, Zeno points and
final state (DIR/summary.json), `zenosim bench MODEL --tolerances ...` for the wall times.

Errors, against the closed forms (see reference_* below; the rocking block's impact times and
Zeno time by quadrature of its energy integral):
  impact times   per contact, the k-th impact of the tool against the k-th of the reference,
                 max |t - t_ref| / t_ref over the impacts the tool reported, and over its
                 first FIRST_IMPACTS impacts alone;
  Zeno times     |t_est - t_ref|; zenosim's estimate is its t_zeno, Siconos's the time of the
                 last impact on that contact (it has no Zeno estimate of its own), counted only
                 if the run ends at rest on that contact;
  final state    max-norm of (q, q_dot) - reference at t_end;
  rocking block  max |theta_dot+/theta_dot- - (I - m b^2)/(I + m b^2)| over the impacts with
                 |theta_dot-| >= 1e-6, and the rest state theta = 0, y = c.
"""

import argparse
import ast
import datetime
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

MODELS = ["corner", "floor-and-wall", "rocking-block"]
TOLERANCES = [1e-6, 1e-8, 1e-10, 1e-12]
# Siconos's TOL_ED variants: "default" leaves Siconos's value; "scaled" sets TOL_ED = factor * tol
# (a gap or a velocity below TOL_ED counts as zero: the integration error must stay under it).
TOLED_SCALE = 1.0
# A contact is at rest at t_end when |h| and |h_dot| are both below this.
REST = 1e-5
# The rocking block's ratio is checked on the impacts with |theta_dot-| at least this.
RATIO_MIN_SPEED = 1e-6
# The impact-time error is also given over the first few impacts alone.
FIRST_IMPACTS = 10
# Events of a Siconos run kept in full in results.json (the counts are always exact).
KEEP_EVENTS = 5000
# A Siconos run stops as stalled after this many events even within its wall-time limit.
MAX_SICONOS_EVENTS = 200000


def log(*parts):
    print(*parts, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# The model files: formulas evaluated the way zenosim reads them.

FUNCTIONS = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos,
    "atan": math.atan, "atan2": math.atan2, "sinh": math.sinh, "cosh": math.cosh,
    "tanh": math.tanh, "exp": math.exp, "ln": math.log, "log": math.log, "sqrt": math.sqrt,
    "abs": abs, "pow": math.pow, "min": min, "max": max,
}
CONSTANTS = {"pi": math.pi}


class Formula:
    """A formula of the model file (numbers, names, pi, + - * / ^ and the functions above),
    parsed once ('^' is the power, as in zenosim) and evaluated with a dict of names."""

    def __init__(self, text):
        self.text = str(text)
        self.tree = ast.parse(self.text.replace("^", "**"), mode="eval").body
        self.names = {n.id for n in ast.walk(self.tree) if isinstance(n, ast.Name)}
        self._check(self.tree)

    def _check(self, node):
        allowed = (ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Constant, ast.Load,
                   ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)
        for n in ast.walk(node):
            if not isinstance(n, allowed):
                raise ValueError(f"unsupported syntax in formula {self.text!r}")
            if isinstance(n, ast.Call) and not (isinstance(n.func, ast.Name)
                                                and n.func.id in FUNCTIONS):
                raise ValueError(f"unknown function in formula {self.text!r}")

    def __call__(self, env):
        return float(self._eval(self.tree, env))

    def _eval(self, n, env):
        if isinstance(n, ast.Constant):
            return n.value
        if isinstance(n, ast.Name):
            if n.id in env:
                return env[n.id]
            if n.id in CONSTANTS:
                return CONSTANTS[n.id]
            raise KeyError(f"unknown name {n.id!r} in formula {self.text!r}")
        if isinstance(n, ast.UnaryOp):
            v = self._eval(n.operand, env)
            return -v if isinstance(n.op, ast.USub) else v
        if isinstance(n, ast.BinOp):
            a, b = self._eval(n.left, env), self._eval(n.right, env)
            op = type(n.op)
            if op is ast.Add:
                return a + b
            if op is ast.Sub:
                return a - b
            if op is ast.Mult:
                return a * b
            if op is ast.Div:
                return a / b
            return a ** b
        if isinstance(n, ast.Call):
            return FUNCTIONS[n.func.id](*[self._eval(a, env) for a in n.args])
        raise ValueError(f"unsupported syntax in formula {self.text!r}")


def load_model(name):
    """The model file read with tomllib: parameters and initial values evaluated, constraints,
    restitutions and t_end; the Lagrangian and the h's kept as formulas."""
    path = os.path.join(ROOT, "models", f"{name}.toml")
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    coords = list(doc["coordinates"])
    raw = dict(doc.get("parameters", {}))
    params, pending = {}, dict(raw)
    while pending:  # parameters may be formulas of other parameters
        progress = False
        for k, v in list(pending.items()):
            if isinstance(v, (int, float)):
                params[k] = float(v)
            else:
                f = Formula(v)
                if not f.names <= set(params) | set(CONSTANTS):
                    continue
                params[k] = f(params)
            del pending[k]
            progress = True
        if not progress:
            raise ValueError(f"{path}: parameters that cannot be evaluated: {sorted(pending)}")
    init = doc.get("initial", {})

    def value(v):
        return float(v) if isinstance(v, (int, float)) else Formula(v)(params)

    q0 = [value(init.get(c, 0.0)) for c in coords]
    v0 = [value(init.get(c + "_dot", 0.0)) for c in coords]
    constraints = []
    for c in doc.get("constraint", []):
        constraints.append({"name": c["name"], "h": Formula(c["h"]),
                            "e": value(c.get("restitution", 0.0))})
    sim = doc.get("simulation", {})
    return {"name": name, "path": path, "coordinates": coords, "params": params,
            "q0": q0, "v0": v0, "constraints": constraints,
            "lagrangian": Formula(doc["lagrangian"]), "t_end": float(sim.get("t_end", 10.0))}


def env_of(model, q, v=None):
    env = dict(model["params"])
    for i, c in enumerate(model["coordinates"]):
        env[c] = q[i]
        env[c + "_dot"] = 0.0 if v is None else v[i]
    return env


def h_values(model, q):
    env = env_of(model, q)
    return {c["name"]: c["h"](env) for c in model["constraints"]}


def h_jacobian(model, q, step=1e-6):
    """dh/dq of every constraint by central differences of the file's formulas."""
    jac = {c["name"]: [] for c in model["constraints"]}
    for i in range(len(q)):
        qp, qm = list(q), list(q)
        qp[i] += step
        qm[i] -= step
        hp, hm = h_values(model, qp), h_values(model, qm)
        for k in jac:
            jac[k].append((hp[k] - hm[k]) / (2 * step))
    return jac


def normal_velocities(model, q, v):
    jac = h_jacobian(model, q)
    return {k: sum(a * b for a, b in zip(row, v)) for k, row in jac.items()}


# --------------------------------------------------------------------------------------------
# The Siconos models, written by hand from the files, and their check against the files.

def siconos_spec(model):
    """What the Siconos child builds: the dynamical system and one interaction per constraint,
    with every number taken from the model file."""
    p, name = model["params"], model["name"]
    n = len(model["coordinates"])
    if name == "corner":
        m = p["m"]
        ds = {"type": "LagrangianLinearTIDS", "mass": [[m, 0.0], [0.0, m]],
              "fext": [-m * p["gx"], -m * p["gy"]]}
        hand = {"wall": {"kind": "linear", "C": [1.0, 0.0], "offset": 0.0},
                "floor": {"kind": "linear", "C": [0.0, 1.0], "offset": 0.0}}
    elif name == "floor-and-wall":
        m = p["m"]
        ds = {"type": "LagrangianLinearTIDS", "mass": [[m, 0.0], [0.0, m]],
              "fext": [0.0, -m * p["g"]]}
        hand = {"floor": {"kind": "linear", "C": [0.0, 1.0], "offset": 0.0},
                "wall": {"kind": "linear", "C": [-1.0, 0.0], "offset": p["d"]}}
    elif name == "rocking-block":
        m, inertia = p["m"], p["I"]
        ds = {"type": "LagrangianDS", "mass": [[m, 0, 0], [0, m, 0], [0, 0, inertia]],
              "fext": [0.0, -m * p["g"], 0.0], "z": [p["b"], p["c"]]}
        hand = {"left": {"kind": "plugin", "prefix": "left", "sign": -1.0},
                "right": {"kind": "plugin", "prefix": "right", "sign": 1.0}}
    else:
        raise ValueError(f"no Siconos model written for {name}")
    contacts = []
    for c in model["constraints"]:
        if c["name"] not in hand:
            raise ValueError(f"{name}: constraint {c['name']!r} has no Siconos counterpart")
        contacts.append(dict(hand[c["name"]], name=c["name"], e=c["e"]))
    if len(contacts) != len(hand):
        raise ValueError(f"{name}: the file's constraints are not the hand-written ones")
    assert len(ds["mass"]) == n
    return {"model": name, "t_end": model["t_end"], "q0": model["q0"], "v0": model["v0"],
            "ds": ds, "contacts": contacts}


def hand_h(spec, contact, q):
    """The hand-written h (what Siconos is given) evaluated in Python, and its gradient."""
    if contact["kind"] == "linear":
        h = sum(a * b for a, b in zip(contact["C"], q)) + contact["offset"]
        return h, list(contact["C"])
    b, c = spec["ds"]["z"]
    s, th = contact["sign"], q[2]
    h = q[1] + s * b * math.sin(th) - c * math.cos(th)
    return h, [0.0, 1.0, s * b * math.cos(th) + c * math.sin(th)]


def check_spec(model, spec):
    """The hand-written Siconos model against the file: M and the forces from the Lagrangian's
    formula (central differences: exact for these quadratic kinetic energies and linear
    potentials up to rounding), the constraints and their gradients at a few states.
    Returns the largest discrepancy of each; raises if one is not at rounding level."""
    import random
    rng = random.Random(1)
    n = len(model["coordinates"])
    lag = model["lagrangian"]
    worst = {"mass": 0.0, "force": 0.0, "h": 0.0, "dh_dq": 0.0}
    for _ in range(5):
        q = [rng.uniform(-0.3, 0.3) for _ in range(n)]
        d = 1e-3
        for i in range(n):
            for j in range(n):
                def L_at(di, dj):
                    v = [0.0] * n
                    v[i] += di
                    v[j] += dj
                    return lag(env_of(model, q, v))
                mij = (L_at(d, d) - L_at(d, -d) - L_at(-d, d) + L_at(-d, -d)) / (4 * d * d)
                worst["mass"] = max(worst["mass"], abs(mij - spec["ds"]["mass"][i][j]))
            qp, qm = list(q), list(q)
            qp[i] += d
            qm[i] -= d
            fi = (lag(env_of(model, qp)) - lag(env_of(model, qm))) / (2 * d)
            worst["force"] = max(worst["force"], abs(fi - spec["ds"]["fext"][i]))
        file_h = h_values(model, q)
        file_j = h_jacobian(model, q)
        for c in spec["contacts"]:
            h, grad = hand_h(spec, c, q)
            worst["h"] = max(worst["h"], abs(h - file_h[c["name"]]))
            worst["dh_dq"] = max(worst["dh_dq"],
                                 max(abs(a - b) for a, b in zip(grad, file_j[c["name"]])))
    limits = {"mass": 1e-6, "force": 1e-6, "h": 1e-12, "dh_dq": 1e-7}
    bad = {k: v for k, v in worst.items() if v > limits[k]}
    if bad:
        raise ValueError(f"{model['name']}: the hand-written Siconos model does not match the "
                         f"file: {bad}")
    return worst


# --------------------------------------------------------------------------------------------
# References (closed forms; the rocking block's impact times by quadrature).

def bouncing_times(t1, e, count=400):
    """Impact times of a ball dropped from rest with first impact t1: t1 (1 + 2e(1 - e^(k-1))/(1 - e))."""
    out = []
    for k in range(1, count + 1):
        t = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        if out and t - out[-1] <= 0:
            break
        out.append(t)
    return out


def reference_corner(model):
    p = model["params"]
    (x0, y0) = model["q0"]
    e = {c["name"]: c["e"] for c in model["constraints"]}
    tx1, ty1 = math.sqrt(2 * x0 / p["gx"]), math.sqrt(2 * y0 / p["gy"])
    impacts = ([{"t": t, "contact": "floor"} for t in bouncing_times(ty1, e["floor"])]
               + [{"t": t, "contact": "wall"} for t in bouncing_times(tx1, e["wall"])])
    impacts.sort(key=lambda i: i["t"])
    zeno = [{"contacts": ["floor"], "t": ty1 * (1 + e["floor"]) / (1 - e["floor"])},
            {"contacts": ["wall"], "t": tx1 * (1 + e["wall"]) / (1 - e["wall"])}]
    return {"impacts": impacts, "zeno": zeno, "final_q": [0.0, 0.0], "final_v": [0.0, 0.0],
            "rest": ["floor", "wall"],
            "formulas": "floor: ty1 (1 + 2 ey (1 - ey^(k-1))/(1 - ey)), ty1 = sqrt(2 y0/gy), "
                        "Zeno ty1 (1+ey)/(1-ey); wall: the same with x, gx, ex"}


def reference_floor_and_wall(model):
    p = model["params"]
    x0, v0 = model["q0"][0], model["v0"][0]
    e_wall = {c["name"]: c["e"] for c in model["constraints"]}["wall"]
    tw = (p["d"] - x0) / v0
    t_end = model["t_end"]
    x_end = p["d"] - e_wall * v0 * (t_end - tw)
    return {"impacts": [{"t": tw, "contact": "wall"}], "zeno": [],
            "final_q": [x_end, 0.0], "final_v": [-e_wall * v0, 0.0], "rest": ["floor"],
            "formulas": "wall impact at (d - x0)/v0, then x = d - e v0 (t - t_wall) on the floor"}


def gauss_legendre(n):
    import numpy as np
    x, w = np.polynomial.legendre.leggauss(n)
    return [(0.5 * (xi + 1), 0.5 * wi) for xi, wi in zip(x, w)]


def reference_rocking_block(model):
    """The block pivots on one corner (frictionless floor: x stays put), y = b sin|th| + c cos|th|.
    With M(th) = m (b cos th - c sin th)^2 + I and V(th) = m g (b sin th + c cos th), the time from
    th = 0 to the apex a (or back) is T(a) = int_0^a sqrt(M / (2 (V(a) - V(th)))) dth (Gauss-
    Legendre after th = a (1 - w^2), which removes the square-root singularity; V(a) - V(th)
    written without cancellation). The first impact is at T(th0); each impact multiplies th_dot
    by r = (I - m b^2)/(I + m b^2), and the next comes 2 T(a_k) later, a_k the apex reached at
    the speed left."""
    p = model["params"]
    m, g, b, c, inertia = p["m"], p["g"], p["b"], p["c"], p["I"]
    th0 = model["q0"][model["coordinates"].index("theta")]
    r = (inertia - m * b * b) / (inertia + m * b * b)
    nodes = gauss_legendre(120)

    def mass(th):
        return m * (b * math.cos(th) - c * math.sin(th)) ** 2 + inertia

    def dv(a, d):  # V(a) - V(a - d), written without cancellation
        s = a - d / 2  # (a + th)/2
        return 2 * m * g * math.sin(d / 2) * (b * math.cos(s) - c * math.sin(s))

    def half_rock(a):
        total = 0.0
        for w, wt in nodes:
            d = a * w * w  # a - th, exact even where w is small
            total += wt * math.sqrt(mass(a - d) / (2 * dv(a, d))) * 2 * a * w
        return total

    def apex(energy):  # solve V(a) - V(0) = energy
        a = energy / (m * g * b)
        for _ in range(100):
            f = m * g * (b * math.sin(a) - 2 * c * math.sin(a / 2) ** 2) - energy
            df = m * g * (b * math.cos(a) - c * math.sin(a))
            step = f / df
            a -= step
            if abs(step) <= 1e-16 * abs(a):
                break
        return a

    m0 = mass(0.0)
    speed = math.sqrt(2 * dv(th0, th0) / m0)  # |theta_dot| just before the first impact
    t = half_rock(th0)
    impacts, side = [], "right"  # theta > 0 rests on the left corner: the right one lands
    for _ in range(200):
        impacts.append({"t": t, "contact": side, "theta_dot_before": speed})
        speed *= r
        dt = 2 * half_rock(apex(0.5 * m0 * speed * speed))
        if dt <= 1e-17 * t:
            break
        t += dt
        side = "left" if side == "right" else "right"
    # what is left after the last term is below rounding
    qf = list(model["q0"])
    qf[model["coordinates"].index("theta")] = 0.0
    qf[model["coordinates"].index("y")] = c
    return {"impacts": impacts, "zeno": [{"contacts": ["left", "right"], "t": t}],
            "final_q": qf, "final_v": [0.0] * len(qf), "rest": ["left", "right"],
            "ratio": r,
            "formulas": "theta_dot+/theta_dot- = (I - m b^2)/(I + m b^2); impact times and "
                        "the Zeno time by quadrature of the energy integral (Gauss-Legendre, "
                        "120 nodes); rest theta = 0, y = c"}


REFERENCES = {"corner": reference_corner, "floor-and-wall": reference_floor_and_wall,
              "rocking-block": reference_rocking_block}


# --------------------------------------------------------------------------------------------
# The Siconos child: one run (and its timing repeats) in its own process.

def siconos_version():
    out = {}
    try:
        out["debian_package"] = subprocess.run(
            ["dpkg-query", "-W", "-f", "${Version}", "python3-siconos"],
            capture_output=True, text=True).stdout.strip() or None
    except OSError:
        out["debian_package"] = None
    try:
        import siconos
        out["python_module"] = getattr(siconos, "version", None)
    except ImportError:
        out["python_module"] = None
    return out


def default_tol_ed(sk):
    """Siconos's TOL_ED as it is in a fresh process (a static of EventDriven, read through an
    instance)."""
    nsds = sk.NonSmoothDynamicalSystem(0.0, 1.0)
    return sk.EventDriven(nsds, sk.TimeDiscretisation(0.0, 1.0)).toleranceED()


def siconos_build(sk, spec, plugin_lib, tol, toled):
    import numpy as np
    t_end = spec["t_end"]
    d = spec["ds"]
    if d["type"] == "LagrangianLinearTIDS":
        ds = sk.LagrangianLinearTIDS(spec["q0"], spec["v0"], np.array(d["mass"], dtype=float))
    else:
        ds = sk.LagrangianDS(spec["q0"], spec["v0"], np.array(d["mass"], dtype=float))
    ds.setFExtPtr(np.array(d["fext"], dtype=float))
    if "z" in d:
        ds.setzPtr(np.array(d["z"], dtype=float))
    nsds = sk.NonSmoothDynamicalSystem(0.0, t_end)
    nsds.insertDynamicalSystem(ds)
    inters = []
    for c in spec["contacts"]:
        if c["kind"] == "linear":
            rel = sk.LagrangianLinearTIR(np.array([c["C"]], dtype=float),
                                         np.array([c["offset"]], dtype=float))
        else:
            pre = f"{plugin_lib}:{c['prefix']}"
            rel = sk.LagrangianScleronomousR(pre + "_h", pre + "_G0", pre + "_dotG0")
        inter = sk.Interaction(sk.NewtonImpactNSL(c["e"]), rel)
        nsds.link(inter, ds)
        inters.append((c["name"], inter))
    # Time events only at 0 and t_end: the integrator runs from event to event by itself.
    sim = sk.EventDriven(nsds, sk.TimeDiscretisation(0.0, t_end))
    osi = sk.LsodarOSI()
    osi.setTol(1, tol, tol)
    sim.insertIntegrator(osi)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
    sim.setToleranceED(toled)  # a static of EventDriven: set on every run
    return ds, inters, sim


def siconos_once(sk, spec, plugin_lib, tol, toled, progress_path=None, keep=True):
    import numpy as np
    t_end = spec["t_end"]
    start = time.perf_counter()
    ds, inters, sim = siconos_build(sk, spec, plugin_lib, tol, toled)
    status, reason, stage = "finished", None, "initialize"
    events, n_ns, n_td, n_impacts = [], 0, 0, 0
    last_progress = start - 1.0  # the first report comes after the first event
    try:
        sim.initialize()
        em = sim.eventsManager()
        while sim.hasNextEvent() and sim.startingTime() < t_end * (1 - 1e-14):
            stage = "advanceToEvent"
            sim.advanceToEvent()
            nonsmooth = em.nextEvent().getType() == sk.NS_EVENT
            stage = "processEvents"
            sim.processEvents()
            if nonsmooth:
                n_ns += 1
                impulses = {name: float(it.lambda_(1)[0]) for name, it in inters}
                if any(v > 0 for v in impulses.values()):
                    n_impacts += 1
                if keep and len(events) < KEEP_EVENTS:
                    events.append({
                        "t": sim.startingTime(),
                        "q": list(np.array(ds.qMemory().getSiconosVector(1))),
                        "v_before": list(np.array(ds.velocityMemory().getSiconosVector(1))),
                        "v_after": list(np.array(ds.velocity())),
                        "impulse": impulses})
            else:
                n_td += 1
            if n_ns >= MAX_SICONOS_EVENTS:
                status, reason = "stalled", f"{n_ns} non-smooth events (the cap)"
                break
            now = time.perf_counter()
            if progress_path and now - last_progress > 0.25:
                last_progress = now
                with open(progress_path, "w") as f:
                    json.dump({"t": sim.startingTime(), "ns_events": n_ns}, f)
        if status == "finished" and sim.startingTime() < t_end * (1 - 1e-12):
            status, reason = "failed", "no event left before t_end"
    except Exception as ex:  # Siconos throws std::exception with its text on stdout
        status, reason = "failed", f"{type(ex).__name__} '{ex}' in {stage}"
    wall = time.perf_counter() - start
    active2 = []
    try:
        for inter in sim.indexSet(2).interactions():
            active2.append(inter.number())
    except Exception:
        active2 = None
    names_by_number = {it.number(): name for name, it in inters}
    return {
        "status": status, "reason": reason, "t_reached": sim.startingTime(),
        "ns_events": n_ns, "td_events": n_td, "impacts_with_impulse": n_impacts,
        "events": events, "events_truncated": n_ns > len(events),
        "final": {"t": sim.startingTime(), "q": list(np.array(ds.q())),
                  "q_dot": list(np.array(ds.velocity())),
                  "contact_force": {name: float(it.lambda_(2)[0]) for name, it in inters},
                  "index_set_2": (None if active2 is None
                                  else sorted(names_by_number.get(k, str(k)) for k in active2))},
        "wall_time_s": wall,
    }


def siconos_child(args):
    with open(args.child) as f:
        job = json.load(f)
    import siconos.kernel as sk
    default_toled = default_tol_ed(sk)
    toled = default_toled if job["toled"] is None else job["toled"]
    run = siconos_once(sk, job["spec"], job["plugin_lib"], job["tol"], toled,
                       progress_path=job["progress"])
    run["toled"] = toled
    run["toled_default"] = default_toled
    # Timing: the same run again (fresh objects), at least 3 times and min_time seconds, when
    # the first one was quick enough.
    times = [run["wall_time_s"]]
    if run["wall_time_s"] < job["repeat_below_s"]:
        timed, begin = [], time.perf_counter()
        while len(timed) < 3 or time.perf_counter() - begin < job["min_time"]:
            timed.append(siconos_once(sk, job["spec"], job["plugin_lib"], job["tol"], toled,
                                      keep=False)["wall_time_s"])
            if len(timed) >= 1000:
                break
        times = timed
    run["wall_time_s"] = {"median": statistics.median(times), "min": min(times),
                          "max": max(times), "repeats": len(times),
                          "first": run["wall_time_s"]}
    with open(job["out"], "w") as f:
        json.dump(run, f)


def siconos_message(text):
    """The informative lines Siconos prints before it throws."""
    keep = []
    for line in text.splitlines():
        s = line.strip()
        if re.search(r"TOL_ED|must be|undetermined|error|Error|exception|failed|Warning", s):
            if s and s not in keep:
                keep.append(s)
    return keep[-5:]


def run_siconos(spec, plugin_lib, tol, toled, args, workdir):
    job_path = os.path.join(workdir, "job.json")
    out_path = os.path.join(workdir, "out.json")
    progress = os.path.join(workdir, "progress.json")
    for p in (out_path, progress):
        if os.path.exists(p):
            os.remove(p)
    with open(job_path, "w") as f:
        json.dump({"spec": spec, "plugin_lib": plugin_lib, "tol": tol, "toled": toled,
                   "out": out_path, "progress": progress, "min_time": args.min_time,
                   "repeat_below_s": args.repeat_below}, f)
    begin = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", job_path],
                              capture_output=True, text=True, timeout=args.timeout)
        timed_out = False
    except subprocess.TimeoutExpired as ex:
        proc, timed_out = ex, True
    elapsed = time.perf_counter() - begin
    stdout = proc.stdout or ""
    stderr = proc.stderr or ""
    if isinstance(stdout, bytes):
        stdout = stdout.decode(errors="replace")
    if isinstance(stderr, bytes):
        stderr = stderr.decode(errors="replace")
    if timed_out or not os.path.exists(out_path):
        reached = None
        if os.path.exists(progress):
            try:
                with open(progress) as f:
                    reached = json.load(f)
            except (OSError, ValueError):
                reached = None
        if timed_out:
            status = "stalled"
            where = (f"at t = {reached['t']:.12g} after {reached['ns_events']} non-smooth events"
                     if reached else "before its first progress report")
            reason = f"no t_end within the {args.timeout:g} s wall-time limit; {where}"
        else:
            status = "crashed"
            rc = getattr(proc, "returncode", None)
            reason = f"the Siconos process ended with status {rc} and no result"
            reached = reached or {}
        return {"status": status, "reason": reason,
                "t_reached": reached.get("t") if reached else None,
                "siconos_output": siconos_message(stdout + "\n" + stderr),
                "stderr_tail": stderr.strip().splitlines()[-3:],
                "wall_time_s": {"median": elapsed, "min": elapsed, "max": elapsed,
                                "repeats": 1, "first": elapsed, "limit_hit": timed_out},
                "toled": toled}
    with open(out_path) as f:
        run = json.load(f)
    run["siconos_output"] = siconos_message(stdout)
    return run


def compile_plugin(workdir):
    src = os.path.join(HERE, "rocking_block_plugin.c")
    lib = os.path.join(workdir, "rocking_block_plugin")
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        return None, "no C compiler (cc) found for the rocking block's Siconos plugin"
    proc = subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", lib + ".so", src, "-lm"],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        return None, f"the plugin did not compile: {proc.stderr.strip()[:500]}"
    # Siconos appends ".so" to the library name it is given.
    return lib, None


# --------------------------------------------------------------------------------------------
# zenosim.

def zenosim_version(zenosim):
    try:
        v = subprocess.run([zenosim, "--version"], capture_output=True, text=True).stdout.strip()
    except OSError:
        v = None
    git = {}
    try:
        git["commit"] = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"],
                                       capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--", "crates"],
                               capture_output=True, text=True).stdout.strip()
        git["uncommitted_engine_changes"] = len(dirty.splitlines()) if dirty else 0
    except OSError:
        pass
    return {"version": v, "git": git}


def run_zenosim(zenosim, model, tol, args, workdir, t_end=None):
    """zenosim run at rtol = atol = tol (to t_end when given, else the file's)."""
    out_dir = os.path.join(workdir, f"zenosim-{model['name']}-{tol:g}"
                           + (f"-to-{t_end:g}" if t_end is not None else ""))
    cmd = [zenosim, "run", model["path"], "--out", out_dir, "--rtol", repr(tol),
           "--atol", repr(tol)] + (["--t-end", repr(t_end)] if t_end is not None else [])
    summary_path = os.path.join(out_dir, "summary.json")
    if os.path.exists(summary_path):
        os.remove(summary_path)
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
        rc, stderr = proc.returncode, proc.stderr
    except subprocess.TimeoutExpired:
        return {"status": "stalled", "reason": f"no result within {args.timeout:g} s",
                "command": " ".join(cmd)}
    if not os.path.exists(summary_path):
        return {"status": "failed", "reason": (stderr or "").strip()[-500:] or f"exit {rc}",
                "exit_status": rc, "command": " ".join(cmd)}
    with open(summary_path) as f:
        summary = json.load(f)
    return {"status": summary.get("status", "unknown"), "reason": summary.get("message"),
            "exit_status": rc, "command": " ".join(cmd), "summary": summary,
            "out_dir": out_dir}


def bench_zenosim(zenosim, model, args):
    cmd = [zenosim, "bench", model["path"], "--tolerances",
           ",".join(repr(t) for t in args.tolerances), "--min-time", repr(args.min_time)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True,
                              timeout=args.timeout * len(args.tolerances) + 60)
    except subprocess.TimeoutExpired:
        return None, "zenosim bench timed out"
    try:
        report = json.loads(proc.stdout)
    except ValueError:
        return None, (proc.stderr or "").strip()[-500:] or f"exit {proc.returncode}"
    return report, None


def event_contacts(ev):
    """The constraint names of a zenosim event or Zeno point: 'contacts' or 'constraints' when
    present (a list of names or of objects with a name), else 'constraint'."""
    names = []
    contacts = ev.get("contacts")
    if not isinstance(contacts, list):
        contacts = ev.get("constraints")
    if isinstance(contacts, list):
        for c in contacts:
            if isinstance(c, str):
                names.append(c)
            elif isinstance(c, dict):
                n = c.get("constraint") or c.get("name")
                if n:
                    names.append(n)
    if not names and ev.get("constraint"):
        c = ev["constraint"]
        names = list(c) if isinstance(c, list) else [c]
    return names


# --------------------------------------------------------------------------------------------
# Metrics, the same for both tools, from a list of impacts (t, q, v_before, v_after).

def impacting(model, q, v_before):
    """The contacts an impact is on: those closed (|h| <= REST) and approaching (h_dot < 0),
    the fastest and any other within a factor 100 of it (a contact held at rest through the
    impact is not one). None: a contact closing at zero speed, no impact."""
    hs = h_values(model, q)
    hd = normal_velocities(model, q, v_before)
    closing = {k: v for k, v in hd.items() if abs(hs[k]) <= REST and v < 0}
    if not closing:
        return []
    fastest = min(closing.values())
    return sorted(k for k, v in closing.items() if v <= 0.01 * fastest)


def metrics(model, ref, impacts, final, zeno_estimates, outcome):
    """impacts: [{t, q, v_before, v_after}]; final: {q, q_dot} or None; zeno_estimates:
    [{contacts, t}] (the tool's own)."""
    null = [imp for imp in impacts if not impacting(model, imp["q"], imp["v_before"])]
    impacts = [imp for imp in impacts if impacting(model, imp["q"], imp["v_before"])]
    out = {"impacts": len(impacts), "null_impacts": [imp["t"] for imp in null]}
    per = {}
    for imp in impacts:
        for c in impacting(model, imp["q"], imp["v_before"]):
            per.setdefault(c, []).append(imp["t"])
    out["impacts_per_contact"] = {k: len(v) for k, v in sorted(per.items())}
    ref_per = {}
    for r in ref["impacts"]:
        ref_per.setdefault(r["contact"], []).append(r["t"])
    errors, unmatched = [], 0
    for c, times in per.items():
        rts = ref_per.get(c, [])
        for k, t in enumerate(times):
            if k < len(rts):
                errors.append({"contact": c, "k": k + 1, "t": t, "t_ref": rts[k],
                               "rel_error": abs(t - rts[k]) / rts[k],
                               "last_on_contact": k == len(times) - 1})
            else:
                unmatched += 1
    worst = max(errors, key=lambda e: e["rel_error"]) if errors else None
    out["impact_time_max_rel_error"] = worst["rel_error"] if worst else None
    out["impact_time_worst"] = worst
    # Deep in a Zeno sequence an error eps in the gap makes an impact time err by eps/|h_dot|:
    # the first impacts (h_dot of order 1) show the integration alone.
    first = sorted(errors, key=lambda e: e["t"])[:FIRST_IMPACTS]
    out["impact_time_max_rel_error_first"] = (max(e["rel_error"] for e in first)
                                              if first else None)
    out["impacts_matched"] = len(errors)
    out["impacts_beyond_reference"] = unmatched
    out["impact_errors"] = errors
    # Rest at t_end: |h| and |h_dot| of the contacts that hold the reference's rest.
    rest = {}
    if final is not None and final.get("q") is not None:
        hs = h_values(model, final["q"])
        hd = normal_velocities(model, final["q"], final["q_dot"])
        for c in ref["rest"]:
            rest[c] = {"h": hs[c], "h_dot": hd[c],
                       "at_rest": abs(hs[c]) <= REST and abs(hd[c]) <= REST}
        ref_state = ref["final_q"] + ref["final_v"]
        state = list(final["q"]) + list(final["q_dot"])
        out["final_state_error"] = max(abs(a - b) for a, b in zip(state, ref_state))
        out["final_t"] = final.get("t")
    else:
        out["final_state_error"] = None
    out["rest"] = rest
    finished = outcome == "finished"
    out["settled"] = finished and bool(rest) and all(r["at_rest"] for r in rest.values())
    # Zeno points.
    zeno = []
    for zr in ref["zeno"]:
        cands = [z for z in zeno_estimates if set(z["contacts"]) & set(zr["contacts"])]
        if cands:
            best = min(cands, key=lambda z: abs(z["t"] - zr["t"]))
            zeno.append({"contacts": zr["contacts"], "t_ref": zr["t"], "t": best["t"],
                         "error": abs(best["t"] - zr["t"]), "source": best.get("source")})
        else:
            zeno.append({"contacts": zr["contacts"], "t_ref": zr["t"], "t": None,
                         "error": None})
    out["zeno"] = zeno
    # Rocking block: the velocity ratio of every impact.
    if "ratio" in ref:
        ith = model["coordinates"].index("theta")
        devs, all_devs = [], []
        for imp in impacts:
            wb, wa = imp["v_before"][ith], imp["v_after"][ith]
            if wb == 0:
                continue
            d = abs(wa / wb - ref["ratio"])
            all_devs.append(d)
            if abs(wb) >= RATIO_MIN_SPEED:
                devs.append(d)
        out["ratio_max_deviation"] = max(devs) if devs else None
        out["ratio_impacts_checked"] = len(devs)
        out["ratio_max_deviation_all_impacts"] = max(all_devs) if all_devs else None
    return out


def zenosim_impacts(summary):
    out = []
    for ev in summary.get("events", []) or []:
        if ev.get("kind") != "impact":
            continue
        before, after = ev.get("before") or {}, ev.get("after") or {}
        if before.get("q") is None or before.get("q_dot") is None or after.get("q_dot") is None:
            continue
        names = event_contacts(ev)
        impulses = ev.get("impulses")
        impulsed = ([n for n, x in zip(names, impulses) if x > 0]
                    if isinstance(impulses, list) and len(impulses) == len(names) else names)
        out.append({"t": ev["t"], "q": before["q"], "v_before": before["q_dot"],
                    "v_after": after["q_dot"], "reported_contacts": names,
                    "impulsed": impulsed})
    return out


def zenosim_zeno(summary):
    out = []
    for z in summary.get("zeno", []) or []:
        t = z.get("t_zeno")
        if t is None:
            continue
        names = event_contacts(z)
        out.append({"contacts": names, "t": t, "source": f"t_zeno ({z.get('kind')})"})
    return out


def siconos_impacts(model, run):
    out = []
    for ev in run.get("events", []):
        if not any(v > 0 for v in ev["impulse"].values()):
            continue  # a non-smooth event without an impulse: no impact
        out.append({"t": ev["t"], "q": ev["q"], "v_before": ev["v_before"],
                    "v_after": ev["v_after"]})
    return out


def siconos_zeno(model, impacts, run, ref):
    """Siconos has no Zeno estimate: the last impact on a contact before it stays closed."""
    if run.get("status") != "finished":
        return []
    final = run["final"]
    hs = h_values(model, final["q"])
    hd = normal_velocities(model, final["q"], final["q_dot"])
    out = []
    for zr in ref["zeno"]:
        if not all(abs(hs[c]) <= REST and abs(hd[c]) <= REST for c in zr["contacts"]):
            continue
        times = [imp["t"] for imp in impacts
                 if set(impacting(model, imp["q"], imp["v_before"])) & set(zr["contacts"])]
        if times:
            out.append({"contacts": zr["contacts"], "t": max(times),
                        "source": "last impact before rest"})
    return out


# --------------------------------------------------------------------------------------------
# The report.

def machine():
    cpu, cores = None, os.cpu_count()
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                cpu = line.split(":", 1)[1].strip()
    except OSError:
        pass
    if not cpu:
        cpu = platform.processor() or "unknown CPU"
    import numpy
    return {"cpu": cpu, "cores": cores, "os": platform.platform(),
            "python": platform.python_version(), "numpy": numpy.__version__}


def fmt(x, digits=2):
    if x is None:
        return "–"
    if isinstance(x, float):
        if x == 0:
            return "0"
        return f"{x:.{digits}e}"
    return str(x)


def outcome_text(tool_status, metrics_, reason, t_reached):
    if tool_status == "finished":
        return "settled" if metrics_.get("settled") else "finished, not at rest"
    where = f" at t = {t_reached:.6g}" if isinstance(t_reached, (int, float)) else ""
    return f"{tool_status}{where}"


def table(results):
    lines = []
    m = results["machine"]
    lines.append("# zenosim against Siconos (event-driven) on three multi-contact models")
    lines.append("")
    lines.append(f"- date: {results['date']}")
    lines.append(f"- machine: {m['cpu']}, {m['cores']} cores; {m['os']}; Python {m['python']}")
    sv = results["siconos"]["version"]
    lines.append(f"- Siconos: Debian python3-siconos {sv.get('debian_package')} "
                 f"(its Python module says {sv.get('python_module')}); EventDriven + LsodarOSI, "
                 "impact LCP + acceleration LCP (Lemke)")
    zv = results["zenosim"]["version"] or {}
    git = zv.get("git", {})
    lines.append(f"- zenosim: {zv.get('version')}, commit {git.get('commit', '?')[:12]}"
                 + (f" with {git['uncommitted_engine_changes']} uncommitted files under crates/"
                    if git.get("uncommitted_engine_changes") else ""))
    lines.append(f"- tolerances rtol = atol = tol ∈ {{{', '.join(f'{t:g}' for t in results['tolerances'])}}}; "
                 f"Siconos TOL_ED: default ({results['siconos']['toled_default']:.3g}) or "
                 f"{results['siconos']['toled_scale']:g}·tol; wall-time limit {results['timeout_s']:g} s per Siconos run")
    lines.append("")
    lines.append("Impact times: max relative error over the impacts the tool reported, each "
                 "matched in order with the closed form's on the same contact (n: how many), "
                 f"then over the first {FIRST_IMPACTS} alone. Zeno error: |t − t_ref| "
                 "(zenosim: its t_zeno; Siconos: its last impact on that contact, if it ends at "
                 "rest there). Final: max-norm error of (q, q̇) at t_end. Wall: median of "
                 "repeated in-process runs (model loading and imports excluded).")
    for name in results["models"]:
        mres = results["results"][name]
        ref = mres["reference"]
        lines.append("")
        lines.append(f"## {name}")
        lines.append("")
        zeno_refs = ", ".join(f"{'+'.join(z['contacts'])} {z['t']:.10g}" for z in ref["zeno"])
        lines.append(f"Reference: {ref['formulas']}. Zeno times: {zeno_refs or 'none'}; "
                     f"{len(ref['impacts'])} reference impacts generated.")
        if "ratio" in ref:
            lines.append(f"Impact ratio θ̇⁺/θ̇⁻ = {ref['ratio']:.12g}.")
        lines.append("")
        head = ["tool", "tol", "outcome", "impacts",
                f"impact t: max rel err (n); first {FIRST_IMPACTS}",
                "Zeno error",
                "final err"]
        if "ratio" in ref:
            head.append("ratio max dev (n)")
        head.append("wall (ms)")
        lines.append("| " + " | ".join(head) + " |")
        lines.append("|" + "---|" * len(head))
        for row in mres["rows"]:
            mt = row.get("metrics") or {}
            zeno = "; ".join(
                (f"{'+'.join(z['contacts'])} {fmt(z['error'])}" if z["error"] is not None
                 else f"{'+'.join(z['contacts'])} –") for z in mt.get("zeno", [])) or "–"
            per = mt.get("impacts_per_contact") or {}
            imp = (f"{mt.get('impacts', 0)}"
                   + (f" ({', '.join(f'{k} {v}' for k, v in per.items())})" if len(per) > 1 else ""))
            err = mt.get("impact_time_max_rel_error")
            errs = (f"{fmt(err)} ({mt.get('impacts_matched', 0)}); "
                    f"{fmt(mt.get('impact_time_max_rel_error_first'))}"
                    if err is not None else "–")
            wall = row.get("wall_time_s")
            wall_s = (f"{wall * 1e3:.3g}" if isinstance(wall, (int, float)) else "–")
            if (row.get("timing") or {}).get("limit_hit"):
                wall_s = f"> {results['timeout_s'] * 1e3:g}"
            cells = [row["tool"], row["tol_label"], row["outcome"], imp, errs, zeno,
                     fmt(mt.get("final_state_error"))]
            if "ratio" in ref:
                cells.append(f"{fmt(mt.get('ratio_max_deviation'))}"
                             f" ({mt.get('ratio_impacts_checked', 0)})")
            cells.append(wall_s)
            lines.append("| " + " | ".join(cells) + " |")
        notes = [r for r in mres["rows"] if r.get("note")]
        if notes:
            lines.append("")
            for r in notes:
                lines.append(f"- {r['tool']} {r['tol_label']}: {r['note']}")
    lines.append("")
    return "\n".join(lines)


def run_all(args):
    """Every model and tolerance of args (models, tolerances, toled, toled_scale, timeout,
    min_time, repeat_below, no_zenosim, zenosim): the results as main writes them."""
    import siconos.kernel as sk
    toled_default = default_tol_ed(sk)
    zenosim = os.path.abspath(args.zenosim)
    have_zenosim = not args.no_zenosim and os.access(zenosim, os.X_OK)
    if not args.no_zenosim and not have_zenosim:
        log(f"peer: no zenosim binary at {zenosim}: zenosim rows are reported as missing")

    results = {
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "machine": machine(),
        "siconos": {"version": siconos_version(), "toled_default": toled_default,
                    "toled_scale": args.toled_scale,
                    "scheme": "EventDriven + LsodarOSI(setTol(1, tol, tol)); "
                              "LCP at SICONOS_OSNSP_ED_IMPACT and SICONOS_OSNSP_ED_SMOOTH_ACC; "
                              "NewtonImpactNSL(e) per constraint"},
        "zenosim": {"binary": zenosim, "version": zenosim_version(zenosim) if have_zenosim else None},
        "tolerances": args.tolerances, "timeout_s": args.timeout, "min_time_s": args.min_time,
        "rest_threshold": REST, "ratio_min_speed": RATIO_MIN_SPEED,
        "models": args.models, "results": {},
    }
    workdir = tempfile.mkdtemp(prefix="zenosim-siconos-")
    try:
        plugin_lib, plugin_error = compile_plugin(workdir)
        for name in args.models:
            model = load_model(name)
            spec = siconos_spec(model)
            check = check_spec(model, spec)
            ref = REFERENCES[name](model)
            log(f"peer: {name}: the hand-written Siconos model matches the file "
                f"(largest differences {', '.join(f'{k} {v:.1e}' for k, v in check.items())})")
            mres = {"file": os.path.relpath(model["path"], ROOT),
                    "parameters": model["params"], "q0": model["q0"], "v0": model["v0"],
                    "t_end": model["t_end"],
                    "restitutions": {c["name"]: c["e"] for c in model["constraints"]},
                    "siconos_model": spec, "siconos_model_check": check,
                    "reference": ref, "rows": []}
            # zenosim
            bench, bench_error = (None, None)
            if have_zenosim:
                bench, bench_error = bench_zenosim(zenosim, model, args)
            for k, tol in enumerate(args.tolerances):
                if not have_zenosim:
                    if not args.no_zenosim:
                        mres["rows"].append({"tool": "zenosim", "tol": tol,
                                             "tol_label": f"{tol:g}", "outcome": "missing",
                                             "note": f"no binary at {zenosim}"})
                    continue
                zr = run_zenosim(zenosim, model, tol, args, workdir)
                row = {"tool": "zenosim", "tol": tol, "tol_label": f"{tol:g}",
                       "status": zr["status"], "reason": zr.get("reason"),
                       "command": zr.get("command")}
                summary = zr.get("summary")
                if summary is not None:
                    impacts = zenosim_impacts(summary)
                    final = summary.get("final")
                    row["metrics"] = metrics(model, ref, impacts, final, zenosim_zeno(summary),
                                             zr["status"])
                    row["zeno_reported"] = summary.get("zeno")
                    row["final"] = final
                    row["impact_times"] = [i["t"] for i in impacts]
                    row["stats"] = summary.get("stats")
                    t_reached = (final or {}).get("t")
                else:
                    row["metrics"] = {}
                    t_reached = None
                row["outcome"] = outcome_text(zr["status"], row["metrics"], zr.get("reason"),
                                              t_reached)
                if zr["status"] != "finished":
                    reason = str(zr.get("reason"))
                    row["note"] = (reason if reason.startswith(zr["status"])
                                   else f"{zr['status']}: {reason}")
                if bench is not None and k < len(bench.get("runs", [])):
                    br = bench["runs"][k]
                    row["wall_time_s"] = (br.get("wall_time_s") or {}).get("median")
                    row["bench"] = {"status": br.get("status"),
                                    "wall_time_s": br.get("wall_time_s"),
                                    "settings": br.get("settings")}
                elif bench_error:
                    row["bench_error"] = bench_error
                mres["rows"].append(row)
                log(f"peer: {name} zenosim tol {tol:g}: {row['outcome']}")
            # Siconos
            for variant in args.toled:
                for tol in args.tolerances:
                    toled = None if variant == "default" else args.toled_scale * tol
                    label = f"{tol:g}" + ("" if variant == "default"
                                          else f", TOL_ED {toled:g}")
                    row = {"tool": "Siconos", "tol": tol, "toled_variant": variant,
                           "tol_label": label}
                    if name == "rocking-block" and plugin_lib is None:
                        row.update({"status": "failed", "outcome": "not run",
                                    "note": plugin_error, "metrics": {}})
                        mres["rows"].append(row)
                        continue
                    run = run_siconos(spec, plugin_lib, tol, toled, args, workdir)
                    impacts = siconos_impacts(model, run) if "events" in run else []
                    final = run.get("final")
                    row["metrics"] = metrics(model, ref, impacts, final,
                                             siconos_zeno(model, impacts, run, ref)
                                             if final else [], run["status"])
                    row.update({"status": run["status"], "reason": run.get("reason"),
                                "toled": run.get("toled", toled),
                                "ns_events": run.get("ns_events"),
                                "impacts_with_impulse": run.get("impacts_with_impulse"),
                                "final": final, "siconos_output": run.get("siconos_output"),
                                "impact_times": [i["t"] for i in impacts],
                                "events_truncated": run.get("events_truncated"),
                                "wall_time_s": (run.get("wall_time_s") or {}).get("median"),
                                "timing": run.get("wall_time_s")})
                    row["outcome"] = outcome_text(run["status"], row["metrics"],
                                                  run.get("reason"), run.get("t_reached"))
                    if run["status"] != "finished":
                        msg = "; ".join(run.get("siconos_output") or [])
                        row["note"] = f"{run['status']}: {run.get('reason')}" + \
                            (f" — Siconos: {msg}" if msg else "")
                    mres["rows"].append(row)
                    log(f"peer: {name} Siconos {label}: {row['outcome']}")
            results["results"][name] = mres
    finally:
        shutil.rmtree(workdir, ignore_errors=True)

    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--zenosim", default=os.path.join(ROOT, "target", "release", "zenosim"),
                        help="the zenosim binary [default: target/release/zenosim]")
    parser.add_argument("--models", default=",".join(MODELS),
                        help=f"comma-separated [default: {','.join(MODELS)}]")
    parser.add_argument("--tolerances", default=",".join(f"{t:g}" for t in TOLERANCES),
                        help="rtol = atol for both tools, comma-separated")
    parser.add_argument("--toled", default="default,scaled",
                        help="Siconos TOL_ED variants: default (Siconos's own) and/or scaled "
                             "(--toled-scale times tol) [default: both]")
    parser.add_argument("--toled-scale", type=float, default=TOLED_SCALE,
                        help=f"TOL_ED = this times tol in the scaled variant [default: {TOLED_SCALE:g}]")
    parser.add_argument("--timeout", type=float, default=60.0,
                        help="wall-time limit of one run, seconds [default: 60]")
    parser.add_argument("--min-time", type=float, default=0.5,
                        help="time each run repeatedly for at least this long [default: 0.5]")
    parser.add_argument("--repeat-below", type=float, default=2.0,
                        help="repeat a Siconos run for timing only if it took less [default: 2]")
    parser.add_argument("--no-zenosim", action="store_true", help="Siconos only")
    parser.add_argument("--out", default=HERE,
                        help="where results-peer.md and results-peer.json go [default: bench/siconos]")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        siconos_child(args)
        return 0
    args.models = [m for m in args.models.split(",") if m]
    args.tolerances = [float(t) for t in args.tolerances.split(",") if t]
    args.toled = [v for v in args.toled.split(",") if v]

    results = run_all(args)
    md = table(results)
    print(md)
    os.makedirs(args.out, exist_ok=True)
    # suite.py writes results.md and results.json (this section included); peer.py alone
    # writes its own files beside them
    with open(os.path.join(args.out, "results-peer.md"), "w") as f:
        f.write(md)
    with open(os.path.join(args.out, "results-peer.json"), "w") as f:
        json.dump(results, f, indent=1, default=str)
        f.write("\n")
    log(f"peer: wrote {os.path.join(args.out, 'results-peer.md')} and results-peer.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
