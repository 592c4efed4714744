//! `zenosim bench` (a model's runs timed, with their outcomes, as JSON) and `zenosim
//! work-precision` (the diagram drawn from measured points), through the binary.

mod common;

use common::{assert_exit, stderr, stdout, Scratch, BALL};
use serde_json::Value;

fn report(output: &std::process::Output) -> Value {
    serde_json::from_str(&stdout(output)).unwrap_or_else(|e| {
        panic!(
            "stdout is one JSON document ({e}):\n{}\n{}",
            stdout(output),
            stderr(output)
        )
    })
}

#[test]
fn a_run_per_tolerance_with_its_outcome_and_wall_time() {
    let scratch = Scratch::new(BALL);
    let output = scratch.zenosim(&[
        "bench",
        "model.toml",
        "--tolerances",
        "1e-6,1e-10",
        "--min-time",
        "0.01",
    ]);
    assert_exit(&output, 0);
    let report = report(&output);
    assert_eq!(report["model"], "ball");
    assert_eq!(report["parameters"]["e"], 0.5);
    assert_eq!(report["initial"]["q"][0], 1.0);
    assert!(report["load_time_s"]["median"].as_f64().unwrap() > 0.0);
    let runs = report["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    // Closed form: τ∞ = √(2 h0/g) (1+e)/(1−e) for the ball dropped from h0 = 1.
    let tau = (2.0f64 / 9.81).sqrt() * 3.0;
    for (run, tol) in runs.iter().zip([1e-6, 1e-10]) {
        assert_eq!(run["settings"]["rtol"], tol);
        assert_eq!(run["settings"]["atol"], tol);
        assert_eq!(run["status"], "finished");
        assert_eq!(run["final"]["t"], 2.0);
        let zeno = &run["zeno"][0];
        let error = (zeno["t_zeno"].as_f64().unwrap() - tau).abs();
        assert!(error < 100.0 * tol, "τ∞ off by {error} at tol {tol}");
        let impacts = run["events"]["impact"].as_u64().unwrap();
        assert_eq!(impacts, run["stats"]["impacts"].as_u64().unwrap());
        assert_eq!(run["events"]["zeno"], 1);
        assert_eq!(run["events"]["liftoff"], 0);
        let time = &run["wall_time_s"];
        let (min, median, max) = (
            time["min"].as_f64().unwrap(),
            time["median"].as_f64().unwrap(),
            time["max"].as_f64().unwrap(),
        );
        assert!(0.0 < min && min <= median && median <= max, "{time}");
        assert!(time["repeats"].as_u64().unwrap() >= 3);
    }
    // A tighter tolerance takes more impacts before the switch (the remaining bounces must
    // be smaller) and more work.
    let count = |k: usize, what: &str| runs[k]["stats"][what].as_u64().unwrap();
    assert!(count(1, "impacts") > count(0, "impacts"));
    assert!(count(1, "rhs_evals") > count(0, "rhs_evals"));
    // A line per tolerance on stderr.
    let err = stderr(&output);
    assert_eq!(err.lines().count(), 2, "{err}");
    assert!(err.starts_with("rtol = atol = 1e-6: finished, "), "{err}");
}

#[test]
fn without_tolerances_the_files_own_settings_are_timed() {
    let scratch = Scratch::new(&format!("{BALL}rtol = 1e-7\natol = 1e-9\n"));
    let output = scratch.zenosim(&["bench", "model.toml", "--min-time", "0"]);
    assert_exit(&output, 0);
    let runs = report(&output)["runs"].as_array().unwrap().clone();
    assert_eq!(runs.len(), 1);
    assert_eq!(runs[0]["settings"]["rtol"], 1e-7);
    assert_eq!(runs[0]["settings"]["atol"], 1e-9);
}

#[test]
fn a_failed_or_stalled_run_is_reported_and_sets_the_exit_status() {
    let scratch = Scratch::new(BALL);
    let output = scratch.zenosim(&["bench", "model.toml", "--zeno", "off", "--min-time", "0"]);
    assert_exit(&output, 3);
    assert_eq!(report(&output)["runs"][0]["status"], "zeno_stalled");

    let faults = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/corpus/faults/nan-force.toml"
    );
    let output = scratch.zenosim(&["bench", faults, "--min-time", "0"]);
    assert_exit(&output, 1);
    assert_eq!(report(&output)["runs"][0]["status"], "failed");
    assert!(stderr(&output).contains("failed"), "{}", stderr(&output));
}

#[test]
fn bad_arguments_and_models_exit_2_with_nothing_on_stdout() {
    let scratch = Scratch::new(BALL);
    for args in [
        &["bench", "model.toml", "--tolerances", "0"][..],
        &["bench", "model.toml", "--tolerances", "1e-6,x"],
        &["bench", "model.toml", "--min-time", "-1"],
        // Regression: a duration past the clock's type panicked.
        &["bench", "model.toml", "--min-time", "1e20"],
        &["bench", "missing.toml"],
    ] {
        let output = scratch.zenosim(args);
        assert_exit(&output, 2);
        assert!(stdout(&output).is_empty(), "{args:?}");
        assert!(!stderr(&output).contains("panicked"), "{args:?}");
    }
}

#[test]
fn the_diagram_is_drawn_from_the_points_or_the_input_is_named() {
    let scratch = Scratch::new(BALL);
    let points = scratch.path("points.json");
    std::fs::write(
        &points,
        r#"{"title": "Work–precision", "subtitle": "test",
            "panels": [{"title": "ball", "error": "|τ∞ − τ|", "series": [
              {"label": "zenosim", "points": [
                {"error": 1e-7, "wall_time_s": 1e-5, "rhs_evals": 300, "tolerance": 1e-6},
                {"error": 2e-11, "wall_time_s": 2e-5, "rhs_evals": 700, "tolerance": 1e-10}]},
              {"label": "peer", "points": [
                {"error": 1e-4, "wall_time_s": 1e-2, "rhs_evals": 9000, "tolerance": 1e-6,
                 "epsilon": 1e-3}]}]}]}"#,
    )
    .unwrap();
    let output = scratch.zenosim(&["work-precision", "points.json", "--out", "wp/d.svg"]);
    assert_exit(&output, 0);
    let svg = std::fs::read_to_string(scratch.path("wp/d.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed SVG");
    let series = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("series"))
        .filter_map(|n| n.attribute("data-name"))
        .collect::<Vec<_>>();
    assert_eq!(series, ["zenosim", "peer", "zenosim", "peer"]);
    assert!(
        svg.contains("tol 1e-6, ε 0.001"),
        "each point says its setting"
    );

    // The default output is the input's name with .svg; PNG by extension.
    assert_exit(&scratch.zenosim(&["work-precision", "points.json"]), 0);
    assert!(scratch.path("points.svg").exists());
    let output = scratch.zenosim(&["work-precision", "points.json", "--out", "d.png"]);
    assert_exit(&output, 0);
    assert!(std::fs::read(scratch.path("d.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));

    std::fs::write(
        &points,
        r#"{"title": "x", "panels": [{"title": "a", "error": "e"}]}"#,
    )
    .unwrap();
    let output = scratch.zenosim(&["work-precision", "points.json", "--out", "bad.svg"]);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(
        err.starts_with("error: points.json:1:") && err.contains("missing field `series`"),
        "{err}"
    );
    assert!(!scratch.path("bad.svg").exists());
    let output = scratch.zenosim(&["work-precision", "points.json", "--out", "d.pdf"]);
    assert_exit(&output, 2);
    assert!(stderr(&output).contains(".svg or .png"));
}
