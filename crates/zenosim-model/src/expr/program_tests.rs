//! Unit tests of the compiled form: folding, fusion, stack depth, dependencies.

use super::*;

fn compile(source: &str) -> Expression {
    Expression::parse(source, &["x", "y"]).unwrap()
}

#[test]
fn constant_subtrees_are_folded() {
    let e = compile("0.5*2*9.81");
    assert_eq!(&*e.code, &[Instr::Const(0.5 * 2.0 * 9.81)]);
    assert_eq!(e.constant_value(), Some(9.81));
    let e = compile("x * (0.5*2) + sin(pi/2)^2");
    assert_eq!(
        &*e.code,
        &[Instr::Load(0), Instr::MulConst(1.0), Instr::AddConst(1.0)]
    );
    // No reassociation: `x*0.5*2` is `(x*0.5)*2`.
    assert_eq!(
        &*compile("x*0.5*2").code,
        &[Instr::Load(0), Instr::MulConst(0.5), Instr::MulConst(2.0)]
    );
    assert_eq!(compile("x*0.5*2").constant_value(), None);
}

#[test]
fn names_and_constants_fuse_into_binary_operations() {
    assert_eq!(
        &*compile("x/y - 2").code,
        &[Instr::Load(0), Instr::DivVar(1), Instr::SubConst(2.0)]
    );
    assert_eq!(
        &*compile("2/x + y").code,
        &[Instr::Const(2.0), Instr::DivVar(0), Instr::AddVar(1)]
    );
    let e = compile("(x - y) * (x*y)");
    assert_eq!(e.eval(&[3.0, 2.0]), 6.0);
    assert_eq!(e.slots(), &[0, 1]);
    assert_eq!(compile("1 + y").slots(), &[1]);
}

#[test]
fn powers_are_specialised_on_constant_exponents() {
    assert_eq!(&*compile("x^2").code, &[Instr::Load(0), Instr::Square]);
    assert_eq!(
        &*compile("pow(x, -3)").code,
        &[Instr::Load(0), Instr::PowI(-3)]
    );
    assert_eq!(
        &*compile("x^(1/2)").code,
        &[Instr::Load(0), Instr::PowF(0.5)]
    );
    assert_eq!(
        &*compile("x^y").code,
        &[Instr::Load(0), Instr::Load(1), Instr::Pow]
    );
    assert_eq!(&*compile("x^3").code, &[Instr::Load(0), Instr::PowI(3)]);
    assert_eq!(compile("(-2)^3").constant_value(), Some(-8.0));
    assert_eq!(
        compile("(-8)^2^-1").constant_value().map(f64::is_nan),
        Some(true)
    );
}

#[test]
fn stack_depth_picks_the_storage() {
    let shallow = compile("x + y*sin(x)");
    assert_eq!(shallow.max_stack, 3);
    // Right-nested sums need one stack slot per level: 40 > 32 goes to the heap.
    let deep_source = format!("{}x{}", "x+(".repeat(40), ")".repeat(40));
    let deep = compile(&deep_source);
    assert_eq!(deep.max_stack, 40);
    assert_eq!(deep.eval(&[1.0, 0.0]), 41.0);
    let middle_source = format!("{}x{}", "x+(".repeat(20), ")".repeat(20));
    assert_eq!(compile(&middle_source).eval(&[1.0, 0.0]), 21.0);
}

#[test]
fn dependencies() {
    let e = compile("y*sin(y) + 0*x");
    assert_eq!(e.names(), &["y".to_string(), "x".to_string()]);
    assert_eq!(e.slots(), &[0, 1]);
    assert!(e.reads(0) && e.reads(1) && !e.reads(2));
    let e = compile("2*pi");
    assert!(e.slots().is_empty() && e.names().is_empty());
    assert_eq!(e.to_string(), "2*pi");
    assert_eq!(e.source(), "2*pi");
}
