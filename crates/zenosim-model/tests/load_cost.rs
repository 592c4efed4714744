//! What loading a model file costs grows linearly with its formulas, and a bound turns a file
//! beyond it into an error instead of minutes of work: the wide Lagrangians and the many
//! constraints of issue 25, which took 74 s and 1 GB (a 99 KB Lagrangian) and 321 s and
//! 1.2 GB (64 constraints) to load.
//!
//! Nothing here is timed (the figures are in BENCHMARKS.md, from `benches/load.rs`): the tests
//! count the operations of the trace, which decide its time and memory.

use zenosim_model::{parse_model, parse_model_with, Limits, ModelFile};

#[path = "common/wide.rs"]
mod wide;
use wide::{coordinates, parameter_chain, wide};

fn load(source: &str) -> ModelFile {
    parse_model("wide.toml", source, &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// The operations its trace took.
fn traced(file: &ModelFile) -> u64 {
    file.model
        .compiled_derivatives()
        .expect("traced")
        .operations_traced()
}

#[test]
fn the_lagrangian_is_traced_once_whatever_the_number_of_constraints() {
    // Each constraint used to trace the Lagrangian's derivatives again, three times (the
    // motion held on it, the acceleration held on it, its direction).
    let one = traced(&load(&wide(500, 1)));
    let two = traced(&load(&wide(500, 2)));
    let many = traced(&load(&wide(500, 64)));
    let per_constraint = two - one;
    // A constraint `q + h0` costs its own derivatives only: a few operations per coordinate,
    // against the Lagrangian's hundreds of thousands.
    assert!(per_constraint < 1_000, "{per_constraint} per constraint");
    assert!(one > 500_000, "the Lagrangian traced in {one} operations");
    // 63 more constraints add their own cost (their programs, the same size or smaller),
    // under 2 % of the Lagrangian's.
    assert!(many <= one + 63 * per_constraint, "{one} {two} {many}");
    assert!(many - one < one / 50, "{one} {two} {many}");
}

#[test]
fn the_trace_grows_linearly_with_the_lagrangian() {
    let small = traced(&load(&wide(500, 1)));
    let large = traced(&load(&wide(2_000, 1)));
    // Four times the factors: four times the operations of the product, and the same of the
    // rest (the kinetic energy, the constraint).
    let ratio = large as f64 / small as f64;
    assert!((3.5..=4.0).contains(&ratio), "{small} → {large}: ×{ratio}");
}

#[test]
fn a_lagrangian_beyond_the_limit_is_refused_saying_how_to_raise_it() {
    // The 99 KB Lagrangian: 49 845 factors, within the formula length limit, which
    // would take over 160 million operations to trace.
    let q = coordinates();
    let head_length = wide(0, 1).lines().nth(2).unwrap().len();
    let factors = (100_000 - head_length) / 2;
    let source = wide(factors, 1);
    let e = parse_model("wide.toml", &source, &[]).unwrap_err();
    let text = e.to_string();
    assert_eq!(e.key(), Some("lagrangian"), "{text}");
    assert!(
        text.contains("more than the limit of 10000000 operations"),
        "{text}"
    );
    assert!(text.contains("--max-derivative-operations"), "{text}");
    assert!(text.starts_with("wide.toml:3:"), "{text}");
    assert_eq!(q.len(), 20);

    // A smaller one loads, and is refused under a lower limit: the limit is what decides.
    let source = wide(500, 1);
    let needed = traced(&load(&source));
    let limits = |max_operations| Limits {
        max_operations,
        ..Limits::default()
    };
    let e = parse_model_with("wide.toml", &source, &[], limits(needed as usize - 1)).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("more than the limit of {} operations", needed - 1)),
        "{e}"
    );
    let file = parse_model_with("wide.toml", &source, &[], limits(needed as usize)).unwrap();
    assert_eq!(traced(&file), needed);
}

#[test]
fn a_long_chain_of_parameters_resolves_in_linear_time() {
    // 40 000 parameters (a megabyte), each the one before plus 1: every name used to be looked up by a
    // scan of all the parameters (12 s for 62 000).
    let count = 40_000;
    let source = parameter_chain(count);
    assert!(source.len() < zenosim_model::MAX_FILE_BYTES as usize);
    let file = load(&source);
    let last = &file.parameters[count - 1];
    assert_eq!(
        (last.0.as_str(), last.1),
        (format!("p{}", count - 1).as_str(), count as f64)
    );
}

#[test]
fn a_twenty_link_pendulum_chain_written_out_loads_well_within_the_limit() {
    // A dense 20 × 20 mass matrix of sums of cosines: the largest natural model we know of.
    let file = load(&wide::pendulum_chain(20));
    let needed = traced(&file);
    let limit = zenosim_model::expr::DEFAULT_MAX_OPERATIONS as u64;
    assert!(needed < limit / 2, "{needed} of {limit}");
    assert_eq!(
        file.model.compiled_derivatives().unwrap().coverage(),
        (4, 4)
    );
}

/// Regression (a review of the limit): every refusal named `lagrangian`, also where the cost
/// was all in a constraint's `h` or in a force. The refusal now names the formula being
/// differentiated when the limit was reached, or, when that was after the formulas (making
/// the programs), the longest one.
#[test]
fn a_refusal_named_the_lagrangian_whatever_formula_cost() {
    let q = coordinates();
    let product = |n: usize| {
        (0..n)
            .map(|i| q[i % q.len()].as_str())
            .collect::<Vec<_>>()
            .join("*")
    };
    let base = wide(1, 2);
    // A little more than what the file costs without its costly formula.
    let limits = Limits {
        max_operations: traced(&load(&base)) as usize + 10_000,
        ..Limits::default()
    };
    let refused = |source: &str| match parse_model_with("wide.toml", source, &[], limits) {
        Ok(file) => panic!("loaded in {} operations", traced(&file)),
        Err(e) => e,
    };

    let costly_h = base.replacen(
        "h = \"b + h0\"",
        &format!("h = \"b + h0 + 1e-9*{}\"", product(4000)),
        1,
    );
    let e = refused(&costly_h);
    assert_eq!(e.key(), Some("constraint[2].h"), "{e}");
    assert!(e.to_string().contains("constraint `c1`'s h"), "{e}");

    let costly_force = base.replace(
        "[initial]",
        &format!("[forces]\nc = \"1e-9*{}\"\n[initial]", product(4000)),
    );
    let e = refused(&costly_force);
    assert_eq!(e.key(), Some("forces.c"), "{e}");
    assert!(e.to_string().contains("the force on `c`"), "{e}");
}

/// Regression (a review of the limit): only the trace was counted, not the programs made from
/// it. Where `M` is constant each constraint's programs hold the whole force, so 64
/// constraints on a large force made programs 64 times the trace (a 1 MB file: 59–102 s,
/// 2.3 GB); and an entry new to the trace costs ten times one found again (8 constraints,
/// each `h` a 4 000-factor product: 8–16 s, 642 MB). Both now count.
#[test]
fn programs_and_new_entries_were_not_counted_against_the_limit() {
    use wide::{forces, products};
    // One constraint on the force loads; 64 on the same force make the programs too large.
    let one = traced(&load(&forces(2_000, 1)));
    assert!(one < 2_000_000, "{one}");
    let e = parse_model("wide.toml", &forces(2_000, 64), &[]).unwrap_err();
    assert!(
        e.to_string().contains("more than the limit of 10000000"),
        "{e}"
    );
    assert_eq!(e.key(), Some("forces.u"), "{e}");

    // Large constraints whose entries are all new.
    let e = parse_model("wide.toml", &products(4_000, 8), &[]).unwrap_err();
    assert!(e.key().unwrap().starts_with("constraint["), "{e}");
}
