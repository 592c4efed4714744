//! The compiled form of an expression, a flat postfix program, and its evaluation.

use std::fmt;

use zenosim::Scalar;

use super::{ExprError, Limits, Scope};

/// One step of a postfix program; operands are popped from and results pushed on a stack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Instr {
    Const(f64),
    Load(usize),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// `x + vars[slot]`: an `Add` whose right operand is a name, fused to save a dispatch.
    AddVar(usize),
    SubVar(usize),
    MulVar(usize),
    DivVar(usize),
    /// `x + c`: an `Add` whose right operand is a constant.
    AddConst(f64),
    SubConst(f64),
    MulConst(f64),
    DivConst(f64),
    /// `x^2` as `x*x`, which is what `powi(2)` computes, without the call.
    Square,
    /// `x^n`, `n` a constant integer.
    PowI(i32),
    /// `x^c`, `c` a constant non-integer.
    PowF(f64),
    /// `x^y`, `y` not constant: `exp(y ln x)`, which needs `x > 0`.
    Pow,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Sqrt,
    Abs,
    Atan2,
    Min,
    Max,
}

impl Instr {
    /// How many operands it pops.
    fn arity(self) -> usize {
        match self {
            Instr::Const(_) | Instr::Load(_) => 0,
            Instr::Add
            | Instr::Sub
            | Instr::Mul
            | Instr::Div
            | Instr::Pow
            | Instr::Atan2
            | Instr::Min
            | Instr::Max => 2,
            _ => 1,
        }
    }

    /// The instruction a call of the language function `name` compiles to, with its arity
    /// (`pow` compiles like `^`, see [`Builder::power`]).
    pub(crate) fn function(name: &str) -> Option<(Instr, usize)> {
        let one = |instr| Some((instr, 1));
        match name {
            "sin" => one(Instr::Sin),
            "cos" => one(Instr::Cos),
            "tan" => one(Instr::Tan),
            "asin" => one(Instr::Asin),
            "acos" => one(Instr::Acos),
            "atan" => one(Instr::Atan),
            "sinh" => one(Instr::Sinh),
            "cosh" => one(Instr::Cosh),
            "tanh" => one(Instr::Tanh),
            "exp" => one(Instr::Exp),
            "ln" | "log" => one(Instr::Ln),
            "sqrt" => one(Instr::Sqrt),
            "abs" => one(Instr::Abs),
            "atan2" => Some((Instr::Atan2, 2)),
            "pow" => Some((Instr::Pow, 2)),
            "min" => Some((Instr::Min, 2)),
            "max" => Some((Instr::Max, 2)),
            _ => None,
        }
    }
}

/// Assembles a program, folding every operation whose operands are all constants.
///
/// In postfix, when the last `k` instructions are constants they are exactly the `k` operands
/// of an operation emitted now, so folding is a peephole on the program's tail.
#[derive(Default)]
pub(crate) struct Builder {
    code: Vec<Instr>,
}

impl Builder {
    /// Emits `instr`, folding it into a constant when its operands are constants.
    pub(crate) fn emit(&mut self, instr: Instr) {
        let arity = instr.arity();
        let tail = self.code.len().saturating_sub(arity);
        if arity > 0
            && self.code.len() >= arity
            && self.code[tail..]
                .iter()
                .all(|i| matches!(i, Instr::Const(_)))
        {
            self.code.push(instr);
            let value = run(&self.code[tail..], &[] as &[f64], &mut [0.0; 2]);
            self.code.truncate(tail);
            self.code.push(Instr::Const(value));
        } else {
            // Fuse a binary operation with a right operand that is a single name or constant.
            let fused = match (instr, self.code.last()) {
                (Instr::Add, Some(&Instr::Load(s))) => Some(Instr::AddVar(s)),
                (Instr::Sub, Some(&Instr::Load(s))) => Some(Instr::SubVar(s)),
                (Instr::Mul, Some(&Instr::Load(s))) => Some(Instr::MulVar(s)),
                (Instr::Div, Some(&Instr::Load(s))) => Some(Instr::DivVar(s)),
                (Instr::Add, Some(&Instr::Const(c))) => Some(Instr::AddConst(c)),
                (Instr::Sub, Some(&Instr::Const(c))) => Some(Instr::SubConst(c)),
                (Instr::Mul, Some(&Instr::Const(c))) => Some(Instr::MulConst(c)),
                (Instr::Div, Some(&Instr::Const(c))) => Some(Instr::DivConst(c)),
                _ => None,
            };
            if let Some(fused) = fused {
                self.code.pop();
                self.code.push(fused);
            } else {
                self.code.push(instr);
            }
        }
    }

    /// Emits the power of the last two values: specialised when the exponent is constant.
    pub(crate) fn power(&mut self) {
        match self.code.last() {
            Some(&Instr::Const(e)) => {
                self.code.pop();
                // Exact integers use powi: exact for a negative base, and cheap.
                let instr = if e == 2.0 {
                    Instr::Square
                } else if e.fract() == 0.0 && e.abs() <= f64::from(i32::MAX) {
                    Instr::PowI(e as i32)
                } else {
                    Instr::PowF(e)
                };
                // Folds when the base is constant too.
                self.emit(instr);
            }
            _ => self.emit(Instr::Pow),
        }
    }

    /// The finished program.
    pub(crate) fn finish(self, source: &str, names: Vec<String>) -> Expression {
        let (mut depth, mut max_stack) = (0usize, 0usize);
        let mut slots = Vec::new();
        for instr in &self.code {
            if let Instr::Load(slot)
            | Instr::AddVar(slot)
            | Instr::SubVar(slot)
            | Instr::MulVar(slot)
            | Instr::DivVar(slot) = instr
            {
                slots.push(*slot);
            }
            depth = depth + 1 - instr.arity();
            max_stack = max_stack.max(depth);
        }
        debug_assert_eq!(depth, 1, "a program leaves exactly one value");
        slots.sort_unstable();
        slots.dedup();
        Expression {
            source: source.to_string(),
            code: self.code.into_boxed_slice(),
            max_stack,
            names,
            slots,
        }
    }
}

/// A parsed expression, compiled for fast repeated evaluation.
///
/// Build it with [`Expression::parse`]; evaluate it with [`Expression::eval`] over `f64` or
/// any dual number.
#[derive(Clone, Debug, PartialEq)]
pub struct Expression {
    source: String,
    code: Box<[Instr]>,
    /// The deepest the evaluation stack gets.
    max_stack: usize,
    names: Vec<String>,
    slots: Vec<usize>,
}

impl Expression {
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
    /// It does not allocate unless the expression nests unusually deep (an evaluation stack of
    /// more than 32 values).
    ///
    /// # Panics
    ///
    /// If `vars` has no entry for one of the [slots](Self::slots) the expression reads.
    #[inline]
    pub fn eval<D: Scalar>(&self, vars: &[D]) -> D {
        let zero = D::from(0.0);
        if self.max_stack <= 8 {
            run(&self.code, vars, &mut [zero; 8])
        } else if self.max_stack <= 32 {
            run(&self.code, vars, &mut [zero; 32])
        } else {
            run(&self.code, vars, &mut vec![zero; self.max_stack])
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

    /// The value, if the expression reads no name (it was folded into a single constant).
    pub fn constant_value(&self) -> Option<f64> {
        match *self.code {
            [Instr::Const(value)] => Some(value),
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

/// Runs `code`, with room for the program's maximal stack depth in `stack`.
///
/// The top of the stack lives in `top`, out of memory: an operation's result feeds the next one
/// through a register instead of a store and a reload, which roughly halves the time per
/// instruction. `stack[..depth]` holds the values below it (`stack[0]` a dummy).
#[inline]
fn run<D: Scalar>(code: &[Instr], vars: &[D], stack: &mut [D]) -> D {
    let mut top = D::from(0.0);
    let mut depth = 0;
    macro_rules! push {
        ($value:expr) => {{
            stack[depth] = top;
            depth += 1;
            top = $value;
        }};
    }
    macro_rules! pop {
        () => {{
            depth -= 1;
            stack[depth]
        }};
    }
    for &instr in code {
        match instr {
            Instr::Const(c) => push!(D::from(c)),
            Instr::Load(slot) => push!(vars[slot]),
            Instr::Neg => top = -top,
            Instr::Add => top = pop!() + top,
            Instr::Sub => top = pop!() - top,
            Instr::Mul => top = pop!() * top,
            Instr::Div => top = pop!() / top,
            Instr::AddVar(slot) => top += vars[slot],
            Instr::SubVar(slot) => top -= vars[slot],
            Instr::MulVar(slot) => top *= vars[slot],
            Instr::DivVar(slot) => top /= vars[slot],
            Instr::AddConst(c) => top += c,
            Instr::SubConst(c) => top -= c,
            Instr::MulConst(c) => top *= c,
            Instr::DivConst(c) => top /= c,
            Instr::Square => top *= top,
            Instr::PowI(n) => top = top.powi(n),
            Instr::PowF(e) => top = top.powf(e),
            // Spelled out rather than `powd`, which is `powf` on f64 but `exp(y ln x)` on dual
            // numbers: f64 values must equal the real parts of dual ones.
            Instr::Pow => top = (pop!().ln() * top).exp(),
            Instr::Sin => top = top.sin(),
            Instr::Cos => top = top.cos(),
            Instr::Tan => top = top.tan(),
            Instr::Asin => top = top.asin(),
            Instr::Acos => top = top.acos(),
            Instr::Atan => top = top.atan(),
            Instr::Sinh => top = top.sinh(),
            Instr::Cosh => top = top.cosh(),
            Instr::Tanh => top = top.tanh(),
            Instr::Exp => top = top.exp(),
            Instr::Ln => top = top.ln(),
            Instr::Sqrt => top = top.sqrt(),
            Instr::Abs => top = top.abs(),
            Instr::Atan2 => top = pop!().atan2(top),
            Instr::Min => {
                let a = pop!();
                // Ties keep the first argument; a NaN on either side is propagated.
                if a.re() <= top.re() || a.re().is_nan() {
                    top = a;
                }
            }
            Instr::Max => {
                let a = pop!();
                if a.re() >= top.re() || a.re().is_nan() {
                    top = a;
                }
            }
        }
    }
    top
}

#[cfg(test)]
#[path = "program_tests.rs"]
mod tests;
