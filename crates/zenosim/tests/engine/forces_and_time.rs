//! Forces, dissipation and surfaces that move (docs/forces-and-time.md), against closed forms.

use zenosim::{
    Constraint, Derived, EventKind, Execution, HybridLagrangian, Outcome, Scalar, Simulation,
    SimulationOptions, Trajectory,
};

/// A ball of unit mass on a table that vibrates as `y_T = a sin(ω t)`: `L = ½ ẏ² − g y`,
/// `h = y − a sin(ω t)`.
struct VibratingTable {
    a: f64,
    omega: f64,
    g: f64,
    constraints: [Constraint; 1],
}

impl HybridLagrangian for VibratingTable {
    const DIMENSION: Option<usize> = Some(1);
    fn dimension(&self) -> usize {
        1
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        v[0] * v[0] * 0.5 - q[0] * self.g
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }
    fn constraint_at<D: Scalar>(&self, _index: usize, t: D, q: &[D]) -> D {
        q[0] - (t * self.omega).sin() * self.a
    }
    fn is_autonomous(&self) -> bool {
        false
    }
}

/// With `a ω² > g`, the ball chatters to rest on the table, is carried, and leaves it where the
/// table's downward acceleration reaches `g`: `a ω² sin(ω t) = g`, the table decelerating
/// (the contact force `g − a ω² sin(ω t)` vanishing while it falls), every time.
#[test]
fn a_ball_on_a_vibrating_table_leaves_it_where_the_table_decelerates_at_g() {
    let (a, omega, g) = (0.003, 20.0 * std::f64::consts::PI, 9.81);
    assert!(a * omega * omega > g);
    let model = VibratingTable {
        a,
        omega,
        g,
        constraints: [Constraint::new("table", 0.2)],
    };
    let options = SimulationOptions {
        t_end: 3.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[0.01], &[0.0], options)
        .unwrap()
        .run(&mut trajectory);
    balance_holds(&model, &run, &trajectory, 1e-8);
    assert!(run.zeno.len() >= 20, "{} Zeno points", run.zeno.len());
    assert_eq!(run.outcome, Outcome::Finished, "{:?}", run.outcome);
    let phase = (g / (a * omega * omega)).asin();
    let liftoffs: Vec<f64> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Liftoff)
        .map(|e| e.t)
        .collect();
    assert!(!liftoffs.is_empty());
    for t in liftoffs {
        let theta = (omega * t).rem_euclid(std::f64::consts::TAU);
        assert!(
            (theta - phase).abs() <= 1e-9,
            "lift-off at t = {t}: phase {theta}, expected {phase}"
        );
    }
}

/// With `a ω² < g` the ball, once at rest on the table after its Zeno point, never leaves it.
#[test]
fn a_ball_on_a_gently_vibrating_table_stays_on_it_after_its_zeno_point() {
    let (a, omega, g) = (0.002, 20.0 * std::f64::consts::PI, 9.81);
    assert!(a * omega * omega < g);
    let model = VibratingTable {
        a,
        omega,
        g,
        constraints: [Constraint::new("table", 0.5)],
    };
    let options = SimulationOptions {
        t_end: 2.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[0.05], &[0.0], options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished, "{:?}", run.outcome);
    assert_eq!(run.zeno.len(), 1);
    assert!(run.events.iter().all(|e| e.kind != EventKind::Liftoff));
    let last = run.events.last().unwrap();
    assert_eq!(last.kind, EventKind::Zeno);
    // Carried by the table from there: y = a sin(ω t) to the tolerance.
    for p in trajectory.points.iter().filter(|p| p.t > last.t) {
        let table = a * (omega * p.t).sin();
        assert!(
            (p.q[0] - table).abs() <= 1e-9,
            "t = {}: y = {}, table {table}",
            p.t,
            p.q[0]
        );
    }
    balance_holds(&model, &run, &trajectory, 1e-8);
}

/// `E(t) − E(0) = W_forces + W_drive + W_constraints − ΔE_impacts` at every sample and at the
/// end, to `tol` relative to the energies and works involved.
fn balance_holds<L: HybridLagrangian>(
    model: &L,
    run: &Execution,
    trajectory: &Trajectory,
    tol: f64,
) {
    let first = &trajectory.points[0];
    let e0 = first.energy;
    let mut worst: f64 = 0.0;
    for p in &trajectory.points {
        let w = p.work;
        let scale = e0.abs()
            + p.energy.abs()
            + w.forces.abs()
            + w.drive.abs()
            + w.constraints.abs()
            + w.impact_loss.abs();
        let residual = (p.energy - e0 - w.balance()).abs() / scale.max(1e-300);
        worst = worst.max(residual);
        assert!(
            residual <= tol,
            "t = {}: E − E0 = {:e}, balance {:e} ({w:?})",
            p.t,
            p.energy - e0,
            w.balance()
        );
    }
    let derived = Derived::new(model).unwrap().at_time(run.t_final);
    let end = derived.energy(&run.final_state.q, &run.final_state.q_dot);
    assert!(
        (end - e0 - run.work.balance()).abs()
            <= tol
                * (e0.abs()
                    + end.abs()
                    + run.work.impact_loss.abs()
                    + run.work.constraints.abs()
                    + run.work.forces.abs())
    );
    eprintln!(
        "energy balance: worst relative residual {worst:e} over {} samples",
        trajectory.points.len()
    );
}

/// A unit ball dropped from `h0` with linear air drag: `L = ½ ẏ² − g y`, the dissipation
/// function `D = ½ c ẏ²` (force `−c ẏ`), the floor `h = y`.
struct DraggedBall {
    c: f64,
    g: f64,
    constraints: [Constraint; 1],
}

impl HybridLagrangian for DraggedBall {
    const DIMENSION: Option<usize> = Some(1);
    fn dimension(&self) -> usize {
        1
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        v[0] * v[0] * 0.5 - q[0] * self.g
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }
    fn dissipation<D: Scalar>(&self, _t: D, _q: &[D], v: &[D]) -> D {
        v[0] * v[0] * (0.5 * self.c)
    }
    fn is_autonomous(&self) -> bool {
        false
    }
}

/// The first root after 0 of `f`, which is positive just after 0: bracketed by a scan in steps
/// of `dt`, then bisected to the last bit.
fn first_root(f: impl Fn(f64) -> f64, dt: f64) -> f64 {
    let (mut a, mut b) = (0.0, dt);
    while f(b) > 0.0 {
        a = b;
        b += dt;
    }
    loop {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            return m;
        }
        if f(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
}

/// The dragged ball's impact times in closed form: a flight from `y0` with speed `v0` is
/// `y(t) = y0 + (v0 + g/c)(1 − e^{−ct})/c − (g/c) t`, its landing a root of it, the speed
/// there `(v0 + g/c) e^{−cT} − g/c`, and the next flight starts at `−e` times it. The Zeno time
/// is their limit (the flights shrink geometrically: summed until they vanish in `f64`).
fn dragged_ball_impacts(c: f64, g: f64, e: f64, h0: f64) -> (Vec<f64>, f64) {
    let (mut t, mut y0, mut v0) = (0.0, h0, 0.0);
    let mut impacts = Vec::new();
    loop {
        // (1 − e^{−cs}) as −expm1(−cs): exact to rounding for the shortest flights.
        let y = |s: f64| y0 - (v0 + g / c) * (-c * s).exp_m1() / c - (g / c) * s;
        let scale = if v0 > 0.0 {
            2.0 * v0 / g
        } else {
            (2.0 * y0 / g).sqrt()
        };
        if scale < 1e-17 * t {
            return (impacts, t);
        }
        let flight = first_root(y, scale / 64.0);
        t += flight;
        impacts.push(t);
        let landing = (v0 + g / c) * (-c * flight).exp() - g / c;
        (y0, v0) = (0.0, -e * landing);
    }
}

#[test]
fn a_ball_with_air_drag_bounces_at_the_closed_form_times_and_zeno_time() {
    let (c, g, e, h0) = (0.8, 9.81, 0.6, 1.0);
    let model = DraggedBall {
        c,
        g,
        constraints: [Constraint::new("floor", e)],
    };
    let (exact, t_zeno) = dragged_ball_impacts(c, g, e, h0);
    let options = SimulationOptions {
        t_end: t_zeno + 1.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[h0], &[0.0], options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished, "{:?}", run.outcome);
    let times = run.impact_times(0);
    let mut worst: f64 = 0.0;
    for (k, (t, x)) in times.iter().zip(&exact).enumerate() {
        let relative = (t - x).abs() / x;
        worst = worst.max(relative);
        assert!(relative <= 1e-9, "impact {k}: {t} against {x}");
    }
    assert_eq!(run.zeno.len(), 1);
    let zeno_error = (run.zeno[0].t_zeno - t_zeno).abs() / t_zeno;
    eprintln!("dragged ball: {} impacts, worst relative error {worst:e}; Zeno time {} against {t_zeno}, relative {zeno_error:e}", times.len(), run.zeno[0].t_zeno);
    assert!(
        zeno_error <= 1e-8,
        "Zeno time {} against {t_zeno}",
        run.zeno[0].t_zeno
    );
    balance_holds(&model, &run, &trajectory, 1e-8);
    // The drag did negative work, the impacts took energy out.
    assert!(run.work.forces < 0.0 && run.work.impact_loss > 0.0);
}

/// A damped oscillator (mass, spring, damper) against a wall: `L = ½ m ẋ² − ½ k (x − x_eq)²`
/// with the spring's rest point `x_eq < 0` beyond the wall `h = x`, and the damper as a
/// generalized force `Q = −c ẋ`.
struct DampedOscillator {
    m: f64,
    k: f64,
    c: f64,
    x_eq: f64,
    constraints: [Constraint; 1],
}

impl HybridLagrangian for DampedOscillator {
    const DIMENSION: Option<usize> = Some(1);
    fn dimension(&self) -> usize {
        1
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let u = q[0] - self.x_eq;
        v[0] * v[0] * (0.5 * self.m) - u * u * (0.5 * self.k)
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }
    fn generalized_force<D: Scalar>(&self, _t: D, _q: &[D], v: &[D], force: &mut [D]) {
        force[0] -= v[0] * self.c;
    }
    fn is_autonomous(&self) -> bool {
        false
    }
}

/// The damped oscillator's impact times in closed form: with `u = x − x_eq`, `α = c/2m`,
/// `ω = √(k/m − α²)`, a flight from `(u0, v0)` is `u(t) = e^{−αt}(u0 cos ωt + (v0 + α u0)/ω
/// sin ωt)`; the wall is reached where `u = −x_eq`.
fn damped_oscillator_impacts(o: &DampedOscillator, e: f64, x0: f64) -> (Vec<f64>, f64) {
    let alpha = o.c / (2.0 * o.m);
    let omega = (o.k / o.m - alpha * alpha).sqrt();
    let (mut t, mut u0, mut v0) = (0.0, x0 - o.x_eq, 0.0);
    let mut impacts = Vec::new();
    loop {
        let b = (v0 + alpha * u0) / omega;
        // x(s) = u(s) + x_eq, with e^{−αs} cos ωs − 1 = expm1(−αs) cos ωs − 2 sin²(ωs/2)
        // exact to rounding for the shortest flights (u0 = −x_eq there).
        let x = |s: f64| {
            let (sin, cos) = (omega * s).sin_cos();
            let half = (0.5 * omega * s).sin();
            u0 * ((-alpha * s).exp_m1() * cos - 2.0 * half * half)
                + (u0 + o.x_eq)
                + b * (-alpha * s).exp() * sin
        };
        let u_dot = |s: f64| {
            (-alpha * s).exp()
                * ((b * omega - alpha * u0) * (omega * s).cos()
                    - (u0 * omega + alpha * b) * (omega * s).sin())
        };
        // The flight's scale: the free fall 2 v0 / |ẍ| near the wall, or a quarter period.
        let acc = o.k * (-o.x_eq) / o.m;
        let scale = if v0 > 0.0 {
            2.0 * v0 / acc
        } else {
            0.5 / omega
        };
        if scale < 1e-17 * t {
            return (impacts, t);
        }
        let flight = first_root(x, scale / 64.0);
        t += flight;
        impacts.push(t);
        (u0, v0) = (-o.x_eq, -e * u_dot(flight));
    }
}

#[test]
fn a_damped_oscillator_against_a_wall_hits_it_at_the_closed_form_times() {
    let model = DampedOscillator {
        m: 1.5,
        k: 40.0,
        c: 0.9,
        x_eq: -0.3,
        constraints: [Constraint::new("wall", 0.7)],
    };
    let x0 = 0.5;
    let (exact, t_zeno) = damped_oscillator_impacts(&model, 0.7, x0);
    let options = SimulationOptions {
        t_end: t_zeno + 1.0,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(&model, &[x0], &[0.0], options)
        .unwrap()
        .run(&mut trajectory);
    assert_eq!(run.outcome, Outcome::Finished, "{:?}", run.outcome);
    let times = run.impact_times(0);
    let mut worst: f64 = 0.0;
    for (k, (t, x)) in times.iter().zip(&exact).enumerate() {
        let relative = (t - x).abs() / x;
        worst = worst.max(relative);
        assert!(relative <= 1e-9, "impact {k}: {t} against {x}");
    }
    assert_eq!(run.zeno.len(), 1);
    let zeno_error = (run.zeno[0].t_zeno - t_zeno).abs() / t_zeno;
    eprintln!("damped oscillator: {} impacts, worst relative error {worst:e}; Zeno time {} against {t_zeno}, relative {zeno_error:e}", times.len(), run.zeno[0].t_zeno);
    assert!(
        zeno_error <= 1e-8,
        "Zeno time {} against {t_zeno}",
        run.zeno[0].t_zeno
    );
    balance_holds(&model, &run, &trajectory, 1e-8);
}
