//! The check of the plot fuzz target (`fuzz/fuzz_targets/plot.rs`), shared with the test that
//! replays the seeds in CI (`crates/zenosim-cli/tests/fuzz_replay.rs`), both of which include
//! this file by `#[path]`.
//!
//! The input is an output folder of `zenosim run`, as bytes:
//! `summary.json NUL trajectory.csv [NUL options]`. The first part becomes `summary.json`, the
//! second (if there is a NUL) `trajectory.csv`, in a new temporary folder; the options are
//! words: `png` draws PNG files instead of SVG, and a word `X,Y` is the `--plane`. Then
//! `zenosim plot` draws every plot of that folder ([`zenosim_cli::draw`]).
//!
//! Nothing may panic. A folder drawn gives every plot (the tangential forces' only for a run
//! whose summary lists constraints with friction); a refused one is a bad input (exit 2),
//! never an output failure (a plot that cannot be drawn), and its message is short: at most
//! [`MAX_MESSAGE`] characters besides the folder's name, however long a bad line, name or
//! value. Time and memory are the fuzzer's to judge (`-timeout`, `-rss_limit_mb`).

use std::path::Path;

use zenosim_cli::{draw, Failure, Format, Plane, FRICTION, PLOTS};

/// The byte between the parts of an input.
pub const SEPARATOR: u8 = 0;

/// The most characters of an error message, the folder's name aside: a message quotes at most
/// a few hundred characters of what it read.
pub const MAX_MESSAGE: usize = 1000;

/// The check of one input: panics on a finding.
pub fn check(data: &[u8]) {
    let mut parts = data.splitn(3, |&byte| byte == SEPARATOR);
    let summary = parts.next().unwrap_or_default();
    let trajectory = parts.next();
    let options = String::from_utf8_lossy(parts.next().unwrap_or_default());
    let words: Vec<&str> = options.split_whitespace().collect();
    let format = if words.contains(&"png") {
        Format::Png
    } else {
        Format::Svg
    };
    let plane: Option<Plane> = words.iter().find_map(|word| word.parse().ok());

    let folder = tempfile::tempdir().expect("a temporary folder");
    let dir = folder.path();
    std::fs::write(dir.join("summary.json"), summary).expect("summary.json written");
    if let Some(trajectory) = trajectory {
        std::fs::write(dir.join("trajectory.csv"), trajectory).expect("trajectory.csv written");
    }
    match draw(dir, format, plane.as_ref()) {
        Ok(written) => {
            let friction = has_friction(summary);
            let plots: Vec<&str> = PLOTS
                .into_iter()
                .filter(|&name| friction || name != FRICTION)
                .collect();
            assert_eq!(written.len(), plots.len(), "{written:?}");
            for (path, name) in written.iter().zip(plots) {
                assert_eq!(path, &dir.join(format!("{name}.{}", format.extension())));
                let size = std::fs::metadata(path).map_or(0, |m| m.len());
                assert!(size > 0, "{} is empty", path.display());
            }
        }
        Err(Failure::BadInput(error)) => check_message(&format!("{error:#}"), dir),
        Err(Failure::Output(error)) => {
            panic!("a plot of a readable folder cannot be drawn: {error:#}")
        }
    }
}

/// Whether `summary` (drawn, so a summary.json that `zenosim plot` reads) lists constraints
/// with friction: a `friction` key with at least one name. Read as the plots read it, the other
/// keys skipped: a string there that is no valid Unicode (a lone surrogate) is no error.
fn has_friction(summary: &[u8]) -> bool {
    #[derive(serde::Deserialize)]
    struct Listed {
        #[serde(default)]
        friction: Vec<String>,
    }
    let listed: Listed = serde_json::from_slice(summary).expect("a summary drawn");
    !listed.friction.is_empty()
}

/// A refusal's message: it names the folder's file, and is short.
fn check_message(message: &str, dir: &Path) {
    let dir = dir.display().to_string();
    assert!(
        message.contains(&dir),
        "the message names no file: {message}"
    );
    let length = message.replace(&dir, "").chars().count();
    assert!(
        length <= MAX_MESSAGE,
        "a message of {length} characters, more than {MAX_MESSAGE}: {}…",
        message.chars().take(2 * MAX_MESSAGE).collect::<String>()
    );
}
