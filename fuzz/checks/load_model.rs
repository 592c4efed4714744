//! The check of the load_model fuzz target (`fuzz/fuzz_targets/load_model.rs`), shared with
//! the test that replays the seeds in CI (`crates/zenosim-cli/tests/fuzz_replay.rs`) and the
//! random-input test of the loader (`crates/zenosim-model/tests/random_input.rs`, which calls
//! its `simulate`), all of which include this file by `#[path]`.
//!
//! The input is taken as a model file. If it is UTF-8 it goes to `parse_model`; lines of the
//! form `#set NAME=VALUE` (TOML comments) become `--set` overrides, so that path is fuzzed too.
//! A refused file must give an error that names the file and says what to do; an accepted one
//! must be accepted by the engine too, and is simulated briefly, within bounds that keep any one
//! input fast:
//! `t_end ≤ 1`, at most 2000 steps, 200 events and 1000 uniform samples.
//! Nothing may panic. How long an input takes is the fuzzer's to judge (`-timeout`).

use zenosim::{Event, Observer, OutputGrid, Sample, Simulation};
use zenosim_model::{parse_model, Location, ModelFile, Override};

const FILE: &str = "fuzz.toml";
const T_END: f64 = 1.0;
const MAX_STEPS: u64 = 2_000;
const MAX_EVENTS: u64 = 200;

/// Takes every sample and event (so the output paths run) and keeps a little of each.
#[derive(Default)]
struct Watch {
    samples: u64,
    events: u64,
    energy: f64,
}

impl Observer for Watch {
    fn sample(&mut self, sample: &Sample<'_>) {
        self.samples += 1;
        self.energy = sample.energy;
    }

    fn event(&mut self, _event: &Event) {
        self.events += 1;
    }
}

fn overrides(source: &str) -> Vec<Override> {
    source
        .lines()
        .filter_map(|line| line.strip_prefix("#set "))
        .filter_map(|arg| arg.parse().ok())
        .collect()
}

/// Runs an accepted model briefly, within the bounds above; panics where the engine refuses
/// what the loader accepted, or a bound is not kept.
pub fn simulate(file: &ModelFile) {
    let mut options = file.options();
    options.t_end = options.t_end.min(T_END);
    options.max_steps = options.max_steps.min(MAX_STEPS);
    options.max_events = options.max_events.min(MAX_EVENTS);
    if let OutputGrid::Uniform(dt) = options.output {
        // At most max_steps / 2 samples: within the engine's t_end / dt <= max_steps, rounding
        // included.
        let dt_min = 2.0 * options.t_end / options.max_steps as f64;
        options.output = OutputGrid::Uniform(dt.max(dt_min));
    }
    let q0 = &file.initial.q;
    let q_dot0 = &file.initial.q_dot;
    // `parse_model` checks everything the engine checks before a run.
    let simulation = Simulation::new(&file.model, q0, q_dot0, options)
        .unwrap_or_else(|e| panic!("parse_model accepted a model that the engine refuses: {e}"));
    let mut watch = Watch::default();
    let execution = simulation.run(&mut watch);
    // The limits are what the options promise.
    assert!(execution.events.len() as u64 <= options.max_events);
    assert!(execution.stats.steps <= options.max_steps);
    std::hint::black_box((
        format!("{:?}", execution.outcome),
        watch.samples,
        watch.events,
        watch.energy,
    ));
}

/// The check of one input: panics on a finding.
pub fn check(data: &[u8]) {
    let Ok(source) = std::str::from_utf8(data) else {
        return;
    };
    match parse_model(FILE, source, &overrides(source)) {
        Ok(file) => simulate(&file),
        Err(error) => {
            // What `ModelError` promises: the file, the place, what is wrong, what to do.
            let text = error.to_string();
            assert!(text.starts_with(&format!("{FILE}:")), "{text}");
            assert!(text.contains("\n   = help: "), "{text}");
            if let Location::At { line, column, .. } = error.location {
                assert!(
                    text.starts_with(&format!("{FILE}:{line}:{column}: ")),
                    "{text}"
                );
                assert!(text.contains(&format!("\n{line} | ")), "no snippet: {text}");
            }
        }
    }
}
