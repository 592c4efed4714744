//! `zenosim run`: the files it writes, their contents, and the exit status of each outcome.

mod common;

use common::*;
use serde_json::Value;

/// The header the issue specifies, for the ball on the sine surface.
const SINE_HEADER: &str = "t,mode,x1,x2,x3,x1_dot,x2_dot,x3_dot,h_surface,lambda_surface,energy";

#[test]
fn a_run_writes_a_complete_trajectory_and_summary() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.run(&[]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"],
        "no temporary file is left"
    );

    let csv = Csv::read(&out.join("trajectory.csv"));
    assert_eq!(csv.header.join(","), SINE_HEADER);
    assert!(csv.rows.len() > 100);
    assert!(
        csv.rows.windows(2).all(|w| w[0].t <= w[1].t),
        "t never decreases"
    );
    assert!(csv
        .rows
        .iter()
        .all(|r| r.mode == "free" || r.mode == "constrained:surface"));
    assert_eq!(csv.rows[0].t, 0.0);

    let s = summary(&out);
    assert_eq!(s["model"], "ball-on-sine");
    assert_eq!(s["status"], "finished");
    assert!(s["message"].as_str().is_some_and(|m| !m.is_empty()));
    assert_eq!(s["coordinates"], serde_json::json!(["x1", "x2", "x3"]));
    assert_eq!(
        s["velocities"],
        serde_json::json!(["x1_dot", "x2_dot", "x3_dot"])
    );
    assert_eq!(s["constraints"], serde_json::json!(["surface"]));
    assert_eq!(s["parameters"]["g"], 9.81);
    assert_eq!(s["settings"]["t_end"], 6.0);
    assert_eq!(s["settings"]["zeno"], "auto");
    assert_eq!(s["settings"]["dt"], Value::Null);

    // The final state is the CSV's last row.
    let last = csv.rows.last().unwrap();
    let fin = &s["final"];
    assert_eq!(fin["t"].as_f64(), Some(last.t));
    assert_eq!(fin["t"].as_f64(), Some(6.0));
    // The CSV's mode names the held constraints after the summary's mode.
    let held = fin["active"].as_array().unwrap().iter();
    let held: Vec<&str> = held.map(|a| a.as_str().unwrap()).collect();
    let mode = match fin["mode"].as_str().unwrap() {
        "free" => "free".to_string(),
        other => format!("{other}:{}", held.join("+")),
    };
    assert_eq!(mode, last.mode);
    assert_eq!(numbers(&fin["q"]), last.values[0..3]);
    assert_eq!(numbers(&fin["q_dot"]), last.values[3..6]);
    let active = fin["active"].as_array().unwrap();
    match last.mode.as_str() {
        "free" => assert!(active.is_empty()),
        _ => assert_eq!(fin["active"], serde_json::json!(["surface"])),
    }

    // The paper's numbers: 26 impacts, then the switch at t ≈ 2.0456 (README).
    let zeno = s["zeno"].as_array().unwrap();
    assert_eq!(zeno.len(), 1);
    let z = &zeno[0];
    assert_eq!(z["constraint"], "surface");
    assert_eq!(z["kind"], "genuine");
    let t_zeno = z["t_zeno"].as_f64().unwrap();
    let t_switch = z["t_switch"].as_f64().unwrap();
    assert!((t_zeno - 2.0456).abs() < 1e-3, "τ∞ = {t_zeno}");
    assert!(t_switch <= t_zeno + 1e-9 && t_zeno - t_switch < 1e-3);
    assert!(z["impacts"].as_u64().unwrap() > 10);
    // Schema 4: the point's state is its `zeno` event's `after`, not repeated.
    assert!(z.get("point").is_none(), "{z}");
    let event = &s["events"][z["event"].as_u64().unwrap() as usize];
    assert_eq!(event["kind"], "zeno");
    assert_eq!(event["t"], z["t_switch"]);
    let q = event["after"].get("q").unwrap_or(&event["before"]["q"]);
    assert_eq!(numbers(q).len(), 3);
    assert_eq!(numbers(&event["after"]["q_dot"]).len(), 3);
    assert!(z["ratio"].as_f64().is_some_and(|r| (r - 0.6).abs() < 0.05));

    // Every event's states are rows of the CSV: the one before and the one after.
    let events = s["events"].as_array().unwrap();
    let impacts = events.iter().filter(|e| e["kind"] == "impact").count();
    assert_eq!(s["stats"]["impacts"].as_u64(), Some(impacts as u64));
    assert!(events.iter().any(|e| e["kind"] == "zeno"));
    for e in events {
        assert!(["impact", "zeno", "liftoff"].contains(&e["kind"].as_str().unwrap()));
        assert_eq!(e["constraint"], "surface");
        let t = e["t"].as_f64().unwrap();
        for side in ["before", "after"] {
            // Schema 4: `after` leaves out a `q` unchanged from `before`.
            let q = numbers(e[side].get("q").unwrap_or(&e["before"]["q"]));
            let q_dot = numbers(&e[side]["q_dot"]);
            assert!(
                csv.rows
                    .iter()
                    .any(|r| r.t == t && r.values[0..3] == q[..] && r.values[3..6] == q_dot[..]),
                "the state {side} the {} at t = {t} is a row of the CSV",
                e["kind"]
            );
        }
    }

    for key in [
        "steps",
        "rejected_steps",
        "rhs_evals",
        "impacts",
        "spurious_events",
    ] {
        assert!(s["stats"][key].is_u64(), "stats.{key}");
    }
    assert_eq!(
        s["trajectory"]["rows"].as_u64(),
        Some(csv.rows.len() as u64)
    );
    let intervals = s["intervals"].as_array().unwrap();
    assert_eq!(intervals.len(), events.len() + 1);
    assert_eq!(intervals.last().unwrap()["end"].as_f64(), Some(6.0));

    // The report names the outcome and the files.
    let report = stdout(&output);
    assert!(report.contains("finished"), "{report}");
    assert!(
        report.contains("trajectory.csv") && report.contains("summary.json"),
        "{report}"
    );
    assert!(report.contains("genuine"), "{report}");
}

#[test]
fn the_constrained_phase_has_its_multiplier_and_stays_on_the_surface() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&[]), 0);
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        "t,mode,x,x_dot,h_floor,lambda_floor,energy"
    );
    let constrained: Vec<_> = csv
        .rows
        .iter()
        .filter(|r| r.mode == "constrained:floor")
        .collect();
    assert!(!constrained.is_empty());
    for r in constrained {
        assert!(r.values[2].abs() < 1e-9, "h = 0 at t = {}", r.t);
        // At rest on the floor the contact holds the weight: λ = −m g.
        assert!((r.values[3] + 9.81).abs() < 1e-6, "λ = {}", r.values[3]);
    }
    let s = summary(&scratch.path("out"));
    assert_eq!(s["final"]["mode"], "constrained");
    assert_eq!(s["final"]["active"], serde_json::json!(["floor"]));
    assert_eq!(s["description"], "A ball dropped on a floor");
    assert_eq!(s["restitutions"]["floor"], 0.5);
    // τ∞ = √(2/g)·(1+e)/(1−e), the closed form.
    let tau = (2.0 / 9.81_f64).sqrt() * 3.0;
    let t_zeno = s["zeno"][0]["t_zeno"].as_f64().unwrap();
    assert!((t_zeno - tau).abs() < 1e-8, "{t_zeno} vs {tau}");
}

#[test]
fn an_autonomous_run_keeps_its_columns_and_balances_its_energy_with_the_impacts() {
    let scratch = Scratch::new(BALL);
    let output = scratch.run(&[]);
    assert_exit(&output, 0);
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        "t,mode,x,x_dot,h_floor,lambda_floor,energy",
        "no energy balance columns for an autonomous model"
    );
    let s = summary(&scratch.path("out"));
    assert_eq!(s["schema_version"], 4);
    let b = &s["energy_balance"];
    let energy = csv.column("energy");
    let (first, last) = (&csv.rows[0], csv.rows.last().unwrap());
    assert_eq!(b["energy_start"].as_f64(), Some(first.values[energy]));
    assert_eq!(b["energy_end"].as_f64(), Some(last.values[energy]));
    assert_eq!(b["energy_end"], s["final"]["energy"]);
    for key in ["work_forces", "work_drive", "work_constraints"] {
        assert_eq!(b[key], 0.0, "{key}");
    }
    // Dropped from 1 and at rest on the floor at the end: the impacts took m g.
    let loss = b["impact_loss"].as_f64().unwrap();
    assert!((loss - 9.81).abs() < 1e-8, "impact loss {loss}");
    let residual = b["residual"].as_f64().unwrap();
    assert!(
        residual.abs() <= 1e-7 * balance_scale(b),
        "residual {residual}"
    );
    // The report says nothing of the balance: the impacts alone change the energy.
    assert!(!stdout(&output).contains("energy:"), "{}", stdout(&output));
}

#[test]
fn a_model_with_forces_writes_the_energy_balance() {
    let scratch = Scratch::new(DRAGGED_BALL);
    let output = scratch.run(&["--plot"]);
    assert_exit(&output, 0);
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    assert_eq!(
        csv.header.join(","),
        format!("t,mode,y,y_dot,h_floor,lambda_floor,energy,{WORK_COLUMNS}")
    );
    let column = |name: &str| csv.column(name);
    let (energy, forces, drive, constraints, loss) = (
        column("energy"),
        column("work_forces"),
        column("work_drive"),
        column("work_constraints"),
        column("impact_loss"),
    );
    // E(t) − E(0) = work_forces + work_drive + work_constraints − impact_loss on every row.
    let e0 = csv.rows[0].values[energy];
    assert_eq!(e0, 9.81);
    for r in &csv.rows {
        let v = &r.values;
        let balance = v[forces] + v[drive] + v[constraints] - v[loss];
        let size = e0.abs() + v[energy].abs() + v[forces].abs() + v[loss].abs();
        assert!(
            (v[energy] - e0 - balance).abs() <= 1e-7 * size,
            "t = {}: E − E(0) = {}, balance {balance}",
            r.t,
            v[energy] - e0
        );
        assert!(v[forces] <= 0.0, "the drag dissipates");
        assert_eq!((v[drive], v[constraints]), (0.0, 0.0), "nothing moves");
        assert!(v[loss] >= 0.0);
    }

    let s = summary(&scratch.path("out"));
    let b = &s["energy_balance"];
    assert_eq!(b["energy_start"].as_f64(), Some(e0));
    let last = csv.rows.last().unwrap();
    assert_eq!(b["energy_end"].as_f64(), Some(last.values[energy]));
    for (key, column) in [("work_forces", forces), ("impact_loss", loss)] {
        let total = b[key].as_f64().unwrap();
        assert!(
            (total - last.values[column]).abs() <= 1e-12 * e0,
            "{key}: {total} in the summary, {} on the last row",
            last.values[column]
        );
    }
    assert!(b["work_forces"].as_f64().unwrap() < 0.0);
    assert!(b["impact_loss"].as_f64().unwrap() > 0.0);
    let residual = b["residual"].as_f64().unwrap();
    assert!(
        residual.abs() <= 1e-7 * balance_scale(b),
        "residual {residual}"
    );

    let report = stdout(&output);
    let line = report
        .lines()
        .find(|l| l.trim_start().starts_with("energy:"))
        .unwrap_or_else(|| panic!("an energy line: {report}"));
    assert!(
        line.contains("forces") && line.contains("impact loss") && line.contains("residual"),
        "{line}"
    );
    let svg = std::fs::read_to_string(scratch.path("out/energy.svg")).unwrap();
    assert!(svg.contains(r#"data-name="E(0) + work − impact loss""#));
}

#[test]
fn zeno_off_stalls_at_the_zeno_point_with_exit_3() {
    let scratch = Scratch::new(BALL);
    let output = scratch.run(&["--zeno", "off"]);
    assert_exit(&output, 3);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["status"], "zeno_stalled");
    assert_eq!(s["settings"]["zeno"], "off");
    let tau = (2.0 / 9.81_f64).sqrt() * 3.0;
    assert!((s["final"]["t"].as_f64().unwrap() - tau).abs() < 1e-6);
    assert!(s["message"].as_str().unwrap().contains("Zeno"));
    assert_eq!(s["zeno"].as_array().unwrap().len(), 1);
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    assert!(csv.rows.iter().all(|r| r.mode == "free"));
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
}

#[test]
fn the_papers_epsilon_rule_switches_early() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--zeno", "1e-3"]), 0);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["settings"]["zeno"], serde_json::json!({"epsilon": 0.001}));
    let z = &s["zeno"][0];
    let (t_switch, t_zeno) = (
        z["t_switch"].as_f64().unwrap(),
        z["t_zeno"].as_f64().unwrap(),
    );
    assert!(t_switch < t_zeno, "{t_switch} < {t_zeno}");
    // Fewer impacts than with the automatic rule, which resolves them to the tolerance.
    let auto = Scratch::new(BALL_ON_SINE);
    assert_exit(&auto.run(&[]), 0);
    let auto = summary(&auto.path("out"));
    assert!(s["stats"]["impacts"].as_u64() < auto["stats"]["impacts"].as_u64());
}

#[test]
fn set_changes_a_parameter_and_an_initial_value() {
    let scratch = Scratch::new(BALL);
    // τ∞ = 3√(2/g) ≈ 1.35 for e = 0.5, 9√(2/g) ≈ 4.06 for e = 0.8: run past both.
    assert_exit(&scratch.run(&["--t-end", "5"]), 0);
    let base = summary(&scratch.path("out"));
    assert_exit(&scratch.run(&["--t-end", "5", "--set", "e=0.8"]), 0);
    let bouncier = summary(&scratch.path("out"));
    assert_eq!(bouncier["parameters"]["e"], 0.8);
    assert_eq!(bouncier["restitutions"]["floor"], 0.8);
    assert!(
        bouncier["stats"]["impacts"].as_u64() > base["stats"]["impacts"].as_u64(),
        "a higher restitution bounces more"
    );

    assert_exit(&scratch.run(&["--set", "x=2", "--set", "g=2*4.905"]), 0);
    let higher = summary(&scratch.path("out"));
    assert_eq!(higher["initial"]["q"], serde_json::json!([2.0]));
    let first = higher["events"][0]["t"].as_f64().unwrap();
    let expected = (2.0 * 2.0 / 9.81_f64).sqrt();
    assert!(
        (first - expected).abs() < 1e-9,
        "first impact at {first}, expected {expected}"
    );
}

#[test]
fn flags_override_the_files_settings() {
    let scratch = Scratch::new(BALL);
    let output = scratch.run(&["--t-end", "0.5", "--rtol", "1e-8", "--atol", "1e-9"]);
    assert_exit(&output, 0);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["settings"]["t_end"], 0.5);
    assert_eq!(s["settings"]["rtol"], 1e-8);
    assert_eq!(s["settings"]["atol"], 1e-9);
    assert_eq!(s["final"]["t"], 0.5);
}

#[test]
fn dt_samples_uniformly_apart_from_the_events() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--dt", "0.01"]), 0);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["settings"]["dt"], 0.01);
    let event_times: Vec<f64> = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["t"].as_f64().unwrap())
        .collect();
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    let grid: Vec<f64> = csv
        .rows
        .iter()
        .map(|r| r.t)
        .filter(|t| !event_times.contains(t))
        .collect();
    assert_eq!(grid.len(), 601, "t = 0, 0.01, …, 6");
    for (k, t) in grid.iter().enumerate() {
        assert!((t - k as f64 * 0.01).abs() < 1e-12, "row {k} at t = {t}");
    }
    // Each event has its two rows.
    for t in &event_times {
        assert!(
            csv.rows.iter().filter(|r| r.t == *t).count() >= 2,
            "t = {t}"
        );
    }
}

#[test]
fn a_failing_run_keeps_what_it_computed_with_exit_1() {
    // The ball takes 49 steps to t = 2: a limit of 20 stops it before its Zeno point.
    let scratch = Scratch::new(&BALL.replace("t_end = 2.0", "t_end = 2.0\nmax_steps = 20"));
    let output = scratch.run(&[]);
    assert_exit(&output, 1);
    let err = stderr(&output);
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains("limit"), "{err}");
    let out = scratch.path("out");
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
    let s = summary(&out);
    assert_eq!(s["status"], "failed");
    assert!(
        s["message"].as_str().unwrap().contains("limit of 20 steps"),
        "{}",
        s["message"]
    );
    let csv = Csv::read(&out.join("trajectory.csv"));
    assert!(!csv.rows.is_empty());
    let last = csv.rows.last().unwrap();
    assert_eq!(s["final"]["t"].as_f64(), Some(last.t));
    assert_eq!(numbers(&s["final"]["q"]), last.values[0..1]);
    assert!(last.t < 2.0);
}

#[test]
fn too_many_events_fail_too() {
    let scratch = Scratch::new(&BALL.replace("t_end = 2.0", "t_end = 2.0\nmax_events = 5"));
    let output = scratch.run(&[]);
    assert_exit(&output, 1);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["status"], "failed");
    assert_eq!(s["events"].as_array().unwrap().len(), 5);
}

#[test]
fn the_default_output_directory_is_out_slash_the_model_name() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.zenosim(&["run", "model.toml", "--t-end", "0.1"]);
    assert_exit(&output, 0);
    let dir = scratch.path("out/ball-on-sine");
    assert_eq!(
        files(&dir),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
    assert!(stdout(&output).contains("out/ball-on-sine/trajectory.csv"));
}

#[test]
fn a_rerun_replaces_the_files() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--t-end", "0.2"]), 0);
    assert_exit(&scratch.run(&["--t-end", "0.3"]), 0);
    let s = summary(&scratch.path("out"));
    assert_eq!(s["final"]["t"], 0.3);
    let csv = Csv::read(&scratch.path("out/trajectory.csv"));
    assert_eq!(csv.rows.last().unwrap().t, 0.3);
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
}

#[test]
fn an_unwritable_output_directory_is_exit_1_naming_it() {
    let scratch = Scratch::new(BALL);
    std::fs::write(scratch.path("plain-file"), "").unwrap();
    let output = scratch.zenosim(&["run", "model.toml", "--out", "plain-file/sub"]);
    assert_exit(&output, 1);
    let err = stderr(&output);
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains("plain-file/sub"), "{err}");
}

/// Regression (a full disk): the run simulated to its end before saying that nothing could be
/// written; it now stops at the first failed write, keeping no temporary file. Files limited to
/// 8 KB stand for the disk (a write past the limit fails with EFBIG); the run asks for 10⁷ rows,
/// minutes of simulation, and must end within seconds.
#[cfg(unix)]
#[test]
fn a_full_disk_stops_the_run_at_once_exit_1_leaving_no_partial_file() {
    let scratch = Scratch::new(BALL);
    let started = std::time::Instant::now();
    let output = scratch.zenosim_limited(16, &LONG_RUN);
    assert!(started.elapsed().as_secs() < 30, "{:?}", started.elapsed());
    assert_exit(&output, 1);
    let err = stderr(&output);
    assert!(err.contains("cannot write "), "{err}");
    assert!(err.contains("trajectory.csv"), "{err}");
    assert!(
        files(&scratch.path("out")).is_empty(),
        "{:?}",
        files(&scratch.path("out"))
    );
}

/// Regression (issue 25: output bounded only by the row limit, a 6.4 KB model wrote 21 GB):
/// `--max-output` caps trajectory.csv. A model file asking for 10⁷ rows (about 700 MB) under a
/// cap of 100 KiB stops at once: the file is valid CSV, holds the rows up to the cap and then
/// the final state (one row past the cap at most), summary.json says `failed` and why, the exit
/// status is 1, and the message names the cap, the file and what to do. The model file cannot
/// raise the cap itself.
#[test]
fn the_output_cap_stops_the_run_keeping_its_rows_and_saying_what_to_do() {
    let hostile = BALL.replace("t_end = 2.0", "t_end = 1e4\ndt = 1e-3");
    let scratch = Scratch::new(&hostile);
    let started = std::time::Instant::now();
    let output = scratch.run(&["--max-output", "100K"]);
    assert!(started.elapsed().as_secs() < 30, "{:?}", started.elapsed());
    assert_exit(&output, 1);
    let out = scratch.path("out");
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"]
    );

    let cap = 100 * 1024;
    let text = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let last_row = text.lines().last().unwrap().len() as u64 + 1;
    let size = text.len() as u64;
    assert!(size <= cap + last_row, "{size} bytes");
    // Filled to the cap, less than a row short.
    assert!(size + 2 * last_row > cap, "{size} bytes");
    let csv = Csv::read(&out.join("trajectory.csv"));
    assert!(csv.rows.len() > 1000, "{} rows", csv.rows.len());

    let s = summary(&out);
    assert_eq!(s["status"], "failed");
    let message = s["message"].as_str().unwrap();
    for part in [
        "trajectory.csv",
        "output cap of 100 KiB",
        "--max-output",
        "--dt",
        "--t-end",
    ] {
        assert!(message.contains(part), "{part}: {message}");
    }
    assert_eq!(
        s["trajectory"]["rows"].as_u64(),
        Some(csv.rows.len() as u64)
    );
    // The file ends with the final state, as every run's does.
    let last = csv.rows.last().unwrap();
    assert_eq!(s["final"]["t"].as_f64(), Some(last.t));
    assert_eq!(numbers(&s["final"]["q"]), last.values[0..1]);
    assert_eq!(numbers(&s["final"]["q_dot"]), last.values[1..2]);
    assert!(last.t < 10.0, "t = {}", last.t);

    let err = stderr(&output);
    for part in [
        "error: the run stopped at t = ",
        "out/trajectory.csv reached the output cap of 100 KiB (--max-output)",
        &format!("it holds {} rows", csv.rows.len()),
        "status failed",
        "--max-output 200KiB",
        "a coarser --dt, or an earlier --t-end",
    ] {
        assert!(err.contains(part), "{part}: {err}");
    }
    let report = stdout(&output);
    assert!(report.contains("status:  failed"), "{report}");

    // The cap is the command line's: a model file cannot raise it.
    let raised = Scratch::new(&hostile.replace("dt = 1e-3", "dt = 1e-3\nmax_output = \"1T\""));
    assert_exit(&raised.run(&[]), 2);
    assert!(!raised.path("out").exists());
    // Its default is 1 GiB.
    let help = stdout(&scratch.zenosim(&["run", "--help"]));
    assert!(help.contains("--max-output <SIZE>"), "{help}");
    assert!(help.contains("[default: 1GiB]"), "{help}");
}

/// Regression: a symlink planted in the output directory under the temporary name
/// (`.trajectory.csv.partial -> ~/anything`) made the run overwrite its target with the
/// user's rights. Temporary files are now created exclusively under names of their own
/// (`.<name>.<pid>-<n>.partial`), one of that form left stale is removed (the link, never its
/// target), one of another form is left alone, and a symlink under a final name is replaced by
/// the file, not written through.
#[cfg(unix)]
#[test]
fn symlinks_planted_in_the_output_directory_are_never_followed() {
    let scratch = Scratch::new(BALL);
    let out = scratch.path("out");
    std::fs::create_dir(&out).unwrap();
    let victim = scratch.path("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    for name in [
        ".trajectory.csv.partial",
        ".trajectory.csv.4000000-0.partial",
        ".summary.json.4000000-1.partial",
        "trajectory.csv",
    ] {
        std::os::unix::fs::symlink(&victim, out.join(name)).unwrap();
    }
    assert_exit(&scratch.run(&[]), 0);
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert_eq!(
        files(&out),
        [
            ".trajectory.csv.partial",
            "model.toml",
            "summary.json",
            "trajectory.csv"
        ]
    );
    let csv = std::fs::symlink_metadata(out.join("trajectory.csv")).unwrap();
    assert!(csv.file_type().is_file());
}

/// `.trajectory.csv.<pid>-<n>.partial` files in `dir`.
fn partials(dir: &std::path::Path) -> Vec<String> {
    files(dir)
        .into_iter()
        .filter(|name| name.starts_with(".trajectory.csv.") && name.ends_with(".partial"))
        .collect()
}

/// A run of 10⁷ rows into `out`: minutes of writing.
const LONG_RUN: [&str; 8] = [
    "run",
    "model.toml",
    "--out",
    "out",
    "--t-end",
    "1e4",
    "--dt",
    "1e-3",
];

/// Starts [`LONG_RUN`] and waits until it has written 100 kB of its rows.
fn start_long_run(scratch: &Scratch) -> std::process::Child {
    let mut child = std::process::Command::new(binary())
        .args(LONG_RUN)
        .current_dir(scratch.dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let out = scratch.path("out");
    let started = std::time::Instant::now();
    let written = || {
        if !out.exists() {
            return 0;
        }
        partials(&out).first().map_or(0, |name| {
            std::fs::metadata(out.join(name)).map_or(0, |m| m.len())
        })
    };
    while written() < 100_000 {
        assert!(
            started.elapsed().as_secs() < 60,
            "the run never started writing"
        );
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child
}

/// Regression: two runs into one output directory shared the temporary names, so one printed
/// "wrote summary.json" while no summary was left and trajectory.csv held the other's rows.
/// The directory is now locked while a run writes into it: the second fails at once, saying
/// why, and the first completes.
#[test]
fn a_second_run_into_a_directory_being_written_fails_at_once() {
    let scratch = Scratch::new(BALL);
    let mut first = start_long_run(&scratch);
    let second = scratch.run(&["--t-end", "0.2"]);
    first.kill().unwrap();
    first.wait().unwrap();
    assert_exit(&second, 1);
    let err = stderr(&second);
    assert!(
        err.contains("another zenosim is writing into this directory"),
        "{err}"
    );
    // Once the first is gone, the directory is free again.
    assert_exit(&scratch.run(&["--t-end", "0.2"]), 0);
}

#[test]
fn a_killed_run_leaves_the_previous_results_as_they_were() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--t-end", "0.3"]), 0);
    let out = scratch.path("out");
    let read = |name: &str| std::fs::read(out.join(name)).unwrap();
    let (old_summary, old_csv) = (read("summary.json"), read("trajectory.csv"));

    // A run of 10⁷ rows, killed (SIGKILL: no chance to clean up) once it is writing.
    let mut child = start_long_run(&scratch);
    child.kill().unwrap();
    child.wait().unwrap();

    // The previous results are untouched; the killed run's rows are only in its hidden
    // temporary file, never under a name that looks complete.
    assert_eq!(read("summary.json"), old_summary);
    assert_eq!(read("trajectory.csv"), old_csv);
    assert_eq!(partials(&out).len(), 1, "{:?}", files(&out));
    assert_eq!(files(&out).len(), 4, "{:?}", files(&out));
    // The next run completes and removes the killed run's temporary file.
    assert_exit(&scratch.run(&["--t-end", "0.2"]), 0);
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
    assert_eq!(summary(&out)["final"]["t"], 0.2);
}

/// Sends `signal` (`INT`, `TERM`) to `child`.
#[cfg(unix)]
fn send(child: &std::process::Child, signal: &str) {
    let status = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// `child`'s exit code, waiting at most a minute.
fn exit_within_a_minute(child: &mut std::process::Child) -> Option<i32> {
    let started = std::time::Instant::now();
    while started.elapsed().as_secs() < 60 {
        if let Some(status) = child.try_wait().unwrap() {
            return status.code();
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.kill().unwrap();
    None
}

/// Regression: Ctrl-C killed the run with no message and no summary.json, leaving a hidden
/// truncated temporary file. SIGINT and SIGTERM now stop the run at its next step and write
/// everything computed, status "interrupted", exit status 128 + the signal.
#[cfg(unix)]
#[test]
fn sigint_and_sigterm_keep_the_run_computed_so_far() {
    for (signal, code) in [("INT", 130), ("TERM", 143)] {
        let scratch = Scratch::new(BALL);
        assert_exit(&scratch.run(&["--t-end", "0.3"]), 0);
        let mut child = start_long_run(&scratch);
        send(&child, signal);
        assert_eq!(exit_within_a_minute(&mut child), Some(code), "SIG{signal}");
        let out = scratch.path("out");
        assert_eq!(
            files(&out),
            ["model.toml", "summary.json", "trajectory.csv"],
            "SIG{signal}"
        );
        let s = summary(&out);
        assert_eq!(s["status"], "interrupted");
        let t = s["final"]["t"].as_f64().unwrap();
        assert!(t > 0.3 && t < 1e4, "t = {t}");
        let csv = Csv::read(&out.join("trajectory.csv"));
        assert_eq!(
            csv.rows.len() as u64,
            s["trajectory"]["rows"].as_u64().unwrap()
        );
        assert_eq!(csv.rows.last().unwrap().t, t);
    }
}

/// A second Ctrl-C stops at once: the previous results stay as they were, or the interrupted
/// run's are complete, and no temporary file is left either way.
#[cfg(unix)]
#[test]
fn a_second_sigint_stops_at_once_leaving_no_temporary_file() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--t-end", "0.3"]), 0);
    let out = scratch.path("out");
    let old_summary = std::fs::read(out.join("summary.json")).unwrap();
    let mut child = start_long_run(&scratch);
    send(&child, "INT");
    send(&child, "INT");
    assert_eq!(exit_within_a_minute(&mut child), Some(130));
    assert_eq!(
        files(&out),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
    let s = summary(&out);
    let now = std::fs::read(out.join("summary.json")).unwrap();
    assert!(now == old_summary || s["status"] == "interrupted");
}

/// Regression (issue 24): the terminal summary printed a line per Zeno point (4007 lines for
/// the vibrating table to t = 400). It stays a few lines: the count, the ranges of impacts and
/// ratios, the first and the last.
#[test]
fn the_terminal_summary_printed_a_line_per_zeno_point() {
    let source = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/vibrating-table.toml"),
    )
    .unwrap();
    let scratch = Scratch::new(&source);
    let output = scratch.run(&["--t-end", "40", "--plot"]);
    assert_exit(&output, 0);
    let s = summary(&scratch.path("out"));
    let count = s["zeno"].as_array().unwrap().len();
    assert!(count > 300, "{count}");
    let report = stdout(&output);
    assert!(report.lines().count() < 20, "{report}");
    assert!(
        report.contains(&format!("  zeno:    {count} Zeno points ({count} genuine")),
        "{report}"
    );
    let first = s["zeno"][0]["t_switch"].as_f64().unwrap();
    let last = s["zeno"][count - 1]["t_switch"].as_f64().unwrap();
    assert!(report.contains("  first:   genuine on 'table'"), "{report}");
    assert!(
        report.contains(&format!("switched at t = {first}")),
        "{report}"
    );
    assert!(
        report.contains(&format!("switched at t = {last}")),
        "{report}"
    );
    assert!(report.contains("ratios 0.19"), "{report}");
}

/// Regression (issue 24): a ball started at rest on the floor was reported as "a Zeno point
/// after 1 impact" (`ratio` null). It says it started there, held.
#[test]
fn a_start_at_rest_was_reported_as_a_zeno_point() {
    let scratch = Scratch::new(&BALL.replace("x = 1.0", "x = 0.0"));
    let output = scratch.run(&[]);
    assert_exit(&output, 0);
    let report = stdout(&output);
    assert!(
        report.starts_with("ball: started at rest on 'floor': held from t = 0; finished at t = 2"),
        "{report}"
    );
    assert!(!report.contains("zeno:"), "{report}");
    let s = summary(&scratch.path("out"));
    assert_eq!(s["zeno"].as_array().unwrap().len(), 0);
    assert_eq!(s["events"].as_array().unwrap().len(), 0);
    assert_eq!(s["intervals"][0]["mode"], "constrained");
}

/// `summary.json` was not bounded by `--max-output`: with `--max-output 20M` a run wrote
/// 49 MiB (its events). The cap now covers it too: its lists of Zeno points, events and
/// intervals keep their first items that fit, `truncated` says how many there were, and the
/// run says so (status failed, exit 1, what to do).
#[test]
fn summary_json_is_bounded_by_the_output_cap() {
    // An elastic ball bounces for ever: 4000 impacts to t = 3600, 0.86 MB of trajectory (two
    // rows an impact) and 1.3 MB of summary.
    let scratch = Scratch::new(&BALL.replace("e = 0.5", "e = 1.0"));
    let output = scratch.run(&[
        "--t-end",
        "3600",
        "--dt",
        "100",
        "--max-events",
        "100000",
        "--max-output",
        "1200K",
    ]);
    assert_exit(&output, 1);
    let error = stderr(&output);
    assert!(
        error.contains("summary.json reached the output cap of 1200 KiB")
            && error.contains("--max-output 2400KiB"),
        "{error}"
    );
    let out = scratch.path("out");
    let total: u64 = ["summary.json", "trajectory.csv", "model.toml"]
        .iter()
        .map(|f| std::fs::metadata(out.join(f)).unwrap().len())
        .sum();
    assert!(total <= 1200 * 1024, "{total} bytes");
    let capped = summary(&out);
    assert_eq!(capped["status"], "failed");
    let events = capped["events"].as_array().unwrap().len();
    let all = capped["truncated"]["events"].as_u64().unwrap() as usize;
    assert!(
        all > 3000 && events > 100 && events < all,
        "{events} of {all}"
    );
    assert!(capped["message"]
        .as_str()
        .unwrap()
        .contains(&format!("the first {events} of the {all} events")));
    // Under the default cap nothing is cut, and `truncated` is left out.
    let output = scratch.run(&["--t-end", "3600", "--dt", "100", "--max-events", "100000"]);
    assert_exit(&output, 0);
    let whole = summary(&out);
    assert!(whole.get("truncated").is_none());
    assert_eq!(whole["events"].as_array().unwrap().len(), all);
}

/// A model file raised the limits that bound a run's memory: two elastic walls 1e-9 apart
/// with `max_events = max_steps = 100000000` in `[simulation]` held every event (Python died
/// when memory ran out). A file may lower the limits, never raise them past the defaults;
/// the command line raises them.
#[test]
fn a_model_file_cannot_raise_the_limits() {
    let scratch = Scratch::new(
        "name = \"walls\"\ncoordinates = [\"x\"]\nlagrangian = \"0.5*x_dot^2\"\n\
         [[constraint]]\nname = \"left\"\nh = \"x\"\nrestitution = 1.0\n\
         [[constraint]]\nname = \"right\"\nh = \"1e-9 - x\"\nrestitution = 1.0\n\
         [initial]\nx = 5e-10\nx_dot = 1.0\n\
         [simulation]\nt_end = 1.0\nmax_events = 100000000\nmax_steps = 100000000\n",
    );
    let output = scratch.run(&[]);
    assert_exit(&output, 1);
    let summary = summary(&scratch.path("out"));
    let message = summary["message"].as_str().unwrap();
    assert!(message.contains("the limit of 100000 events"), "{message}");
    assert!(message.contains("may only lower the limit"), "{message}");
    // The command line raises it (and a file's lower value stands).
    let output = scratch.run(&["--max-events", "150000"]);
    assert_exit(&output, 1);
    let message = common::summary(&scratch.path("out"))["message"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(message.contains("the limit of 150000 events"), "{message}");
}
