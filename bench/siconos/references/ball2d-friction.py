"""Reference of models/siconos/ball2d-friction.toml (Siconos
2DRigidBodies/Ball2D_kernel_only_with_friction.cpp).

Run: python3 bench/siconos/references/ball2d-friction.py (needs mpmath; under a second). Writes
models/siconos/references/ball2d-friction.json.

Closed form, evaluated in mpmath at 50 digits. The disk (mass m, radius R, inertia I) falls
along -x onto the ground x = R from x0 at rest, spinning at w0: it lands at t1 = sqrt(2 (x0 - R)/g)
at normal speed v1 = g t1, slipping at s = y_dot - R theta_dot = -R w0. The impact law
(Newton's in the normal direction, Coulomb's on the slip after the impact) on a disk: the
normal impulse is m (1 + e) v1 whatever the tangential one (the normal and tangential
directions are decoupled through the mass matrix), and a tangential impulse L changes the slip
by L (1/m + R^2/I). It sticks (s+ = 0) if that L = -s-/(1/m + R^2/I) is within the cone
|L| <= mu m (1 + e) v1, else it slips through with L = -mu m (1 + e) v1 sign(s-) (checked
here: the example sticks). After a sticking impact the slip is 0 and stays 0 through every
later impact (no tangential impulse: the normal one does not change the slip), and in flight
(no force along the ground). So the bounces are the bouncing ball's: impact k at
t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), the Zeno point at t1 (1 + e)/(1 - e); after it the disk
rolls on the ground at the velocities the first impact left (gravity is normal to the ground:
no friction force). Listed: every impact up to 1e-14 s before the Zeno point, with its
tangential impulse; the state at t_end. Accuracy: the closed form's, rounded to f64.
"""

import mpmath

from common import check_parameters, write_reference

mpmath.mp.dps = 50

NAME = "ball2d-friction"
# The example's values (Ball2D_kernel_only_with_friction.cpp): m, R, the inertia 2/5 m R^2,
# g, e, mu of NewtonImpactFrictionNSL(e, 0, mu, 2), position_init, rotation_init; T = 10.
EXAMPLE = {"m": 1, "R": mpmath.mpf("0.5"), "I": mpmath.mpf(2) / 5 * mpmath.mpf("0.5") ** 2,
           "g": mpmath.mpf("9.81"), "e": mpmath.mpf("0.9"), "mu": mpmath.mpf("0.1"), "x0": 1,
           "w0": 2}
T_END = mpmath.mpf(10)


def main():
    p = check_parameters(NAME, EXAMPLE)
    m, R, I, g, e, mu, x0, w0 = (p[k] for k in ("m", "R", "I", "g", "e", "mu", "x0", "w0"))
    t1 = mpmath.sqrt(2 * (x0 - R) / g)
    v1 = g * t1
    normal = m * (1 + e) * v1
    slip_before = -R * w0  # y_dot - R theta_dot at the first impact
    stick = -slip_before / (1 / m + R * R / I)
    if abs(stick) <= mu * normal:
        tangential, how = stick, "sticks"
    else:
        tangential, how = -mu * normal * mpmath.sign(slip_before), "slips"
    y_dot = tangential / m
    theta_dot = w0 - R * tangential / I
    slip_after = y_dot - R * theta_dot
    if how == "sticks":
        assert abs(slip_after) < mpmath.mpf("1e-40")
    else:
        raise SystemExit("the first impact slips: the closed form below assumes it sticks")
    zeno = t1 * (1 + e) / (1 - e)
    impacts = []
    k = 1
    while True:
        t = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        if zeno - t < mpmath.mpf("1e-14"):
            break
        impacts.append({"t": t, "contacts": ["ground"],
                        "normal_impulse": m * (1 + e) * v1 * e ** (k - 1),
                        "tangential_impulse": tangential if k == 1 else 0})
        k += 1
    final_q = [R, y_dot * (T_END - t1), w0 * t1 + theta_dot * (T_END - t1)]
    write_reference(
        NAME,
        "examples/mechanics/2DRigidBodies/Ball2D_kernel_only_with_friction.cpp",
        "closed form: a sticking first impact (Newton + Coulomb), then the bouncing ball's "
        "impacts t1 (1 + 2 e (1 - e^(k-1))/(1 - e)) without slip, Zeno time t1 (1 + e)/(1 - e), "
        "then rolling",
        1e-15,
        impacts=impacts,
        zeno=[{"t": zeno, "constraints": ["ground"]}],
        final={"t": T_END, "q": final_q, "q_dot": [0, y_dot, theta_dot]},
        first_impact={"slip_before": slip_before, "normal_impulse": normal,
                      "tangential_impulse": tangential, "cone": mu * normal, "outcome": how,
                      "y_dot_after": y_dot, "theta_dot_after": theta_dot},
        notes=f"{len(impacts)} impacts listed, up to 1e-14 s before the Zeno point. The first "
        f"impact {how}: its tangential impulse {float(tangential):.6g} is within the cone "
        f"{float(mu * normal):.6g}; the disk leaves rolling at y_dot = {float(y_dot):.6g}, "
        f"theta_dot = {float(theta_dot):.6g}, and no later impact has a tangential impulse.",
    )


if __name__ == "__main__":
    main()
