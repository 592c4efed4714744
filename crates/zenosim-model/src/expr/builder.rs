//! Assembles the accumulator program of an expression from the parser's postfix stream:
//! constant folding, constants as immediate operands, fusion, temporaries.
//!
//! The parser emits operands and operations in postfix order. The builder keeps the operands of
//! the operations still to come on a stack, and emits instructions as operations arrive:
//! - an operation whose operands are all constants is folded into a constant, computed by the
//!   same functions evaluation uses, over `f64`;
//! - a constant operand becomes an immediate of the instruction (`x*c`, `c-x`, `x^n`);
//! - a product of inputs (`x*y`, `x^2`, `c*x`) is not computed until it is used: a sum or a
//!   difference with the accumulator absorbs it (`acc + x*y` is one instruction);
//! - at most one operand is in the accumulator; before an instruction overwrites it while it is
//!   still needed, it is spilled to the temporary of its stack position.

use super::instr::Instr;
use super::ops::{self, Op};
use super::program::Expression;

/// A value on the builder's operand stack.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Operand {
    Const(f64),
    /// The input slot `a`.
    Input(usize),
    /// `in[a] * in[b]`, not computed yet.
    Product(usize, usize),
    /// `in[a] * k`, not computed yet.
    Scaled(usize, f64),
    /// In the accumulator.
    Acc,
    /// Spilled to the temporary of its stack position.
    Temp(usize),
}

/// Assembles a program; see the module documentation.
#[derive(Default)]
pub(crate) struct Builder {
    code: Vec<Instr>,
    stack: Vec<Operand>,
    /// The highest the operand stack got: a bound on the number of temporaries.
    max_stack: usize,
    /// The distinct slots read, in increasing order.
    slots: Vec<usize>,
}

impl Builder {
    /// Pushes a constant operand.
    pub(crate) fn constant(&mut self, value: f64) {
        self.push(Operand::Const(value));
    }

    /// Pushes the value of input slot `slot`.
    pub(crate) fn variable(&mut self, slot: usize) {
        if let Err(at) = self.slots.binary_search(&slot) {
            self.slots.insert(at, slot);
        }
        self.push(Operand::Input(slot));
    }

    fn push(&mut self, operand: Operand) {
        self.stack.push(operand);
        self.max_stack = self.max_stack.max(self.stack.len());
    }

    fn pop(&mut self) -> Operand {
        self.stack
            .pop()
            .expect("the parser emits an operation after its operands")
    }

    /// Emits `instr`, which overwrites the accumulator: an operand still on the stack that
    /// lives there is spilled first. (The operands `instr` consumes are already popped.)
    fn emit(&mut self, instr: Instr) {
        if let Some(t) = self.stack.iter().rposition(|&o| o == Operand::Acc) {
            self.code.push(Instr::Spill { t });
            self.stack[t] = Operand::Temp(t);
        }
        self.code.push(instr);
    }

    /// Brings `operand` into the accumulator.
    fn load_acc(&mut self, operand: Operand) {
        match operand {
            Operand::Acc => {}
            Operand::Const(k) => self.emit(Instr::Const { k }),
            Operand::Input(a) => self.emit(Instr::Load { a }),
            Operand::Product(a, b) => self.emit(Instr::MulRR { a, b }),
            Operand::Scaled(a, k) => self.emit(Instr::MulRK { a, k }),
            Operand::Temp(t) => self.emit(Instr::LoadT { t }),
        }
    }

    /// Applies `op` to the operands on top of the stack.
    pub(crate) fn apply(&mut self, op: Op) {
        if op.arity() == 1 {
            let x = self.pop();
            match x {
                Operand::Const(x) => self.constant(op.unary(x)),
                Operand::Input(a) => self.emit_acc(Instr::UnaryR { op, a }),
                x => {
                    self.load_acc(x);
                    self.emit_acc(Instr::Unary { op });
                }
            }
            return;
        }
        let r = self.pop();
        let l = self.pop();
        match (op, l, r) {
            (Op::Pow, l, Operand::Const(e)) => self.power(l, e),
            (_, Operand::Const(x), Operand::Const(y)) => self.constant(op.binary(x, y)),
            (Op::Mul, Operand::Input(a), Operand::Input(b)) => self.push(Operand::Product(a, b)),
            (Op::Mul, Operand::Input(a), Operand::Const(k))
            | (Op::Mul, Operand::Const(k), Operand::Input(a)) => {
                self.push(Operand::Scaled(a, k));
            }
            (Op::Add | Op::Sub | Op::Mul | Op::Div, l, r) => self.arithmetic(op, l, r),
            (op, l, r) => self.general(op, l, r),
        }
    }

    /// `op(l, r)` for `Pow` with a varying exponent, `Atan2`, `Min`, `Max`: the left operand
    /// named (an input or a temporary), the right one in the accumulator.
    fn general(&mut self, op: Op, l: Operand, r: Operand) {
        let position = self.stack.len();
        self.stack.extend([l, r]);
        if !matches!(l, Operand::Input(_) | Operand::Temp(_)) {
            // Computing `l` spills `r` if it is in the accumulator.
            self.load_acc(l);
            self.code.push(Instr::Spill { t: position });
            self.stack[position] = Operand::Temp(position);
        }
        let r = self.pop();
        self.load_acc(r);
        let instr = match self.pop() {
            Operand::Input(a) => Instr::BinaryRA { op, a },
            Operand::Temp(t) => Instr::BinaryTA { op, t },
            other => unreachable!("{other:?} was named above"),
        };
        self.emit_acc(instr);
    }

    /// Emits `instr` and pushes its result, the accumulator.
    fn emit_acc(&mut self, instr: Instr) {
        self.emit(instr);
        self.push(Operand::Acc);
    }

    /// `l^e` for a constant `e`: `l*l` for 2, `powi` for other integers, `powf` otherwise.
    fn power(&mut self, l: Operand, e: f64) {
        // Exact integers use powi: exact for a negative base, and cheap.
        let integer = e.fract() == 0.0 && e.abs() <= f64::from(i32::MAX);
        match l {
            Operand::Const(x) if e == 2.0 => self.constant(x * x),
            Operand::Const(x) if integer => self.constant(ops::powi(x, e as i32)),
            Operand::Const(x) => self.constant(ops::powf(x, e)),
            Operand::Input(a) if e == 2.0 => self.push(Operand::Product(a, a)),
            l => {
                self.load_acc(l);
                self.emit_acc(if e == 2.0 {
                    Instr::MulAA
                } else if integer {
                    Instr::PowI { n: e as i32 }
                } else {
                    Instr::PowF { k: e }
                });
            }
        }
    }

    /// `l op r` for the four arithmetic operations, not both constant.
    fn arithmetic(&mut self, op: Op, l: Operand, r: Operand) {
        use Operand::{Acc, Const, Input, Product, Scaled, Temp};
        let lazy = |o: Operand| matches!(o, Product(..) | Scaled(..));
        // A sum or difference of the accumulator and a lazy product: one fused instruction.
        if matches!(op, Op::Add | Op::Sub) && (l == Acc && lazy(r) || lazy(l) && r == Acc) {
            let acc_left = l == Acc;
            let instr = match (if acc_left { r } else { l }, op, acc_left) {
                (Product(a, b), Op::Add, _) => Instr::MulAddRR { a, b },
                (Product(a, b), _, true) => Instr::SubMulRR { a, b },
                (Product(a, b), _, false) => Instr::MulSubRR { a, b },
                (Scaled(a, k), Op::Add, _) => Instr::MulAddRK { a, k },
                (Scaled(a, k), _, true) => Instr::SubMulRK { a, k },
                (Scaled(a, k), _, false) => Instr::MulSubRK { a, k },
                _ => unreachable!("a lazy product"),
            };
            return self.emit_acc(instr);
        }
        // Otherwise lazy products are computed: the left one into the accumulator (it may
        // then absorb a lazy right one); a lazy right one with the left already in the
        // accumulator or a temporary is brought into the accumulator, spilling the left.
        if lazy(l) {
            let position = self.stack.len();
            // Computing `l` spills `r` if it is in the accumulator.
            self.stack.extend([l, r]);
            self.load_acc(l);
            self.stack[position] = Acc;
            let r = self.pop();
            let l = self.pop();
            return self.arithmetic(op, l, r);
        }
        // (A temporary above the accumulator cannot happen in postfix order, and is handled
        // the same way: the left operand is spilled if it is in the accumulator.)
        if lazy(r) || matches!(r, Temp(_)) {
            self.push(l);
            self.load_acc(r);
            let l = self.pop();
            return self.arithmetic(op, l, Acc);
        }
        let instr = match (op, l, r) {
            (Op::Add, Acc, Input(a)) | (Op::Add, Input(a), Acc) => Instr::AddAR { a },
            (Op::Add, Acc, Const(k)) | (Op::Add, Const(k), Acc) => Instr::AddAK { k },
            (Op::Add, Temp(t), Acc) => Instr::AddTA { t },
            (Op::Add, Input(a), Input(b)) => Instr::AddRR { a, b },
            (Op::Add, Input(a), Const(k)) | (Op::Add, Const(k), Input(a)) => Instr::AddRK { a, k },
            (Op::Sub, Acc, Input(a)) => Instr::SubAR { a },
            (Op::Sub, Input(a), Acc) => Instr::SubRA { a },
            (Op::Sub, Acc, Const(k)) => Instr::SubAK { k },
            (Op::Sub, Const(k), Acc) => Instr::SubKA { k },
            (Op::Sub, Temp(t), Acc) => Instr::SubTA { t },
            (Op::Sub, Input(a), Input(b)) => Instr::SubRR { a, b },
            (Op::Sub, Input(a), Const(k)) => Instr::SubRK { a, k },
            (Op::Sub, Const(k), Input(a)) => Instr::SubKR { k, a },
            (Op::Mul, Acc, Input(a)) => Instr::MulAR { a },
            (Op::Mul, Input(a), Acc) => Instr::MulRA { a },
            (Op::Mul, Acc, Const(k)) | (Op::Mul, Const(k), Acc) => Instr::MulAK { k },
            (Op::Mul, Temp(t), Acc) => Instr::MulTA { t },
            (Op::Div, Acc, Input(a)) => Instr::DivAR { a },
            (Op::Div, Input(a), Acc) => Instr::DivRA { a },
            (Op::Div, Acc, Const(k)) => Instr::DivAK { k },
            (Op::Div, Const(k), Acc) => Instr::DivKA { k },
            (Op::Div, Temp(t), Acc) => Instr::DivTA { t },
            (Op::Div, Input(a), Input(b)) => Instr::DivRR { a, b },
            (Op::Div, Input(a), Const(k)) => Instr::DivRK { a, k },
            (Op::Div, Const(k), Input(a)) => Instr::DivKR { k, a },
            (op, l, r) => unreachable!("{op:?} of {l:?} and {r:?} was normalised above"),
        };
        self.emit_acc(instr);
    }

    /// The finished program.
    pub(crate) fn finish(mut self, source: &str, names: Vec<String>) -> Expression {
        let result = self.pop();
        debug_assert!(self.stack.is_empty(), "a program leaves exactly one value");
        self.load_acc(result);
        let temps = self
            .code
            .iter()
            .filter_map(|instr| match *instr {
                Instr::Spill { t } => Some(t + 1),
                _ => None,
            })
            .max()
            .unwrap_or(0);
        debug_assert!(temps <= self.max_stack);
        Expression::new(source, self.code.into(), temps, names, self.slots)
    }
}
