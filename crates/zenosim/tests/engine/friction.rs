//! Coulomb friction at contacts (docs/friction.md), against closed forms: a ball with backspin
//! on a rough floor, a block on a rough incline, a block on a spring carried by a belt
//! (stick-slip, static above kinetic), and Painlevé's paradox.

use zenosim::{
    ActiveSet, Constraint, Error, EventKind, Friction, HybridLagrangian, Mode, Outcome, Scalar,
    Simulation, SimulationOptions, Trajectory,
};

const G: f64 = 9.81;

/// A solid ball of radius `r` and unit mass (`I = 2/5 r²`) over a rough floor: `(x, y, θ)`,
/// `θ` counter-clockwise, `h = y − r`, slip `s = ẋ + r θ̇` (the contact point's velocity).
struct Ball {
    r: f64,
    constraints: Vec<Constraint>,
}

impl Ball {
    fn new(r: f64, e: f64, mu: f64) -> Self {
        Self {
            r,
            constraints: vec![Constraint::new("floor", e).with_friction(Friction::coulomb(mu))],
        }
    }
}

impl HybridLagrangian for Ball {
    const DIMENSION: Option<usize> = Some(3);
    fn dimension(&self) -> usize {
        3
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let inertia = 0.4 * self.r * self.r;
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + v[2] * v[2] * (0.5 * inertia) - q[1] * G
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[1] - self.r
    }
    fn slip<D: Scalar>(&self, _index: usize, _c: usize, _t: D, _q: &[D], v: &[D]) -> D {
        v[0] + v[2] * self.r
    }
}

fn simulate<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    t_end: f64,
) -> (zenosim::Execution, Trajectory) {
    let options = SimulationOptions {
        t_end,
        ..Default::default()
    };
    let mut trajectory = Trajectory::default();
    let run = Simulation::new(model, q0, q_dot0, options)
        .unwrap()
        .run(&mut trajectory);
    (run, trajectory)
}

/// Dropped from height `y0` (centre) at `ẋ0` with backspin `θ̇0`, so that it sticks at its first
/// impact (the cone allows the tangential impulse `(2/7) |s⁻|` within `μ (1 + e) v₁`): it leaves
/// rolling, `ẋ⁺ = (5 ẋ⁻ − 2 r θ̇⁻)/7`, `θ̇⁺ = −ẋ⁺/r` (docs/friction.md), its normal motion the
/// bouncing ball's (impacts at `t₁ (1 + 2e (1 − e^(k−1))/(1 − e))`, Zeno point at
/// `t₁ (1 + e)/(1 − e)`, `t₁ = √(2 (y0 − r)/g)`), and rolls on after it, sticking.
#[test]
fn a_ball_with_backspin_sticks_at_its_first_impact_and_rolls_on() {
    let (r, e, mu) = (0.1, 0.5, 0.5);
    let (y0, x_dot0, w0) = (1.0, 1.0, -20.0);
    let ball = Ball::new(r, e, mu);
    let (run, trajectory) = simulate(&ball, &[0.0, y0, 0.0], &[x_dot0, 0.0, w0], 3.0);
    assert_eq!(run.outcome, Outcome::Finished);
    let t1 = (2.0 * (y0 - r) / G).sqrt();
    let rolling = (5.0 * x_dot0 - 2.0 * r * w0) / 7.0;
    let impacts: Vec<_> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .collect();
    let first = impacts[0];
    assert!((first.t - t1).abs() < 1e-12, "{}", first.t);
    assert!((first.after.q_dot[0] - rolling).abs() < 1e-12);
    assert!((first.after.q_dot[2] + rolling / r).abs() < 1e-11);
    // The tangential impulse: the change of ẋ (unit mass), within the cone.
    let v1 = G * t1;
    assert!((first.tangential[0] - (rolling - x_dot0)).abs() < 1e-12);
    assert!(first.tangential[0].abs() <= mu * first.impulses[0] + 1e-12);
    assert!((first.impulses[0] - (1.0 + e) * v1).abs() < 1e-10);
    for (k, impact) in impacts.iter().enumerate().take(12) {
        let k = k as i32 + 1;
        let expected = t1 * (1.0 + 2.0 * e * (1.0 - e.powi(k - 1)) / (1.0 - e));
        assert!(
            (impact.t - expected).abs() < 1e-10,
            "impact {k}: {}",
            impact.t
        );
        // Rolling at every impact after the first: no slip, no tangential impulse.
        if k > 1 {
            assert!(impact.tangential[0].abs() < 1e-12, "{impact:?}");
        }
    }
    let zeno = &run.zeno[0];
    assert!((zeno.t_zeno - t1 * (1.0 + e) / (1.0 - e)).abs() < 1e-9);
    let floor = ActiveSet::single(0);
    assert_eq!(run.final_mode, Mode::Constrained(floor));
    let s = &run.final_state;
    assert!((s.q_dot[0] - rolling).abs() < 1e-9, "{s:?}");
    assert!((s.q_dot[0] + r * s.q_dot[2]).abs() < 1e-9, "{s:?}");
    let last = trajectory.points.last().unwrap();
    assert_eq!(last.grips.stick, floor);
    // Rolling on a level floor needs no friction.
    assert!(last.friction[0].abs() < 1e-9, "{last:?}");
}

/// With little friction (the cone does not allow the first impact to stop the slip) the ball
/// slides through every impact, each taking out `(7/2) μ Λₙ` of slip (unit mass), through the
/// Zeno point, then slides on the floor, its slip decaying at `(7/2) μ g`, until it rolls at the
/// velocity its angular momentum about the contact gives, `(5 ẋ₀ − 2 r θ̇₀)/7`. Closed forms:
/// the slip at the Zeno point is `s₀ + (7/2) μ (1 + e) v₁/(1 − e)` (the impacts' normal
/// impulses sum to `(1 + e) v₁/(1 − e)`), and it sticks `|s_Z|/((7/2) μ g)` later.
#[test]
fn a_ball_with_backspin_and_little_friction_slides_through_its_zeno_point() {
    let (r, e, mu) = (0.1, 0.5, 0.02);
    let (y0, x_dot0, w0) = (1.0, 1.0, -20.0);
    let ball = Ball::new(r, e, mu);
    let (run, trajectory) = simulate(&ball, &[0.0, y0, 0.0], &[x_dot0, 0.0, w0], 3.0);
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let t1 = (2.0 * (y0 - r) / G).sqrt();
    let v1 = G * t1;
    let s0 = x_dot0 + r * w0;
    let t_zeno = t1 * (1.0 + e) / (1.0 - e);
    let s_zeno = s0 + 3.5 * mu * (1.0 + e) * v1 / (1.0 - e);
    assert!(s_zeno < 0.0);
    let t_stick = t_zeno + s_zeno.abs() / (3.5 * mu * G);
    let rolling = (5.0 * x_dot0 - 2.0 * r * w0) / 7.0;
    // Every impact slides: the tangential impulse is μ Λₙ, along +x (against the slip).
    for impact in run.events.iter().filter(|e| e.kind == EventKind::Impact) {
        let (normal, tangential) = (impact.impulses[0], impact.tangential[0]);
        assert!(
            (tangential - mu * normal).abs() <= 1e-12 * (1.0 + normal),
            "{impact:?}"
        );
    }
    let zeno = &run.zeno[0];
    assert!((zeno.t_zeno - t_zeno).abs() < 1e-9, "{zeno:?}");
    // The held motion starts at the switch, T_rem before the Zeno point, its slip there
    // decaying at (7/2) μ g to the tail's at the point (docs/friction.md).
    let after = &zeno.point.q_dot;
    let slip = after[0] + r * after[2] + 3.5 * mu * G * (zeno.t_zeno - zeno.t_switch);
    assert!((slip - s_zeno).abs() < 1e-8, "{slip} against {s_zeno}");
    let stick: Vec<_> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Stick)
        .collect();
    assert_eq!(stick.len(), 1, "{:?}", run.events.last());
    assert!(
        (stick[0].t - t_stick).abs() < 1e-8,
        "{} against {t_stick}",
        stick[0].t
    );
    let s = &run.final_state;
    assert!((s.q_dot[0] - rolling).abs() < 1e-9, "{s:?}");
    // While it slides on the floor, friction does work at the rate fₜ s = −μ g |s| < 0, and
    // the energy balance closes (docs/friction.md).
    let last = trajectory.points.last().unwrap();
    assert!(last.work.friction < 0.0, "{:?}", last.work);
    assert!(
        trajectory.balance_residual() < 1e-8,
        "{}",
        trajectory.balance_residual()
    );
}

/// A block (a point of unit mass) on an incline of angle `α`, in the incline's frame: `x` down
/// the slope, `y` off it; `h = y`, slip `s = ẋ`.
struct Incline {
    alpha: f64,
    constraints: Vec<Constraint>,
}

impl HybridLagrangian for Incline {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let (s, c) = self.alpha.sin_cos();
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + q[0] * (G * s) - q[1] * (G * c)
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[1]
    }
    fn slip<D: Scalar>(&self, _index: usize, _c: usize, _t: D, _q: &[D], v: &[D]) -> D {
        v[0]
    }
}

/// Launched down a rough incline at `v₀`: where `μ > tan α` it decelerates at
/// `g (μ cos α − sin α)`, stops at `v₀ / that`, and stays (the static cone holds it); where
/// `μ < tan α` it slides on, accelerating at `g (sin α − μ cos α)`. Closed forms.
#[test]
fn a_block_launched_down_a_rough_incline_stops_or_slides_on() {
    let (alpha, v0) = (0.3_f64, 2.0);
    for mu in [0.5, 0.2] {
        let block = Incline {
            alpha,
            constraints: vec![Constraint::new("slope", 0.0).with_friction(Friction::coulomb(mu))],
        };
        let (run, _) = simulate(&block, &[0.0, 0.0], &[v0, 0.0], 3.0);
        assert_eq!(run.outcome, Outcome::Finished, "μ = {mu}: {}", run.outcome);
        let a = G * (alpha.sin() - mu * alpha.cos());
        let s = &run.final_state;
        if mu > alpha.tan() {
            let t_stop = v0 / -a;
            let stopped = v0 * t_stop + 0.5 * a * t_stop * t_stop;
            let stick = run
                .events
                .iter()
                .find(|e| e.kind == EventKind::Stick)
                .expect("it stops");
            assert!(
                (stick.t - t_stop).abs() < 1e-9,
                "{} against {t_stop}",
                stick.t
            );
            assert!((s.q[0] - stopped).abs() < 1e-9, "{s:?} against {stopped}");
            assert!(s.q_dot[0].abs() < 1e-12, "{s:?}");
        } else {
            assert!(run.events.is_empty(), "{:?}", run.events);
            let x = v0 * 3.0 + 0.5 * a * 9.0;
            assert!((s.q[0] - x).abs() < 1e-9, "{s:?} against {x}");
            assert!((s.q_dot[0] - (v0 + 3.0 * a)).abs() < 1e-9, "{s:?}");
        }
        assert_eq!(run.final_mode, Mode::Constrained(ActiveSet::single(0)));
    }
}

/// A block of unit mass on a belt that moves at `v_b`, tied to a wall by a spring `k`:
/// `(x, y)`, `h = y`, slip `s = ẋ − v_b`, static `μₛ` above kinetic `μₖ`.
struct Belt {
    k: f64,
    belt: f64,
    constraints: Vec<Constraint>,
}

impl HybridLagrangian for Belt {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1]) * 0.5 - q[0] * q[0] * (0.5 * self.k) - q[1] * G
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[1]
    }
    fn slip<D: Scalar>(&self, _index: usize, _c: usize, _t: D, _q: &[D], v: &[D]) -> D {
        v[0] - self.belt
    }
}

/// The belt drags the block along, sticking, until the spring's pull reaches the static cone,
/// `k x = μₛ g`; then it slips back, a harmonic motion about `μₖ g/k` with `ω = √k`, until its
/// velocity is the belt's again, where it sticks. Closed forms for the first stick, slip and
/// stick: starting at rest at `x = 0` it slips (the belt is faster) and sticks where
/// `ẋ = v_b` first; then sticks until `x = μₛ g/k`.
#[test]
fn a_block_on_a_belt_sticks_and_slips_with_static_above_kinetic() {
    let (k, v_b, mu_s, mu_k) = (4.0_f64, 0.5, 0.6, 0.4);
    let block = Belt {
        k,
        belt: v_b,
        constraints: vec![Constraint::new("belt", 0.0).with_friction(Friction {
            static_coefficient: mu_s,
            kinetic_coefficient: mu_k,
        })],
    };
    let (run, trajectory) = simulate(&block, &[0.0, 0.0], &[0.0, 0.0], 10.0);
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
    let omega = k.sqrt();
    let centre = mu_k * G / k;
    // First slip, from rest at x = 0 (s = −v_b < 0: friction +μₖ g drags it): x = c (1 − cos ωt),
    // ẋ = c ω sin ωt, which reaches v_b at sin ωt = v_b/(c ω).
    let t_stick = (v_b / (centre * omega)).asin() / omega;
    let x_stick = centre * (1.0 - (omega * t_stick).cos());
    // Then it rides the belt until k x = μₛ g.
    let x_slip = mu_s * G / k;
    let t_slip = t_stick + (x_slip - x_stick) / v_b;
    let kinds: Vec<_> = run.events.iter().map(|e| (e.kind, e.t)).collect();
    assert_eq!(kinds[0].0, EventKind::Stick, "{kinds:?}");
    assert!(
        (kinds[0].1 - t_stick).abs() < 1e-9,
        "{kinds:?} against {t_stick}"
    );
    assert_eq!(kinds[1].0, EventKind::Slip, "{kinds:?}");
    assert!(
        (kinds[1].1 - t_slip).abs() < 1e-9,
        "{kinds:?} against {t_slip}"
    );
    // It slips backwards relative to the belt (s < 0) after breaking away.
    assert_eq!(run.events[1].grips.backward, ActiveSet::single(0));
    // Then it slips (ẋ about the kinetic centre, amplitude from (x_slip, v_b)) until ẋ = v_b
    // again: x − c = a cos(ω τ + φ) with a cos φ = x_slip − c, −a ω sin φ = v_b.
    let (dx, dv) = (x_slip - centre, v_b);
    let phase = (-dv / omega).atan2(dx);
    // ẋ = −a ω sin(ω τ + φ) = v_b again at ω τ + φ = −π − φ (the other solution).
    let tau = (-std::f64::consts::PI - 2.0 * phase) / omega;
    let t_stick2 = t_slip + tau.rem_euclid(2.0 * std::f64::consts::PI / omega);
    assert_eq!(kinds[2].0, EventKind::Stick, "{kinds:?}");
    assert!(
        (kinds[2].1 - t_stick2).abs() < 1e-8,
        "{kinds:?} against {t_stick2}"
    );
    // From there the cycle repeats: it sticks where ẋ = v_b again, at x = 2c − x_slip (the
    // slip's ellipse about the kinetic centre), rides the belt back to x_slip, `2 (x_slip − c)`
    // at v_b, and slips for t_stick2 − t_slip.
    let period = (t_stick2 - t_slip) + 2.0 * (x_slip - centre) / v_b;
    assert_eq!(kinds.len(), 5, "{kinds:?}");
    for i in 3..5 {
        assert_eq!(kinds[i].0, kinds[i - 2].0, "{kinds:?}");
        let gap = kinds[i].1 - kinds[i - 2].1;
        assert!(
            (gap - period).abs() < 1e-8,
            "{kinds:?}: {gap} against {period}"
        );
    }
    // Friction never does positive work on the slip (fₜ s ≤ 0).
    let mut friction_work = f64::NEG_INFINITY;
    for p in &trajectory.points {
        assert!(p.work.friction <= 1e-12, "{p:?}");
        friction_work = p.work.friction;
    }
    assert!(friction_work < 0.0);
}

/// A rod of length `2l` and unit mass leaning on a rough floor at one end:
/// `(x, y, θ)` its centre and its angle to the floor, the end at `(x − l cos θ, y − l sin θ)`,
/// `h = y − l sin θ`, slip the end's horizontal velocity `ẋ + l sin θ θ̇`.
struct Rod {
    l: f64,
    constraints: Vec<Constraint>,
}

impl HybridLagrangian for Rod {
    const DIMENSION: Option<usize> = Some(3);
    fn dimension(&self) -> usize {
        3
    }
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let inertia = self.l * self.l / 3.0;
        (v[0] * v[0] + v[1] * v[1]) * 0.5 + v[2] * v[2] * (0.5 * inertia) - q[1] * G
    }
    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[1] - q[2].sin() * self.l
    }
    fn slip<D: Scalar>(&self, _index: usize, _c: usize, _t: D, q: &[D], v: &[D]) -> D {
        v[0] + q[2].sin() * v[2] * self.l
    }
}

/// Painlevé's paradox (Génot and Brogliato 1999): a rod sliding on its end with large `μ` at a
/// shallow angle has, slipping, an effective normal mass `A M⁻¹ (A − μ sign(s) S)ᵀ < 0` (its
/// normal acceleration falls as its normal force grows): the contact problem has no solution or
/// two. Here `1 + 3 cos²θ − 3 μ sin θ cos θ < 0` for `θ = 0.7`, `μ = 3` (`l = 1`). The run
/// stops with the paradox, naming the contact, everything up to it kept.
#[test]
fn a_rod_sliding_on_a_rough_floor_stops_at_painleves_paradox() {
    let (l, mu, theta) = (1.0_f64, 3.0, 0.7_f64);
    assert!(1.0 + 3.0 * theta.cos().powi(2) - 3.0 * mu * theta.sin() * theta.cos() < 0.0);
    let rod = Rod {
        l,
        constraints: vec![Constraint::new("end", 0.0).with_friction(Friction::coulomb(mu))],
    };
    // Resting on its end, sliding towards its lower side (s < 0: friction pushes +x).
    let (run, _) = simulate(&rod, &[0.0, l * theta.sin(), theta], &[-1.0, 0.0, 0.0], 1.0);
    match &run.outcome {
        Outcome::Failed(Error::Painleve { constraints, .. }) => {
            assert_eq!(constraints, &["end".to_string()])
        }
        other => panic!("expected Painlevé's paradox, got {other:?}"),
    }
    // With little friction the same rod slides and falls, no paradox.
    let rod = Rod {
        l,
        constraints: vec![Constraint::new("end", 0.0).with_friction(Friction::coulomb(0.1))],
    };
    let (run, _) = simulate(&rod, &[0.0, l * theta.sin(), theta], &[-1.0, 0.0, 0.0], 0.2);
    assert_eq!(run.outcome, Outcome::Finished, "{}", run.outcome);
}
