//! A compiled expression and its evaluation.

use std::fmt;

use zenosim::Scalar;

use super::instr::{execute, Instr};
use super::{ExprError, Limits, Scope};

/// A parsed expression, compiled for fast repeated evaluation.
///
/// Build it with [`Expression::parse`]; evaluate it with [`Expression::eval`] over `f64` or
/// any dual number.
#[derive(Clone, Debug, PartialEq)]
pub struct Expression {
    source: String,
    /// The accumulator program, see [`super::instr`].
    pub(super) code: Box<[Instr]>,
    /// How many temporaries the program uses at most.
    pub(super) temps: usize,
    names: Vec<String>,
    slots: Vec<usize>,
    /// One past the highest slot read (0 when none is): kept beside the program, so that
    /// [`Expression::eval_at`] tells whether it reads the time with one comparison.
    extent: usize,
}

impl Expression {
    /// Wraps a finished program.
    pub(super) fn new(
        source: &str,
        code: Box<[Instr]>,
        temps: usize,
        names: Vec<String>,
        slots: Vec<usize>,
    ) -> Self {
        let extent = slots.last().map_or(0, |&last| last + 1);
        Self {
            source: source.to_string(),
            code,
            temps,
            names,
            slots,
            extent,
        }
    }

    /// Parses `source`, resolving each name through `scope`, with the default [`Limits`].
    pub fn parse<S: Scope + ?Sized>(source: &str, scope: &S) -> Result<Self, ExprError> {
        Self::parse_with(source, scope, &Limits::default())
    }

    /// Parses `source`, resolving each name through `scope`, within `limits`.
    pub fn parse_with<S: Scope + ?Sized>(
        source: &str,
        scope: &S,
        limits: &Limits,
    ) -> Result<Self, ExprError> {
        super::parser::parse(source, scope, limits)
    }

    /// Evaluates the expression with `vars[slot]` as the value of each name bound to `slot`.
    ///
    /// The same as [`eval_split`](Self::eval_split) with everything in `first`.
    ///
    /// # Panics
    ///
    /// If `vars` has no entry for one of the [slots](Self::slots) the expression reads.
    #[inline]
    pub fn eval<D: Scalar>(&self, vars: &[D]) -> D {
        self.eval_split(vars, &[])
    }

    /// Evaluates the expression with its variables in two slices: slot `s` reads `first[s]` if
    /// `s < first.len()`, and `second[s - first.len()]` otherwise.
    ///
    /// Meant for `L(q, q̇)`: with the coordinates bound to slots `0..n` and the velocities to
    /// `n..2n`, `eval_split(q, q_dot)` evaluates it without copying `q` and `q̇` into one buffer.
    /// It does not allocate unless the expression nests unusually deep (more than 32 values
    /// waiting at once, which takes more than 32 levels of nesting).
    ///
    /// # Panics
    ///
    /// If `first` and `second` together have no entry for one of the [slots](Self::slots) the
    /// expression reads.
    #[inline]
    pub fn eval_split<D: Scalar>(&self, first: &[D], second: &[D]) -> D {
        self.run(|slot: usize| match first.get(slot) {
            Some(&value) => value,
            None => second[slot - first.len()],
        })
    }

    /// Evaluates the expression at the time `t`: slot `s` reads `first[s]` if
    /// `s < first.len()`, `second[s - first.len()]` if that is within `second`, and `t` for
    /// every slot past the end of both.
    ///
    /// Meant for formulas of the time: with the coordinates bound to slots `0..n`, the
    /// velocities to `n..2n` and the time `t` to slot `2n`, `eval_at(q, q_dot, t)` evaluates
    /// `L(t, q, q̇)`, and `eval_at(q, &[], t)` a formula `h(t, q)` of the coordinates and the
    /// time (which reads no velocity, so that its slot `2n` lies past both slices).
    ///
    /// An expression that reads no slot past the two slices (one that does not depend on the
    /// time) is evaluated exactly as [`eval_split`](Self::eval_split) evaluates it, through the
    /// same code: the time costs it one comparison.
    // Inlined whole, with the time's path out of line and cold: where the time is not read the
    // caller runs `eval_split` as if it had called it, and autonomous formulas evaluate as fast
    // as they did before the time existed.
    #[inline(always)]
    pub fn eval_at<D: Scalar>(&self, first: &[D], second: &[D], t: D) -> D {
        if self.extent <= first.len() + second.len() {
            return self.eval_split(first, second);
        }
        self.eval_timed(first, second, t)
    }

    /// [`eval_at`](Self::eval_at) for an expression that reads the time: its own copy of the
    /// interpreter, whose slot reader falls back on `t` past both slices.
    #[cold]
    #[inline(never)]
    fn eval_timed<D: Scalar>(&self, first: &[D], second: &[D], t: D) -> D {
        self.run(|slot: usize| match first.get(slot) {
            Some(&value) => value,
            None => second.get(slot - first.len()).copied().unwrap_or(t),
        })
    }

    /// Runs the program with slot `s` read as `input(s)`, on a register file on the stack
    /// unless the expression nests unusually deep.
    #[inline(always)]
    fn run<D: Scalar>(&self, input: impl Fn(usize) -> D + Copy) -> D {
        let zero = D::from(0.0);
        match self.temps {
            0 => execute(&self.code, input, &mut []),
            1..=4 => execute(&self.code, input, &mut [zero; 4]),
            5..=32 => execute(&self.code, input, &mut [zero; 32]),
            _ => execute(&self.code, input, &mut vec![zero; self.temps]),
        }
    }

    /// The source the expression was parsed from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The distinct names the expression reads, in the order they first appear.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The distinct slots the expression reads, in increasing order: what it depends on.
    pub fn slots(&self) -> &[usize] {
        &self.slots
    }

    /// Whether the expression reads `slot`.
    pub fn reads(&self, slot: usize) -> bool {
        self.slots.binary_search(&slot).is_ok()
    }

    /// The number of instructions of the compiled program: the work of one evaluation.
    pub fn operations(&self) -> usize {
        self.code.len()
    }

    /// The value, if the expression reads no name (it was folded into a single constant).
    pub fn constant_value(&self) -> Option<f64> {
        match *self.code {
            [Instr::Const { k, .. }] => Some(k),
            _ => None,
        }
    }
}

/// Shows the source as written.
impl fmt::Display for Expression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.source)
    }
}

#[cfg(test)]
#[path = "program_tests.rs"]
mod tests;
