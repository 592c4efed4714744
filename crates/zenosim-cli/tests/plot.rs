//! `zenosim run --plot` and `zenosim plot DIR`: the files they write, that they parse (SVG) or
//! decode (PNG), and that they show what they must: the series, the event marks, the switch
//! line, the curve `h = 0`, the Zeno diagnostic; and the refusals of bad directories.
//!
//! The SVG groups its parts: `<g class="series|impacts|switch|stall|constraint|flights|…"
//! data-name="…">`. Positions are checked against the data: the time axis is calibrated on a
//! series' first and last points (t = 0 and t_end), the plane on two impacts.

mod common;

use common::*;
use roxmltree::{Document, Node};
use serde_json::Value;

/// The plots, by name.
const PLOTS: [&str; 6] = [
    "figure",
    "velocities",
    "displacements",
    "plane",
    "energy",
    "zeno",
];

/// The file `name` read as text.
fn text(path: &std::path::Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The groups of `class` (named `name`, if given).
fn groups<'a>(doc: &'a Document<'a>, class: &str, name: Option<&str>) -> Vec<Node<'a, 'a>> {
    doc.descendants()
        .filter(|n| n.has_tag_name("g") && n.attribute("class") == Some(class))
        .filter(|n| name.is_none_or(|name| n.attribute("data-name") == Some(name)))
        .collect()
}

/// The elements `tag` inside `nodes`.
fn inside<'a>(nodes: &[Node<'a, 'a>], tag: &str) -> Vec<Node<'a, 'a>> {
    nodes
        .iter()
        .flat_map(|g| g.descendants().filter(|n| n.has_tag_name(tag)))
        .collect()
}

/// A polyline's points.
fn points(polyline: &Node<'_, '_>) -> Vec<(f64, f64)> {
    polyline
        .attribute("points")
        .expect("a polyline has points")
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').expect("x,y");
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// A circle's centre.
fn centre(circle: &Node<'_, '_>) -> (f64, f64) {
    let at = |a: &str| circle.attribute(a).unwrap().parse::<f64>().unwrap();
    (at("cx"), at("cy"))
}

/// Every text of the document.
fn texts(doc: &Document<'_>) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").to_string())
        .collect()
}

/// The times of the events of `kind` in the summary.
fn event_times(s: &Value, kind: &str) -> Vec<f64> {
    s["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == kind)
        .map(|e| e["t"].as_f64().unwrap())
        .collect()
}

/// The linear map from `a.0 → a.1` and `b.0 → b.1`.
fn line_through(a: (f64, f64), b: (f64, f64)) -> impl Fn(f64) -> f64 {
    move |x| a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
}

/// Checks a time chart of the paper's ball: its series, the impact marks at the impacts'
/// times, the switch line at the switch; the pixel of time `t`.
fn check_time_chart(doc: &Document<'_>, series: &[&str], s: &Value) -> impl Fn(f64) -> f64 {
    let t_end = s["settings"]["t_end"].as_f64().unwrap();
    let mut axis = None;
    for name in series {
        let lines = inside(&groups(doc, "series", Some(name)), "polyline");
        assert_eq!(lines.len(), 1, "one line for {name}");
        let p = points(&lines[0]);
        assert!(p.len() > 100, "{name}: {} points", p.len());
        assert!(
            p.windows(2).all(|w| w[0].0 <= w[1].0),
            "{name} goes forward in time"
        );
        axis.get_or_insert((p[0].0, p[p.len() - 1].0));
    }
    let (left, right) = axis.expect("a series");
    let x_of = line_through((0.0, left), (t_end, right));

    let impacts = event_times(s, "impact");
    let marks = inside(&groups(doc, "impacts", None), "circle");
    assert_eq!(marks.len(), impacts.len(), "one mark per impact");
    for (mark, t) in marks.iter().zip(&impacts) {
        assert!(
            (centre(mark).0 - x_of(*t)).abs() <= 1.0,
            "impact at t = {t}"
        );
    }
    assert!(
        texts(doc).contains(&format!("impact ({})", impacts.len())),
        "the legend counts the impacts"
    );
    x_of
}

/// The x of a group's vertical line, and its label.
fn vertical_line(doc: &Document<'_>, class: &str) -> (f64, String) {
    let g = groups(doc, class, Some("surface"));
    assert_eq!(g.len(), 1, "one {class} group");
    let lines = inside(&g, "polyline");
    assert_eq!(lines.len(), 1);
    let p = points(&lines[0]);
    assert_eq!(p.len(), 2);
    assert_eq!(p[0].0, p[1].0, "vertical");
    assert!((p[0].1 - p[1].1).abs() > 100.0, "across the plot");
    let label = inside(&g, "text")[0].text().unwrap().to_string();
    (p[0].0, label)
}

#[test]
fn run_plot_draws_the_papers_figure_5() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.run(&["--plot"]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    let mut expected: Vec<String> = PLOTS.iter().map(|p| format!("{p}.svg")).collect();
    expected.extend(["model.toml", "summary.json", "trajectory.csv"].map(String::from));
    expected.sort();
    assert_eq!(files(&out), expected, "every plot, no temporary file");
    let report = stdout(&output);
    for plot in PLOTS {
        assert!(report.contains(&format!("out/{plot}.svg")), "{report}");
    }
    let s = summary(&out);
    assert_eq!(s["h"]["surface"], "x3 - sin(x2)", "summary.json holds h");
    let t_switch = s["zeno"][0]["t_switch"].as_f64().unwrap();

    for plot in PLOTS {
        let svg = text(&out.join(format!("{plot}.svg")));
        let doc = Document::parse(&svg).unwrap_or_else(|e| panic!("{plot}.svg: {e}"));
        let root = doc.root_element();
        assert!(root.has_tag_name("svg"), "{plot}");
        assert!(root.attribute("width").unwrap().parse::<u32>().unwrap() >= 800);
        assert!(
            texts(&doc).iter().any(|t| t.contains("ball-on-sine")),
            "{plot}: the title names the model"
        );
    }

    for (plot, series) in [
        ("velocities", ["x1_dot", "x2_dot", "x3_dot"]),
        ("displacements", ["x1", "x2", "x3"]),
    ] {
        let svg = text(&out.join(format!("{plot}.svg")));
        let doc = Document::parse(&svg).unwrap();
        let x_of = check_time_chart(&doc, &series, &s);
        let (x, label) = vertical_line(&doc, "switch");
        assert!((x - x_of(t_switch)).abs() <= 1.0, "{plot}: the switch line");
        assert!(label.contains("switch to constrained motion"), "{label}");
        assert!(label.contains(&format!("{t_switch:.5}")), "{label}");
        assert!(groups(&doc, "stall", None).is_empty());
        let all = texts(&doc);
        for name in series.iter().chain(&["t"]) {
            assert!(all.iter().any(|t| t == name), "{plot}: label {name}");
        }
    }

    // The figure holds both time charts and the plane.
    let svg = text(&out.join("figure.svg"));
    let doc = Document::parse(&svg).unwrap();
    assert_eq!(groups(&doc, "series", None).len(), 7);
    assert_eq!(groups(&doc, "switch", None).len(), 3);
    let impacts = event_times(&s, "impact").len();
    assert_eq!(
        inside(&groups(&doc, "impacts", None), "circle").len(),
        3 * impacts
    );
}

#[test]
fn the_plane_draws_the_surface_under_the_path() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let out = scratch.path("out");
    let s = summary(&out);
    let svg = text(&out.join("plane.svg"));
    let doc = Document::parse(&svg).unwrap();
    assert!(texts(&doc).iter().any(|t| t.contains("x3 against x2")));

    // Calibrate the axes on the two impacts furthest apart.
    let events: Vec<&Value> = s["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "impact")
        .collect();
    let marks = inside(&groups(&doc, "impacts", None), "circle");
    assert_eq!(marks.len(), events.len());
    let q = |k: usize| numbers(&events[k]["before"]["q"]);
    let (a, b) = (
        0,
        (1..events.len())
            .max_by(|&i, &j| {
                let d = |k: usize| (q(k)[1] - q(0)[1]).abs();
                d(i).total_cmp(&d(j))
            })
            .unwrap(),
    );
    let (pa, pb) = (centre(&marks[a]), centre(&marks[b]));
    let x2_of = line_through((pa.0, q(a)[1]), (pb.0, q(b)[1]));
    let x3_of = line_through((pa.1, q(a)[2]), (pb.1, q(b)[2]));
    // Every impact mark sits where its impact happened.
    for (k, mark) in marks.iter().enumerate() {
        let (x, y) = centre(mark);
        assert!((x2_of(x) - q(k)[1]).abs() < 0.02, "impact {k}");
        assert!((x3_of(y) - q(k)[2]).abs() < 0.02, "impact {k}");
    }

    // The surface h = 0: x3 = sin(x2), across the plot, drawn before (under) the path.
    let surface = groups(&doc, "constraint", Some("surface"));
    assert_eq!(surface.len(), 1);
    let curve: Vec<(f64, f64)> = inside(&surface, "polyline")
        .iter()
        .flat_map(points)
        .collect();
    assert!(curve.len() > 100);
    for &(x, y) in &curve {
        let (x2, x3) = (x2_of(x), x3_of(y));
        assert!(
            (x3 - x2.sin()).abs() < 0.04,
            "({x2}, {x3}) is on x3 = sin(x2)"
        );
    }
    let path = groups(&doc, "series", Some("path"));
    assert_eq!(inside(&path, "polyline").len(), 1);
    let position = |n: &Node<'_, '_>| n.range().start;
    assert!(
        position(&surface[0]) < position(&path[0]),
        "the surface is under the path"
    );
    // The path starts at the initial state.
    let start = inside(&groups(&doc, "start", None), "circle");
    let (x, y) = centre(&start[0]);
    assert!((x2_of(x) - std::f64::consts::FRAC_PI_3).abs() < 0.02);
    assert!((x3_of(y) - 2.0).abs() < 0.02);
    assert_eq!(
        groups(&doc, "switch", Some("surface")).len(),
        1,
        "the Zeno point"
    );
}

#[test]
fn zeno_off_draws_figure_4_stuck_at_the_zeno_point() {
    let scratch = Scratch::new(BALL_ON_SINE);
    let output = scratch.run(&["--zeno", "off", "--plot"]);
    assert_exit(&output, 3);
    let out = scratch.path("out");
    let s = summary(&out);
    let t_stop = s["final"]["t"].as_f64().unwrap();
    let svg = text(&out.join("displacements.svg"));
    let doc = Document::parse(&svg).unwrap();
    assert!(groups(&doc, "switch", None).is_empty(), "nothing switched");
    let (x, label) = vertical_line(&doc, "stall");
    assert!(label.contains("stalled at the Zeno point"), "{label}");
    // The lines stop at the stall, a third of the way along the axis to t_end = 6.
    assert!((t_stop - 2.0456).abs() < 1e-3, "{t_stop}");
    let lines = inside(&groups(&doc, "series", Some("x3")), "polyline");
    let p = points(&lines[0]);
    assert!(
        (p[p.len() - 1].0 - x).abs() <= 1.0,
        "the line ends at the stall"
    );
    let width: f64 = doc
        .root_element()
        .attribute("width")
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        x < 0.4 * width,
        "the axis goes on to t_end: the stall at {x} of {width}"
    );
    assert!(texts(&doc).contains(&"6".to_string()), "a tick at t = 6");
    let figure = text(&out.join("figure.svg"));
    assert!(
        figure.contains("stuck at the Zeno point"),
        "the figure's title"
    );
}

#[test]
fn the_zeno_diagnostic_is_a_straight_line_on_a_log_scale() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let out = scratch.path("out");
    let s = summary(&out);
    let z = &s["zeno"][0];
    let svg = text(&out.join("zeno.svg"));
    let doc = Document::parse(&svg).unwrap();
    let flights = inside(&groups(&doc, "flights", Some("surface")), "circle");
    let impacts = z["impacts"].as_u64().unwrap() as usize;
    assert_eq!(
        flights.len(),
        impacts - 1,
        "a flight between each two impacts"
    );
    // The flights shrink geometrically: on a log scale, equal steps down.
    let y: Vec<f64> = flights.iter().map(|c| centre(c).1).collect();
    let steps: Vec<f64> = y.windows(2).map(|w| w[1] - w[0]).collect();
    let tail = &steps[steps.len() - 15..];
    assert!(tail.iter().all(|d| *d > 0.0), "shrinking: {steps:?}");
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    assert!(
        tail.iter().all(|d| (d - mean).abs() <= 1.5),
        "straight: {tail:?}"
    );
    assert!(!inside(&groups(&doc, "fit", Some("surface")), "polyline").is_empty());
    let notes = texts(&doc).join("\n");
    let tau = z["t_zeno"].as_f64().unwrap();
    let ratio = z["ratio"].as_f64().unwrap();
    assert!(notes.contains(&format!("τ∞ ≈ {tau:.6}")), "{notes}");
    assert!(notes.contains(&format!("r = {ratio:.4}")), "{notes}");
    assert!(notes.contains("restitution e = 0.6"), "{notes}");
}

#[test]
fn plot_dir_draws_pngs_that_decode() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let output = scratch.zenosim(&["plot", "out", "--format", "png"]);
    assert_exit(&output, 0);
    let out = scratch.path("out");
    // The impacts' colour, as the SVG paints them.
    let svg = text(&out.join("velocities.svg"));
    let doc = Document::parse(&svg).unwrap();
    let fill = inside(&groups(&doc, "impacts", None), "circle")[0]
        .attribute("fill")
        .unwrap()
        .to_string();
    let rgb: Vec<u8> = (0..3)
        .map(|k| u8::from_str_radix(&fill[1 + 2 * k..3 + 2 * k], 16).unwrap())
        .collect();
    for plot in PLOTS {
        let path = out.join(format!("{plot}.png"));
        assert!(stdout(&output).contains(&format!("{plot}.png")));
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder
            .read_info()
            .unwrap_or_else(|e| panic!("{plot}.png: {e}"));
        let mut pixels = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut pixels).unwrap();
        assert!(info.width >= 800 && info.height >= 400, "{plot}.png");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let rgb_pixels = pixels.chunks(3);
        let marked = rgb_pixels.clone().filter(|p| *p == rgb.as_slice()).count();
        let white = rgb_pixels.filter(|p| *p == [255, 255, 255]).count();
        let total = (info.width * info.height) as usize;
        assert!(
            white > total / 2 && white < total,
            "{plot}.png is drawn on white"
        );
        if plot != "zeno" {
            assert!(
                marked > 100,
                "{plot}.png shows the impacts: {marked} pixels"
            );
        }
    }
    // The SVGs are still there, untouched by the PNG run.
    assert!(out.join("figure.svg").exists());
}

#[test]
fn the_plane_flag_chooses_the_axes() {
    let scratch = Scratch::new(BALL_ON_SINE);
    assert_exit(&scratch.run(&["--plot", "--plane", "x1,x2"]), 0);
    let svg = text(&scratch.path("out/plane.svg"));
    let doc = Document::parse(&svg).unwrap();
    assert!(texts(&doc).iter().any(|t| t.contains("x2 against x1")));
    assert!(groups(&doc, "constraint", None).is_empty(), "h reads x3");
    // A phase plane of the ball on the floor: the floor h = x is the line x = 0.
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let svg = text(&scratch.path("out/plane.svg"));
    let doc = Document::parse(&svg).unwrap();
    assert!(texts(&doc).iter().any(|t| t.contains("x_dot against x")));
    let floor = inside(&groups(&doc, "constraint", Some("floor")), "polyline");
    let p: Vec<(f64, f64)> = floor.iter().flat_map(points).collect();
    assert!(
        p.len() >= 2 && p.iter().all(|q| (q.0 - p[0].0).abs() <= 1.0),
        "vertical"
    );
    // `zenosim plot` redraws another plane from the same files.
    assert_exit(&scratch.zenosim(&["plot", "out", "--plane", "x_dot,x"]), 0);
    let svg = text(&scratch.path("out/plane.svg"));
    assert!(svg.contains("x against x_dot"));
}

#[test]
fn a_few_rows_and_many_rows_both_draw() {
    // Three rows: every one is drawn, joined smoothly.
    let scratch = Scratch::new(BALL);
    assert_exit(
        &scratch.run(&["--plot", "--dt", "0.2", "--t-end", "0.4"]),
        0,
    );
    let svg = text(&scratch.path("out/displacements.svg"));
    let doc = Document::parse(&svg).unwrap();
    let line = inside(&groups(&doc, "series", Some("x")), "polyline");
    assert!(points(&line[0]).len() >= 3);
    assert!(groups(&doc, "impacts", None).is_empty(), "no impact yet");
    assert!(texts(&doc).contains(&"impact (0)".to_string()));

    // 40 000 steps: the lines are decimated, no impact mark is lost.
    let source = BALL.replace("t_end = 2.0", "t_end = 2.0\nmax_step = 5e-5");
    let scratch = Scratch::new(&source);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let s = summary(&scratch.path("out"));
    assert!(s["trajectory"]["rows"].as_u64().unwrap() > 40_000);
    for (plot, series) in [
        ("velocities", "x_dot"),
        ("displacements", "x"),
        ("energy", "energy"),
    ] {
        let svg = text(&scratch.path(&format!("out/{plot}.svg")));
        let doc = Document::parse(&svg).unwrap();
        let lines = inside(&groups(&doc, "series", None), "polyline");
        assert_eq!(lines.len(), 1);
        let n = points(&lines[0]).len();
        assert!((1000..=4 * 2048).contains(&n), "{plot}: {n} points");
        let _ = check_time_chart(&doc, &[series], &s);
    }
}

#[test]
fn a_rerun_without_plot_removes_the_old_plots() {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&["--plot"]), 0);
    assert_exit(&scratch.run(&["--plot", "--format", "png"]), 0);
    assert_eq!(
        files(&scratch.path("out")).len(),
        3 + 6,
        "the SVGs are gone"
    );
    assert_exit(&scratch.run(&[]), 0);
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
}

/// The distance from `p` to the polyline `line`, in pixels.
fn distance_to(p: (f64, f64), line: &[(f64, f64)]) -> f64 {
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let length = dx * dx + dy * dy;
            let s = if length > 0.0 {
                (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / length).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p.0 - a.0 - s * dx).hypot(p.1 - a.1 - s * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

/// A trajectory with the energy balance's columns (a model that is not autonomous) draws
/// `E(0) + work − impact loss` dashed over the energy, where it coincides with it. The columns
/// are written here into the ball's trajectory, with the impacts' loss `E(0) − E(t)` that its
/// balance has.
#[test]
fn the_energy_plot_draws_the_balance_over_the_energy() {
    let scratch = ball_run();
    let path = scratch.path("out/trajectory.csv");
    let csv = text(&path);
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let energy = header.split(',').position(|c| c == "energy").unwrap();
    let mut e0 = None;
    let mut out = format!("{header},{WORK_COLUMNS}\n");
    for line in lines {
        let e: f64 = line.split(',').nth(energy).unwrap().parse().unwrap();
        let e0 = *e0.get_or_insert(e);
        out.push_str(&format!("{line},0,0,0,{}\n", e0 - e));
    }
    std::fs::write(&path, out).unwrap();
    let output = scratch.zenosim(&["plot", "out"]);
    assert_exit(&output, 0);

    let s = summary(&scratch.path("out"));
    let svg = text(&scratch.path("out/energy.svg"));
    let doc = Document::parse(&svg).unwrap();
    let _ = check_time_chart(&doc, &["energy"], &s);
    let label = "E(0) + work − impact loss";
    assert!(
        texts(&doc).contains(&label.to_string()),
        "the legend names it"
    );
    let energy = points(&inside(&groups(&doc, "series", Some("energy")), "polyline")[0]);
    let dashes = inside(&groups(&doc, "series", Some(label)), "polyline");
    assert!(dashes.len() > 50, "dashed: {} dashes", dashes.len());
    let dashes: Vec<(f64, f64)> = dashes.iter().flat_map(points).collect();
    // From the start to the end, on the energy's line.
    let (left, right) = (energy[0].0, energy[energy.len() - 1].0);
    let xs = dashes.iter().map(|p| p.0);
    let (first, last) = (
        xs.clone().fold(f64::INFINITY, f64::min),
        xs.fold(0.0, f64::max),
    );
    assert!(
        first - left < 15.0 && right - last < 15.0,
        "{first}..{last}"
    );
    for p in &dashes {
        let d = distance_to(*p, &energy);
        assert!(d <= 1.5, "{p:?} is {d} px from the energy");
    }
    // The other plots do not draw it.
    let svg = text(&scratch.path("out/figure.svg"));
    assert!(!svg.contains(label));
}

/// With impacts on several constraints (the corner: the floor's, then the wall's while the
/// floor holds), each constraint's impacts are marked on a row of their own, named, and the
/// switch onto both walls names them.
#[test]
fn impacts_are_marked_per_constraint_and_a_switch_names_its_set() {
    let source = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/corner.toml"),
    )
    .unwrap();
    let scratch = Scratch::new(&source);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let s = summary(&scratch.path("out"));
    let svg = text(&scratch.path("out/velocities.svg"));
    let doc = Document::parse(&svg).unwrap();
    for name in ["wall", "floor"] {
        let count = s["events"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|e| e["kind"] == "impact" && e["constraint"] == name)
            .count();
        let marks = inside(&groups(&doc, "impacts", Some(name)), "circle");
        assert_eq!(marks.len(), count, "{name}");
        assert!(texts(&doc).contains(&format!("impact on {name} ({count})")));
    }
    // The rows are apart: every wall mark on one height, every floor mark on another.
    let height = |name| {
        let marks = inside(&groups(&doc, "impacts", Some(name)), "circle");
        let ys: Vec<f64> = marks.iter().map(|c| centre(c).1).collect();
        assert!(ys.windows(2).all(|w| w[0] == w[1]), "{name}");
        ys[0]
    };
    assert!((height("wall") - height("floor")).abs() >= 8.0);
    let labels: Vec<String> = texts(&doc);
    assert!(
        labels
            .iter()
            .any(|t| t.starts_with("switch to constrained motion on wall+floor")),
        "{labels:?}"
    );
}

/// Regression: the Zeno diagnostic of an accumulation that alternates between constraints (the
/// rocking block's corners) was an empty panel, its sequence cut at every change of constraint.
/// It draws every flight of the accumulation, on a line of ratio 7/13 (the block's closed form).
#[test]
fn an_alternating_accumulation_draws_its_flights() {
    let source = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/rocking-block.toml"),
    )
    .unwrap();
    let scratch = Scratch::new(&source);
    assert_exit(&scratch.run(&["--plot"]), 0);
    let s = summary(&scratch.path("out"));
    let last = s["zeno"].as_array().unwrap().last().unwrap().clone();
    assert_eq!(last["constraints"], serde_json::json!(["left", "right"]));
    let svg = text(&scratch.path("out/zeno.svg"));
    let doc = Document::parse(&svg).unwrap();
    let marks = inside(&groups(&doc, "flights", None), "circle");
    let impacts = last["impacts"].as_u64().unwrap() as usize;
    assert!(impacts >= 10, "{impacts}");
    assert_eq!(
        marks.len(),
        impacts - 1,
        "a flight between each two impacts"
    );
    let all = texts(&doc);
    assert!(
        all.iter().any(|t| t.contains("on 'left'+'right'")),
        "{all:?}"
    );
    assert!(all.iter().any(|t| t == "fit: ratio r = 0.5385"), "{all:?}");
}

// ----- refusals -------------------------------------------------------------------------------

/// `zenosim plot <args>` refused with exit 2 and an `error: ` message, which it returns.
fn plot_refused(scratch: &Scratch, args: &[&str]) -> String {
    let mut all = vec!["plot"];
    all.extend_from_slice(args);
    let output = scratch.zenosim(&all);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(err.starts_with("error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// A scratch directory with a complete run of the ball in `out`.
fn ball_run() -> Scratch {
    let scratch = Scratch::new(BALL);
    assert_exit(&scratch.run(&[]), 0);
    scratch
}

#[test]
fn a_directory_without_a_run_is_refused_naming_the_file() {
    let scratch = Scratch::new(BALL);
    let err = plot_refused(&scratch, &["nowhere"]);
    assert!(err.contains("nowhere/summary.json"), "{err}");
    let scratch = ball_run();
    std::fs::remove_file(scratch.path("out/trajectory.csv")).unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(err.contains("out/trajectory.csv"), "{err}");
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json"],
        "nothing is written"
    );
}

#[test]
fn a_malformed_trajectory_names_its_line() {
    let scratch = ball_run();
    let path = scratch.path("out/trajectory.csv");
    let csv = text(&path);
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    lines[4] = lines[4].replacen(",free,", ",free,abc", 1);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(err.contains("out/trajectory.csv:5:"), "{err}");
    assert!(err.contains("`abc") && err.contains("column x"), "{err}");

    lines = csv.lines().map(str::to_string).collect();
    lines[7] = "0.5,free,1".to_string();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(err.contains("out/trajectory.csv:8:"), "{err}");
    assert!(err.contains("3 fields"), "{err}");

    // A trajectory cut short no longer matches its summary.
    lines = csv.lines().map(str::to_string).collect();
    lines.truncate(10);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(
        err.contains("9 rows") && err.contains("do not belong together"),
        "{err}"
    );

    // Another model's trajectory.
    std::fs::write(&path, "t,mode,y,y_dot,h_floor,lambda_floor,energy\n").unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(
        err.contains("out/trajectory.csv:1:") && err.contains("header"),
        "{err}"
    );
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
}

#[test]
fn a_malformed_summary_names_its_line_and_column() {
    let scratch = ball_run();
    let path = scratch.path("out/summary.json");
    let json = text(&path);
    std::fs::write(&path, json.replacen("\"events\": [", "\"events\": [}", 1)).unwrap();
    let err = plot_refused(&scratch, &["out"]);
    let line = json.lines().position(|l| l.contains("\"events\"")).unwrap() + 1;
    assert!(err.contains(&format!("out/summary.json:{line}:")), "{err}");
    std::fs::write(&path, "{\"model\": 3}").unwrap();
    let err = plot_refused(&scratch, &["out"]);
    assert!(err.contains("out/summary.json:1:"), "{err}");
}

#[test]
fn bad_plot_arguments_are_refused_before_anything_is_written() {
    let scratch = ball_run();
    let err = plot_refused(&scratch, &["out", "--plane", "x,z"]);
    assert!(err.contains("`z`") && err.contains("x, x_dot"), "{err}");
    plot_refused(&scratch, &["out", "--plane", "x"]);
    plot_refused(&scratch, &["out", "--format", "gif"]);
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );

    // `run`: checked before the output directory is touched.
    let scratch = Scratch::new(BALL);
    for args in [
        &["--plot", "--plane", "x,y"][..],
        &["--format", "png"],
        &["--plane", "x,x_dot"],
    ] {
        let output = scratch.run(args);
        assert_exit(&output, 2);
        assert!(
            stderr(&output).starts_with("error: "),
            "{}",
            stderr(&output)
        );
        assert!(!scratch.path("out").exists(), "{args:?}");
    }
}

#[cfg(unix)]
#[test]
fn a_plot_that_cannot_be_written_is_exit_1_and_leaves_no_partial_file() {
    // Files limited to 2 KB: the first plot's write fails (EFBIG), as on a full disk.
    let scratch = ball_run();
    let output = scratch.zenosim_limited(4, &["plot", "out"]);
    assert_exit(&output, 1);
    let err = stderr(&output);
    assert!(err.starts_with("error: cannot write "), "{err}");
    assert!(err.contains("figure.svg"), "{err}");
    assert_eq!(
        files(&scratch.path("out")),
        ["model.toml", "summary.json", "trajectory.csv"]
    );
}

/// `zenosim <args>` in `scratch`, killed after `limit`: its exit status, or `None` if it was
/// still running (a hang).
fn status_within(scratch: &Scratch, args: &[&str], limit: std::time::Duration) -> Option<i32> {
    let mut child = std::process::Command::new(binary())
        .args(args)
        .current_dir(scratch.dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("zenosim starts");
    let start = std::time::Instant::now();
    while start.elapsed() < limit {
        if let Some(status) = child.try_wait().expect("zenosim is waited for") {
            return status.code();
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

/// Regression: an axis range near f64's limits (a ball at rest at 1.7e308), or one too narrow
/// for f64 to place ticks on (at rest at 1e15), made plotters' tick generator loop forever, and
/// `zenosim run --plot` never ended. Ranges are now finite and resolvable (`chart::drawable`).
#[test]
fn plots_of_values_near_f64_limits_are_drawn_and_end() {
    for (h0, t_end) in [("1.7e308", "2"), ("1e15", "2"), ("1", "1.7e308")] {
        let source = BALL
            .replace("g = 9.81", "g = 0.0")
            .replace("x = 1.0", &format!("x = {h0}"));
        let scratch = Scratch::new(&source);
        let args = [
            "run",
            "model.toml",
            "--out",
            "out",
            "--plot",
            "--t-end",
            t_end,
        ];
        let status = status_within(&scratch, &args, std::time::Duration::from_secs(60));
        assert_eq!(status, Some(0), "x = {h0}, t_end = {t_end}");
        for plot in ["displacements.svg", "plane.svg", "energy.svg"] {
            assert!(scratch.path("out").join(plot).exists(), "{plot}");
        }
    }
}

// ----- found by the plot fuzz target (fuzz/fuzz_targets/plot.rs) -------------------------------

/// The summary.json of the ball's run in `scratch`, changed by `change`.
fn change_summary(scratch: &Scratch, change: impl FnOnce(&mut Value)) {
    let path = scratch.path("out/summary.json");
    let mut summary: Value = serde_json::from_str(&text(&path)).unwrap();
    change(&mut summary);
    std::fs::write(&path, summary.to_string()).unwrap();
}

#[test]
fn a_long_string_of_the_wrong_type_in_the_summary_is_quoted_short() {
    // serde quotes a string where it expects another type whole: the message was 5 KB.
    let scratch = ball_run();
    change_summary(&scratch, |s| {
        s["coordinates"] = Value::from("x".repeat(5000))
    });
    let err = plot_refused(&scratch, &["out"]);
    assert!(
        err.len() < 600,
        "{} bytes: {}…",
        err.len(),
        err.chars().take(600).collect::<String>()
    );
    assert!(
        err.contains("out/summary.json:1:") && err.contains("bytes in all)"),
        "{err}"
    );
}

#[test]
fn a_plane_of_unknown_names_lists_the_columns_short() {
    // The message listed every coordinate and velocity: 40 KB for 3000 coordinates.
    let scratch = ball_run();
    change_summary(&scratch, |s| {
        s["coordinates"] = (0..3000).map(|i| format!("y{i}")).collect();
        s["velocities"] = (0..3000).map(|i| format!("y{i}_dot")).collect();
    });
    let long = format!("{},b", "a".repeat(1000));
    let err = plot_refused(&scratch, &["out", "--plane", &long]);
    assert!(
        err.len() < 800,
        "{} bytes: {}…",
        err.len(),
        err.chars().take(800).collect::<String>()
    );
    assert!(
        err.contains("y0, y1, y2") && err.contains("bytes in all"),
        "{err}"
    );
}

/// Counts the bytes each thread has allocated and not freed, for the leak test.
struct CountingAllocator;

thread_local! {
    static LIVE_BYTES: std::cell::Cell<isize> = const { std::cell::Cell::new(0) };
}

fn count(bytes: isize) {
    // `try_with`: nothing to count in a thread being torn down.
    let _ = LIVE_BYTES.try_with(|live| live.set(live.get() + bytes));
}

// SAFETY: every call is passed on to the system allocator unchanged; the count is a side note.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        count(layout.size() as isize);
        // SAFETY: as the caller's.
        unsafe { std::alloc::System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        count(-(layout.size() as isize));
        // SAFETY: as the caller's.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, size: usize) -> *mut u8 {
        count(size as isize - layout.size() as isize);
        // SAFETY: as the caller's.
        unsafe { std::alloc::System.realloc(ptr, layout, size) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

#[test]
fn drawing_plots_again_and_again_leaks_no_memory() {
    // Each temporary file's path was kept for a second Ctrl-C as a C string never freed, though
    // `zenosim plot` handles no signal: about 100 bytes a file, without bound in a process that
    // draws again and again (the fuzz target; LeakSanitizer found it).
    let scratch = ball_run();
    let dir = scratch.path("out");
    let draw = || zenosim_cli::draw(&dir, zenosim_cli::Format::Svg, None).expect("drawn");
    // Once first: the font, the locks' table and other caches are filled once for all.
    draw();
    let live = || LIVE_BYTES.with(std::cell::Cell::get);
    let before = live();
    for _ in 0..10 {
        draw();
    }
    let leaked = live() - before;
    assert!(leaked <= 0, "10 drawings kept {leaked} bytes");
}
