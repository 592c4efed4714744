//! Bad models and bad arguments: exit 2, a message that starts with `error: ` and says where,
//! and nothing written.

mod common;

use common::*;

/// Runs `args` and checks: exit 2, an `error: ` message, no output directory.
fn refused(scratch: &Scratch, args: &[&str]) -> String {
    let output = scratch.zenosim(args);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(err.starts_with("error: "), "{err}");
    assert!(!scratch.path("out").exists(), "nothing is created");
    assert!(stdout(&output).is_empty());
    err
}

fn run_refused(scratch: &Scratch, args: &[&str]) -> String {
    let mut all = vec!["run", "model.toml", "--out", "out"];
    all.extend_from_slice(args);
    refused(scratch, &all)
}

#[test]
fn a_syntax_error_names_file_line_and_column() {
    let scratch = Scratch::new(&BALL.replace("m = 1.0", "m = = 1.0"));
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("model.toml:8:"), "{err}");
    let err = refused(&scratch, &["check", "model.toml"]);
    assert!(err.contains("model.toml:8:"), "{err}");
}

#[test]
fn an_unknown_name_in_a_formula_names_its_place() {
    let scratch = Scratch::new(&BALL.replace("m*g*x\"", "m*gg*x\""));
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("model.toml:5:"), "{err}");
    assert!(err.contains("gg"), "{err}");
}

#[test]
fn set_of_an_unknown_name_is_refused_naming_it() {
    let scratch = Scratch::new(BALL);
    let err = run_refused(&scratch, &["--set", "bogus=1"]);
    assert!(err.contains("bogus"), "{err}");
    let err = refused(&scratch, &["check", "model.toml", "--set", "bogus=1"]);
    assert!(err.contains("bogus"), "{err}");
}

#[test]
fn set_without_equals_is_refused() {
    let scratch = Scratch::new(BALL);
    let err = run_refused(&scratch, &["--set", "x"]);
    assert!(err.contains("NAME=VALUE"), "{err}");
}

#[test]
fn an_inadmissible_set_is_refused() {
    let scratch = Scratch::new(BALL);
    run_refused(&scratch, &["--set", "x=-1"]);
    run_refused(&scratch, &["--set", "e=1.5"]);
}

#[test]
fn bad_flag_values_are_refused() {
    let scratch = Scratch::new(BALL);
    let err = run_refused(&scratch, &["--zeno", "banana"]);
    assert!(err.contains("auto, off"), "{err}");
    for args in [
        ["--zeno", "-1"],
        ["--zeno", "0"],
        ["--rtol", "-1"],
        ["--rtol", "0"],
        ["--atol", "nan"],
        ["--t-end", "inf"],
        ["--t-end", "-2"],
        ["--dt", "0"],
        ["--dt", "x"],
        ["--max-output", "0"],
        ["--max-output", "-1"],
        ["--max-output", "1Q"],
        ["--max-output", "K"],
        ["--max-output", "99999999999T"],
    ] {
        let err = run_refused(&scratch, &args);
        assert!(err.contains(args[0]), "{err}");
    }
    // Positive, but finer than f64 resolves: the engine refuses it before anything is written.
    let err = run_refused(&scratch, &["--rtol", "1e-17"]);
    assert!(err.contains("rtol"), "{err}");
    run_refused(&scratch, &["--bogus"]);
    refused(&scratch, &["run"]);
    refused(&scratch, &["frobnicate"]);
}

#[test]
fn a_missing_model_file_is_named() {
    let scratch = Scratch::new(BALL);
    let err = refused(&scratch, &["run", "missing.toml", "--out", "out"]);
    assert!(err.contains("missing.toml"), "{err}");
    let err = refused(&scratch, &["check", "missing.toml"]);
    assert!(err.contains("missing.toml"), "{err}");
    // A directory is not a model file either.
    std::fs::create_dir(scratch.path("adir")).unwrap();
    let err = refused(&scratch, &["run", "adir", "--out", "out"]);
    assert!(err.contains("adir"), "{err}");
}

#[test]
fn a_non_utf8_model_file_is_refused_with_its_place() {
    let scratch = Scratch::new("");
    std::fs::write(&scratch.model, b"name = \"ball\"\n# caf\xe9\n").unwrap();
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("model.toml:2:6"), "{err}");
    assert!(err.contains("UTF-8"), "{err}");
}

#[test]
fn a_model_file_over_1_mib_is_refused() {
    let mut source = BALL.to_string();
    source.push_str(&"# padding\n".repeat(110_000));
    let scratch = Scratch::new(&source);
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("larger than 1 MiB"), "{err}");
}

#[test]
fn an_empty_model_file_is_refused() {
    let scratch = Scratch::new("");
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("model.toml"), "{err}");
}

#[test]
fn garbage_never_panics() {
    for source in [
        "\u{0}\u{1}",
        "[[[",
        "name = 1",
        "name = \"x\"\ncoordinates = []\nlagrangian = \"0\"",
        "name = \"x\"\ncoordinates = [\"x\"]\nlagrangian = \"x_dot^2\"\n[[constraint]]\nname=\"c\"\nh=\"0*x\"\nrestitution=0.5",
    ] {
        let scratch = Scratch::new(source);
        let output = scratch.run(&[]);
        assert!(
            matches!(output.status.code(), Some(1 | 2)),
            "{source:?}: {:?}\n{}",
            output.status,
            stderr(&output)
        );
        assert!(!stderr(&output).contains("panicked"), "{}", stderr(&output));
    }
}

/// Regression: a model's name and a line quoted from the file were printed raw, so escape
/// sequences in them could clear the screen or retitle the terminal. Every control character
/// but the newline and the tab is now printed as an escape (`\u{1b}`). (Constraint names are
/// refused unless ASCII letters, digits, `_` and `-`; the refusal quotes them escaped.)
#[test]
fn control_characters_in_names_and_quoted_lines_are_printed_escaped() {
    let named = BALL.replace(
        "name = \"ball\"",
        "name = \"ball\\u001b]0;pwned\\u0007\\u001b[2J\\u202e\"",
    );
    let scratch = Scratch::new(&named);
    for args in [
        &["check", "model.toml"][..],
        &["run", "model.toml", "--out", "out"],
    ] {
        let output = scratch.zenosim(args);
        assert_exit(&output, 0);
        let printed = format!("{}{}", stdout(&output), stderr(&output));
        assert!(
            printed.contains("ball\\u{1b}]0;pwned\\u{7}\\u{1b}[2J\\u{202e}"),
            "{printed}"
        );
        assert!(!printed.contains('\u{1b}') && !printed.contains('\u{7}'));
        assert!(!printed.contains('\u{202e}'));
    }
    let refused_name = BALL.replace("name = \"floor\"", "name = \"floor\\u001b[31m\"");
    let err = run_refused(&Scratch::new(&refused_name), &[]);
    assert!(err.contains("floor\\u{1b}[31m"), "{err}");
    assert!(!err.contains('\u{1b}'), "{err}");
    // A raw escape byte in the file, quoted in the error that points at it.
    let scratch = Scratch::new(&BALL.replace("h = \"x\"", "h = \"x\u{1b}[2J\""));
    let err = run_refused(&scratch, &[]);
    assert!(err.contains("\\u{1b}[2J"), "{err}");
    assert!(!err.contains('\u{1b}'), "{err}");
}
