//! The corpus of broken inputs, run through the `zenosim` binary.
//!
//! - `corpus/bad/NAME.toml`: a model file with one mistake, the comment on its first line says
//!   which. `zenosim run` and `zenosim check` refuse it with exit 2, write nothing, and print
//!   exactly `corpus/bad/NAME.stderr`: the file, the line and column or the key, what is wrong
//!   and what to do. After a deliberate change of wording, `ZENOSIM_BLESS=1 cargo test -p
//!   zenosim-cli --test corpus` rewrites the `.stderr` files; review their diff.
//! - Hostile files made here: 10 MB, and 100 000 nested parentheses.
//! - `corpus/faults/NAME.toml`: a valid model whose run fails partway (NaN, a mass matrix that
//!   loses definiteness, a vanishing constraint gradient at an impact or in contact, a step size
//!   that underflows, an event storm, a contact problem without a solution, contacts whose
//!   gradients are nearly but not exactly dependent). The run ends with exit 1 and status `failed`, says when
//!   and why, and leaves a complete, readable trajectory and summary of everything up to then.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use zenosim::Readable;

fn corpus(kind: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus")
        .join(kind)
}

/// The corpus's `.toml` files of `kind`, sorted.
fn cases(kind: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus(kind))
        .expect("the corpus directory")
        .map(|entry| entry.expect("an entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// A scratch directory holding a copy of `model` under its own name (so messages name it as
/// a user in that directory would see it).
fn scratch_with(model: &Path) -> (Scratch, String) {
    let name = model.file_name().unwrap().to_string_lossy().into_owned();
    let scratch = Scratch::new("");
    std::fs::copy(model, scratch.path(&name)).expect("the model is copied");
    (scratch, name)
}

/// `zenosim args` refuses: exit 2, nothing on stdout, no output directory; its stderr.
fn refused(scratch: &Scratch, args: &[&str]) -> String {
    let output = scratch.zenosim(args);
    assert_exit(&output, 2);
    assert!(stdout(&output).is_empty(), "{}", stdout(&output));
    assert!(
        !scratch.path("out").exists(),
        "{args:?} wrote an output directory"
    );
    stderr(&output)
}

#[test]
fn every_bad_model_is_refused_with_its_message() {
    let bless = std::env::var_os("ZENOSIM_BLESS").is_some();
    let files = cases("bad");
    assert!(
        files.len() >= 30,
        "the corpus is there ({} files)",
        files.len()
    );
    let mut mismatches = Vec::new();
    for model in &files {
        let (scratch, name) = scratch_with(model);
        let first = std::fs::read_to_string(model).unwrap();
        assert!(
            first.starts_with("# "),
            "{name}: the first line says what is wrong"
        );
        let err = refused(&scratch, &["run", &name, "--out", "out"]);
        // `check` reads the model the same way and says the same.
        assert_eq!(refused(&scratch, &["check", &name]), err, "{name}: check");
        // Every message names the file first, then a line and column or a key, and says what
        // to do.
        assert!(err.starts_with(&format!("error: {name}:")), "{err}");
        assert!(err.contains("help: "), "{name} says what to do:\n{err}");
        let expected = model.with_extension("stderr");
        if bless {
            std::fs::write(&expected, &err).unwrap();
            continue;
        }
        let want = std::fs::read_to_string(&expected)
            .unwrap_or_else(|_| panic!("{} is missing: bless the corpus", expected.display()));
        if err != want {
            mismatches.push(format!("{name}:\n--- expected\n{want}--- got\n{err}"));
        }
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn every_expected_message_has_its_model() {
    for entry in std::fs::read_dir(corpus("bad")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "stderr") {
            assert!(
                path.with_extension("toml").exists(),
                "{} has no model",
                path.display()
            );
        }
    }
}

#[test]
fn a_10_mb_file_is_refused_unread() {
    let scratch = Scratch::new(&format!("{}\n", "# padding ".repeat(1_000_000)));
    let err = refused(&scratch, &["run", "model.toml", "--out", "out"]);
    assert_eq!(
        err,
        "error: model.toml: the file is larger than 1 MiB; a model file is a few kilobytes: \
         check that this is the right file\n"
    );
}

/// `BALL` with the floor's `h` replaced by `h`.
fn ball_with_floor(h: &str) -> String {
    let model = BALL.replace("h = \"x\"", &format!("h = \"{h}\""));
    assert_ne!(model, BALL);
    model
}

#[test]
fn a_hundred_thousand_nested_parentheses_are_refused_fast() {
    let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    let scratch = Scratch::new(&ball_with_floor(&deep));
    let err = refused(&scratch, &["run", "model.toml", "--out", "out"]);
    assert!(
        err.starts_with("error: model.toml:14:5: constraint[1].h: "),
        "{err}"
    );
    assert!(err.contains("200001 characters long, more than the limit of 100000"));
    assert!(err.contains("--max-formula-length"), "{err}");
    // Allowed that long, the nesting is the next limit, at the 257th parenthesis.
    let err = refused(
        &scratch,
        &[
            "run",
            "model.toml",
            "--out",
            "out",
            "--max-formula-length",
            "300000",
        ],
    );
    assert!(
        err.starts_with("error: model.toml:14:262: constraint[1].h: "),
        "{err}"
    );
    assert!(err.contains("nests more than 256 levels"), "{err}");
    assert!(err.contains("--max-formula-depth"), "{err}");
    // Allowed both, it is just x: the ball runs (the parser and the evaluator use no recursion).
    let output = scratch.run(&[
        "--max-formula-length",
        "300000",
        "--max-formula-depth",
        "100000",
    ]);
    assert_exit(&output, 0);
}

#[test]
fn a_model_whose_derivatives_exceed_the_limit_runs_once_it_is_raised() {
    let source = std::fs::read_to_string(corpus("bad").join("derivatives-too-large.toml"))
        .expect("in the corpus");
    let scratch = Scratch::new(&source);
    let err = refused(&scratch, &["check", "model.toml"]);
    assert!(
        err.contains("more than the limit of 10000000 operations"),
        "{err}"
    );
    // It needs about 11 million: raised to 20 million, it runs.
    let output = scratch.run(&["--max-derivative-operations", "20000000", "--t-end", "0.01"]);
    assert_exit(&output, 0);
}

/// What a fault's run must say: the model, and the cause in its message.
const FAULTS: [(&str, &str); 7] = [
    ("blow-up", "the step size"),
    (
        "event-storm",
        "the limit of 2000 events was reached, the last 100 of them within",
    ),
    (
        "flat-impact",
        "constraint 'floor' has ∂h/∂q = 0 where it must act",
    ),
    ("nan-force", "the state or its derivative is not finite"),
    (
        "nearly-dependent",
        "constraints 'floor' and 'ramp' have to hold together but their gradients ∂h/∂q are nearly dependent",
    ),
    (
        "pinched",
        "the contact problem on constraints 'floor' and 'cap' has no solution",
    ),
    (
        "vanishing-mass",
        "the mass matrix ∂²L/∂q̇² is not positive definite",
    ),
];

#[test]
fn the_fault_corpus_is_the_table() {
    let names: Vec<String> = cases("faults")
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, FAULTS.map(|(name, _)| name.to_string()));
}

#[test]
fn a_run_that_fails_keeps_everything_up_to_the_failure() {
    for (name, cause) in FAULTS {
        let (scratch, file) = scratch_with(&corpus("faults").join(format!("{name}.toml")));
        let output = scratch.zenosim(&["run", &file, "--out", "out"]);
        assert_exit(&output, 1);
        let summary = summary(&scratch.path("out"));
        assert_eq!(summary["status"], "failed", "{name}");
        let t = summary["final"]["t"].as_f64().expect("the final time");
        let message = summary["message"].as_str().unwrap();
        // When, and why.
        let when = format!("at t = {}: ", Readable(t));
        assert!(message.contains(&when), "{name}: {message} (at {t})");
        assert!(message.contains(cause), "{name}: {message}");
        let err = stderr(&output);
        assert!(
            err.contains(&format!("error: the simulation failed {when}")),
            "{name}: {err}"
        );
        assert!(err.contains(cause), "{name}: {err}");
        // The trajectory is complete and readable, and ends where the run stopped.
        let csv = Csv::read(&scratch.path("out/trajectory.csv"));
        assert_eq!(
            csv.rows.len() as u64,
            summary["trajectory"]["rows"].as_u64().unwrap(),
            "{name}"
        );
        assert!(
            csv.rows.windows(2).all(|w| w[0].t <= w[1].t),
            "{name}: times in order"
        );
        let last = csv.rows.last().expect("at least the initial state");
        assert!(
            last.t <= t,
            "{name}: the last row ({}) is not after the failure ({t})",
            last.t
        );
        assert!(
            csv.rows
                .iter()
                .all(|r| r.values.iter().all(|v| v.is_finite())),
            "{name}: only finite states are kept"
        );
        // The events up to then are recorded.
        let events = summary["events"].as_array().unwrap();
        assert_eq!(
            events.len() as u64,
            summary["stats"]["events"].as_u64().unwrap(),
            "{name}"
        );
        if name == "event-storm" {
            assert_eq!(events.len(), 2000);
        }
        // No temporary file is left.
        assert_eq!(
            files(&scratch.path("out")),
            ["model.toml", "summary.json", "trajectory.csv"],
            "{name}"
        );
    }
}

#[test]
fn limits_can_be_set_on_the_command_line() {
    let scratch = Scratch::new(BALL);
    // The ball bounces about 37 times before its Zeno point; 5 events are not enough.
    let output = scratch.run(&["--max-events", "5"]);
    assert_exit(&output, 1);
    let summary = summary(&scratch.path("out"));
    let message = summary["message"].as_str().unwrap();
    assert!(
        message.contains("the limit of 5 events was reached"),
        "{message}"
    );
    assert!(
        message.contains("--max-events N; a model file's max_events may only lower the limit"),
        "{message}"
    );
    assert_eq!(summary["events"].as_array().unwrap().len(), 5);
    let output = scratch.run(&["--max-steps", "10"]);
    assert_exit(&output, 1);
    let summary = common::summary(&scratch.path("out"));
    assert!(summary["message"]
        .as_str()
        .unwrap()
        .contains("the limit of 10 steps was reached"));
    assert_eq!(summary["stats"]["steps"], 10);
    // A limit must be a whole number ≥ 1.
    refused(
        &Scratch::new(BALL),
        &["run", "model.toml", "--out", "out", "--max-steps", "0"],
    );
    refused(
        &Scratch::new(BALL),
        &["run", "model.toml", "--out", "out", "--max-events", "-3"],
    );
}
