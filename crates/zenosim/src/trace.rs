//! A traced number: evaluating a function over it records the function's arithmetic, once, as
//! a list of `f64` operations (a tape), which [`crate::compiled`] turns into a program.
//!
//! [`Sym`] implements num-dual's `DualNum`, so num-dual's own dual numbers can be built over it:
//! `HyperDual<Sym>` records exactly the `f64` operations that `HyperDual<f64>` performs, in the
//! same order. Replaying the tape therefore gives the same numbers, bit for bit, as the automatic
//! differentiation it was traced from, with three kinds of simplification that cannot change a
//! finite result:
//! - constants are folded (the same `f64` operation, done once);
//! - `x + 0`, `x − 0`, `x · 1`, `x / 1`, `x · 0` are simplified (most parts of a seeded dual
//!   number are zero); only the sign of a zero result could tell, and for `x · 0` a non-finite
//!   `x`: such an `x` is kept as a *witness*, which the program checks to be finite;
//! - an operation already on the tape with the same operands is reused.
//!
//! A traced number has no value, so code that branches on one (`abs`, `min`, comparisons,
//! reading the real part) cannot be traced: such a question marks the tape *poisoned*, and the
//! trace is discarded (the caller falls back to evaluating the duals directly).

use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::fmt;
use std::hash::{BuildHasherDefault, Hasher};
use std::iter::{Product, Sum};
use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

use num_dual::{DualNum, DualStruct, Mappable};
use num_traits::{FromPrimitive, Inv, Num, One, Signed, Zero};

/// A one-operand `f64` operation of the tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Un {
    Neg,
    Recip,
    Sqrt,
    Cbrt,
    Exp,
    Exp2,
    ExpM1,
    Ln,
    Log2,
    Log10,
    Ln1p,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Asinh,
    Acosh,
    Atanh,
    Abs,
    Signum,
    Powi(i32),
    /// `powf` with a constant exponent (its bits).
    Powf(u64),
    /// `log` to a constant base (its bits).
    Log(u64),
}

impl Un {
    /// The operation on an `f64`: the very function num-dual calls for `f64`.
    #[inline(always)]
    pub(crate) fn apply(self, x: f64) -> f64 {
        match self {
            Un::Neg => -x,
            Un::Recip => x.recip(),
            Un::Sqrt => x.sqrt(),
            Un::Cbrt => x.cbrt(),
            Un::Exp => x.exp(),
            Un::Exp2 => x.exp2(),
            Un::ExpM1 => x.exp_m1(),
            Un::Ln => x.ln(),
            Un::Log2 => x.log2(),
            Un::Log10 => x.log10(),
            Un::Ln1p => x.ln_1p(),
            Un::Sin => x.sin(),
            Un::Cos => x.cos(),
            Un::Tan => x.tan(),
            Un::Asin => x.asin(),
            Un::Acos => x.acos(),
            Un::Atan => x.atan(),
            Un::Sinh => x.sinh(),
            Un::Cosh => x.cosh(),
            Un::Tanh => x.tanh(),
            Un::Asinh => x.asinh(),
            Un::Acosh => x.acosh(),
            Un::Atanh => x.atanh(),
            Un::Abs => x.abs(),
            Un::Signum => x.signum(),
            Un::Powi(n) => x.powi(n),
            Un::Powf(bits) => x.powf(f64::from_bits(bits)),
            Un::Log(bits) => x.log(f64::from_bits(bits)),
        }
    }
}

/// A two-operand `f64` operation of the tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Bin {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Atan2,
    Powf,
}

impl Bin {
    /// The operation on two `f64`s.
    #[inline(always)]
    pub(crate) fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Bin::Add => a + b,
            Bin::Sub => a - b,
            Bin::Mul => a * b,
            Bin::Div => a / b,
            Bin::Rem => a % b,
            Bin::Atan2 => a.atan2(b),
            Bin::Powf => a.powf(b),
        }
    }
}

/// An entry of the tape; operands are earlier entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Node {
    /// Input `k` of the traced function.
    Input(u32),
    /// A constant (its bits).
    Const(u64),
    Un(Un, u32),
    Bin(Bin, u32, u32),
    /// `a · b + c` fused (`f64::mul_add`).
    MulAdd(u32, u32, u32),
}

/// What recording a new entry counts against a trace's budget, in operations.
pub(crate) const NEW_ENTRY: u64 = 8;

/// The recording of one trace.
#[derive(Debug)]
pub(crate) struct Tape {
    pub(crate) nodes: Vec<Node>,
    seen: HashMap<Node, u32, BuildHasherDefault<NodeHasher>>,
    /// The entries a product with a structural zero dropped: `x · 0` is 0 only while `x` is
    /// finite, so a program must check them (and defer to the dual numbers if one is not).
    pub(crate) witnesses: Vec<u32>,
    /// The tainted entries (see [`Sym`]) that an operation sensitive to the sign of a zero
    /// takes: they must not be zero.
    pub(crate) nonzero: Vec<u32>,
    /// Set when the traced code asked a question a traced number cannot answer.
    pub(crate) poisoned: bool,
    /// The operations of the traced code so far, those folded or found already on the tape
    /// included: what the trace has cost.
    work: u64,
    /// The most operations the trace may record; past it the trace is [`exhausted`].
    budget: u64,
    /// The current part of a [`Recording`] (from 1), and per entry the last part that listed
    /// it among the `witnesses` and among `nonzero`: each part lists an entry once, however
    /// often its code asks (a hyper-dual pass drops the same products in every pass).
    part: u32,
    listed: Vec<[u32; 2]>,
}

/// What a program checks of an entry.
#[derive(Clone, Copy)]
enum Check {
    Finite = 0,
    Nonzero = 1,
}

impl Default for Tape {
    fn default() -> Self {
        Tape::with_budget(u64::MAX)
    }
}

impl Tape {
    fn with_budget(budget: u64) -> Tape {
        Tape {
            nodes: Vec::new(),
            seen: HashMap::default(),
            witnesses: Vec::new(),
            nonzero: Vec::new(),
            poisoned: false,
            work: 0,
            budget,
            part: 1,
            listed: Vec::new(),
        }
    }

    /// Lists entry `id` among those its part's program must check so.
    fn check(&mut self, id: u32, check: Check) {
        let i = id as usize;
        if self.listed.len() <= i {
            self.listed.resize(self.nodes.len().max(i + 1), [0, 0]);
        }
        if self.listed[i][check as usize] == self.part {
            return;
        }
        self.listed[i][check as usize] = self.part;
        match check {
            Check::Finite => self.witnesses.push(id),
            Check::Nonzero => self.nonzero.push(id),
        }
    }

    fn push(&mut self, node: Node) -> u32 {
        if let Some(&id) = self.seen.get(&node) {
            return id;
        }
        // A new entry costs about ten times an operation found again (its place in a large
        // table is a cache miss): it counts as NEW_ENTRY operations against the budget.
        self.work = self.work.saturating_add(NEW_ENTRY - 1);
        if self.work > self.budget {
            EXHAUSTED.with(|flag| flag.set(true));
            self.poisoned = true;
        }
        let id = u32::try_from(self.nodes.len()).unwrap_or(u32::MAX);
        if id == u32::MAX {
            // Four billion operations: no model is that big; refuse rather than wrap.
            self.poisoned = true;
            return 0;
        }
        self.nodes.push(node);
        self.seen.insert(node, id);
        id
    }

    /// The entry `node` is at, if it was recorded.
    pub(crate) fn id_of(&self, node: Node) -> Option<u32> {
        self.seen.get(&node).copied()
    }

    fn operand(&mut self, x: Sym) -> u32 {
        match x.term {
            Term::Const(c) => self.push(Node::Const(c.to_bits())),
            Term::Node(id) => id,
        }
    }

    /// The part of the tape that `outputs` and the entries `checks` names depend on, as a tape
    /// of its own (in the same order, renumbered), with `outputs` renumbered: what one program
    /// of a [`Recording`] is made of. `scratch` is [`u32::MAX`] for every entry, and is left so.
    pub(crate) fn extract(
        &self,
        outputs: &[Sym],
        checks: &Checks,
        scratch: &mut Vec<u32>,
    ) -> (Tape, Vec<Sym>) {
        scratch.resize(self.nodes.len(), u32::MAX);
        let mut live: Vec<u32> = Vec::new();
        let mut stack: Vec<u32> = outputs
            .iter()
            .filter_map(|out| match out.term {
                Term::Node(id) => Some(id),
                Term::Const(_) => None,
            })
            .chain(checks.finite.iter().copied())
            .chain(checks.nonzero.iter().copied())
            .collect();
        while let Some(id) = stack.pop() {
            if scratch[id as usize] != u32::MAX {
                continue;
            }
            scratch[id as usize] = 0;
            live.push(id);
            match self.nodes[id as usize] {
                Node::Input(_) | Node::Const(_) => {}
                Node::Un(_, a) => stack.push(a),
                Node::Bin(_, a, b) => stack.extend([a, b]),
                Node::MulAdd(a, b, c) => stack.extend([a, b, c]),
            }
        }
        live.sort_unstable();
        for (new, &id) in live.iter().enumerate() {
            scratch[id as usize] = new as u32;
        }
        let at = |id: u32| scratch[id as usize];
        let nodes: Vec<Node> = live
            .iter()
            .map(|&id| match self.nodes[id as usize] {
                node @ (Node::Input(_) | Node::Const(_)) => node,
                Node::Un(op, a) => Node::Un(op, at(a)),
                Node::Bin(op, a, b) => Node::Bin(op, at(a), at(b)),
                Node::MulAdd(a, b, c) => Node::MulAdd(at(a), at(b), at(c)),
            })
            .collect();
        let mut tape = Tape {
            nodes,
            ..Tape::default()
        };
        tape.seen.reserve(tape.nodes.len());
        for (new, &node) in tape.nodes.iter().enumerate() {
            tape.seen.insert(node, new as u32);
        }
        tape.witnesses = checks.finite.iter().map(|&id| at(id)).collect();
        tape.nonzero = checks.nonzero.iter().map(|&id| at(id)).collect();
        let outputs = outputs
            .iter()
            .map(|out| match out.term {
                Term::Node(id) => Sym::node(at(id), out.tainted),
                Term::Const(_) => *out,
            })
            .collect();
        for &id in &live {
            scratch[id as usize] = u32::MAX;
        }
        (tape, outputs)
    }
}

/// The hash of a tape's entries: a multiply and a rotation per field (the tape hashes every
/// operation a trace records, and `std`'s default hasher, built to resist chosen keys, cost a
/// quarter of a model file's loading). The keys are operations of the model's own formulas,
/// whose collisions could only slow its own loading, which the budget bounds.
#[derive(Clone, Copy, Default)]
pub(crate) struct NodeHasher(u64);

impl NodeHasher {
    #[inline]
    fn add(&mut self, x: u64) {
        // An odd constant with its bits spread (the fractional digits of the golden ratio).
        const K: u64 = 0x9e37_79b9_7f4a_7c15;
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(K);
    }
}

impl Hasher for NodeHasher {
    #[inline]
    fn finish(&self) -> u64 {
        // The table takes its bucket from the low bits and its tag from the high ones: fold
        // the well-mixed high half into both.
        self.0 ^ (self.0 >> 32)
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }
    #[inline]
    fn write_u8(&mut self, x: u8) {
        self.add(u64::from(x));
    }
    #[inline]
    fn write_u32(&mut self, x: u32) {
        self.add(u64::from(x));
    }
    #[inline]
    fn write_i32(&mut self, x: i32) {
        self.add(u64::from(x as u32));
    }
    #[inline]
    fn write_u64(&mut self, x: u64) {
        self.add(x);
    }
    #[inline]
    fn write_isize(&mut self, x: isize) {
        self.add(x as u64);
    }
    #[inline]
    fn write_usize(&mut self, x: usize) {
        self.add(x as u64);
    }
}

thread_local! {
    static TAPE: RefCell<Option<Tape>> = const { RefCell::new(None) };
    /// Set when the running trace needed more than its budget: every result since is
    /// unusable, and the rest of the trace only folds constants (it costs next to nothing).
    /// A flag of its own, not the tape's, because a model file asks it at every evaluation of
    /// a formula over dual numbers, traced or not ([`crate::Compiled::trace_exhausted`]): a
    /// plain read, where the tape takes a borrow.
    static EXHAUSTED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` on the current thread's tape; `None` when no trace is running.
fn with_tape<R>(f: impl FnOnce(&mut Tape) -> R) -> Option<R> {
    TAPE.with(|tape| tape.borrow_mut().as_mut().map(f))
}

/// Whether a trace is running on this thread.
pub(crate) fn active() -> bool {
    TAPE.with(|tape| tape.borrow().is_some())
}

/// Whether the running trace is past its budget.
#[inline]
pub(crate) fn exhausted() -> bool {
    EXHAUSTED.with(Cell::get)
}

/// Counts one operation of the traced code against the budget: `false` once past it (the
/// operation then gives NaN, and the trace is unusable).
fn tick() -> bool {
    with_tape(|tape| {
        tape.work += 1;
        if tape.work > tape.budget {
            EXHAUSTED.with(|flag| flag.set(true));
            tape.poisoned = true;
        }
        !exhausted()
    })
    .unwrap_or(true)
}

/// Marks the running trace as unusable.
fn poison() {
    with_tape(|tape| tape.poisoned = true);
}

/// Removes the tape when the trace ends, also when the traced code panics.
struct Session;

impl Drop for Session {
    fn drop(&mut self) {
        TAPE.with(|tape| tape.borrow_mut().take());
        EXHAUSTED.with(|flag| flag.set(false));
    }
}

/// Traces `f` over `inputs` traced inputs: the tape and `f`'s outputs, or `None` when the trace
/// is poisoned or another trace is already running on this thread.
#[cfg(test)]
pub(crate) fn trace(inputs: usize, f: &dyn Fn(&[Sym]) -> Vec<Sym>) -> Option<(Tape, Vec<Sym>)> {
    let recording = Recording::start(inputs, u64::MAX)?;
    let (outputs, checks) = recording.part(|| f(recording.inputs()));
    let tape = recording.finish();
    checks.usable.then_some((tape, outputs))
}

/// What a program made of a part of a [`Recording`] must check, and whether it can be made.
#[derive(Clone, Debug)]
pub(crate) struct Checks {
    /// Entries that must be finite (see [`Tape::witnesses`]).
    pub(crate) finite: Vec<u32>,
    /// Entries that must not be zero (see [`Tape::nonzero`]).
    pub(crate) nonzero: Vec<u32>,
    /// Whether the part's numbers are traced: neither poisoned nor past the budget.
    pub(crate) usable: bool,
}

impl Checks {
    /// The checks of a part computed from this one's numbers and `other`'s.
    pub(crate) fn and(&self, other: &Checks) -> Checks {
        let mut both = self.clone();
        both.finite.extend_from_slice(&other.finite);
        both.nonzero.extend_from_slice(&other.nonzero);
        both.usable &= other.usable;
        both
    }
}

/// One trace on the current thread's tape, shared by several parts: each is computed once, and
/// the parts computed from it (the motion from `M` and the force) take its numbers, not a trace
/// of their own. [`Recording::part`] tells what each part adds; [`Tape::extract`] makes its
/// program.
pub(crate) struct Recording {
    inputs: Vec<Sym>,
    _session: Session,
}

impl Recording {
    /// Starts a recording over `inputs` traced inputs that may record `budget` operations;
    /// `None` when a trace is already running on this thread.
    pub(crate) fn start(inputs: usize, budget: u64) -> Option<Recording> {
        if active() {
            return None;
        }
        TAPE.with(|tape| *tape.borrow_mut() = Some(Tape::with_budget(budget)));
        let session = Session;
        let inputs = (0..inputs)
            .map(|k| {
                let id = with_tape(|tape| tape.push(Node::Input(k as u32))).unwrap_or(0);
                Sym::node(id, false)
            })
            .collect();
        Some(Recording {
            inputs,
            _session: session,
        })
    }

    /// The traced inputs.
    pub(crate) fn inputs(&self) -> &[Sym] {
        &self.inputs
    }

    /// Computes one part: its result, and the checks and verdict of what it recorded (not
    /// those of the parts it took numbers from: see [`Checks::and`]).
    pub(crate) fn part<R>(&self, f: impl FnOnce() -> R) -> (R, Checks) {
        let (finite, nonzero) = with_tape(|tape| {
            tape.poisoned = false;
            tape.part += 1;
            (tape.witnesses.len(), tape.nonzero.len())
        })
        .unwrap_or((0, 0));
        let result = f();
        let checks = with_tape(|tape| Checks {
            finite: tape.witnesses[finite..].to_vec(),
            nonzero: tape.nonzero[nonzero..].to_vec(),
            usable: !tape.poisoned && !exhausted(),
        })
        .unwrap_or(Checks {
            finite: Vec::new(),
            nonzero: Vec::new(),
            usable: false,
        });
        (result, checks)
    }

    /// The operations traced so far (see [`Tape::work`]).
    pub(crate) fn work(&self) -> u64 {
        with_tape(|tape| tape.work).unwrap_or(0)
    }

    /// The budget it was started with.
    pub(crate) fn budget(&self) -> u64 {
        with_tape(|tape| tape.budget).unwrap_or(0)
    }

    /// Whether the recording needed more than its budget.
    pub(crate) fn exhausted(&self) -> bool {
        exhausted()
    }

    /// The tape, which ends the recording.
    pub(crate) fn finish(self) -> Tape {
        TAPE.with(|tape| tape.borrow_mut().take())
            .unwrap_or_default()
    }
}

// A model file tells the traced number from `f64` by its size (it has no derivative either):
// `over_budget` in zenosim-model, which asks the budget of every scalar but `f64`.
const _: () = assert!(size_of::<Sym>() != size_of::<f64>());

/// A traced number: a constant, or an entry of the running tape.
///
/// It is *tainted* when a simplification may have given it the other sign of zero than the dual
/// numbers would (`x + 0 → x` when `x` is `−0`, `x · 0 → +0` when `x < 0`). That cannot change
/// a sum or a product that is not zero, but it decides `atan2(±0, −1) = ±π` and `1/±0 = ±∞`:
/// a tainted operand of such an operation must not be zero when the program runs (a tainted
/// constant zero there makes the trace unusable).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sym {
    pub(crate) term: Term,
    tainted: bool,
}

/// What a [`Sym`] is.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Term {
    Const(f64),
    /// An entry of the tape.
    Node(u32),
}

impl Sym {
    fn konst(value: f64) -> Sym {
        Sym {
            term: Term::Const(value),
            tainted: false,
        }
    }

    fn node(id: u32, tainted: bool) -> Sym {
        Sym {
            term: Term::Node(id),
            tainted,
        }
    }

    fn taint(self, tainted: bool) -> Sym {
        Sym {
            tainted: self.tainted || tainted,
            ..self
        }
    }

    pub(crate) fn constant(self) -> Option<f64> {
        match self.term {
            Term::Const(c) => Some(c),
            Term::Node(_) => None,
        }
    }

    fn is(self, value: f64) -> bool {
        self.constant() == Some(value)
    }

    /// Whether an operation whose result depends on the sign of a zero operand may take this
    /// one: an untainted number may; a tainted entry may if it is not zero when the program
    /// runs (it becomes a witness the program checks); a tainted constant is zero: it may not.
    fn sign_known(self) -> bool {
        if !self.tainted {
            return true;
        }
        match self.term {
            Term::Const(_) => false,
            Term::Node(id) => {
                with_tape(|tape| tape.check(id, Check::Nonzero));
                true
            }
        }
    }

    /// A folded constant: tainted only if it is a zero from a tainted operand.
    fn folded(value: f64, tainted: bool) -> Sym {
        Sym::konst(value).taint(tainted && value == 0.0)
    }

    fn record(tainted: bool, node: impl FnOnce(&mut Tape) -> Node) -> Sym {
        with_tape(|tape| {
            let node = node(tape);
            Sym::node(tape.push(node), tainted)
        })
        .unwrap_or(Sym::konst(f64::NAN))
    }

    fn un(self, op: Un) -> Sym {
        if !tick() {
            return Sym::konst(f64::NAN);
        }
        let sign_decides = matches!(op, Un::Recip | Un::Signum)
            || matches!(op, Un::Powi(n) if n < 0)
            || matches!(op, Un::Powf(e) if f64::from_bits(e) < 0.0);
        if sign_decides && !self.sign_known() {
            return Sym::ask(Sym::konst(f64::NAN));
        }
        if let Term::Const(c) = self.term {
            return Sym::folded(op.apply(c), self.tainted);
        }
        if op == Un::Neg {
            let inner = with_tape(|tape| match self.term {
                Term::Node(id) => match tape.nodes.get(id as usize) {
                    Some(Node::Un(Un::Neg, x)) => Some(*x),
                    _ => None,
                },
                Term::Const(_) => None,
            })
            .flatten();
            if let Some(x) = inner {
                return Sym::node(x, self.tainted);
            }
        }
        Sym::record(self.tainted, |tape| Node::Un(op, tape.operand(self)))
    }

    fn bin(op: Bin, a: Sym, b: Sym) -> Sym {
        if !tick() {
            return Sym::konst(f64::NAN);
        }
        let signs_known = match op {
            Bin::Atan2 | Bin::Rem => a.sign_known() && b.sign_known(),
            Bin::Div | Bin::Powf => b.sign_known(),
            Bin::Add | Bin::Sub | Bin::Mul => true,
        };
        if !signs_known {
            return Sym::ask(Sym::konst(f64::NAN));
        }
        let tainted = a.tainted || b.tainted;
        if let (Term::Const(x), Term::Const(y)) = (a.term, b.term) {
            return Sym::folded(op.apply(x, y), tainted);
        }
        let zero = |x: Sym| x.is(0.0);
        // `x + 0 → x`, `x − 0 → x`, `0 − x → −x`: exact but for the sign of a zero result, so
        // the result is tainted, except where IEEE 754 makes it exact (`x + (−0)`, `x − (+0)`,
        // `(−0) − x`).
        let negative_zero = |x: Sym| {
            x.constant()
                .is_some_and(|c| c == 0.0 && c.is_sign_negative())
        };
        match op {
            Bin::Add if zero(a) => return b.taint(!negative_zero(a) || a.tainted),
            Bin::Add if zero(b) => return a.taint(!negative_zero(b) || b.tainted),
            Bin::Sub if zero(b) => return a.taint(negative_zero(b) || b.tainted),
            Bin::Sub if zero(a) => return b.un(Un::Neg).taint(!negative_zero(a) || a.tainted),
            Bin::Mul if zero(a) || zero(b) => {
                let other = if zero(a) { b } else { a };
                if let Term::Node(id) = other.term {
                    with_tape(|tape| tape.check(id, Check::Finite));
                }
                return Sym::konst(0.0).taint(true);
            }
            Bin::Mul if a.is(1.0) => return b.taint(a.tainted),
            Bin::Mul if b.is(1.0) => return a.taint(b.tainted),
            Bin::Mul if a.is(-1.0) => return b.un(Un::Neg).taint(a.tainted),
            Bin::Mul if b.is(-1.0) => return a.un(Un::Neg).taint(b.tainted),
            Bin::Div if b.is(1.0) => return a.taint(b.tainted),
            _ => {}
        }
        Sym::record(tainted, |tape| {
            let (x, y) = (tape.operand(a), tape.operand(b));
            Node::Bin(op, x, y)
        })
    }

    fn ask<T>(answer: T) -> T {
        poison();
        answer
    }
}

impl From<f64> for Sym {
    fn from(value: f64) -> Self {
        Sym::konst(value)
    }
}

impl fmt::Display for Sym {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.term {
            Term::Const(c) => write!(f, "{c}"),
            Term::Node(id) => write!(f, "%{id}"),
        }
    }
}

/// `Sym ∘ Sym`, `Sym ∘ &Sym` and `Sym ∘ f64` for one operator, and its assigning form.
macro_rules! binary_ops {
    ($($trait:ident $method:ident $assign:ident $assign_method:ident => $op:expr;)*) => {$(
        impl $trait for Sym {
            type Output = Sym;
            fn $method(self, rhs: Sym) -> Sym {
                Sym::bin($op, self, rhs)
            }
        }
        impl $trait<&Sym> for Sym {
            type Output = Sym;
            fn $method(self, rhs: &Sym) -> Sym {
                Sym::bin($op, self, *rhs)
            }
        }
        impl $trait<f64> for Sym {
            type Output = Sym;
            fn $method(self, rhs: f64) -> Sym {
                Sym::bin($op, self, Sym::konst(rhs))
            }
        }
        impl $assign for Sym {
            fn $assign_method(&mut self, rhs: Sym) {
                *self = Sym::bin($op, *self, rhs);
            }
        }
        impl $assign<f64> for Sym {
            fn $assign_method(&mut self, rhs: f64) {
                *self = Sym::bin($op, *self, Sym::konst(rhs));
            }
        }
    )*};
}

binary_ops! {
    Add add AddAssign add_assign => Bin::Add;
    Sub sub SubAssign sub_assign => Bin::Sub;
    Mul mul MulAssign mul_assign => Bin::Mul;
    Div div DivAssign div_assign => Bin::Div;
    Rem rem RemAssign rem_assign => Bin::Rem;
}

impl Neg for Sym {
    type Output = Sym;
    fn neg(self) -> Sym {
        self.un(Un::Neg)
    }
}

impl Zero for Sym {
    fn zero() -> Self {
        Sym::konst(0.0)
    }
    fn is_zero(&self) -> bool {
        match self.term {
            Term::Const(c) => c == 0.0,
            Term::Node(_) => Sym::ask(false),
        }
    }
}

impl One for Sym {
    fn one() -> Self {
        Sym::konst(1.0)
    }
    fn is_one(&self) -> bool {
        match self.term {
            Term::Const(c) => c == 1.0,
            Term::Node(_) => Sym::ask(false),
        }
    }
}

impl Num for Sym {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(text: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        f64::from_str_radix(text, radix).map(Sym::konst)
    }
}

impl Signed for Sym {
    fn abs(&self) -> Self {
        self.un(Un::Abs)
    }
    fn abs_sub(&self, other: &Self) -> Self {
        match (self.term, other.term) {
            (Term::Const(a), Term::Const(b)) => Sym::konst(Signed::abs_sub(&a, &b)),
            _ => Sym::ask(Sym::konst(f64::NAN)),
        }
    }
    fn signum(&self) -> Self {
        self.un(Un::Signum)
    }
    fn is_positive(&self) -> bool {
        match self.term {
            Term::Const(c) if !(self.tainted && c == 0.0) => c.is_sign_positive(),
            _ => Sym::ask(false),
        }
    }
    fn is_negative(&self) -> bool {
        match self.term {
            Term::Const(c) if !(self.tainted && c == 0.0) => c.is_sign_negative(),
            _ => Sym::ask(false),
        }
    }
}

impl Inv for Sym {
    type Output = Sym;
    fn inv(self) -> Sym {
        self.un(Un::Recip)
    }
}

impl Sum for Sym {
    fn sum<I: Iterator<Item = Sym>>(iter: I) -> Sym {
        iter.fold(Sym::zero(), |acc, x| acc + x)
    }
}

impl Product for Sym {
    fn product<I: Iterator<Item = Sym>>(iter: I) -> Sym {
        iter.fold(Sym::one(), |acc, x| acc * x)
    }
}

impl FromPrimitive for Sym {
    fn from_i64(n: i64) -> Option<Self> {
        f64::from_i64(n).map(Sym::konst)
    }
    fn from_u64(n: u64) -> Option<Self> {
        f64::from_u64(n).map(Sym::konst)
    }
    fn from_f64(n: f64) -> Option<Self> {
        Some(Sym::konst(n))
    }
}

impl DualStruct for Sym {
    type Real = f64;
    type Inner = Sym;
    /// A traced number has no value: asking for it poisons the trace.
    fn re(&self) -> f64 {
        match self.term {
            Term::Const(c) if !(self.tainted && c == 0.0) => c,
            _ => Sym::ask(f64::NAN),
        }
    }
    fn from_inner(inner: &Sym) -> Self {
        *inner
    }
}

impl Mappable<Sym> for Sym {
    type Output<O> = O;
    fn map_dual<G: Fn(Sym) -> O, O>(self, g: G) -> O {
        g(self)
    }
}

/// Comparisons answer for constants only; any other poisons the trace.
impl PartialEq for Sym {
    fn eq(&self, other: &Sym) -> bool {
        match (self.term, other.term) {
            (Term::Const(a), Term::Const(b)) => a == b,
            _ => Sym::ask(false),
        }
    }
}

impl PartialEq<f64> for Sym {
    fn eq(&self, other: &f64) -> bool {
        *self == Sym::konst(*other)
    }
}

impl PartialOrd for Sym {
    fn partial_cmp(&self, other: &Sym) -> Option<std::cmp::Ordering> {
        match (self.term, other.term) {
            (Term::Const(a), Term::Const(b)) => a.partial_cmp(&b),
            _ => Sym::ask(None),
        }
    }
}

impl PartialOrd<f64> for Sym {
    fn partial_cmp(&self, other: &f64) -> Option<std::cmp::Ordering> {
        self.partial_cmp(&Sym::konst(*other))
    }
}

impl DualNum for Sym {
    type Primitive = f64;
    const NDERIV: usize = 0;
    type InnerDual = Sym;

    fn from_re(re: Sym) -> Self {
        re
    }
    fn scale(self, factor: &Sym) -> Self {
        self * *factor
    }
    fn mul_add(&self, a: Self, b: Self) -> Self {
        if !tick() {
            return Sym::konst(f64::NAN);
        }
        if let (Term::Const(x), Term::Const(y), Term::Const(z)) = (self.term, a.term, b.term) {
            return Sym::folded(x.mul_add(y, z), self.tainted || a.tainted || b.tainted);
        }
        let this = *self;
        Sym::record(this.tainted || a.tainted || b.tainted, |tape| {
            let (x, y, z) = (tape.operand(this), tape.operand(a), tape.operand(b));
            Node::MulAdd(x, y, z)
        })
    }
    fn recip(&self) -> Self {
        self.un(Un::Recip)
    }
    fn powi(&self, n: i32) -> Self {
        self.un(Un::Powi(n))
    }
    fn powf(&self, n: f64) -> Self {
        self.un(Un::Powf(n.to_bits()))
    }
    fn powd(&self, exp: Self) -> Self {
        Sym::bin(Bin::Powf, *self, exp)
    }
    fn sqrt(&self) -> Self {
        self.un(Un::Sqrt)
    }
    fn cbrt(&self) -> Self {
        self.un(Un::Cbrt)
    }
    fn exp(&self) -> Self {
        self.un(Un::Exp)
    }
    fn exp2(&self) -> Self {
        self.un(Un::Exp2)
    }
    fn exp_m1(&self) -> Self {
        self.un(Un::ExpM1)
    }
    fn ln(&self) -> Self {
        self.un(Un::Ln)
    }
    fn log(&self, base: f64) -> Self {
        self.un(Un::Log(base.to_bits()))
    }
    fn log2(&self) -> Self {
        self.un(Un::Log2)
    }
    fn log10(&self) -> Self {
        self.un(Un::Log10)
    }
    fn ln_1p(&self) -> Self {
        self.un(Un::Ln1p)
    }
    fn sin(&self) -> Self {
        self.un(Un::Sin)
    }
    fn cos(&self) -> Self {
        self.un(Un::Cos)
    }
    fn tan(&self) -> Self {
        self.un(Un::Tan)
    }
    /// `f64::sin_cos` is `(sin, cos)`, so the two are recorded apart (and shared).
    fn sin_cos(&self) -> (Self, Self) {
        (self.un(Un::Sin), self.un(Un::Cos))
    }
    fn asin(&self) -> Self {
        self.un(Un::Asin)
    }
    fn acos(&self) -> Self {
        self.un(Un::Acos)
    }
    fn atan(&self) -> Self {
        self.un(Un::Atan)
    }
    fn atan2(&self, other: Self) -> Self {
        Sym::bin(Bin::Atan2, *self, other)
    }
    fn sinh(&self) -> Self {
        self.un(Un::Sinh)
    }
    fn cosh(&self) -> Self {
        self.un(Un::Cosh)
    }
    fn tanh(&self) -> Self {
        self.un(Un::Tanh)
    }
    fn asinh(&self) -> Self {
        self.un(Un::Asinh)
    }
    fn acosh(&self) -> Self {
        self.un(Un::Acosh)
    }
    fn atanh(&self) -> Self {
        self.un(Un::Atanh)
    }
    /// num-dual's spherical Bessel functions branch on the value: not traced.
    fn sph_j0(&self) -> Self {
        Sym::ask(Sym::konst(f64::NAN))
    }
    fn sph_j1(&self) -> Self {
        Sym::ask(Sym::konst(f64::NAN))
    }
    fn sph_j2(&self) -> Self {
        Sym::ask(Sym::konst(f64::NAN))
    }
}
