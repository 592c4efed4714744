#!/usr/bin/env python3
"""The peer comparison: zenosim against scipy.integrate.solve_ivp on the shipped models.

Run it through bench/run (which builds zenosim and sets up the virtual environment), e.g.

    bench/run                 # the full grid (about 3 minutes on a 2-core machine)
    bench/run --quick         # a small grid, a few seconds
    bench/run --self-test     # only check the hand-written equations against zenosim
    bench/run --help

What the scipy side is: what a careful scipy user writes by hand.
  * The equations of motion, the impact law and the constrained (post-Zeno) dynamics are
    derived on paper and written out per model (scalar `math` inside the right-hand side, the
    fastest plain Python there is for a handful of states).
  * Impacts are terminal events of solve_ivp (event h(q), direction -1). At each event the
    paper's rule decides, on the state just before the impact: if |h| <= eps and |A qdot| <= eps,
    apply the paper's map R_inf for that model and integrate the constrained dynamics to t_end;
    otherwise apply the impact law and restart solve_ivp from the impact.
  * The restart trap (a segment restarted on the surface reports its own start as an event,
    because solve_ivp's sign test `g(t0) >= 0 and g(t1) <= 0` holds when g(t0) = 0 and a whole
    flight fits into the first step; brentq then returns t0): handled as users do, by
      1. event direction -1 (a departure is never an event),
      2. putting the restart state exactly on the surface's admissible side (y = 0,
         x3 = sin(x2), theta = +-pi/2 in floating point: h(q0) >= 0, never -1e-17, which
         would hide the next landing: "falls through the floor"),
      3. masking the segment's own start: the event function returns +1 at t == t_start (so a
         landing inside the first step is bracketed from the start, and the start is never a
         root),
      4. ignoring (counting as spurious, no reset) an event whose state moves away from the
         surface (A qdot >= 0): resetting it would flip the velocity into the surface.
  * Caps: at most --max-impacts events and --max-wall seconds per run (a SIGALRM timer); a run
    that hits either, that fails in solve_ivp, that falls through the surface or that reaches
    t_end without ever passing the Zeno point is recorded as failed, with the reason.

Errors (the reference of each is written into every output):
  * bouncing ball: |tau_inf estimate - t1 (1+e)/(1-e)|, t1 = sqrt(2 h0/g) (closed form);
    scipy's estimate is its switch time, zenosim's its reported t_zeno (t_switch also kept).
  * cart pendulum: relative error of p_x = (Mc+m) xdot + m l cos(theta) thetadot at t_end.
  * spherical pendulum: relative error of p_phi = m l^2 sin(theta)^2 phidot at t_end.
  * ball on sine (paper, and the authors' demo): max-norm error of the final state (q, qdot)
    against zenosim's own run at rtol = atol = 1e-13 (or the tightest that finishes); scipy's
    most accurate run is compared with that reference too, as an independent check.

Cost: wall time of the whole hand-written loop (time.perf_counter, repeated until at least
--min-time seconds and --min-repeats runs, median); right-hand-side evaluations (sum of nfev
over the segments); event-function evaluations counted apart.
"""

import argparse
import datetime
import json
import math
import os
import platform
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

DEFAULT_TOLERANCES = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
DEFAULT_EPSILONS = [1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10]
DEFAULT_METHODS = ["DOP853", "RK45"]
DEFAULT_MODELS = ["bouncing-ball", "ball-on-sine", "cart-pendulum", "spherical-pendulum",
                  "ball-on-sine-demo"]
HEADLINE_MODEL = "ball-on-sine"
HEADLINE_TOL = 1e-10
# How far (decades of tol and of ε) the match is refined above the grid's (see `refine`).
REFINE_DECADES = 2
# How many of the cheapest matches are timed again, one after the other (see `retime`).
RETIME = 4
REFERENCE_TOLERANCES = [1e-13, 1e-12, 1e-11]


def log(*parts):
    print(*parts, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# The models, written by hand. Each gives: the free equations of motion (closed form, scalar
# math), the constraint h, its gradient A, the impact law, the projection onto the surface used
# at restarts, the paper's R_inf, the constrained dynamics (closed form), and for the self-test
# the same mechanics in plain matrix form (M, F with M qddot = F, A, qdot' Hess(h) qdot).
# --------------------------------------------------------------------------------------------

class Model:
    """Common parts: state y = (q, qdot)."""

    coordinates = ()

    def __init__(self, parameters):
        self.p = dict(parameters)

    @property
    def n(self):
        return len(self.coordinates)

    # generic mechanics (numpy), used by the impact law and by the self-test
    def impact(self, y):
        """q+ = q, qdot+ = qdot - (1+e) (A qdot)/(A M^-1 A') M^-1 A'."""
        n = self.n
        q, qd = y[:n], y[n:]
        a = self.A(q)
        minv_at = np.linalg.solve(self.M(q), a)
        out = np.array(y, dtype=float)
        out[n:] = qd - (1.0 + self.p["e"]) * (a @ qd) / (a @ minv_at) * minv_at
        return out

    def accel_generic(self, y):
        n = self.n
        q, qd = y[:n], y[n:]
        return np.linalg.solve(self.M(q), self.F(q, qd))

    def constrained_accel_generic(self, y):
        """M qddot = F - A' lam, lam = (A M^-1 A')^-1 (Adot qdot + A M^-1 F)."""
        n = self.n
        q, qd = y[:n], y[n:]
        m = self.M(q)
        a = self.A(q)
        free = np.linalg.solve(m, self.F(q, qd))
        minv_at = np.linalg.solve(m, a)
        lam = (self.curvature(q, qd) + a @ free) / (a @ minv_at)
        return free - minv_at * lam

    def energy(self, y):
        n = self.n
        q, qd = y[:n], y[n:]
        return 0.5 * qd @ self.M(q) @ qd + self.V(q)


class BouncingBall(Model):
    coordinates = ("y",)

    def make_rhs(self):
        g = self.p["g"]

        def rhs(t, s):
            return [s[1], -g]
        return rhs

    def make_constrained_rhs(self):
        # lam = m (0 - g), qddot = -g - lam/m = 0: the ball rests on the floor.
        def rhs(t, s):
            return [s[1], 0.0]
        return rhs

    def h(self, q):
        return q[0]

    def h_columns(self, ys):
        return ys[0]

    def A(self, q):
        return np.array([1.0])

    def curvature(self, q, qd):
        return 0.0

    def M(self, q):
        return np.array([[self.p["m"]]])

    def F(self, q, qd):
        return np.array([-self.p["m"] * self.p["g"]])

    def V(self, q):
        return self.p["m"] * self.p["g"] * q[0]

    def a_qdot(self, y):
        return y[1]

    def project(self, y):
        y = np.array(y, dtype=float)
        y[0] = 0.0
        return y

    def r_inf(self, y):
        return np.array([0.0, 0.0])


class BallOnSine(Model):
    coordinates = ("x1", "x2", "x3")

    def make_rhs(self):
        g = self.p["g"]

        def rhs(t, s):
            return [s[3], s[4], s[5], 0.0, 0.0, -g]
        return rhs

    def make_constrained_rhs(self):
        g = self.p["g"]
        sin, cos = math.sin, math.cos

        def rhs(t, s):
            x2, v2 = s[1], s[4]
            c = cos(x2)
            # lam/m = (Adot qdot - A M^-1 N)/(A M^-1 A' m) = (sin(x2) v2^2 - g)/(1 + cos^2)
            lm = (sin(x2) * v2 * v2 - g) / (1.0 + c * c)
            # qddot = (0, 0, -g) - A' lam/m, A = (0, -cos x2, 1)
            return [s[3], v2, s[5], 0.0, c * lm, -g - lm]
        return rhs

    def h(self, q):
        return q[2] - math.sin(q[1])

    def h_columns(self, ys):
        return ys[2] - np.sin(ys[1])

    def A(self, q):
        return np.array([0.0, -math.cos(q[1]), 1.0])

    def curvature(self, q, qd):
        return math.sin(q[1]) * qd[1] ** 2

    def M(self, q):
        return self.p["m"] * np.eye(3)

    def F(self, q, qd):
        return np.array([0.0, 0.0, -self.p["m"] * self.p["g"]])

    def V(self, q):
        return self.p["m"] * self.p["g"] * q[2]

    def a_qdot(self, y):
        return y[5] - math.cos(y[1]) * y[4]

    def project(self, y):
        y = np.array(y, dtype=float)
        y[2] = math.sin(y[1])
        return y

    def r_inf(self, y):
        # The paper's map: (x1, x2, sin x2, x1dot, x2dot, cos(x2) x2dot).
        x1, x2, _, v1, v2, _ = y
        return np.array([x1, x2, math.sin(x2), v1, v2, math.cos(x2) * v2])


class FallingPendulum(Model):
    """A pendulum q = (θ, ·), θ from the upward vertical, stopped at the horizontal: h = cos θ
    (the cart's deck, the ground)."""

    def h(self, q):
        return math.cos(q[0])

    def h_columns(self, ys):
        return np.cos(ys[0])

    def A(self, q):
        return np.array([-math.sin(q[0]), 0.0])

    def curvature(self, q, qd):
        return -math.cos(q[0]) * qd[0] ** 2


class CartPendulum(FallingPendulum):
    """q = (theta, x), theta from the upward vertical, bob at (x + l sin, l cos)."""
    coordinates = ("theta", "x")

    def make_rhs(self):
        Mc, m, l, g = self.p["Mc"], self.p["m"], self.p["l"], self.p["g"]
        a, d = m * l * l, Mc + m
        sin, cos = math.sin, math.cos

        def rhs(t, s):
            th, wt = s[0], s[2]
            sn, cs = sin(th), cos(th)
            b = m * l * cs
            f1 = m * g * l * sn          # M qddot = F
            f2 = m * l * sn * wt * wt
            det = a * d - b * b
            return [wt, s[3], (d * f1 - b * f2) / det, (a * f2 - b * f1) / det]
        return rhs

    # The free accelerations are written out again here rather than computed by calling the
    # free rhs: a Python call per evaluation would slow the peer, which gets its best shot.
    def make_constrained_rhs(self):
        Mc, m, l, g = self.p["Mc"], self.p["m"], self.p["l"], self.p["g"]
        a, d = m * l * l, Mc + m
        sin, cos = math.sin, math.cos

        def rhs(t, s):
            th, wt = s[0], s[2]
            sn, cs = sin(th), cos(th)
            b = m * l * cs
            f1 = m * g * l * sn
            f2 = m * l * sn * wt * wt
            det = a * d - b * b
            tf = (d * f1 - b * f2) / det   # free accelerations
            xf = (a * f2 - b * f1) / det
            # A = (-sin, 0); M^-1 A' = (-d sin, b sin)/det; A M^-1 A' = d sin^2/det;
            # lam = (Adot qdot + A M^-1 F)/(A M^-1 A'), Adot qdot = -cos thetadot^2.
            lam = (-cs * wt * wt - sn * tf) / (d * sn * sn / det)
            return [wt, s[3], tf + d * sn * lam / det, xf - b * sn * lam / det]
        return rhs

    def M(self, q):
        Mc, m, l = self.p["Mc"], self.p["m"], self.p["l"]
        b = m * l * math.cos(q[0])
        return np.array([[m * l * l, b], [b, Mc + m]])

    def F(self, q, qd):
        m, l, g = self.p["m"], self.p["l"], self.p["g"]
        sn = math.sin(q[0])
        return np.array([m * g * l * sn, m * l * sn * qd[0] ** 2])

    def V(self, q):
        return self.p["m"] * self.p["g"] * self.p["l"] * math.cos(q[0])

    def a_qdot(self, y):
        return -math.sin(y[0]) * y[2]

    def project(self, y):
        y = np.array(y, dtype=float)
        y[0] = math.copysign(math.pi / 2, y[0])   # cos(fl(pi/2)) = 6e-17 > 0
        return y

    def r_inf(self, y):
        # The paper's map: (theta, x, thetadot, xdot) -> (sign(theta) pi/2, x, 0, xdot).
        return np.array([math.copysign(math.pi / 2, y[0]), y[1], 0.0, y[3]])

    def momentum(self, y):
        Mc, m, l = self.p["Mc"], self.p["m"], self.p["l"]
        return (Mc + m) * y[3] + m * l * math.cos(y[0]) * y[2]


class SphericalPendulum(FallingPendulum):
    """q = (theta, phi), theta from the upward vertical."""
    coordinates = ("theta", "phi")

    def make_rhs(self):
        gl = self.p["g"] / self.p["l"]
        sin, cos = math.sin, math.cos

        def rhs(t, s):
            th, wt, wp = s[0], s[2], s[3]
            sn, cs = sin(th), cos(th)
            return [wt, wp, sn * cs * wp * wp + gl * sn, -2.0 * cs / sn * wt * wp]
        return rhs

    def make_constrained_rhs(self):
        sin, cos = math.sin, math.cos

        def rhs(t, s):
            th, wt, wp = s[0], s[2], s[3]
            sn, cs = sin(th), cos(th)
            # lam = (Adot qdot + A M^-1 F)/(A M^-1 A'); M^-1 A' = (-sin/(m l^2), 0):
            # thetaddot = free + sin lam/(m l^2) = -cos thetadot^2/sin, phiddot as free.
            return [wt, wp, -cs * wt * wt / sn, -2.0 * cs / sn * wt * wp]
        return rhs

    def M(self, q):
        ml2 = self.p["m"] * self.p["l"] ** 2
        return np.diag([ml2, ml2 * math.sin(q[0]) ** 2])

    def F(self, q, qd):
        m, l, g = self.p["m"], self.p["l"], self.p["g"]
        sn, cs = math.sin(q[0]), math.cos(q[0])
        ml2 = m * l * l
        return np.array([ml2 * sn * cs * qd[1] ** 2 + m * g * l * sn,
                         -2.0 * ml2 * sn * cs * qd[0] * qd[1]])

    def V(self, q):
        return self.p["m"] * self.p["g"] * self.p["l"] * math.cos(q[0])

    def a_qdot(self, y):
        return -math.sin(y[0]) * y[2]

    def project(self, y):
        y = np.array(y, dtype=float)
        y[0] = math.copysign(math.pi / 2, y[0])
        return y

    def r_inf(self, y):
        # The paper's map: (theta, phi, thetadot, phidot) -> (pi/2, phi, 0, phidot).
        return np.array([math.pi / 2, y[1], 0.0, y[3]])

    def momentum(self, y):
        m, l = self.p["m"], self.p["l"]
        return m * l * l * math.sin(y[0]) ** 2 * y[3]


MODEL_CLASSES = {
    "bouncing-ball": BouncingBall,
    "ball-on-sine": BallOnSine,
    "ball-on-sine-demo": BallOnSine,
    "cart-pendulum": CartPendulum,
    "spherical-pendulum": SphericalPendulum,
}


# --------------------------------------------------------------------------------------------
# The scipy simulation: the hand-written loop.
# --------------------------------------------------------------------------------------------

class RunFailed(Exception):
    pass


class WallTimeout(Exception):
    pass


def _alarm(signum, frame):
    raise WallTimeout()


def simulate(model, y0, t_end, method, tol, eps, max_impacts):
    """One run of the hand-written loop. Returns a dict; raises RunFailed with the reason."""
    rhs = model.make_rhs()
    h = model.h
    n = model.n
    a_qdot = model.a_qdot
    t = 0.0
    y = np.array(y0, dtype=float)
    nfev = 0
    nev = 0
    impacts = 0
    spurious = 0
    segments = 0
    t_switch = None
    while t < t_end:
        t_start = t
        count = [0]

        def event(tt, s):
            count[0] += 1
            if tt == t_start:
                return 1.0          # the segment's own start is never a landing
            return h(s)
        event.terminal = True
        event.direction = -1

        sol = solve_ivp(rhs, (t, t_end), y, method=method, rtol=tol, atol=tol, events=event)
        segments += 1
        nfev += sol.nfev
        nev += count[0]
        if sol.status == -1:
            raise RunFailed(f"solve_ivp failed at t = {sol.t[-1]:.6g}: {sol.message}")
        lowest = float(np.min(model.h_columns(sol.y)))
        if lowest < -1e-6:
            raise RunFailed(f"fell through the surface (h = {lowest:.3g}) before "
                            f"t = {sol.t[-1]:.6g}")
        if sol.status == 1:
            t = float(sol.t_events[0][0])
            y = np.array(sol.y_events[0][0])
            hv, av = h(y[:n]), a_qdot(y)
            if abs(hv) <= eps and abs(av) <= eps:
                y = model.r_inf(y)
                t_switch = t
                break
            if av < 0.0:
                y = model.project(model.impact(y))
                impacts += 1
            else:
                spurious += 1      # leaving the surface: not an impact, no reset
            if impacts + spurious >= max_impacts:
                raise RunFailed(f"event storm: {impacts} impacts and {spurious} spurious "
                                f"events by t = {t:.9g} without the eps rule triggering")
        else:
            t = float(sol.t[-1])
            y = sol.y[:, -1]
    if t_switch is None:
        raise RunFailed(f"reached t_end after {impacts} impacts without passing the Zeno "
                        f"point (|A qdot| never <= eps at an impact)")
    if t_switch < t_end:
        sol = solve_ivp(model.make_constrained_rhs(), (t_switch, t_end), y, method=method,
                        rtol=tol, atol=tol)
        segments += 1
        nfev += sol.nfev
        if sol.status == -1:
            raise RunFailed(f"solve_ivp failed in the constrained mode: {sol.message}")
        y = sol.y[:, -1]
    return {"final": y, "t_switch": t_switch, "nfev": nfev, "event_evals": nev,
            "impacts": impacts, "spurious_events": spurious, "segments": segments}


def run_once(model, y0, t_end, method, tol, eps, max_impacts, max_wall):
    """One run under the wall-time cap: (result or None, wall seconds, failure message)."""
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, max_wall)
    start = time.perf_counter()
    try:
        result = simulate(model, y0, t_end, method, tol, eps, max_impacts)
        wall = time.perf_counter() - start
        return result, wall, None
    except WallTimeout:
        return None, time.perf_counter() - start, f"wall-time cap of {max_wall:g} s reached"
    except RunFailed as failure:
        return None, time.perf_counter() - start, str(failure)
    except Exception as failure:  # noqa: BLE001 - recorded, never hidden
        return None, time.perf_counter() - start, f"{type(failure).__name__}: {failure}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def timed(model, y0, t_end, method, tol, eps, args):
    """Run, then repeat until min_time and min_repeats; median wall time."""
    result, wall, failure = run_once(model, y0, t_end, method, tol, eps, args.max_impacts,
                                     args.max_wall)
    if failure is not None:
        return None, {"median": wall, "repeats": 1}, failure
    walls = [wall]
    while sum(walls) < args.min_time or len(walls) < args.min_repeats:
        start = time.perf_counter()
        simulate(model, y0, t_end, method, tol, eps, args.max_impacts)
        walls.append(time.perf_counter() - start)
    return result, {"median": statistics.median(walls), "min": min(walls), "max": max(walls),
                    "repeats": len(walls)}, None


def scipy_point(name, model, y0, t_end, method, tol, eps, args, err_fn, refined=False):
    """One scipy configuration, timed (`timed`), as a point of peer.json."""
    result, wall, failure = timed(model, y0, t_end, method, tol, eps, args)
    point = {"tool": "scipy", "model": name, "method": method, "tolerance": tol,
             "epsilon": eps, "wall_time_s": wall}
    if refined:
        point["refined"] = True
    tag = " (refinement)" if refined else ""
    if failure is None:
        err = err_fn(result["final"], result["t_switch"], result["t_switch"])
        point.update(status="ok", error=err, nfev=result["nfev"], rhs_evals=result["nfev"],
                     event_evals=result["event_evals"], impacts=result["impacts"],
                     spurious_events=result["spurious_events"], segments=result["segments"],
                     t_switch=result["t_switch"], final=np.asarray(result["final"]).tolist())
        log(f"   {method} tol {tol:g} eps {eps:g}{tag}: error {g3(err)}, "
            f"{tdur(wall['median'])} ({wall['repeats']}x), {result['nfev']} rhs, "
            f"{result['impacts']} impacts"
            + (f" + {result['spurious_events']} spurious" if result["spurious_events"] else ""))
    else:
        point.update(status="failed", reason=failure, error=None)
        log(f"   {method} tol {tol:g} eps {eps:g}{tag}: FAILED ({failure}) after "
            f"{tdur(wall['median'])}")
    return point


def one_two_five(low, high):
    """The values 1, 2, 5 × 10^k in [low, high] (up to rounding)."""
    out = []
    for k in range(math.floor(math.log10(low)) - 1, math.ceil(math.log10(high)) + 1):
        for m in (1, 2, 5):
            v = float(f"{m}e{k}")
            if low * (1 - 1e-9) <= v <= high * (1 + 1e-9):
                out.append(v)
    return out


def refine(name, model, y0, t_end, zerr, sp_points, args, err_fn):
    """A decade grid matches zenosim with a configuration up to 10x more accurate (and dearer)
    than needed, which flatters the ratio. So, per method, the grid's cheapest configuration
    that reaches zenosim's error `zerr` is the corner of a finer box: tol and ε each on the
    1-2-5 sequence up to `REFINE_DECADES` decades looser (ε at most the grid's largest). A
    method none of whose configurations reaches `zerr` gets its most accurate one's tol, a
    decade tighter on the same sequence (scipy may get there just past the grid). Every
    configuration found so that is not on the grid is run once; of those that reach `zerr`,
    the `args.refine` fastest (of all methods together) are timed like the grid's and returned
    as points (`"refined": true`)."""
    done = {(p["method"], f"{p['tolerance']:g}", f"{p['epsilon']:g}") for p in sp_points}
    candidates = []
    for method in args.methods:
        ok = [p for p in sp_points if p["method"] == method and p["status"] == "ok"]
        if not ok:
            continue
        reach = [p for p in ok if p["error"] <= zerr]
        if not reach:
            best = min(ok, key=lambda p: p["error"])
            for tol in one_two_five(best["tolerance"] / 10, best["tolerance"]):
                if (method, f"{tol:g}", f"{best['epsilon']:g}") not in done:
                    candidates.append((method, tol, best["epsilon"]))
            continue
        base = min(reach, key=lambda p: p["wall_time_s"]["median"])
        span = 10.0 ** REFINE_DECADES
        for tol in one_two_five(base["tolerance"], base["tolerance"] * span):
            for eps in one_two_five(base["epsilon"],
                                    min(base["epsilon"] * span, max(args.epsilons))):
                if (method, f"{tol:g}", f"{eps:g}") not in done:
                    candidates.append((method, tol, eps))
    log(f"== {name}: refining the match: {len(candidates)} configurations on a 1-2-5 grid, "
        f"each run once")
    passed = []
    for method, tol, eps in candidates:
        result, wall, failure = run_once(model, y0, t_end, method, tol, eps, args.max_impacts,
                                         args.max_wall)
        if failure is None:
            err = err_fn(result["final"], result["t_switch"], result["t_switch"])
            if err <= zerr:
                passed.append((wall, method, tol, eps))
    passed.sort()
    log(f"   {len(passed)} reach zenosim's error {g3(zerr)}; timing the "
        f"{min(len(passed), args.refine)} fastest")
    return [scipy_point(name, model, y0, t_end, method, tol, eps, args, err_fn, refined=True)
            for _, method, tol, eps in passed[:args.refine]]


# --------------------------------------------------------------------------------------------
# Errors.
# --------------------------------------------------------------------------------------------

def error_spec(name, params, initial_y, reference):
    """(panel title, error description, reference text, function of (final y, t_switch, t_zeno))."""
    if name == "bouncing-ball":
        e, g, h0 = params["e"], params["g"], params["h0"]
        t1 = math.sqrt(2 * h0 / g)
        tau = t1 * (1 + e) / (1 - e)
        return (f"bouncing ball (e = {e:g}): Zeno time",
                "|τ∞ − t₁(1+e)/(1−e)| (s)",
                f"closed form τ∞ = t₁(1+e)/(1−e) = {tau!r} s, t₁ = √(2h₀/g); scipy's estimate "
                f"is its switch time, zenosim's its reported t_zeno",
                lambda y, t_switch, t_zeno: abs(t_zeno - tau), tau)
    if name == "cart-pendulum":
        m = CartPendulum(params)
        p0 = float(m.momentum(initial_y))
        return ("cart pendulum (e = 0.9): conserved momentum p_x at t_end",
                "|p_x(t_end) − p_x(0)| / |p_x(0)|",
                f"p_x = (M_c+m)ẋ + m l cos θ θ̇ at the initial state = {p0!r} (conserved)",
                lambda y, t_switch, t_zeno: abs(m.momentum(y) - p0) / abs(p0), p0)
    if name == "spherical-pendulum":
        m = SphericalPendulum(params)
        p0 = float(m.momentum(initial_y))
        return ("spherical pendulum (e = 0.9): conserved momentum p_φ at t_end",
                "|p_φ(t_end) − p_φ(0)| / |p_φ(0)|",
                f"p_φ = m l² sin²θ φ̇ at the initial state = {p0!r} (conserved)",
                lambda y, t_switch, t_zeno: abs(m.momentum(y) - p0) / abs(p0), p0)
    # ball on sine: the reference run of zenosim
    ref_y, ref_tol, ref_t = reference
    title = ("ball on sine (paper, Example 6): final state at t = 6" if name == "ball-on-sine"
             else f"ball on sine (authors' demo, e = {params['e']:g}): final state at "
                  f"t = {ref_t:g}")
    return (title, "max |(q, q̇)(t_end) − reference|",
            f"zenosim's own run at rtol = atol = {ref_tol:g} (t = {ref_t:g})",
            lambda y, t_switch, t_zeno: float(np.max(np.abs(np.asarray(y) - ref_y))), None)


# --------------------------------------------------------------------------------------------
# zenosim's side.
# --------------------------------------------------------------------------------------------

def zenosim_bench(binary, model_path, tolerances, min_time, extra=()):
    """`zenosim bench`: its JSON report. Exit 1 (a run failed) still gives the report."""
    cmd = [binary, "bench", model_path, "--tolerances", ",".join(f"{t:g}" for t in tolerances),
           "--min-time", f"{min_time:g}", *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode not in (0, 1, 3) or not proc.stdout.strip():
        raise SystemExit(f"`{' '.join(cmd)}` failed (exit {proc.returncode}):\n{proc.stderr}")
    return json.loads(proc.stdout)


def zenosim_has(binary, subcommand):
    proc = subprocess.run([binary, subcommand, "--help"], capture_output=True, text=True)
    return proc.returncode == 0


def zenosim_run_report(binary, model_path, tolerances):
    """Fallback while `zenosim bench` does not exist: `zenosim run` per tolerance, timed as a
    whole process (start, load, output): an upper bound of zenosim's time, flagged."""
    runs = []
    top = None
    for tol in tolerances:
        with tempfile.TemporaryDirectory() as out:
            start = time.perf_counter()
            subprocess.run([binary, "run", model_path, "--rtol", f"{tol:g}", "--atol",
                            f"{tol:g}", "--out", out], capture_output=True, text=True)
            wall = time.perf_counter() - start
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
        kinds = [e["kind"] for e in s.get("events", [])]
        runs.append({"settings": s["settings"], "status": s["status"], "message": s["message"],
                     "final": s["final"], "zeno": s["zeno"],
                     "events": {k: kinds.count(k) for k in ("impact", "zeno", "liftoff")},
                     "stats": s["stats"],
                     "wall_time_s": {"median": wall, "min": wall, "max": wall, "repeats": 1,
                                     "timing": "process (fallback: zenosim bench missing)"}})
        top = s
    return {"zenosim": "?", "model": top["model"], "coordinates": top["coordinates"],
            "parameters": top["parameters"], "initial": top["initial"],
            "constraints": top["constraints"], "runs": runs, "fallback": True}


def final_state(run):
    return np.array(run["final"]["q"] + run["final"]["q_dot"], dtype=float)


# --------------------------------------------------------------------------------------------
# Self-test: the hand-written mechanics against zenosim.
# --------------------------------------------------------------------------------------------

def parse_check(text):
    """Numbers from `zenosim check`: energy, h, A qdot, mass matrix rows."""
    out = {"M": []}
    lines = text.splitlines()
    in_m = False
    for line in lines:
        s = line.strip()
        if s.startswith("mass matrix"):
            in_m = True
            continue
        if in_m and s.startswith("["):
            out["M"].append([float(v) for v in s.strip("[]").split()])
            continue
        in_m = False
        if s.startswith("energy"):
            out["energy"] = float(s.split()[1])
        elif s.startswith("h(q0)"):
            out["h"] = float(s.split("=")[1])
        elif s.startswith("A q̇"):
            out["A_qdot"] = float(s.split("=")[1])
    return out


def self_test(binary, model_files):
    log("self-test: the hand-written equations against zenosim")
    rng = np.random.default_rng(6)
    failures = []
    worst = {}

    def check(label, value, limit):
        key = label.split(":")[0]
        worst[key] = max(worst.get(key, 0.0), value)
        if not (value <= limit):
            failures.append(f"{label}: {value:.3g} > {limit:g}")

    for name, path in model_files.items():
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([binary, "run", path, "--out", out, "--rtol", "1e-12", "--atol",
                            "1e-12"], check=True, capture_output=True)
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
        model = MODEL_CLASSES[name](s["parameters"])
        if tuple(s["coordinates"]) != model.coordinates:
            raise SystemExit(f"{name}: zenosim's coordinates {s['coordinates']} are not "
                             f"{model.coordinates}")
        n = model.n
        y0 = np.array(s["initial"]["q"] + s["initial"]["q_dot"], dtype=float)
        names = list(s["coordinates"]) + [c + "_dot" for c in s["coordinates"]]
        # 1. M, h, A qdot, energy at the initial state and at random states, vs `zenosim check`
        states = [y0] + [y0 + rng.normal(0, 0.3, 2 * n) for _ in range(3)]
        for y in states:
            cmd = [binary, "check", path]
            for k, v in zip(names, y):
                cmd += ["--set", f"{k}={float(v)!r}"]
            c = parse_check(subprocess.run(cmd, check=True, capture_output=True,
                                           text=True).stdout)
            scale = max(1.0, abs(c["energy"]))
            check(f"energy vs zenosim check: {name}", abs(model.energy(y) - c["energy"]) / scale,
                  1e-12)
            check(f"h vs zenosim check: {name}", abs(model.h(y[:n]) - c["h"]), 1e-12)
            check(f"h vs zenosim check: {name} (vectorised)",
                  abs(float(model.h_columns(y[:, None])[0]) - c["h"]), 1e-12)
            check(f"A qdot vs zenosim check: {name}", abs(model.a_qdot(y) - c["A_qdot"]), 1e-12)
            mz = np.array(c["M"])
            check(f"M vs zenosim check: {name}",
                  float(np.max(np.abs(model.M(y[:n]) - mz)) / np.max(np.abs(mz))), 1e-12)
            # closed-form right-hand sides against the generic matrix form
            rhs, crhs = model.make_rhs(), model.make_constrained_rhs()
            check(f"free rhs vs matrix form: {name}",
                  float(np.max(np.abs(np.array(rhs(0, y))[n:] - model.accel_generic(y)))), 1e-9)
            yc = model.r_inf(y)
            check(f"constrained rhs vs matrix form: {name}",
                  float(np.max(np.abs(np.array(crhs(0, yc))[n:]
                                      - model.constrained_accel_generic(yc)))), 1e-9)
        # 2. free flight to halfway to the first impact, vs zenosim --zeno off
        impacts = [e for e in s["events"] if e["kind"] == "impact"]
        t_half = impacts[0]["t"] / 2
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([binary, "run", path, "--out", out, "--rtol", "1e-12", "--atol",
                            "1e-12", "--t-end", repr(t_half)], check=True, capture_output=True)
            with open(os.path.join(out, "summary.json")) as f:
                half = json.load(f)
        sol = solve_ivp(model.make_rhs(), (0, t_half), y0, method="DOP853", rtol=1e-12,
                        atol=1e-12)
        check(f"free flight to t = t_impact/2 vs zenosim: {name}",
              float(np.max(np.abs(sol.y[:, -1] - final_state(half)))), 1e-8)
        # 3. the impact law on zenosim's impacts
        for e in impacts[:5]:
            before = np.array(e["before"]["q"] + e["before"]["q_dot"])
            # summary.json schema 4 leaves out `after.q` where it is `before.q`.
            after = np.array(e["after"].get("q", e["before"]["q"]) + e["after"]["q_dot"])
            check(f"impact law vs zenosim's impacts: {name}",
                  float(np.max(np.abs(model.impact(before)[n:] - after[n:]))), 1e-10)
        # 4. the constrained dynamics from zenosim's Zeno point to t_end
        z = s["zeno"][0]
        # Schema 4: the Zeno point's state is its event's `after` (`point` only for a stall).
        if "point" in z:
            point = z["point"]
        else:
            event = s["events"][z["event"]]
            point = {"q": event["after"].get("q", event["before"]["q"]),
                     "q_dot": event["after"]["q_dot"]}
        yz = np.array(point["q"] + point["q_dot"], dtype=float)
        t_end = s["final"]["t"]
        sol = solve_ivp(model.make_constrained_rhs(), (z["t_switch"], t_end), yz,
                        method="DOP853", rtol=1e-12, atol=1e-12)
        check(f"constrained motion from zenosim's Zeno point to t_end vs zenosim: {name}",
              float(np.max(np.abs(sol.y[:, -1] - final_state(s)))), 1e-7)
        # 5. zenosim's runs have no lift-off (the scipy loop has no lift-off handling)
        kinds = {e["kind"] for e in s["events"]}
        if "liftoff" in kinds:
            failures.append(f"{name}: zenosim's run lifts off; the scipy loop cannot follow")
    for key in sorted(worst):
        log(f"  {key}: worst {worst[key]:.2e}")
    if failures:
        for f in failures:
            log("  FAILED " + f)
        raise SystemExit("self-test failed")
    log("self-test passed")
    return worst


# --------------------------------------------------------------------------------------------
# Reporting.
# --------------------------------------------------------------------------------------------

def machine():
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "os": platform.platform(),
            "python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__}


def pareto(points):
    """The least-wall-time front: points sorted by wall time, each more accurate than all
    cheaper ones by more than 1 % (errors that differ by less are the same switch seen at other
    tolerances: ties, not improvements)."""
    ok = sorted((p for p in points if p["status"] == "ok"),
                key=lambda p: (p["wall_time_s"]["median"], p["error"]))
    front, best = [], math.inf
    for p in ok:
        if p["error"] < 0.99 * best:
            front.append(p)
            best = p["error"]
    return front


def retime(name, model, y0, t_end, zen, scipy_points, args):
    """The `RETIME` cheapest scipy configurations that reach zenosim's error, by the grid's
    times, timed again one after the other: the grid's times were taken minutes apart, while
    the machine's speed drifts, so its cheapest is not always the cheapest. Their new medians,
    by `id` of the point."""
    if zen is None or zen["status"] != "finished":
        return {}
    reach = sorted((p for p in scipy_points
                    if p["status"] == "ok" and p["error"] <= zen["error"]),
                   key=lambda p: p["wall_time_s"]["median"])[:RETIME]
    if reach:
        log(f"== {name}: the {len(reach)} cheapest matches, timed again one after the other")
    out = {}
    for p in reach:
        _, wall, failure = timed(model, y0, t_end, p["method"], p["tolerance"], p["epsilon"],
                                 args)
        if failure is None:
            out[id(p)] = wall["median"]
            log(f"   again: {p['method']} tol {p['tolerance']:g} eps {p['epsilon']:g}: "
                f"{tdur(wall['median'])} (grid {tdur(p['wall_time_s']['median'])})")
    return out


def matched(zen, scipy_points, retimed=None):
    """Wall-time ratio scipy/zenosim at matched accuracy (or the lower bound). With `retimed`
    (`retime`), the match is the fastest of the configurations timed again, by their new
    times."""
    ok = [p for p in scipy_points if p["status"] == "ok"]
    if zen is None or zen["status"] != "finished" or not ok:
        return None
    zerr, zwall = zen["error"], zen["wall_time_s"]["median"]
    reach = [p for p in ok if p["error"] <= zerr]
    retimed = retimed or {}
    wall_of = {id(p): p["wall_time_s"]["median"] for p in ok} | retimed
    if reach:
        again = [p for p in reach if id(p) in retimed]
        best = min(again or reach, key=lambda p: wall_of[id(p)])
        kind = "matched"
    else:
        # scipy's most accurate configuration; near-ties (within 1 %, e.g. the same switch at
        # different tolerances) go to the cheapest of them, so that timing noise does not pick
        kind = "lower bound"
        least = min(p["error"] for p in ok)
        best = min((p for p in ok if p["error"] <= 1.01 * least),
                   key=lambda p: p["wall_time_s"]["median"])
    return {"kind": kind, "ratio": wall_of[id(best)] / zwall, "retimed": len(retimed),
            "rhs_ratio": best["nfev"] / max(1, zen["rhs_evals"]),
            "zenosim": {"tolerance": zen["tolerance"], "error": zerr, "wall_time_s": zwall},
            "scipy": {k: best[k] for k in ("method", "tolerance", "epsilon", "error", "nfev")}
            | {"refined": bool(best.get("refined"))}
            | {"wall_time_s": wall_of[id(best)]}}


def paired(binary, path, model, y0, t_end, match, args):
    """The matched ratio again, timed back to back: `args.pairs` rounds of zenosim (`zenosim
    bench`, the headline tolerance) and the matched scipy configuration, in alternating order,
    each round's ratio from the two medians. The machine's speed drifts by tens of per cent
    from one minute to the next; a ratio of two times taken seconds apart is not biased by it,
    one of times taken minutes apart is."""
    s = match["scipy"]
    ratios, scipy_s, zenosim_s = [], [], []
    for k in range(args.pairs):
        def zen():
            report = zenosim_bench(binary, path, [match["zenosim"]["tolerance"]],
                                   args.zenosim_min_time)
            return report["runs"][0]["wall_time_s"]["median"]

        def sci():
            _, wall, failure = timed(model, y0, t_end, s["method"], s["tolerance"], s["epsilon"],
                                     args)
            return None if failure else wall["median"]

        if k % 2 == 0:
            z, w = zen(), sci()
        else:
            w, z = sci(), zen()
        if w is None:
            return None
        ratios.append(w / z)
        scipy_s.append(w)
        zenosim_s.append(z)
        log(f"   pair {k + 1}: scipy {tdur(w)}, zenosim {tdur(z)}: {w / z:.0f}×")
    return {"pairs": len(ratios), "median": statistics.median(ratios), "min": min(ratios),
            "max": max(ratios), "ratios": ratios, "scipy_s": scipy_s, "zenosim_s": zenosim_s}


def g3(x):
    if x is None:
        return "—"
    if x == 0:
        return "0"
    return f"{x:.3g}"


def tdur(s):
    if s is None:
        return "—"
    if s < 1e-3:
        return f"{s * 1e6:.3g} µs"
    if s < 1:
        return f"{s * 1e3:.3g} ms"
    return f"{s:.3g} s"


def ratio_text(r):
    if r is None:
        return "no scipy configuration finished"
    s = r["scipy"]
    head = (f"**{r['ratio']:.0f}×**" if r["ratio"] >= 10 else f"**{r['ratio']:.2g}×**")
    pair = r.get("paired")
    if pair:
        gap = pair["median"] / r["ratio"]
        drift = ("; the two differ by more than 1.5×: the machine's speed changed between the "
                 "grid and the pairs" if gap > 1.5 or gap < 1 / 1.5 else "")
        head = (f"**{pair['median']:.0f}×** (median of {pair['pairs']} back-to-back pairs, "
                f"{pair['min']:.0f}–{pair['max']:.0f}×; {r['ratio']:.0f}× from the grid's "
                f"times{drift})")
    if r["kind"] == "matched":
        dagger = " †" if s.get("refined") else ""
        return (f"{head} (scipy {s['method']}{dagger} tol {g3(s['tolerance'])} "
                f"ε {g3(s['epsilon'])}: "
                f"error {g3(s['error'])} ≤ zenosim's {g3(r['zenosim']['error'])}, "
                f"{tdur(s['wall_time_s'])} vs {tdur(r['zenosim']['wall_time_s'])}; "
                f"rhs evaluations {r['rhs_ratio']:.3g}×)")
    return (f"≥ {head} — a lower bound: no scipy configuration reaches zenosim's error "
            f"{g3(r['zenosim']['error'])}; scipy's most accurate (within 1 %: {s['method']} tol "
            f"{g3(s['tolerance'])} ε {g3(s['epsilon'])}) has error {g3(s['error'])} and takes "
            f"{tdur(s['wall_time_s'])} vs zenosim's {tdur(r['zenosim']['wall_time_s'])} "
            f"(rhs evaluations {r['rhs_ratio']:.3g}×)")


def table(results, info, args, headline_tol):
    out = []
    w = out.append
    w("# Peer comparison: zenosim against scipy.integrate.solve_ivp")
    w("")
    w(f"Machine: {info['machine']['cpu']}, {info['machine']['cores']} cores; "
      f"{info['date']}; Python {info['machine']['python']}, numpy {info['machine']['numpy']}, "
      f"scipy {info['machine']['scipy']}; zenosim {info['zenosim_version']}.")
    w("")
    w(f"scipy grid: methods {', '.join(args.methods)}; rtol = atol = tol ∈ "
      f"{{{', '.join(g3(t) for t in args.tolerances)}}}; ε ∈ "
      f"{{{', '.join(g3(e) for e in args.epsilons)}}} (the paper's rule with its R∞)"
      + (f"; then, per model and method, tol and ε on a 1-2-5 grid up to {REFINE_DECADES} "
         f"decades looser than the grid's cheapest match of zenosim's error (a method without "
         f"one: tol a decade tighter than its most accurate), the {args.refine} fastest that "
         f"reach it timed too (marked †), and the {RETIME} cheapest matches timed again one "
         f"after the other, the match the fastest of those" if args.refine > 0 else
         "; no refinement of the match (`--refine 0`): the ratio may be flattered by the "
         "grid's spacing")
      + f". Wall time: median of ≥ {args.min_repeats} runs and ≥ {args.min_time:g} s; zenosim's "
      f"from `zenosim bench` (in-process, ≥ 3 runs and ≥ {args.zenosim_min_time:g} s, model "
      f"loading excluded, as scipy's imports are).")
    w("")
    w(f"## Wall-time ratio scipy / zenosim at matched accuracy (zenosim at rtol = atol = "
      f"{g3(headline_tol)})")
    w("")
    w("| model | error measure | zenosim error | ratio |")
    w("|---|---|---|---|")
    for r in results:
        m = r["matched"]
        flag = " (reference disputed: see below)" if r.get("warning") else ""
        w(f"| {r['model']} | {r['error_measure'].replace('|', '&#124;')} | "
          f"{g3(m['zenosim']['error']) if m else '—'} | {ratio_text(m)}{flag} |")
    w("")
    for r in results:
        w(f"## {r['title']}")
        w("")
        w(f"Error: {r['error_measure']}. Reference: {r['reference']}.")
        if r["model"] in ("cart-pendulum", "spherical-pendulum"):
            w("Note: the ε rule is tested at impacts, where h ≈ 1e-16, so the paper's R∞ "
              "changes this momentum by only ~h·θ̇: the measure sees the integration of the "
              "flights and of the constrained motion, hardly the switch itself (an early switch, "
              "large ε, costs nothing here but fewer impacts).")
        if r.get("independent_check"):
            w(f"Independent check: {r['independent_check']}")
        w("")
        w("zenosim (its own Zeno detection, `--zeno auto`):")
        w("")
        w("| tol | status | error | wall (median) | rhs evals | impacts | note |")
        w("|---|---|---|---|---|---|---|")
        for z in r["zenosim"]:
            note = z.get("note", "")
            w(f"| {g3(z['tolerance'])} | {z['status']} | {g3(z['error'])} | "
              f"{tdur(z['wall_time_s']['median'])} | {z['rhs_evals']} | {z['impacts']} | "
              f"{note} |")
        w("")
        sp = r["scipy"]
        nok = sum(p["status"] == "ok" for p in sp)
        w(f"scipy, the Pareto front (least wall time for its error, improvements under 1 % "
          f"counted as ties) of {nok} finished "
          f"configurations out of {len(sp)}:")
        w("")
        w("| method | tol | ε | error | wall (median) | rhs evals | event evals | impacts "
          "| switch t |")
        w("|---|---|---|---|---|---|---|---|---|")
        for p in r["front"]:
            dagger = " †" if p.get("refined") else ""
            w(f"| {p['method']}{dagger} | {g3(p['tolerance'])} | {g3(p['epsilon'])} "
              f"| {g3(p['error'])} "
              f"| {tdur(p['wall_time_s']['median'])} | {p['nfev']} | {p['event_evals']} | "
              f"{p['impacts']}{'+' + str(p['spurious_events']) + ' spurious' if p['spurious_events'] else ''} "
              f"| {p['t_switch']:.10g} |")
        fails = [p for p in sp if p["status"] != "ok"]
        if fails:
            w("")
            w(f"scipy runs that failed ({len(fails)}):")
            w("")
            reasons = {}
            for p in fails:
                key = p["reason"].split(" (")[0].split(":")[0]
                reasons.setdefault(key, []).append(
                    f"{p['method']} tol {g3(p['tolerance'])} ε {g3(p['epsilon'])}")
            for key, cfgs in reasons.items():
                w(f"- {key}: {'; '.join(cfgs)}")
        w("")
        w(f"Matched accuracy against zenosim at tol {g3(headline_tol)}: {ratio_text(r['matched'])}")
        w("")
    return "\n".join(out)


# --------------------------------------------------------------------------------------------
# Main.
# --------------------------------------------------------------------------------------------

def floats(text):
    return [float(v) for v in text.split(",") if v.strip()]


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="bench/run",
        description="Compare zenosim with scipy.integrate.solve_ivp (terminal events and the "
                    "paper's eps rule written by hand) on the shipped models: errors, wall "
                    "times, work-precision fronts. Writes bench/results/{peer.json, "
                    "work-precision.json, table.md, work-precision.svg}.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="a small grid (DOP853; tol 1e-6,1e-10; eps 1e-3,1e-6; short timing): "
                         "under a minute")
    ap.add_argument("--self-test", action="store_true",
                    help="only check the hand-written equations against zenosim, then stop")
    ap.add_argument("--no-self-test", action="store_true",
                    help="skip the self-test that otherwise runs first")
    ap.add_argument("--models", default=",".join(DEFAULT_MODELS),
                    help="comma-separated model names (files models/NAME.toml)")
    ap.add_argument("--methods", default=",".join(DEFAULT_METHODS))
    ap.add_argument("--tolerances", default=",".join(f"{t:g}" for t in DEFAULT_TOLERANCES),
                    help="scipy's rtol = atol values")
    ap.add_argument("--epsilons", default=",".join(f"{e:g}" for e in DEFAULT_EPSILONS),
                    help="the eps rule's thresholds")
    ap.add_argument("--zenosim-tolerances", default=None,
                    help="zenosim's rtol = atol values [default: --tolerances plus the "
                         "headline 1e-10]")
    ap.add_argument("--min-time", type=float, default=0.2,
                    help="repeat each scipy configuration until this many seconds")
    ap.add_argument("--min-repeats", type=int, default=3)
    ap.add_argument("--zenosim-min-time", type=float, default=0.5,
                    help="zenosim bench --min-time")
    ap.add_argument("--pairs", type=int, default=7,
                    help="rounds of timing zenosim and the matched scipy configuration back to "
                         "back, for the headline ratio (0: the grid's times only)")
    ap.add_argument("--refine", type=int, default=3,
                    help="after the grid, search a 1-2-5 grid of tol and ε above each "
                         "method's cheapest match of zenosim's headline error, and time this "
                         "many of the fastest configurations found (0: the grid only)")
    ap.add_argument("--max-impacts", type=int, default=1000,
                    help="a scipy run with more events fails as an event storm")
    ap.add_argument("--max-wall", type=float, default=20.0,
                    help="a scipy run that takes longer (one run) fails")
    ap.add_argument("--zenosim", default=os.path.join(ROOT, "target", "release", "zenosim"),
                    help="the zenosim binary")
    ap.add_argument("--out", default=os.path.join(HERE, "results"), help="output directory")
    args = ap.parse_args(argv)
    if args.quick:
        args.methods = "DOP853"
        args.tolerances = "1e-6,1e-10"
        args.epsilons = "1e-3,1e-6"
        args.min_time = 0.02
        args.min_repeats = 1
        args.zenosim_min_time = 0.05
        args.max_wall = 5.0
        args.pairs = min(args.pairs, 1)
        args.refine = min(args.refine, 1)
    args.methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    args.tolerances = floats(args.tolerances)
    args.epsilons = floats(args.epsilons)
    args.models = [m.strip() for m in args.models.split(",") if m.strip()]
    if args.zenosim_tolerances is None:
        args.zenosim_tolerances = sorted(set(args.tolerances) | {HEADLINE_TOL}, reverse=True)
    else:
        args.zenosim_tolerances = floats(args.zenosim_tolerances)
    for m in args.models:
        if m not in MODEL_CLASSES:
            ap.error(f"unknown model {m!r}: one of {', '.join(MODEL_CLASSES)}")
    return args


def user_args(argv):
    """The arguments a user gave bench/run (without the binary's path that bench/run adds)."""
    out, skip = [], False
    for a in argv:
        if skip:
            skip = False
        elif a == "--zenosim":
            skip = True
        elif not a.startswith("--zenosim="):
            out.append(a)
    return out


def main(argv):
    args = parse_args(argv)
    started = time.perf_counter()
    binary = args.zenosim
    if not os.path.exists(binary):
        raise SystemExit(f"zenosim binary not found at {binary}: build it with "
                         f"`cargo build --release -p zenosim-cli` (bench/run does)")
    model_files = {m: os.path.join(ROOT, "models", f"{m}.toml") for m in args.models}
    if not args.no_self_test or args.self_test:
        self_test(binary, model_files)
        if args.self_test:
            return 0

    info = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "machine": machine(), "command": "bench/run " + " ".join(user_args(argv))}
    m = info["machine"]
    log(f"machine: {m['cpu']}, {m['cores']} cores; {info['date']}; Python {m['python']}, "
        f"numpy {m['numpy']}, scipy {m['scipy']}")
    has_bench = zenosim_has(binary, "bench")
    if not has_bench:
        log("WARNING: `zenosim bench` is missing: zenosim is timed as whole `zenosim run` "
            "processes (start-up, loading and output included; an upper bound)")

    # warm scipy up (first-call imports inside solve_ivp) outside every measurement
    warm = BouncingBall({"m": 1.0, "g": 9.81, "e": 0.5, "h0": 1.0})
    simulate(warm, [1.0, 0.0], 3.0, "RK45", 1e-6, 1e-3, 100)

    results = []
    panels = []
    all_points = []
    for name in args.models:
        path = model_files[name]
        log(f"== {name}: zenosim")
        if has_bench:
            report = zenosim_bench(binary, path, args.zenosim_tolerances, args.zenosim_min_time)
        else:
            report = zenosim_run_report(binary, path, args.zenosim_tolerances)
        info["zenosim_version"] = report.get("zenosim", "?")
        model = MODEL_CLASSES[name](report["parameters"])
        if tuple(report["coordinates"]) != model.coordinates:
            raise SystemExit(f"{name}: zenosim's coordinates {report['coordinates']} are not "
                             f"the script's {model.coordinates}")
        y0 = np.array(report["initial"]["q"] + report["initial"]["q_dot"], dtype=float)
        t_end = report["runs"][0]["settings"]["t_end"]
        for run in report["runs"]:
            if run["events"].get("liftoff", 0):
                raise SystemExit(f"{name}: zenosim's run at tol {run['settings']['rtol']:g} "
                                 f"lifts off the constraint; the scipy loop has no lift-off "
                                 f"handling, so the comparison would be wrong")
            if not run["zeno"]:
                raise SystemExit(f"{name}: zenosim finds no Zeno point before t_end "
                                 f"(tol {run['settings']['rtol']:g}): nothing to compare")

        reference = None
        independent = None
        warning = None
        if name in ("ball-on-sine", "ball-on-sine-demo"):
            for rtol in REFERENCE_TOLERANCES:
                ref = zenosim_bench(binary, path, [rtol], 0.001) if has_bench else \
                    zenosim_run_report(binary, path, [rtol])
                run = ref["runs"][0]
                if run["status"] == "finished" and not run["events"].get("liftoff", 0):
                    reference = (final_state(run), rtol, run["final"]["t"])
                    break
                log(f"   reference at {rtol:g} did not finish: {run['message']}")
            if reference is None:
                raise SystemExit(f"{name}: no zenosim reference run finished")
        title, measure, ref_text, err_fn, _ = error_spec(name, report["parameters"], y0,
                                                         reference)

        zen_points = []
        for run in report["runs"]:
            tol = run["settings"]["rtol"]
            z = run["zeno"][0]
            y = final_state(run)
            err = err_fn(y, z["t_switch"], z["t_zeno"])
            point = {"tool": "zenosim", "model": name, "method": run["settings"]["method"],
                     "tolerance": tol, "epsilon": None, "status": run["status"],
                     "message": run["message"], "error": err,
                     "wall_time_s": run["wall_time_s"], "rhs_evals": run["stats"]["rhs_evals"],
                     "nfev": run["stats"]["rhs_evals"], "impacts": run["events"]["impact"],
                     "t_switch": z["t_switch"], "t_zeno": z["t_zeno"], "final": y.tolist()}
            if name == "bouncing-ball":
                t1 = math.sqrt(2 * report["parameters"]["h0"] / report["parameters"]["g"])
                e = report["parameters"]["e"]
                tau = t1 * (1 + e) / (1 - e)
                point["t_switch_error"] = abs(z["t_switch"] - tau)
                point["note"] = f"t_switch error {g3(point['t_switch_error'])}"
            if reference is not None and tol == reference[1]:
                point["note"] = "the reference itself"
            zen_points.append(point)
            all_points.append(point)
            log(f"   tol {tol:g}: {run['status']}, error {g3(err)}, "
                f"{tdur(run['wall_time_s']['median'])}, {run['stats']['rhs_evals']} rhs")

        log(f"== {name}: scipy ({len(args.methods) * len(args.tolerances) * len(args.epsilons)}"
            f" configurations)")
        sp_points = []
        for method in args.methods:
            for tol in args.tolerances:
                for eps in args.epsilons:
                    point = scipy_point(name, model, y0, t_end, method, tol, eps, args, err_fn)
                    sp_points.append(point)
                    all_points.append(point)

        zen_head = next((z for z in zen_points if z["tolerance"] == HEADLINE_TOL), None)
        if zen_head is None and zen_points:
            zen_head = min(zen_points, key=lambda z: abs(math.log(z["tolerance"] / HEADLINE_TOL)))
        if zen_head is not None and zen_head["status"] == "finished" and args.refine > 0:
            refined = refine(name, model, y0, t_end, zen_head["error"], sp_points, args, err_fn)
            sp_points += refined
            all_points += refined

        front = pareto(sp_points)
        retimed = (retime(name, model, y0, t_end, zen_head, sp_points, args)
                   if args.refine > 0 else {})
        match = matched(zen_head, sp_points, retimed)
        if match is not None and has_bench and args.pairs > 0:
            log(f"== {name}: the matched pair, back to back")
            match["paired"] = paired(binary, path, model, y0, t_end, match, args)
        if reference is not None:
            ok = [p for p in sp_points if p["status"] == "ok"]
            if ok:
                best = min(ok, key=lambda p: p["error"])
                independent = (f"scipy's most accurate run ({best['method']} tol "
                               f"{g3(best['tolerance'])} ε {g3(best['epsilon'])}) ends "
                               f"{g3(best['error'])} (max norm) from zenosim's reference.")
                own = [z["error"] for z in zen_points
                       if z["status"] == "finished" and z["tolerance"] != reference[1]]
                # scipy's own agreement: its most accurate run against the next most accurate
                # one that differs from it. A disagreement with the reference counts only when
                # scipy has settled (its best runs agree far better than with the reference).
                fb = np.asarray(best["final"])
                others = sorted((p for p in ok if p is not best), key=lambda p: p["error"])
                spread = next((float(np.max(np.abs(np.asarray(p["final"]) - fb)))
                               for p in others
                               if np.max(np.abs(np.asarray(p["final"]) - fb)) > 0), math.inf)
                if (own and best["error"] > 1e3 * max(min(own), 1e-14)
                        and best["error"] > 10 * spread and best["error"] > 1e-8):
                    warning = (f"scipy's most accurate runs agree with each other to "
                               f"{g3(spread)} but disagree with zenosim's reference by "
                               f"{g3(best['error'])}, far more than zenosim's own convergence "
                               f"(its tightest run is {g3(min(own))} from the reference): one "
                               f"of the two is biased, so this panel's errors and ratio are "
                               f"not trustworthy until that is explained.")
                    independent += " **WARNING: " + warning + "**"
                    log("WARNING: " + name + ": " + warning)
        results.append({"model": name, "title": title, "error_measure": measure,
                        "reference": ref_text, "independent_check": independent,
                        "zenosim": zen_points, "scipy": sp_points, "front": front,
                        "matched": match, "t_end": t_end, "warning": warning})

        def wp(p):
            return {"tolerance": p["tolerance"], "epsilon": p["epsilon"], "error": p["error"],
                    "wall_time_s": p["wall_time_s"]["median"], "rhs_evals": p["nfev"]}
        short = {"bouncing-ball": "bouncing ball: Zeno time",
                 "ball-on-sine": "paper's ball on sine: state at t = 6",
                 "cart-pendulum": "cart pendulum: momentum p_x",
                 "spherical-pendulum": "spherical pendulum: momentum p_φ",
                 "ball-on-sine-demo": "demo ball on sine: state at t = 20"}[name]
        panels.append({"title": short, "error": measure, "series": [
            {"label": "zenosim", "points": [wp(z) for z in zen_points
                                            if z["status"] == "finished"
                                            and not (reference and z["tolerance"]
                                                     == reference[1])]},
            {"label": f"scipy (best of {'/'.join(args.methods)} + ε rule)",
             "points": [wp(p) for p in front]}]})

    os.makedirs(args.out, exist_ok=True)
    info["elapsed_s"] = time.perf_counter() - started
    info.setdefault("zenosim_version", "?")
    text = table(results, info, args, HEADLINE_TOL)
    text += (f"\nFull run took {info['elapsed_s']:.0f} s (`{info['command'].strip()}`).\n")
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write(text)
    head = {"info": info, "grid": {"methods": args.methods, "tolerances": args.tolerances,
                                   "epsilons": args.epsilons,
                                   "zenosim_tolerances": args.zenosim_tolerances,
                                   "min_time_s": args.min_time, "min_repeats": args.min_repeats,
                                   "max_impacts": args.max_impacts, "max_wall_s": args.max_wall,
                                   "refine": args.refine, "refine_decades": REFINE_DECADES,
                                   "retime": RETIME if args.refine > 0 else 0},
            "models": [{k: r[k] for k in ("model", "title", "error_measure", "reference",
                                          "independent_check", "warning", "t_end", "matched")}
                       for r in results]}
    with open(os.path.join(args.out, "peer.json"), "w") as f:
        # one point per line: small, and readable in a diff
        f.write("{\n" + "".join(f"{json.dumps(k)}: {json.dumps(v, ensure_ascii=False)},\n"
                                for k, v in head.items()))
        f.write('"points": [\n' + ",\n".join(json.dumps(p, ensure_ascii=False)
                                               for p in all_points) + "\n]}\n")
    wp_path = os.path.join(args.out, "work-precision.json")
    with open(wp_path, "w") as f:
        json.dump({"title": "Work–precision: zenosim against scipy.integrate.solve_ivp",
                   "subtitle": f"{m['cpu']}, {m['cores']} cores, {info['date']}; scipy "
                               f"{m['scipy']}, numpy {m['numpy']}",
                   "panels": panels}, f, indent=1)
    print(text)
    if zenosim_has(binary, "work-precision"):
        svg = os.path.join(args.out, "work-precision.svg")
        proc = subprocess.run([binary, "work-precision", wp_path, "--out", svg],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            log(f"zenosim work-precision failed (exit {proc.returncode}): {proc.stderr}")
            return 1
        log(f"diagram: {os.path.relpath(svg, ROOT)}")
    else:
        log("`zenosim work-precision` does not exist yet: no diagram drawn")
    log(f"results in {os.path.relpath(args.out, ROOT)}/ (took {info['elapsed_s']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
