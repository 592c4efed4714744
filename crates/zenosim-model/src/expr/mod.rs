//! The expression language of model files: parse a formula once, evaluate it many times over
//! `f64` or dual numbers.
//!
//! # The language
//!
//! | Element | Written | Notes |
//! |---|---|---|
//! | numbers | `2`, `1.5e-3`, `.5`, `3.`, `1E+3` | decimal, with an optional exponent |
//! | names | `m`, `x1_dot`, `_k` | a letter or `_`, then letters, digits or `_` (ASCII); the caller's [`Scope`] says which exist |
//! | constant | `pi` | π; `t` and every other name come from the scope |
//! | operators | `+ - * / ^` | `^` is the power |
//! | signs | `-x`, `+x` | |
//! | grouping | `( … )` | |
//! | calls | `sin(x)`, `atan2(y, x)` | see below |
//!
//! Precedence, from loosest to tightest: `+ -` (left-associative), `* /` (left-associative),
//! the signs, `^` (right-associative). Hence `-x^2` is `-(x^2)`, `-2^2 = -4`, `2^3^2 = 2^9`,
//! `1-2-3 = -4`, `8/4/2 = 1`, and `2^-1 = 0.5`, `2*-3 = -6` are accepted.
//!
//! The functions take one argument, except those marked:
//! `sin cos tan asin acos atan atan2(y, x) sinh cosh tanh exp ln log sqrt abs pow(x, y)
//! min(a, b) max(a, b)`.
//! **`log` is the natural logarithm**, the same as `ln` (as in C and Python); there is no
//! base-10 logarithm: write `ln(x)/ln(10)`.
//!
//! Whitespace (spaces, tabs, carriage returns, newlines) separates tokens and is otherwise
//! ignored, so a formula may span several lines; errors report the line and column.
//!
//! # Evaluation
//!
//! [`Expression::parse`] compiles the source into a flat register program. Names the [`Scope`]
//! binds to constants (model parameters, say) compile to their values, and subexpressions
//! without variables are folded into constants (`0.5*m*x` with `m = 2` becomes `1*x`; `0.5*2*9.81`
//! becomes `9.81`, exactly as evaluated left to right; nothing is reassociated, so `x*0.5*2`
//! keeps both multiplications). Constants are operands of the instructions (`x*c` scales a dual
//! number), and a product feeding a sum is fused with it. [`Expression::eval`],
//! [`Expression::eval_split`] and [`Expression::eval_at`] (which reads the time from the slots
//! past the state's) run the program over a small register file, with no recursion, generic
//! over [`zenosim::Scalar`]:
//! - the value over `f64` is the real part of the value over any dual number, bit for bit
//!   (where num-dual rounds a real part differently, as in `a/b`, `tan`, `tanh` and powers,
//!   the real part is set to the `f64` value);
//! - `x^n` and `pow(x, n)` with a constant integer `n` use `powi` (exact for negative `x`; `x^2`
//!   is `x*x`); a constant non-integer exponent uses `powf`; an exponent that varies uses
//!   `exp(n ln x)` (over `f64` too), which needs `x > 0`.
//! - `min` and `max` compare real parts and return the whole chosen number, derivatives
//!   included; on a tie they return the first argument, and a NaN argument is propagated.
//! - `abs` is `DualNum`'s: its derivative is the sign of the real part.
//!
//! ```
//! use std::collections::HashMap;
//! use zenosim_model::expr::{Bindings, Expression};
//!
//! let scope = HashMap::from([("m".to_string(), 0), ("x".to_string(), 1)]);
//! let energy = Expression::parse("0.5 * m * x^2", &scope).unwrap();
//! assert_eq!(energy.eval(&[2.0, 3.0]), 9.0);
//! assert_eq!(energy.slots(), &[0, 1]);
//!
//! // With `m` a known parameter, `0.5 * m` folds into one constant.
//! let scope = Bindings::new().with_constant("m", 2.0).with_slot("x", 0);
//! let energy = Expression::parse("0.5 * m * x^2", &scope).unwrap();
//! assert_eq!(energy.eval(&[3.0]), 9.0);
//! assert_eq!(energy.slots(), &[0]);
//! assert_eq!(energy.names(), &["m", "x"]);
//! ```

mod builder;
mod error;
mod instr;
mod lexer;
mod ops;
mod parser;
mod program;

use std::collections::{BTreeMap, HashMap};

pub use error::ExprError;
pub use program::Expression;

/// The functions of the language, in the order messages list them.
pub const FUNCTION_NAMES: [&str; 18] = [
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "exp", "ln",
    "log", "sqrt", "abs", "pow", "min", "max",
];

/// The constants of the language (`pi`).
pub const CONSTANT_NAMES: [&str; 1] = ["pi"];

/// The default of [`Limits::max_depth`].
pub const DEFAULT_MAX_DEPTH: usize = 256;

/// The default of [`Limits::max_length`].
pub const DEFAULT_MAX_LENGTH: usize = 100_000;

/// The default of [`Limits::max_operations`]: 10 million, 2.7 times what a 20-link pendulum
/// chain written out in full needs (3.7 million; the shipped models need at most a few
/// thousand).
pub const DEFAULT_MAX_OPERATIONS: usize = 10_000_000;

/// Whether `name` belongs to the language itself (a function or a constant) and therefore
/// cannot name a parameter or a coordinate: the parser never asks the scope about it.
pub fn is_reserved(name: &str) -> bool {
    FUNCTION_NAMES.contains(&name) || CONSTANT_NAMES.contains(&name)
}

/// Bounds on what [`Expression::parse_with`] accepts, and on the work of differentiating a model
/// file's formulas, so that hostile or broken input fails fast.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The deepest nesting accepted: parentheses, function calls, signs and operators waiting
    /// for their right operand all count (`-(a+(b))` nests 4 deep). It also bounds the
    /// evaluation stack.
    pub max_depth: usize,
    /// The longest source accepted, in characters.
    pub max_length: usize,
    /// The most operations that tracing a model file's derivatives may take (each operation
    /// the automatic differentiation does on a traced number: see
    /// `zenosim::Compiled::trace_bounded`), an entry new to the trace and each entry of the
    /// programs made from it counting as 8. It grows linearly with the formulas' size, and
    /// bounds the time and memory that loading a model takes.
    pub max_operations: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_depth: DEFAULT_MAX_DEPTH,
            max_length: DEFAULT_MAX_LENGTH,
            max_operations: DEFAULT_MAX_OPERATIONS,
        }
    }
}

/// Where the names of an expression are bound: the caller decides which names exist and gives
/// each either a constant value or a variable slot, the index into the slice passed to
/// [`Expression::eval`].
///
/// Implemented for maps from names to slots, for closures `Fn(&str) -> Option<usize>`, for
/// lists of names (a name's slot is its position), for `()` (no names at all), and by
/// [`Bindings`], which binds constants too.
pub trait Scope {
    /// The slot of `name`, or `None` if the name is not defined.
    fn resolve(&self, name: &str) -> Option<usize>;

    /// The value of `name` if it is bound to a constant, known when the expression is compiled;
    /// asked before [`resolve`](Self::resolve). By default no name is.
    ///
    /// A constant name compiles to its value, which is folded with the constants around it:
    /// with `m` and `g` constants, `0.5*m*v^2 - m*g*z` evaluates `c1*v^2 - c2*z`. It is listed
    /// in [`Expression::names`] (so callers can track what depends on it) but, reading no
    /// variable, not in [`Expression::slots`].
    fn constant(&self, name: &str) -> Option<f64> {
        let _ = name;
        None
    }
}

/// A [`Scope`] built from names bound to variable slots and names bound to constants.
///
/// ```
/// use zenosim_model::expr::{Bindings, Expression};
///
/// let scope = Bindings::from_parts([("x", 0), ("v", 1)], [("k", 4.0)]);
/// let force = Expression::parse("-k*x", &scope).unwrap();
/// assert_eq!(force.eval(&[0.5, 0.0]), -2.0);
/// assert_eq!(force.slots(), &[0]);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bindings {
    slots: HashMap<String, usize>,
    constants: HashMap<String, f64>,
}

impl Bindings {
    /// No names.
    pub fn new() -> Self {
        Self::default()
    }

    /// The names of `slots` bound to their slots and those of `constants` to their values; a
    /// name in both is a constant.
    pub fn from_parts<S: Into<String>, C: Into<String>>(
        slots: impl IntoIterator<Item = (S, usize)>,
        constants: impl IntoIterator<Item = (C, f64)>,
    ) -> Self {
        Self {
            slots: slots.into_iter().map(|(n, s)| (n.into(), s)).collect(),
            constants: constants.into_iter().map(|(n, v)| (n.into(), v)).collect(),
        }
    }

    /// Binds `name` to variable slot `slot`, replacing any earlier binding of `name`.
    pub fn with_slot(mut self, name: impl Into<String>, slot: usize) -> Self {
        let name = name.into();
        self.constants.remove(&name);
        self.slots.insert(name, slot);
        self
    }

    /// Binds `name` to the constant `value`, replacing any earlier binding of `name`.
    pub fn with_constant(mut self, name: impl Into<String>, value: f64) -> Self {
        let name = name.into();
        self.slots.remove(&name);
        self.constants.insert(name, value);
        self
    }
}

impl Scope for Bindings {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.slots.get(name).copied()
    }

    fn constant(&self, name: &str) -> Option<f64> {
        self.constants.get(name).copied()
    }
}

impl<F: Fn(&str) -> Option<usize>> Scope for F {
    fn resolve(&self, name: &str) -> Option<usize> {
        self(name)
    }
}

impl<S: std::hash::BuildHasher> Scope for HashMap<String, usize, S> {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.get(name).copied()
    }
}

impl<S: std::hash::BuildHasher> Scope for HashMap<&str, usize, S> {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.get(name).copied()
    }
}

impl Scope for BTreeMap<String, usize> {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.get(name).copied()
    }
}

impl Scope for BTreeMap<&str, usize> {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.get(name).copied()
    }
}

impl<T: AsRef<str>> Scope for [T] {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.iter().position(|n| n.as_ref() == name)
    }
}

impl<T: AsRef<str>, const N: usize> Scope for [T; N] {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.as_slice().resolve(name)
    }
}

impl<T: AsRef<str>> Scope for Vec<T> {
    fn resolve(&self, name: &str) -> Option<usize> {
        self.as_slice().resolve(name)
    }
}

/// No names: only constant expressions parse.
impl Scope for () {
    fn resolve(&self, _name: &str) -> Option<usize> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scopes() {
        let map = HashMap::from([("a".to_string(), 3)]);
        assert_eq!(map.resolve("a"), Some(3));
        assert_eq!(map.resolve("b"), None);
        let list = ["x", "y"];
        assert_eq!(list.resolve("y"), Some(1));
        assert_eq!(vec!["p".to_string()].resolve("p"), Some(0));
        let closure = |name: &str| (name == "t").then_some(7);
        assert_eq!(closure.resolve("t"), Some(7));
        assert_eq!(().resolve("t"), None);
        let tree = BTreeMap::from([("k", 1)]);
        assert_eq!(tree.resolve("k"), Some(1));
    }

    #[test]
    fn reserved_names() {
        assert!(is_reserved("pi") && is_reserved("log") && is_reserved("atan2"));
        assert!(!is_reserved("t") && !is_reserved("x") && !is_reserved("Sin"));
    }

    #[test]
    fn default_limits() {
        let limits = Limits::default();
        assert_eq!(
            (limits.max_depth, limits.max_length, limits.max_operations),
            (256, 100_000, 10_000_000)
        );
    }
}
