//! Property tests: no input makes the parser panic, well-formed expressions evaluate to what a
//! direct recursive evaluation of the same tree gives, and their compiled derivatives are the
//! differentiated ones. (Unit tests of the crate, so that they reuse its instantiation of the
//! engine for `FileModel` instead of compiling another.)

use crate::expr::{ExprError, Expression};
use crate::FileModel;
use proptest::prelude::*;

const NAMES: [&str; 3] = ["x", "y", "z"];
const VALUES: [f64; 3] = [0.7, -1.3, 2.5];

/// Parses, and if that succeeds evaluates; if it fails, checks the error points into the source.
fn parse_and_maybe_eval(source: &str) {
    match Expression::parse(source, &NAMES) {
        Ok(e) => {
            let _ = e.eval(&VALUES);
            assert!(e.slots().iter().all(|&s| s < NAMES.len()));
        }
        Err(error) => {
            let message = error.to_string();
            assert!(!message.is_empty());
            if let Some((line, column)) = error.position() {
                let text = source
                    .split('\n')
                    .nth(line - 1)
                    .expect("line within the source");
                assert!(
                    column >= 1 && column <= text.chars().count() + 1,
                    "{error:?} in {source:?}"
                );
            } else {
                assert!(matches!(
                    error,
                    ExprError::Empty | ExprError::TooLong { .. }
                ));
            }
        }
    }
}

const SOUP: [&str; 30] = [
    "x", "y", "z", "pi", "t", "2", ".5", "3.", "1e3", "1e", "+", "-", "*", "/", "^", "(", ")", ",",
    "sin", "atan2", "min", "pow", "sine", "ln", " ", "\n", "\t", "#", "é", ".",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_strings_never_panic(source in "\\PC{0,40}") {
        parse_and_maybe_eval(&source);
    }

    #[test]
    fn random_ascii_never_panics(source in "[ -~\n\t]{0,40}") {
        parse_and_maybe_eval(&source);
    }

    #[test]
    fn token_soups_never_panic(tokens in prop::collection::vec(prop::sample::select(&SOUP[..]), 0..40)) {
        parse_and_maybe_eval(&tokens.concat());
    }
}

/// A well-formed expression, for the reference evaluator.
#[derive(Clone, Debug)]
enum Tree {
    Number(f64),
    Var(usize),
    Pi,
    Neg(Box<Tree>),
    Binary(char, Box<Tree>, Box<Tree>),
    Call(&'static str, Vec<Tree>),
    /// Redundant parentheses.
    Group(Box<Tree>),
}

impl Tree {
    /// How tightly the printed form binds: `+ -` 1, `* /` 2, sign 3, `^` 4, atoms 5.
    fn precedence(&self) -> u8 {
        match self {
            Tree::Binary('+' | '-', ..) => 1,
            Tree::Binary('*' | '/', ..) => 2,
            Tree::Neg(_) => 3,
            Tree::Binary(..) => 4,
            _ => 5,
        }
    }

    /// Prints with as few parentheses as the grammar allows (plus the `Group`s).
    fn print(&self) -> String {
        let child = |tree: &Tree, at_least: u8| {
            if tree.precedence() >= at_least {
                tree.print()
            } else {
                format!("({})", tree.print())
            }
        };
        match self {
            Tree::Number(v) => format!("{v:?}"),
            Tree::Var(i) => NAMES[*i].to_string(),
            Tree::Pi => "pi".into(),
            Tree::Neg(a) => format!("-{}", child(a, 3)),
            // `^` is right-associative and its right operand may start with a sign.
            Tree::Binary('^', a, b) => format!("{}^{}", child(a, 5), child(b, 3)),
            Tree::Binary(op, a, b) => {
                let p = self.precedence();
                format!("{} {op} {}", child(a, p), child(b, p + 1))
            }
            Tree::Call(f, args) => {
                let args: Vec<_> = args.iter().map(Tree::print).collect();
                format!("{f}({})", args.join(", "))
            }
            Tree::Group(a) => format!("({})", a.print()),
        }
    }

    /// Whether a constant part of the formula is zero (`0.0`, `pi - pi`).
    fn has_zero_constant(&self) -> bool {
        if self.is_constant() {
            return self.eval(&[0.0; 3]) == 0.0;
        }
        match self {
            Tree::Neg(a) | Tree::Group(a) => a.has_zero_constant(),
            Tree::Binary(_, a, b) => a.has_zero_constant() || b.has_zero_constant(),
            Tree::Call(_, args) => args.iter().any(Tree::has_zero_constant),
            _ => false,
        }
    }

    fn is_constant(&self) -> bool {
        match self {
            Tree::Var(_) => false,
            Tree::Number(_) | Tree::Pi => true,
            Tree::Neg(a) | Tree::Group(a) => a.is_constant(),
            Tree::Binary(_, a, b) => a.is_constant() && b.is_constant(),
            Tree::Call(_, args) => args.iter().all(Tree::is_constant),
        }
    }

    /// The reference: a direct recursive evaluation with the documented semantics.
    fn eval(&self, vars: &[f64]) -> f64 {
        let power = |x: f64, exponent: &Tree| {
            let y = exponent.eval(vars);
            if !exponent.is_constant() {
                (x.ln() * y).exp()
            } else if y.fract() == 0.0 && y.abs() <= f64::from(i32::MAX) {
                x.powi(y as i32)
            } else {
                x.powf(y)
            }
        };
        match self {
            Tree::Number(v) => *v,
            Tree::Var(i) => vars[*i],
            Tree::Pi => std::f64::consts::PI,
            Tree::Neg(a) => -a.eval(vars),
            Tree::Group(a) => a.eval(vars),
            Tree::Binary(op, a, b) => {
                let x = a.eval(vars);
                match op {
                    '+' => x + b.eval(vars),
                    '-' => x - b.eval(vars),
                    '*' => x * b.eval(vars),
                    '/' => x / b.eval(vars),
                    _ => power(x, b),
                }
            }
            Tree::Call(f, args) => {
                let x = args[0].eval(vars);
                match *f {
                    "sin" => x.sin(),
                    "cos" => x.cos(),
                    "atan" => x.atan(),
                    "tanh" => x.tanh(),
                    "exp" => x.exp(),
                    "log" => x.ln(),
                    "sqrt" => x.sqrt(),
                    "abs" => x.abs(),
                    "atan2" => x.atan2(args[1].eval(vars)),
                    "pow" => power(x, &args[1]),
                    "min" => {
                        let y = args[1].eval(vars);
                        if x <= y || x.is_nan() {
                            x
                        } else {
                            y
                        }
                    }
                    "max" => {
                        let y = args[1].eval(vars);
                        if x >= y || x.is_nan() {
                            x
                        } else {
                            y
                        }
                    }
                    other => unreachable!("{other}"),
                }
            }
        }
    }
}

fn tree() -> impl Strategy<Value = Tree> {
    let leaf = prop_oneof![
        prop::sample::select(vec![0.5, 2.0, 3.0, 1e-3, 0.1, 1.5e3, 7.25, 0.0])
            .prop_map(Tree::Number),
        (0..NAMES.len()).prop_map(Tree::Var),
        Just(Tree::Pi),
    ];
    leaf.prop_recursive(6, 48, 3, |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| Tree::Neg(Box::new(a))),
            inner.clone().prop_map(|a| Tree::Group(Box::new(a))),
            (
                prop::sample::select(vec!['+', '-', '*', '/', '^']),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(op, a, b)| Tree::Binary(op, Box::new(a), Box::new(b))),
            (
                prop::sample::select(vec![
                    "sin", "cos", "atan", "tanh", "exp", "log", "sqrt", "abs"
                ]),
                inner.clone()
            )
                .prop_map(|(f, a)| Tree::Call(f, vec![a])),
            (
                prop::sample::select(vec!["atan2", "pow", "min", "max"]),
                inner.clone(),
                inner
            )
                .prop_map(|(f, a, b)| Tree::Call(f, vec![a, b])),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn compiled_evaluation_equals_the_reference(
        tree in tree(),
        vars in prop::array::uniform3(-3.0f64..3.0),
    ) {
        let source = tree.print();
        let expression = Expression::parse(&source, &NAMES)
            .unwrap_or_else(|e| panic!("{source}: {e}"));
        let (got, expected) = (expression.eval(&vars), tree.eval(&vars));
        prop_assert!(
            got.to_bits() == expected.to_bits() || (got.is_nan() && expected.is_nan()),
            "{source} at {vars:?}: compiled {got}, reference {expected}"
        );
        prop_assert_eq!(expression.constant_value().is_some(), tree.is_constant(), "{}", source);
    }
}

/// A three-coordinate model built from one random formula `t(x, y, z)`:
/// `L = (ẋ² + ẏ ż) t + t` (so `M`, the force and the mixed term all involve `t`) and `h = t`,
/// with or without its derivatives compiled. Built directly, not through a file: the formula
/// need not make a valid model.
fn tree_model(t: &str, compile: bool) -> FileModel {
    const STATE: [&str; 6] = ["x", "y", "z", "x_dot", "y_dot", "z_dot"];
    let lagrangian = format!("(x_dot^2 + y_dot*z_dot)*({t}) + ({t})");
    let mut model = FileModel::new(
        NAMES.iter().map(|n| n.to_string()).collect(),
        Expression::parse(&lagrangian, &STATE).unwrap(),
        vec![(
            zenosim::Constraint::new("c", 0.5),
            Expression::parse(t, &NAMES).unwrap(),
            Vec::new(),
            None,
        )],
        Vec::new(),
        None,
    );
    if compile {
        model.compiled = Some(zenosim::Compiled::trace(&model));
    }
    model
}

proptest! {
    // Failing cases are reported, not stored next to the sources.
    #![proptest_config(ProptestConfig {
        cases: 600,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// The compiled derivatives of a file formula are what differentiating it gives: bit for bit
    /// when the formula has no operation whose real part the interpreter adjusts (division,
    /// powers, tanh), else to rounding (there the compiled numbers are num-dual's own, as for a
    /// model written in Rust, and the interpreter's differ by an ulp of a real part). Values
    /// that are not finite are the same too: where a product the tracer dropped (`x · 0`) has an
    /// `x` that is not finite, zenosim differentiates instead.
    #[test]
    fn compiled_file_derivatives_are_the_differentiated_ones(
        tree in tree(),
        q in prop::array::uniform3(-3.0f64..3.0),
        v in prop::array::uniform3(-3.0f64..3.0),
    ) {
        let t = tree.print();
        let fast = tree_model(&t, true);
        let slow = tree_model(&t, false);
        let (traced, parts) = fast.compiled_derivatives().unwrap().coverage();
        // Branches on values (abs, min, max) cannot be traced. Nor can an operation whose
        // result depends on the sign of a zero (atan2, a division, a power) of a zero constant
        // that a simplification may have signed otherwise than num-dual (`ln(0 * x)` needs
        // `1/(±0)`). Nor can the motion held on a constraint whose gradient is identically
        // zero (a formula without a coordinate, or `x1 - x1`): it divides by `A M⁻¹ Aᵀ = 0`
        // (a simulation refuses such a constraint at its start). Such a gradient evaluates to 0,
        // or to NaN where the formula is not finite (`pi / (y - y)`: `0 · ∞`). Any other formula
        // is traced in full.
        let branches = ["abs", "min", "max"].iter().any(|f| t.contains(f));
        let (_, gradient) = zenosim::Derived::new(&slow).unwrap().constraint(0, &q);
        let flat = gradient.iter().all(|&a| a == 0.0 || a.is_nan());
        if !branches && !tree.has_zero_constant() && !flat {
            prop_assert_eq!(traced, parts, "{}", t);
        }
        let exact = !["/", "^", "pow", "tanh"].iter().any(|op| t.contains(op));
        // Everything derived at (q, q̇), as a list of named numbers.
        let derive_at = |model: &FileModel, q: &[f64; 3]| {
            let d = zenosim::Derived::new(model).unwrap();
            let mut values = vec![("energy", d.energy(q, &v))];
            values.extend(d.mass_matrix(q, &v).0.into_iter().map(|m| ("M", m)));
            let (h, a) = d.constraint(0, q);
            values.push(("h", h));
            values.extend(a.into_iter().map(|x| ("A", x)));
            values.push(("A q̇", d.normal_velocity(0, q, &v)));
            if let Some(acc) = d.acceleration(q, &v) {
                values.extend(acc.into_iter().map(|x| ("q̈", x)));
            } else {
                values.push(("no q̈", 0.0));
            }
            values
        };
        let (compiled, differentiated) = (derive_at(&fast, &q), derive_at(&slow, &q));
        // Where the formula is ill-conditioned (`sin(z^36)`), an ulp decides the value: moving
        // `q` by 1e-13 relative, the differentiated values themselves move.
        let nudged = derive_at(&slow, &q.map(|x| x * (1.0 + 1e-13)));
        prop_assert_eq!(compiled.len(), differentiated.len());
        for (((what, a), (_, b)), (_, c)) in compiled.iter().zip(&differentiated).zip(&nudged) {
            let (a, b, c) = (*a, *b, *c);
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-6 * (1.0 + x.abs() + y.abs());
            if exact {
                prop_assert!(
                    a.to_bits() == b.to_bits() || a == b || (a.is_nan() && b.is_nan()),
                    "{what} of {t}: compiled {a:e}, differentiated {b:e}"
                );
            } else if a.is_finite() && b.is_finite() && close(b, c) {
                prop_assert!(
                    close(a, b),
                    "{what} of {t}: compiled {a:e}, differentiated {b:e}"
                );
            }
        }
    }
}
