//! Random initial states on every shipped model (issue 5): the executions never fall through a
//! constraint, never hang and never gain energy.
//!
//! Each model in `models/` runs from random admissible states to its own `t_end`, with its own
//! options. The states are drawn in a box around the model's initial state and scale
//! ([`Spec::base`]), and a quarter each of them moved exactly onto a constraint (moving into it,
//! away from it or along it), onto it at rest or sliding, and just above it ([`Start`]). An
//! observer ([`Checker`]) checks every sample and event as it comes, without storing the
//! trajectory; half the runs are sampled at the end of every step, half on a grid finer than
//! the steps ([`GRID_POINTS`]):
//! - no fall-through: `h_i ≥ −tol_i` at every sample, `tol_i` the integration's position
//!   tolerance as `h_i` sees it; on the constraint, `|h_i| ≤ tol_i`;
//! - no energy gain: the energy never rises above its lowest earlier value by more than the
//!   integration error the run may have accumulated, and no event (impact, switch to the
//!   constrained motion, lift-off) adds more than the state's energy resolution. Every shipped
//!   model is conservative between impacts, with `e ≤ 1`. The one exception is the model's
//!   own `R∞` (`zeno_reset`, the paper's map in `ball-on-sine-demo.toml`): what it adds is
//!   the model's, bounded by [`MODEL_MAP_GAIN`] and reported;
//! - no hang: every run ends `Finished` within [`STEP_LIMIT`] steps and the model's event limit.
//!
//! [`DEFAULT_CASES`] cases per model; `ZENOSIM_RANDOM_STATES=5000` runs more, and
//! `ZENOSIM_RANDOM_SEED=<n>` draws other ones. A failure prints the initial state and a
//! `zenosim run` command that repeats it. `--nocapture` prints each model's statistics.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};
use zenosim::{
    Completion, Derived, Event, EventKind, HybridLagrangian, Mode, Observer, Outcome, OutputGrid,
    Sample, Simulation, SimulationOptions, Tolerances,
};
use zenosim_model::{parse_model, FileModel, ModelFile};

/// Cases per model in the ordinary test run: the six models take about 5 s together in the
/// test profile on one core, 3 s on two (up to 6 s on a busy machine; the ball-on-sine demo, to
/// t = 20 with e = 0.9, takes a third of it). 900 runs: each start kind about 225 times.
const DEFAULT_CASES: u32 = 150;

/// The most accepted steps a run may take: the longest of 12 × 5000 random runs took 2656, so
/// a run that needs nearly 40 times that is stuck, and this limit ends it (failed,
/// `Error::Limit`) in well under a second, for the test to report. Events are limited by the
/// model (100 000; the most in a random run was 1157).
const STEP_LIMIT: u64 = 100_000;

/// The most energy a model's own `R∞` may add at a switch, relative to the size of the energy's
/// terms `Σ|∂E/∂y_i||y_i|`. The paper's map for the ball on the sine (`x3 = sin x2`,
/// `ẋ3 = cos x2 ẋ2`) removes the normal velocity `A q̇` left at the switch through `ẋ3` alone,
/// not along `M⁻¹Aᵀ` as the plastic projection does, so it changes the kinetic energy at first
/// order, by `−ẋ3 A q̇`. The engine switches where the remaining bounces are below what it
/// resolves (heights of ~1e-12 to 1e-10), which leaves up to ~6e-5 of normal speed: gains up to
/// 9e-6 of the energy's size in the random runs so far. 1e-4 leaves a factor 10, and still
/// fails a map or a switch that adds energy at the scale of the motion.
const MODEL_MAP_GAIN: f64 = 1e-4;

/// Half the cases are sampled every `t_end / GRID_POINTS` on the integrator's dense output
/// (finer than its steps: 2656 steps at most in 12 × 5000 runs) instead of at the step ends, so
/// that a body that passes through a surface and back inside one step shows: with the engine's
/// search for such dips disabled, these samples catch it within 1000 cases, the step ends do
/// not; and they found three ways the engine let a body through (see the engine's
/// `tests/engine/random_states.rs`). The energy slack counts steps, so those cases check the
/// events' energy only.
const GRID_POINTS: f64 = 5000.0;

/// The repository's `models/` folder.
fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

fn load(name: &str) -> ModelFile {
    let path = models_dir().join(name);
    let source = std::fs::read_to_string(&path).unwrap();
    parse_model(name, &source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn parameter(file: &ModelFile, name: &str) -> f64 {
    file.parameters
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{}: no parameter {name}", file.name))
        .1
}

fn lerp(u: f64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * u
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `Σ_j |A_j q_j|`: the size of `h`'s terms (coordinates `h` ignores do not count).
fn terms(a: &[f64], q: &[f64]) -> f64 {
    a.iter().zip(q).map(|(ai, qi)| (ai * qi).abs()).sum()
}

/// A state `(q, q̇)`.
type State = (Vec<f64>, Vec<f64>);

// ----- drawing the states --------------------------------------------------------------------

/// How a model's random states are drawn.
struct Spec {
    /// The file under `models/`.
    file: &'static str,
    /// A state in the model's box from eight uniform numbers in `[0, 1)` (`u[6]`, `u[7]` are
    /// left for [`initial_state`]), admissible (`h ≥ 0`) by construction.
    base: fn(&ModelFile, &[f64; 8]) -> State,
    /// The seed of the random states.
    seed: u64,
    /// A quantity of the initial state whose smallest value over the cases is reported.
    closest: Option<(&'static str, Measure)>,
}

/// A quantity of a model's initial state.
type Measure = fn(&ModelFile, &State) -> f64;

/// Where a case starts, relative to the constraints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    /// Anywhere in the box.
    Box,
    /// On a constraint (`h = 0` to rounding), with the base state's normal velocity `A q̇`:
    /// into the surface (an impact at t = 0) or away from it.
    OnSurface,
    /// On a constraint at `A q̇ = 0`: resting on it, or sliding along it.
    Resting,
    /// `10⁻¹²` to `10⁻³` of the constraint's scale above it, with the base state's normal
    /// velocity: short flights, impacts within the first step.
    JustAbove,
}

impl Start {
    fn from_index(index: u8) -> Self {
        match index {
            0 => Start::Box,
            1 => Start::OnSurface,
            2 => Start::Resting,
            _ => Start::JustAbove,
        }
    }
}

/// A random case: the start kind ([`Start`] from `kind % 4`; sampled on a grid when
/// `kind ≥ 4`, see [`GRID_POINTS`]) and eight uniform numbers.
type Case = (u8, [f64; 8]);

/// Whether a case is sampled on the uniform grid.
fn on_grid(case: &Case) -> bool {
    case.0 >= 4
}

/// The initial state of `case`: the model's base state, moved onto or near a constraint (the
/// one `u[7]` picks) as [`Start`] says, through the engine's own projection `R∞` (positions
/// along `M⁻¹Aᵀ` onto `h = 0`, the normal velocity removed). `Err` says why it is refused.
fn initial_state(
    spec: &Spec,
    file: &ModelFile,
    derived: &Derived<FileModel>,
    case: &Case,
) -> Result<State, &'static str> {
    let (kind, u) = case;
    let start = Start::from_index(kind % 4);
    let (mut q, mut v) = (spec.base)(file, u);
    let m = file.model.constraints().len();
    if start != Start::Box {
        let index = ((u[7] * m as f64) as usize).min(m - 1);
        let (_, a_before) = derived.constraint(index, &q);
        let v_normal = dot(&a_before, &v);
        towards_constraint(derived, index, &mut q)?;
        derived
            .project(index, &mut q, &mut v)
            .ok_or("the projection onto the constraint failed")?;
        let (_, a) = derived.constraint(index, &q);
        let a2 = dot(&a, &a);
        if start != Start::Resting {
            // Along Aᵀ, so that A q̇ = v_normal.
            for (vi, ai) in v.iter_mut().zip(&a) {
                *vi += v_normal * ai / a2;
            }
        }
        if start == Start::JustAbove {
            let height = 10f64.powf(lerp(u[6], -12.0, -3.0)) * (1.0 + terms(&a, &q));
            for (qi, ai) in q.iter_mut().zip(&a) {
                *qi += height * ai / a2;
            }
        }
    }
    for index in 0..m {
        let (h, a) = derived.constraint(index, &q);
        // What Simulation::new allows: the rounding of h's terms on the surface.
        if h.is_nan() || h < -1e-12 * (h.abs() + terms(&a, &q)).max(1.0) {
            return Err("h < 0 (inadmissible)");
        }
    }
    // A start where M is singular (the spherical pendulum exactly at its pole θ = 0, where its
    // coordinates are singular) is no state of the system: Simulation::new refuses it.
    if !derived.mass_matrix(&q, &v).1 {
        return Err("M is singular at the start (the spherical pendulum at its pole)");
    }
    Ok((q, v))
}

/// Damped Newton steps along `Aᵀ` (at most 0.5 long) that bring `q` close to `h = 0` from
/// anywhere in the box, from where the engine's projection (undamped Newton) converges: from
/// `θ = 0.1`, the pendulums' `h = cos θ` would send an undamped step to `θ = 10`.
fn towards_constraint(
    derived: &Derived<FileModel>,
    index: usize,
    q: &mut [f64],
) -> Result<(), &'static str> {
    for _ in 0..100 {
        let (h, a) = derived.constraint(index, q);
        let a2 = dot(&a, &a);
        if !(a2 > 0.0 && h.is_finite()) {
            return Err("no direction towards the constraint (A = 0)");
        }
        let length = h.abs() / a2.sqrt();
        let damping = if length > 0.5 { 0.5 / length } else { 1.0 };
        for (qi, ai) in q.iter_mut().zip(&a) {
            *qi -= damping * h * ai / a2;
        }
        if length <= 1e-3 {
            return Ok(());
        }
    }
    Err("the damped Newton steps did not reach the constraint")
}

/// The bouncing ball: heights up to twice its drop height `h0`, speeds up to the impact speed
/// `√(2 g h0)` of its own drop, either way.
fn bouncing_ball(file: &ModelFile, u: &[f64; 8]) -> State {
    let (h0, g) = (parameter(file, "h0"), parameter(file, "g"));
    let speed = (2.0 * g * h0).sqrt();
    (vec![2.0 * h0 * u[0]], vec![lerp(u[1], -speed, speed)])
}

/// The ball on `x3 = sin x2` (both files): `x2` a period around the file's `π/3`, up to 3 above
/// the surface (the file starts 1.13 above it), `x1` within 1 of the file's 0, each velocity up
/// to 3 either way (the file's drop lands at 4.7).
fn ball_on_sine(_: &ModelFile, u: &[f64; 8]) -> State {
    let x2 = FRAC_PI_3 + lerp(u[1], -PI, PI);
    let q = vec![lerp(u[0], -1.0, 1.0), x2, x2.sin() + 3.0 * u[2]];
    let v = vec![
        lerp(u[3], -3.0, 3.0),
        lerp(u[4], -3.0, 3.0),
        lerp(u[5], -3.0, 3.0),
    ];
    (q, v)
}

/// The pendulum on the cart: every admissible angle `|θ| ≤ π/2` (`h = cos θ ≥ 0`), the cart
/// within a rod length `l` of the origin; `θ̇` up to `2√(g/l)`, enough to swing over the top
/// from the deck (`√(2g/l)` with the cart held), `ẋ` up to 3 either way (the file's −1.4).
fn cart_pendulum(file: &ModelFile, u: &[f64; 8]) -> State {
    let (l, g) = (parameter(file, "l"), parameter(file, "g"));
    let rate = 2.0 * (g / l).sqrt();
    let q = vec![lerp(u[0], -FRAC_PI_2, FRAC_PI_2), lerp(u[1], -l, l)];
    let v = vec![lerp(u[2], -rate, rate), lerp(u[3], -3.0, 3.0)];
    (q, v)
}

/// The spherical pendulum: `0 ≤ θ ≤ π/2` (`h = cos θ ≥ 0`), any `φ`, `θ̇` up to `2√(g/l)`
/// (enough to swing over the pole), `φ̇` up to 2 either way (the file's 1.0). Only `θ = 0`
/// itself is refused (`M` singular, see [`initial_state`]): the engine passes the pole at any
/// distance ([`the_spherical_pendulum_passes_its_pole_at_any_distance`]).
fn spherical_pendulum(file: &ModelFile, u: &[f64; 8]) -> State {
    let (l, g) = (parameter(file, "l"), parameter(file, "g"));
    let rate = 2.0 * (g / l).sqrt();
    let q = vec![lerp(u[0], 0.0, FRAC_PI_2), lerp(u[1], -PI, PI)];
    let v = vec![lerp(u[2], -rate, rate), lerp(u[3], -2.0, 2.0)];
    (q, v)
}

/// The closest approach `θ*` of the spherical pendulum to its pole `θ = 0`, where its
/// coordinates are singular (`M = m l² diag(1, sin²θ)`). With `p = sin²θ φ̇` (conserved) and the
/// energy `ε = ½θ̇² + U(θ)` per `m l²`, `U(θ) = ½ p²/sin²θ + (g/l) cos θ` decreases on
/// `(0, π/2]` and impacts only lower `ε`: the whole run stays in `θ ≥ θ*`, `U(θ*) = ε` (0 if
/// `p = 0` and `ε ≥ g/l`: it swings through the pole).
fn closest_approach_to_the_pole(file: &ModelFile, (q, v): &State) -> f64 {
    let (l, g) = (parameter(file, "l"), parameter(file, "g"));
    let p = q[0].sin().powi(2) * v[1];
    let u = |theta: f64| 0.5 * p * p / theta.sin().powi(2) + g / l * theta.cos();
    let energy = 0.5 * v[0] * v[0] + u(q[0]);
    if q[0] <= 0.0 || (p == 0.0 && energy >= g / l) {
        return 0.0;
    }
    // Bisection on [0, θ0]: U(lo) > ε ≥ U(hi).
    let (mut lo, mut hi) = (0.0_f64, q[0]);
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            return hi;
        }
        if u(mid) > energy {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

/// The ball, the cylinder of radius `R` and the floor at `y = −H`: `|x| ≤ 2R`, from the floor
/// to `R` above the cylinder's top, a point inside the cylinder reflected radially out of it
/// (`r ↦ 2R − r`); each velocity up to 3 either way (the file's drop from the top lands on
/// the floor at 7.6). The cylinder and the floor are `H − R` apart: no simultaneous contacts.
fn ball_off_cylinder(file: &ModelFile, u: &[f64; 8]) -> State {
    let (radius, depth) = (parameter(file, "R"), parameter(file, "H"));
    let (mut x, mut y) = (
        lerp(u[0], -2.0 * radius, 2.0 * radius),
        lerp(u[1], -depth, 2.0 * radius),
    );
    let r = x.hypot(y);
    if r < radius {
        if r == 0.0 {
            (x, y) = (0.0, 2.0 * radius);
        } else {
            let stretch = (2.0 * radius - r) / r;
            (x, y) = (x * stretch, y * stretch);
        }
    }
    let v = vec![lerp(u[2], -3.0, 3.0), lerp(u[3], -3.0, 3.0)];
    (vec![x, y], v)
}

/// The corner: anywhere in twice the drop box, at up to the wall's and the floor's own impact
/// speeds, either way.
fn corner(file: &ModelFile, u: &[f64; 8]) -> State {
    let (x0, y0) = (parameter(file, "x0"), parameter(file, "y0"));
    let (gx, gy) = (parameter(file, "gx"), parameter(file, "gy"));
    let (sx, sy) = ((2.0 * gx * x0).sqrt(), (2.0 * gy * y0).sqrt());
    (
        vec![2.0 * x0 * u[0], 2.0 * y0 * u[1]],
        vec![lerp(u[2], -sx, sx), lerp(u[3], -sy, sy)],
    )
}

/// The V-groove: anywhere in the wedge up to twice the starting height, at up to the speed
/// a fall from there gives.
fn v_groove(file: &ModelFile, u: &[f64; 8]) -> State {
    let (k, y0, g) = (
        parameter(file, "k"),
        parameter(file, "y0"),
        parameter(file, "g"),
    );
    let y = 2.0 * y0 * u[0];
    let x = lerp(u[1], -y / k, y / k);
    let s = (2.0 * g * 2.0 * y0).sqrt();
    (vec![x, y], vec![lerp(u[2], -s, s), lerp(u[3], -s, s)])
}

/// The floor and the wall: between the wall and twice its distance behind, up to a metre
/// high, at up to twice the shipped speed.
fn floor_and_wall(file: &ModelFile, u: &[f64; 8]) -> State {
    let (d, v0) = (parameter(file, "d"), parameter(file, "v0"));
    (
        vec![lerp(u[0], -d, d), u[1]],
        vec![lerp(u[2], -2.0 * v0, 2.0 * v0), lerp(u[3], -2.0, 2.0)],
    )
}

/// The rocking block: tilted up to 0.3 either way, its lower corner up to 0.2 above the floor,
/// rocking at up to 3 rad/s and moving at up to 1 m/s.
fn rocking_block(file: &ModelFile, u: &[f64; 8]) -> State {
    let (b, c) = (parameter(file, "b"), parameter(file, "c"));
    let theta = lerp(u[0], -0.3, 0.3);
    let y = c * theta.cos() + b * theta.sin().abs() + 0.2 * u[1];
    (
        vec![lerp(u[2], -1.0, 1.0), y, theta],
        vec![
            lerp(u[3], -1.0, 1.0),
            lerp(u[4], -1.0, 1.0),
            lerp(u[5], -3.0, 3.0),
        ],
    )
}

/// The ball with backspin: up to 1 above the floor, moving at up to 3 either way, spinning at up
/// to 40 rad/s either way.
fn ball_backspin(file: &ModelFile, u: &[f64; 8]) -> State {
    let r = parameter(file, "r");
    (
        vec![lerp(u[0], -1.0, 1.0), r + u[1], lerp(u[2], -PI, PI)],
        vec![
            lerp(u[3], -3.0, 3.0),
            lerp(u[4], -3.0, 3.0),
            lerp(u[5], -40.0, 40.0),
        ],
    )
}

/// A block on a rough plane (the incline, the belt): up to 0.5 off it, moving at up to 3
/// either way along it and 2 off it.
fn block_on_plane(_: &ModelFile, u: &[f64; 8]) -> State {
    (
        vec![lerp(u[0], -1.0, 1.0), 0.5 * u[1]],
        vec![lerp(u[2], -3.0, 3.0), lerp(u[3], -2.0, 2.0)],
    )
}

/// The rod on a rough floor: tilted by 0.1 to 1.4, its lower end up to 0.3 above the floor,
/// moving at up to 2 either way and turning at up to 3 rad/s.
fn painleve_rod(file: &ModelFile, u: &[f64; 8]) -> State {
    let l = parameter(file, "l");
    let theta = lerp(u[0], 0.1, 1.4);
    (
        vec![0.0, l * theta.sin() + 0.3 * u[1], theta],
        vec![
            lerp(u[2], -2.0, 2.0),
            lerp(u[3], -2.0, 2.0),
            lerp(u[4], -3.0, 3.0),
        ],
    )
}

/// The sphere in space: up to 0.5 above the plane, moving at up to 3 along and across it and
/// 3 up or down, spinning at up to 20 rad/s about each axis (impacts, slips and rolls in
/// space).
fn sphere_in_space(file: &ModelFile, u: &[f64; 8]) -> State {
    let r = parameter(file, "r");
    (
        vec![0.0, 0.0, r + 0.5 * u[0], 0.0, 0.0, 0.0],
        vec![
            lerp(u[1], -3.0, 3.0),
            lerp(u[2], -3.0, 3.0),
            lerp(u[3], -3.0, 3.0),
            lerp(u[4], -20.0, 20.0),
            lerp(u[5], -20.0, 20.0),
            // u[6] and u[7] are the start's: the spin about the vertical from u[0]'s digits.
            lerp((7.0 * u[0]).fract(), -20.0, 20.0),
        ],
    )
}

/// The dumbbell in space: tilted by up to 0.3 rad, its lower end up to 0.3 above the floor,
/// heading anywhere, its centre moving at up to 2 along each axis, tilting at up to 2 rad/s and
/// turning at up to 5 rad/s.
fn dumbbell(file: &ModelFile, u: &[f64; 8]) -> State {
    let l = parameter(file, "l");
    let tilt = lerp(u[0], -0.3, 0.3);
    (
        vec![
            0.0,
            0.0,
            0.5 * l * tilt.sin().abs() + 0.3 * u[1],
            tilt,
            lerp(u[2], -PI, PI),
        ],
        vec![
            lerp(u[3], -2.0, 2.0),
            lerp(u[4], -2.0, 2.0),
            lerp(u[5], -2.0, 2.0),
            // u[6] and u[7] are the start's: the tilt's and the turn's rates from u[0]'s and
            // u[1]'s digits.
            lerp((7.0 * u[0]).fract(), -2.0, 2.0),
            lerp((7.0 * u[1]).fract(), -5.0, 5.0),
        ],
    )
}

/// The rimless wheel: spoke 0 within a spoke's spacing of the slope's normal, the hub up to 0.3
/// above the lowest tip, moving at up to 2 either way and turning at up to 3 rad/s.
fn rimless_wheel(file: &ModelFile, u: &[f64; 8]) -> State {
    let (l, a) = (parameter(file, "l"), parameter(file, "a"));
    let theta = lerp(u[0], -a, a);
    (
        vec![0.0, l * theta.cos() + 0.3 * u[1], theta],
        vec![
            lerp(u[2], -2.0, 2.0),
            lerp(u[3], -2.0, 2.0),
            lerp(u[4], -3.0, 3.0),
        ],
    )
}

/// Newton's cradle: gaps of up to half a diameter, speeds up to 1 either way.
fn newtons_cradle(file: &ModelFile, u: &[f64; 8]) -> State {
    let d = parameter(file, "d");
    let x1 = u[0];
    let x2 = x1 + d + 0.5 * d * u[1];
    let x3 = x2 + d + 0.5 * d * u[2];
    let v = |k: usize| lerp(u[k], -1.0, 1.0);
    (vec![x1, x2, x3], vec![v(3), v(4), v(5)])
}

/// The double pendulum: the first link from the stop to horizontal, the second anywhere its
/// tip clears the ground, at up to 2 rad/s each.
fn double_pendulum_stop(file: &ModelFile, u: &[f64; 8]) -> State {
    let (ths, h) = (parameter(file, "ths"), parameter(file, "H"));
    let (l1, l2) = (parameter(file, "l1"), parameter(file, "l2"));
    let th1 = lerp(u[0], ths, FRAC_PI_2);
    let lowest = ((h - l1 * th1.cos()) / l2).clamp(-1.0, 1.0).acos();
    let th2 = lerp(u[1], lowest, std::f64::consts::PI - 1e-3) * if u[2] < 0.5 { -1.0 } else { 1.0 };
    (
        vec![th1, th2],
        vec![lerp(u[3], -2.0, 2.0), lerp(u[4], -2.0, 2.0)],
    )
}

/// The damped oscillator: up to twice its release point from the wall, at up to 3 m/s.
fn damped_oscillator(file: &ModelFile, u: &[f64; 8]) -> State {
    let x0 = parameter(file, "x0");
    (vec![2.0 * x0 * u[0]], vec![lerp(u[1], -3.0, 3.0)])
}

/// The dragged ball: up to twice its drop height, at up to 5 m/s either way.
fn dragged_ball(file: &ModelFile, u: &[f64; 8]) -> State {
    let h0 = parameter(file, "h0");
    (vec![2.0 * h0 * u[0]], vec![lerp(u[1], -5.0, 5.0)])
}

/// The arm: its first joint up to 1.5 rad from the stop, the second within 1 rad of its set
/// point, at up to 2 rad/s each.
fn pd_arm(file: &ModelFile, u: &[f64; 8]) -> State {
    let (stop, r2) = (parameter(file, "stop"), parameter(file, "r2"));
    (
        vec![lerp(u[0], stop - 1.5, stop), lerp(u[1], r2 - 1.0, r2 + 1.0)],
        vec![lerp(u[2], -2.0, 2.0), lerp(u[3], -2.0, 2.0)],
    )
}

/// The vibrating table (at `t = 0`, where it is at 0): up to 5 cm above it, at up to 1 m/s.
fn vibrating_table(_file: &ModelFile, u: &[f64; 8]) -> State {
    (vec![0.05 * u[0]], vec![lerp(u[1], -1.0, 1.0)])
}

/// The table: tilted up to 0.2 in pitch and roll, its lowest leg up to 0.3 above the floor,
/// moving at up to 1 m/s and 2 rad/s.
fn table(file: &ModelFile, u: &[f64; 8]) -> State {
    let (a, b) = (parameter(file, "a"), parameter(file, "b"));
    let (p, r) = (lerp(u[0], -0.2, 0.2), lerp(u[1], -0.2, 0.2));
    let z = a * p.sin().abs() + b * r.sin().abs() + 0.3 * u[2];
    (
        vec![z, p, r],
        vec![
            lerp(u[3], -1.0, 1.0),
            lerp(u[4], -2.0, 2.0),
            lerp(u[5], -2.0, 2.0),
        ],
    )
}

const SPECS: [Spec; 25] = [
    Spec {
        file: "rimless-wheel.toml",
        base: rimless_wheel,
        seed: 35,
        closest: None,
    },
    Spec {
        file: "ball-backspin.toml",
        base: ball_backspin,
        seed: 30,
        closest: None,
    },
    Spec {
        file: "belt-stick-slip.toml",
        base: block_on_plane,
        seed: 31,
        closest: None,
    },
    Spec {
        file: "housner-block.toml",
        base: rocking_block,
        seed: 32,
        closest: None,
    },
    Spec {
        file: "sphere-slide-spin.toml",
        base: sphere_in_space,
        seed: 36,
        closest: None,
    },
    Spec {
        file: "dumbbell-landing.toml",
        base: dumbbell,
        seed: 38,
        closest: None,
    },
    Spec {
        file: "painleve-rod.toml",
        base: painleve_rod,
        seed: 33,
        closest: None,
    },
    Spec {
        file: "rough-incline.toml",
        base: block_on_plane,
        seed: 34,
        closest: None,
    },
    Spec {
        file: "ball-off-cylinder.toml",
        base: ball_off_cylinder,
        seed: 1,
        closest: None,
    },
    Spec {
        file: "ball-on-sine-demo.toml",
        base: ball_on_sine,
        seed: 2,
        closest: None,
    },
    Spec {
        file: "ball-on-sine.toml",
        base: ball_on_sine,
        seed: 3,
        closest: None,
    },
    Spec {
        file: "bouncing-ball.toml",
        base: bouncing_ball,
        seed: 4,
        closest: None,
    },
    Spec {
        file: "cart-pendulum.toml",
        base: cart_pendulum,
        seed: 5,
        closest: None,
    },
    Spec {
        file: "corner.toml",
        base: corner,
        seed: 7,
        closest: None,
    },
    Spec {
        file: "damped-oscillator.toml",
        base: damped_oscillator,
        seed: 13,
        closest: None,
    },
    Spec {
        file: "double-pendulum-stop.toml",
        base: double_pendulum_stop,
        seed: 8,
        closest: None,
    },
    Spec {
        file: "dragged-ball.toml",
        base: dragged_ball,
        seed: 14,
        closest: None,
    },
    Spec {
        file: "floor-and-wall.toml",
        base: floor_and_wall,
        seed: 9,
        closest: None,
    },
    Spec {
        file: "newtons-cradle.toml",
        base: newtons_cradle,
        seed: 10,
        closest: None,
    },
    Spec {
        file: "pd-arm.toml",
        base: pd_arm,
        seed: 15,
        closest: None,
    },
    Spec {
        file: "rocking-block.toml",
        base: rocking_block,
        seed: 11,
        closest: None,
    },
    Spec {
        file: "spherical-pendulum.toml",
        base: spherical_pendulum,
        seed: 6,
        closest: Some((
            "sin θ* (the closest approach to the pole)",
            |file, state| closest_approach_to_the_pole(file, state).sin(),
        )),
    },
    Spec {
        file: "table.toml",
        base: table,
        seed: 12,
        closest: None,
    },
    Spec {
        file: "v-groove.toml",
        base: v_groove,
        seed: 17,
        closest: None,
    },
    Spec {
        file: "vibrating-table.toml",
        base: vibrating_table,
        seed: 16,
        closest: None,
    },
];

// ----- the checks ----------------------------------------------------------------------------

/// What one run showed.
#[derive(Clone, Debug, Default)]
struct RunRecord {
    /// The largest rise of the energy above its lowest earlier value.
    gain: f64,
    /// The largest such rise as a fraction of the slack at that time.
    gain_of_slack: f64,
    /// The largest energy change across an event, in units of what it is allowed.
    event_gain_of_slack: f64,
    /// The largest energy the model's own `R∞` added at a switch, relative to the energy's size.
    map_gain: f64,
    /// The largest normal speed `|A q̇|/|A|` at a switch (before it).
    switch_normal_speed: f64,
    /// The largest size of the energy's terms, `Σ|∂E/∂y_i||y_i|`.
    energy_size: f64,
    /// The lowest `h` (any constraint).
    lowest_h: f64,
    /// The lowest `h/tol` (any constraint).
    lowest_h_of_tol: f64,
    /// The largest `|h|/tol` of the active constraint in the constrained motion.
    constrained_h_of_tol: f64,
}

/// The observer that checks every sample and event as it comes; the first violation is kept.
struct Checker<'a, 'm> {
    derived: &'a Derived<'m, FileModel>,
    model: &'m FileModel,
    /// Whether the switch applies the model's own `R∞` before the projection.
    model_map: bool,
    tolerances: Tolerances,
    /// `√(2n)`: an error of RMS norm ≤ 1 allows `|δy_i| ≤ √(2n) sc_i` in each component.
    per_component: f64,
    /// Whether the samples are the step ends, over which the energy slack is counted.
    at_steps: bool,
    /// The lowest energy so far (raised by what the model's own `R∞` adds).
    lowest_energy: f64,
    /// The energy error the integration may have made so far.
    slack: f64,
    /// Whether a constraint has friction, and whether a surface moves under one (its slip is
    /// not 0 at rest): then the balance counts the surface's work, and an event may add it.
    frictional: bool,
    moving_surface: bool,
    record: RunRecord,
    violation: Option<String>,
}

impl<'a, 'm> Checker<'a, 'm> {
    fn new(
        derived: &'a Derived<'m, FileModel>,
        file: &'m ModelFile,
        options: &SimulationOptions,
    ) -> Self {
        Self {
            derived,
            model: &file.model,
            model_map: options.completion == Completion::ModelMap,
            tolerances: options.tolerances,
            per_component: ((2 * file.model.dimension()) as f64).sqrt(),
            at_steps: options.output == OutputGrid::Steps,
            lowest_energy: f64::INFINITY,
            slack: 0.0,
            frictional: file.model.constraints().iter().any(|c| c.has_friction()),
            moving_surface: (0..file.model.constraints().len()).any(|i| {
                let n = file.model.dimension();
                file.model.constraints()[i].has_friction()
                    && (0..file.model.slip_components(i)).any(|c| {
                        file.model
                            .slip(i, c, 0.0, &file.initial.q, &vec![0.0; n])
                            .abs()
                            > 0.0
                    })
            }),
            record: RunRecord {
                lowest_h: f64::INFINITY,
                lowest_h_of_tol: f64::INFINITY,
                ..RunRecord::default()
            },
            violation: None,
        }
    }

    /// The energy resolution at `(q, q̇)`: `ε_E = Σ_i |∂E/∂y_i| sc_i`, `sc_i = atol + rtol |y_i|`
    /// (what an error of one tolerance unit in each component changes the energy by), and the
    /// size of the energy's terms `Σ_i |∂E/∂y_i| |y_i|`. The derivatives by central differences:
    /// they are scales, and their relative error (~1e-10) does not matter.
    fn energy_resolution(&self, q: &[f64], q_dot: &[f64]) -> (f64, f64) {
        let n = q.len();
        let mut y: Vec<f64> = q.iter().chain(q_dot).copied().collect();
        let energy = |y: &[f64]| self.derived.energy(&y[..n], &y[n..]);
        let Tolerances { rtol, atol } = self.tolerances;
        let (mut resolution, mut size) = (0.0, 0.0);
        for i in 0..2 * n {
            let yi = y[i];
            let step = 1e-6 * yi.abs().max(1.0);
            y[i] = yi + step;
            let up = energy(&y);
            y[i] = yi - step;
            let down = energy(&y);
            y[i] = yi;
            let slope = ((up - down) / (2.0 * step)).abs();
            resolution += slope * (atol + rtol * yi.abs());
            size += slope * yi.abs();
        }
        (resolution, size)
    }

    fn violate(&mut self, message: String) {
        if self.violation.is_none() {
            self.violation = Some(message);
        }
    }
}

impl Observer for Checker<'_, '_> {
    fn sample(&mut self, s: &Sample<'_>) {
        // Never falls through: h_i ≥ −tol_i, tol_i = |A_i| atol + rtol (|h_i| + Σ_j |A_ij q_j|),
        // the integration's position tolerance atol + rtol |q| as h_i sees it (through the
        // coordinates it depends on, as the engine's own checks weigh them). The engine reports
        // every impact on the admissible side and holds the constrained motion on h = 0 to
        // rounding, so h below −tol_i is the body through the surface by more than the
        // integration resolves; and on the constraint, |h_i| ≤ tol_i.
        let Tolerances { rtol, atol } = self.tolerances;
        let at_time = self.derived.at_time(s.t);
        for i in 0..self.model.constraints().len() {
            let (h, a) = at_time.constraint(i, s.q);
            let tol = dot(&a, &a).sqrt() * atol + rtol * (h.abs() + terms(&a, s.q));
            let record = &mut self.record;
            record.lowest_h = record.lowest_h.min(h);
            record.lowest_h_of_tol = record.lowest_h_of_tol.min(h / tol);
            let active = matches!(s.mode, Mode::Constrained(set) if set.contains(i));
            if active {
                record.constrained_h_of_tol = record.constrained_h_of_tol.max(h.abs() / tol);
            }
            if h.is_nan() || h < -tol || (active && h > tol) {
                self.violate(format!(
                    "{} constraint {i} at t = {}: h = {h:e}, tolerance {tol:e} ({} mode, q = {:?}, q_dot = {:?})",
                    if active { "left" } else { "fell through" },
                    s.t,
                    s.mode.name(),
                    s.q,
                    s.q_dot
                ));
            }
        }
        // Never gains energy: E(t) ≤ min_{s ≤ t} E(s) + slack(t). The integrator holds each
        // step's local error to an RMS norm ≤ 1 in units sc_i = atol + rtol |y_i|, so each
        // component is off by at most √(2n) sc_i, and the energy by at most √(2n) ε_E (see
        // energy_resolution). The energy is a first integral of every mode (the shipped models
        // are conservative, and a constraint does no work), so the local errors add up along the
        // run and nothing else moves it within a mode; the events move the state by no more
        // than the integration resolves (roots to rounding; the projection onto h = 0 from
        // within the tolerance), and otherwise take energy out (e ≤ 1, the plastic projection).
        // So the slack is √(2n) Σ ε_E over the samples so far (one per step, two per event); a
        // rise beyond it is energy the engine made, not integration error. (Seen: at most 1% of
        // the slack, 6e-11 of the energy's size.)
        if !self.at_steps {
            return;
        }
        let (resolution, size) = self.energy_resolution(s.q, s.q_dot);
        self.slack += self.per_component * resolution;
        self.record.energy_size = self.record.energy_size.max(size);
        // A model with forces or time may gain energy, but not beyond what the forces, its
        // time dependence and the moving surfaces put in (docs/forces-and-time.md): the energy
        // less that, E − W_forces − W_drive − W_constraints, obeys the same rule.
        // With friction the energy only falls, but for what a moving surface puts in (in
        // W_constraints); friction's own work is ≤ 0 and stays in.
        let energy = if self.model.is_autonomous() && !self.frictional {
            s.energy
        } else {
            s.energy - (s.work.forces + s.work.drive + s.work.constraints)
        };
        let gain = energy - self.lowest_energy;
        if gain > 0.0 {
            self.record.gain = self.record.gain.max(gain);
            self.record.gain_of_slack = self.record.gain_of_slack.max(gain / self.slack);
        }
        if gain.is_nan() || gain > self.slack {
            self.violate(format!(
                "gained energy at t = {}: E = {energy:e} is {gain:e} above its lowest earlier value, beyond the slack {:e} ({} mode, q = {:?}, q_dot = {:?})",
                s.t,
                self.slack,
                s.mode.name(),
                s.q,
                s.q_dot
            ));
        }
        self.lowest_energy = self.lowest_energy.min(energy);
    }

    fn event(&mut self, event: &Event) {
        // With forces or time the samples on both sides of the event check the balance instead
        // (a rising table may kick the ball: the energy rises, by the impulse's work).
        if !self.model.is_autonomous() || self.moving_surface {
            return;
        }
        // At a Zeno point with friction the held motion starts at the switch, T_rem before the
        // point, and the switch gives back what its kinetic friction will take over T_rem (the
        // tail's tangential impulses were applied in full; docs/friction.md, "Zeno points with
        // friction"): the energy may rise by that, and falls back by T_rem. The check restarts
        // after the switch.
        if self.frictional && event.kind == EventKind::Zeno {
            let after = &event.after;
            self.lowest_energy = self
                .lowest_energy
                .max(self.derived.energy(&after.q, &after.q_dot));
            return;
        }
        // No event adds energy (with friction neither: the impact law's loss is never negative,
        // docs/friction.md): an impact changes q̇ alone and takes out
        // ½(1−e²)(A q̇)²/(A M⁻¹ Aᵀ) ≥ 0; the switch moves q onto h = 0 from within the position
        // tolerance and takes the normal velocity out; a lift-off changes nothing. Allowed:
        // √(2n) ε_E of the state before (a state error of one step's tolerance). (Seen: at most
        // 5e-7 of it.) The model's own R∞ is the model's: what it adds (MODEL_MAP_GAIN) is
        // credited, and the engine's projection after it must not add more.
        let (before, after) = (&event.before, &event.after);
        let e_before = self.derived.energy(&before.q, &before.q_dot);
        let e_after = self.derived.energy(&after.q, &after.q_dot);
        let (resolution, size) = self.energy_resolution(&before.q, &before.q_dot);
        let allowed = self.per_component * resolution;
        let mut map_gain: f64 = 0.0;
        if event.kind == EventKind::Zeno {
            let (_, a) = self.derived.constraint(event.constraint, &before.q);
            let normal_speed = dot(&a, &before.q_dot).abs() / dot(&a, &a).sqrt();
            let record = &mut self.record;
            record.switch_normal_speed = record.switch_normal_speed.max(normal_speed);
            let (mut q, mut q_dot) = (before.q.clone(), before.q_dot.clone());
            if self.model_map
                && self
                    .model
                    .completion_map(event.constraint, &mut q, &mut q_dot)
            {
                map_gain = (self.derived.energy(&q, &q_dot) - e_before).max(0.0);
                self.record.map_gain = self.record.map_gain.max(map_gain / size);
            }
        }
        self.lowest_energy += map_gain;
        let ratio = (e_after - e_before - map_gain) / allowed;
        self.record.event_gain_of_slack = self.record.event_gain_of_slack.max(ratio);
        if ratio.is_nan() || ratio > 1.0 || map_gain > MODEL_MAP_GAIN * size {
            self.violate(format!(
                "the {} on constraint {} at t = {} changed the energy by {:e} (allowed {allowed:e}, of which the model's own R∞ {map_gain:e}): before q = {:?}, q_dot = {:?}; after q = {:?}, q_dot = {:?}",
                event.kind.name(),
                event.constraint,
                event.t,
                e_after - e_before,
                before.q,
                before.q_dot,
                after.q,
                after.q_dot
            ));
        }
    }
}

// ----- running the cases ---------------------------------------------------------------------

/// The options of a random run: the file's (its own `t_end`, tolerances and Zeno strategy),
/// sampled at every step or on the grid, at most [`STEP_LIMIT`] steps.
fn options(file: &ModelFile, grid: bool) -> SimulationOptions {
    let options = file.options();
    SimulationOptions {
        output: if grid {
            OutputGrid::Uniform(options.t_end / GRID_POINTS)
        } else {
            OutputGrid::Steps
        },
        max_steps: STEP_LIMIT,
        ..options
    }
}

/// What one case gave.
struct CaseReport {
    record: RunRecord,
    steps: u64,
    events: usize,
    zeno_points: usize,
    wall: Duration,
}

/// Runs the model from `state`; `Err` says what went wrong: a check, or an outcome other than
/// `Finished` (no failure is expected: a random state is a simultaneous contact in none of the
/// shipped models, and the pendulum's pole is passed, see above).
fn run_case(
    file: &ModelFile,
    derived: &Derived<FileModel>,
    state: &State,
    grid: bool,
) -> Result<CaseReport, String> {
    let options = options(file, grid);
    let (q, v) = state;
    let simulation = Simulation::new(&file.model, q, v, options)
        .map_err(|e| format!("the initial state is refused: {e}"))?;
    let mut checker = Checker::new(derived, file, &options);
    let start = Instant::now();
    let run = simulation.run(&mut checker);
    let wall = start.elapsed();
    if let Some(violation) = checker.violation {
        return Err(violation);
    }
    // Painlevé's paradox is the model's (a rod with μ = 3): the run says so and stops.
    let paradox = matches!(
        run.outcome,
        Outcome::Failed(zenosim::Error::Painleve { .. })
    );
    if run.outcome != Outcome::Finished && !paradox {
        return Err(format!(
            "the run ended {} at t = {} ({:?})",
            run.outcome, run.t_final, run.outcome
        ));
    }
    Ok(CaseReport {
        record: checker.record,
        steps: run.stats.steps,
        events: run.events.len(),
        zeno_points: run.zeno.len(),
        wall,
    })
}

/// The statistics of a model's cases.
#[derive(Default)]
struct Tally {
    cases: u64,
    on_grid: u64,
    refused: BTreeMap<&'static str, u64>,
    starts: BTreeMap<String, u64>,
    gain_relative: f64,
    gain_of_slack: f64,
    event_gain_of_slack: f64,
    map_gain: f64,
    switch_normal_speed: f64,
    lowest_h: f64,
    lowest_h_of_tol: f64,
    constrained_h_of_tol: f64,
    most_steps: u64,
    most_events: usize,
    zeno_points: u64,
    slowest: Duration,
    wall: Duration,
    closest: f64,
}

impl Tally {
    fn add(&mut self, start: Start, grid: bool, report: &CaseReport) {
        let r = &report.record;
        self.cases += 1;
        self.on_grid += u64::from(grid);
        *self.starts.entry(format!("{start:?}")).or_default() += 1;
        self.gain_relative = self.gain_relative.max(r.gain / r.energy_size);
        self.gain_of_slack = self.gain_of_slack.max(r.gain_of_slack);
        self.event_gain_of_slack = self.event_gain_of_slack.max(r.event_gain_of_slack);
        self.map_gain = self.map_gain.max(r.map_gain);
        self.switch_normal_speed = self.switch_normal_speed.max(r.switch_normal_speed);
        self.lowest_h = self.lowest_h.min(r.lowest_h);
        self.lowest_h_of_tol = self.lowest_h_of_tol.min(r.lowest_h_of_tol);
        self.constrained_h_of_tol = self.constrained_h_of_tol.max(r.constrained_h_of_tol);
        self.most_steps = self.most_steps.max(report.steps);
        self.most_events = self.most_events.max(report.events);
        self.zeno_points += report.zeno_points as u64;
        self.slowest = self.slowest.max(report.wall);
        self.wall += report.wall;
    }
}

/// The cases per model: `ZENOSIM_RANDOM_STATES`, else [`DEFAULT_CASES`].
fn case_count() -> u32 {
    match std::env::var("ZENOSIM_RANDOM_STATES") {
        Ok(text) => text
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("ZENOSIM_RANDOM_STATES={text:?} is not a case count")),
        Err(_) => DEFAULT_CASES,
    }
}

/// The model's seed, shifted by `ZENOSIM_RANDOM_SEED` if set.
fn seed(spec: &Spec) -> u64 {
    match std::env::var("ZENOSIM_RANDOM_SEED") {
        Ok(text) => {
            let base: u64 = text
                .trim()
                .parse()
                .unwrap_or_else(|_| panic!("ZENOSIM_RANDOM_SEED={text:?} is not a number"));
            base.wrapping_mul(1000).wrapping_add(spec.seed)
        }
        Err(_) => spec.seed,
    }
}

/// A `zenosim run` command that starts the model from `state` (`{:?}` prints each `f64` so that
/// it reads back to the same number).
fn command(file: &ModelFile, state: &State, options: &SimulationOptions) -> String {
    let mut text = format!("cargo run --release -- run models/{}.toml", file.name);
    if let OutputGrid::Uniform(dt) = options.output {
        text += &format!(" --dt {dt:?}");
    }
    let coordinates = file.model.coordinate_names();
    let velocities = file.velocity_names();
    let values = state.0.iter().chain(&state.1);
    for (name, value) in coordinates.iter().chain(&velocities).zip(values) {
        text += &format!(" --set '{name}={value:?}'");
    }
    text
}

/// Runs the random cases of one model file and prints their statistics.
fn check_model(file_name: &str) {
    let spec = SPECS
        .iter()
        .find(|s| s.file == file_name)
        .unwrap_or_else(|| panic!("no random states for {file_name}"));
    let file = load(spec.file);
    let derived = Derived::new(&file.model).unwrap();
    let cases = case_count();
    let seed = seed(spec);
    let config = Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        // Refused states do not count as cases (none were refused in 6 × 5000).
        max_global_rejects: cases.max(1024),
        // A shrinking step is a whole run: bound the time a failure takes to report.
        max_shrink_iters: 200,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let tally = RefCell::new(Tally {
        lowest_h: f64::INFINITY,
        lowest_h_of_tol: f64::INFINITY,
        closest: f64::INFINITY,
        ..Tally::default()
    });
    let strategy = (0u8..8, prop::array::uniform8(0.0..1.0f64));
    let started = Instant::now();
    let result = runner.run(&strategy, |case| {
        let state = match initial_state(spec, &file, &derived, &case) {
            Ok(state) => state,
            Err(reason) => {
                *tally.borrow_mut().refused.entry(reason).or_default() += 1;
                return Err(TestCaseError::reject(reason));
            }
        };
        let grid = on_grid(&case);
        let report = run_case(&file, &derived, &state, grid).map_err(TestCaseError::fail)?;
        let mut tally = tally.borrow_mut();
        tally.add(Start::from_index(case.0 % 4), grid, &report);
        if let Some((_, closest)) = spec.closest {
            tally.closest = tally.closest.min(closest(&file, &state));
        }
        Ok(())
    });
    if let Err(error) = result {
        let (reason, case) = match error {
            TestError::Fail(reason, case) => (reason.to_string(), case),
            TestError::Abort(reason) => panic!("{}: aborted: {reason}", spec.file),
        };
        let detail = match initial_state(spec, &file, &derived, &case) {
            Ok(state) => {
                let options = options(&file, on_grid(&case));
                format!(
                    "initial state q = {:?}, q_dot = {:?}, to t_end = {}, sampled {:?} (at most {STEP_LIMIT} steps)\nrepeat: {}",
                    state.0,
                    state.1,
                    options.t_end,
                    options.output,
                    command(&file, &state, &options)
                )
            }
            Err(reason) => format!("(refused: {reason})"),
        };
        panic!(
            "{} (seed {seed}), case {case:?}: {reason}\n{detail}",
            spec.file
        );
    }
    let t = tally.into_inner();
    println!(
        "{}: {} cases ({} sampled on the grid), all finished, in {:.1} s ({:.1} s in the runs, the slowest {:.0} ms), seed {seed}\n  \
         starts {:?}, refused {:?}\n  \
         {} Zeno points; at most {} steps and {} events in a run\n  \
         largest energy gain {:.1e} of the energy's size ({:.1e} of the slack); across an event {:.1e} of the allowed\n  \
         by the model's own R∞ {:.1e} of the energy's size; normal speed at a switch up to {:.1e}\n  \
         lowest h {:.1e} ({:.1e} of the tolerance); on the constraint |h| up to {:.1e} of the tolerance",
        spec.file,
        t.cases,
        t.on_grid,
        started.elapsed().as_secs_f64(),
        t.wall.as_secs_f64(),
        t.slowest.as_secs_f64() * 1e3,
        t.starts,
        t.refused,
        t.zeno_points,
        t.most_steps,
        t.most_events,
        t.gain_relative,
        t.gain_of_slack,
        t.event_gain_of_slack,
        t.map_gain,
        t.switch_normal_speed,
        t.lowest_h,
        t.lowest_h_of_tol,
        t.constrained_h_of_tol,
    );
    if let Some((what, _)) = spec.closest {
        println!("  smallest {what}: {:.1e}", t.closest);
    }
}

#[test]
fn every_shipped_model_has_random_states() {
    let mut shipped: Vec<_> = std::fs::read_dir(models_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    shipped.sort();
    let mut covered: Vec<_> = SPECS.iter().map(|s| s.file.to_string()).collect();
    covered.sort();
    assert_eq!(shipped, covered);
}

#[test]
fn ball_backspin_random_states() {
    check_model("ball-backspin.toml");
}

#[test]
fn belt_stick_slip_random_states() {
    check_model("belt-stick-slip.toml");
}

#[test]
fn housner_block_random_states() {
    check_model("housner-block.toml");
}

#[test]
fn sphere_slide_spin_random_states() {
    check_model("sphere-slide-spin.toml");
}

#[test]
fn dumbbell_landing_random_states() {
    check_model("dumbbell-landing.toml");
}

#[test]
fn painleve_rod_random_states() {
    check_model("painleve-rod.toml");
}

#[test]
fn rimless_wheel_random_states() {
    check_model("rimless-wheel.toml");
}

#[test]
fn rough_incline_random_states() {
    check_model("rough-incline.toml");
}

#[test]
fn ball_off_cylinder_random_states() {
    check_model("ball-off-cylinder.toml");
}

/// States the random cases found the ball going through the cylinder from (30000 cases, seed
/// 1), each checked on the fine output grid as the cases are:
/// - a rebound off the cylinder's top whose next step, unbounded by any predicted return,
///   carried the ball back into the cylinder and out again before its first sample (event
///   location now searches the first interval after a rebound like any other);
/// - a ball at rest on the cylinder and pressed into it, whose crossing found at its start was
///   retried with ever longer steps until one reached past the cylinder (the retries now keep
///   the step that found it).
#[test]
fn ball_off_cylinder_states_that_once_went_through_it() {
    let file = load("ball-off-cylinder.toml");
    let derived = Derived::new(&file.model).unwrap();
    let states = [
        (
            [-1.398799385791662, 0.22563907856354476],
            [2.890922136653855, 2.813314948843745],
        ),
        (
            [-0.5967714708789854, 0.8024112483913298],
            [-0.00042826344100443947, -0.00031850924837373285],
        ),
    ];
    for (q, v) in states {
        let state = (q.to_vec(), v.to_vec());
        if let Err(reason) = run_case(&file, &derived, &state, true) {
            panic!("from q = {q:?}, q_dot = {v:?}: {reason}");
        }
    }
}

#[test]
fn ball_on_sine_demo_random_states() {
    check_model("ball-on-sine-demo.toml");
}

#[test]
fn ball_on_sine_random_states() {
    check_model("ball-on-sine.toml");
}

#[test]
fn bouncing_ball_random_states() {
    check_model("bouncing-ball.toml");
}

#[test]
fn cart_pendulum_random_states() {
    check_model("cart-pendulum.toml");
}

#[test]
fn damped_oscillator_random_states() {
    check_model("damped-oscillator.toml");
}

#[test]
fn dragged_ball_random_states() {
    check_model("dragged-ball.toml");
}

#[test]
fn pd_arm_random_states() {
    check_model("pd-arm.toml");
}

#[test]
fn vibrating_table_random_states() {
    check_model("vibrating-table.toml");
}

#[test]
fn corner_random_states() {
    check_model("corner.toml");
}

#[test]
fn double_pendulum_stop_random_states() {
    check_model("double-pendulum-stop.toml");
}

#[test]
fn floor_and_wall_random_states() {
    check_model("floor-and-wall.toml");
}

#[test]
fn newtons_cradle_random_states() {
    check_model("newtons-cradle.toml");
}

#[test]
fn rocking_block_random_states() {
    check_model("rocking-block.toml");
}

#[test]
fn spherical_pendulum_random_states() {
    check_model("spherical-pendulum.toml");
}

/// The spherical pendulum swung from the ground towards its pole (`θ̇ = −1.5` carries it over
/// the top when `φ̇ = 0`) with ever smaller `φ̇`: it passes the coordinate singularity
/// `sin θ = 0` at `sin θ* ≈ 1.85 φ̇`, down to `φ̇ = 10⁻¹⁸`, and through it at `φ̇ = 0`; every
/// run finishes and passes the checks.
#[test]
fn table_random_states() {
    check_model("table.toml");
}

#[test]
fn v_groove_random_states() {
    check_model("v-groove.toml");
}

#[test]
fn the_spherical_pendulum_passes_its_pole_at_any_distance() {
    let file = load("spherical-pendulum.toml");
    let derived = Derived::new(&file.model).unwrap();
    for k in (0..=20).step_by(2) {
        let phi_dot = if k == 20 { 0.0 } else { 10f64.powi(-k) };
        let state = (vec![FRAC_PI_2 - 1e-3, 0.3], vec![-1.5, phi_dot]);
        let closest = closest_approach_to_the_pole(&file, &state).sin();
        assert!(
            closest <= 2.0 * phi_dot,
            "φ̇ = {phi_dot:e}: sin θ* = {closest:e}"
        );
        run_case(&file, &derived, &state, false).unwrap_or_else(|e| panic!("φ̇ = {phi_dot:e}: {e}"));
    }
}

// ----- random models with friction -------------------------------------------------------------

/// A shipped model with friction and its parameters drawn from eight uniform numbers: its
/// friction coefficients, restitutions, geometry and launch, each over a range where the
/// model is what its file says (a rough contact, a body that stays on its surface's side).
fn random_frictional_model(k: usize, u: &[f64; 8]) -> (&'static str, Vec<(&'static str, f64)>) {
    let between = |x: f64, a: f64, b: f64| a + (b - a) * x;
    match k {
        0 => (
            "ball-backspin.toml",
            vec![
                ("mu", between(u[0], 0.0, 1.5)),
                ("e", between(u[1], 0.0, 0.95)),
                ("v0", between(u[2], -3.0, 3.0)),
                ("w0", between(u[3], -40.0, 40.0)),
                ("y0", between(u[4], 0.1, 2.0)),
            ],
        ),
        1 => (
            "rough-incline.toml",
            vec![
                ("alpha", between(u[0], 0.0, 1.2)),
                ("mu", between(u[1], 0.0, 2.0)),
                ("v0", between(u[2], -3.0, 3.0)),
            ],
        ),
        2 => (
            "belt-stick-slip.toml",
            vec![
                ("k", between(u[0], 0.5, 20.0)),
                ("vb", between(u[1], -2.0, 2.0)),
            ],
        ),
        3 => (
            "housner-block.toml",
            vec![
                ("b", between(u[0], 0.05, 0.5)),
                ("c", between(u[1], 0.1, 1.0)),
                ("mu", between(u[2], 0.05, 2.0)),
                ("th0", between(u[3], 0.0, 0.2)),
            ],
        ),
        4 => (
            "rimless-wheel.toml",
            vec![
                ("gamma", between(u[0], 0.0, 0.3)),
                ("mu", between(u[1], 0.3, 2.0)),
                ("w0", between(u[2], 0.0, 3.0)),
            ],
        ),
        5 => (
            "painleve-rod.toml",
            vec![
                ("mu", between(u[0], 0.0, 4.0)),
                ("th0", between(u[1], 0.1, 1.4)),
            ],
        ),
        7 => (
            "dumbbell-landing.toml",
            vec![
                ("mu", between(u[0], 0.0, 1.5)),
                ("e", between(u[1], 0.0, 0.9)),
                ("u", between(u[2], -2.0, 2.0)),
                ("v", between(u[3], -2.0, 2.0)),
                ("w", between(u[4], -5.0, 5.0)),
                // Tilted by up to 0.3 rad (one end lands first), from high enough.
                ("h", between(u[5], 0.31, 0.6)),
                ("th", between(u[6], -0.3, 0.3)),
                ("th_dot", between(u[7], -2.0, 2.0)),
            ],
        ),
        _ => (
            "sphere-slide-spin.toml",
            vec![
                ("mu", between(u[0], 0.0, 1.5)),
                ("vx", between(u[1], -3.0, 3.0)),
                ("vy", between(u[2], -3.0, 3.0)),
                ("wx", between(u[3], -30.0, 30.0)),
                ("wy", between(u[4], -30.0, 30.0)),
                ("wz", between(u[5], -30.0, 30.0)),
            ],
        ),
    }
}

/// Random models with friction: the shipped frictional models, planar and in space,
/// with random coefficients, restitutions, geometry and launches, each run from its own initial
/// state and checked as the random states are (no panic, no hang, no contact crossed below its
/// rounding, no energy gained at an impact or while slipping); Painlevé's paradox, where the
/// rod's friction brings it, is the model's answer.
#[test]
fn random_frictional_models() {
    let cases = case_count();
    let config = Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(37),
        max_shrink_iters: 50,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let strategy = (0usize..8, prop::array::uniform8(0.0..1.0f64));
    let result = runner.run(&strategy, |(k, u)| {
        let (name, values) = random_frictional_model(k, &u);
        let overrides: Vec<zenosim_model::Override> = values
            .iter()
            .map(|(name, value)| zenosim_model::Override {
                name: name.to_string(),
                value: format!("{value:e}"),
            })
            .collect();
        let source = std::fs::read_to_string(models_dir().join(name)).unwrap();
        let file = parse_model(name, &source, &overrides)
            .map_err(|e| TestCaseError::fail(format!("{name} {values:?}: refused: {e}")))?;
        let derived = Derived::new(&file.model)
            .map_err(|e| TestCaseError::fail(format!("{name} {values:?}: {e}")))?;
        let state = (file.initial.q.clone(), file.initial.q_dot.clone());
        run_case(&file, &derived, &state, false)
            .map(|_| ())
            .map_err(|e| TestCaseError::fail(format!("{name} {values:?}: {e}")))
    });
    if let Err(error) = result {
        panic!("{error}");
    }
}
