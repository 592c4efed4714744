//! A model file and the same system written in Rust give the same execution: the shipped model
//! files against the engine's Rust models of the paper's examples (event times to 1e-12, or as
//! well as the speed at which a surface is approached resolves them).

use std::path::PathBuf;

use zenosim::models::{BallOnSine, BouncingBall, CartPendulum, Example, SphericalPendulum};
use zenosim::{
    Completion, Event, EventKind, Execution, HybridLagrangian, Outcome, Simulation,
    SimulationOptions,
};
use zenosim_model::{parse_model, ModelFile};

/// The repository's `models/` folder.
fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

/// The file names of the shipped models, sorted.
fn shipped_models() -> Vec<String> {
    let mut names: Vec<_> = std::fs::read_dir(models_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    names
}

fn load(name: &str) -> ModelFile {
    let path = models_dir().join(name);
    let source = std::fs::read_to_string(&path).unwrap();
    parse_model(name, &source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn run<L: HybridLagrangian>(
    model: &L,
    q0: &[f64],
    q_dot0: &[f64],
    options: SimulationOptions,
) -> Execution {
    Simulation::new(model, q0, q_dot0, options)
        .unwrap()
        .run(&mut ())
}

/// How far apart the two runs may time the impact `event`: 1e-12, or `1e-13/|ḣ|` where the
/// event's constraint is approached at `|ḣ| < 0.1` (`ḣ` along the state before it, by central
/// differences along `q̇`), but never more than 1e-9.
fn time_bound<L: HybridLagrangian>(model: &L, event: &Event) -> f64 {
    let (q, q_dot) = (&event.before.q, &event.before.q_dot);
    let delta = 1e-7 / q_dot.iter().fold(1e-300, |m: f64, v| m.max(v.abs()));
    let along = |s: f64| -> Vec<f64> { q.iter().zip(q_dot).map(|(x, v)| x + s * v).collect() };
    let h = |s: f64| model.constraint(event.constraint, &along(s));
    let h_dot = (h(delta) - h(-delta)) / (2.0 * delta);
    (1e-13 / h_dot.abs()).clamp(1e-12, 1e-9)
}

/// Runs a model file from its initial state with its own options.
fn run_file(file: &ModelFile) -> Execution {
    run(
        &file.model,
        &file.initial.q,
        &file.initial.q_dot,
        file.options(),
    )
}

/// Runs the file and the Rust example with the file's options and compares the executions.
fn same_execution<M: HybridLagrangian>(file: &str, rust: Example<M>, completion: Completion) {
    let file = load(file);
    let options = SimulationOptions {
        completion,
        ..file.options()
    };
    assert_eq!(
        options.completion,
        file.options().completion,
        "the file's own R∞ setting"
    );
    assert_eq!(options.t_end, rust.t_end);
    // The same initial state, up to rounding: `pi/3` in the file is `π/3` rounded twice
    // (1.0471975511965976) while Rust's FRAC_PI_3 is rounded once (…979). Both runs start from
    // the file's state, so that they differ in the model's functions only.
    let gap = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    assert!(
        gap(&file.initial.q, &rust.q0) <= 4.0 * f64::EPSILON,
        "{:?}",
        file.initial.q
    );
    assert_eq!(file.initial.q_dot, rust.q_dot0);

    let from_file = run(&file.model, &file.initial.q, &file.initial.q_dot, options);
    let from_rust = run(&rust.model, &file.initial.q, &file.initial.q_dot, options);
    assert_eq!(from_file.outcome, Outcome::Finished);
    assert_eq!(from_rust.outcome, Outcome::Finished);

    // The same events, at the same times.
    let kinds = |x: &Execution| x.events.iter().map(|e| e.kind).collect::<Vec<_>>();
    assert_eq!(kinds(&from_file), kinds(&from_rust), "{}", file.name);
    // Each to 1e-12, or to what a state difference of 1e-13 explains where that is more: a
    // crossing approached at the speed `ḣ` moves by `δ/|ḣ|` when the state moves by `δ`. The
    // impacts deep in a Zeno sequence are approached ever more slowly, and two computations that
    // round differently time them only that well: the twins' step sizes differ by about 1e-9
    // relative, and the spherical pendulum's last impacts, at `ḣ` near 1.6e-5, differ by up to
    // 7e-11 (a state difference of about 1e-15). A switch at a Zeno point is timed as the
    // impact it follows; a lift-off (decided by the normal force, not by `h`) to 1e-12.
    let bounds: Vec<f64> = from_file
        .events
        .iter()
        .scan(1e-12, |last, e| {
            *last = match e.kind {
                EventKind::Zeno => *last,
                EventKind::Impact => time_bound(&rust.model, e),
                _ => 1e-12,
            };
            Some(*last)
        })
        .collect();
    let mut worst: f64 = 0.0;
    let mut worst_allowed: f64 = 0.0;
    for ((a, b), &allowed) in from_file.events.iter().zip(&from_rust.events).zip(&bounds) {
        assert!(
            (a.t - b.t).abs() <= allowed,
            "{}: {:?} at t = {}: times differ by {:e}, more than {allowed:e}",
            file.name,
            a.kind,
            a.t,
            a.t - b.t
        );
        worst = worst.max((a.t - b.t).abs());
        worst_allowed = worst_allowed.max(allowed);
    }
    let impacts = from_file
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .count();
    assert!(impacts > 10, "{}: {impacts} impacts", file.name);
    assert_eq!(from_file.zeno.len(), from_rust.zeno.len());
    let switches = from_file
        .events
        .iter()
        .zip(&bounds)
        .filter(|(e, _)| e.kind == EventKind::Zeno);
    for ((a, b), (_, &allowed)) in from_file.zeno.iter().zip(&from_rust.zeno).zip(switches) {
        assert_eq!(a.kind, b.kind);
        // τ∞ is the switch's time and a remainder much shorter than the last flights.
        assert!(
            (a.t_zeno - b.t_zeno).abs() <= allowed,
            "τ∞ {} vs {} (at most {allowed:e} apart)",
            a.t_zeno,
            b.t_zeno
        );
    }
    // And the same state at the stop time.
    let state_gap = from_file
        .final_state
        .q
        .iter()
        .chain(&from_file.final_state.q_dot)
        .zip(
            from_rust
                .final_state
                .q
                .iter()
                .chain(&from_rust.final_state.q_dot),
        )
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        state_gap <= 1e-9,
        "{}: final states differ by {state_gap:e}",
        file.name
    );
    println!(
        "{}: {} events, {impacts} impacts, event times differ by at most {worst:e} (allowed up to {worst_allowed:e}), final state by {state_gap:e}",
        file.name,
        from_file.events.len()
    );
}

#[test]
fn the_papers_ball() {
    same_execution(
        "ball-on-sine.toml",
        BallOnSine::paper(),
        Completion::Projection,
    );
}

#[test]
fn the_demo_ball_with_the_papers_map() {
    // The file gives the paper's R∞ as its zeno_reset; the Rust model has it built in.
    same_execution(
        "ball-on-sine-demo.toml",
        BallOnSine::demo(),
        Completion::ModelMap,
    );
}

#[test]
fn the_cart_pendulum() {
    same_execution(
        "cart-pendulum.toml",
        CartPendulum::demo(),
        Completion::Projection,
    );
}

#[test]
fn the_spherical_pendulum() {
    same_execution(
        "spherical-pendulum.toml",
        SphericalPendulum::demo(),
        Completion::Projection,
    );
}

#[test]
fn the_bouncing_ball() {
    let rust = Example {
        model: BouncingBall::new(1.0, 9.81, 0.5),
        q0: vec![1.0],
        q_dot0: vec![0.0],
        t_end: 3.0,
    };
    let tau = rust.model.zeno_time(1.0);
    same_execution("bouncing-ball.toml", rust, Completion::Projection);
    // The file's header comment gives the Zeno time; check it against the closed form.
    let text = std::fs::read_to_string(models_dir().join("bouncing-ball.toml")).unwrap();
    assert!(
        text.contains(&format!("{tau:.7}")),
        "closed form τ∞ = {tau}"
    );
}

#[test]
fn every_shipped_model_loads_and_runs_to_its_stop_time() {
    let names = shipped_models();
    assert!(names.len() >= 6, "{names:?}");
    for name in names {
        let file = load(&name);
        assert_eq!(
            format!("{}.toml", file.name),
            name,
            "a model's name is its file's"
        );
        let run = run(
            &file.model,
            &file.initial.q,
            &file.initial.q_dot,
            file.options(),
        );
        if name == "painleve-rod.toml" {
            // The one model made to fail: at Painlevé's paradox, at once (docs/friction.md).
            assert!(
                matches!(
                    run.outcome,
                    Outcome::Failed(zenosim::Error::Painleve { .. })
                ),
                "{name}: {}",
                run.outcome
            );
            continue;
        }
        assert_eq!(run.outcome, Outcome::Finished, "{name}");
        assert_eq!(run.t_final, file.settings.t_end, "{name}");
        // Every model reaches the constrained motion: through a Zeno point, or held from the
        // start where it starts at rest on a constraint (floor-and-wall slides on its floor).
        let held_from_start = matches!(run.intervals[0].mode, zenosim::Mode::Constrained(_));
        assert!(
            !run.zeno.is_empty() || held_from_start,
            "{name} reaches a Zeno point or starts held"
        );
    }
}

/// The largest difference of the event times of two executions with the same events.
fn event_time_gap(a: &Execution, b: &Execution) -> f64 {
    let kinds = |x: &Execution| x.events.iter().map(|e| e.kind).collect::<Vec<_>>();
    assert_eq!(kinds(a), kinds(b));
    a.events
        .iter()
        .zip(&b.events)
        .map(|(x, y)| (x.t - y.t).abs())
        .fold(0.0, f64::max)
}

/// Every shipped model's derivatives are compiled in full, so none falls back to
/// differentiating through the interpreter, and the compiled model runs as the interpreted one
/// does: the formulas use no operation whose real part the interpreter adjusts (division, tan,
/// tanh, powers beyond 3), so the numbers are the same and so are the event times.
#[test]
fn shipped_models_run_compiled_as_interpreted() {
    let names = shipped_models();
    for name in names {
        let file = load(&name);
        let compiled = file.model.compiled_derivatives().expect("compiled");
        let (traced, parts) = compiled.coverage();
        assert_eq!(traced, parts, "{name}: {traced} of {parts} parts compiled");
        let interpreted = file.model.clone().interpreted();
        assert!(interpreted.compiled_derivatives().is_none());
        let (q0, v0) = (&file.initial.q, &file.initial.q_dot);
        let fast = run(&file.model, q0, v0, file.options());
        let slow = run(&interpreted, q0, v0, file.options());
        let gap = event_time_gap(&fast, &slow);
        assert!(gap <= 1e-12, "{name}: event times differ by {gap:e}");
        assert_eq!(fast.final_state.q, slow.final_state.q, "{name}");
        assert_eq!(fast.final_state.q_dot, slow.final_state.q_dot, "{name}");
        println!(
            "{name}: {} compiled operations, {} events, same as interpreted",
            compiled.operations(),
            fast.events.len()
        );
    }
}

/// The compiled held acceleration hands a state where the squares of its norms over- or
/// underflow (a ball of mass 1e-156: `|M⁻¹Aᵀ|² = ∞`; of 1e201: `s² = 0`) to the general path,
/// which decides from the vectors that the floor acts: the ball comes to rest on it after the
/// Zeno point, as the interpreted model's does, to the bit. (A deferral turned into an error
/// would fail the run at the first step on the floor.)
#[test]
fn the_compiled_held_motion_defers_where_the_squares_overflow() {
    let source = std::fs::read_to_string(models_dir().join("bouncing-ball.toml")).unwrap();
    for mass in ["1e-156", "1e201"] {
        let mass: zenosim_model::Override = format!("m={mass}").parse().unwrap();
        let file = parse_model("bouncing-ball.toml", &source, std::slice::from_ref(&mass))
            .unwrap_or_else(|e| panic!("{e}"));
        let compiled = file.model.compiled_derivatives().expect("compiled");
        assert_eq!(compiled.coverage().0, compiled.coverage().1, "{mass}");
        let interpreted = file.model.clone().interpreted();
        let (q0, v0) = (&file.initial.q, &file.initial.q_dot);
        let fast = run(&file.model, q0, v0, file.options());
        let slow = run(&interpreted, q0, v0, file.options());
        assert_eq!(fast.outcome, Outcome::Finished, "{mass}");
        assert!(
            matches!(fast.final_mode, zenosim::Mode::Constrained(_)),
            "{mass}: {:?}",
            fast.final_mode
        );
        assert_eq!(fast.zeno.len(), 1, "{mass}");
        assert_eq!(event_time_gap(&fast, &slow), 0.0, "{mass}");
        assert_eq!(fast.final_state.q, slow.final_state.q, "{mass}");
        assert_eq!(fast.final_state.q_dot, slow.final_state.q_dot, "{mass}");
    }
}

/// A formula that branches on a value (`abs`) cannot be traced: that constraint is
/// differentiated through the interpreter, the rest is compiled, and the run is right.
/// A particle at x = 0.5 moving at 1 between elastic walls at x = ±1 (h = 1 − |x|) hits them
/// at t = 0.5, 2.5, 4.5 (closed form).
#[test]
fn a_formula_with_abs_falls_back_to_differentiation_for_that_part() {
    let source = r#"
name = "walls"
coordinates = ["x"]
lagrangian = "0.5*x_dot^2"
[[constraint]]
name = "walls"
h = "1 - abs(x)"
restitution = 1.0
[initial]
x = 0.5
x_dot = 1.0
[simulation]
t_end = 5.0
"#;
    let file = parse_model("walls.toml", source, &[]).unwrap_or_else(|e| panic!("{e}"));
    let compiled = file.model.compiled_derivatives().expect("compiled");
    // The Lagrangian's terms, the energy and the free motion; not the constraint's
    // derivatives, its guard, the motion or acceleration held on it nor its direction.
    assert_eq!(compiled.coverage(), (3, 8));
    let run = run_file(&file);
    assert_eq!(run.outcome, Outcome::Finished);
    let impacts: Vec<f64> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .map(|e| e.t)
        .collect();
    assert_eq!(impacts.len(), 3, "{impacts:?}");
    for (t, exact) in impacts.iter().zip([0.5, 2.5, 4.5]) {
        assert!((t - exact).abs() <= 1e-9, "impact at {t}, exactly {exact}");
    }
}

#[test]
fn the_lift_off_model_lifts_off_and_lands() {
    let file = load("ball-off-cylinder.toml");
    let run = run_file(&file);
    assert_eq!(run.outcome, Outcome::Finished);
    // Bounces to rest on the cylinder, slides off, bounces to rest on the floor.
    let liftoffs: Vec<_> = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Liftoff)
        .collect();
    assert_eq!(
        liftoffs.len(),
        1,
        "{:?}",
        run.events.iter().map(|e| (e.kind, e.t)).collect::<Vec<_>>()
    );
    assert_eq!(run.zeno.len(), 2);
    assert_eq!((run.zeno[0].constraint, run.zeno[1].constraint), (0, 1));
    let liftoff = liftoffs[0];
    assert!(run.zeno[0].t_switch < liftoff.t && liftoff.t < run.zeno[1].t_switch);
    // It lets go where the normal force vanishes: v² = g R cos θ (from m v²/R = m g cos θ).
    let (q, v) = (&liftoff.after.q, &liftoff.after.q_dot);
    let radius = (q[0] * q[0] + q[1] * q[1]).sqrt();
    let cos_theta = q[1] / radius;
    let speed2 = v[0] * v[0] + v[1] * v[1];
    assert!(
        (speed2 - 9.81 * radius * cos_theta).abs() < 1e-7,
        "{speed2} vs {}",
        9.81 * radius * cos_theta
    );
    assert!(cos_theta > 0.5 && cos_theta < 0.7, "cos θ = {cos_theta}");
}
