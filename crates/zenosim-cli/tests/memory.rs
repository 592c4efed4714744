//! Memory stays flat however long the run: a million accepted steps, streamed to disk, in under
//! 50 MB resident, and their plots drawn in under 50 MB too. Linux only (it reads the child's
//! peak RSS, VmHWM, from /proc).
//!
//! `cargo test -p zenosim-cli --test memory -- --nocapture` prints the figures.

mod common;

/// A ball thrown far above its floor, so that it flies the whole run; `max_step` makes the
/// integrator take 10⁶ steps in t ∈ [0, 1].
#[cfg(target_os = "linux")]
const LONG_FLIGHT: &str = r#"
name = "long-flight"
coordinates = ["x"]
lagrangian = "0.5*x_dot^2 - g*x"

[parameters]
g = 9.81

[[constraint]]
name = "floor"
h = "x"
restitution = 0.5

[initial]
x = 1000.0

[simulation]
t_end = 1.0
max_step = 1e-6
method = "dopri5"
"#;

/// The peak resident set (VmHWM) of process `pid` in kB, if it can be read.
#[cfg(target_os = "linux")]
fn peak_kb(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Runs `zenosim <args>` in `dir`, sampling its resident set: its exit code, its peak RSS in
/// kB and how long it took.
#[cfg(target_os = "linux")]
fn peak_of(dir: &std::path::Path, args: &[&str]) -> (Option<i32>, u64, std::time::Duration) {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};

    let start = Instant::now();
    let mut child = Command::new(common::binary())
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("zenosim starts");
    let pid = child.id();
    let mut peak = 0;
    let status = loop {
        if let Some(kb) = peak_kb(pid) {
            peak = peak.max(kb);
        }
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            break status;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    (status.code(), peak, start.elapsed())
}

#[cfg(target_os = "linux")]
#[test]
fn a_million_steps_stay_under_50_mb() {
    let scratch = common::Scratch::new(LONG_FLIGHT);
    let (code, peak, elapsed) = peak_of(scratch.dir.path(), &["run", "model.toml", "--out", "out"]);
    assert_eq!(code, Some(0));
    let summary = common::summary(&scratch.path("out"));
    let steps = summary["stats"]["steps"].as_u64().unwrap();
    let rows = summary["trajectory"]["rows"].as_u64().unwrap();
    let bytes = std::fs::metadata(scratch.path("out/trajectory.csv"))
        .unwrap()
        .len();
    println!(
        "{steps} steps, {rows} rows, {:.1} MB of CSV in {:.2} s; peak RSS {:.1} MB",
        bytes as f64 / 1e6,
        elapsed.as_secs_f64(),
        peak as f64 / 1024.0
    );
    assert!(steps >= 1_000_000, "{steps} steps");
    assert!(rows > steps);
    assert!(peak > 0, "the peak RSS was read");
    assert!(peak < 50 * 1024, "peak RSS {peak} kB");

    // Its plots: the trajectory is read row by row and decimated, never held whole.
    let (code, peak, elapsed) = peak_of(scratch.dir.path(), &["plot", "out"]);
    assert_eq!(code, Some(0));
    println!(
        "plotted in {:.2} s; peak RSS {:.1} MB",
        elapsed.as_secs_f64(),
        peak as f64 / 1024.0
    );
    assert!(scratch.path("out/figure.svg").exists());
    assert!(peak > 0 && peak < 50 * 1024, "peak RSS {peak} kB");
}

/// Regression: `zenosim plot` allocated its decimated series for every coordinate that
/// summary.json lists before reading any data (50 000 names asked for 21 GB and aborted), and a
/// trajectory of one line of any length was read whole and echoed into the error. The series
/// now share a bounded number of columns, a line longer than any row of the run's columns is
/// refused as it is read, and messages quote at most 200 characters.
#[cfg(target_os = "linux")]
#[test]
fn plot_memory_is_bounded_whatever_summary_json_lists() {
    let scratch = common::Scratch::new(common::BALL);
    let (code, ..) = peak_of(scratch.dir.path(), &["run", "model.toml", "--out", "real"]);
    assert_eq!(code, Some(0));
    let text = std::fs::read_to_string(scratch.path("real/summary.json")).unwrap();
    let mut summary: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = summary["trajectory"]["rows"].as_u64().unwrap();

    // 20 000 coordinates, with a trajectory of that many columns.
    let n = 20_000;
    let names: Vec<String> = (0..n).map(|i| format!("c{i}")).collect();
    let velocities: Vec<String> = names.iter().map(|c| format!("{c}_dot")).collect();
    summary["coordinates"] = serde_json::json!(names);
    summary["velocities"] = serde_json::json!(velocities);
    let wide = scratch.path("wide");
    std::fs::create_dir(&wide).unwrap();
    std::fs::write(wide.join("summary.json"), summary.to_string()).unwrap();
    let mut csv = ["t", "mode"].map(String::from).to_vec();
    csv.extend(names.iter().chain(&velocities).cloned());
    csv.extend(["h_floor", "lambda_floor", "energy"].map(String::from));
    let mut csv = csv.join(",") + "\n";
    for row in 0..rows {
        let zeros = vec!["0"; 2 * n].join(",");
        csv += &format!("{},free,{zeros},1,0,0\n", row as f64 * 1e-3);
    }
    std::fs::write(wide.join("trajectory.csv"), csv).unwrap();
    let (code, peak, elapsed) = peak_of(scratch.dir.path(), &["plot", "wide"]);
    println!(
        "{n} coordinates plotted in {:.2} s; peak RSS {:.1} MB",
        elapsed.as_secs_f64(),
        peak as f64 / 1024.0
    );
    assert_eq!(code, Some(0));
    assert!(peak > 0 && peak < 200 * 1024, "peak RSS {peak} kB");

    // A trajectory of one 20 MB line: refused as it is read, and not echoed.
    let line = scratch.path("line");
    std::fs::create_dir(&line).unwrap();
    std::fs::write(line.join("summary.json"), &text).unwrap();
    let long = format!("t,mode,{}\n", "x".repeat(20_000_000));
    std::fs::write(line.join("trajectory.csv"), long).unwrap();
    let output = scratch.zenosim(&["plot", "line"]);
    common::assert_exit(&output, 2);
    let err = common::stderr(&output);
    assert!(
        err.contains("trajectory.csv:1:") && err.contains("longer than"),
        "{err}"
    );
    assert!(err.len() < 1000, "{} bytes of message", err.len());
}
