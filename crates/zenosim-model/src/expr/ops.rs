//! The operations of the language and their meaning over any [`Scalar`], shared by constant
//! folding (over `f64`) and evaluation (over `f64` and dual numbers).
//!
//! Every function here computes the real part of a dual result exactly as the same function
//! computes an `f64`, bit for bit. num-dual does not always: it divides as `a · (1/b)`, takes
//! `tan` as `sin/cos` and `tanh` as `sinh/cosh`, and `x^n` as `x^(n−3)·x·x·x`, each of which can
//! round differently from the `f64` operation (27% of divisions do). Those operations therefore
//! move num-dual's real part onto the `f64` value, see [`with_real_part`].

use zenosim::{Compiled, Scalar};

/// An operation of the language, as the parser emits it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// `x^y` and `pow(x, y)`: specialised by the builder when `y` is constant.
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

impl Op {
    /// How many operands it takes.
    pub(crate) fn arity(self) -> usize {
        match self {
            Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Pow | Op::Atan2 | Op::Min | Op::Max => 2,
            _ => 1,
        }
    }

    /// The operation a call of the language function `name` compiles to, with its arity.
    pub(crate) fn function(name: &str) -> Option<(Op, usize)> {
        let op = match name {
            "sin" => Op::Sin,
            "cos" => Op::Cos,
            "tan" => Op::Tan,
            "asin" => Op::Asin,
            "acos" => Op::Acos,
            "atan" => Op::Atan,
            "sinh" => Op::Sinh,
            "cosh" => Op::Cosh,
            "tanh" => Op::Tanh,
            "exp" => Op::Exp,
            "ln" | "log" => Op::Ln,
            "sqrt" => Op::Sqrt,
            "abs" => Op::Abs,
            "atan2" => Op::Atan2,
            "pow" => Op::Pow,
            "min" => Op::Min,
            "max" => Op::Max,
            _ => return None,
        };
        Some((op, op.arity()))
    }

    /// A one-operand operation applied to `x`.
    #[inline(always)]
    pub(crate) fn unary<D: Scalar>(self, x: D) -> D {
        match self {
            Op::Neg => -x,
            Op::Sin => x.sin(),
            Op::Cos => x.cos(),
            Op::Tan => tan(x),
            Op::Asin => x.asin(),
            Op::Acos => x.acos(),
            Op::Atan => x.atan(),
            Op::Sinh => x.sinh(),
            Op::Cosh => x.cosh(),
            Op::Tanh => tanh(x),
            Op::Exp => x.exp(),
            Op::Ln => x.ln(),
            Op::Sqrt => x.sqrt(),
            Op::Abs => x.abs(),
            _ => unreachable!("{self:?} takes two operands"),
        }
    }

    /// A two-operand operation applied to `a` and `b`; `Pow` is the general `exp(b ln a)`.
    #[inline(always)]
    pub(crate) fn binary<D: Scalar>(self, a: D, b: D) -> D {
        match self {
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => div(a, b),
            Op::Pow => pow(a, b),
            Op::Atan2 => a.atan2(b),
            Op::Min => min(a, b),
            Op::Max => max(a, b),
            _ => unreachable!("{self:?} takes one operand"),
        }
    }
}

/// `y` with its real part set to `re()`, the derivative parts unchanged.
///
/// `re` is the `f64` value of the operation that gave `y` and differs from `y`'s real part by a
/// rounding at most, so their difference is exact (Sterbenz) and subtracting it lands exactly on
/// `re`. Should it not (`y` overflowed where `f64` did not), the derivative parts are moved onto
/// `re` through a zero real part; if `y`'s real part is not even finite (`tanh(±∞)`, whose
/// derivatives num-dual gets as NaN), the result is `re` with zero derivatives.
#[inline]
pub(crate) fn with_real_part<D: Scalar>(y: D, re: impl FnOnce() -> f64) -> D {
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    // Over f64 (no derivatives) `y` was computed as `re` was: nothing to move. While zenosim
    // traces the derivatives (`Compiled`), numbers have no values: num-dual's arithmetic is
    // recorded as it is, as for a model written in Rust.
    if D::NDERIV == 0 || Compiled::is_tracing() {
        return y;
    }
    let re = re();
    let current = y.re();
    if same(current, re) {
        return y;
    }
    if !current.is_finite() {
        return D::from(re);
    }
    let shifted = y - (current - re);
    if same(shifted.re(), re) {
        shifted
    } else {
        (y - current) + re
    }
}

/// `a / b`, with the real part `a.re / b.re`.
#[inline(always)]
pub(crate) fn div<D: Scalar>(a: D, b: D) -> D {
    with_real_part(a / b, || a.re() / b.re())
}

/// `c / x`: the reciprocal scaled, with the real part `c / x.re`.
#[inline(always)]
pub(crate) fn div_into<D: Scalar>(c: f64, x: D) -> D {
    if D::NDERIV == 0 {
        D::from(c) / x
    } else {
        with_real_part(x.recip() * c, || c / x.re())
    }
}

/// `c - x`, computed as `-x + c`, which IEEE 754 defines to be the same (zeros included).
#[inline(always)]
pub(crate) fn sub_from<D: Scalar>(c: f64, x: D) -> D {
    -x + c
}

/// `x^n`, `n` an integer: `powi`, exact for a negative `x`.
#[inline(always)]
pub(crate) fn powi<D: Scalar>(x: D, n: i32) -> D {
    // num-dual's `powi` multiplies n(n − 1) as an `i32` for the second derivative, which
    // overflows beyond this; `powf` of the same integer computes its factors as `f64`.
    const LARGEST: u32 = 46_340;
    match n {
        // num-dual's own real parts are f64's here: 1, x, x·x, (x·x)·x.
        0..=3 => x.powi(n),
        _ if D::NDERIV == 0 || n.unsigned_abs() <= LARGEST => {
            with_real_part(x.powi(n), || x.re().powi(n))
        }
        _ => with_real_part(x.powf(f64::from(n)), || x.re().powi(n)),
    }
}

/// `x^e`, `e` a constant that is not an integer: `powf`.
#[inline(always)]
pub(crate) fn powf<D: Scalar>(x: D, e: f64) -> D {
    with_real_part(x.powf(e), || x.re().powf(e))
}

/// `x^y` for a varying `y`: `exp(y ln x)`, over `f64` too (not `powf`), so that `f64` values are
/// the real parts of dual ones; it needs `x > 0`.
#[inline(always)]
pub(crate) fn pow<D: Scalar>(x: D, y: D) -> D {
    (x.ln() * y).exp()
}

#[inline(always)]
fn tan<D: Scalar>(x: D) -> D {
    with_real_part(x.tan(), || x.re().tan())
}

#[inline(always)]
fn tanh<D: Scalar>(x: D) -> D {
    with_real_part(x.tanh(), || x.re().tanh())
}

/// The smaller by real part, derivatives included; a tie keeps `a`, a NaN is propagated.
#[inline(always)]
pub(crate) fn min<D: Scalar>(a: D, b: D) -> D {
    if a.re() <= b.re() || a.re().is_nan() {
        a
    } else {
        b
    }
}

/// The larger by real part, derivatives included; a tie keeps `a`, a NaN is propagated.
#[inline(always)]
pub(crate) fn max<D: Scalar>(a: D, b: D) -> D {
    if a.re() >= b.re() || a.re().is_nan() {
        a
    } else {
        b
    }
}
