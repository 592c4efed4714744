//! Fuzzes `zenosim plot` on mutated output folders (`summary.json NUL trajectory.csv [NUL
//! options]`): the check is `fuzz/checks/plot.rs`, shared with the CI replay of the seeds.

#![no_main]

#[path = "../checks/plot.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
