//! `zenosim report DIR` and `zenosim run --report`: the file they write (one page, its data a
//! JSON blob read back here), what it holds (every event, the frames of the animation, the
//! plots' series, the Zeno points), its size for a run of 10⁶ rows, and the refusals of bad
//! folders. The page itself is tested in a browser by tests/report_browser.rs.

mod common;

use std::path::Path;
use std::time::Instant;

use common::*;
use serde_json::Value;

/// The page's data, parsed from its `<script type="application/json">`.
fn data(dir: &Path) -> Value {
    let page = std::fs::read_to_string(dir.join("report.html")).expect("report.html exists");
    let start = page
        .find(r#"<script type="application/json" id="zenosim-data">"#)
        .expect("the data element")
        + r#"<script type="application/json" id="zenosim-data">"#.len();
    let end = start + page[start..].find("</script>").expect("its end");
    serde_json::from_str(&page[start..end]).expect("the data is JSON")
}

/// The page's length in bytes.
fn size(dir: &Path) -> u64 {
    std::fs::metadata(dir.join("report.html"))
        .expect("report.html exists")
        .len()
}

#[test]
fn run_report_writes_the_page_of_the_run() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.run(&["--report"]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    assert!(
        stdout(&output).contains("report.html"),
        "{}",
        stdout(&output)
    );
    let summary = summary(&out);
    let data = data(&out);
    assert_eq!(data["model"], "ball-on-sine");
    assert_eq!(data["status"], "finished");
    assert_eq!(data["coordinates"], summary["coordinates"]);

    // Every event, at its exact time, in the table and among the frames with both its rows (a
    // Zeno point has three: the last state, the state R∞ reaches, the constrained one).
    let events = summary["events"].as_array().unwrap();
    let times = numbers(&data["events"]["t"]);
    assert_eq!(times.len(), events.len());
    let frames = numbers(&data["frames"]["t"]);
    for (event, t) in events.iter().zip(&times) {
        assert_eq!(event["t"].as_f64().unwrap(), *t);
        assert!(frames.iter().filter(|f| *f == t).count() >= 2, "t = {t}");
    }
    assert!(frames.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(frames[0], 0.0);
    assert_eq!(*frames.last().unwrap(), 6.0);
    // The long steps of the free flights are filled in: a frame every two columns of 6/2000.
    assert!(frames.windows(2).all(|w| w[1] - w[0] < 2.0 * 6.0 / 2000.0));
    let t_switch = summary["zeno"][0]["t_switch"].as_f64().unwrap();
    assert_eq!(data["zeno"][0]["t_switch"].as_f64().unwrap(), t_switch);
    // After the switch, the frames' mode holds the surface.
    let modes = data["modes"].as_array().unwrap();
    let after = frames.iter().rposition(|&t| t == t_switch).unwrap();
    let mode = data["frames"]["mode"][after].as_u64().unwrap() as usize;
    assert_eq!(modes[mode], "constrained:surface");

    // The plots' series: q, q̇ and the energy, as the static plots decimate them.
    let names: Vec<&str> = data["series"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["x1", "x2", "x3", "x1_dot", "x2_dot", "x3_dot", "energy"]
    );
    // Frictionless: no tangential forces, no friction states, no impulses in the events; the
    // energy balance without the work of friction.
    assert_eq!(data.get("friction"), None);
    assert_eq!(data["events"].get("impulses"), None);
    assert!(data["modes"]
        .as_array()
        .unwrap()
        .iter()
        .all(|m| !m.as_str().unwrap().contains(';')));
    assert_eq!(data["balance"], summary["energy_balance"]);
    assert_eq!(data["balance"].get("work_friction"), None);
    // No drawing in this model: the page says how to add one.
    assert_eq!(data["mechanism"], Value::Null);
    let note = data["note"].as_str().unwrap();
    assert!(note.contains("no [drawing]"), "{note}");
    let bytes = size(&out);
    assert!(bytes < 1_000_000, "{bytes} bytes");
    eprintln!("the paper's ball: report.html of {bytes} bytes");

    // `zenosim report DIR` writes the same page.
    let html = std::fs::read(out.join("report.html")).unwrap();
    std::fs::remove_file(out.join("report.html")).unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 0);
    assert_eq!(std::fs::read(out.join("report.html")).unwrap(), html);
    assert_eq!(
        files(&out),
        [
            "model.toml",
            "report.html",
            "summary.json",
            "trajectory.csv"
        ]
    );
}

/// The shipped model `name`'s text.
fn shipped(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../models/{name}.toml"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A run with friction: the block on the belt (stick-slip) has its tangential force among the
/// plots, the friction states of its frames' modes, its stick and slip events with the other
/// events, and the work of friction in its energy balance; the ball dropped with backspin has
/// its impacts' normal and tangential impulses, as summary.json has them.
#[test]
fn a_run_with_friction_reports_its_forces_states_impulses_and_work() {
    let scratch = Scratch::new(&shipped("belt-stick-slip"));
    assert_exit(&scratch.run(&["--report"]), 0);
    let out = scratch.path("out");
    let summary = summary(&out);
    let data = data(&out);
    assert_eq!(data["friction"], serde_json::json!(["belt"]));
    let series = data["series"].as_array().unwrap();
    let force = series
        .iter()
        .find(|s| s["name"] == "f_belt")
        .expect("the tangential force is plotted");
    assert_eq!(force["group"], "Tangential forces");
    assert_eq!(
        series
            .iter()
            .filter(|s| s["group"] == "Tangential forces")
            .count(),
        1
    );
    // The force as the CSV has it (to single precision): within the static cone, and on the
    // kinetic force μₖ m g = 0.4 g where the block slips.
    let values = numbers(&force["y"]);
    assert!(values.len() > 100, "{} points", values.len());
    let g = 9.81;
    assert!(values.iter().all(|f| f.abs() <= 0.6 * g * (1.0 + 1e-6)));
    let kinetic = values
        .iter()
        .filter(|f| (*f - 0.4 * g).abs() < 1e-5)
        .count();
    assert!(kinetic > values.len() / 10, "{kinetic} of {}", values.len());

    // Each frame's mode says whether the belt sticks or slips, and both happen.
    let modes: Vec<&str> = data["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap())
        .collect();
    let stick = modes
        .iter()
        .position(|m| *m == "constrained:belt;stick:belt");
    let slip = modes
        .iter()
        .position(|m| *m == "constrained:belt;slip:belt");
    let frame_modes: Vec<usize> = data["frames"]["mode"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_u64().unwrap() as usize)
        .collect();
    for state in [stick, slip] {
        let state = state.expect("a mode of each state");
        assert!(frame_modes.iter().filter(|&&m| m == state).count() > 10);
    }
    // Every event, the stick and slip events among them, in the table.
    let kinds: Vec<&str> = data["events"]["kind"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| {
            data["events"]["kinds"][k.as_u64().unwrap() as usize]
                .as_str()
                .unwrap()
        })
        .collect();
    let expected: Vec<&str> = summary["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["kind"].as_str().unwrap())
        .collect();
    assert_eq!(kinds, expected);
    assert!(
        kinds.contains(&"stick") && kinds.contains(&"slip"),
        "{kinds:?}"
    );
    // The energy balance, with the work of friction (the belt's work in the moving
    // constraints').
    assert_eq!(data["balance"], summary["energy_balance"]);
    let work = data["balance"]["work_friction"].as_f64().unwrap();
    assert!(work < -1.0, "{work}");

    // The ball with backspin: its impacts' impulses, normal and tangential, on the floor.
    let scratch = Scratch::new(&shipped("ball-backspin"));
    assert_exit(&scratch.run(&["--report"]), 0);
    let out = scratch.path("out");
    let (summary, data) = (self::summary(&out), self::data(&out));
    let impulses = &data["events"]["impulses"];
    let names = &data["events"]["names"];
    let events = summary["events"].as_array().unwrap();
    assert_eq!(impulses["normal"].as_array().unwrap().len(), events.len());
    for (k, event) in events.iter().enumerate() {
        assert_eq!(impulses["normal"][k], event["impulses"], "event {k}");
        let tangential = event.get("tangential_impulses").cloned();
        let tangential = tangential.unwrap_or(serde_json::json!([]));
        assert_eq!(impulses["tangential"][k], tangential, "event {k}");
        let contacts: Vec<&Value> = impulses["contacts"][k]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| &names[c.as_u64().unwrap() as usize])
            .collect();
        let expected: Vec<&Value> = event["contacts"].as_array().unwrap().iter().collect();
        assert_eq!(contacts, expected, "event {k}");
    }
    // The first impact sticks: the tangential impulse (5 ẋ⁻ − 2 r θ̇⁻)/7 − ẋ⁻ that stops the
    // slip, (5 − 2·0.1·(−20))/7 − 1 = 2/7.
    let first = impulses["tangential"][0][0].as_f64().unwrap();
    assert!((first - 2.0 / 7.0).abs() < 1e-9, "{first}");
}

#[test]
fn a_run_of_a_million_rows_makes_a_report_of_a_few_megabytes() {
    // The ball on the floor sampled every 2 µs for 2 s: 10⁶ rows, the events among them.
    let scratch = Scratch::new(BALL);
    let output = scratch.run(&["--dt", "2e-6"]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    let summary = summary(&out);
    let rows = summary["trajectory"]["rows"].as_u64().unwrap();
    assert!(rows >= 1_000_000, "{rows} rows");
    let start = Instant::now();
    let output = scratch.zenosim(&["report", "out"]);
    let elapsed = start.elapsed();
    assert_exit(&output, 0);
    let bytes = size(&out);
    eprintln!(
        "{rows} rows: report.html of {bytes} bytes, written in {:.2} s",
        elapsed.as_secs_f64()
    );
    assert!(bytes < 3_000_000, "{bytes} bytes");
    let data = data(&out);
    let events = summary["events"].as_array().unwrap();
    assert!(events.len() > 10);
    let frames = numbers(&data["frames"]["t"]);
    assert!(
        frames.len() < 3 * 2000 + 2 * events.len(),
        "{}",
        frames.len()
    );
    let times = numbers(&data["events"]["t"]);
    for (event, t) in events.iter().zip(&times) {
        assert_eq!(event["t"].as_f64().unwrap(), *t);
        assert!(frames.iter().filter(|f| *f == t).count() >= 2, "t = {t}");
    }
    for series in data["series"].as_array().unwrap() {
        assert!(series["t"].as_array().unwrap().len() <= 4 * 2048);
    }
}

#[test]
fn a_folder_without_a_run_is_refused_naming_the_file() {
    let scratch = Scratch::new(BALL);
    std::fs::create_dir(scratch.path("empty")).unwrap();
    let output = scratch.zenosim(&["report", "empty"]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(
        error.contains("summary.json") && error.contains("zenosim run"),
        "{error}"
    );
    assert_eq!(files(&scratch.path("empty")), Vec::<String>::new());
}

#[test]
fn a_broken_trajectory_is_refused_and_nothing_is_written() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&[]), 0);
    let out = scratch.path("out");
    let path = out.join("trajectory.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let broken = text.replacen("\n0.", "\nzero.", 1);
    assert_ne!(broken, text);
    std::fs::write(&path, broken).unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(
        error.contains("trajectory.csv:") && error.contains("not a number"),
        "{error}"
    );
    assert!(!files(&out).iter().any(|f| f.contains("report")));

    std::fs::remove_file(&path).unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 2);
    assert!(
        stderr(&output).contains("trajectory.csv"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn a_broken_model_file_is_refused_naming_it() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&[]), 0);
    let out = scratch.path("out");
    std::fs::write(out.join("model.toml"), "name = \"ball\"\ncoordinates = [\n").unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(
        error.contains("model.toml") && error.contains("remove it"),
        "{error}"
    );
    assert!(!out.join("report.html").exists());

    // A model file of another model does not belong to the run.
    std::fs::write(out.join("model.toml"), BALL_ON_SINE).unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(error.contains("does not belong"), "{error}");

    // Without it, the report has no mechanism and says why.
    std::fs::remove_file(out.join("model.toml")).unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 0);
    let note = data(&out)["note"].as_str().unwrap().to_string();
    assert!(note.contains("no model.toml"), "{note}");
}

#[test]
fn a_new_run_removes_the_old_report() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--report"]), 0);
    assert!(scratch.path("out/report.html").exists());
    assert_exit(&scratch.run(&[]), 0);
    assert!(
        !scratch.path("out/report.html").exists(),
        "a report of the previous run stays beside the new one"
    );
}

/// The paper's ball with a drawing that reads a parameter `lift` (the point `raised`).
const DRAWING: &str = r#"
[drawing]
points = { contact = ["x2", "x3"], raised = ["x2", "x3 + lift"] }
surfaces = [{ constraint = "surface", curve = ["s", "sin(s)"], s = [-4, 2], samples = 50 }]
circles = [{ at = "contact", radius = 0.05 }]
trace = "contact"
"#;

/// The paper's ball, its parameter `lift` 1, with [`DRAWING`] (and `tail` after it).
fn drawn_ball(tail: &str) -> String {
    let model = BALL_ON_SINE.replace("g = 9.81\n", "g = 9.81\nlift = 1.0\n");
    format!("{model}{DRAWING}{tail}")
}

/// Runs `model` with `args` (which keeps the model file beside the run) and writes the report;
/// the scratch directory and the report's exit.
fn report_of(model: &str, args: &[&str]) -> (Scratch, std::process::Output) {
    let scratch = Scratch::new(model);
    assert_exit(&scratch.run(args), 0);
    let output = scratch.zenosim(&["report", "out"]);
    (scratch, output)
}

#[test]
fn the_mechanism_is_drawn_at_every_frame_with_the_runs_parameters() {
    let (scratch, output) = report_of(&drawn_ball(""), &["--set", "lift=2.5"]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    let data = data(&out);
    let mechanism = &data["mechanism"];
    assert_eq!(data["note"], Value::Null);
    assert_eq!(mechanism["dimension"], 2);
    let names: Vec<&str> = mechanism["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(names.len(), 2 + 50);
    assert_eq!(names[..3], ["contact", "raised", "surface#0"]);
    assert_eq!(mechanism["trace"], 0);
    // The surface's samples never move: given once; the two points move.
    assert_eq!(mechanism["moving"], serde_json::json!([0, 1]));
    let fixed = mechanism["fixed"].as_array().unwrap();
    assert!(fixed[2..].iter().all(|p| p.is_array()));
    let (s, y) = (fixed[2][0].as_f64().unwrap(), fixed[2][1].as_f64().unwrap());
    assert!((s + 4.0).abs() < 1e-6 && (y - s.sin()).abs() < 1e-6);

    let frames = numbers(&data["frames"]["t"]);
    let q = numbers(&data["frames"]["q"]);
    let positions = numbers(&mechanism["positions"]);
    assert_eq!(positions.len(), frames.len() * 2 * 2);
    for (k, t) in frames.iter().enumerate() {
        let (x2, x3) = (q[3 * k + 1], q[3 * k + 2]);
        let p = &positions[4 * k..4 * k + 4];
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * (1.0 + b.abs());
        assert!(close(p[0], x2) && close(p[1], x3), "contact at t = {t}");
        // `lift` is the run's (--set lift=2.5), not the file's 1.
        assert!(
            close(p[3], x3 + 2.5),
            "raised at t = {t}: {} vs {}",
            p[3],
            x3
        );
    }
    // At the Zeno point's switch (its last row) the contact point is on the surface.
    let t_switch = summary(&out)["zeno"][0]["t_switch"].as_f64().unwrap();
    let k = frames.iter().rposition(|&t| t == t_switch).unwrap();
    let (x, y) = (positions[4 * k], positions[4 * k + 1]);
    assert!((y - x.sin()).abs() < 1e-6, "({x}, {y})");
}

#[test]
fn a_drawing_that_is_not_finite_along_the_run_is_refused_naming_it() {
    // x3 − 2 is 0 at the start: the point `pole` is infinite there.
    let model = drawn_ball("").replace(
        "raised = [\"x2\", \"x3 + lift\"]",
        "raised = [\"x2\", \"x3 + lift\"], pole = [\"x2\", \"1/(x3 - 2)\"]",
    );
    let (scratch, output) = report_of(&model, &[]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(
        error.contains("out/model.toml: ") && error.contains("`pole`") && error.contains("t = 0"),
        "{error}"
    );
    assert!(!scratch.path("out/report.html").exists());
}

#[test]
fn a_three_dimensional_drawing_is_projected_on_x_y() {
    let model = drawn_ball("").replace(
        "[drawing]\npoints = { contact = [\"x2\", \"x3\"], raised = [\"x2\", \"x3 + lift\"] }\n\
         surfaces = [{ constraint = \"surface\", curve = [\"s\", \"sin(s)\"], s = [-4, 2], samples = 50 }]",
        "[drawing]\npoints = { contact = [\"x2\", \"x3\", \"x1\"], raised = [\"x2\", \"x3 + lift\", 0] }",
    );
    assert!(model.contains("\"x1\"]"), "{model}");
    let (scratch, output) = report_of(&model, &[]);
    assert_exit(&output, 0);
    let data = data(&scratch.path("out"));
    assert_eq!(data["mechanism"]["dimension"], 3);
    let frames = numbers(&data["frames"]["t"]).len();
    assert_eq!(
        numbers(&data["mechanism"]["positions"]).len(),
        frames * 2 * 2
    );
}

#[test]
fn a_state_that_is_not_finite_keeps_the_last_drawing() {
    // A run that diverged: its last row's x3 is NaN.
    let model = drawn_ball("");
    let scratch = Scratch::new(&model);
    assert_exit(&scratch.run(&["--t-end", "1"]), 0);
    let out = scratch.path("out");
    let path = out.join("trajectory.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let last = lines.pop().unwrap();
    let mut fields: Vec<&str> = last.split(',').collect();
    fields[4] = "NaN";
    lines.push(fields.join(","));
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let output = scratch.zenosim(&["report", "out"]);
    assert_exit(&output, 0);
    let data = data(&out);
    let positions = numbers(&data["mechanism"]["positions"]);
    let n = positions.len();
    assert_eq!(positions[n - 4..], positions[n - 8..n - 4]);
}

/// The report reads the model file again for its drawing: `zenosim report` had no
/// `--max-derivative-operations`, and `run --report` read it within the default limits whatever
/// the run was given. Both read it within the limits given now.
#[test]
fn the_report_reads_the_model_within_the_limits_it_is_given() {
    let (scratch, output) = report_of(&drawn_ball(""), &[]);
    assert_exit(&output, 0);
    let output = scratch.zenosim(&["report", "out", "--max-derivative-operations", "1"]);
    assert_exit(&output, 2);
    let error = stderr(&output);
    assert!(
        error.contains("more than the limit of 1 operations"),
        "{error}"
    );
}
