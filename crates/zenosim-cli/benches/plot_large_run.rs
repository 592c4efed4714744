//! Drawing the plots of a run of 10⁶ steps, as a user does it: `zenosim plot DIR` (a new
//! process that reads `summary.json` and the 180 MB `trajectory.csv`, decimates and writes the
//! six plots), in SVG and in PNG.
//!
//! The run, the paper's ball with `max_step = 6e-6` (10⁶ steps, 26 impacts, a Zeno point), is
//! made once before the measurement (about 15 s). Target (issue 4): under 2 s on a 2-core
//! machine. Run with `cargo bench -p zenosim-cli --bench plot_large_run`.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};

#[path = "../tests/common/mod.rs"]
mod common;

/// Runs `zenosim <args>` in `scratch`; panics unless it succeeds.
fn zenosim(scratch: &common::Scratch, args: &[&str]) {
    let output = scratch.zenosim(args);
    assert!(
        output.status.success(),
        "zenosim {args:?}: {}",
        common::stderr(&output)
    );
}

fn plots(c: &mut Criterion) {
    // The paper's ball, its steps capped at 6e-6 to t = 6.
    let model = common::BALL_ON_SINE.replace("t_end = 6.0", "t_end = 6.0\nmax_step = 6e-6");
    let scratch = common::Scratch::new(&model);
    zenosim(&scratch, &["run", "model.toml", "--out", "out"]);
    let summary = common::summary(&scratch.path("out"));
    let bytes = std::fs::metadata(scratch.path("out/trajectory.csv")).map_or(0, |m| m.len());
    eprintln!(
        "the run: {} steps, {} rows, {} impacts, {:.0} MB of CSV",
        summary["stats"]["steps"],
        summary["trajectory"]["rows"],
        summary["stats"]["impacts"],
        bytes as f64 / 1e6
    );

    let mut group = c.benchmark_group("plots of a 10^6-step run");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.bench_function("zenosim plot (svg)", |b| {
        b.iter(|| zenosim(&scratch, &["plot", "out"]))
    });
    group.bench_function("zenosim plot --format png", |b| {
        b.iter(|| zenosim(&scratch, &["plot", "out", "--format", "png"]))
    });
    group.finish();
}

criterion_group!(benches, plots);
criterion_main!(benches);
