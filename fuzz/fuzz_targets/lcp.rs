//! Fuzzes the contact problems' LCP solver (`zenosim::lcp`) on problems as bytes: the check is
//! `fuzz/checks/lcp.rs`, shared with the CI replay of the seeds.

#![no_main]

#[path = "../checks/lcp.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
