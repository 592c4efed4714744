//! How long one evaluation of a compiled Lagrangian takes, over `f64` and `HyperDual64`.
//!
//! Run with `cargo run --release -p zenosim-model --example eval_speed`.

use std::hint::black_box;
use std::time::Instant;

use num_dual::HyperDual64;
use zenosim_model::expr::Expression;

/// The expression timed; set `EXPR` at build time to time another one over the same names.
const SOURCE: &str = match option_env!("EXPR") {
    Some(source) => source,
    None => "0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2) - m*g*x3",
};
const NAMES: [&str; 8] = ["m", "g", "x1", "x2", "x3", "x1_dot", "x2_dot", "x3_dot"];

/// Nanoseconds per call of `f`, the best of five rounds of `n` calls.
fn time_per_call(n: u32, mut f: impl FnMut() -> f64) -> f64 {
    (0..5)
        .map(|_| {
            let start = Instant::now();
            let mut sum = 0.0;
            for _ in 0..n {
                sum += f();
            }
            black_box(sum);
            start.elapsed().as_nanos() as f64 / f64::from(n)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The default Lagrangian written in Rust, for comparison.
fn native<D: zenosim::Scalar>(v: &[D]) -> D {
    let (m, g) = (v[0], v[1]);
    (v[5].powi(2) + v[6].powi(2) + v[7].powi(2)) * m * 0.5 - m * g * v[4]
}

fn main() {
    let expression = Expression::parse(SOURCE, &NAMES).expect("the Lagrangian parses");
    let values = [2.0, 9.81, 0.1, 0.2, 0.3, 1.0, -2.0, 0.5];
    let hyper: Vec<HyperDual64> = values
        .iter()
        .enumerate()
        .map(|(i, &v)| match i {
            5 => HyperDual64::new(v, 1.0, 0.0, 0.0),
            6 => HyperDual64::new(v, 0.0, 1.0, 0.0),
            _ => HyperDual64::from(v),
        })
        .collect();
    if SOURCE.starts_with("0.5*m*(") {
        assert_eq!(expression.eval(&values), native(&values));
        assert_eq!(expression.eval(&hyper), native(&hyper));
    }

    let n = 5_000_000;
    let f64_compiled = time_per_call(n, || expression.eval(black_box(&values[..])));
    let f64_native = time_per_call(n, || native(black_box(&values[..])));
    let hyper_compiled = time_per_call(n, || expression.eval(black_box(&hyper[..])).eps1eps2);
    let hyper_native = time_per_call(n, || native(black_box(&hyper[..])).eps1eps2);
    println!("{SOURCE}");
    println!("f64:         {f64_compiled:6.1} ns/eval (native Rust {f64_native:.1} ns)");
    println!("HyperDual64: {hyper_compiled:6.1} ns/eval (native Rust {hyper_native:.1} ns)");
}
