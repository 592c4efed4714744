#!/usr/bin/env python3
"""zenosim and Siconos side by side on Siconos's own impact examples, against independent
references; then the three multi-contact models of peer.py.

Run it through bench/siconos/run (which installs Debian's python3-siconos if it is missing and
builds zenosim), or directly with the system python (Siconos is a Debian package for it):

    /usr/bin/python3 bench/siconos/suite.py --zenosim target/release/zenosim
    /usr/bin/python3 bench/siconos/suite.py --examples bouncing-ball-ed --no-peer
    /usr/bin/python3 bench/siconos/suite.py --help

Per example (one module under examples/, see examples/__init__.py):
  * the model file models/siconos/<name>.toml (ported from the Siconos example) and its
    reference models/siconos/references/<name>.json (made independently of both tools);
  * Siconos runs the example's scheme (EventDriven + LsodarOSI, or TimeStepping with
    MoreauJeanOSI and the example's step) on a model the example module writes from the file
    (every number from the file); suite.py checks it against the file before any run (mass
    matrix, forces, h and dh/dq at a few states) and stops if they differ;
  * event-driven examples: Siconos at LSODAR tolerances 1e-6 ... 1e-12, with its default TOL_ED
    and with TOL_ED = tol; time-stepping examples: Siconos at the example's step and others;
    zenosim at tolerances 1e-6 ... 1e-12;
  * the errors, computed the same way for both tools: impact times (per contact, the k-th
    impact against the reference's k-th), Zeno times, with friction the stick, slip and
    reversal times (per contact and kind), the final state; and the wall times. Where a
    reference also computes the model under another law (its "alternatives"), the same
    errors against it.
Writes results.md (the tables, with the peer models' section after them) and results.json.
"""

import argparse
import datetime
import importlib
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import peer  # noqa: E402  (the formulas, zenosim's runs, the machine)
import siconos_side  # noqa: E402
from examples import EXAMPLES  # noqa: E402

TOLERANCES = [1e-6, 1e-8, 1e-10, 1e-12]
# A contact is closed when |h| is at most this (event-driven tools), at rest when |h| and
# |h_dot| are.
REST = 1e-5
# The impact-time error is also given over the first few impacts alone.
FIRST_IMPACTS = 10


def log(*parts):
    print(*parts, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# The model files (with t, [forces] and dissipation) and their dynamics.

def load_model(path):
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    coords = list(doc["coordinates"])
    raw = dict(doc.get("parameters", {}))
    params, pending = {}, dict(raw)
    while pending:
        progress = False
        for k, v in list(pending.items()):
            if isinstance(v, (int, float)):
                params[k] = float(v)
            else:
                f = peer.Formula(v)
                if not f.names <= set(params) | set(peer.CONSTANTS):
                    continue
                params[k] = f(params)
            del pending[k]
            progress = True
        if not progress:
            raise ValueError(f"{path}: parameters that cannot be evaluated: {sorted(pending)}")
    init = doc.get("initial", {})

    def value(v):
        return float(v) if isinstance(v, (int, float)) else peer.Formula(v)(params)

    sim = doc.get("simulation", {})
    forces = doc.get("forces", {})
    return {
        "name": os.path.splitext(os.path.basename(path))[0], "path": path, "doc": doc,
        "coordinates": coords, "params": params,
        "q0": [value(init.get(c, 0.0)) for c in coords],
        "v0": [value(init.get(c + "_dot", 0.0)) for c in coords],
        "constraints": [dict({"name": c["name"], "h": peer.Formula(c["h"]),
                              "e": value(c.get("restitution", 0.0))}, **friction_of(c, value))
                        for c in doc.get("constraint", [])],
        "lagrangian": peer.Formula(doc["lagrangian"]),
        "forces": {k: peer.Formula(v) for k, v in forces.items()},
        "dissipation": peer.Formula(doc["dissipation"]) if "dissipation" in doc else None,
        "t_end": float(sim.get("t_end", 10.0)),
        "header": header_comment(path),
    }


def friction_of(c, value):
    """A constraint's friction (docs/friction.md): its coefficients and its slip formula, or
    nothing for a frictionless one."""
    if "friction" not in c:
        return {}
    f = c["friction"]
    if isinstance(f, dict):
        mu_s, mu_k = value(f["static"]), value(f["kinetic"])
    else:
        mu_s = mu_k = value(f)
    (slip,) = c["slip"]
    return {"mu_static": mu_s, "mu_kinetic": mu_k, "slip": peer.Formula(slip)}


def header_comment(path):
    lines = []
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            lines.append(line[1:].strip())
    return "\n".join(lines)


def env(model, t, q, v):
    e = dict(model["params"])
    e["t"] = t
    for i, c in enumerate(model["coordinates"]):
        e[c] = q[i]
        e[c + "_dot"] = v[i]
    return e


def file_h(model, t, q):
    e = env(model, t, q, [0.0] * len(q))
    return {c["name"]: c["h"](e) for c in model["constraints"]}


def file_slip(model, t, q, v):
    """The slip of every constraint with friction at (t, q, v)."""
    e = env(model, t, q, v)
    return {c["name"]: c["slip"](e) for c in model["constraints"] if c.get("slip")}


def file_slip_row(model, t, q):
    """Per constraint with friction, its slip's row S = ds/dv and its part s0 = s(t, q, 0)
    (the slip is affine in the velocities: S_j = s(e_j) - s(0), exact)."""
    n = len(q)
    zero = file_slip(model, t, q, [0.0] * n)
    rows = {k: [] for k in zero}
    for j in range(n):
        v = [0.0] * n
        v[j] = 1.0
        sj = file_slip(model, t, q, v)
        for k in rows:
            rows[k].append(sj[k] - zero[k])
    return rows, zero


def file_jac(model, t, q, step=1e-6):
    jac = {c["name"]: [] for c in model["constraints"]}
    for i in range(len(q)):
        qp, qm = list(q), list(q)
        qp[i] += step
        qm[i] -= step
        hp, hm = file_h(model, t, qp), file_h(model, t, qm)
        for k in jac:
            jac[k].append((hp[k] - hm[k]) / (2 * step))
    return jac


def file_h_dot(model, t, q, v, step=1e-6):
    """dh/dt along (q, v): A v + dh/dt (a moving surface)."""
    jac = file_jac(model, t, q)
    hp, hm = file_h(model, t + step, q), file_h(model, t - step, q)
    return {k: sum(a * b for a, b in zip(jac[k], v)) + (hp[k] - hm[k]) / (2 * step)
            for k in jac}


def file_dynamics(model, t, q, v, d=1e-4, dv=0.5):
    """M = d2L/dv2 and F = dL/dq - (d2L/dv dq) v - d2L/dv dt + Q - dD/dv, by central differences
    of the file's formulas: steps dv in the velocities (exact up to rounding for L and D
    quadratic in them, as in every file here) and d in positions and time."""
    n = len(q)
    lag = model["lagrangian"]

    def L(tt, qq, vv):
        return lag(env(model, tt, qq, vv))

    def shifted(x, i, s):
        y = list(x)
        y[i] += s
        return y

    def dL_dv(tt, qq, vv, i):
        return (L(tt, qq, shifted(vv, i, dv)) - L(tt, qq, shifted(vv, i, -dv))) / (2 * dv)

    mass = [[(dL_dv(t, q, shifted(v, j, dv), i) - dL_dv(t, q, shifted(v, j, -dv), i)) / (2 * dv)
             for j in range(n)] for i in range(n)]
    force = []
    for i in range(n):
        dLq = (L(t, shifted(q, i, d), v) - L(t, shifted(q, i, -d), v)) / (2 * d)
        # (d/de) dL/dv_i at (t + e, q + e v): the mixed terms along the motion
        qp = [a + d * b for a, b in zip(q, v)]
        qm = [a - d * b for a, b in zip(q, v)]
        mixed = (dL_dv(t + d, qp, v, i) - dL_dv(t - d, qm, v, i)) / (2 * d)
        f = dLq - mixed
        c = model["coordinates"][i]
        if c in model["forces"]:
            f += model["forces"][c](env(model, t, q, v))
        if model["dissipation"] is not None:
            dis = model["dissipation"]
            f -= (dis(env(model, t, q, shifted(v, i, dv)))
                  - dis(env(model, t, q, shifted(v, i, -dv)))) / (2 * dv)
        force.append(f)
    return mass, force


# --------------------------------------------------------------------------------------------
# Between the file's coordinates and Siconos's dynamical systems.

def split_state(spec, model, x, t, example):
    """The file's state vector x (over its coordinates) as one list per DS; a dof that is not a
    file coordinate (a driven body) takes the example's value at t."""
    out = []
    for k, d in enumerate(spec["ds"]):
        row = []
        for j, c in enumerate(d["coords"]):
            if c in model["coordinates"]:
                row.append(x[model["coordinates"].index(c)])
            else:
                row.append(example.driven_value(model, spec, k, j, t, x))
        out.append(row)
    return out


def join_state(spec, model, per_ds):
    """Siconos's per-DS state as the file's state vector (dofs that are not coordinates of the
    file are dropped)."""
    x = [None] * len(model["coordinates"])
    for d, vals in zip(spec["ds"], per_ds):
        for c, val in zip(d["coords"], vals):
            if c in model["coordinates"]:
                x[model["coordinates"].index(c)] = val
    return x


def check_spec(model, spec, plugins, example, states=6):
    """The Siconos model against the file at a few states near the initial one: the mass matrix
    and the forces (per file coordinate), h and dh/dq of every constraint. Returns the largest
    differences, relative to the size of what is compared; raises if one is above LIMITS."""
    rng = random.Random(2)
    n = len(model["coordinates"])
    worst = {"mass": 0.0, "force": 0.0, "h": 0.0, "dh_dq": 0.0}
    names = {it["name"] for it in spec["interactions"]}
    if names != {c["name"] for c in model["constraints"]}:
        raise ValueError(f"{model['name']}: the Siconos interactions {sorted(names)} are not the "
                         f"file's constraints {sorted(c['name'] for c in model['constraints'])}")
    laws = check_laws(model, spec)
    if hasattr(example, "check_spec"):
        # a model Siconos writes otherwise (a first-order system): the example's own check
        worst = dict(laws, **example.check_spec(model, spec, plugins))
        bad = {k: v for k, v in worst.items() if v > 1e-6}
        if bad:
            raise ValueError(f"{model['name']}: the Siconos model does not match the file: {bad}")
        return worst
    if any(c.get("slip") for c in model["constraints"]):
        worst["slip_row"] = 0.0
    worst.update(laws)
    scale_q = [max(abs(x), 1e-3) for x in model["q0"]]
    scales = {"mass": 0.0, "force": 0.0}  # mass and force: relative to their largest entry
    for s in range(states):
        t = model["t_end"] * rng.random() if s else 0.0
        q = [a + (0.05 * sc * rng.uniform(-1, 1) if s else 0.0)
             for a, sc in zip(model["q0"], scale_q)]
        v = [a + rng.uniform(-1, 1) * (0.5 + abs(a)) for a in model["v0"]]
        mass, force = file_dynamics(model, t, q, v)
        qs = split_state(spec, model, q, t, example)
        vs = split_state(spec, model, v, t, example)  # driven dofs: their velocity at t
        ev = siconos_side.evaluate(spec, plugins, t, qs, vs)
        sic_mass = [[0.0] * n for _ in range(n)]
        sic_force = [0.0] * n
        for d, m, f in zip(spec["ds"], ev["mass"], ev["force"]):
            idx = [model["coordinates"].index(c) if c in model["coordinates"] else None
                   for c in d["coords"]]
            for a, ia in enumerate(idx):
                if ia is None:
                    continue
                sic_force[ia] = f[a]
                for b, ib in enumerate(idx):
                    if ib is not None:
                        sic_mass[ia][ib] = m[a][b]
        scales["mass"] = max(scales["mass"], max(abs(x) for row in mass for x in row))
        worst["mass"] = max(worst["mass"], max(abs(a - b) for ra, rb in zip(mass, sic_mass)
                                               for a, b in zip(ra, rb)))
        scales["force"] = max(scales["force"], max(abs(x) for x in force))
        worst["force"] = max(worst["force"],
                             max(abs(a - b) for a, b in zip(force, sic_force)))
        hs = file_h(model, t, q)
        jac = file_jac(model, t, q)
        for it in spec["interactions"]:
            name = it["name"]
            hscale = max(abs(hs[name]), max(abs(x) for x in jac[name]) * max(scale_q), 1e-300)
            worst["h"] = max(worst["h"], abs(hs[name] - ev["h"][name]) / hscale)
            # Siconos's dh/dq is over the concatenated dofs of its DSs: map to the file's
            sic = [0.0] * n
            cols = [c for i in it["ds"] for c in spec["ds"][i]["coords"]]
            for c, val in zip(cols, ev["jac"][name]):
                if c in model["coordinates"]:
                    sic[model["coordinates"].index(c)] = val
            jscale = max(max(abs(x) for x in jac[name]), 1e-300)
            worst["dh_dq"] = max(worst["dh_dq"],
                                 max(abs(a - b) for a, b in zip(jac[name], sic)) / jscale)
            if name in ev["tangent"]:
                # Siconos's tangential row against the file's slip row S (up to its sign,
                # which Coulomb's isotropic law does not see); the slip must have no part
                # s0 (no moving surface in these relations)
                rows, s0 = file_slip_row(model, t, q)
                tan = [0.0] * n
                for c, val in zip(cols, ev["tangent"][name]):
                    if c in model["coordinates"]:
                        tan[model["coordinates"].index(c)] = val
                srow = rows[name]
                sscale = max(max(abs(x) for x in srow), 1e-300)
                diff = min(max(abs(a - b) for a, b in zip(srow, tan)),
                           max(abs(a + b) for a, b in zip(srow, tan)))
                worst["slip_row"] = max(worst["slip_row"], diff / sscale,
                                        abs(s0[name]) / sscale)
    for k in ("mass", "force"):
        worst[k] = worst[k] / scales[k] if scales[k] > 0 else worst[k]
    extra = example.check_extra(model, spec, plugins) if hasattr(example, "check_extra") else {}
    worst.update(extra)
    limits = {"mass": 1e-6, "force": 1e-5, "h": 1e-12, "dh_dq": 1e-6, "slip_row": 1e-12,
              "laws": 1e-15}
    bad = {k: v for k, v in worst.items() if v > limits.get(k, 1e-6)}
    if bad:
        raise ValueError(f"{model['name']}: the Siconos model does not match the file: {bad}")
    return worst


def check_laws(model, spec):
    """Each interaction's law against its constraint's: restitution and Coulomb's coefficient
    (NewtonImpactFrictionNSL where the file has friction, with one coefficient: Siconos has no
    static one; NewtonImpactNSL where it has none; a relay has no restitution, its bound is
    the example's check). The largest difference, relative."""
    worst = 0.0
    file = {c["name"]: c for c in model["constraints"]}
    for it in spec["interactions"]:
        c = file[it["name"]]
        if it.get("relay") is not None:
            continue
        worst = max(worst, abs(it["e"] - c["e"]))
        fr = it.get("friction")
        if (fr is None) != (c.get("slip") is None):
            raise ValueError(f"{model['name']}: {it['name']} has friction in one model only")
        if fr is not None:
            if c["mu_static"] != c["mu_kinetic"]:
                raise ValueError(f"{model['name']}: {it['name']}: Siconos's Coulomb law has one "
                                 "coefficient")
            worst = max(worst, abs(fr["mu"] - c["mu_kinetic"]) / max(c["mu_kinetic"], 1e-300),
                        abs(fr.get("et", 0.0)))
    return {"laws": worst}


# --------------------------------------------------------------------------------------------
# Impacts, the same way for both tools.

def approaching(model, t, q, v, candidates=None):
    """The contacts an impact at (t, q, v_before) is on: the candidates (all constraints if
    None) with h_dot < 0, the fastest and any within a factor 100 of it."""
    hd = file_h_dot(model, t, q, v)
    closing = {k: x for k, x in hd.items() if x < 0 and (candidates is None or k in candidates)}
    if not closing:
        return []
    fastest = min(closing.values())
    return sorted(k for k, x in closing.items() if x <= 0.01 * fastest)


def impacts_event_driven(model, events):
    """Event-driven tools (zenosim, Siconos ED): an impact is an event with a velocity jump on
    a contact that is closed (|h| <= REST), has an impulse there (the event's "impulsed": the
    contacts the tool applied a positive impulse to) and is approaching (see approaching).
    Without the impulse a contact a few micrometres away, approaching, would count as struck
    although the tool struck it only later (the column of beads)."""
    out = []
    for ev in events:
        hs = file_h(model, ev["t"], ev["q"])
        closed = {k for k, x in hs.items() if abs(x) <= REST and k in ev["impulsed"]}
        if ev["v_before"] == ev["v_after"]:
            continue
        cs = approaching(model, ev["t"], ev["q"], ev["v_before"], closed)
        if cs:
            out.append({"t": ev["t"], "contacts": cs, "q": ev["q"],
                        "v_before": ev["v_before"], "v_after": ev["v_after"]})
    return out


def impacts_time_stepping(model, spec, events):
    """Time-stepping: an impact is the first step of a run of steps with an impulse on a
    contact (the contact closes), approaching at the start of the step; its time is the end of
    that step (the velocity after it is the one after the impact)."""
    out = []
    prev_k, prev_closed = None, set()
    for ev in events:
        closed = {k for k, x in ev["impulse"].items() if x > 0}
        new = closed if ev["k"] != (prev_k or -9) + 1 else closed - prev_closed
        if new:
            q = join_state(spec, model, ev["q"])
            vb = join_state(spec, model, ev["v_before"])
            cs = approaching(model, ev["t_start"], q, vb, new)
            if cs:
                out.append({"t": ev["t"], "contacts": cs, "q": q, "v_before": vb,
                            "v_after": join_state(spec, model, ev["v_after"])})
        prev_k, prev_closed = ev["k"], closed
    return out


def reference_window(model, ref):
    """The end of the reference's window when it stops before the model's t_end (the
    slider-cranks: 0.03 of 0.2), else None. Inside it every impact, Zeno point and lift-off of
    the reference is listed; the final state is the one at its end."""
    rf = ref.get("final") or {}
    t = rf.get("t")
    if t is not None and t < model["t_end"] * (1 - 1e-12):
        return t
    return None


def match_per_contact(tool, reference):
    """Per contact, the k-th time of the tool against the k-th of the reference: the matched
    pairs (contact, k, t, t_ref, error) and how many of the tool's had no partner."""
    errors, unmatched = [], 0
    for c, times in tool.items():
        rts = reference.get(c, [])
        for k, t in enumerate(times):
            if k < len(rts):
                errors.append({"contact": c, "k": k + 1, "t": t, "t_ref": rts[k],
                               "error": abs(t - rts[k])})
            else:
                unmatched += 1
    return errors, unmatched


def per_contact(items, key="contacts"):
    out = {}
    for it in items:
        for c in it.get(key) or []:
            out.setdefault(c, []).append(it["t"])
    return out


def match_friction(tool, reference):
    """Per contact and kind (stick, slip, reversal), the k-th friction event of the tool
    against the k-th of the reference: the matched pairs and how many of the tool's had none."""
    def grouped(events):
        out = {}
        for ev in events:
            for c in ev.get("constraints") or [ev.get("contact")]:
                out.setdefault((c, ev["kind"]), []).append(ev["t"])
        return out
    ref = grouped(reference)
    errors, unmatched = [], 0
    for (c, kind), times in sorted(grouped(tool).items()):
        rts = ref.get((c, kind), [])
        for k, t in enumerate(times):
            if k < len(rts):
                errors.append({"contact": c, "kind": kind, "k": k + 1, "t": t, "t_ref": rts[k],
                               "error": abs(t - rts[k])})
            else:
                unmatched += 1
    return errors, unmatched


def metrics(model, ref, impacts, final, zeno_estimates, final_dt=0.0, window=None,
            liftoffs=None, friction=None):
    """final_dt: how far from the reference's final time the tool's final state may be and
    still be compared (a time-stepping run ends on its grid: up to one step h from t_end).
    window: the end of the reference's window (reference_window): only the impacts and lift-offs
    up to it are matched, and `final` is the tool's state there (from a run to that time).
    liftoffs: the tool's lift-offs ({"t", "contacts"}), matched like the impacts when the
    reference lists some. friction: the tool's friction events ({"t", "contact", "kind"}: a
    held contact that sticks, starts to slip, or reverses its slip), matched per contact and
    kind when the reference lists some (friction_events). Where the reference has
    alternatives (the same model under another law), the same metrics against each."""
    out = {"impacts": len(impacts)}
    if ref.get("friction_events") is not None and friction is not None:
        ferr, fun = match_friction(friction, ref["friction_events"])
        counts = {}
        for ev in friction:
            counts[ev["kind"]] = counts.get(ev["kind"], 0) + 1
        out["friction_events"] = counts
        out["friction_event_errors"] = ferr[:2000]
        out["friction_events_matched"] = len(ferr)
        out["friction_events_beyond_reference"] = fun
        out["friction_event_max_error"] = max((e["error"] for e in ferr), default=None)
    if ref.get("alternatives"):
        out["alternatives"] = {}
        for alt in ref["alternatives"]:
            sub = metrics(model, alt, impacts, final, zeno_estimates, final_dt, window,
                          liftoffs, friction)
            out["alternatives"][alt["name"]] = {
                k: sub.get(k) for k in ("impact_time_max_error", "impact_time_max_error_first",
                                        "impacts_matched", "impacts_beyond_reference", "zeno",
                                        "final_state_error", "friction_event_max_error",
                                        "friction_events_matched")}
    per = per_contact(impacts)
    out["impacts_per_contact"] = {k: len(v) for k, v in sorted(per.items())}
    if window is not None:
        out["window"] = window
        inside = [i for i in impacts if i["t"] <= window]
        out["impacts_in_window"] = len(inside)
        per = per_contact(inside)
        out["impacts_in_window_per_contact"] = {k: len(v) for k, v in sorted(per.items())}
    ref_per = per_contact(ref.get("impacts") or [])
    out["reference_impacts"] = len(ref.get("impacts") or [])
    errors, unmatched = match_per_contact(per, ref_per)
    out["impact_time_max_error"] = max((e["error"] for e in errors), default=None)
    first = sorted(errors, key=lambda e: e["t_ref"])[:FIRST_IMPACTS]
    out["impact_time_max_error_first"] = max((e["error"] for e in first), default=None)
    out["impacts_matched"] = len(errors)
    out["impacts_beyond_reference"] = unmatched
    out["impact_errors"] = errors[:2000]
    zeno = []
    for zr in ref.get("zeno") or []:
        names = zr.get("constraints") or zr.get("contacts") or []
        cands = [z for z in zeno_estimates if set(z["contacts"]) & set(names)]
        if cands:
            best = min(cands, key=lambda z: abs(z["t"] - zr["t"]))
            zeno.append({"contacts": names, "t_ref": zr["t"], "t": best["t"],
                         "error": abs(best["t"] - zr["t"]), "source": best.get("source")})
        else:
            zeno.append({"contacts": names, "t_ref": zr["t"], "t": None, "error": None})
    out["zeno"] = zeno
    if ref.get("liftoffs") and liftoffs is not None:
        lifts = [x for x in liftoffs if window is None or x["t"] <= window]
        lerr, lun = match_per_contact(per_contact(lifts), per_contact(ref["liftoffs"],
                                                                     "constraints"))
        out["liftoff_errors"] = lerr
        out["liftoffs_beyond_reference"] = lun
        out["liftoff_max_error"] = max((e["error"] for e in lerr), default=None)
    rf = ref.get("final")
    out["final_state_error"] = None
    if final is not None and rf and rf.get("q") is not None and final.get("q") is not None:
        out["final_t"] = final["t"]
        if abs(final["t"] - rf["t"]) <= max(1e-9 * max(1.0, abs(rf["t"])), final_dt):
            pairs = list(zip(final["q"], rf["q"]))
            if rf.get("q_dot") is not None:
                pairs += list(zip(final["q_dot"], rf["q_dot"]))
            out["final_state_error"] = max(abs(a - b) for a, b in pairs)
            out["final_q_error"] = max(abs(a - b) for a, b in zip(final["q"], rf["q"]))
    rest = ref.get("rest")
    if not rf and rest and final is not None and final.get("q") is not None:
        # no state at t_end, only the one the motion ends in: the final state against it
        out["final_t"] = final["t"]
        out["rest_state_error"] = max(abs(a - b) for a, b in
                                      list(zip(final["q"], rest["q"]))
                                      + list(zip(final["q_dot"], rest["q_dot"])))
        out["rest_q_error"] = max(abs(a - b) for a, b in zip(final["q"], rest["q"]))
    return out


# --------------------------------------------------------------------------------------------
# The runs.

def run_siconos(spec, scheme, libs, args, workdir):
    job_path = os.path.join(workdir, "job.json")
    out_path = os.path.join(workdir, "out.json")
    progress = os.path.join(workdir, "progress.json")
    for p in (out_path, progress):
        if os.path.exists(p):
            os.remove(p)
    with open(job_path, "w") as f:
        json.dump({"spec": spec, "scheme": scheme, "libs": libs, "out": out_path,
                   "progress": progress, "min_time": args.min_time,
                   "repeat_below_s": args.repeat_below}, f)
    begin = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, os.path.join(HERE, "siconos_side.py"), job_path],
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
        reached = {}
        if os.path.exists(progress):
            try:
                with open(progress) as f:
                    reached = json.load(f)
            except (OSError, ValueError):
                reached = {}
        if timed_out:
            status = "stalled"
            where = (f"at t = {reached['t']:.12g}" if reached else
                     "before its first progress report")
            reason = f"no t_end within the {args.timeout:g} s wall-time limit; {where}"
        else:
            status = "crashed"
            reason = (f"the Siconos process ended with status "
                      f"{getattr(proc, 'returncode', None)} and no result")
        return {"status": status, "reason": reason, "t_reached": reached.get("t"),
                "siconos_output": peer.siconos_message(stdout + "\n" + stderr),
                "stderr_tail": stderr.strip().splitlines()[-3:],
                "wall_time_s": {"median": elapsed, "repeats": 1, "limit_hit": timed_out}}
    with open(out_path) as f:
        run = json.load(f)
    run["siconos_output"] = peer.siconos_message(stdout)
    if run.get("status") != "finished" and not run["siconos_output"]:
        # nothing matched peer's keywords: the last lines Siconos printed
        run["siconos_output"] = [ln.strip() for ln in (stdout + stderr).splitlines()
                                 if ln.strip()][-3:]
    return run


# A contact is held by a time-stepping run through a run of at least this many consecutive
# steps with an impulse on it, or a contact force (D1Minus's acceleration-level problem); fewer
# is a contact that closes, or a scheme that chatters.
HOLD_STEPS = 10


def holds(run, names):
    """The time-stepping run's holds of all the contacts names: (start of the first step, end of
    the last step, whether the last step is the run's last), per run of at least HOLD_STEPS
    consecutive steps with an impulse or a contact force on each of them."""
    out, first, prev = [], None, None

    def close():
        if first is not None and prev["k"] - first["k"] + 1 >= HOLD_STEPS:
            out.append((first["t_start"], prev["t"], prev["k"] == run.get("steps")))

    for ev in run.get("events") or []:
        force = ev.get("force") or {}
        on = all(ev["impulse"].get(c, 0.0) > 0 or force.get(c, 0.0) > 0 for c in names)
        if on and prev is not None and ev["k"] == prev["k"] + 1:
            prev = ev
            continue
        close()
        first, prev = (ev, ev) if on else (None, None)
    close()
    return out


def siconos_zeno(model, spec, scheme, run, impacts, ref, end_run=None):
    """Siconos has no Zeno estimate: its last impact on the contacts before they stay closed,
    counted if they are closed after it: event-driven, at the end of the run (|h| and |h_dot|
    <= REST); time-stepping, in a hold (HOLD_STEPS) through the end of the run or, where the
    reference has them lift off after the Zeno point, through the time half-way between the
    two; the estimate is then the last impact up to the hold's first step. end_run: the run
    that ends at the end of the reference's window, if there is one."""
    end_run = end_run or run
    if run.get("status") != "finished" or end_run.get("status") != "finished" \
            or not end_run.get("final"):
        return []
    final = end_run["final"]
    q = join_state(spec, model, final["q"])
    v = join_state(spec, model, final["q_dot"])
    hs = file_h(model, final["t"], q)
    hd = file_h_dot(model, final["t"], q, v)
    out = []
    for zr in ref.get("zeno") or []:
        names = zr.get("constraints") or zr.get("contacts") or []
        lift = [x["t"] for x in ref.get("liftoffs") or []
                if x["t"] > zr["t"] and set(x.get("constraints") or x.get("contacts") or [])
                & set(names)]
        if scheme["kind"] == "ED":
            if lift:
                continue  # no state between events is kept
            if not all(abs(hs[c]) <= REST and abs(hd[c]) <= REST for c in names):
                continue
            t_last, source = final["t"], "last impact before rest"
        else:
            if lift:
                t_check = 0.5 * (zr["t"] + min(lift))
                hold = [(a, b) for a, b, _ in holds(run, names) if a < t_check <= b]
                source = f"last impact before its hold through t = {t_check:.6g}"
            else:
                hold = [(a, b) for a, b, last in holds(end_run, names) if last]
                source = "last impact before its hold to the end"
            if not hold:
                continue
            t_last = hold[0][0] + 1.5 * scheme["h"]  # an impact is timed at its step's end
        times = [imp["t"] for imp in impacts
                 if set(imp["contacts"]) & set(names) and imp["t"] <= t_last]
        if times:
            out.append({"contacts": names, "t": max(times), "source": source})
    return out


def siconos_liftoffs(model, run):
    """Time-stepping: a lift-off ends a hold of a contact (HOLD_STEPS) before the run's last
    step; its time is the end of the hold's last step. Event-driven runs: none computed."""
    events = run.get("events") or []
    if not events or "k" not in events[0]:
        return None
    out = []
    for c in model["constraints"]:
        out += [{"t": b, "contacts": [c["name"]]} for _, b, last in holds(run, [c["name"]])
                if not last]
    return sorted(out, key=lambda x: x["t"])


def outcome_text(status, t_reached):
    if status == "finished":
        return "finished"
    where = f" at t = {t_reached:.6g}" if isinstance(t_reached, (int, float)) else ""
    return f"{status}{where}"


def zenosim_friction(model, out_dir):
    """zenosim's friction events from its trajectory.csv: the state of each constraint with
    friction row by row (open, stick, or slip with the sign of the slip, from the mode and the
    sign of f_<name>: fₜ opposes the slip), and each change between two held states: "stick"
    (from slipping), "slip" (from sticking), "reversal" (slip to slip of the other sign)."""
    import csv
    names = [c["name"] for c in model["constraints"] if c.get("slip")]
    path = os.path.join(out_dir or "", "trajectory.csv")
    if not names or not os.path.exists(path):
        return None
    out, prev = [], {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            parts = row["mode"].split(";")
            held = set(parts[0].split(":", 1)[1].split("+")) if ":" in parts[0] else set()
            sticking = set()
            for part in parts[1:]:
                if part.startswith("stick:"):
                    sticking = set(part[len("stick:"):].split("+"))
            t = float(row["t"])
            for c in names:
                if c not in held:
                    st = "open"
                elif c in sticking:
                    st = "stick"
                else:
                    st = "slip+" if float(row[f"f_{c}"]) < 0 else "slip-"
                before = prev.get(c)
                if before not in (None, "open") and st != "open" and st != before:
                    kind = ("stick" if st == "stick" else "slip" if before == "stick"
                            else "reversal")
                    out.append({"t": t, "contact": c, "kind": kind, "from": before, "to": st})
                prev[c] = st
    return out


# A time-stepping run's stop between two slips of opposite signs lasting at most this many
# steps is a reversal (merge_short_stops).
STOP_STEPS = 2


def merge_short_stops(transitions, h):
    """A time-stepping run's friction events with its momentary stops merged: a stick of at
    most STOP_STEPS steps between two slips of opposite signs is the scheme's way through a
    reversal (the theta-method lands a step on x_dot = 0 where the relay's force can hold it
    there), one reversal at the stop's time. Longer stops, and stops between slips of the same
    sign, stay sticks."""
    out, pending = [], {}
    for ev in transitions:
        c = ev["contact"]
        if ev["kind"] == "stick":
            pending[c] = ev
            out.append(ev)
            continue
        stop = pending.pop(c, None)
        if (ev["kind"] == "slip" and stop is not None and stop["from"] != ev["to"]
                and ev["t"] - stop["t"] <= STOP_STEPS * h * (1 + 1e-9)):
            out.remove(stop)
            out.append({"t": stop["t"], "contact": c, "kind": "reversal",
                        "from": stop["from"], "to": ev["to"]})
            continue
        out.append(ev)
    return sorted(out, key=lambda e: e["t"])


def zenosim_liftoffs(summary):
    return [{"t": ev["t"], "contacts": peer.event_contacts(ev)}
            for ev in summary.get("events") or [] if ev.get("kind") == "liftoff"]


def zenosim_rows(model, ref, zenosim, args, workdir):
    rows = []
    window = reference_window(model, ref)
    bench, bench_error = peer.bench_zenosim(zenosim, model, args)
    for k, tol in enumerate(args.tolerances):
        zr = peer.run_zenosim(zenosim, model, tol, args, workdir)
        row = {"tool": "zenosim", "setting": f"tol {tol:g}", "tol": tol,
               "status": zr["status"], "reason": zr.get("reason"), "command": zr.get("command")}
        summary = zr.get("summary")
        t_reached = None
        if summary is not None:
            events = []
            for ev in peer.zenosim_impacts(summary):
                events.append(ev)
            impacts = impacts_event_driven(model, events)
            final = summary.get("final")
            compared = final
            if window is not None:
                # the state at the end of the reference's window: a run to that time
                wr = peer.run_zenosim(zenosim, model, tol, args, workdir, t_end=window)
                ws = wr.get("summary") or {}
                compared = ws.get("final") if wr["status"] == "finished" else None
                row["window_run"] = {"command": wr.get("command"), "status": wr["status"],
                                     "reason": wr.get("reason"), "final": ws.get("final")}
            friction = zenosim_friction(model, zr.get("out_dir"))
            row["metrics"] = metrics(model, ref, impacts, compared, peer.zenosim_zeno(summary),
                                     window=window, liftoffs=zenosim_liftoffs(summary),
                                     friction=friction)
            if friction is not None:
                row["friction_event_times"] = friction[:2000]
            row["final"] = final
            row["impact_times"] = [i["t"] for i in impacts][:2000]
            row["zeno_reported"] = summary.get("zeno")
            row["stats"] = summary.get("stats")
            t_reached = (final or {}).get("t")
        else:
            row["metrics"] = {}
        row["outcome"] = outcome_text(zr["status"], t_reached)
        if zr["status"] != "finished":
            reason = str(zr.get("reason"))
            row["note"] = reason if reason.startswith(zr["status"]) else f"{zr['status']}: {reason}"
        if bench is not None and k < len(bench.get("runs", [])):
            br = bench["runs"][k]
            row["wall_time_s"] = (br.get("wall_time_s") or {}).get("median")
            row["bench"] = {"status": br.get("status"), "wall_time_s": br.get("wall_time_s")}
        elif bench_error:
            row["bench_error"] = bench_error
        rows.append(row)
        log(f"suite: {model['name']} zenosim tol {tol:g}: {row['outcome']}")
    return rows


def run_scheme(spec, scheme, libs, args, workdir, timing=True):
    """One Siconos run of the scheme (D1Minus through the C++ runner), timed by repeats if
    timing; a dict as siconos_side.run_once's, or a "not run" one."""
    if scheme.get("osi") == "D1MinusLinearOSI":
        if args.d1minus_runner is None:
            try:
                args.d1minus_runner = siconos_side.compile_d1minus_runner(args.build_dir)
            except Exception as err:
                args.d1minus_runner = err
        if isinstance(args.d1minus_runner, Exception):
            return {"status": "not run", "reason": str(args.d1minus_runner)}
        return siconos_side.run_d1minus(args.d1minus_runner, spec, scheme, libs, workdir,
                                        args.timeout, args.repeat_below if timing else 0.0,
                                        args.min_time)
    if not timing:
        args = argparse.Namespace(**dict(vars(args), repeat_below=0.0))
    return run_siconos(spec, scheme, libs, args, workdir)


def siconos_rows(model, ref, example, spec, libs, args, workdir):
    rows = []
    window = reference_window(model, ref)
    base = example.SCHEME
    settings = []
    if base["kind"] == "ED":
        for variant in args.toled:
            for tol in args.tolerances:
                s = dict(base, tol=tol, toled=None if variant == "default" else tol)
                label = f"tol {tol:g}" + ("" if variant == "default" else f", TOL_ED {tol:g}")
                settings.append((label, s))
    else:
        for h in example.steps(base):
            s = dict(base, h=h)
            label = f"h {h:g}" + (" (example)" if h == base["h"] else "")
            settings.append((label, s))
    for label, scheme in settings:
        row = {"tool": "Siconos", "setting": label, "scheme": scheme}
        run = run_scheme(spec, scheme, libs, args, workdir)
        if run["status"] == "not run":
            row.update({"status": "not run", "outcome": "not run", "metrics": {},
                        "note": f"not run: {run['reason']}"})
            rows.append(row)
            continue
        events = run.get("events") or []
        if scheme["kind"] == "ED":
            evs = [{"t": e["t"], "q": join_state(spec, model, e["q"]),
                    "v_before": join_state(spec, model, e["v_before"]),
                    "v_after": join_state(spec, model, e["v_after"]),
                    "impulsed": [k for k, x in e["impulse"].items() if x > 0]}
                   for e in events if any(x > 0 for x in e["impulse"].values())]
            impacts = impacts_event_driven(model, evs)
        else:
            impacts = impacts_time_stepping(model, spec, events)
        final = None
        if run.get("final"):
            final = {"t": run["final"]["t"], "q": join_state(spec, model, run["final"]["q"]),
                     "q_dot": join_state(spec, model, run["final"]["q_dot"])}
        compared, end_run = final, run
        friction = run.get("friction_transitions")
        if friction is not None and scheme["kind"] == "TS":
            friction = merge_short_stops(friction, scheme["h"])
        if window is not None and run["status"] == "finished":
            # the state at the end of the reference's window: a run to that time
            end_run = run_scheme(dict(spec, t_end=window), scheme, libs, args, workdir,
                                 timing=False)
            compared = None
            if end_run.get("status") == "finished" and end_run.get("final"):
                compared = {"t": end_run["final"]["t"],
                            "q": join_state(spec, model, end_run["final"]["q"]),
                            "q_dot": join_state(spec, model, end_run["final"]["q_dot"])}
            row["window_run"] = {"status": end_run.get("status"),
                                 "reason": end_run.get("reason"), "final": compared}
        row["metrics"] = metrics(model, ref, impacts, compared,
                                 siconos_zeno(model, spec, scheme, run, impacts, ref, end_run),
                                 final_dt=scheme["h"] if scheme["kind"] == "TS" else 0.0,
                                 window=window, liftoffs=siconos_liftoffs(model, run),
                                 friction=friction)
        if friction is not None:
            row["friction_event_times"] = friction[:2000]
        row.update({"status": run["status"], "reason": run.get("reason"), "final": final,
                    "ns_events": run.get("ns_events"), "steps": run.get("steps"),
                    "newton_iterations": run.get("newton_iterations"),
                    "events_truncated": run.get("events_truncated"),
                    "siconos_output": run.get("siconos_output"),
                    "impact_times": [i["t"] for i in impacts][:2000],
                    "wall_time_s": (run.get("wall_time_s") or {}).get("median"),
                    "timing": run.get("wall_time_s")})
        row["outcome"] = outcome_text(run["status"], run.get("t_reached"))
        if run["status"] != "finished":
            msg = "; ".join(run.get("siconos_output") or [])
            row["note"] = f"{run['status']}: {run.get('reason')}" + \
                (f" — Siconos: {msg}" if msg else "")
        rows.append(row)
        log(f"suite: {model['name']} Siconos {label}: {row['outcome']}")
    return rows


# --------------------------------------------------------------------------------------------
# The report.

def fmt(x, digits=2):
    return peer.fmt(x, digits)


def table(results):
    lines = []
    m = results["machine"]
    lines.append("# zenosim and Siconos on Siconos's impact examples")
    lines.append("")
    lines.append(f"- date: {results['date']}")
    load = (f"load average before the runs {results['load_before']}, after "
            f"{results['load_after']}")
    if results.get("load_after_peer"):
        load = (f"load average (1, 5, 15 min) before the runs {results['load_before']}, after "
                f"the examples {results['load_after']}, after the peer models (Part 2) "
                f"{results['load_after_peer']}")
    lines.append(f"- machine: {m['cpu']}, {m['cores']} cores; {m['os']}; Python {m['python']}; "
                 + load)
    sv = results["siconos"]["version"]
    lines.append(f"- Siconos: Debian python3-siconos {sv.get('debian_package')} (its Python "
                 f"module says {sv.get('python_module')}); examples from siconos-tutorials "
                 f"{results['siconos']['examples_commit'][:12]}")
    zv = results["zenosim"]["version"] or {}
    git = zv.get("git", {})
    lines.append(f"- zenosim: {zv.get('version')}, commit {git.get('commit', '?')[:12]}"
                 + (f" with {git['uncommitted_engine_changes']} uncommitted files under crates/"
                    if git.get("uncommitted_engine_changes") else ""))
    lines.append(f"- zenosim: rtol = atol = tol; Siconos event-driven: LSODAR rtol = atol = tol, "
                 f"TOL_ED its default ({results['siconos']['toled_default']:.3g}) or tol; "
                 f"Siconos time-stepping: the example's integrator at the example's step h and "
                 f"others; wall-time limit {results['timeout_s']:g} s per run")
    for u in results.get("updates") or []:
        zc = ((u.get("zenosim") or {}).get("version") or {}).get("git", {}).get("commit", "?")
        lines.append(f"- {u['example']}: run again on {u['date']} (zenosim commit {zc[:12]}; "
                     f"load average {u['load_before']} before, {u['load_after']} after)")
    lines.append("")
    lines.append("Impacts: how many the tool had (per contact where several). Impact t: max "
                 "|t − t_ref| over the impacts matched with the reference's (per contact, the "
                 f"k-th with the k-th; n of them), then over the first {FIRST_IMPACTS}. Zeno: "
                 "|t − t_ref| per Zeno point of the reference (zenosim: its t_zeno; Siconos: "
                 "its last impact there, if the contact is closed after it: at the end, or "
                 "half-way to the reference's lift-off). Final: max-norm error of (q, q̇) at "
                 "t_end; where the reference stops earlier (a window: the slider-cranks), at "
                 "its end, from a run to that time, and only the impacts and lift-offs in the "
                 "window are matched; where it has only the state the motion ends in (rest), "
                 "against that. Wall: median of repeated in-process runs. README.md says how "
                 "each is computed.")
    for name in results["examples"]:
        ex = results["results"][name]
        lines.append("")
        lines.append(f"## {name}")
        lines.append("")
        lines.append(f"Siconos example: `{ex['example']}` ({ex['scheme_text']}). Model: "
                     f"`{ex['file']}`. Reference: `{ex['reference_file']}`"
                     + (f" ({ex['reference_method']})" if ex.get("reference_method") else "")
                     + ".")
        if ex.get("error"):
            lines.append("")
            lines.append(f"Not run: {ex['error']}")
            continue
        zr = ex["reference_summary"]
        ending = (f"final state at t = {zr['final_t']:g}" if zr["final_t"] is not None
                  else "no state at t_end, the state the motion ends in (rest)"
                  if zr.get("rest") else "no final state")
        lines.append(f"Reference: {zr['impacts']} impacts, Zeno points "
                     f"{zr['zeno'] or 'none'}"
                     + (f", lift-offs {zr['liftoffs']}" if zr.get("liftoffs") else "")
                     + (f", friction events {zr['friction']}" if zr.get("friction") else "")
                     + f", {ending}.")
        lines.append("")
        lifts = bool((ex.get("reference") or {}).get("liftoffs"))
        fric = (ex.get("reference") or {}).get("friction_events") is not None
        head = ["tool", "setting", "outcome", "impacts",
                f"impact t: max abs err (n); first {FIRST_IMPACTS}", "Zeno err"] \
            + (["lift-off err (n)"] if lifts else []) \
            + (["stick/slip events", "stick/slip t: max abs err (n)"] if fric else []) \
            + ["final err", "wall (ms)"]
        lines.append("| " + " | ".join(head) + " |")
        lines.append("|" + "---|" * len(head))
        for row in ex["rows"]:
            mt = row.get("metrics") or {}
            zeno = "; ".join(
                (f"{'+'.join(z['contacts'])} {fmt(z['error'])}" if z["error"] is not None
                 else f"{'+'.join(z['contacts'])} –") for z in mt.get("zeno", [])) or "–"
            per = mt.get("impacts_per_contact") or {}
            imp = ("–" if not mt else f"{mt.get('impacts', 0)}"
                   + (f" ({', '.join(f'{k} {v}' for k, v in per.items())})" if len(per) > 1
                      else ""))
            if mt.get("window") is not None:
                per = mt.get("impacts_in_window_per_contact") or {}
                imp = (f"{mt.get('impacts', 0)}; to {mt['window']:g}: "
                       f"{mt.get('impacts_in_window', 0)}"
                       + (f" ({', '.join(f'{k} {v}' for k, v in per.items())})" if len(per) > 1
                          else ""))
            err = mt.get("impact_time_max_error")
            errs = (f"{fmt(err)} ({mt.get('impacts_matched', 0)}); "
                    f"{fmt(mt.get('impact_time_max_error_first'))}" if err is not None else "–")
            wall = row.get("wall_time_s")
            wall_s = f"{wall * 1e3:.3g}" if isinstance(wall, (int, float)) else "–"
            if (row.get("timing") or {}).get("limit_hit"):
                wall_s = f"> {results['timeout_s'] * 1e3:g}"
            final = fmt(mt.get("final_state_error"))
            if mt.get("rest_state_error") is not None:
                final = f"{fmt(mt['rest_state_error'])} (rest)"
            lift = []
            if lifts:
                lift = ["–" if mt.get("liftoff_max_error") is None else
                        f"{fmt(mt['liftoff_max_error'])} ({len(mt.get('liftoff_errors') or [])})"]
            fr = []
            if fric:
                counts = mt.get("friction_events")
                fr = ["–" if counts is None else
                      (", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "none"),
                      "–" if mt.get("friction_event_max_error") is None else
                      f"{fmt(mt['friction_event_max_error'])} "
                      f"({mt.get('friction_events_matched', 0)})"]
            lines.append("| " + " | ".join([row["tool"], row["setting"], row["outcome"], imp,
                                            errs, zeno] + lift + fr + [final, wall_s]) + " |")
        for alt in (ex.get("reference") or {}).get("alternatives") or []:
            lines.append("")
            lines.append(f"Against the reference's alternative `{alt['name']}` "
                         f"({alt.get('description', '')}):")
            lines.append("")
            lines.append("| tool | setting | impact t: max abs err (n) | final err |")
            lines.append("|---|---|---|---|")
            for row in ex["rows"]:
                am = ((row.get("metrics") or {}).get("alternatives") or {}).get(alt["name"])
                if am is None:
                    continue
                err = am.get("impact_time_max_error")
                errs = "–" if err is None else f"{fmt(err)} ({am.get('impacts_matched', 0)})"
                lines.append(f"| {row['tool']} | {row['setting']} | {errs} | "
                             f"{fmt(am.get('final_state_error'))} |")
        notes = [r for r in ex["rows"] if r.get("note")]
        if notes:
            lines.append("")
            for r in notes:
                lines.append(f"- {r['tool']} {r['setting']}: {r['note']}")
        if ex.get("discussion"):
            lines.append("")
            lines.append(ex["discussion"])
    lines.append("")
    return "\n".join(lines)


def reference_summary(ref):
    zeno = ", ".join(f"{'+'.join(z.get('constraints') or z.get('contacts') or [])} "
                     f"{z['t']:.10g}" for z in ref.get("zeno") or [])
    lifts = ", ".join(f"{'+'.join(z.get('constraints') or z.get('contacts') or [])} "
                      f"{z['t']:.10g}" for z in ref.get("liftoffs") or [])
    counts = {}
    for ev in ref.get("friction_events") or []:
        counts[ev["kind"]] = counts.get(ev["kind"], 0) + 1
    friction = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
    return {"impacts": len(ref.get("impacts") or []), "zeno": zeno, "liftoffs": lifts,
            "friction": friction,
            "final_t": (ref.get("final") or {}).get("t"), "rest": bool(ref.get("rest"))}


# Lists of one record per impact (or lift-off), stored by column: {"contact": [...], "k": [...],
# "t": [...], ...}, the i-th record being the i-th entry of each column.
COLUMNAR = ("impact_errors", "liftoff_errors", "friction_event_errors")
# A value whose JSON is at most this long is written on one line.
LINE = 120


def by_columns(x):
    """x with every list under a COLUMNAR key, if it is a list of records with the same keys,
    stored by column (every number kept; a list already stored so is left as it is)."""
    if isinstance(x, dict):
        out = {}
        for k, v in x.items():
            if (k in COLUMNAR and isinstance(v, list) and v and all(isinstance(r, dict) for r in v)
                    and all(list(r) == list(v[0]) for r in v)):
                out[k] = {c: [r[c] for r in v] for c in v[0]}
            else:
                out[k] = by_columns(v)
        return out
    if isinstance(x, list):
        return [by_columns(v) for v in x]
    return x


def json_text(x, depth=0):
    """Compact JSON with line breaks: a value that fits in LINE characters, or a list of
    numbers and strings, on one line; otherwise one key (or item) per line."""
    flat = json.dumps(x, separators=(",", ":"), ensure_ascii=False, default=str)
    if len(flat) <= LINE or not isinstance(x, (dict, list)) or not x:
        return flat
    if isinstance(x, list) and not any(isinstance(v, (dict, list)) for v in x):
        return flat
    pad = " " * (depth + 1)
    if isinstance(x, dict):
        items = [pad + json.dumps(str(k), ensure_ascii=False) + ":" + json_text(v, depth + 1)
                 for k, v in x.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * depth + "}"
    items = [pad + json_text(v, depth + 1) for v in x]
    return "[\n" + ",\n".join(items) + "\n" + " " * depth + "]"


def write_json(results, path):
    with open(path, "w") as f:
        f.write(json_text(by_columns(results)))
        f.write("\n")


def load_avg():
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "?"


def examples_commit():
    return "b6c9bfd1940a69dae512a3e39cf5f1a951e3eebe"


def render(path, out):
    with open(path) as f:
        results = json.load(f)
    for name, ex in results["results"].items():
        if name in EXAMPLES:
            example = importlib.import_module(f"examples.{EXAMPLES[name]}")
            ex["discussion"] = getattr(example, "DISCUSSION", "").strip()
    md = table(results)
    if results.get("peer"):
        md += "\n" + peer.table(results["peer"]).replace("# zenosim against",
                                                         "# Part 2: zenosim against", 1)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write(md)
    write_json(results, path)
    log(f"suite: wrote {os.path.join(out, 'results.md')}")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--zenosim", default=os.path.join(ROOT, "target", "release", "zenosim"))
    parser.add_argument("--examples", default=",".join(EXAMPLES),
                        help=f"comma-separated [default: {','.join(EXAMPLES)}]")
    parser.add_argument("--models-dir", default=os.path.join(ROOT, "models", "siconos"),
                        help="where <name>.toml and references/<name>.json are "
                             "[default: models/siconos]")
    parser.add_argument("--tolerances", default=",".join(f"{t:g}" for t in TOLERANCES))
    parser.add_argument("--toled", default="default,scaled",
                        help="event-driven Siconos: TOL_ED default and/or scaled (= tol)")
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="wall-time limit of one run, seconds [default: 120]")
    parser.add_argument("--min-time", type=float, default=0.5)
    parser.add_argument("--repeat-below", type=float, default=2.0,
                        help="repeat a Siconos run for timing only if it took less [default: 2]")
    parser.add_argument("--no-zenosim", action="store_true")
    parser.add_argument("--no-peer", action="store_true",
                        help="leave out the three multi-contact models of peer.py")
    parser.add_argument("--out", default=HERE)
    parser.add_argument("--update", action="store_true",
                        help="run only --examples and put their results into the existing "
                             "results.json of --out (the rest, peer models included, kept)")
    parser.add_argument("--render", metavar="RESULTS_JSON",
                        help="only write results.md again from a results.json (with the "
                             "examples' current DISCUSSION paragraphs)")
    args = parser.parse_args()
    if args.render:
        return render(args.render, args.out)
    args.examples = [e for e in args.examples.split(",") if e]
    args.tolerances = [float(t) for t in args.tolerances.split(",") if t]
    args.toled = [v for v in args.toled.split(",") if v]

    import siconos.kernel as sk
    zenosim = os.path.abspath(args.zenosim)
    have_zenosim = not args.no_zenosim and os.access(zenosim, os.X_OK)
    results = {
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "machine": peer.machine(), "load_before": load_avg(),
        "siconos": {"version": peer.siconos_version(),
                    "toled_default": siconos_side.default_tol_ed(sk),
                    "examples_commit": examples_commit()},
        "zenosim": {"binary": zenosim,
                    "version": peer.zenosim_version(zenosim) if have_zenosim else None},
        "tolerances": args.tolerances, "timeout_s": args.timeout, "rest_threshold": REST,
        "examples": args.examples, "results": {},
    }
    workdir = tempfile.mkdtemp(prefix="zenosim-siconos-suite-")
    args.build_dir, args.d1minus_runner = workdir, None
    try:
        for name in args.examples:
            example = importlib.import_module(f"examples.{EXAMPLES[name]}")
            path = os.path.join(args.models_dir, f"{name}.toml")
            ref_path = os.path.join(args.models_dir, "references", f"{name}.json")
            ex = {"example": example.EXAMPLE, "scheme_text": example.SCHEME_TEXT,
                  "file": os.path.relpath(path, ROOT),
                  "reference_file": os.path.relpath(ref_path, ROOT),
                  "discussion": getattr(example, "DISCUSSION", "").strip(), "rows": []}
            results["results"][name] = ex
            if not os.path.exists(path) or not os.path.exists(ref_path):
                ex["error"] = "the model file or its reference is not there yet"
                log(f"suite: {name}: {ex['error']}")
                continue
            model = load_model(path)
            with open(ref_path) as f:
                ref = json.load(f)
            ex["reference_method"] = ref.get("method")
            ex["reference_summary"] = reference_summary(ref)
            ex["reference"] = {k: ref.get(k) for k in ("example", "commit", "model", "method",
                                                      "accuracy", "notes", "final", "zeno",
                                                      "liftoffs", "rest", "friction_events")}
            if ref.get("alternatives"):
                ex["reference"]["alternatives"] = [
                    {k: a.get(k) for k in ("name", "description", "final")}
                    for a in ref["alternatives"]]
            try:
                spec = example.spec(model)
                spec["name"] = name
                libs = siconos_side.compile_plugins(spec, workdir)
                plugins = siconos_side.PluginEval(libs)
                ex["siconos_model_check"] = check_spec(model, spec, plugins, example)
            except Exception as err:  # a model that does not match is reported, not run
                ex["error"] = f"{type(err).__name__}: {err}"
                log(f"suite: {name}: {ex['error']}")
                continue
            ex["siconos_model"] = spec
            log(f"suite: {name}: the Siconos model matches the file (largest relative "
                f"differences {', '.join(f'{k} {v:.1e}' for k, v in ex['siconos_model_check'].items())})")
            if have_zenosim:
                ex["rows"] += zenosim_rows(model, ref, zenosim, args, workdir)
            ex["rows"] += siconos_rows(model, ref, example, spec, libs, args, workdir)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    results["load_after"] = load_avg()
    if args.update:
        with open(os.path.join(args.out, "results.json")) as f:
            old = json.load(f)
        for name in args.examples:
            old["results"][name] = results["results"][name]
            if name not in old["examples"]:  # a new example: its table after the others
                old["examples"].append(name)
            old.setdefault("updates", []).append(
                {"example": name, "date": results["date"], "load_before": results["load_before"],
                 "load_after": results["load_after"], "zenosim": results["zenosim"]})
        write_json(old, os.path.join(args.out, "results.json"))
        return render(os.path.join(args.out, "results.json"), args.out)
    md = table(results)
    if not args.no_peer:
        peer_args = argparse.Namespace(
            zenosim=zenosim, models=peer.MODELS, tolerances=args.tolerances,
            toled=args.toled, toled_scale=1.0, timeout=min(args.timeout, 60.0),
            min_time=args.min_time, repeat_below=args.repeat_below,
            no_zenosim=args.no_zenosim, out=None, child=None)
        peer_results = peer.run_all(peer_args)
        results["peer"] = peer_results
        results["load_after_peer"] = load_avg()
        md = table(results)
        md += "\n" + peer.table(peer_results).replace("# zenosim against", "# Part 2: zenosim against", 1)
    print(md)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write(md)
    write_json(results, os.path.join(args.out, "results.json"))
    log(f"suite: wrote {os.path.join(args.out, 'results.md')} and results.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
