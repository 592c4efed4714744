//! The fuzz targets' checks (`fuzz/checks/`), run on stable Rust as the fuzzer runs them, so
//! that CI (which has neither nightly Rust nor cargo-fuzz) keeps them passing: every seed and
//! every committed regression of each target, then a fixed number of deterministic mutations
//! of them (bit flips, extreme bytes, deletions, copies, tokens of the target's dictionary,
//! splices of two inputs) — the fuzzer's work in miniature, within a budget of inputs, not of
//! time. An input that fails is written under `CARGO_TARGET_TMPDIR/fuzz-replay/`, to be
//! replayed with `cargo +nightly fuzz run <target> <file>`.
//!
//! `ZENOSIM_FUZZ_CASES=N` runs `N` mutations per target instead of [`MUTATIONS`].

#[path = "../../../fuzz/checks/lcp.rs"]
mod lcp;
#[path = "../../../fuzz/checks/load_model.rs"]
mod load_model;
#[path = "../../../fuzz/checks/plot.rs"]
mod plot;

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::thread;
use std::time::{Duration, Instant};

/// The mutations per target.
const MUTATIONS: usize = 300;

/// How long one input may take before it counts as a hang (generous: the fuzzers' own limits,
/// `-timeout=10` and `-timeout=5`, are for an optimised build on a quiet machine).
const HANG: Duration = Duration::from_secs(30);

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The files of `dir` (relative to the root), sorted; none if it does not exist.
fn files(dir: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .map(|entries| {
            entries
                .map(|entry| entry.expect("a directory entry").path())
                .filter(|path| path.is_file())
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// A fuzz target: its check, its seeds and regressions, its dictionary.
struct Target {
    name: &'static str,
    check: fn(&[u8]),
    /// The folders of its seeds and committed regressions.
    inputs: &'static [&'static str],
    /// Its libFuzzer dictionary.
    dict: &'static str,
    /// Its `-max_len`: no mutation grows longer.
    max_len: usize,
}

const LOAD_MODEL: Target = Target {
    name: "load_model",
    check: load_model::check,
    inputs: &[
        "fuzz/seeds/load_model",
        "models",
        "fuzz/regressions/load_model",
    ],
    dict: "fuzz/load_model.dict",
    max_len: 4096,
};

const PLOT: Target = Target {
    name: "plot",
    check: plot::check,
    inputs: &["fuzz/seeds/plot", "fuzz/regressions/plot"],
    dict: "fuzz/plot.dict",
    max_len: 16384,
};

const LCP: Target = Target {
    name: "lcp",
    check: lcp::check,
    inputs: &["fuzz/seeds/lcp", "fuzz/regressions/lcp"],
    dict: "fuzz/lcp.dict",
    max_len: 2048,
};

impl Target {
    /// Its seeds and regressions: (name, bytes).
    fn inputs(&self) -> Vec<(String, Vec<u8>)> {
        let inputs: Vec<_> = self
            .inputs
            .iter()
            .flat_map(|dir| files(dir))
            .map(|path| {
                let bytes = std::fs::read(&path).expect("an input is read");
                (path.display().to_string(), bytes)
            })
            .collect();
        assert!(!inputs.is_empty(), "{}: no seeds", self.name);
        inputs
    }

    /// Its dictionary's tokens (libFuzzer's format: `name="value"`, `\"`, `\\` and `\xNN`).
    fn tokens(&self) -> Vec<Vec<u8>> {
        let text = std::fs::read_to_string(root().join(self.dict)).expect("the dictionary");
        let tokens: Vec<Vec<u8>> = text
            .lines()
            .filter(|line| !line.starts_with('#'))
            .filter_map(|line| {
                let value = &line[line.find('"')? + 1..line.rfind('"')?];
                Some(unescape(value))
            })
            .collect();
        assert!(!tokens.is_empty(), "{}: an empty dictionary", self.dict);
        tokens
    }

    /// Runs the check on `input`, on a worker thread, and fails (saving the input) if it panics
    /// or takes more than [`HANG`]. Returns how long it took.
    fn run(&self, label: &str, input: Vec<u8>) -> Duration {
        let check = self.check;
        let (sender, receiver) = mpsc::channel();
        let bytes = input.clone();
        let start = Instant::now();
        let worker = thread::spawn(move || {
            check(&bytes);
            let _ = sender.send(());
        });
        let failure = match receiver.recv_timeout(HANG) {
            Ok(()) => {
                let _ = worker.join();
                return start.elapsed();
            }
            Err(RecvTimeoutError::Timeout) => format!("no answer within {HANG:?}"),
            Err(RecvTimeoutError::Disconnected) => "a panic (above)".to_string(),
        };
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-replay");
        std::fs::create_dir_all(&dir).expect("the folder of failed inputs");
        let saved = dir.join(format!("{}-{}", self.name, label.replace('/', "_")));
        std::fs::write(&saved, &input).expect("the failed input is saved");
        panic!(
            "{}: {label}: {failure}; the input is {} (replay it with `cargo +nightly fuzz run \
             {} {}`)",
            self.name,
            saved.display(),
            self.name,
            saved.display()
        );
    }

    /// Every seed and regression.
    fn replay(&self) {
        let mut slowest = (Duration::ZERO, String::new());
        let inputs = self.inputs();
        for (name, bytes) in &inputs {
            let took = self.run(name, bytes.clone());
            slowest = slowest.max((took, name.clone()));
        }
        eprintln!(
            "{}: {} seeds and regressions, the slowest {:?} ({})",
            self.name,
            inputs.len(),
            slowest.0,
            slowest.1
        );
    }

    /// [`MUTATIONS`] (or `ZENOSIM_FUZZ_CASES`) mutations of the seeds and regressions.
    fn mutate(&self) {
        let cases = std::env::var("ZENOSIM_FUZZ_CASES")
            .ok()
            .and_then(|n| n.parse().ok())
            .unwrap_or(MUTATIONS);
        let inputs = self.inputs();
        let tokens = self.tokens();
        let mut random = Random(0x2545_f491_4f6c_dd1d);
        let start = Instant::now();
        for case in 0..cases {
            let (name, seed) = &inputs[random.below(inputs.len())];
            let mut input = seed.clone();
            // One to four mutations stacked, as libFuzzer does.
            for _ in 0..=random.below(4) {
                let other = &inputs[random.below(inputs.len())].1;
                mutate(&mut input, other, &tokens, &mut random);
            }
            input.truncate(self.max_len);
            let file = Path::new(name)
                .file_name()
                .map_or("", |f| f.to_str().unwrap());
            self.run(&format!("mutation-{case}-of-{file}"), input);
        }
        eprintln!("{}: {cases} mutations in {:?}", self.name, start.elapsed());
    }
}

/// A byte string of the dictionary, its escapes resolved.
fn unescape(value: &str) -> Vec<u8> {
    let bytes = value.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1)) {
            (b'\\', Some(b'x')) => {
                let hex = std::str::from_utf8(&bytes[i + 2..i + 4]).expect("two hex digits");
                out.push(u8::from_str_radix(hex, 16).expect("two hex digits"));
                i += 4;
            }
            (b'\\', Some(&escaped)) => {
                out.push(escaped);
                i += 2;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    out
}

/// xorshift64*: a small generator, the same sequence on every machine.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Bytes that break parsers: the ends of ranges, digits and signs, quotes, separators.
const EXTREME_BYTES: &[u8] = b"\x00\x01\x7f\x80\xff09-+.e\"',:\n\r\t[]{}\\ ";

/// Applies one of libFuzzer's kinds of mutation to `input`: a bit flipped, an extreme byte
/// written or inserted, a range deleted, a range copied elsewhere, a dictionary token inserted
/// or written over, or a splice with `other`.
fn mutate(input: &mut Vec<u8>, other: &[u8], tokens: &[Vec<u8>], random: &mut Random) {
    let position = |random: &mut Random, len: usize| random.below(len + 1);
    let n = input.len();
    match random.below(7) {
        0 if n > 0 => {
            let at = random.below(n);
            input[at] ^= 1 << random.below(8);
        }
        1 if n > 0 => {
            let at = random.below(n);
            input[at] = EXTREME_BYTES[random.below(EXTREME_BYTES.len())];
        }
        2 => {
            let at = position(random, n);
            input.insert(at, EXTREME_BYTES[random.below(EXTREME_BYTES.len())]);
        }
        3 if n > 0 => {
            let at = random.below(n);
            let len = 1 + random.below((n - at).min(64));
            input.drain(at..at + len);
        }
        4 if n > 0 => {
            // A part copied elsewhere (libFuzzer's CopyPart): how lines and terms multiply.
            let from = random.below(n);
            let len = 1 + random.below((n - from).min(256));
            let part = input[from..from + len].to_vec();
            let at = position(random, n);
            input.splice(at..at, part);
        }
        5 => {
            let token = &tokens[random.below(tokens.len())];
            let at = position(random, n);
            if random.below(2) == 0 {
                input.splice(at..at, token.iter().copied());
            } else {
                let end = (at + token.len()).min(n);
                input.splice(at..end, token.iter().copied());
            }
        }
        _ => {
            // A splice: this input's start, the other's end (libFuzzer's CrossOver).
            let cut = position(random, n);
            let from = position(random, other.len());
            input.truncate(cut);
            input.extend_from_slice(&other[from..]);
        }
    }
}

#[test]
fn load_model_seeds_and_regressions_pass() {
    LOAD_MODEL.replay();
}

#[test]
fn load_model_mutations_pass() {
    LOAD_MODEL.mutate();
}

#[test]
fn plot_seeds_and_regressions_pass() {
    PLOT.replay();
}

#[test]
fn plot_mutations_pass() {
    PLOT.mutate();
}

#[test]
fn lcp_seeds_and_regressions_pass() {
    LCP.replay();
}

#[test]
fn lcp_mutations_pass() {
    LCP.mutate();
}
