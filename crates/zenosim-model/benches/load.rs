//! Loading a model file: parsing, checking, and tracing its derivatives, for the large files of
//! issue 25 (a wide Lagrangian, many constraints, a long chain of parameters) and a large
//! natural one (a 20-link pendulum chain written out in full). The files beyond the limit on
//! the derivatives' operations are refused: what is measured is how long that takes. Run with
//! `cargo bench -p zenosim-model --bench load`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use zenosim_model::parse_model;

#[path = "../tests/common/wide.rs"]
mod wide;

fn bench(c: &mut Criterion, name: &str, source: &str) {
    let verdict = match parse_model(name, source, &[]) {
        Ok(file) => format!(
            "loads, {} operations traced",
            file.model
                .compiled_derivatives()
                .map_or(0, |c| c.operations_traced())
        ),
        Err(e) => format!("refused: {}", e.to_string().lines().next().unwrap_or("")),
    };
    eprintln!("{name} ({} bytes): {verdict}", source.len());
    let mut group = c.benchmark_group("load");
    group.sample_size(10);
    group.bench_function(name, |b| {
        b.iter(|| black_box(parse_model(name, source, &[]).is_ok()))
    });
    group.finish();
}

fn load(c: &mut Criterion) {
    // The widest Lagrangian within the formula length limit (99 KB): refused.
    bench(c, "wide 49845 factors", &wide::wide(49_845, 1));
    // 64 constraints on a Lagrangian of 10 000 factors (issue 25's 20 KB file): refused.
    bench(
        c,
        "wide 10000 factors, 64 constraints",
        &wide::wide(10_000, 64),
    );
    // A review's attacks through the programs (a 1 MB file: 20 forces of 25 000 factors, 64
    // constraints) and through new entries (8 constraints, each h a 4 000-factor product):
    // refused.
    bench(
        c,
        "forces 25000 factors, 64 constraints",
        &wide::forces(25_000, 64),
    );
    bench(c, "8 products of 4000 factors", &wide::products(4_000, 8));
    // Within the limit.
    bench(
        c,
        "wide 1000 factors, 64 constraints",
        &wide::wide(1_000, 64),
    );
    bench(c, "wide 2000 factors", &wide::wide(2_000, 1));
    bench(
        c,
        "40000 chained parameters",
        &wide::parameter_chain(40_000),
    );
    bench(c, "20-link pendulum chain", &wide::pendulum_chain(20));
}

criterion_group!(benches, load);
criterion_main!(benches);
