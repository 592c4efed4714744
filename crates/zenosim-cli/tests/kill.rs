//! The kill loop of issue 25: runs into a folder holding an earlier complete run, stopped by
//! SIGKILL, SIGINT, SIGTERM or two SIGINTs at random moments (a seeded generator: the same
//! signals and moments every time, up to the machine's timing), 50 times. Each leaves the earlier
//! results, or a new complete run, or an `interrupted` run complete up to its last step: never a
//! mix, and no temporary file but those of a process killed outright (SIGKILL, or a signal before
//! the handlers are installed), which the next run removes (src/output.rs). A folder without
//! `summary.json` holds no complete run (docs/output.md); only a SIGKILL between the renames of
//! the new files can leave one, in the microseconds they take (it was milliseconds, and this
//! loop met such a folder once or twice in 50 kills: see `output::tests`).
//!
//! `cargo test -p zenosim-cli --test kill -- --nocapture` prints what each signal led to.

#![cfg(unix)]

mod common;

use std::collections::BTreeMap;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::*;
use serde_json::Value;

/// The run that is killed: an elastic ball (it never comes to rest) to t = 20, a row every
/// millisecond (20 000 rows, 2 MB), about 0.1 s here: long enough for the signals to land while
/// it loads, simulates and writes, finishes its files and renames them. Each flight is a step
/// of about 900 rows, so a SIGINT stops it within a few milliseconds. (A ball that comes to
/// rest takes steps that double, the last holding half the rows; a signal is only seen after
/// it.)
const MODEL: (&str, &str) = ("e = 0.5", "e = 1.0");
const T_END: f64 = 20.0;
const RUN: [&str; 8] = [
    "run",
    "model.toml",
    "--out",
    "out",
    "--t-end",
    "20",
    "--dt",
    "1e-3",
];

/// The earlier complete run in the folder: the same model to t = 0.3.
const EARLIER_T_END: f64 = 0.3;

const ITERATIONS: usize = 50;

/// SplitMix64: a small seeded generator (the tests need no crate for it).
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[low, high)`.
    fn between(&mut self, low: Duration, high: Duration) -> Duration {
        low + (high - low).mul_f64(self.unit())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Signal {
    Kill,
    Int,
    Term,
    /// Two SIGINTs: the second stops at once.
    IntTwice,
}

/// The folder's two files, as bytes (`None`: absent).
#[derive(Clone, Debug, PartialEq)]
struct Files {
    summary: Option<Vec<u8>>,
    csv: Option<Vec<u8>>,
}

impl Files {
    fn read(out: &Path) -> Self {
        let read = |name: &str| std::fs::read(out.join(name)).ok();
        Self {
            summary: read("summary.json"),
            csv: read("trajectory.csv"),
        }
    }
}

/// What the folder holds once checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Held {
    /// `status` finished at `t_end`.
    Finished,
    /// An interrupted run, complete up to its last step.
    Interrupted,
    /// `trajectory.csv` without `summary.json`: no complete run.
    NoSummary,
}

/// Checks that the folder holds a complete run whose `summary.json` and `trajectory.csv` belong
/// together (or a complete `trajectory.csv` and no summary), and says which.
fn check(out: &Path, files: &Files, t_ends: &[f64]) -> Held {
    assert!(files.csv.is_some(), "trajectory.csv is always there");
    // Complete rows of the header's width, ending with a newline.
    let csv = Csv::read(&out.join("trajectory.csv"));
    let Some(summary) = &files.summary else {
        return Held::NoSummary;
    };
    let s: Value = serde_json::from_slice(summary).expect("summary.json parses");
    let rows = s["trajectory"]["rows"].as_u64().expect("trajectory.rows");
    assert_eq!(
        rows,
        csv.rows.len() as u64,
        "the summary counts the CSV's rows"
    );
    let last = csv.rows.last().expect("a row");
    let fin = &s["final"];
    let t = fin["t"].as_f64().expect("final.t");
    assert_eq!(t, last.t, "the CSV ends at the summary's final time");
    assert_eq!(numbers(&fin["q"]), last.values[0..1]);
    assert_eq!(numbers(&fin["q_dot"]), last.values[1..2]);
    let intervals = s["intervals"].as_array().expect("intervals");
    assert_eq!(intervals.last().unwrap()["end"].as_f64(), Some(t));
    let t_end = s["settings"]["t_end"].as_f64().expect("settings.t_end");
    assert!(t_ends.contains(&t_end), "t_end = {t_end}");
    match s["status"].as_str() {
        Some("finished") => {
            assert_eq!(t, t_end, "finished at t = {t}");
            Held::Finished
        }
        Some("interrupted") => {
            assert!(t < t_end, "interrupted at t = {t}");
            let message = s["message"].as_str().unwrap();
            assert!(message.starts_with("interrupted at t = "), "{message}");
            Held::Interrupted
        }
        other => panic!("status {other:?}"),
    }
}

/// The hidden temporary files in `out`.
fn partials(out: &Path) -> Vec<String> {
    files(out)
        .into_iter()
        .filter(|name| name.starts_with('.'))
        .inspect(|name| assert!(name.ends_with(".partial"), "a hidden file {name}"))
        .collect()
}

/// Sends `signal` to the process `pid`.
fn send(pid: u32, signal: i32) {
    // SAFETY: `kill` has no memory-safety preconditions; `pid` is our child, not yet waited for.
    let sent = unsafe { libc::kill(pid as libc::pid_t, signal) };
    assert_eq!(sent, 0, "kill({pid}, {signal})");
}

#[test]
fn a_kill_loop_leaves_the_earlier_run_or_a_complete_one_never_a_mix() {
    let started = Instant::now();
    let scratch = Scratch::new(&BALL.replace(MODEL.0, MODEL.1));
    let out = scratch.path("out");
    let earlier_t_end = EARLIER_T_END.to_string();
    assert_exit(&scratch.run(&["--t-end", &earlier_t_end]), 0);
    let t_ends = [EARLIER_T_END, T_END];
    assert_eq!(check(&out, &Files::read(&out), &t_ends), Held::Finished);

    // How long the run takes here, to spread the signals over it.
    let mut times: Vec<Duration> = (0..3)
        .map(|_| {
            let run = Instant::now();
            let output = scratch.zenosim(&[&RUN[..2], &["--out", "timing"], &RUN[4..]].concat());
            assert_exit(&output, 0);
            run.elapsed()
        })
        .collect();
    times.sort();
    let full = times[1];

    let mut random = Random(0x2025_0025);
    let mut seen: BTreeMap<(Signal, String), usize> = BTreeMap::new();
    for iteration in 0..ITERATIONS {
        let before = Files::read(&out);
        let stale = partials(&out);
        let signal = match random.next() % 4 {
            0 => Signal::Kill,
            1 => Signal::Int,
            2 => Signal::Term,
            _ => Signal::IntTwice,
        };
        // A fifth in the first 8 ms (starting, loading the model, the first rows), a fifth
        // around the end (the file synced, the summary, the renames), the rest anywhere.
        let phase = random.unit();
        let delay = if phase < 0.2 {
            random.between(Duration::ZERO, Duration::from_millis(8))
        } else if phase < 0.4 {
            random.between(full.mul_f64(0.8), full.mul_f64(1.1))
        } else {
            random.between(Duration::ZERO, full)
        };
        let second = random.between(Duration::ZERO, Duration::from_millis(5));
        let context = format!("iteration {iteration}: {signal:?} after {delay:?}");
        eprintln!("{context}");

        let mut child = Command::new(binary())
            .args(RUN)
            .current_dir(scratch.dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let pid = child.id();
        std::thread::sleep(delay);
        match signal {
            Signal::Kill => child.kill().unwrap(),
            Signal::Int => send(pid, libc::SIGINT),
            Signal::Term => send(pid, libc::SIGTERM),
            Signal::IntTwice => {
                send(pid, libc::SIGINT);
                std::thread::sleep(second);
                send(pid, libc::SIGINT);
            }
        }
        let output = child.wait_with_output().unwrap();
        let err = stderr(&output);

        let after = Files::read(&out);
        let left = partials(&out);
        let mut visible: Vec<String> = files(&out)
            .into_iter()
            .filter(|name| !name.starts_with('.'))
            .collect();
        visible.retain(|name| name != "summary.json");
        // The model's copy is renamed with the trajectory, each over the previous run's.
        assert_eq!(visible, ["model.toml", "trajectory.csv"], "{context}");
        let unchanged = after == before;
        let held = check(&out, &after, &t_ends);

        let outcome = match (output.status.code(), output.status.signal()) {
            (Some(code), _) => {
                // A process that ended by itself leaves no temporary file, not even the stale
                // ones of those killed before it.
                assert!(left.is_empty(), "{context}: exit {code} left {left:?}");
                match (code, signal) {
                    (0, _) => assert_eq!(held, Held::Finished, "{context}: exit 0"),
                    (130, Signal::Int) | (143, Signal::Term) => {
                        assert_eq!(held, Held::Interrupted, "{context}: exit {code}");
                        let name = if code == 130 { "SIGINT" } else { "SIGTERM" };
                        assert!(
                            err.contains(&format!("interrupted by {name}")),
                            "{context}: {err}"
                        );
                    }
                    // The second SIGINT stops at once, leaving the earlier files; or, during
                    // the renames, once they are done.
                    (130, Signal::IntTwice) => {
                        assert!(unchanged || held != Held::NoSummary, "{context}: exit 130")
                    }
                    _ => panic!("{context}: exit {code}: {err}"),
                }
                format!("exit {code}")
            }
            (None, Some(number)) => {
                // Killed outright: by SIGKILL, or by SIGINT or SIGTERM before the handlers
                // were installed (the first millisecond, before anything is written).
                let own = format!(".{pid}-");
                assert!(
                    left.iter()
                        .all(|name| stale.contains(name) || name.contains(&own)),
                    "{context}: {left:?}"
                );
                if number == libc::SIGKILL {
                    assert_eq!(signal, Signal::Kill, "{context}");
                    // The earlier files, a new complete run, or between the renames the new
                    // (or old) trajectory without a summary.
                } else {
                    assert!(
                        match number {
                            libc::SIGINT => matches!(signal, Signal::Int | Signal::IntTwice),
                            libc::SIGTERM => signal == Signal::Term,
                            _ => false,
                        },
                        "{context}: killed by signal {number}"
                    );
                    assert!(unchanged, "{context}: killed by signal {number}");
                    assert_eq!(left, stale, "{context}");
                }
                format!("killed by signal {number}")
            }
            (None, None) => panic!("{context}: {:?}", output.status),
        };
        let kind = format!("{held:?}{}", if unchanged { " (unchanged)" } else { "" });
        *seen
            .entry((signal, format!("{outcome}, {kind}")))
            .or_default() += 1;
    }

    // The next run removes whatever a killed one left, and completes.
    assert_exit(&scratch.run(&RUN[4..]), 0);
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
    assert_eq!(check(&out, &Files::read(&out), &t_ends), Held::Finished);
    eprintln!("a run to t = {T_END}: {full:?} (median of 3)");
    for ((signal, what), count) in &seen {
        eprintln!("{count:3} × {signal:?}: {what}");
    }
    eprintln!("{ITERATIONS} kills in {:?}", started.elapsed());
}
