//! `zenosim check`: what it prints of a model at its initial state.

mod common;

use common::*;

#[test]
fn check_prints_what_zenosim_derives() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.zenosim(&["check", "model.toml"]);
    assert_exit(&output, 0);
    let report = stdout(&output);
    for expected in [
        "ball-on-sine",
        "The paper's ball",
        "dimension    3",
        "x1, x2, x3",
        "x1_dot, x2_dot, x3_dot",
        "g = 9.81",
        "mass matrix M(q0)",
        "positive definite",
        "[ 1  0  0 ]",
        "[ 0  1  0 ]",
        "[ 0  0  1 ]",
        "energy",
        "surface",
        "restitution = 0.6",
        "t_end      = 6",
        "zeno       = auto",
    ] {
        assert!(report.contains(expected), "`{expected}` in\n{report}");
    }
    // h(q0) = 2 − sin(π/3), A(q0) = (0, −cos(π/3), 1).
    let h = 2.0 - (std::f64::consts::FRAC_PI_3).sin();
    let printed = value_of(&report, "h(q0)       = ");
    assert!(
        (printed - h).abs() < 1e-15,
        "h(q0) = {printed}, expected {h}"
    );
    let a = -(std::f64::consts::FRAC_PI_3).cos();
    let line = report.lines().find(|l| l.contains("A(q0)")).unwrap();
    let inside = line.split(['[', ']']).nth(1).unwrap();
    let printed: Vec<f64> = inside.split(", ").map(|x| x.parse().unwrap()).collect();
    assert_eq!(printed.len(), 3, "{line}");
    assert_eq!((printed[0], printed[2]), (0.0, 1.0), "{line}");
    assert!((printed[1] - a).abs() < 1e-15, "{line}");
    // Energy ½ m v² + m g x3 = 0.125 + 19.62.
    assert!(report.contains("energy       19.745"), "{report}");
    assert!(!scratch.path("out").exists(), "check writes nothing");
}

/// The number after `prefix` on its line of `report`.
fn value_of(report: &str, prefix: &str) -> f64 {
    let line = report
        .lines()
        .find_map(|l| l.trim_start().strip_prefix(prefix))
        .unwrap_or_else(|| panic!("`{prefix}` in\n{report}"));
    line.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn check_applies_set() {
    let scratch = Scratch::new(BALL);
    let output = scratch.zenosim(&["check", "model.toml", "--set", "m=2", "--set", "x=3"]);
    assert_exit(&output, 0);
    let report = stdout(&output);
    assert!(report.contains("[ 2 ]"), "{report}");
    assert!(report.contains("h(q0)       = 3"), "{report}");
    assert!(report.contains("restitution = 0.5"), "{report}");
}

#[test]
fn help_documents_the_default_output_directory() {
    let scratch = Scratch::new(BALL);
    let output = scratch.zenosim(&["run", "--help"]);
    assert_exit(&output, 0);
    assert!(stdout(&output).contains("out/<model name>"));
}

/// The repository's example models (`models/*.toml`): each is valid, and the paper's example
/// runs to the paper's numbers.
#[test]
fn the_example_models_check_and_the_papers_runs() {
    let models = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models");
    let Ok(entries) = std::fs::read_dir(&models) else {
        return;
    };
    let scratch = Scratch::new("");
    for entry in entries {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let output = scratch.zenosim(&["check", path.to_str().unwrap()]);
            assert_exit(&output, 0);
        }
    }
    let paper = models.join("ball-on-sine.toml");
    if paper.exists() {
        let output = scratch.zenosim(&["run", paper.to_str().unwrap(), "--out", "paper"]);
        assert_exit(&output, 0);
        let s = summary(&scratch.path("paper"));
        // 26 impacts, then the switch at t ≈ 2.04561 (README, the paper's Fig. 5).
        assert_eq!(s["stats"]["impacts"], 26);
        let t_switch = s["zeno"][0]["t_switch"].as_f64().unwrap();
        assert!((t_switch - 2.04561).abs() < 1e-5, "{t_switch}");
    }
}
