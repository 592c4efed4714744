//! A model's derivatives traced once into straight-line `f64` programs.
//!
//! zenosim differentiates `L` and `h` by evaluating them over dual numbers, a dozen times per
//! right-hand side. For a model whose `L` and `h` are cheap to inline (Rust code) that is fast;
//! for one that is interpreted (a model file) each evaluation pays the interpreter again.
//! [`Compiled::trace`] instead runs zenosim's own differentiation once over a traced number
//! ([`crate::trace`]), which records every `f64` operation the dual numbers perform, and keeps
//! what the outputs need as a program. Running it gives the same numbers, bit for bit, as the
//! differentiation it was traced from, up to the sign of a zero; see [`crate::trace`] for the
//! simplifications and why they cannot change a result otherwise.
//!
//! The equations of motion are traced whole ([`crate::motion`]): derivatives, `M`'s Cholesky
//! factorisation and the solves, so that a right-hand side is one program. Where `M` is
//! constant (a point mass in Cartesian coordinates) the factorisation folds to constants, and
//! the paper's ball in free flight costs no operation at all.

use crate::derivatives::{
    constraint_parts_of, energy_of, force_of, guard_along_of, mass_matrix_of, with_dimension,
    ConstraintParts, LagrangianTerms,
};
use crate::model::HybridLagrangian;
use crate::motion::{
    constrained_from, direction_from, free_from, held_from, ConstrainedMotion, Direction, Factor,
    FreeMotion, HeldAcceleration, HeldView, Outputs,
};
use crate::trace::{self, Bin, Checks, Node, Sym, Tape, Term, Un};
use nalgebra::{SMatrix, SVector};
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};

/// One instruction; its result goes to the next register.
///
/// `repr(u8)` puts the variant in a byte of its own, which the interpreter's `match` indexes
/// its jump table with (left to itself, the compiler hides it among the values of `Un`, and
/// every step pays for finding it there).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
enum Step {
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Un(Un, u32),
    Bin(Bin, u32, u32),
    MulAdd(u32, u32, u32),
    /// `sin` into this register and `cos` into the next (one libm call, as num-dual's `f64`
    /// code gets): the next step's result goes to the register after both.
    SinCos(u32),
}

/// A straight-line program of `f64` operations.
///
/// Registers: the inputs `q`, `q̇` and `t` (`2n + 1`), the constants, then one per step (two
/// per [`Step::SinCos`]).
#[derive(Clone, Debug)]
struct Program {
    inputs: usize,
    constants: Box<[f64]>,
    steps: Box<[Step]>,
    /// The registers the steps fill: one per step, two per [`Step::SinCos`].
    work: usize,
    outputs: Box<[u32]>,
    /// Registers that must be finite for the outputs to be the dual numbers' (the values that
    /// products with a structural zero dropped).
    finite: Box<[u32]>,
    /// Registers that must not be zero for the outputs to be the dual numbers' (possibly
    /// mis-signed zeros that a sign-sensitive operation takes).
    nonzero: Box<[u32]>,
    /// The registers a run needs: the inputs, the constants, the steps' (`work`), then the
    /// outputs gathered in order.
    registers: usize,
    /// The outputs, when all are constants (a program with no step: the free motion of a point
    /// mass under constant forces); a run then only checks the witnesses among the inputs
    /// (the constants' were checked when it was built).
    constant_outputs: Option<Box<[f64]>>,
    /// Whether a step reads the last input, `t` (an autonomous model's programs do not: a run
    /// then leaves its register alone).
    uses_time: bool,
    /// Tells programs apart (a clone keeps it: its constants are the same), so that a run finds
    /// its constants still in place when the thread's last run was of the same program.
    id: u64,
}

/// The registers of this thread's runs, and the [`Program::id`] of the program whose constants
/// they hold. A run writes every register before it reads it, so they are never cleared.
struct Registers {
    /// For programs of at most [`SMALL`] registers (those of every model but the largest).
    small: [f64; SMALL],
    /// For larger programs.
    large: Vec<f64>,
    constants_of: u64,
}

/// The size of [`Registers::small`]: indexed by a byte, it needs no bounds check.
const SMALL: usize = 256;

thread_local! {
    static REGISTERS: RefCell<Registers> = const {
        RefCell::new(Registers { small: [0.0; SMALL], large: Vec::new(), constants_of: 0 })
    };
}

/// Registers as a program addresses them.
trait Bank {
    fn get(&self, k: usize) -> f64;
    fn set(&mut self, k: usize, value: f64);
    /// Registers `from..from + values.len()` set to `values`, in one copy.
    fn fill(&mut self, from: usize, values: &[f64]);
}

/// Indexed by the low byte of the register number: the program's registers are fewer than
/// [`SMALL`], so that is the register number itself.
impl Bank for [f64; SMALL] {
    #[inline(always)]
    fn get(&self, k: usize) -> f64 {
        self[k as u8 as usize]
    }
    #[inline(always)]
    fn set(&mut self, k: usize, value: f64) {
        self[k as u8 as usize] = value;
    }
    #[inline(always)]
    fn fill(&mut self, from: usize, values: &[f64]) {
        self[from..from + values.len()].copy_from_slice(values);
    }
}

impl Bank for [f64] {
    #[inline(always)]
    fn get(&self, k: usize) -> f64 {
        self[k]
    }
    #[inline(always)]
    fn set(&mut self, k: usize, value: f64) {
        self[k] = value;
    }
    #[inline(always)]
    fn fill(&mut self, from: usize, values: &[f64]) {
        self[from..from + values.len()].copy_from_slice(values);
    }
}

/// Builds a program's steps from tape entries whose values are registers, possibly negated (a
/// register and whether its value is to be negated: how a negation on the tape reaches its
/// users).
///
/// A negated operand costs no step where IEEE 754 gives the same bits without it: a product
/// or quotient takes the bases and is itself negated when exactly one operand is; `a + (−b)`
/// is `a − b` and `a − (−b)` is `a + b` (subtraction is defined as adding the negation), and
/// `(−a) + b = b − a`, `(−a) − (−b) = b − a` (addition commutes); `fma(−a, −b, c)` is
/// `fma(a, b, c)`. Elsewhere (a function's argument, `(−a) − b`, whose folding could flip the
/// sign of a zero result) the negation is done once, by a [`Step::Neg`], and reused.
struct Emitter {
    steps: Vec<Step>,
    /// The registers filled so far (the next step's is `base + work`).
    work: usize,
    base: usize,
    /// Registers holding a negated register's value, by the register negated.
    negations: HashMap<u32, u32>,
    /// The steps appended so far, and their registers: a step appended again is reused (two
    /// entries of the tape can fold to the same step, as `(−a)·b` and `a·(−b)` do).
    done: HashMap<Step, u32>,
}

impl Emitter {
    fn new(base: usize) -> Self {
        Self {
            steps: Vec::new(),
            work: 0,
            base,
            negations: HashMap::new(),
            done: HashMap::new(),
        }
    }

    /// Appends `step` (unless it is there already); its register.
    fn step(&mut self, step: Step) -> u32 {
        if let Some(&here) = self.done.get(&step) {
            return here;
        }
        let here = (self.base + self.work) as u32;
        self.steps.push(step);
        self.work += if matches!(step, Step::SinCos(_)) {
            2
        } else {
            1
        };
        self.done.insert(step, here);
        here
    }

    /// A [`Step::SinCos`] of register `a`: the register of the sine (the cosine's is the next).
    fn sin_cos(&mut self, a: u32) -> u32 {
        self.step(Step::SinCos(a))
    }

    /// A register holding the value of `(register, negated)`, negating it (once) if need be.
    fn value(&mut self, (register, negated): (u32, bool)) -> u32 {
        if !negated {
            return register;
        }
        if let Some(&done) = self.negations.get(&register) {
            return done;
        }
        let done = self.step(Step::Neg(register));
        self.negations.insert(register, done);
        done
    }

    /// `a + b`, as a register and whether it is negated.
    fn add(&mut self, (ra, na): (u32, bool), (rb, nb): (u32, bool)) -> (u32, bool) {
        let step = match (na, nb) {
            (false, false) => Step::Add(ra, rb),
            (false, true) => Step::Sub(ra, rb),
            (true, false) => Step::Sub(rb, ra),
            (true, true) => Step::Sub(self.value((ra, true)), rb),
        };
        (self.step(step), false)
    }

    /// `a − b`, as a register and whether it is negated.
    fn sub(&mut self, (ra, na): (u32, bool), (rb, nb): (u32, bool)) -> (u32, bool) {
        let step = match (na, nb) {
            (false, false) => Step::Sub(ra, rb),
            (false, true) => Step::Add(ra, rb),
            (true, true) => Step::Sub(rb, ra),
            (true, false) => Step::Sub(self.value((ra, true)), rb),
        };
        (self.step(step), false)
    }

    /// `fma(a, b, c)`, as a register and whether it is negated.
    fn mul_add(
        &mut self,
        (ra, na): (u32, bool),
        (rb, nb): (u32, bool),
        c: (u32, bool),
    ) -> (u32, bool) {
        let (ra, rb) = if na == nb {
            (ra, rb)
        } else {
            (self.value((ra, na)), self.value((rb, nb)))
        };
        let rc = self.value(c);
        (self.step(Step::MulAdd(ra, rb, rc)), false)
    }
}

/// How a program does the negations on its tape.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Negations {
    /// Each by a step, where the tape has it.
    Each,
    /// Folded into the operations that take them, wherever [`Emitter`] can.
    Folded,
    /// Folded, except a negation whose value an output or a function takes: that one by a
    /// step, whose result what it feeds takes as well (folded instead, it would have to be
    /// done after each of them).
    UnlessWanted,
}

/// The numbers of a traced motion in the order of its [`Outputs`].
fn outputs_of<O: Outputs<Sym>>(motion: &O) -> Vec<Sym> {
    let mut out = Vec::new();
    motion.write(&mut out);
    out
}

/// The next [`Program::id`] (0 is no program).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

impl Program {
    /// Keeps the entries of `tape` that `outputs` depend on, in order, doing its negations as
    /// `negations` says (`None`: in the way that takes the fewest steps).
    fn from_tape(
        tape: &Tape,
        inputs: usize,
        outputs: &[Sym],
        negations: Option<Negations>,
    ) -> Program {
        let nodes = &tape.nodes;
        let mut live = vec![false; nodes.len()];
        for out in outputs {
            if let Term::Node(id) = out.term {
                live[id as usize] = true;
            }
        }
        let witnesses = |list: &[u32]| {
            let mut list = list.to_vec();
            list.sort_unstable();
            list.dedup();
            list
        };
        let (finite, nonzero) = (witnesses(&tape.witnesses), witnesses(&tape.nonzero));
        for &id in finite.iter().chain(&nonzero) {
            live[id as usize] = true;
        }
        for id in (0..nodes.len()).rev() {
            if !live[id] {
                continue;
            }
            match nodes[id] {
                Node::Input(_) | Node::Const(_) => {}
                Node::Un(_, a) => live[a as usize] = true,
                Node::Bin(_, a, b) => {
                    live[a as usize] = true;
                    live[b as usize] = true;
                }
                Node::MulAdd(a, b, c) => {
                    live[a as usize] = true;
                    live[b as usize] = true;
                    live[c as usize] = true;
                }
            }
        }

        // Registers: inputs by their number, then the live constants (and constant outputs),
        // then the live operations.
        let mut register = vec![u32::MAX; nodes.len()];
        let mut constants = Vec::new();
        for (id, node) in nodes.iter().enumerate() {
            match *node {
                Node::Input(k) => register[id] = k,
                Node::Const(bits) if live[id] => {
                    register[id] = (inputs + constants.len()) as u32;
                    constants.push(f64::from_bits(bits));
                }
                _ => {}
            }
        }
        let mut output_registers = vec![0u32; outputs.len()];
        for (k, out) in outputs.iter().enumerate() {
            if let Term::Const(c) = out.term {
                output_registers[k] = (inputs + constants.len()) as u32;
                constants.push(c);
            }
        }
        let base = inputs + constants.len();
        let live_partner = |id: usize, partner: Un, a: u32| {
            tape.id_of(Node::Un(partner, a))
                .filter(|&p| live[p as usize] && p as usize != id)
        };
        // The entries whose negation, if they are one, is wanted as a value (by an output, or
        // as the argument of a function), for [`Negations::UnlessWanted`].
        let mut wanted = vec![false; nodes.len()];
        for out in outputs {
            if let Term::Node(id) = out.term {
                wanted[id as usize] = true;
            }
        }
        for node in nodes.iter().zip(&live).filter(|(_, &l)| l).map(|(n, _)| n) {
            match *node {
                Node::Un(op, a) if op != Un::Neg => wanted[a as usize] = true,
                Node::Bin(Bin::Add | Bin::Sub | Bin::Mul | Bin::Div, ..) => {}
                Node::Bin(_, a, b) => {
                    wanted[a as usize] = true;
                    wanted[b as usize] = true;
                }
                _ => {}
            }
        }
        // The steps, with each way of doing the negations: the shortest program is kept.
        let emit_with = |negations: Negations| {
            let mut register = register.clone();
            let mut output_registers = output_registers.clone();
            let eager = |id: usize| match negations {
                Negations::Each => true,
                Negations::Folded => false,
                Negations::UnlessWanted => wanted[id],
            };
            let mut negated = vec![false; nodes.len()];
            let mut emit = Emitter::new(base);
            for (id, node) in nodes.iter().enumerate() {
                if !live[id] || register[id] != u32::MAX {
                    continue;
                }
                let x = |e: u32| (register[e as usize], negated[e as usize]);
                let (here, negative) = match *node {
                    Node::Input(_) | Node::Const(_) => continue,
                    Node::Un(Un::Neg, a) if eager(id) => {
                        let (ra, na) = x(a);
                        (emit.value((ra, !na)), false)
                    }
                    Node::Un(Un::Neg, a) => {
                        let (ra, na) = x(a);
                        (ra, !na)
                    }
                    Node::Un(op @ (Un::Sin | Un::Cos), a) => {
                        let partner = if op == Un::Sin { Un::Cos } else { Un::Sin };
                        let ra = emit.value(x(a));
                        match live_partner(id, partner, a) {
                            Some(p) => {
                                let (sin, cos) = if op == Un::Sin {
                                    (id, p as usize)
                                } else {
                                    (p as usize, id)
                                };
                                let here = emit.sin_cos(ra);
                                register[sin] = here;
                                register[cos] = here + 1;
                                continue;
                            }
                            None => (emit.step(Step::Un(op, ra)), false),
                        }
                    }
                    Node::Un(op, a) => {
                        let ra = emit.value(x(a));
                        (emit.step(Step::Un(op, ra)), false)
                    }
                    Node::Bin(Bin::Add, a, b) => emit.add(x(a), x(b)),
                    Node::Bin(Bin::Sub, a, b) => emit.sub(x(a), x(b)),
                    // The sign of a product or quotient is that of its operands' product, exactly
                    // (zeros and infinities included).
                    Node::Bin(Bin::Mul, a, b) => {
                        let ((ra, na), (rb, nb)) = (x(a), x(b));
                        (emit.step(Step::Mul(ra, rb)), na != nb)
                    }
                    Node::Bin(Bin::Div, a, b) => {
                        let ((ra, na), (rb, nb)) = (x(a), x(b));
                        (emit.step(Step::Div(ra, rb)), na != nb)
                    }
                    Node::Bin(op, a, b) => {
                        let (ra, rb) = (emit.value(x(a)), emit.value(x(b)));
                        (emit.step(Step::Bin(op, ra, rb)), false)
                    }
                    Node::MulAdd(a, b, c) => emit.mul_add(x(a), x(b), x(c)),
                };
                register[id] = here;
                negated[id] = negative;
            }
            for (k, out) in outputs.iter().enumerate() {
                if let Term::Node(id) = out.term {
                    output_registers[k] = emit.value((register[id as usize], negated[id as usize]));
                }
            }
            (emit, register, output_registers)
        };
        let (emit, register, output_registers) = match negations {
            Some(only) => emit_with(only),
            None => [Negations::Folded, Negations::UnlessWanted, Negations::Each]
                .into_iter()
                .map(emit_with)
                .min_by_key(|(emit, ..)| emit.work)
                .expect("three ways"),
        };
        let Emitter { steps, work, .. } = emit;
        let registers = |ids: &[u32]| -> Box<[u32]> {
            let mut list: Vec<u32> = ids.iter().map(|&id| register[id as usize]).collect();
            list.sort_unstable();
            list.dedup();
            list.into()
        };
        let (mut finite, mut nonzero) = (registers(&finite), registers(&nonzero));
        // Without steps, every witness is an input or a constant: the constants' are checked
        // here once (a program whose constant witness fails always runs, and always fails), and
        // a run checks the inputs' only.
        let constant_outputs = output_registers
            .iter()
            .map(|&r| {
                let k = (r as usize).checked_sub(inputs)?;
                constants.get(k).copied()
            })
            .collect::<Option<Box<[f64]>>>()
            .filter(|_| steps.is_empty())
            .filter(|_| {
                let constant = |w: &u32| constants.get((*w as usize).wrapping_sub(inputs));
                finite.iter().filter_map(constant).all(|c| c.is_finite())
                    && nonzero.iter().filter_map(constant).all(|&c| c != 0.0)
            });
        if constant_outputs.is_some() {
            let input = |list: &[u32]| {
                list.iter()
                    .copied()
                    .filter(|&w| (w as usize) < inputs)
                    .collect()
            };
            finite = input(&finite);
            nonzero = input(&nonzero);
        }
        Program {
            inputs,
            registers: inputs + constants.len() + work + output_registers.len(),
            work,
            constant_outputs,
            uses_time: nodes
                .iter()
                .enumerate()
                .any(|(id, node)| live[id] && *node == Node::Input(inputs as u32 - 1)),
            constants: constants.into(),
            steps: steps.into(),
            outputs: output_registers.into(),
            finite,
            nonzero,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// Runs the program and reads its outputs as an `O`.
    fn run_outputs<O: crate::motion::Outputs<f64>>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<O> {
        self.run(t, q, q_dot, O::read)
    }

    /// Runs the program on `(q, q̇)` and hands its outputs, in order, to `read`; `None` when a
    /// witness says the dual numbers would not give these outputs here (the caller uses them
    /// instead).
    ///
    /// Only this wrapper is generic: the interpreter ([`Program::execute`]) is compiled once,
    /// not once per kind of output and dimension. Inlined: a call of its own costs a tenth of
    /// a right-hand side's interpretation.
    #[inline(always)]
    fn run<R>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        read: impl FnOnce(&[f64]) -> R,
    ) -> Option<R> {
        if let Some(outputs) = &self.constant_outputs {
            return self
                .constant_witnesses_hold(t, q, q_dot)
                .then(|| read(outputs));
        }
        // `read` only converts numbers (it runs no program), so the registers are free here.
        REGISTERS.with(|cell| self.execute(&mut cell.borrow_mut(), t, q, q_dot).map(read))
    }

    /// The witnesses of a program without steps: inputs only (its constants' were checked
    /// when it was built).
    fn constant_witnesses_hold(&self, t: f64, q: &[f64], q_dot: &[f64]) -> bool {
        let n = q.len();
        let input = |w: u32| match w as usize {
            w if w < n => q[w],
            w if w < 2 * n => q_dot[w - n],
            _ => t,
        };
        self.finite.iter().all(|&w| input(w).is_finite())
            && self.nonzero.iter().all(|&w| input(w) != 0.0)
    }

    /// Runs the program in `registers`: its outputs, in order, or `None` when a witness fails.
    fn execute<'r>(
        &self,
        registers: &'r mut Registers,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<&'r [f64]> {
        assert!(
            q.len() == q_dot.len() && q.len() + q_dot.len() + 1 == self.inputs,
            "a program of {} inputs run on {} + {} numbers and t",
            self.inputs,
            q.len(),
            q_dot.len()
        );
        // The constants stay in place while the thread runs the same program.
        let fill = registers.constants_of != self.id;
        registers.constants_of = self.id;
        let tail = self.inputs + self.constants.len() + self.work;
        let outputs = tail..tail + self.outputs.len();
        if self.registers <= SMALL {
            let regs = &mut registers.small;
            self.execute_in(regs, fill, t, q, q_dot)
                .then(|| &regs[outputs])
        } else {
            let regs = &mut registers.large;
            if regs.len() < self.registers {
                regs.resize(self.registers, 0.0);
            }
            let regs = &mut regs[..self.registers];
            self.execute_in(regs, fill, t, q, q_dot)
                .then(|| &regs[outputs])
        }
    }

    /// Runs the program in `regs` (its constants in place unless `fill`), and gathers its
    /// outputs after its steps; `false` when a witness fails.
    #[inline(always)]
    fn execute_in<B: Bank + ?Sized>(
        &self,
        regs: &mut B,
        fill: bool,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> bool {
        let n = q.len();
        for (k, (&x, &v)) in q.iter().zip(q_dot).enumerate() {
            regs.set(k, x);
            regs.set(n + k, v);
        }
        if self.uses_time {
            regs.set(2 * n, t);
        }
        if fill {
            regs.fill(self.inputs, &self.constants);
        }
        // Each step's result goes to the next register (two for a `SinCos`).
        let mut here = self.inputs + self.constants.len();
        for step in &self.steps {
            let x = |k: u32| regs.get(k as usize);
            let value = match *step {
                Step::Add(a, b) => x(a) + x(b),
                Step::Sub(a, b) => x(a) - x(b),
                Step::Mul(a, b) => x(a) * x(b),
                Step::Div(a, b) => x(a) / x(b),
                Step::Neg(a) => -x(a),
                Step::Un(op, a) => op.apply(x(a)),
                Step::Bin(op, a, b) => op.apply(x(a), x(b)),
                Step::MulAdd(a, b, c) => x(a).mul_add(x(b), x(c)),
                Step::SinCos(a) => {
                    let (sin, cos) = x(a).sin_cos();
                    regs.set(here, sin);
                    here += 1;
                    cos
                }
            };
            regs.set(here, value);
            here += 1;
        }
        // Without a branch per witness: `x · 0` is ±0 for a finite `x` and NaN otherwise, and a
        // NaN stays in the sum.
        let finite = self.finite.iter().fold(0.0, |sum, &w| {
            let x = regs.get(w as usize);
            sum + x * 0.0
        }) == 0.0;
        let nonzero = self.nonzero.iter().all(|&w| regs.get(w as usize) != 0.0);
        if !(finite && nonzero) {
            return false;
        }
        for &r in self.outputs.iter() {
            let value = regs.get(r as usize);
            regs.set(here, value);
            here += 1;
        }
        true
    }
}

/// A model's derivatives, traced once ([`Compiled::trace`]) into straight-line `f64` programs
/// that zenosim runs instead of differentiating the model at every step.
///
/// A model returns it from [`HybridLagrangian::compiled`]. It pays off for a model whose
/// functions are expensive to evaluate over dual numbers (an interpreted formula, as in a model
/// file); a Rust model is usually as fast without, because the compiler already folds its dual
/// numbers. The results are the same, bit for bit (up to the sign of a zero): where a value the
/// programs simplified away is not finite, zenosim differentiates instead.
///
/// The parts (the Euler–Lagrange terms, each constraint's derivatives, each guard, the energy,
/// and where `M` is constant the free motion, the motion held on each constraint and each
/// constraint's direction) are traced in one recording, each once, and each becomes a program
/// of its own. A part whose code branches on a value (`abs`, `min`, `max`, a comparison)
/// cannot be traced; zenosim then differentiates that part as usual.
#[derive(Clone, Debug)]
pub struct Compiled {
    dimension: usize,
    /// The upper triangle of `M` by rows, then the force.
    terms: Option<Program>,
    /// Per constraint: `h`, `A`, `A q̇`, `∇²h q̇`.
    constraints: Vec<Option<Program>>,
    /// Per constraint: `h`, `ḣ`, `ḧ` along free flight.
    guards: Vec<Option<Program>>,
    energy: Option<Program>,
    /// The free motion.
    free: Option<Program>,
    /// Per constraint: the motion held on it.
    held: Vec<Option<Program>>,
    /// Per constraint: the acceleration held on it (what a right-hand side needs of `held`).
    held_acc: Vec<Option<Program>>,
    /// Per constraint: its direction.
    directions: Vec<Option<Program>>,
    /// Whether the traced `M` is constant: the motion is then traced whole too.
    constant_mass: bool,
    /// Whether the trace needed more operations than its budget allowed (and has no programs).
    exhausted: bool,
    /// The operations the trace recorded (see [`Compiled::operations_traced`]).
    traced: u64,
}

impl Compiled {
    /// Traces `model`'s derivatives. A model of dimension 0 or above
    /// [`MAX_DIMENSION`](crate::MAX_DIMENSION), or not the [`HybridLagrangian::DIMENSION`] its
    /// type declares, gets no programs (the simulation refuses it anyway).
    pub fn trace<L: HybridLagrangian>(model: &L) -> Compiled {
        Self::trace_bounded(model, u64::MAX)
    }

    /// [`Compiled::trace`], tracing at most `max_operations` operations: past that the trace
    /// stops, and [`Compiled::exhausted`] says so. An operation folded or found again on the
    /// trace counts 1, one that records a new entry 8 (its place in a large table is a cache
    /// miss), and so does each entry of each program made from the
    /// trace (where `M` is constant every constraint's programs hold the whole force), so that
    /// the time and memory of the whole are bounded. A model file's loading bounds its cost so
    /// (`Limits::max_operations` in zenosim-model).
    ///
    /// The operations a model needs grow linearly with the size of its formulas: one trace of
    /// `M` (`n(n+1)/2` evaluations of `L` over hyper-dual numbers), the force (`2n`
    /// evaluations), the energy (one), and each constraint's derivatives (`n + 1` evaluations
    /// of `h`), each a few operations per operation of the formula.
    pub fn trace_bounded<L: HybridLagrangian>(model: &L, max_operations: u64) -> Compiled {
        let n = model.dimension();
        let count = model.constraints().len();
        if crate::derivatives::checked_dimension(model).is_err() {
            return Compiled::untraced(n, count);
        }
        with_dimension!(L; n, N => Self::trace_within::<N, L>(model, max_operations))
    }

    /// [`Compiled::trace`] for a model of dimension `N` (the tests trace one `N` only).
    #[cfg(test)]
    pub(crate) fn trace_n<const N: usize, L: HybridLagrangian>(model: &L) -> Compiled {
        Self::trace_within::<N, L>(model, u64::MAX)
    }

    /// [`Compiled::trace_bounded`] for a model of dimension `N`.
    ///
    /// One recording for every part: `M` and the force are traced once, and each part that
    /// needs them (the free motion, the motion held on each constraint) takes their traced
    /// numbers rather than tracing the Lagrangian again, so that the cost of tracing is that
    /// of `M`, the force, the energy and each constraint's derivatives, each once. Each part's
    /// program keeps what its outputs need of the one tape.
    fn trace_within<const N: usize, L: HybridLagrangian>(model: &L, budget: u64) -> Compiled {
        let count = model.constraints().len();
        // The inputs: q, q̇, then t.
        let inputs = 2 * N + 1;
        let Some(recording) = trace::Recording::start(inputs, budget) else {
            return Compiled::untraced(N, count);
        };
        let x = recording.inputs();
        let (t, q, q_dot) = (x[2 * N], &x[..N], &x[N..2 * N]);
        let (mass, mass_checks) =
            recording.part(|| mass_matrix_of::<Sym, N, L>(model, t, q, q_dot));
        let (force, force_checks) = recording.part(|| force_of::<Sym, N, L>(model, t, q, q_dot));
        let terms = LagrangianTerms { mass, force };
        let terms_checks = mass_checks.and(&force_checks);
        let energy = recording.part(|| vec![energy_of::<Sym, L>(model, t, q, q_dot)]);
        let parts: Vec<_> = (0..count)
            .map(|index| {
                recording.part(|| constraint_parts_of::<Sym, N, L>(model, index, t, q, q_dot))
            })
            .collect();
        let guards: Vec<_> = (0..count)
            .map(|index| {
                recording.part(|| {
                    let (h, h_dot, h_ddot) = guard_along_of::<Sym, L>(model, index, t, q, q_dot);
                    vec![h, h_dot, h_ddot]
                })
            })
            .collect();
        let entries = N * (N + 1) / 2;
        let mut terms_out = Vec::with_capacity(entries + N);
        for i in 0..N {
            for j in i..N {
                terms_out.push(terms.mass[(i, j)]);
            }
        }
        terms_out.extend(terms.force.iter().copied());
        let constant_mass =
            terms_checks.usable && terms_out[..entries].iter().all(|m| m.constant().is_some());

        // The motion whole, where `M` is constant: its factorisation folds away, and each
        // right-hand side is one program (where `M` varies, the motion is assembled from the
        // parts at run time, and these programs would go unused).
        let whole = |outputs: &dyn Fn() -> Vec<Sym>, needs: &Checks| {
            let (outputs, own) = recording.part(outputs);
            (outputs, own.and(needs))
        };
        let mut free = None;
        let mut held = Vec::new();
        let mut held_acc = Vec::new();
        let mut directions = Vec::new();
        if constant_mass {
            free = Some(whole(&|| outputs_of(&free_from(&terms)), &terms_checks));
            for (p, p_checks) in &parts {
                // The acceleration held on the constraint is read from the motion held on it,
                // traced once for both.
                let (motion, own) = recording.part(|| constrained_from(&terms, p, q_dot));
                let held_checks = own.and(&terms_checks.and(p_checks));
                held.push((outputs_of(&motion), held_checks.clone()));
                held_acc.push(whole(&|| outputs_of(&held_from(&motion)), &held_checks));
                directions.push(whole(
                    &|| outputs_of(&direction_from(p, &Factor::new(&terms.mass)).0),
                    &mass_checks.and(p_checks),
                ));
            }
        }
        let mut exhausted = recording.exhausted();
        let mut traced = recording.work();
        let budget = recording.budget();
        let tape = recording.finish();
        let mut scratch = Vec::new();
        // Making the programs counts against the budget too, each entry of each program as a
        // new entry of the trace: where `M` is constant every constraint's programs hold the
        // whole force, so they can add up to far more than the trace itself.
        let mut program = |(outputs, checks): &(Vec<Sym>, Checks)| {
            if exhausted || !checks.usable {
                return None;
            }
            let (part, outputs) = tape.extract(outputs, checks, &mut scratch);
            traced = traced.saturating_add(trace::NEW_ENTRY * part.nodes.len() as u64);
            if traced > budget {
                exhausted = true;
                return None;
            }
            Some(Program::from_tape(&part, inputs, &outputs, None))
        };
        let constraint_outputs = |c: &ConstraintParts<N, Sym>| {
            let mut out = vec![c.h];
            out.extend(c.gradient.iter().copied());
            out.push(c.a_q_dot);
            out.extend(c.hessian_q_dot.iter().copied());
            out.push(c.h_t);
            out.push(c.time_drift);
            out
        };
        let terms = program(&(terms_out, terms_checks));
        let energy = program(&energy);
        let constraints = parts
            .iter()
            .map(|(p, checks)| program(&(constraint_outputs(p), checks.clone())))
            .collect();
        let guards = guards.iter().map(&mut program).collect();
        let free = free.as_ref().and_then(&mut program);
        let mut programs = |list: &[(Vec<Sym>, Checks)]| -> Vec<Option<Program>> {
            if list.is_empty() {
                vec![None; count]
            } else {
                list.iter().map(&mut program).collect()
            }
        };
        let held = programs(&held);
        let held_acc = programs(&held_acc);
        let directions = programs(&directions);
        if exhausted {
            return Compiled {
                exhausted,
                traced,
                constant_mass,
                ..Compiled::untraced(N, count)
            };
        }
        Compiled {
            dimension: N,
            constant_mass,
            exhausted,
            traced,
            terms,
            constraints,
            guards,
            energy,
            free,
            held,
            held_acc,
            directions,
        }
    }

    /// A model with no programs.
    fn untraced(dimension: usize, count: usize) -> Compiled {
        Compiled {
            dimension,
            terms: None,
            constraints: vec![None; count],
            guards: vec![None; count],
            energy: None,
            free: None,
            held: vec![None; count],
            held_acc: vec![None; count],
            directions: vec![None; count],
            constant_mass: false,
            exhausted: false,
            traced: 0,
        }
    }

    /// Whether a trace with a budget ([`Compiled::trace_bounded`]) is running on this thread
    /// and has used it up: the rest of the trace is discarded, so a model whose functions are
    /// costly to evaluate (an interpreted formula) may skip them while this holds.
    pub fn trace_exhausted() -> bool {
        trace::exhausted()
    }

    /// Whether a trace is running on this thread: the numbers a model's functions see are then
    /// traced and have no values (asking for one makes that part untraceable). A function that
    /// adjusts num-dual's results by their values (a model file keeps the real parts of dual
    /// numbers equal to `f64` results) should leave num-dual's arithmetic alone while this holds.
    pub fn is_tracing() -> bool {
        trace::active()
    }

    /// Every part that applies, traced or not: the motion's whole programs apply only where
    /// `M` is constant.
    fn parts(&self) -> impl Iterator<Item = &Option<Program>> {
        let whole = if self.constant_mass {
            self.held.len()
        } else {
            0
        };
        [&self.terms, &self.energy]
            .into_iter()
            .chain(self.constant_mass.then_some(&self.free))
            .chain(&self.constraints)
            .chain(&self.guards)
            .chain(&self.held[..whole])
            .chain(&self.held_acc[..whole])
            .chain(&self.directions[..whole])
    }

    /// How many of the parts were traced, and how many apply: the Euler–Lagrange terms, the
    /// energy, and two per constraint (its derivatives and its guard); where `M` is constant,
    /// also the free motion and three per constraint (the motion held on it, the acceleration
    /// held on it and its direction).
    pub fn coverage(&self) -> (usize, usize) {
        let total = self.parts().count();
        (self.parts().filter(|p| p.is_some()).count(), total)
    }

    /// The number of `f64` operations of all programs together.
    pub fn operations(&self) -> usize {
        self.parts().flatten().map(|p| p.work).sum()
    }

    /// Whether the motion is traced whole: where the traced Euler–Lagrange terms give every
    /// entry of `M` as a constant, the motion's programs fold `M`'s factorisation away and are
    /// the cheaper way to the motion; otherwise its parts are (see [`crate::motion`]), and the
    /// motion is not traced whole.
    pub(crate) fn whole_motion(&self) -> bool {
        self.free.is_some()
    }

    /// The operations of the traced code (each operation on a traced number, those folded
    /// into constants or found already recorded included), new entries and program entries
    /// counted 8 times: what [`Compiled::trace_bounded`] bounds.
    pub fn operations_traced(&self) -> u64 {
        self.traced
    }

    /// Whether the trace stopped at its budget ([`Compiled::trace_bounded`]): the model's
    /// derivatives need more operations than it allows, and no part is traced.
    pub fn exhausted(&self) -> bool {
        self.exhausted
    }

    /// Whether the free motion is traced and the same at every state: a constant `M` and
    /// constant forces (a point mass under gravity), so that free flight is a parabola in time.
    pub fn constant_free_motion(&self) -> bool {
        self.free
            .as_ref()
            .is_some_and(|p| p.constant_outputs.is_some())
    }

    /// The number of operations of the free motion's program, if traced.
    #[cfg(test)]
    pub(crate) fn free_operations(&self) -> Option<usize> {
        self.free.as_ref().map(|p| p.work)
    }

    /// Whether some program needs more registers than a run keeps in its small bank (so that
    /// it runs in the large one).
    #[cfg(test)]
    pub(crate) fn uses_large_registers(&self) -> bool {
        self.parts().flatten().any(|p| p.registers > SMALL)
    }

    /// The program of dimension `N` in `slot`, if traced.
    fn program<'c, const N: usize>(
        &self,
        slot: Option<&'c Option<Program>>,
    ) -> Option<&'c Program> {
        slot?.as_ref().filter(|_| self.dimension == N)
    }

    /// The free motion at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn free_motion<const N: usize>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<FreeMotion<N>> {
        self.program::<N>(Some(&self.free))?
            .run_outputs(t, q, q_dot)
    }

    /// The motion held on constraint `index` at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn constrained_motion<const N: usize>(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<ConstrainedMotion<N>> {
        self.program::<N>(self.held.get(index))?
            .run_outputs(t, q, q_dot)
    }

    /// The acceleration held on constraint `index` at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn held_acceleration<const N: usize>(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<HeldAcceleration<N>> {
        self.program::<N>(self.held_acc.get(index))?
            .run_outputs(t, q, q_dot)
    }

    /// The acceleration held on constraint `index` at `(q, q̇)`, read in place by `read`, if
    /// traced for dimension `N` and not refused by a witness.
    #[inline(always)]
    pub(crate) fn held_view<const N: usize, R>(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
        read: impl FnOnce(HeldView<'_, N>) -> R,
    ) -> Option<R> {
        self.program::<N>(self.held_acc.get(index))?
            .run(t, q, q_dot, |flat| read(HeldView::new(flat)))
    }

    /// Constraint `index`'s direction at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn direction<const N: usize>(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<Direction<N>> {
        self.program::<N>(self.directions.get(index))?
            .run_outputs(t, q, q_dot)
    }

    /// `M` and the force at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn lagrangian_terms<const N: usize>(
        &self,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<LagrangianTerms<N>> {
        let program = self.terms.as_ref().filter(|_| self.dimension == N)?;
        program.run(t, q, q_dot, |out| {
            let mut mass = SMatrix::<f64, N, N>::zeros();
            let mut k = 0;
            for i in 0..N {
                for j in i..N {
                    mass[(i, j)] = out[k];
                    mass[(j, i)] = out[k];
                    k += 1;
                }
            }
            let force = SVector::<f64, N>::from_column_slice(&out[k..k + N]);
            LagrangianTerms { mass, force }
        })
    }

    /// Constraint `index`'s derivatives at `(q, q̇)`, if traced for dimension `N`.
    pub(crate) fn constraint_parts<const N: usize>(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<ConstraintParts<N, f64>> {
        let program = self
            .constraints
            .get(index)?
            .as_ref()
            .filter(|_| self.dimension == N)?;
        program.run(t, q, q_dot, |out| ConstraintParts {
            h: out[0],
            gradient: SVector::<f64, N>::from_column_slice(&out[1..N + 1]),
            a_q_dot: out[N + 1],
            hessian_q_dot: SVector::<f64, N>::from_column_slice(&out[N + 2..2 * N + 2]),
            h_t: out[2 * N + 2],
            time_drift: out[2 * N + 3],
        })
    }

    /// `h`, `ḣ`, `ḧ` of constraint `index` along free flight, if traced.
    pub(crate) fn guard_along(
        &self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Option<(f64, f64, f64)> {
        let program = self
            .guards
            .get(index)?
            .as_ref()
            .filter(|_| q.len() == self.dimension)?;
        program.run(t, q, q_dot, |out| (out[0], out[1], out[2]))
    }

    /// The energy at `(q, q̇)`, if traced.
    pub(crate) fn energy(&self, t: f64, q: &[f64], q_dot: &[f64]) -> Option<f64> {
        let program = self.energy.as_ref().filter(|_| q.len() == self.dimension)?;
        program.run(t, q, q_dot, |out| out[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every way a negation reaches an operation, as a function of `(x, y, z)` over any number:
    /// traced, it gives the folded program; over `f64`, the reference.
    fn negations<T: crate::Scalar>(x: T, y: T, z: T) -> Vec<T> {
        let (nx, ny, nz) = (-x, -y, -z);
        vec![
            nx * y,
            x * ny,
            nx * ny,
            nx / y,
            x / ny,
            nx / ny,
            nx + y,
            x + ny,
            nx + ny,
            nx - y,
            x - ny,
            nx - ny,
            nx.mul_add(y, z),
            x.mul_add(ny, z),
            nx.mul_add(ny, z),
            x.mul_add(y, nz),
            nx.mul_add(y, nz),
            nx.mul_add(ny, nz),
            nx.sin(),
            nx.sin() * nx.cos(),
            -(nx * y),
            -(-(nx * y)) + z,
            nx,
            -nx,
            (nx * y) * (nx * z),
            nx.powd(y),
        ]
    }

    #[test]
    fn folded_negations_give_the_same_bits() {
        // Inputs (x, y) as q, (z, unused) as q̇, and t unused.
        let (tape, outputs) = trace::trace(5, &|v| negations(v[0], v[1], v[2])).expect("traced");
        let with = |negations| Program::from_tape(&tape, 5, &outputs, negations);
        let ways = [Negations::Each, Negations::Folded, Negations::UnlessWanted];
        let specials = [
            0.0,
            -0.0,
            1.5,
            -2.25,
            3e-310,
            f64::INFINITY,
            -f64::INFINITY,
            f64::NAN,
        ];
        for program in ways.map(Some).into_iter().chain([None]).map(with) {
            for &x in &specials {
                for &y in &specials {
                    for &z in &specials {
                        let expected = negations(x, y, z);
                        let outputs = program
                            .run(0.0, &[x, y], &[z, 0.0], <[f64]>::to_vec)
                            .expect("no witnesses to fail");
                        for (k, (a, b)) in outputs.iter().zip(&expected).enumerate() {
                            assert!(
                                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                                "output {k} at ({x:e}, {y:e}, {z:e}): {a:e} against {b:e}"
                            );
                        }
                    }
                }
            }
        }
        // Folded, a negation is done once, and only where no operation can fold it: of `x`
        // (for `(−x) − y`, `(−x) + (−y)`, `fma(−x, y, ·)`, the functions of `−x`, the output
        // `−x`), of `y` (`fma(x, −y, z)`), of `z` (`fma(x, y, −z)`), and of `x y` and `x / y`
        // (the outputs `(−x) y = x (−y)` and `(−x) / y = x / (−y)`, each one step).
        let negations_done =
            |p: &Program| p.steps.iter().filter(|s| matches!(s, Step::Neg(_))).count();
        assert_eq!(negations_done(&with(Some(Negations::Folded))), 5);
        // The program kept is the shortest of the three, shorter than with each negation done.
        let work = ways.map(|w| with(Some(w)).work);
        let kept = with(None).work;
        assert_eq!(kept, *work.iter().min().unwrap());
        assert!(kept < work[0], "{work:?}");
    }
}

#[cfg(test)]
mod budget_tests {
    use super::*;
    use crate::models::{BallOnSine, PendulumChain};

    /// What a budget does: enough for the trace changes nothing; one operation less, and the
    /// trace keeps no program and says so.
    fn check<L: HybridLagrangian>(model: &L) {
        let full = Compiled::trace(model);
        assert!(!full.exhausted());
        let needed = full.operations_traced();
        let enough = Compiled::trace_bounded(model, needed);
        assert!(!enough.exhausted());
        assert_eq!(enough.coverage(), full.coverage());
        assert_eq!(enough.operations(), full.operations());
        let short = Compiled::trace_bounded(model, needed - 1);
        assert!(short.exhausted());
        assert_eq!(short.coverage(), (0, full.coverage().1));
        assert!(!Compiled::is_tracing() && !Compiled::trace_exhausted());
    }

    #[test]
    fn a_trace_past_its_budget_keeps_no_program() {
        // M varies (the parts only) and M constant (the motion whole, too).
        check(&PendulumChain::new(4, 0.5, 0.5, 9.81, 1.0, 0.5));
        check(&BallOnSine::paper().model);
    }
}
