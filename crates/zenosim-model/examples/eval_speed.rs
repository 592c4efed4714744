//! How long one evaluation of a compiled Lagrangian and constraint takes, against the same
//! functions written in Rust (`zenosim::models::BallOnSine`), over each number type the engine
//! evaluates them with.
//!
//! Run with `cargo run --release -p zenosim-model --example eval_speed`. As a model file does,
//! it binds the parameters `m` and `g` to constants and evaluates `L(q, q̇)` with
//! [`Expression::eval_split`]. Per right-hand side of the ODE with `n = 3` the engine evaluates
//! `L` six times over `HyperDual64`, once over `HyperDualVec<3, 1>` and once over `DualVec<3>`;
//! the constraint once over `HyperDualVec<3, 1>`.

use std::hint::black_box;
use std::time::Instant;

use num_dual::{DualSVec64, HyperDual64, HyperDualSVec64};
use zenosim::models::BallOnSine;
use zenosim::{HybridLagrangian, Scalar};
use zenosim_model::expr::{Bindings, Expression};

/// The Lagrangian timed; set `EXPR` at build time to time another one over the same names.
const SOURCE: &str = match option_env!("EXPR") {
    Some(source) => source,
    None => "0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2) - m*g*x3",
};
const CONSTRAINT: &str = "x3 - sin(x2)";
const NAMES: [&str; 6] = ["x1", "x2", "x3", "x1_dot", "x2_dot", "x3_dot"];
const MASS: f64 = 2.0;
const GRAVITY: f64 = 9.81;

/// The engine's `HyperDualVec<f64, Const<3>, U1>` and `DualVec<f64, Const<3>>`.
type Mixed = HyperDualSVec64<3, 1>;
type Grad = DualSVec64<3>;

/// Nanoseconds per call of `f`, the best of seven rounds of `n` calls.
fn time_per_call<T>(n: u32, mut f: impl FnMut() -> T) -> f64 {
    (0..7)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..n {
                black_box(f());
            }
            start.elapsed().as_nanos() as f64 / f64::from(n)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Times `L` compiled and native over `D`; asserts they agree when `L` is the default.
fn compare<D: Scalar>(
    label: &str,
    n: u32,
    expression: &Expression,
    model: &BallOnSine,
    (q, q_dot): (&[D], &[D]),
) {
    if option_env!("EXPR").is_none() {
        let (compiled, native) = (expression.eval_split(q, q_dot), model.lagrangian(q, q_dot));
        assert_eq!(format!("{compiled:?}"), format!("{native:?}"), "{label}");
    }
    let compiled = time_per_call(n, || expression.eval_split(black_box(q), black_box(q_dot)));
    let native = time_per_call(n, || model.lagrangian(black_box(q), black_box(q_dot)));
    println!(
        "{label:<22} {compiled:6.1} ns/eval (native Rust {native:5.1} ns, ratio {:.2})",
        compiled / native
    );
}

fn main() {
    let mut scope = Bindings::new()
        .with_constant("m", MASS)
        .with_constant("g", GRAVITY);
    for (slot, name) in NAMES.iter().enumerate() {
        scope = scope.with_slot(*name, slot);
    }
    let lagrangian = Expression::parse(SOURCE, &scope).expect("the Lagrangian parses");
    let constraint = Expression::parse(CONSTRAINT, &scope).expect("the constraint parses");
    let model = black_box(BallOnSine::new(MASS, GRAVITY, 0.6));

    let q = [0.1, 0.2, 0.3];
    let q_dot = [1.0, -2.0, 0.5];
    // As the engine seeds them: the mass matrix entry (0, 1), the mixed term, the gradient.
    let q_hyper = q.map(HyperDual64::from);
    let q_dot_hyper: [HyperDual64; 3] = std::array::from_fn(|k| {
        let unit = |m: usize| if k == m { 1.0 } else { 0.0 };
        HyperDual64::new(q_dot[k], unit(0), unit(1), 0.0)
    });
    // ε₂ along q̇ in q: the unit seed scaled by q̇_i.
    let along_q_dot = |x: Mixed, i: usize| {
        let mut x = x.derivative2(0);
        x.eps2 *= q_dot[i];
        x
    };
    let q_mixed: [Mixed; 3] = std::array::from_fn(|i| along_q_dot(Mixed::from_re(q[i]), i));
    let q_dot_mixed: [Mixed; 3] = std::array::from_fn(|i| Mixed::from_re(q_dot[i]).derivative1(i));
    let q_grad: [Grad; 3] = std::array::from_fn(|i| Grad::from_re(q[i]).derivative(i));
    let q_dot_grad = q_dot.map(Grad::from_re);
    let q_constraint: [Mixed; 3] =
        std::array::from_fn(|i| along_q_dot(Mixed::from_re(q[i]).derivative1(i), i));

    let n = 2_000_000;
    println!("L = {SOURCE}, m = {MASS}, g = {GRAVITY} bound as constants");
    compare("f64", n, &lagrangian, &model, (&q, &q_dot));
    compare(
        "HyperDual64",
        n,
        &lagrangian,
        &model,
        (&q_hyper, &q_dot_hyper),
    );
    let (mixed, grad) = (
        (&q_mixed[..], &q_dot_mixed[..]),
        (&q_grad[..], &q_dot_grad[..]),
    );
    compare("HyperDualVec<3, 1>", n / 2, &lagrangian, &model, mixed);
    compare("DualVec<3>", n / 2, &lagrangian, &model, grad);

    assert_eq!(
        format!("{:?}", constraint.eval(&q_constraint)),
        format!("{:?}", model.constraint(0, &q_constraint))
    );
    let compiled = time_per_call(n / 2, || constraint.eval(black_box(&q_constraint)));
    let native = time_per_call(n / 2, || model.constraint(0, black_box(&q_constraint)));
    println!("h = {CONSTRAINT}");
    println!(
        "{:<22} {compiled:6.1} ns/eval (native Rust {native:5.1} ns, ratio {:.2})",
        "HyperDualVec<3, 1>",
        compiled / native
    );
}
