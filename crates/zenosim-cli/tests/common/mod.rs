//! Shared helpers of the command-line tests: models, running the binary, reading its output.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A ball dropped from x = 1 on a floor, e = 0.5: τ∞ = √(2/g)·(1+e)/(1−e) = 3√(2/g) ≈ 1.3546.
pub const BALL: &str = r#"
name = "ball"
description = "A ball dropped on a floor"
coordinates = ["x"]
lagrangian = "0.5*m*x_dot^2 - m*g*x"

[parameters]
m = 1.0
g = 9.81
e = 0.5

[[constraint]]
name = "floor"
h = "x"
restitution = "e"

[initial]
x = 1.0

[simulation]
t_end = 2.0
"#;

/// The paper's Example 6: a ball on x3 = sin(x2), e = 0.6 (Ames et al. 2006).
pub const BALL_ON_SINE: &str = r#"
name = "ball-on-sine"
description = "The paper's ball bouncing on the surface x3 = sin(x2)"
coordinates = ["x1", "x2", "x3"]
lagrangian = "0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2) - m*g*x3"

[parameters]
m = 1.0
g = 9.81

[[constraint]]
name = "surface"
h = "x3 - sin(x2)"
restitution = 0.6

[initial]
x2 = "pi/3"
x3 = 2.0
x1_dot = 0.5

[simulation]
t_end = 6.0
"#;

/// A ball with linear air drag (`D = ½ c ẏ²`) dropped on a floor: a model that is not
/// autonomous, so its trajectory has the energy balance's columns.
pub const DRAGGED_BALL: &str = r#"
name = "dragged-ball"
coordinates = ["y"]
lagrangian = "0.5*m*y_dot^2 - m*g*y"
dissipation = "0.5*c*y_dot^2"

[parameters]
m = 1.0
g = 9.81
c = 0.8
e = 0.6

[[constraint]]
name = "floor"
h = "y"
restitution = "e"

[initial]
y = 1.0

[simulation]
t_end = 2.0
"#;

/// The columns of the energy balance, after `energy`, for a model that is not autonomous.
pub const WORK_COLUMNS: &str = "work_forces,work_drive,work_constraints,impact_loss";

/// The size of the energies and works of `summary.json`'s `energy_balance`: the scale of its
/// residual.
pub fn balance_scale(balance: &serde_json::Value) -> f64 {
    [
        "energy_start",
        "energy_end",
        "work_forces",
        "work_drive",
        "work_constraints",
        "impact_loss",
    ]
    .iter()
    .map(|key| balance[key].as_f64().expect(key).abs())
    .fold(0.0, f64::max)
}

/// The path of the `zenosim` binary.
pub fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_zenosim")
}

/// A scratch directory with `model.toml` holding `source`.
pub struct Scratch {
    pub dir: tempfile::TempDir,
    pub model: PathBuf,
}

impl Scratch {
    pub fn new(source: &str) -> Self {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let model = dir.path().join("model.toml");
        std::fs::write(&model, source).expect("the model file is written");
        Self { dir, model }
    }

    /// `<scratch>/<name>`.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Runs `zenosim <args>` in the scratch directory.
    pub fn zenosim(&self, args: &[&str]) -> Output {
        Command::new(binary())
            .args(args)
            .current_dir(self.dir.path())
            .output()
            .expect("zenosim runs")
    }

    /// Runs `zenosim <args>` in the scratch directory with its files limited to `blocks` blocks
    /// of 512 bytes (a shell's `ulimit -f`): a write past it fails as on a full disk.
    #[cfg(unix)]
    pub fn zenosim_limited(&self, blocks: u32, args: &[&str]) -> Output {
        Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -f {blocks} && exec \"$0\" \"$@\""))
            .arg(binary())
            .args(args)
            .current_dir(self.dir.path())
            .output()
            .expect("sh runs zenosim")
    }

    /// `zenosim run model.toml --out out <args>`.
    pub fn run(&self, args: &[&str]) -> Output {
        let mut all = vec!["run", "model.toml", "--out", "out"];
        all.extend_from_slice(args);
        self.zenosim(&all)
    }
}

/// The text of stderr.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The text of stdout.
pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The exit status, with stderr shown when it is not the expected one.
pub fn assert_exit(output: &Output, code: i32) {
    assert_eq!(
        output.status.code(),
        Some(code),
        "stdout:\n{}\nstderr:\n{}",
        stdout(output),
        stderr(output)
    );
}

/// A CSV file read whole: its header and its rows (`mode` kept as text).
pub struct Csv {
    pub header: Vec<String>,
    pub rows: Vec<Row>,
}

pub struct Row {
    pub t: f64,
    pub mode: String,
    /// Every column after `mode`.
    pub values: Vec<f64>,
}

impl Csv {
    pub fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).expect("the CSV is readable");
        assert!(text.ends_with('\n'), "the CSV ends with a complete line");
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .expect("a header")
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .enumerate()
            .map(|(i, line)| {
                let fields: Vec<&str> = line.split(',').collect();
                assert_eq!(
                    fields.len(),
                    header.len(),
                    "row {} has the header's width: {line}",
                    i + 2
                );
                let number = |f: &str| -> f64 {
                    f.parse()
                        .unwrap_or_else(|_| panic!("row {}: `{f}` is not a number", i + 2))
                };
                Row {
                    t: number(fields[0]),
                    mode: fields[1].to_string(),
                    values: fields[2..].iter().map(|f| number(f)).collect(),
                }
            })
            .collect();
        Self { header, rows }
    }

    /// The column `name`'s index among the values (after `t` and `mode`).
    pub fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
            - 2
    }
}

/// `summary.json`, parsed.
pub fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json exists");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

/// The files in `dir`, sorted.
pub fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("the directory exists")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// A JSON array of numbers.
pub fn numbers(value: &serde_json::Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap_or_else(|| panic!("{value} is an array"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("{x} is a number")))
        .collect()
}
