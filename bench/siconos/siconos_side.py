"""The Siconos side of the example suite: build a Siconos model from a spec (a plain dict that an
example module under examples/ writes from the model file), run it with the example's scheme,
and record what the metrics need. Also evaluates a spec in Python (ctypes for the C plugins), so
that suite.py can check it against the model file before any run.

A spec:

  {"t0", "t_end",
   "ds": [ {"kind": "linear", "coords": [file coordinate per dof], "q0", "v0",
            "mass": [[..]], "K": [[..]] (optional), "fext": [..]},
           {"kind": "plugin", "coords", "q0", "v0", "plugin": KEY,
            "functions": {"mass", "FGyr", "jacobianFGyrq", "jacobianFGyrqDot", "FInt",
                          "jacobianFIntq", "jacobianFIntqDot"} (those the example uses),
            "fext": [..] (optional)},
            ("class": "LagrangianDS" makes it a LagrangianDS with that constant mass matrix,
             no K),
           {"kind": "driven", ... as "linear", "boundary": {"dofs": [..], "plugin": KEY,
            "function": NAME}}  (a body whose velocity is prescribed: not in the file),
           {"kind": "first_order", "coords": [file coordinates], "positions": [index in x or
            None per coordinate], "velocities": [the same], "x0", "A", "M" (optional),
            "b": {"plugin": KEY, "function": NAME} (optional)}  (x' = A x + b(t) + r, or
            M x' = ..., a FirstOrderLinearTIDS or, with M or b, a FirstOrderLinearDS; a
            coordinate without an index is held at 0 by a contact the file has and Siconos
            does not) ],
   "interactions": [ {"name", "e", "ds": [indices],
                      "friction": {"mu", "et"} (optional: NewtonImpactFrictionNSL(e, et, mu, 2),
                                   and the relation has two rows, normal then tangential),
                      "relay": [lb, ub] (instead of e: RelayNSL(1, lb, ub) on a first-order DS),
                      "relation": {"kind": "linear", "C": [[..]], "offset": [..]}
                               or {"kind": "scleronomous", "plugin": KEY, "h", "G0",
                                   "dotG0" (optional)}
                               or {"kind": "first_order_linear", "C": [[..]], "B": [[..]]}} ],
   "stick_velocity": a slip speed below which a held contact sticks (time-stepping: the
                     friction states of each step, from which its stick/slip transitions),
   "plugins": {KEY: {"source": file under bench/siconos/plugins, "defines": {NAME: number}}}}

Every number of a spec comes from the model file; the plugins' parameters are compiled in as
-D defines (written with 17 significant digits).

A scheme:
  {"kind": "ED", "h": step of the TimeDiscretisation (its time events), "tol": rtol = atol of
   LsodarOSI, "toled": TOL_ED or None}
  {"kind": "TS", "osi": "MoreauJeanOSI", "theta", "gamma" (optional), "h",
   "newton_tol" (optional), "newton_max_iter" (optional),
   "problem": "LCP" (default), "FrictionContact" or "Relay", "solver" (a numerics solver id
   or its name in siconos.numerics, optional), "solver_tol", "solver_max_iter" (optional),
   "newton_linear" (optional: setNewtonOptions(SICONOS_TS_LINEAR))}
  {"kind": "TS", "osi": "EulerMoreauOSI", "theta", "h", "problem": "Relay", ...}  (first order)
"""

import ctypes
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
PLUGIN_DIR = os.path.join(HERE, "plugins")
# Events of a Siconos run kept in full (time-stepping: every step with an impulse, from which
# the impacts are counted; a run with more says so, events_truncated).
KEEP_EVENTS = 100000
# An event-driven run stops as stalled after this many non-smooth events.
MAX_NS_EVENTS = 200000


# --------------------------------------------------------------------------------------------
# Plugins: compiled at run time, parameters from the model file as -D defines.

def compile_plugins(spec, workdir):
    """Compiles every plugin of the spec; returns {KEY: library path without .so} or raises."""
    libs = {}
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    for key, p in (spec.get("plugins") or {}).items():
        if not cc:
            raise RuntimeError("no C compiler (cc) for the Siconos plugins")
        src = os.path.join(PLUGIN_DIR, p["source"])
        lib = os.path.join(workdir, f"{spec['name']}-{key}")
        defines = [f"-D{k}={v!r}" if isinstance(v, str) else f"-D{k}={float(v):.17g}"
                   for k, v in sorted(p.get("defines", {}).items())]
        cmd = [cc, "-O2", "-shared", "-fPIC", *defines, "-o", lib + ".so", src, "-lm"]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"the plugin {p['source']} did not compile: "
                               f"{proc.stderr.strip()[:500]}")
        libs[key] = lib  # Siconos appends ".so" to the name it is given
    return libs


class PluginEval:
    """The C plugins of a spec called through ctypes: what Siconos is given, evaluated in
    Python for the check against the model file. Signatures of Siconos 4.4 (PluginTypes.hpp):
    mass FPtr7 (n, q, M, nz, z); FGyr FPtr5 (n, q, v, out, nz, z); FInt FPtr6 (t, n, q, v,
    out, nz, z); h, G0 FPtr3 (n, q, ny, out, nz, z); dotG0 FPtr2 (n, q, nv, v, out, nz, z);
    prescribed velocity (t, n, out). Matrices are column-major."""

    def __init__(self, libs):
        self.libs = {k: ctypes.CDLL(v + ".so") for k, v in libs.items()}

    @staticmethod
    def _arr(xs):
        return (ctypes.c_double * max(1, len(xs)))(*xs)

    def jacobian(self, key, name, q, rows):
        """A relation's G0 with `rows` rows (Siconos passes the size of y), row by row."""
        f = getattr(self.libs[key], name)
        n = ctypes.c_uint
        size = rows * len(q)
        out = (ctypes.c_double * size)()
        z = (ctypes.c_double * 1)()
        f(n(len(q)), self._arr(q), n(rows), out, n(0), z)
        return [[out[r + rows * j] for j in range(len(q))] for r in range(rows)]

    def call(self, key, name, kind, q=(), v=(), t=0.0, out_size=1):
        f = getattr(self.libs[key], name)
        n = ctypes.c_uint
        out = (ctypes.c_double * out_size)()
        z = (ctypes.c_double * 1)()
        if kind == "mass" or kind == "h":
            if kind == "mass":
                f(n(len(q)), self._arr(q), out, n(0), z)
            else:
                f(n(len(q)), self._arr(q), n(out_size), out, n(0), z)
        elif kind == "gyr":
            f(n(len(q)), self._arr(q), self._arr(v), out, n(0), z)
        elif kind == "int":
            f(ctypes.c_double(t), n(len(q)), self._arr(q), self._arr(v), out, n(0), z)
        elif kind == "dotG":
            f(n(len(q)), self._arr(q), n(len(v)), self._arr(v), out, n(0), z)
        elif kind == "velocity":
            f(ctypes.c_double(t), n(out_size), out)
        elif kind == "b":  # a first-order DS's b(t): (t, n, b, nz, z)
            f(ctypes.c_double(t), n(out_size), out, n(0), z)
        else:
            raise ValueError(kind)
        return list(out)


def ds_sizes(spec):
    return [len(d["q0"]) for d in spec["ds"]]


def evaluate(spec, plugins, t, qs, vs):
    """The spec in Python at time t and the states qs, vs (one list per DS): per DS the mass
    matrix and the force F = fext - fint - fgyr - K q (M q'' = F + contact forces); per
    interaction h and dh/dq over the concatenated q of its DSs (for a driven DS its dofs follow
    the prescribed motion: h and dh/dq are taken with the driven DS's state as given)."""
    out = {"mass": [], "force": [], "h": {}, "jac": {}}
    for d, q, v in zip(spec["ds"], qs, vs):
        n = len(q)
        if d["kind"] in ("linear", "driven"):
            mass = [list(r) for r in d["mass"]]
            force = list(d.get("fext", [0.0] * n))
            for i in range(n):
                for j in range(n):
                    force[i] -= (d.get("K") or [[0.0] * n] * n)[i][j] * q[j]
        else:
            fn = d["functions"]
            m = plugins.call(d["plugin"], fn["mass"], "mass", q=q, out_size=n * n)
            mass = [[m[i + n * j] for j in range(n)] for i in range(n)]
            force = list(d.get("fext", [0.0] * n))
            if "FGyr" in fn:
                g = plugins.call(d["plugin"], fn["FGyr"], "gyr", q=q, v=v, out_size=n)
                force = [a - b for a, b in zip(force, g)]
            if "FInt" in fn:
                g = plugins.call(d["plugin"], fn["FInt"], "int", q=q, v=v, t=t, out_size=n)
                force = [a - b for a, b in zip(force, g)]
        out["mass"].append(mass)
        out["force"].append(force)
    out["tangent"] = {}
    for it in spec["interactions"]:
        if it["relation"]["kind"] == "first_order_linear":
            continue  # no h: the example's own check (check_spec)
        qcat = [x for i in it["ds"] for x in qs[i]]
        r = it["relation"]
        rows = 2 if it.get("friction") else 1
        if r["kind"] == "linear":
            h = sum(a * b for a, b in zip(r["C"][0], qcat)) + (r.get("offset") or [0.0])[0]
            jac = [list(row) for row in r["C"][:rows]]
        else:
            h = plugins.call(r["plugin"], r["h"], "h", q=qcat, out_size=1)[0]
            if rows == 1:
                jac = [plugins.call(r["plugin"], r["G0"], "h", q=qcat, out_size=len(qcat))]
            else:
                jac = plugins.jacobian(r["plugin"], r["G0"], qcat, rows)
        out["h"][it["name"]] = h
        out["jac"][it["name"]] = jac[0]
        if rows == 2:
            out["tangent"][it["name"]] = jac[1]
    return out


# --------------------------------------------------------------------------------------------
# Building and running.

def build(sk, spec, scheme, libs):
    import numpy as np
    import siconos.numerics as sn
    t0, t_end = spec.get("t0", 0.0), spec["t_end"]
    nsds = sk.NonSmoothDynamicalSystem(t0, t_end)
    dss = []
    for d in spec["ds"]:
        if d["kind"] == "first_order":
            x0 = np.array(d["x0"], dtype=float)
            A = np.array(d["A"], dtype=float)
            if d.get("M") is None and d.get("b") is None:
                ds = sk.FirstOrderLinearTIDS(x0, A)
            else:
                ds = sk.FirstOrderLinearDS(x0, A)
                if d.get("M") is not None:
                    ds.setMPtr(np.array(d["M"], dtype=float))
                if d.get("b") is not None:
                    ds.setComputebFunction(libs[d["b"]["plugin"]], d["b"]["function"])
            nsds.insertDynamicalSystem(ds)
            dss.append(ds)
            continue
        q0 = np.array(d["q0"], dtype=float)
        v0 = np.array(d["v0"], dtype=float)
        if d["kind"] == "linear" and d.get("class") == "LagrangianDS":
            # a LagrangianDS with a constant mass matrix, as an example may write it
            ds = sk.LagrangianDS(q0, v0, np.array(d["mass"], dtype=float))
        elif d["kind"] in ("linear", "driven"):
            ds = sk.LagrangianLinearTIDS(q0, v0, np.array(d["mass"], dtype=float))
            if d.get("K") is not None:
                ds.setKPtr(np.array(d["K"], dtype=float))
        else:
            fn = d["functions"]
            lib = libs[d["plugin"]]
            ds = sk.LagrangianDS(q0, v0, f"{lib}:{fn['mass']}")
            for key, setter in (("FGyr", "setComputeFGyrFunction"),
                                ("jacobianFGyrq", "setComputeJacobianFGyrqFunction"),
                                ("jacobianFGyrqDot", "setComputeJacobianFGyrqDotFunction"),
                                ("FInt", "setComputeFIntFunction"),
                                ("jacobianFIntq", "setComputeJacobianFIntqFunction"),
                                ("jacobianFIntqDot", "setComputeJacobianFIntqDotFunction")):
                if key in fn:
                    getattr(ds, setter)(lib, fn[key])
        if d.get("fext") is not None:
            ds.setFExtPtr(np.array(d["fext"], dtype=float))
        if d["kind"] == "driven":
            b = d["boundary"]
            bc = sk.BoundaryCondition(list(b["dofs"]))
            bc.setComputePrescribedVelocityFunction(libs[b["plugin"]], b["function"])
            ds.setBoundaryConditions(bc)
        nsds.insertDynamicalSystem(ds)
        dss.append(ds)
    inters = []
    for it in spec["interactions"]:
        r = it["relation"]
        if r["kind"] == "linear":
            rel = sk.LagrangianLinearTIR(np.array(r["C"], dtype=float),
                                         np.array(r.get("offset") or [0.0], dtype=float))
        elif r["kind"] == "first_order_linear":
            rel = sk.FirstOrderLinearR(np.array(r["C"], dtype=float),
                                       np.array(r["B"], dtype=float))
        else:
            lib = libs[r["plugin"]]
            if r.get("dotG0"):
                rel = sk.LagrangianScleronomousR(f"{lib}:{r['h']}", f"{lib}:{r['G0']}",
                                                 f"{lib}:{r['dotG0']}")
            else:
                rel = sk.LagrangianScleronomousR(f"{lib}:{r['h']}", f"{lib}:{r['G0']}")
        if it.get("relay") is not None:
            law = sk.RelayNSL(1, float(it["relay"][0]), float(it["relay"][1]))
        elif it.get("friction") is not None:
            fr = it["friction"]
            law = sk.NewtonImpactFrictionNSL(it["e"], fr.get("et", 0.0), fr["mu"], 2)
        else:
            law = sk.NewtonImpactNSL(it["e"])
        inter = sk.Interaction(law, rel)
        if len(it["ds"]) == 1:
            nsds.link(inter, dss[it["ds"][0]])
        else:
            nsds.link(inter, dss[it["ds"][0]], dss[it["ds"][1]])
        inters.append((it["name"], inter))
    td = sk.TimeDiscretisation(t0, scheme["h"])
    if scheme["kind"] == "ED":
        sim = sk.EventDriven(nsds, td)
        osi = sk.LsodarOSI()
        osi.setTol(1, scheme["tol"], scheme["tol"])
        sim.insertIntegrator(osi)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
        if scheme.get("toled") is not None:
            sim.setToleranceED(scheme["toled"])
    elif scheme["kind"] == "TS":
        if scheme["osi"] == "EulerMoreauOSI":
            osi = sk.EulerMoreauOSI(scheme["theta"])
        elif scheme["osi"] != "MoreauJeanOSI":
            raise ValueError(f"{scheme['osi']} is not in Siconos's Python bindings")
        elif scheme.get("gamma") is not None:
            osi = sk.MoreauJeanOSI(scheme["theta"], scheme["gamma"])
        else:
            osi = sk.MoreauJeanOSI(scheme["theta"])
        problem = scheme.get("problem", "LCP")
        if problem == "FrictionContact":
            osnspb = sk.FrictionContact(2)
        elif problem == "Relay":
            osnspb = sk.Relay()
        else:
            osnspb = sk.LCP()
        if scheme.get("solver") is not None:
            solver = scheme["solver"]
            osnspb.setSolverId(getattr(sn, solver) if isinstance(solver, str) else solver)
        options = osnspb.numericsSolverOptions()
        if scheme.get("solver_tol") is not None:
            options.dparam[sn.SICONOS_DPARAM_TOL] = scheme["solver_tol"]
        if scheme.get("solver_max_iter") is not None:
            options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = scheme["solver_max_iter"]
        sim = sk.TimeStepping(nsds, td, osi, osnspb)
        if scheme.get("newton_linear"):
            sim.setNewtonOptions(sk.SICONOS_TS_LINEAR)
        if scheme.get("newton_tol") is not None:
            sim.setNewtonTolerance(scheme["newton_tol"])
        if scheme.get("newton_max_iter") is not None:
            sim.setNewtonMaxIteration(scheme["newton_max_iter"])
    else:
        raise ValueError(scheme["kind"])
    return dss, inters, sim


def _state(np, dss, which, spec=None):
    """Per DS its positions (which = "q") or velocities ("velocity"); a first-order DS's are
    read off its state x through the spec's "positions" and "velocities" (a coordinate
    without an index is held at 0)."""
    out = []
    for k, ds in enumerate(dss):
        d = (spec or {}).get("ds", [{}] * len(dss))[k]
        if d.get("kind") == "first_order":
            x = np.array(ds.x())
            idx = d["positions"] if which == "q" else d["velocities"]
            out.append([float(x[i]) if i is not None else 0.0 for i in idx])
        else:
            out.append(list(np.array(getattr(ds, which)())))
    return out


def _impulses(inters, spec):
    """The normal impulse of each interaction in the step (0 for a relay, which has none)."""
    relay = {it["name"] for it in spec["interactions"] if it.get("relay") is not None}
    return {name: (0.0 if name in relay else float(it.lambda_(1)[0])) for name, it in inters}


def _friction_states(np, dss, inters, spec):
    """The friction state of each frictional interaction at the end of a step: "open" (no
    normal impulse), "stick" (a slip speed at most spec["stick_velocity"]), "slip+" or
    "slip-" (the sign of Siconos's tangential velocity). A relay (a first-order DS's Coulomb
    law with a given normal force) is always held; its slip is its output C x."""
    eps = spec.get("stick_velocity", 0.0)
    out = {}
    specs = {it["name"]: it for it in spec["interactions"]}
    for name, inter in inters:
        it = specs[name]
        if it.get("relay") is not None:
            k = it["ds"][0]
            x = np.array(dss[k].x())
            u = float(sum(c * xi for c, xi in zip(it["relation"]["C"][0], x)))
        elif it.get("friction") is not None:
            if not float(inter.lambda_(1)[0]) > 0:
                out[name] = "open"
                continue
            u = float(inter.y(1)[1])
        else:
            continue
        out[name] = "stick" if abs(u) <= eps else ("slip+" if u > 0 else "slip-")
    return out


def run_once(sk, spec, scheme, libs, progress_path=None, keep=True):
    """One run from t0 to t_end. Events (ED: every non-smooth event; TS: every step with an
    impulse on some contact) with the state before and after."""
    import numpy as np
    t_end = spec["t_end"]
    start = time.perf_counter()
    dss, inters, sim = build(sk, spec, scheme, libs)
    status, reason, stage = "finished", None, "initialize"
    events, n_ns, n_steps, transitions = [], 0, 0, []
    last_progress = start - 1.0
    truncated = False
    try:
        sim.initialize()
        if scheme["kind"] == "ED":
            em = sim.eventsManager()
            while sim.hasNextEvent() and sim.startingTime() < t_end * (1 - 1e-14):
                stage = "advanceToEvent"
                sim.advanceToEvent()
                nonsmooth = em.nextEvent().getType() == sk.NS_EVENT
                stage = "processEvents"
                sim.processEvents()
                n_steps += 1
                if nonsmooth:
                    n_ns += 1
                    if keep and len(events) < KEEP_EVENTS:
                        events.append({
                            "t": sim.startingTime(),
                            "q": [list(np.array(ds.qMemory().getSiconosVector(1)))
                                  for ds in dss],
                            "v_before": [list(np.array(ds.velocityMemory().getSiconosVector(1)))
                                         for ds in dss],
                            "v_after": _state(np, dss, "velocity"),
                            "impulse": {name: float(it.lambda_(1)[0]) for name, it in inters}})
                    elif keep:
                        truncated = True
                    if n_ns >= MAX_NS_EVENTS:
                        status, reason = "stalled", f"{n_ns} non-smooth events (the cap)"
                        break
                now = time.perf_counter()
                if progress_path and now - last_progress > 0.25:
                    last_progress = now
                    with open(progress_path, "w") as f:
                        json.dump({"t": sim.startingTime(), "ns_events": n_ns}, f)
            if status == "finished" and sim.startingTime() < t_end * (1 - 1e-12):
                status, reason = "failed", "no event left before t_end"
        else:
            tracked = any(it.get("friction") is not None or it.get("relay") is not None
                          for it in spec["interactions"])
            # the friction states before the first step are not known (a contact at rest
            # at t0 sticks or slips as the first step decides): no event at the first step
            grips = {}
            while sim.hasNextEvent():
                q_before = _state(np, dss, "q", spec) if keep else None
                v_before = _state(np, dss, "velocity", spec) if keep else None
                t_before = sim.startingTime()
                stage = "computeOneStep"
                sim.computeOneStep()
                n_steps += 1
                if keep and tracked:
                    states = _friction_states(np, dss, inters, spec)
                    for name, st in states.items():
                        before = grips.get(name)
                        kind = None
                        if before not in (None, "open") and st != "open" and st != before:
                            kind = ("stick" if st == "stick" else "slip" if before == "stick"
                                    else "reversal")
                        if kind and len(transitions) < KEEP_EVENTS:
                            transitions.append({"t": sim.nextTime(), "contact": name,
                                                "kind": kind, "from": before, "to": st})
                    grips = states
                if keep:
                    imp = _impulses(inters, spec)
                    if any(x > 0 for x in imp.values()):
                        if len(events) < KEEP_EVENTS:
                            events.append({"k": n_steps, "t": sim.nextTime(),
                                           "t_start": t_before,
                                           "q": q_before,
                                           "q_after": _state(np, dss, "q", spec),
                                           "v_before": v_before,
                                           "v_after": _state(np, dss, "velocity", spec),
                                           "impulse": imp})
                        else:
                            truncated = True
                stage = "nextStep"
                sim.nextStep()
                now = time.perf_counter()
                if progress_path and now - last_progress > 0.25:
                    last_progress = now
                    with open(progress_path, "w") as f:
                        json.dump({"t": sim.startingTime(), "steps": n_steps}, f)
    except Exception as ex:  # Siconos throws std::exception with its text on stdout
        status, reason = "failed", f"{type(ex).__name__} '{ex}' in {stage}"
    wall = time.perf_counter() - start
    relay = {it["name"] for it in spec["interactions"] if it.get("relay") is not None}
    return {
        "status": status, "reason": reason, "t_reached": sim.startingTime(),
        "ns_events": n_ns, "steps": n_steps, "events": events, "events_truncated": truncated,
        "friction_transitions": transitions,
        "final": {"t": sim.startingTime(), "q": _state(np, dss, "q", spec),
                  "q_dot": _state(np, dss, "velocity", spec),
                  "lambda": {name: [float(x) for x in np.array(it.lambda_(0 if name in relay
                                                                        else 1))]
                             for name, it in inters}},
        "newton_iterations": (sim.getNewtonCumulativeNbIterations()
                              if scheme["kind"] == "TS" else None),
        "wall_time_s": wall,
    }


def child(job_path):
    with open(job_path) as f:
        job = json.load(f)
    import siconos.kernel as sk
    scheme = dict(job["scheme"])
    if scheme["kind"] == "ED" and scheme.get("toled") is None:
        scheme["toled_default"] = default_tol_ed(sk)
    run = run_once(sk, job["spec"], scheme, job["libs"], progress_path=job["progress"])
    times = [run["wall_time_s"]]
    if run["wall_time_s"] < job["repeat_below_s"]:
        timed, begin = [], time.perf_counter()
        while len(timed) < 3 or time.perf_counter() - begin < job["min_time"]:
            timed.append(run_once(sk, job["spec"], scheme, job["libs"],
                                  keep=False)["wall_time_s"])
            if len(timed) >= 1000:
                break
        times = timed
    run["wall_time_s"] = {"median": statistics.median(times), "min": min(times),
                          "max": max(times), "repeats": len(times),
                          "first": run["wall_time_s"]}
    with open(job["out"], "w") as f:
        json.dump(run, f)


def default_tol_ed(sk):
    nsds = sk.NonSmoothDynamicalSystem(0.0, 1.0)
    return sk.EventDriven(nsds, sk.TimeDiscretisation(0.0, 1.0)).toleranceED()


if __name__ == "__main__":
    child(sys.argv[1])


# --------------------------------------------------------------------------------------------
# D1MinusLinearOSI: not in the Python bindings; d1minus_runner.cpp, compiled at run time.

D1MINUS_TYPES = {"halfexplicit_acceleration_level": 0, "halfexplicit_velocity_level": 3}


def compile_d1minus_runner(workdir):
    """Compiles d1minus_runner.cpp against Siconos's kernel (Debian's libsiconos-kernel-dev,
    which python3-siconos brings); returns the binary's path or raises."""
    cxx = os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++")
    if not cxx:
        raise RuntimeError("no C++ compiler (c++) for d1minus_runner.cpp")
    exe = os.path.join(workdir, "d1minus_runner")
    cmd = [cxx, "-O2", "-std=c++17", "-I/usr/include/siconos", "-I/usr/include/siconos/kernel",
           "-I/usr/include/siconos/numerics", "-o", exe, os.path.join(HERE, "d1minus_runner.cpp"),
           "-lsiconos_kernel", "-lsiconos_numerics"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"d1minus_runner.cpp did not compile: {proc.stderr.strip()[-800:]}")
    return exe


def d1minus_job_text(spec, scheme, libs, repeats, progress, out):
    def nums(xs):
        return " ".join(f"{float(x):.17g}" for x in xs)

    lines = [f"{spec.get('t0', 0.0):.17g} {spec['t_end']:.17g} {scheme['h']:.17g} "
             f"{D1MINUS_TYPES[scheme.get('type', 'halfexplicit_acceleration_level')]}",
             f"{repeats} {progress} {out}", str(len(spec["ds"]))]
    for d in spec["ds"]:
        n = len(d["q0"])
        if d["kind"] == "linear":
            lines.append(f"0 {n} {nums(d['q0'])} {nums(d['v0'])}")
            lines.append(nums(x for row in d["mass"] for x in row))
            if d.get("K") is not None:
                lines.append("1 " + nums(x for row in d["K"] for x in row))
            else:
                lines.append("0")
            lines.append(nums(d.get("fext") or [0.0] * n))
        elif d["kind"] == "plugin":
            fn = d["functions"]
            names = [fn.get(k, "-") for k in ("FGyr", "jacobianFGyrq", "jacobianFGyrqDot",
                                              "FInt", "jacobianFIntq", "jacobianFIntqDot")]
            lines.append(f"1 {n} {nums(d['q0'])} {nums(d['v0'])}")
            lines.append(f"{libs[d['plugin']]} {fn['mass']} {' '.join(names)}")
            lines.append(("1 " + nums(d["fext"])) if d.get("fext") is not None else "0")
        else:
            raise ValueError(f"d1minus_runner: no {d['kind']} DS")
    lines.append(str(len(spec["interactions"])))
    for it in spec["interactions"]:
        r = it["relation"]
        head = f"{it['e']:.17g} {len(it['ds'])} {' '.join(str(i) for i in it['ds'])}"
        if r["kind"] == "linear":
            lines.append(f"{head} 0 {len(r['C'][0])} {nums(r['C'][0])} "
                         f"{(r.get('offset') or [0.0])[0]:.17g}")
        else:
            lines.append(f"{head} 1 {libs[r['plugin']]} {r['h']} {r['G0']} "
                         f"{r.get('dotG0') or '-'}")
    return "\n".join(lines) + "\n"


def run_d1minus(runner, spec, scheme, libs, workdir, timeout, repeat_below, min_time):
    """One D1Minus run (and its timing repeats) through the runner; the result as run_once's."""
    progress = os.path.join(workdir, "progress.json")
    out = os.path.join(workdir, "d1minus-out.json")
    job = os.path.join(workdir, "d1minus-job.txt")
    names = [it["name"] for it in spec["interactions"]]

    def once(repeats, limit):
        for p in (progress, out):
            if os.path.exists(p):
                os.remove(p)
        with open(job, "w") as f:
            f.write(d1minus_job_text(spec, scheme, libs, repeats, progress, out))
        try:
            proc = subprocess.run([runner, job], capture_output=True, text=True, timeout=limit)
        except subprocess.TimeoutExpired:
            return None, ""
        if not os.path.exists(out):
            return {"status": "crashed", "returncode": proc.returncode}, proc.stdout + proc.stderr
        with open(out) as f:
            return json.load(f), proc.stdout

    begin = time.perf_counter()
    res, text = once(1, timeout)
    if res is None or res.get("status") == "crashed":
        reached = None
        if os.path.exists(progress):
            try:
                with open(progress) as f:
                    reached = json.load(f).get("t")
            except (OSError, ValueError):
                reached = None
        elapsed = time.perf_counter() - begin
        status = "stalled" if res is None else "crashed"
        reason = (f"no t_end within the {timeout:g} s wall-time limit" if res is None
                  else f"the runner ended with status {res.get('returncode')} and no result")
        return {"status": status, "reason": reason, "t_reached": reached,
                "stdout": text[-2000:],
                "wall_time_s": {"median": elapsed, "repeats": 1, "limit_hit": res is None}}
    walls = list(res["wall_time_s"])
    if walls and walls[0] < repeat_below:
        repeats = max(3, min(1000, int(min_time / max(walls[0], 1e-6)) + 1))
        again, _ = once(repeats, timeout)
        if again is not None and again.get("wall_time_s"):
            walls = list(again["wall_time_s"])
    for ev in res["events"]:
        ev["impulse"] = dict(zip(names, ev["impulse"]))
        ev["force"] = dict(zip(names, ev["force"]))
    if res.get("final"):
        res["final"]["lambda"] = {n: v for n, v in zip(names, res["final"]["lambda"])}
    res["ns_events"] = None
    res["wall_time_s"] = {"median": statistics.median(walls) if walls else None,
                          "min": min(walls) if walls else None,
                          "max": max(walls) if walls else None, "repeats": len(walls)}
    res["siconos_stdout_tail"] = text[-2000:]
    return res
