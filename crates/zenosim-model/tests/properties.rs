//! Property tests: no input makes the parser panic, and well-formed expressions evaluate to what
//! a direct recursive evaluation of the same tree gives.

use proptest::prelude::*;
use zenosim_model::expr::{ExprError, Expression};

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
