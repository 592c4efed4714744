//! Values and derivatives of expressions: precedence, every function, dual numbers.

use approx::assert_relative_eq;
use num_dual::{first_derivative, Dual64, HyperDual64};
use zenosim_model::expr::Expression;

const NAMES: [&str; 3] = ["x", "y", "t"];

/// A source and the `f64` function it should compute.
type Case2 = (&'static str, fn(f64, f64) -> f64);
/// A source and its derivative.
type Case1 = (&'static str, fn(f64) -> f64);

fn value(source: &str, x: f64, y: f64) -> f64 {
    Expression::parse(source, &NAMES)
        .unwrap_or_else(|e| panic!("{source}: {e}"))
        .eval(&[x, y, 0.0])
}

#[test]
fn precedence_and_associativity() {
    for (source, expected) in [
        ("-2^2", -4.0),
        ("2^3^2", 512.0),
        ("(2^3)^2", 64.0),
        ("1-2-3", -4.0),
        ("8/4/2", 1.0),
        ("2*-3", -6.0),
        ("-(-x)", 5.0),
        ("--x", 5.0),
        ("-x^2", -25.0),
        ("2^-1", 0.5),
        ("2^-x", 2f64.powi(-5)),
        ("+x", 5.0),
        ("1+2*3", 7.0),
        ("(1+2)*3", 9.0),
        ("2*3^2", 18.0),
        ("-2*3", -6.0),
        ("1 - -1", 2.0),
        ("2^3*4", 32.0),
        ("2^-1*4", 2.0),
        ("12/2*3", 18.0),
        ("x - y + 1", 3.0),
        ("-x - -y", -2.0),
    ] {
        assert_eq!(value(source, 5.0, 3.0), expected, "{source}");
    }
}

#[test]
fn numbers_whitespace_and_pi() {
    assert_eq!(
        value("1.5e-3 + .5 + 3. + 1E+3", 0.0, 0.0),
        1.5e-3 + 0.5 + 3.0 + 1e3
    );
    assert_eq!(value(" \t x\n *\r\n  y ", 2.0, 4.0), 8.0);
    assert_eq!(value("pi", 0.0, 0.0), std::f64::consts::PI);
    assert_eq!(value("2*pi*x", 0.5, 0.0), std::f64::consts::PI);
    // `t` is an ordinary name, bound by the scope.
    let e = Expression::parse("t + 1", &NAMES).unwrap();
    assert_eq!(e.eval(&[0.0, 0.0, 41.0]), 42.0);
}

#[test]
fn every_function_matches_f64() {
    let cases: [Case2; 18] = [
        ("sin(x)", |x, _| x.sin()),
        ("cos(x)", |x, _| x.cos()),
        ("tan(x)", |x, _| x.tan()),
        ("asin(x)", |x, _| x.asin()),
        ("acos(x)", |x, _| x.acos()),
        ("atan(x)", |x, _| x.atan()),
        ("atan2(y, x)", |x, y| y.atan2(x)),
        ("sinh(x)", |x, _| x.sinh()),
        ("cosh(x)", |x, _| x.cosh()),
        ("tanh(x)", |x, _| x.tanh()),
        ("exp(x)", |x, _| x.exp()),
        ("ln(y)", |_, y| y.ln()),
        ("log(y)", |_, y| y.ln()),
        ("sqrt(y)", |_, y| y.sqrt()),
        ("abs(x)", |x, _| x.abs()),
        ("pow(y, x)", |x, y| y.powf(x)),
        ("min(x, y)", |x, y| x.min(y)),
        ("max(x, y)", |x, y| x.max(y)),
    ];
    for (source, f) in cases {
        for (x, y) in [(0.3, 2.5), (-0.7, 0.4), (0.0, 1.0), (0.99, 7.0)] {
            assert_relative_eq!(value(source, x, y), f(x, y), max_relative = 1e-14);
        }
    }
    // log is the natural logarithm.
    assert_eq!(value("log(x)", std::f64::consts::E, 0.0), 1.0);
    // Constant arguments are folded, to the same values.
    assert_eq!(value("atan2(1, -1)", 0.0, 0.0), 1f64.atan2(-1.0));
    assert_eq!(value("pow(2, 0.5)", 0.0, 0.0), 2f64.powf(0.5));
    assert_eq!(value("max(-1, -2) + min(3, 4)", 0.0, 0.0), 2.0);
}

#[test]
fn integer_powers_are_exact_for_negative_bases() {
    assert_eq!(value("x^3", -2.0, 0.0), -8.0);
    assert_eq!(value("x^-2", -2.0, 0.0), 0.25);
    assert_eq!(value("pow(x, 2)", -3.0, 0.0), 9.0);
    assert_eq!(value("x^0", 0.0, 0.0), 1.0);
    // A varying exponent goes through exp(y ln x).
    assert_relative_eq!(value("x^y", 2.0, 10.0), 1024.0, max_relative = 1e-14);
    assert_relative_eq!(
        value("x^(y/2)", 3.0, 1.0),
        3f64.sqrt(),
        max_relative = 1e-14
    );
}

fn dual(source: &str, x: Dual64) -> Dual64 {
    Expression::parse(source, &["x"]).unwrap().eval(&[x])
}

#[test]
fn first_derivatives_through_dual_numbers() {
    let cases: [Case1; 10] = [
        ("sin(x)^2", |x| (2.0 * x).sin()),
        ("x^3 - 2*x", |x| 3.0 * x * x - 2.0),
        ("exp(-x^2/2)", |x| -x * (-x * x / 2.0).exp()),
        ("ln(x) + log(x)", |x| 2.0 / x),
        ("sqrt(x)", |x| 0.5 / x.sqrt()),
        ("atan2(x, 1)", |x| 1.0 / (1.0 + x * x)),
        ("x^x", |x| x.powf(x) * (x.ln() + 1.0)),
        ("pow(x, 2.5)", |x| 2.5 * x.powf(1.5)),
        ("tanh(x)", |x| 1.0 - x.tanh().powi(2)),
        ("1/x", |x| -1.0 / (x * x)),
    ];
    for (source, derivative) in cases {
        for x in [0.3, 1.1, 2.7] {
            let (f, df) = first_derivative(|x: Dual64| dual(source, x), x);
            assert_relative_eq!(f, value(source, x, 0.0), max_relative = 1e-14);
            assert_relative_eq!(df, derivative(x), max_relative = 1e-12);
        }
    }
}

#[test]
fn min_max_abs_carry_the_chosen_derivative() {
    let x = Dual64::new(2.0, 1.0);
    // min(x, 3x^2): x is smaller at 2, so d/dx = 1; max picks 3x^2, d/dx = 6x = 12.
    assert_eq!(dual("min(x, 3*x^2)", x), Dual64::new(2.0, 1.0));
    assert_eq!(dual("max(x, 3*x^2)", x), Dual64::new(12.0, 12.0));
    assert_eq!(dual("min(3*x^2, x)", x), Dual64::new(2.0, 1.0));
    assert_eq!(dual("max(3*x^2, x)", x), Dual64::new(12.0, 12.0));
    // Ties keep the first argument.
    assert_eq!(dual("min(x, 4 - x)", x).eps, 1.0);
    assert_eq!(dual("max(4 - x, x)", x).eps, -1.0);
    // abs: the sign of the real part.
    assert_eq!(dual("abs(x - 5)", x), Dual64::new(3.0, -1.0));
    assert_eq!(dual("abs(x)", x), Dual64::new(2.0, 1.0));
    // NaN propagates from either side.
    assert!(dual("min(x, ln(-1))", x).re.is_nan());
    assert!(dual("max(ln(-1), x)", x).re.is_nan());
}

#[test]
fn hessian_entry_through_hyper_dual_numbers() {
    // L = 0.5*m*(v1^2 + v2^2) - m*g*q*sin(v1): ∂²L/∂v1∂v2 = 0; ∂²L/∂v1∂q = -m g cos(v1).
    let scope = ["m", "g", "q", "v1", "v2"];
    let l = Expression::parse("0.5*m*(v1^2 + v2^2) - m*g*q*sin(v1)", &scope).unwrap();
    let (m, g, q, v1, v2) = (2.0, 9.81, 0.7, 0.3, -1.2);
    let c = HyperDual64::from;
    let vars = [
        c(m),
        c(g),
        HyperDual64::new(q, 0.0, 1.0, 0.0),
        HyperDual64::new(v1, 1.0, 0.0, 0.0),
        c(v2),
    ];
    let r = l.eval(&vars);
    assert_relative_eq!(r.re, 0.5 * m * (v1 * v1 + v2 * v2) - m * g * q * v1.sin());
    assert_relative_eq!(r.eps1, m * v1 - m * g * q * v1.cos(), max_relative = 1e-14);
    assert_relative_eq!(r.eps2, -m * g * v1.sin(), max_relative = 1e-14);
    assert_relative_eq!(r.eps1eps2, -m * g * v1.cos(), max_relative = 1e-14);
    // The mass-matrix entry ∂²L/∂v1² = m - m g q (-sin v1).
    let vars = [c(m), c(g), c(q), HyperDual64::new(v1, 1.0, 1.0, 0.0), c(v2)];
    assert_relative_eq!(
        l.eval(&vars).eps1eps2,
        m + m * g * q * v1.sin(),
        max_relative = 1e-14
    );
}

#[test]
fn generic_over_every_scalar() {
    fn twice<D: zenosim::Scalar>(e: &Expression, x: D) -> D {
        e.eval(&[x]) * 2.0
    }
    let e = Expression::parse("x^2", &["x"]).unwrap();
    assert_eq!(twice(&e, 3.0), 18.0);
    assert_eq!(twice(&e, Dual64::new(3.0, 1.0)).eps, 12.0);
    assert_eq!(
        twice(&e, HyperDual64::new(3.0, 1.0, 1.0, 0.0)).eps1eps2,
        4.0
    );
}
