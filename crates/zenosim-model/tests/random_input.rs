//! Random input never makes the loader panic or hang (issue 5): mutated shipped models, random
//! formulas and extreme numbers spliced into them, random overrides, and random TOML. Every
//! refusal is a `ModelError` that keeps what `error.rs` promises (the file, the place, the
//! offending line under a caret, what to do); every model that loads is accepted by the engine
//! and runs a short, bounded simulation without panicking. Each case runs on a worker thread and
//! fails if it takes more than [`HANG`].
//!
//! `ZENOSIM_RANDOM_CASES=N` runs `N` cases per property instead of the default 256 (under a
//! second in all, so that the ordinary tests stay fast; the fuzz target in `fuzz/` explores much
//! further).

use std::sync::mpsc::{self, RecvTimeoutError};
use std::thread;
use std::time::Duration;

use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::Config;
use zenosim_model::expr::FUNCTION_NAMES;
use zenosim_model::{parse_model, Location, ModelError, Override};

const FILE: &str = "random.toml";

/// The shipped models, the starting points of the mutations.
const MODELS: [&str; 6] = [
    include_str!("../../../models/ball-on-sine.toml"),
    include_str!("../../../models/ball-on-sine-demo.toml"),
    include_str!("../../../models/ball-off-cylinder.toml"),
    include_str!("../../../models/bouncing-ball.toml"),
    include_str!("../../../models/cart-pendulum.toml"),
    include_str!("../../../models/spherical-pendulum.toml"),
];

/// How long one case may take before it counts as a hang (generous: a slow CI machine
/// loads and runs a case in milliseconds; a hang never returns).
const HANG: Duration = Duration::from_secs(20);

/// The fuzz target's check: its `simulate` runs an accepted model within the same bounds here
/// (`t_end ≤ 1`, 2000 steps, 200 events, 1000 uniform samples).
#[path = "../../../fuzz/checks/load_model.rs"]
#[allow(dead_code)]
mod load_model;

fn cases(default: u32) -> u32 {
    std::env::var("ZENOSIM_RANDOM_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(default)
}

fn config(default: u32) -> Config {
    Config {
        cases: cases(default),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Runs `f` on another thread and fails if it panics or does not return within [`HANG`].
fn within<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (sender, receiver) = mpsc::channel();
    let worker = thread::spawn(move || {
        let _ = sender.send(f());
    });
    match receiver.recv_timeout(HANG) {
        Ok(value) => {
            let _ = worker.join();
            value
        }
        Err(RecvTimeoutError::Timeout) => panic!("no answer within {HANG:?}: a hang"),
        Err(RecvTimeoutError::Disconnected) => match worker.join() {
            Err(panic) => std::panic::resume_unwind(panic),
            Ok(()) => unreachable!("the worker returned without sending"),
        },
    }
}

/// What became of one input.
#[derive(Debug)]
enum Verdict {
    Refused(ModelError),
    Loaded,
}

/// Loads `source` with `overrides`, checks the error if refused, and runs a short simulation if
/// accepted; all on a worker thread, within [`HANG`].
fn check(source: String, overrides: Vec<Override>) -> Result<Verdict, TestCaseError> {
    let (source, overrides, verdict) = within(move || {
        let verdict = match parse_model(FILE, &source, &overrides) {
            Ok(file) => {
                load_model::simulate(&file);
                Verdict::Loaded
            }
            Err(error) => Verdict::Refused(error),
        };
        (source, overrides, verdict)
    });
    if let Verdict::Refused(error) = &verdict {
        error_keeps_its_promises(error, &source, &overrides)?;
    }
    Ok(verdict)
}

/// A short, bounded run of an accepted model. `parse_model` checks everything the engine
/// checks before a run, so the engine must accept it.
/// What `ModelError` promises (crates/zenosim-model/src/error.rs): its `Display` names the file,
/// then the line and column (and the key) or the missing key or the override, then what is
/// wrong, the offending line with a caret under the place, and what to do.
fn error_keeps_its_promises(
    error: &ModelError,
    source: &str,
    overrides: &[Override],
) -> Result<(), TestCaseError> {
    let text = error.to_string();
    prop_assert_eq!(&*error.file, FILE);
    prop_assert!(!error.message.trim().is_empty(), "no message: {}", text);
    let help = error.help.as_deref().unwrap_or("");
    prop_assert!(!help.trim().is_empty(), "no help: {}", text);
    prop_assert!(text.ends_with(&format!("\n   = help: {help}")), "{}", text);
    match &error.location {
        Location::At { line, column, key } => {
            let head = match key {
                Some(key) => format!("{FILE}:{line}:{column}: {key}: "),
                None => format!("{FILE}:{line}:{column}: "),
            };
            prop_assert!(text.starts_with(&head), "expected {:?} in:\n{}", head, text);
            // The line exists (a file that ends in a newline has an empty last line) and the
            // column is within it, or just past its end.
            let lines: Vec<&str> = source.split('\n').collect();
            prop_assert!(
                *line >= 1 && *line <= lines.len(),
                "line out of the file: {}",
                text
            );
            // (Counting a CRLF line's '\r', which the snippet does not show.)
            let width = lines[line - 1].chars().count();
            let shown = lines[line - 1].trim_end_matches('\r');
            prop_assert!(
                *column >= 1 && *column <= width + 1,
                "column {} of a line {} long: {}",
                column,
                width,
                text
            );
            // The snippet repeats that line (cut around the column if it is long) with a caret.
            let number = line.to_string();
            let pad = " ".repeat(number.len());
            let quoted = format!("\n{number} | ");
            prop_assert!(text.contains(&quoted), "no snippet: {}", text);
            if width <= 120 {
                prop_assert!(
                    text.contains(&format!("{quoted}{shown}\n{pad} | ")),
                    "the snippet is not line {}:\n{}",
                    line,
                    text
                );
            }
        }
        Location::Missing(key) => {
            let head = format!("{FILE}: missing key `{key}`: ");
            prop_assert!(text.starts_with(&head), "expected {:?} in:\n{}", head, text);
        }
        Location::Override(arg) => {
            prop_assert!(
                overrides.iter().any(|o| o.to_string() == *arg),
                "an override that was not given: {}",
                text
            );
            let head = format!("{FILE}: --set {arg}: ");
            prop_assert!(text.starts_with(&head), "expected {:?} in:\n{}", head, text);
        }
        Location::File => {
            // The file as a whole: no place to point at.
            prop_assert!(text.starts_with(&format!("{FILE}: ")), "{}", text);
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Strategies.

/// Fragments inserted by mutations: TOML punctuation, the language's tokens, names, numbers.
const SOUP: &[&str] = &[
    "\"",
    "'",
    "\"\"\"",
    "'''",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "=",
    ",",
    ".",
    "#",
    "\n",
    "\r\n",
    "\t",
    " ",
    "\\",
    "\\n",
    "\\u00e9",
    "é",
    "\u{0}",
    "-",
    "+",
    "*",
    "/",
    "^",
    "(",
    ")",
    "e",
    "x",
    "y",
    "t",
    "pi",
    "_dot",
    "x_dot",
    "theta",
    "m",
    "g",
    "1",
    "0",
    "-0",
    "1e",
    ".5",
    "3.",
    "1e999",
    "nan",
    "inf",
    "true",
    "name",
    "h",
    "restitution",
    "constraint",
    "[[constraint]]",
    "[parameters]",
    "[initial]",
    "[simulation]",
    "t_end",
    "zeno",
    "\"auto\"",
    "\"off\"",
    "{ epsilon = 1e-3 }",
    "method",
    "\"dopri5\"",
    "dt",
    "max_step",
    "max_steps",
    "max_events",
    "zeno_reset",
    "sin(",
    "atan2(",
    "sqrt(",
    "ln(",
    "min(",
    "pow(",
    "abs(",
];

/// Extreme and odd values for `key = value`: TOML numbers, and formulas in strings.
const EXTREMES: &[&str] = &[
    "nan",
    "+nan",
    "-nan",
    "inf",
    "+inf",
    "-inf",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    "1e-308",
    "5e-324",
    "1e-320",
    "-0",
    "-0.0",
    "0",
    "0.0",
    "1",
    "-1",
    "9223372036854775807",
    "-9223372036854775808",
    "0x7fffffffffffffff",
    "0o777",
    "0b1",
    "1_000_000",
    "1e-15",
    "1e-16",
    "1e-300",
    "1e300",
    "18446744073709551615",
    "\"nan\"",
    "\"inf\"",
    "\"1e999\"",
    "\"1e308 * 10\"",
    "\"-0\"",
    "\"0/0\"",
    "\"1/0\"",
    "\"-1/0\"",
    "\"sqrt(-1)\"",
    "\"ln(0)\"",
    "\"exp(1000)\"",
    "\"asin(2)\"",
    "\"pow(0, -1)\"",
    "\"(-8)^(1/3)\"",
    "\"1e-320 / 1e10\"",
    "\"9223372036854775808\"",
    "\"2^1024\"",
    "\"\"",
    "\" \"",
    "true",
    "[]",
    "{}",
    "1979-05-27",
];

/// Names a formula may use: the shipped models' coordinates, velocities and parameters, and
/// some that no model defines.
const NAMES: &[&str] = &[
    "x",
    "y",
    "x1",
    "x2",
    "x3",
    "theta",
    "phi",
    "x_dot",
    "y_dot",
    "x2_dot",
    "x3_dot",
    "theta_dot",
    "m",
    "g",
    "e",
    "l",
    "R",
    "H",
    "h0",
    "Mc",
    "pi",
    "t",
    "zz",
    "sine",
    "_",
    "x_dot_dot",
];

const NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "0.5",
    ".5",
    "3.",
    "1e3",
    "1E+3",
    "1e-3",
    "1e308",
    "1e-308",
    "5e-324",
    "1e999",
    "1e",
    "1.5e-3",
    "9007199254740993",
    "00",
    "1..2",
];

/// A random formula, as source text: well formed most of the time, with unknown names and
/// functions, wrong arities, extreme numbers and stray tokens.
fn formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        3 => prop::sample::select(NAMES).prop_map(str::to_string),
        2 => prop::sample::select(NUMBERS).prop_map(str::to_string),
        1 => prop::sample::select(SOUP).prop_map(str::to_string),
    ];
    leaf.prop_recursive(6, 48, 3, |inner| {
        let functions: Vec<&'static str> = FUNCTION_NAMES
            .iter()
            .copied()
            .chain(["sinus", "log10", "f", "Sin"])
            .collect();
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(&["+", "-", "*", "/", "^", " ", ","][..]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
            (prop::sample::select(&["-", "+", "--"][..]), inner.clone())
                .prop_map(|(sign, a)| format!("{sign}{a}")),
            inner.clone().prop_map(|a| format!("({a})")),
            (
                prop::sample::select(functions),
                prop::collection::vec(inner, 0..4)
            )
                .prop_map(|(f, args)| format!("{f}({})", args.join(", "))),
        ]
    })
}

/// One edit of a file's text.
#[derive(Clone, Debug)]
enum Edit {
    Delete(Index, usize),
    Insert(Index, &'static str),
    Replace(Index, char),
    SwapLines(Index, Index),
    DuplicateLine(Index),
    DeleteLine(Index),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        3 => (any::<Index>(), 1..8_usize).prop_map(|(i, n)| Edit::Delete(i, n)),
        3 => (any::<Index>(), prop::sample::select(SOUP)).prop_map(|(i, s)| Edit::Insert(i, s)),
        3 => (any::<Index>(), any::<char>()).prop_map(|(i, c)| Edit::Replace(i, c)),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Edit::SwapLines(a, b)),
        1 => any::<Index>().prop_map(Edit::DuplicateLine),
        1 => any::<Index>().prop_map(Edit::DeleteLine),
    ]
}

fn apply(text: &str, edit: &Edit) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
    let at = |index: &Index, len: usize| if len == 0 { 0 } else { index.index(len) };
    match edit {
        Edit::Delete(i, n) => {
            let start = at(i, chars.len());
            let end = (start + n).min(chars.len());
            chars.drain(start..end);
        }
        Edit::Insert(i, s) => {
            let start = at(i, chars.len() + 1);
            chars.splice(start..start, s.chars());
        }
        Edit::Replace(i, c) => {
            if !chars.is_empty() {
                let index = at(i, chars.len());
                chars[index] = *c;
            }
        }
        Edit::SwapLines(a, b) => {
            let (a, b) = (at(a, lines.len()), at(b, lines.len()));
            if !lines.is_empty() {
                lines.swap(a, b);
            }
            return lines.concat();
        }
        Edit::DuplicateLine(i) => {
            if !lines.is_empty() {
                let index = at(i, lines.len());
                lines.insert(index, lines[index]);
            }
            return lines.concat();
        }
        Edit::DeleteLine(i) => {
            if !lines.is_empty() {
                lines.remove(at(i, lines.len()));
            }
            return lines.concat();
        }
    }
    chars.into_iter().collect()
}

/// The byte ranges of the values of `key = value` lines (comments stripped roughly).
fn values(text: &str) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        if let Some(eq) = line.find('=') {
            let body = line.trim_end();
            let start = eq + 1 + (line[eq + 1..].len() - line[eq + 1..].trim_start().len());
            let end = match body[start.min(body.len())..].find(" #") {
                Some(hash) => start + hash,
                None => body.len(),
            };
            if start < end && !line.trim_start().starts_with('#') {
                ranges.push(offset + start..offset + end);
            }
        }
        offset += line.len();
    }
    ranges
}

/// The byte ranges of the contents of double-quoted strings on `key = "…"` lines.
fn quoted(text: &str) -> Vec<std::ops::Range<usize>> {
    values(text)
        .into_iter()
        .filter_map(|r| {
            let v = &text[r.clone()];
            (v.len() >= 2 && v.starts_with('"') && v.ends_with('"') && !v.starts_with("\"\"\""))
                .then(|| r.start + 1..r.end - 1)
        })
        .collect()
}

fn replace_range(text: &str, range: std::ops::Range<usize>, with: &str) -> String {
    format!("{}{with}{}", &text[..range.start], &text[range.end..])
}

/// Random `--set` overrides: the shipped models' names, and others, set to numbers, formulas
/// and extreme values.
fn overrides() -> impl Strategy<Value = Vec<Override>> {
    let value = prop_oneof![
        prop::sample::select(EXTREMES).prop_map(|v| v.trim_matches('"').to_string()),
        formula(),
    ];
    let some = prop::collection::vec(
        (prop::sample::select(NAMES), value).prop_map(|(name, value)| Override {
            name: name.to_string(),
            value,
        }),
        1..3,
    );
    prop_oneof![3 => Just(Vec::new()), 1 => some]
}

/// `text` as a TOML basic string.
fn toml_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A random TOML value, rendered: strings (formulas and names), numbers, booleans, dates,
/// arrays and inline tables.
fn toml_value() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        formula().prop_map(|f| toml_string(&f)),
        prop::sample::select(EXTREMES).prop_map(str::to_string),
        prop::sample::select(NAMES).prop_map(toml_string),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        any::<i64>().prop_map(|v| v.to_string()),
        Just("\"auto\"".to_string()),
    ];
    leaf.prop_recursive(3, 12, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(|v| format!("[{}]", v.join(", "))),
            prop::collection::btree_map(prop::sample::select(NAMES), inner, 0..4).prop_map(|v| {
                let entries: Vec<String> = v.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                format!("{{ {} }}", entries.join(", "))
            }),
        ]
    })
}

/// The coordinates of random models.
const COORDINATES: &[&str] = &["x", "y", "theta", "q"];

/// Names that cannot be coordinates (or repeat one), added now and then.
const BAD_COORDINATES: &[&str] = &["t", "x_dot", "pi", "mode", "x", "h_c0", "1x", ""];

/// A value of a random model: mostly a plain number or a formula, sometimes anything.
fn model_value() -> impl Strategy<Value = String> {
    prop_oneof![
        12 => prop::sample::select(&["1.0", "0.5", "2", "9.81", "0", "\"2*pi\"", "\"m/2\""][..])
            .prop_map(str::to_string),
        2 => formula().prop_map(|f| toml_string(&f)),
        1 => toml_value(),
    ]
}

/// `key = value` lines, each key once.
fn table(keys: &[&str], value: BoxedStrategy<String>) -> BoxedStrategy<String> {
    let keys: Vec<String> = keys.iter().map(|k| k.to_string()).collect();
    prop::collection::btree_map(prop::sample::select(keys), value, 0..5)
        .prop_map(|entries| {
            let lines: Vec<String> = entries.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            lines.join("\n")
        })
        .boxed()
}

/// A random model-shaped TOML document: its coordinates, a Lagrangian with (usually) a kinetic
/// term in each, parameters, constraints, forces, a dissipation function, initial values and
/// settings, each part plausible or random, some missing, some extra.
fn toml_document() -> impl Strategy<Value = String> {
    let coordinates = (
        prop::sample::subsequence(COORDINATES, 1..=3),
        prop::option::weighted(0.1, prop::sample::select(BAD_COORDINATES)),
    )
        .prop_map(|(mut good, bad)| {
            good.extend(bad);
            good
        });
    coordinates.prop_flat_map(|coordinates| {
        let kinetic: Vec<String> = coordinates
            .iter()
            .map(|c| format!("0.5*m*{c}_dot^2"))
            .collect();
        let kinetic = kinetic.join(" + ");
        let names = toml_value_of(&coordinates);
        let velocities: Vec<String> = coordinates.iter().map(|c| format!("{c}_dot")).collect();
        let mut state: Vec<&str> = coordinates.clone();
        state.extend(velocities.iter().map(String::as_str));

        let potential = prop_oneof![
            3 => (
                prop::sample::select(coordinates.clone()),
                prop::sample::select(&["{}", "9.81*{}", "{}^2", "cos({})", "0*{}", "-{}"][..]),
            )
                .prop_map(|(c, shape)| shape.replace("{}", c)),
            1 => formula(),
        ];
        let lagrangian = prop_oneof![
            12 => potential.prop_map(move |v| toml_string(&format!("{kinetic} - ({v})"))),
            3 => formula().prop_map(|f| toml_string(&f)),
            1 => toml_value(),
        ];
        let h = prop_oneof![
            12 => (prop::sample::select(coordinates.clone()), prop::sample::select(NUMBERS))
                .prop_map(|(c, n)| toml_string(&format!("{c} + {n}"))),
            2 => formula().prop_map(|f| toml_string(&f)),
            1 => toml_value(),
        ];
        let restitution = prop_oneof![
            3 => prop::sample::select(&["0.5", "\"e\"", "1", "0", "1.5", "-0.0"][..])
                .prop_map(str::to_string),
            1 => model_value(),
        ];
        // Forces on the coordinates, now and then on a velocity, the time or an unknown name.
        let mut force_keys: Vec<&str> = coordinates.clone();
        force_keys.extend(["x_dot", "t", "zz"]);
        let owned_state: Vec<String> = state.iter().map(|s| s.to_string()).collect();
        let force = prop_oneof![
            6 => (prop::sample::select(owned_state), prop::sample::select(&["-{}", "0.1*sin(t)*{}", "2"][..]))
                .prop_map(|(v, shape)| toml_string(&shape.replace("{}", &v))),
            1 => formula().prop_map(|f| toml_string(&f)),
            1 => model_value(),
        ];
        let forces = table(&force_keys, force.boxed());
        let dissipation = prop_oneof![
            6 => prop::sample::select(velocities.clone())
                .prop_map(|v| toml_string(&format!("0.5*(1 + 0.1*t)*{v}^2"))),
            2 => formula().prop_map(|f| toml_string(&f)),
            1 => model_value(),
        ];
        let constraint = (
            h,
            restitution,
            prop::option::weighted(0.2, table(&state, model_value().boxed())),
        )
            .prop_map(|(h, e, reset)| {
                let reset = reset
                    .map(|r| format!("zeno_reset = {{ {} }}\n", r.replace('\n', ", ")))
                    .unwrap_or_default();
                format!("h = {h}\nrestitution = {e}\n{reset}")
            });
        (
            prop::option::weighted(0.97, toml_value_or(Just(toml_string("random")).boxed())),
            prop::option::weighted(0.97, names),
            prop::option::weighted(0.97, lagrangian),
            prop::option::weighted(0.9, table(&["g", "e", "k", "l"], model_value().boxed())),
            prop_oneof![6 => Just("1.0".to_string()), 1 => model_value()],
            prop::collection::vec(constraint, 1..3),
            prop::option::weighted(0.7, table(&state, model_value().boxed())),
            prop::option::weighted(0.5, simulation()),
            prop::option::weighted(0.1, (prop::sample::select(SOUP), toml_value())),
            prop::option::weighted(0.2, forces),
            prop::option::weighted(0.2, dissipation),
        )
            .prop_map(
                |(
                    name,
                    coordinates,
                    lagrangian,
                    parameters,
                    m,
                    constraints,
                    initial,
                    simulation,
                    extra,
                    forces,
                    dissipation,
                )| {
                    let mut text = String::new();
                    let mut line = |key: &str, value: Option<String>| {
                        if let Some(value) = value {
                            text.push_str(&format!("{key} = {value}\n"));
                        }
                    };
                    line("name", name);
                    line("coordinates", coordinates);
                    line("lagrangian", lagrangian);
                    line("dissipation", dissipation);
                    if let Some((key, value)) = extra {
                        line(&toml_string(key), Some(value));
                    }
                    let mut section = |header: &str, body: Option<String>| {
                        if let Some(body) = body {
                            text.push_str(&format!("\n{header}\n{body}\n"));
                        }
                    };
                    section("[parameters]", parameters.map(|p| format!("m = {m}\n{p}")));
                    for (i, body) in constraints.into_iter().enumerate() {
                        section("[[constraint]]", Some(format!("name = \"c{i}\"\n{body}")));
                    }
                    section("[forces]", forces);
                    section("[initial]", initial);
                    section("[simulation]", simulation);
                    text
                },
            )
    })
}

/// The keys of `[simulation]`, each with values to try.
const SIMULATION: [(&str, &[&str]); 9] = [
    (
        "t_end",
        &["0.5", "1", "10", "0", "-1", "1e-300", "\"2*pi\""],
    ),
    ("rtol", &["1e-8", "1e-10", "1e-15", "1e-16", "0", "1"]),
    ("atol", &["1e-8", "1e-12", "1e-300", "0", "1"]),
    (
        "zeno",
        &[
            "\"auto\"",
            "\"off\"",
            "{ epsilon = 1e-3 }",
            "{ epsilon = 0 }",
            "{ eps = 1 }",
            "{}",
            "\"1e-3\"",
        ],
    ),
    ("method", &["\"dopri5\"", "\"dop853\"", "\"rk4\""]),
    ("dt", &["0.01", "0.3", "1e-300", "0"]),
    ("max_step", &["0.1", "1e-3", "0", "inf"]),
    (
        "max_events",
        &["3", "100", "0", "18446744073709551616", "1.5", "-1"],
    ),
    (
        "max_steps",
        &["10", "1000", "0", "9223372036854775807", "\"10\""],
    ),
];

/// A `[simulation]` body: each key or not, with a value that suits it or any other.
fn simulation() -> BoxedStrategy<String> {
    let entries: Vec<BoxedStrategy<Option<String>>> = SIMULATION
        .iter()
        .map(|&(key, values)| {
            let value = prop_oneof![
                9 => prop::sample::select(values).prop_map(str::to_string),
                1 => model_value(),
            ];
            prop::option::weighted(0.3, value.prop_map(move |v| format!("{key} = {v}"))).boxed()
        })
        .collect();
    entries
        .prop_map(|lines| lines.into_iter().flatten().collect::<Vec<_>>().join("\n"))
        .boxed()
}

/// `coordinates = [...]`: the names, usually.
fn toml_value_of(coordinates: &[&'static str]) -> BoxedStrategy<String> {
    let list: Vec<String> = coordinates.iter().map(|c| toml_string(c)).collect();
    toml_value_or(Just(format!("[{}]", list.join(", "))).boxed())
}

/// `usual` mostly, sometimes any value.
fn toml_value_or(usual: BoxedStrategy<String>) -> BoxedStrategy<String> {
    prop_oneof![19 => usual, 1 => toml_value()].boxed()
}

// ---------------------------------------------------------------------------------------------
// Properties.

proptest! {
    #![proptest_config(config(256))]

    /// Byte- and line-level damage to a shipped model, with random overrides.
    #[test]
    fn mutated_models(
        model in prop::sample::select(&MODELS[..]),
        edits in prop::collection::vec(edit(), 1..4),
        overrides in overrides(),
    ) {
        let source = edits.iter().fold(model.to_string(), |text, e| apply(&text, e));
        check(source, overrides)?;
    }

    /// A random formula in place of (or spliced into) one of a shipped model's strings.
    #[test]
    fn random_formulas(
        model in prop::sample::select(&MODELS[..]),
        which in any::<Index>(),
        splice in any::<bool>(),
        at in any::<Index>(),
        formula in formula(),
    ) {
        let strings = quoted(model);
        let range = strings[which.index(strings.len())].clone();
        let source = if splice {
            // Inside the string, at a character boundary.
            let text = &model[range.clone()];
            let boundaries: Vec<usize> =
                text.char_indices().map(|(i, _)| i).chain([text.len()]).collect();
            let point = range.start + boundaries[at.index(boundaries.len())];
            replace_range(model, point..point, &formula.replace('"', "'"))
        } else {
            replace_range(model, range, &formula.replace('"', "'"))
        };
        check(source, Vec::new())?;
    }

    /// Extreme numbers (NaN, infinities, 1e308, -0, huge integers, bad formulas) as values.
    #[test]
    fn extreme_values(
        model in prop::sample::select(&MODELS[..]),
        picks in prop::collection::vec((any::<Index>(), prop::sample::select(EXTREMES)), 1..4),
    ) {
        let mut source = model.to_string();
        for (which, value) in picks {
            let ranges = values(&source);
            let range = ranges[which.index(ranges.len())].clone();
            source = replace_range(&source, range, value);
        }
        check(source, Vec::new())?;
    }

    /// Random model-shaped TOML.
    #[test]
    fn random_toml(source in toml_document(), overrides in overrides()) {
        check(source, overrides)?;
    }

    /// Random text, mostly the language's and TOML's fragments.
    #[test]
    fn token_soup(tokens in prop::collection::vec(prop::sample::select(SOUP), 0..60)) {
        check(tokens.concat(), Vec::new())?;
    }
}

/// Formulas nested up to the depth limit (256) load; deeper ones are refused, however deep.
#[test]
fn deep_formulas_are_refused() {
    for depth in [255, 256, 257, 100_000] {
        let deep = format!("{}y{}", "(".repeat(depth), ")".repeat(depth));
        let source = MODELS[3].replace("h = \"y\"", &format!("h = \"{deep}\""));
        let verdict = check(source, Vec::new()).unwrap();
        assert_eq!(
            matches!(verdict, Verdict::Loaded),
            depth <= 256,
            "{verdict:?}"
        );
    }
}

/// The mutations keep the shipped models recognisable: unmutated, each loads.
#[test]
fn shipped_models_load() {
    for model in MODELS {
        let verdict = check(model.to_string(), Vec::new()).unwrap();
        assert!(matches!(verdict, Verdict::Loaded), "{verdict:?}");
        assert!(!values(model).is_empty() && !quoted(model).is_empty());
    }
}
