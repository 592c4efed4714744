//! The instructions of a compiled expression and the loop that runs them.
//!
//! An accumulator machine: every instruction leaves its result in the accumulator `acc`, a local
//! that the compiler keeps in machine registers, so a result feeds the next instruction without
//! a round trip through memory. The other operand of an instruction is named by the instruction
//! itself: an input slot (read straight from the caller's slices), a constant (applied as an
//! `f64`: `x * c` scales a dual number instead of multiplying it by a lifted one), or a temporary,
//! where a value waits while `acc` computes another. The letters of a name say where the
//! operands are, left to right: `A` the accumulator, `R` an input, `K` a constant, `T` a
//! temporary (`SubKA`: `acc = k - acc`).

use zenosim::Scalar;

use super::ops::{self, Op};

/// One instruction; `a`, `b` are input slots, `t` a temporary, `k` a constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Instr {
    /// `acc = in[a]`.
    Load {
        a: usize,
    },
    /// `acc = temps[t]`.
    LoadT {
        t: usize,
    },
    /// `acc = k`.
    Const {
        k: f64,
    },
    /// `temps[t] = acc` (the accumulator keeps its value).
    Spill {
        t: usize,
    },
    /// `acc = op(acc)`, a one-operand function or the sign.
    Unary {
        op: Op,
    },
    /// `acc = op(in[a])`.
    UnaryR {
        op: Op,
        a: usize,
    },
    /// `acc = acc^n`, `n` a constant integer other than 2.
    PowI {
        n: i32,
    },
    /// `acc = acc^k`, `k` a constant non-integer.
    PowF {
        k: f64,
    },
    /// `acc = op(temps[t], acc)` for `Pow`, `Atan2`, `Min`, `Max`.
    BinaryTA {
        op: Op,
        t: usize,
    },
    /// `acc = op(in[a], acc)` for `Pow`, `Atan2`, `Min`, `Max`.
    BinaryRA {
        op: Op,
        a: usize,
    },
    AddRR {
        a: usize,
        b: usize,
    },
    /// `acc = acc + in[a]`, also for `in[a] + acc`: addition commutes bit for bit, part by part.
    AddAR {
        a: usize,
    },
    AddTA {
        t: usize,
    },
    /// `acc = acc + k`, also for `k + acc`.
    AddAK {
        k: f64,
    },
    /// `acc = in[a] + k`, also for `k + in[a]`.
    AddRK {
        a: usize,
        k: f64,
    },
    SubRR {
        a: usize,
        b: usize,
    },
    SubAR {
        a: usize,
    },
    SubRA {
        a: usize,
    },
    SubTA {
        t: usize,
    },
    SubAK {
        k: f64,
    },
    SubKA {
        k: f64,
    },
    SubRK {
        a: usize,
        k: f64,
    },
    SubKR {
        k: f64,
        a: usize,
    },
    MulRR {
        a: usize,
        b: usize,
    },
    MulAR {
        a: usize,
    },
    MulRA {
        a: usize,
    },
    MulTA {
        t: usize,
    },
    /// `acc = acc * k`, also for `k * acc`: a dual number scaled.
    MulAK {
        k: f64,
    },
    MulRK {
        a: usize,
        k: f64,
    },
    /// `acc = acc * acc`: `x^2`.
    MulAA,
    DivRR {
        a: usize,
        b: usize,
    },
    DivAR {
        a: usize,
    },
    DivRA {
        a: usize,
    },
    DivTA {
        t: usize,
    },
    DivAK {
        k: f64,
    },
    DivKA {
        k: f64,
    },
    DivRK {
        a: usize,
        k: f64,
    },
    DivKR {
        k: f64,
        a: usize,
    },
    /// `acc = in[a]*in[b] + acc`, also for `acc + in[a]*in[b]`.
    MulAddRR {
        a: usize,
        b: usize,
    },
    /// `acc = in[a]*in[b] - acc`.
    MulSubRR {
        a: usize,
        b: usize,
    },
    /// `acc = acc - in[a]*in[b]`.
    SubMulRR {
        a: usize,
        b: usize,
    },
    /// `acc = in[a]*k + acc`, also for `acc + in[a]*k`.
    MulAddRK {
        a: usize,
        k: f64,
    },
    /// `acc = in[a]*k - acc`.
    MulSubRK {
        a: usize,
        k: f64,
    },
    /// `acc = acc - in[a]*k`.
    SubMulRK {
        a: usize,
        k: f64,
    },
}

/// Runs `code` with input slot `s` read as `input(s)`, and `temps` for the temporaries; returns
/// the accumulator.
///
/// `input` is inlined into every instruction that reads a slot: the evaluations
/// ([`super::Expression::eval_split`], [`super::Expression::eval_at`]) each pass their own
/// reader, and each gets its own copy of the loop.
///
/// # Panics
///
/// If `input` panics on a slot the program reads, or `temps` is shorter than the program
/// needs (the builder sizes it).
// Every arm spells out `acc = …`, the same shape for all; `acc += x` would read the same.
#[allow(clippy::assign_op_pattern)]
#[inline(always)]
pub(crate) fn execute<D: Scalar>(code: &[Instr], input: impl Fn(usize) -> D, temps: &mut [D]) -> D {
    let mut acc = D::from(0.0);
    for instr in code {
        match *instr {
            Instr::Load { a } => acc = input(a),
            Instr::LoadT { t } => acc = temps[t],
            Instr::Const { k } => acc = D::from(k),
            Instr::Spill { t } => temps[t] = acc,
            Instr::Unary { op } => acc = op.unary(acc),
            Instr::UnaryR { op, a } => acc = op.unary(input(a)),
            Instr::PowI { n } => acc = ops::powi(acc, n),
            Instr::PowF { k } => acc = ops::powf(acc, k),
            Instr::BinaryTA { op, t } => acc = op.binary(temps[t], acc),
            Instr::BinaryRA { op, a } => acc = op.binary(input(a), acc),
            Instr::AddRR { a, b } => acc = input(a) + input(b),
            Instr::AddAR { a } => acc = acc + input(a),
            Instr::AddTA { t } => acc = temps[t] + acc,
            Instr::AddAK { k } => acc = acc + k,
            Instr::AddRK { a, k } => acc = input(a) + k,
            Instr::SubRR { a, b } => acc = input(a) - input(b),
            Instr::SubAR { a } => acc = acc - input(a),
            Instr::SubRA { a } => acc = input(a) - acc,
            Instr::SubTA { t } => acc = temps[t] - acc,
            Instr::SubAK { k } => acc = acc - k,
            Instr::SubKA { k } => acc = ops::sub_from(k, acc),
            Instr::SubRK { a, k } => acc = input(a) - k,
            Instr::SubKR { k, a } => acc = ops::sub_from(k, input(a)),
            Instr::MulRR { a, b } => acc = input(a) * input(b),
            Instr::MulAR { a } => acc = acc * input(a),
            Instr::MulRA { a } => acc = input(a) * acc,
            Instr::MulTA { t } => acc = temps[t] * acc,
            Instr::MulAK { k } => acc = acc * k,
            Instr::MulRK { a, k } => acc = input(a) * k,
            Instr::MulAA => acc = acc * acc,
            Instr::DivRR { a, b } => acc = ops::div(input(a), input(b)),
            Instr::DivAR { a } => acc = ops::div(acc, input(a)),
            Instr::DivRA { a } => acc = ops::div(input(a), acc),
            Instr::DivTA { t } => acc = ops::div(temps[t], acc),
            Instr::DivAK { k } => acc = acc / k,
            Instr::DivKA { k } => acc = ops::div_into(k, acc),
            Instr::DivRK { a, k } => acc = input(a) / k,
            Instr::DivKR { k, a } => acc = ops::div_into(k, input(a)),
            Instr::MulAddRR { a, b } => acc = input(a) * input(b) + acc,
            Instr::MulSubRR { a, b } => acc = input(a) * input(b) - acc,
            Instr::SubMulRR { a, b } => acc = acc - input(a) * input(b),
            Instr::MulAddRK { a, k } => acc = input(a) * k + acc,
            Instr::MulSubRK { a, k } => acc = input(a) * k - acc,
            Instr::SubMulRK { a, k } => acc = acc - input(a) * k,
        }
    }
    acc
}
