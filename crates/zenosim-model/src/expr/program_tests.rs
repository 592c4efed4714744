//! Unit tests of the compiled form: the instructions chosen, folding, fusion, temporaries,
//! constant bindings, split inputs, and agreement with a direct recursive evaluation.

use num_dual::{Dual64, DualNum, DualSVec64, HyperDual64};
use proptest::prelude::*;

use super::super::instr::Instr;
use super::super::ops::{self, Op};
use super::super::{Bindings, Limits};
use super::*;

const NAMES: [&str; 3] = ["x", "y", "z"];

fn compile(source: &str) -> Expression {
    Expression::parse(source, &NAMES).unwrap_or_else(|e| panic!("{source}: {e}"))
}

/// Both NaN, or equal bit for bit.
fn same_bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Equal as numbers (a zero's sign aside), or both NaN.
fn same_value(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// Hyper-dual inputs seeded on `x` (ε₁) and `y` (ε₂), with a cross term on `z`.
fn hyper(values: [f64; 3]) -> [HyperDual64; 3] {
    [
        HyperDual64::new(values[0], 1.0, 0.0, 0.0),
        HyperDual64::new(values[1], 0.0, 1.0, 0.0),
        HyperDual64::new(values[2], 0.5, -0.25, 1.0),
    ]
}

fn hyper_parts(h: HyperDual64) -> [f64; 4] {
    [h.re, h.eps1, h.eps2, h.eps1eps2]
}

#[test]
fn constant_subtrees_are_folded() {
    let e = compile("0.5*2*9.81");
    assert_eq!(
        &*e.code,
        &[Instr::Const {
            k: 0.5 * 2.0 * 9.81
        }]
    );
    assert_eq!(e.constant_value(), Some(9.81));
    let e = compile("x * (0.5*2) + sin(pi/2)^2");
    assert_eq!(
        &*e.code,
        &[Instr::MulRK { a: 0, k: 1.0 }, Instr::AddAK { k: 1.0 }]
    );
    // No reassociation: `x*0.5*2` is `(x*0.5)*2`.
    assert_eq!(
        &*compile("x*0.5*2").code,
        &[Instr::MulRK { a: 0, k: 0.5 }, Instr::MulAK { k: 2.0 }]
    );
    assert_eq!(compile("x*0.5*2").constant_value(), None);
    assert_eq!(compile("x").constant_value(), None);
}

#[test]
fn the_paper_lagrangian_is_five_instructions() {
    let scope = Bindings::new()
        .with_constant("m", 2.0)
        .with_constant("g", 9.81)
        .with_slot("x3", 2)
        .with_slot("x1_dot", 3)
        .with_slot("x2_dot", 4)
        .with_slot("x3_dot", 5);
    let e = Expression::parse("0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2) - m*g*x3", &scope).unwrap();
    assert_eq!(
        &*e.code,
        &[
            Instr::MulRR { a: 3, b: 3 },
            Instr::MulAddRR { a: 4, b: 4 },
            Instr::MulAddRR { a: 5, b: 5 },
            Instr::MulAK { k: 1.0 },
            Instr::SubMulRK {
                a: 2,
                k: 2.0 * 9.81
            },
        ]
    );
    assert_eq!(e.temps, 0);
    assert_eq!(e.names(), &["m", "x1_dot", "x2_dot", "x3_dot", "g", "x3"]);
    assert_eq!(e.slots(), &[2, 3, 4, 5]);
    assert!(!e.reads(0) && e.reads(2));
    let (q, q_dot) = ([0.1, 0.2, 0.3], [1.0, -2.0, 0.5]);
    let native = (1.0f64 + 4.0 + 0.25) * (0.5 * 2.0) - 0.3 * (2.0 * 9.81);
    assert_eq!(e.eval_split(&q, &q_dot), native);
}

#[test]
fn names_bound_to_constants_fold_and_are_listed() {
    let scope = Bindings::from_parts([("x", 0)], [("k", 4.0), ("c", 0.5)]);
    let e = Expression::parse("-k*x + c*k", &scope).unwrap();
    assert_eq!(
        &*e.code,
        &[Instr::MulRK { a: 0, k: -4.0 }, Instr::AddAK { k: 2.0 }]
    );
    assert_eq!(e.names(), &["k", "x", "c"]);
    assert_eq!(e.slots(), &[0]);
    assert_eq!(e.eval(&[1.5]), -4.0);
    // Only constants: one constant, which reads no slot.
    let e = Expression::parse("k^2 + pi*0", &scope).unwrap();
    assert_eq!(e.constant_value(), Some(16.0));
    assert!(e.slots().is_empty());
    assert_eq!(e.names(), &["k"]);
    assert_eq!(e.eval::<f64>(&[]), 16.0);
    // The constant wins over a slot of the same name; a later binding replaces an earlier one.
    let both = Bindings::new().with_slot("k", 0).with_constant("k", 3.0);
    assert_eq!(
        Expression::parse("k", &both).unwrap().constant_value(),
        Some(3.0)
    );
    let back = both.with_slot("k", 1);
    assert_eq!(Expression::parse("k", &back).unwrap().slots(), &[1]);
    // A constant is not a function.
    let error = Expression::parse("k(2)", &scope).unwrap_err();
    assert!(error.to_string().contains("not a function"), "{error}");
}

#[test]
fn a_custom_scope_can_bind_constants() {
    struct Parameters;
    impl Scope for Parameters {
        fn resolve(&self, name: &str) -> Option<usize> {
            (name == "t").then_some(0)
        }
        fn constant(&self, name: &str) -> Option<f64> {
            (name == "omega").then_some(2.0)
        }
    }
    let e = Expression::parse("sin(omega*t)", &Parameters).unwrap();
    assert_eq!(
        &*e.code,
        &[Instr::MulRK { a: 0, k: 2.0 }, Instr::Unary { op: Op::Sin }]
    );
    assert_eq!(e.eval(&[0.25]), 0.5f64.sin());
    // The provided method binds nothing.
    assert_eq!(NAMES.constant("x"), None);
}

#[test]
fn products_fuse_with_sums() {
    let code = |source: &str| compile(source).code.to_vec();
    assert_eq!(
        code("x + y*z"),
        [Instr::MulRR { a: 1, b: 2 }, Instr::AddAR { a: 0 }]
    );
    assert_eq!(
        code("sin(x) - y*z"),
        [
            Instr::UnaryR { op: Op::Sin, a: 0 },
            Instr::SubMulRR { a: 1, b: 2 }
        ]
    );
    assert_eq!(
        code("y*z - sin(x)"),
        [
            Instr::UnaryR { op: Op::Sin, a: 0 },
            Instr::MulSubRR { a: 1, b: 2 }
        ]
    );
    assert_eq!(
        code("2*y - sin(x)"),
        [
            Instr::UnaryR { op: Op::Sin, a: 0 },
            Instr::MulSubRK { a: 1, k: 2.0 }
        ]
    );
    assert_eq!(
        code("sin(x) + y*3"),
        [
            Instr::UnaryR { op: Op::Sin, a: 0 },
            Instr::MulAddRK { a: 1, k: 3.0 }
        ]
    );
    assert_eq!(
        code("x^2 + y^2"),
        [Instr::MulRR { a: 0, b: 0 }, Instr::MulAddRR { a: 1, b: 1 }]
    );
}

#[test]
fn temporaries_hold_values_while_the_accumulator_works() {
    let e = compile("(x+y)*(y+z)");
    assert_eq!(
        &*e.code,
        &[
            Instr::AddRR { a: 0, b: 1 },
            Instr::Spill { t: 0 },
            Instr::AddRR { a: 1, b: 2 },
            Instr::MulTA { t: 0 },
        ]
    );
    assert_eq!(e.temps, 1);
    assert_eq!(e.eval(&[1.0, 2.0, 3.0]), 15.0);
    // min/max/atan2 and a varying exponent take their left operand from a temporary or input.
    assert_eq!(
        &*compile("min(x, 0)").code,
        &[
            Instr::Const { k: 0.0 },
            Instr::BinaryRA { op: Op::Min, a: 0 }
        ]
    );
    assert_eq!(
        &*compile("2^x").code,
        &[
            Instr::Const { k: 2.0 },
            Instr::Spill { t: 0 },
            Instr::Load { a: 0 },
            Instr::BinaryTA { op: Op::Pow, t: 0 },
        ]
    );
    assert_eq!(compile("2^x").eval(&[3.0]), (2f64.ln() * 3.0).exp());
    assert_eq!(compile("max(x*y, sin(z))").eval(&[1.0, 2.0, 0.5]), 2.0);
    assert_eq!(
        compile("atan2(sin(z), x*y)").eval(&[1.0, 2.0, 0.5]),
        0.5f64.sin().atan2(2.0)
    );
}

/// Regression: a lazy product on the left of a product with the accumulator on the right used
/// to overwrite the accumulator (`x*0.5 * -x` found by the property test below).
#[test]
fn a_lazy_product_left_of_the_accumulator_keeps_it() {
    let e = compile("x*0.5 * -x");
    assert_eq!(e.eval(&[3.0, 0.0, 0.0]), -4.5);
    assert_eq!(
        compile("(x*y) / sin(z)").eval(&[2.0, 3.0, 0.5]),
        6.0 / 0.5f64.sin()
    );
    assert_eq!(compile("(x*y) - z*x").eval(&[2.0, 3.0, 0.5]), 5.0);
}

#[test]
fn powers_are_specialised_on_constant_exponents() {
    assert_eq!(&*compile("x^2").code, &[Instr::MulRR { a: 0, b: 0 }]);
    assert_eq!(
        &*compile("sin(x)^2").code,
        &[Instr::UnaryR { op: Op::Sin, a: 0 }, Instr::MulAA]
    );
    assert_eq!(
        &*compile("pow(x, -3)").code,
        &[Instr::Load { a: 0 }, Instr::PowI { n: -3 }]
    );
    assert_eq!(
        &*compile("x^(1/2)").code,
        &[Instr::Load { a: 0 }, Instr::PowF { k: 0.5 }]
    );
    assert_eq!(
        &*compile("x^y").code,
        &[Instr::Load { a: 1 }, Instr::BinaryRA { op: Op::Pow, a: 0 }]
    );
    assert_eq!(compile("(-2)^3").constant_value(), Some(-8.0));
    assert_eq!(
        compile("(-8)^2^-1").constant_value().map(f64::is_nan),
        Some(true)
    );
}

#[test]
fn dependencies() {
    let e = compile("y*sin(y) + 0*x");
    assert_eq!(e.names(), &["y".to_string(), "x".to_string()]);
    assert_eq!(e.slots(), &[0, 1]);
    assert!(e.reads(0) && e.reads(1) && !e.reads(2));
    let e = compile("2*pi");
    assert!(e.slots().is_empty() && e.names().is_empty());
    assert_eq!(e.to_string(), "2*pi");
    assert_eq!(e.source(), "2*pi");
}

#[test]
fn split_inputs_read_the_second_slice_past_the_first() {
    let e = compile("x - 10*y + 100*z");
    let all = [1.0, 2.0, 3.0];
    for split in 0..=3 {
        let (first, second) = all.split_at(split);
        assert_eq!(e.eval_split(first, second), 281.0, "split at {split}");
    }
    let h = hyper(all);
    assert_eq!(
        hyper_parts(e.eval_split(&h[..1], &h[1..])),
        hyper_parts(e.eval(&h))
    );
}

#[test]
fn the_time_is_read_from_the_slots_past_both_slices() {
    // `z` plays the time: slot 2, past `x` and `y`.
    let e = compile("x - 10*y + 100*z");
    assert_eq!(e.eval_at(&[1.0], &[2.0], 3.0), 281.0);
    // `h(t, q)`: the state's first slice alone, every slot past it is the time.
    let h = compile("x + 10*z");
    assert_eq!(h.eval_at(&[1.0], &[], 3.0), 31.0);
    // A formula of the state alone ignores the time, and runs as `eval_split`.
    let l = compile("x*y - x/y");
    for (x, y) in [(1.5, 0.3), (-2.0, 7.0)] {
        assert!(same_bits(
            l.eval_at(&[x], &[y], 9.0),
            l.eval_split(&[x], &[y])
        ));
    }
    // Over dual numbers, the time carries its own derivative.
    let t = Dual64::new(3.0, 1.0);
    let got = compile("x*sin(2*z)").eval_at(&[Dual64::from(1.5)], &[Dual64::from(0.0)], t);
    assert_eq!(got.re, 1.5 * (2.0 * 3.0f64).sin());
    assert_eq!(got.eps, 1.5 * 2.0 * (2.0 * 3.0f64).cos());
}

#[test]
#[should_panic]
fn a_missing_input_panics() {
    compile("x + z").eval_split(&[1.0], &[2.0]);
}

#[test]
fn deep_expressions_evaluate_without_recursion() {
    let limits = Limits {
        max_depth: 20_000,
        ..Limits::default()
    };
    let parse = |source: &str| Expression::parse_with(source, &NAMES, &limits).unwrap();
    // Right-nested sums keep one value waiting per level: temporaries on the heap.
    let n = 5_000;
    let right = parse(&format!("{}x{}", "sin(x)+(".repeat(n), ")".repeat(n)));
    assert!(right.temps > 32);
    let expected = (0..n).fold(0.5, |sum, _| 0.5f64.sin() + sum);
    assert_eq!(right.eval(&[0.5]), expected);
    assert_eq!(right.eval(&hyper([0.5, 0.0, 0.0])).re, expected);
    // Nested calls and signs need no temporaries at all.
    let nested = parse(&format!("{}x{}", "-sin(".repeat(n), ")".repeat(n)));
    assert_eq!(nested.temps, 0);
    let expected = (0..n).fold(0.5f64, |x, _| -x.sin());
    assert_eq!(nested.eval(&[0.5]), expected);
    // Between 4 and 32 waiting values: the larger array on the stack.
    let middle = parse(&format!("{}x{}", "sin(x)+(".repeat(20), ")".repeat(20)));
    // The innermost sum takes `x` straight from the input: 19 values wait.
    assert_eq!(middle.temps, 19);
    assert_eq!(
        middle.eval(&[1.0]),
        (0..20).fold(1.0, |s, _| 1f64.sin() + s)
    );
}

/// Every instruction kind, with a source that compiles to it.
const EVERY_INSTRUCTION: [(&str, &str); 45] = [
    ("Load", "x^3"),
    ("LoadT", "min(2, sin(x))"),
    ("Const", "min(x, 1)"),
    ("Spill", "(x+y)*(y+z)"),
    ("Unary", "-(x+y)"),
    ("UnaryR", "cos(x)"),
    ("PowI", "x^-3"),
    ("PowF", "x^2.5"),
    ("BinaryTA", "max(sin(x), y)"),
    ("BinaryRA", "atan2(x, y)"),
    ("AddRR", "x + y"),
    ("AddAR", "sin(x) + y"),
    ("AddTA", "(x+y) + (x-z)"),
    ("AddAK", "sin(x) + 2"),
    ("AddRK", "3 + x"),
    ("SubRR", "x - y"),
    ("SubAR", "sin(x) - y"),
    ("SubRA", "y - sin(x)"),
    ("SubTA", "(x+y) - (x-z)"),
    ("SubAK", "sin(x) - 2"),
    ("SubKA", "2 - sin(x)"),
    ("SubRK", "x - 2"),
    ("SubKR", "2 - x"),
    ("MulRR", "x*y"),
    ("MulAR", "sin(x)*y"),
    ("MulRA", "y*sin(x)"),
    ("MulTA", "(x+y)*(x-z)"),
    ("MulAK", "sin(x)*2"),
    ("MulRK", "2*x"),
    ("MulAA", "sin(x)^2"),
    ("DivRR", "x/y"),
    ("DivAR", "sin(x)/y"),
    ("DivRA", "y/sin(x)"),
    ("DivTA", "(x+y)/(x-z)"),
    ("DivAK", "sin(x)/3"),
    ("DivKA", "3/sin(x)"),
    ("DivRK", "x/3"),
    ("DivKR", "3/x"),
    ("MulAddRR", "sin(x) + y*z"),
    ("MulSubRR", "y*z - sin(x)"),
    ("SubMulRR", "sin(x) - y*z"),
    ("MulAddRK", "sin(x) + 3*y"),
    ("MulSubRK", "3*y - sin(x)"),
    ("SubMulRK", "sin(x) - y*3"),
    ("Unary tan, tanh", "tan(x) + tanh(y)"),
];

#[test]
fn every_instruction_agrees_over_f64_and_dual_numbers() {
    let points = [
        [0.7, -1.3, 2.5],
        [1.1, 0.3, -0.6],
        [-2.9, 1.7, 0.1],
        [0.0, -0.0, 1e-3],
        [123.456, 7.0, -3.25],
    ];
    for (kind, source) in EVERY_INSTRUCTION {
        let e = compile(source);
        let name = kind.split(' ').next().unwrap_or(kind);
        assert!(
            e.code.iter().any(|i| format!("{i:?}").starts_with(name)),
            "{source} should use {kind}: {:?}",
            e.code
        );
        for values in points {
            let value = e.eval(&values);
            let reference = Reference::parse(source).eval(&values);
            assert!(same_bits(value, reference), "{source} at {values:?}");
            let h = e.eval(&hyper(values));
            let expected = Reference::parse(source).eval(&hyper(values));
            for (got, want) in hyper_parts(h).into_iter().zip(hyper_parts(expected)) {
                assert!(
                    same_value(got, want),
                    "{source} at {values:?}: {h:?} {expected:?}"
                );
            }
            assert!(same_bits(h.re, value), "{source} at {values:?}");
            let d = e.eval(&values.map(|v| Dual64::new(v, 1.0)));
            assert!(same_bits(d.re, value), "{source} at {values:?}");
            let v: [DualSVec64<3>; 3] =
                std::array::from_fn(|i| DualSVec64::<3>::from_re(values[i]).derivative(i));
            assert!(same_bits(e.eval(&v).re, value), "{source} at {values:?}");
        }
    }
}

/// num-dual rounds the real part of these differently from `f64`; the evaluator does not.
#[test]
fn real_parts_are_the_f64_values_where_num_dual_rounds_differently() {
    let sources = [
        "x/y", "3/x", "tan(x)", "tanh(x)", "x^5", "x^-3", "x^-1", "x^2.5", "x^7",
    ];
    for source in sources {
        let e = compile(source);
        for i in 1..2000 {
            let values = [
                0.1 + f64::from(i) * 0.00137,
                0.3 + f64::from(i % 37) * 0.0711,
                0.0,
            ];
            let value = e.eval(&values);
            assert!(
                same_bits(e.eval(&hyper(values)).re, value),
                "{source} at {values:?}"
            );
        }
    }
    // The corner where num-dual's real part is not finite: tanh(±∞) is ±1, derivatives 0.
    let h = compile("tanh(x)").eval(&[HyperDual64::new(f64::INFINITY, 1.0, 1.0, 0.0)]);
    assert_eq!(hyper_parts(h), [1.0, 0.0, 0.0, 0.0]);
    // Derivatives are still num-dual's.
    let x = HyperDual64::new(1.3, 1.0, 1.0, 0.0);
    let h = compile("x^5").eval(&[x]);
    let expected = x.powi(5);
    assert_eq!(
        [h.eps1, h.eps2, h.eps1eps2],
        [expected.eps1, expected.eps2, expected.eps1eps2]
    );
}

/// num-dual's `powi` would multiply n(n − 1) as an `i32` (overflow: a panic in a debug build,
/// a wrong second derivative in a release one); such powers go through `powf`.
#[test]
fn a_huge_integer_power_has_its_derivatives() {
    let n = 100_000.0;
    let h = compile("x^100000").eval(&[HyperDual64::new(1.0, 1.0, 1.0, 0.0)]);
    // At x = 1: x^n = 1, n x^(n−1) = n, n(n−1) x^(n−2) = n(n−1), all exact.
    assert_eq!(hyper_parts(h), [1.0, n, n, n * (n - 1.0)]);
    let h = compile("x^(-100000)").eval(&[HyperDual64::new(1.0, 1.0, 1.0, 0.0)]);
    assert_eq!(hyper_parts(h), [1.0, -n, -n, n * (n + 1.0)]);
}

#[test]
fn with_real_part_moves_only_the_real_part() {
    let y = HyperDual64::new(1.0 + f64::EPSILON, 2.0, 3.0, 4.0);
    assert_eq!(
        hyper_parts(ops::with_real_part(y, || 1.0)),
        [1.0, 2.0, 3.0, 4.0]
    );
    let y = HyperDual64::new(f64::MAX, 2.0, 3.0, 4.0);
    assert_eq!(
        hyper_parts(ops::with_real_part(y, || f64::INFINITY)),
        [f64::INFINITY, 2.0, 3.0, 4.0]
    );
    let nan = ops::with_real_part(y, || f64::NAN);
    assert!(nan.re.is_nan() && nan.eps1 == 2.0);
    assert_eq!(
        ops::with_real_part(5.0, || 6.0),
        5.0,
        "f64 values are left alone"
    );
}

/// A well-formed expression tree, for the reference evaluator.
#[derive(Clone, Debug)]
enum Reference {
    Number(f64),
    Var(usize),
    Neg(Box<Reference>),
    Binary(char, Box<Reference>, Box<Reference>),
    Call(Op, Vec<Reference>),
}

impl Reference {
    /// The tree of a source in the restricted grammar of [`EVERY_INSTRUCTION`] and of
    /// [`Reference::print`]: fully parenthesised by the printer, or simple enough here.
    fn parse(source: &str) -> Reference {
        // Reuse the real parser's precedence by printing back: build from a tiny Pratt parser.
        let tokens: Vec<String> = tokenize(source);
        let mut position = 0;
        let tree = parse_sum(&tokens, &mut position);
        assert_eq!(position, tokens.len(), "{source}");
        tree
    }

    fn is_constant(&self) -> bool {
        match self {
            Reference::Number(_) => true,
            Reference::Var(_) => false,
            Reference::Neg(a) => a.is_constant(),
            Reference::Binary(_, a, b) => a.is_constant() && b.is_constant(),
            Reference::Call(_, args) => args.iter().all(Reference::is_constant),
        }
    }

    /// The documented semantics, evaluated directly: constants apply as `f64`s, powers by a
    /// constant exponent use `powi`/`powf` (`x^2` is `x*x`), others `exp(y ln x)`.
    fn eval<D: zenosim::Scalar>(&self, vars: &[D]) -> D {
        if self.is_constant() {
            return D::from(self.eval_f64());
        }
        match self {
            Reference::Number(_) => unreachable!("constant"),
            Reference::Var(i) => vars[*i],
            Reference::Neg(a) => -a.eval(vars),
            Reference::Binary(op, a, b) => {
                let constant = |t: &Reference| t.is_constant().then(|| t.eval_f64());
                match (op, constant(a), constant(b)) {
                    ('^', _, Some(e)) => power(a.eval(vars), e),
                    ('+', Some(k), _) => b.eval(vars) + k,
                    ('+', _, Some(k)) => a.eval(vars) + k,
                    ('-', Some(k), _) => ops::sub_from(k, b.eval(vars)),
                    ('-', _, Some(k)) => a.eval(vars) - k,
                    ('*', Some(k), _) => b.eval(vars) * k,
                    ('*', _, Some(k)) => a.eval(vars) * k,
                    ('/', Some(k), _) => ops::div_into(k, b.eval(vars)),
                    ('/', _, Some(k)) => a.eval(vars) / k,
                    ('+', ..) => a.eval(vars) + b.eval(vars),
                    ('-', ..) => a.eval(vars) - b.eval(vars),
                    ('*', ..) => a.eval(vars) * b.eval(vars),
                    ('/', ..) => ops::div(a.eval(vars), b.eval(vars)),
                    _ => ops::pow(a.eval(vars), b.eval(vars)),
                }
            }
            Reference::Call(Op::Pow, args) if args[1].is_constant() => {
                power(args[0].eval(vars), args[1].eval_f64())
            }
            Reference::Call(op, args) if args.len() == 2 => {
                op.binary(args[0].eval(vars), args[1].eval(vars))
            }
            Reference::Call(op, args) => op.unary(args[0].eval(vars)),
        }
    }

    fn eval_f64(&self) -> f64 {
        match self {
            Reference::Number(v) => *v,
            Reference::Var(_) => unreachable!("a constant tree"),
            Reference::Neg(a) => -a.eval_f64(),
            Reference::Binary('^', a, b) => power(a.eval_f64(), b.eval_f64()),
            Reference::Binary(op, a, b) => {
                let op = match op {
                    '+' => Op::Add,
                    '-' => Op::Sub,
                    '*' => Op::Mul,
                    _ => Op::Div,
                };
                op.binary(a.eval_f64(), b.eval_f64())
            }
            Reference::Call(Op::Pow, args) => power(args[0].eval_f64(), args[1].eval_f64()),
            Reference::Call(op, args) if args.len() == 2 => {
                op.binary(args[0].eval_f64(), args[1].eval_f64())
            }
            Reference::Call(op, args) => op.unary(args[0].eval_f64()),
        }
    }

    /// Prints with every operation parenthesised.
    fn print(&self) -> String {
        match self {
            Reference::Number(v) if v.is_sign_negative() => format!("({v:?})"),
            Reference::Number(v) => format!("{v:?}"),
            Reference::Var(i) => NAMES[*i].to_string(),
            Reference::Neg(a) => format!("(-{})", a.print()),
            Reference::Binary(op, a, b) => format!("({} {op} {})", a.print(), b.print()),
            Reference::Call(op, args) => {
                let name = format!("{op:?}").to_lowercase();
                let args: Vec<_> = args.iter().map(Reference::print).collect();
                format!("{name}({})", args.join(", "))
            }
        }
    }
}

/// `x^e` for a constant `e`, as documented.
fn power<D: zenosim::Scalar>(x: D, e: f64) -> D {
    if e == 2.0 {
        x * x
    } else if e.fract() == 0.0 && e.abs() <= f64::from(i32::MAX) {
        ops::powi(x, e as i32)
    } else {
        ops::powf(x, e)
    }
}

fn tokenize(source: &str) -> Vec<String> {
    let mut tokens = Vec::new();
    let chars: Vec<char> = source.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric()
                    || chars[i] == '.'
                    || (matches!(chars[i], '+' | '-') && matches!(chars[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            tokens.push(chars[start..i].iter().collect());
        } else if c.is_ascii_alphabetic() {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_alphanumeric() {
                i += 1;
            }
            tokens.push(chars[start..i].iter().collect());
        } else {
            tokens.push(c.to_string());
            i += 1;
        }
    }
    tokens
}

fn parse_sum(tokens: &[String], at: &mut usize) -> Reference {
    let mut left = parse_product(tokens, at);
    while let Some(op @ ("+" | "-")) = tokens.get(*at).map(String::as_str) {
        *at += 1;
        let right = parse_product(tokens, at);
        left = Reference::Binary(op.chars().next().unwrap_or('+'), left.into(), right.into());
    }
    left
}

fn parse_product(tokens: &[String], at: &mut usize) -> Reference {
    let mut left = parse_sign(tokens, at);
    while let Some(op @ ("*" | "/")) = tokens.get(*at).map(String::as_str) {
        *at += 1;
        let right = parse_sign(tokens, at);
        left = Reference::Binary(op.chars().next().unwrap_or('*'), left.into(), right.into());
    }
    left
}

fn parse_sign(tokens: &[String], at: &mut usize) -> Reference {
    if tokens[*at] == "-" {
        *at += 1;
        return Reference::Neg(parse_sign(tokens, at).into());
    }
    parse_power(tokens, at)
}

fn parse_power(tokens: &[String], at: &mut usize) -> Reference {
    let base = parse_atom(tokens, at);
    if tokens.get(*at).map(String::as_str) == Some("^") {
        *at += 1;
        let exponent = parse_sign(tokens, at);
        return Reference::Binary('^', base.into(), exponent.into());
    }
    base
}

fn parse_atom(tokens: &[String], at: &mut usize) -> Reference {
    let token = tokens[*at].clone();
    *at += 1;
    if token == "(" {
        let inner = parse_sum(tokens, at);
        assert_eq!(tokens[*at], ")");
        *at += 1;
        return inner;
    }
    if let Some(i) = NAMES.iter().position(|&n| n == token) {
        return Reference::Var(i);
    }
    if token == "pi" {
        return Reference::Number(std::f64::consts::PI);
    }
    if let Some((op, arity)) = Op::function(&token) {
        assert_eq!(tokens[*at], "(");
        *at += 1;
        let mut args = vec![parse_sum(tokens, at)];
        while tokens[*at] == "," {
            *at += 1;
            args.push(parse_sum(tokens, at));
        }
        assert_eq!((tokens[*at].as_str(), args.len()), (")", arity));
        *at += 1;
        return Reference::Call(op, args);
    }
    Reference::Number(token.parse().unwrap_or_else(|_| panic!("number {token}")))
}

fn tree() -> impl Strategy<Value = Reference> {
    let leaf = prop_oneof![
        prop::sample::select(vec![0.5, 2.0, 3.0, -1.0, 0.1, 7.25, 0.0]).prop_map(Reference::Number),
        (0..NAMES.len()).prop_map(Reference::Var),
        (0..NAMES.len()).prop_map(Reference::Var),
    ];
    leaf.prop_recursive(7, 64, 3, |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| Reference::Neg(Box::new(a))),
            (
                prop::sample::select(vec!['+', '-', '*', '/', '^', '+', '*']),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(op, a, b)| Reference::Binary(op, Box::new(a), Box::new(b))),
            (
                prop::sample::select(vec![
                    Op::Sin,
                    Op::Cos,
                    Op::Tan,
                    Op::Atan,
                    Op::Tanh,
                    Op::Exp,
                    Op::Ln,
                    Op::Sqrt,
                    Op::Abs,
                    Op::Sinh
                ]),
                inner.clone()
            )
                .prop_map(|(op, a)| Reference::Call(op, vec![a])),
            (
                prop::sample::select(vec![Op::Atan2, Op::Pow, Op::Min, Op::Max]),
                inner.clone(),
                inner
            )
                .prop_map(|(op, a, b)| Reference::Call(op, vec![a, b])),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The compiled program (folded, fused, with temporaries) computes what a direct recursive
    /// evaluation does: bit for bit over f64, and over hyper-dual numbers bit for bit in the
    /// real part and equal in the derivatives.
    #[test]
    fn compiled_evaluation_equals_the_reference(
        tree in tree(),
        values in prop::array::uniform3(-3.0f64..3.0),
    ) {
        let source = tree.print();
        let e = compile(&source);
        prop_assert_eq!(e.constant_value().is_some(), tree.is_constant(), "{}", source);
        let (got, want) = (e.eval(&values), tree.eval(&values));
        prop_assert!(same_bits(got, want), "{} at {:?}: {} vs {}", source, values, got, want);
        let (h, expected) = (e.eval(&hyper(values)), tree.eval(&hyper(values)));
        prop_assert!(same_bits(h.re, got), "{} at {:?}: {:?} vs {}", source, values, h, got);
        for (a, b) in hyper_parts(h).into_iter().zip(hyper_parts(expected)) {
            prop_assert!(same_value(a, b), "{} at {:?}: {:?} vs {:?}", source, values, h, expected);
        }
        // Any split of the inputs gives the same number.
        let split = e.eval_split(&values[..1], &values[1..]);
        prop_assert!(same_bits(split, got));
        // So does `z` read as the time, past both slices; and with every slot in the slices
        // the time is not read.
        let at = e.eval_at(&values[..1], &values[1..2], values[2]);
        prop_assert!(same_bits(at, got));
        prop_assert!(same_bits(e.eval_at(&values, &[], f64::NAN), got));
        let h_at = e.eval_at(&hyper(values)[..2], &[], hyper(values)[2]);
        for (a, b) in hyper_parts(h_at).into_iter().zip(hyper_parts(h)) {
            prop_assert!(same_bits(a, b), "{} at {:?}: {:?} vs {:?}", source, values, h_at, h);
        }
    }
}
