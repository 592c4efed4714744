//! `zenosim bench`: how long a model file's run takes, at one or several tolerances, measured
//! in this process (no trajectory written, so the time is the simulation's own), with the
//! run's outcome beside it so that its accuracy can be judged.
//!
//! The report is one JSON document on stdout (for scripts such as `bench/run`, the comparison
//! with scipy); a line per tolerance goes to stderr as each is measured.

use std::time::{Duration, Instant};

use anyhow::anyhow;
use serde::Serialize;
use zenosim::{Execution, HybridLagrangian, Outcome, Simulation, SimulationOptions};
use zenosim_model::ModelFile;
use zenosim_runs::json_layout;
use zenosim_runs::message::{message, plural};
use zenosim_runs::number::number;
use zenosim_runs::summary::{
    constraint_names, status, FinalJson, Pairs, Record, SettingsJson, StateJson, StatsJson,
    TrajectoryJson, ZenoJson,
};

use crate::cli::BenchArgs;
use crate::{
    print_error, print_report, Classify, Failure, EXIT_FAILED, EXIT_OK, EXIT_ZENO_STALLED,
};

/// The fewest timed repetitions of anything measured.
const MIN_REPEATS: usize = 3;
/// The most: a run of microseconds stops here rather than after `--min-time`.
const MAX_REPEATS: usize = 100_000;

/// `zenosim bench MODEL.toml`.
pub fn bench(args: &BenchArgs) -> Result<u8, Failure> {
    let load = || args.input.load(&args.formulas);
    let file = load().bad_input()?;
    // Reading, parsing, checking and compiling the file, as every `zenosim run` does.
    let load_time = measure(args.min_time / 4.0, || {
        let _ = std::hint::black_box(load());
    });

    let base = options(&file, args);
    let tolerances = match &args.tolerances {
        Some(list) => list.iter().map(|&tol| (tol, tol)).collect(),
        None => vec![(base.tolerances.rtol, base.tolerances.atol)],
    };
    let constraints = constraint_names(&file);

    let mut runs = Vec::new();
    for (rtol, atol) in tolerances {
        let mut options = base;
        options.tolerances.rtol = rtol;
        options.tolerances.atol = atol;
        let simulation =
            Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)
                .map_err(|error| {
                    anyhow!(
                        "{}: cannot simulate this model at rtol = {}, atol = {}: {error}",
                        args.input.model.display(),
                        number(rtol),
                        number(atol)
                    )
                })
                .bad_input()?;
        let execution = simulation.run(&mut ());
        let time = measure(args.min_time, || {
            std::hint::black_box(simulation.run(&mut ()));
        });
        eprintln!("{}", line(&options, &execution, &time));
        runs.push((options, execution, time));
    }

    let report = Report {
        zenosim: env!("CARGO_PKG_VERSION"),
        model: &file.name,
        coordinates: file.model.coordinate_names(),
        parameters: Pairs::parameters(&file),
        initial: (&file.initial).into(),
        constraints: constraints.iter().map(String::as_str).collect(),
        load_time_s: load_time,
        runs: runs
            .iter()
            .map(|(options, execution, time)| {
                run_json(&file, options, execution, &constraints, time)
            })
            .collect(),
    };
    let mut json = Vec::new();
    json_layout::to_writer(&mut json, &report, 3)
        .map_err(|error| anyhow!("cannot write the report: {error}"))
        .output()?;
    json.push(b'\n');
    print_report(&String::from_utf8_lossy(&json));

    // The worst outcome decides the exit status, as for `zenosim run`.
    let failed = runs
        .iter()
        .find(|(_, e, _)| matches!(e.outcome, Outcome::Failed(_)));
    if let Some((options, _, _)) = failed {
        print_error(&format!(
            "the run at rtol = {}, atol = {} failed (its message is in the report)",
            number(options.tolerances.rtol),
            number(options.tolerances.atol)
        ));
        return Ok(EXIT_FAILED);
    }
    let stalled = runs
        .iter()
        .any(|(_, e, _)| matches!(e.outcome, Outcome::ZenoStalled { .. }));
    Ok(if stalled { EXIT_ZENO_STALLED } else { EXIT_OK })
}

/// The file's settings with the command line's `--t-end` and `--zeno`.
fn options(file: &ModelFile, args: &BenchArgs) -> SimulationOptions {
    let mut options = file.options();
    if let Some(t_end) = args.t_end {
        options.t_end = t_end;
    }
    if let Some(zeno) = args.zeno {
        options.zeno = zeno;
    }
    options
}

/// Wall times of repeated calls, in seconds.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Timing {
    /// The median.
    pub median: f64,
    /// The fastest.
    pub min: f64,
    /// The slowest.
    pub max: f64,
    /// How many calls were timed.
    pub repeats: usize,
}

/// Times `f` until `min_time` seconds have passed and it ran at least [`MIN_REPEATS`] times (at
/// most [`MAX_REPEATS`]), after one untimed call that warms the caches.
fn measure(min_time: f64, mut f: impl FnMut()) -> Timing {
    f();
    let budget = Duration::from_secs_f64(min_time.max(0.0));
    let start = Instant::now();
    let mut times = Vec::new();
    while times.len() < MIN_REPEATS || (start.elapsed() < budget && times.len() < MAX_REPEATS) {
        let t0 = Instant::now();
        f();
        times.push(t0.elapsed().as_secs_f64());
    }
    summarise(&mut times)
}

/// The median, extremes and count of `times` (not empty).
fn summarise(times: &mut [f64]) -> Timing {
    times.sort_by(f64::total_cmp);
    let n = times.len();
    let median = if n % 2 == 1 {
        times[n / 2]
    } else {
        0.5 * (times[n / 2 - 1] + times[n / 2])
    };
    Timing {
        median,
        min: times[0],
        max: times[n - 1],
        repeats: n,
    }
}

/// The line said on stderr for one tolerance.
fn line(options: &SimulationOptions, run: &Execution, time: &Timing) -> String {
    let tol = &options.tolerances;
    let tolerance = if tol.rtol == tol.atol {
        format!("rtol = atol = {}", number(tol.rtol))
    } else {
        format!("rtol = {}, atol = {}", number(tol.rtol), number(tol.atol))
    };
    format!(
        "{tolerance}: {}, {}, {}, {} rhs evaluations; {} median of {} runs (fastest {})",
        status(&run.outcome),
        plural(run.stats.impacts as usize, "impact"),
        plural(run.zeno.len(), "Zeno point"),
        run.stats.rhs_evals,
        seconds(time.median),
        time.repeats,
        seconds(time.min)
    )
}

/// A duration in the unit that suits it.
fn seconds(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.3} ms", s * 1e3)
    } else {
        format!("{s:.3} s")
    }
}

/// The report.
#[derive(Serialize)]
struct Report<'a> {
    zenosim: &'static str,
    model: &'a str,
    coordinates: Vec<String>,
    parameters: Pairs<'a>,
    initial: StateJson<'a>,
    constraints: Vec<&'a str>,
    /// Reading, parsing, checking and compiling the model file.
    load_time_s: Timing,
    runs: Vec<RunJson<'a>>,
}

/// One tolerance's run: as in `summary.json`, with its wall time.
#[derive(Serialize)]
struct RunJson<'a> {
    settings: SettingsJson,
    status: &'static str,
    message: String,
    #[serde(rename = "final")]
    final_: FinalJson<'a>,
    zeno: Vec<ZenoJson<'a>>,
    events: EventCounts,
    stats: StatsJson,
    wall_time_s: Timing,
}

/// Events by kind.
#[derive(Serialize)]
struct EventCounts {
    impact: usize,
    zeno: usize,
    liftoff: usize,
}

fn run_json<'a>(
    file: &'a ModelFile,
    options: &'a SimulationOptions,
    run: &'a Execution,
    constraints: &'a [String],
    time: &Timing,
) -> RunJson<'a> {
    let summary = Record {
        file,
        options,
        run,
        constraint_names: constraints,
        message: message(run, constraints),
        trajectory: TrajectoryJson { file: "", rows: 0 },
    }
    .summary();
    let count = |kind: zenosim::EventKind| run.events.iter().filter(|e| e.kind == kind).count();
    RunJson {
        settings: summary.settings,
        status: summary.status,
        message: summary.message,
        final_: summary.final_,
        zeno: summary.zeno.collect(),
        events: EventCounts {
            impact: count(zenosim::EventKind::Impact),
            zeno: count(zenosim::EventKind::Zeno),
            liftoff: count(zenosim::EventKind::Liftoff),
        },
        stats: summary.stats,
        wall_time_s: *time,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timings_have_a_median() {
        let t = summarise(&mut [3.0, 1.0, 2.0]);
        assert_eq!((t.median, t.min, t.max, t.repeats), (2.0, 1.0, 3.0, 3));
        assert_eq!(summarise(&mut [4.0, 1.0, 2.0, 3.0]).median, 2.5);
    }

    #[test]
    fn measuring_repeats_at_least_three_times() {
        let mut calls = 0;
        let t = measure(0.0, || calls += 1);
        assert_eq!(t.repeats, MIN_REPEATS);
        assert_eq!(calls, MIN_REPEATS + 1, "one more, untimed, to warm up");
    }

    #[test]
    fn durations_are_written_in_their_unit() {
        assert_eq!(seconds(4.6e-4), "460.0 µs");
        assert_eq!(seconds(0.0123), "12.300 ms");
        assert_eq!(seconds(2.5), "2.500 s");
    }
}
