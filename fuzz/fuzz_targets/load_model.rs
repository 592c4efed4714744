//! Fuzzes the model-file loader, and the engine on every model it accepts: the check is
//! `fuzz/checks/load_model.rs`, shared with the CI replay of the seeds.

#![no_main]

#[path = "../checks/load_model.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
