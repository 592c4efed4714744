//! The engine's benchmarks, in one binary (one release build for all of them):
//! - `runs`: whole runs of the paper's examples written as Rust models;
//! - `evaluation`: one evaluation of each model's equations of motion, and event location;
//! - `scaling`: how a run's cost grows with `t_end`, with the number of impacts before the Zeno
//!   point (`e`) and with the number of coordinates (a chain of pendulums on a wall);
//! - `lcp`: the contact problems' LCP solver on the sets the engine meets.
//!
//! Run with `cargo bench -p zenosim --bench engine [-- FILTER]`.

mod evaluation;
mod lcp;
mod runs;
mod scaling;

criterion::criterion_group!(
    benches,
    runs::paper_ball,
    runs::demos,
    evaluation::benches,
    scaling::benches,
    lcp::benches
);
criterion::criterion_main!(benches);
