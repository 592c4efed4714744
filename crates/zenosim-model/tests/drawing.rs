//! `[drawing]`: its points evaluated against hand-computed positions, `--set` followed, its
//! shapes read in the file's order, and every way it can be refused.

use zenosim::HybridLagrangian;
use zenosim_model::{
    parse_model, parse_model_with, DrawingError, Limits, Location, ModelError, ModelFile, Override,
    Shape,
};

/// A pendulum of length `l` hanging from a pivot that moves with `x`, drawn with a rod, a bob
/// and a floor; the cases below break one thing in it.
const PENDULUM: &str = r#"name = "pendulum"
coordinates = ["theta", "x"]
lagrangian = "0.5*m*l^2*theta_dot^2 + 0.5*x_dot^2 + m*g*l*cos(theta)"

[parameters]
m = 1.0
g = 9.81
l = 2.0
r = "l/10"
e = 0.5

[[constraint]]
name = "ground"
h = "H - l*cos(theta)"
restitution = "e"

[[constraint]]
name = "rail"
h = "x + 5"
restitution = "e"

[initial]
theta = 0.3

[drawing]
points = { pivot = ["x", 0], bob = ["x + l*sin(theta)", "-l*cos(theta)"], left = [-3, "-H"], right = ["3", "-H"], marker = ["0.5*t", 1] }
segments = [["pivot", "bob"]]
circles = [{ at = "bob", radius = "r" }]
polylines = [{ through = ["left", "pivot", "right"], closed = true }]
surfaces = [{ constraint = "ground", through = ["left", "right"] }]
trace = "bob"
"#;

fn source() -> String {
    // `H` is a parameter of h and of the drawing.
    PENDULUM.replace("e = 0.5\n", "e = 0.5\nH = 2.5\n")
}

fn load(source: &str, overrides: &[Override]) -> Result<ModelFile, ModelError> {
    parse_model("case.toml", source, overrides)
}

fn set(text: &str) -> Override {
    text.parse().unwrap()
}

fn positions(file: &ModelFile, t: f64, q: &[f64]) -> Vec<f64> {
    let drawing = file.drawing.as_ref().expect("a drawing");
    let mut out = vec![f64::NAN; drawing.points().len() * drawing.dimension()];
    drawing.evaluate(t, q, &mut out).expect("finite");
    out
}

#[test]
fn the_points_are_where_the_formulas_put_them() {
    let file = load(&source(), &[]).unwrap();
    let drawing = file.drawing.as_ref().unwrap();
    assert_eq!(
        drawing.points(),
        ["pivot", "bob", "left", "right", "marker"],
        "the file's order"
    );
    assert_eq!(drawing.dimension(), 2);
    assert_eq!(drawing.trace(), Some(1));
    // θ = 0.3, x = 0.25, l = 2, t = 0.8: the bob at (x + l sin θ, −l cos θ), by hand with
    // sin 0.3 = 0.29552020666134, cos 0.3 = 0.95533648912561.
    let out = positions(&file, 0.8, &[0.3, 0.25]);
    let expected = [
        0.25,
        0.0,
        0.25 + 2.0 * 0.29552020666134,
        -2.0 * 0.95533648912561,
        -3.0,
        -2.5,
        3.0,
        -2.5,
        0.4,
        1.0,
    ];
    for (k, (got, want)) in out.iter().zip(expected).enumerate() {
        assert!((got - want).abs() < 1e-12, "value {k}: {got} vs {want}");
    }
    // One point alone, the same.
    let mut bob = [0.0; 2];
    drawing
        .evaluate_point(1, 0.8, &[0.3, 0.25], &mut bob)
        .unwrap();
    assert_eq!(bob, out[2..4]);
}

#[test]
fn the_shapes_are_read_in_the_files_order() {
    let file = load(&source(), &[]).unwrap();
    let drawing = file.drawing.as_ref().unwrap();
    assert_eq!(
        drawing.shapes(),
        [
            Shape::Segment { from: 0, to: 1 },
            Shape::Circle {
                center: 1,
                radius: 0.2
            },
            Shape::Polyline {
                points: vec![2, 0, 3],
                closed: true
            },
            Shape::Surface {
                constraint: 0,
                points: vec![2, 3]
            },
        ]
    );
    assert!(drawing.reads_time(), "the marker moves with t");
}

#[test]
fn set_changes_the_drawing() {
    let file = load(&source(), &[set("l=3"), set("H=4")]).unwrap();
    let out = positions(&file, 0.0, &[0.0, 0.0]);
    assert_eq!(&out[2..8], [0.0, -3.0, -3.0, -4.0, 3.0, -4.0]);
    // r = l/10 follows l.
    let drawing = file.drawing.as_ref().unwrap();
    assert!(matches!(
        drawing.shapes()[1],
        Shape::Circle { radius, .. } if (radius - 0.3).abs() < 1e-15
    ));
}

#[test]
fn a_model_without_a_drawing_has_none() {
    let end = source().find("[drawing]").unwrap();
    let file = load(&source()[..end], &[]).unwrap();
    assert!(file.drawing.is_none());
}

#[test]
fn triples_are_points_in_space() {
    let end = source().find("[drawing]").unwrap();
    let text = format!(
        "{}[drawing]\npoints = {{ a = [\"x\", 0, \"theta\"], b = [1, 2, \"t\"] }}\nsegments = [[\"a\", \"b\"]]\n",
        &source()[..end]
    );
    let file = load(&text, &[]).unwrap();
    assert_eq!(file.drawing.as_ref().unwrap().dimension(), 3);
    assert_eq!(
        positions(&file, 5.0, &[0.1, 0.2]),
        [0.2, 0.0, 0.1, 1.0, 2.0, 5.0]
    );
}

#[test]
fn a_curve_is_sampled_evenly() {
    let end = source().find("[drawing]").unwrap();
    let text = format!(
        "{}[drawing]\npoints = {{ bob = [\"l*sin(theta)\", \"-l*cos(theta)\"] }}\n\
         surfaces = [{{ constraint = \"ground\", curve = [\"s\", \"-H + 0.1*s*t\"], s = [-2, \"l\"], samples = 5 }}]\n",
        &source()[..end]
    );
    let file = load(&text, &[]).unwrap();
    let drawing = file.drawing.as_ref().unwrap();
    assert_eq!(
        drawing.points(),
        ["bob", "ground#0", "ground#1", "ground#2", "ground#3", "ground#4"]
    );
    assert_eq!(
        drawing.shapes(),
        [Shape::Surface {
            constraint: 0,
            points: vec![1, 2, 3, 4, 5]
        }]
    );
    // s from −2 to l = 2 in 4 steps of 1; at t = 10 the curve is y = −2.5 + s.
    let out = positions(&file, 10.0, &[0.0, 0.0]);
    assert_eq!(
        &out[2..],
        [-2.0, -4.5, -1.0, -3.5, 0.0, -2.5, 1.0, -1.5, 2.0, -0.5]
    );
}

#[test]
fn a_formula_that_is_not_finite_is_an_error_not_a_panic() {
    let text = source().replace("marker = [\"0.5*t\", 1]", "marker = [\"sqrt(x)\", 1]");
    let file = load(&text, &[]).unwrap();
    let drawing = file.drawing.as_ref().unwrap();
    let mut out = vec![0.0; 10];
    assert!(drawing.evaluate(0.0, &[0.0, 1.0], &mut out).is_ok());
    let error = drawing.evaluate(0.0, &[0.0, -1.0], &mut out).unwrap_err();
    assert!(
        matches!(&error, DrawingError::NotFinite { point, axis: 0, .. } if point == "marker"),
        "{error:?}"
    );
    assert!(error.to_string().contains("`marker`"), "{error}");
    // Wrong lengths are errors too.
    assert!(matches!(
        drawing.evaluate(0.0, &[0.0], &mut out),
        Err(DrawingError::Length { expected: 2, .. })
    ));
    assert!(matches!(
        drawing.evaluate(0.0, &[0.0, 1.0], &mut out[..9]),
        Err(DrawingError::Length { expected: 10, .. })
    ));
}

/// The error of `source` with `from` replaced by `to` (which must occur).
fn refused(from: &str, to: &str) -> ModelError {
    let text = source();
    assert!(text.contains(from), "{from}");
    match load(&text.replacen(from, to, 1), &[]) {
        Ok(_) => panic!("accepted with {to}"),
        Err(e) => e,
    }
}

/// Asserts the error points at `line:column` (1-based), under `key`, and that its message
/// holds `message`.
fn at(error: &ModelError, line: usize, column: usize, key: Option<&str>, message: &str) {
    match &error.location {
        Location::At {
            line: l,
            column: c,
            key: k,
        } => {
            assert_eq!((*l, *c), (line, column), "{error}");
            assert_eq!(k.as_deref(), key, "{error}");
        }
        other => panic!("not at a place: {other:?}: {error}"),
    }
    assert!(error.message.contains(message), "{error}");
    assert!(error.help.is_some(), "{error}");
    assert_eq!(&*error.file, "case.toml");
}

/// The line the drawing's points are on in `source()`, 1-based.
fn points_line() -> usize {
    source()
        .lines()
        .position(|l| l.starts_with("points"))
        .unwrap()
        + 1
}

/// The 1-based column of the `n`-th (from 0) occurrence of `needle` on the points' line.
fn column_of(line: &str, needle: &str) -> usize {
    line.find(needle).unwrap() + 1
}

#[test]
fn an_unknown_point_in_a_shape() {
    let error = refused(
        "segments = [[\"pivot\", \"bob\"]]",
        "segments = [[\"pivot\", \"bobb\"]]",
    );
    // Columns counted on the lines of `PENDULUM`: the opening quote of the name.
    let line = points_line() + 1;
    at(
        &error,
        line,
        23,
        Some("drawing.segments[0][1]"),
        "unknown point `bobb`",
    );
    assert!(error.help.as_ref().unwrap().contains("`bob`"), "{error}");
    let error = refused("at = \"bob\"", "at = \"ball\"");
    at(
        &error,
        points_line() + 2,
        19,
        Some("drawing.circles[0].at"),
        "unknown point `ball`",
    );
    let error = refused("trace = \"bob\"", "trace = \"tip\"");
    at(
        &error,
        points_line() + 5,
        9,
        Some("drawing.trace"),
        "unknown point `tip`",
    );
}

#[test]
fn an_unknown_constraint() {
    let error = refused("constraint = \"ground\"", "constraint = \"floor\"");
    at(
        &error,
        points_line() + 4,
        28,
        Some("drawing.surfaces[0].constraint"),
        "unknown constraint `floor`",
    );
    let help = error.help.unwrap();
    assert!(
        help.contains("`ground`") && help.contains("`rail`"),
        "{help}"
    );
}

#[test]
fn a_point_with_one_or_four_formulas() {
    let line = points_line();
    for (to, count) in [("[\"x\"]", "1 formula"), ("[\"x\", 0, 0, 0]", "4 formulas")] {
        let error = refused("pivot = [\"x\", 0]", &format!("pivot = {to}"));
        at(
            &error,
            line,
            20,
            Some("drawing.points.pivot"),
            &format!("point `pivot` has {count}"),
        );
    }
}

#[test]
fn mixed_pairs_and_triples() {
    let error = refused(
        "bob = [\"x + l*sin(theta)\", \"-l*cos(theta)\"]",
        "bob = [\"x\", 0, 1]",
    );
    let text = source();
    let line_text = text.lines().nth(points_line() - 1).unwrap();
    at(
        &error,
        points_line(),
        column_of(line_text, "bob = ") + 6,
        Some("drawing.points.bob"),
        "point `bob` has 3 formulas, but point `pivot` has 2",
    );
}

#[test]
fn a_syntax_error_in_a_formula() {
    let error = refused("-l*cos(theta)", "-l*cos(theta");
    let text = source();
    let line_text = text.lines().nth(points_line() - 1).unwrap();
    // The caret at the `(` that is never closed.
    let column = column_of(line_text, "-l*cos(theta") + "-l*cos".len();
    at(
        &error,
        points_line(),
        column,
        Some("drawing.points.bob[1]"),
        "in the drawing's point `bob`",
    );
}

#[test]
fn a_formula_using_a_velocity_or_an_unknown_name() {
    let text = source();
    let line_text = text.lines().nth(points_line() - 1).unwrap();
    let error = refused("pivot = [\"x\", 0]", "pivot = [\"x_dot\", 0]");
    at(
        &error,
        points_line(),
        column_of(line_text, "pivot = ") + 10,
        Some("drawing.points.pivot[0]"),
        "the drawing's point `pivot` uses the velocity `x_dot`",
    );
    assert!(error.help.unwrap().contains("not of velocities"));
    let error = refused("pivot = [\"x\", 0]", "pivot = [\"y\", 0]");
    at(
        &error,
        points_line(),
        column_of(line_text, "pivot = ") + 10,
        Some("drawing.points.pivot[0]"),
        "unknown name `y` in the drawing's point `pivot`",
    );
}

#[test]
fn a_radius_that_is_not_a_positive_finite_number() {
    for (radius, message) in [
        ("0", "radius is 0; it must be > 0"),
        ("\"-r\"", "radius is -0.2; it must be > 0"),
        ("\"1/0\"", "radius evaluates to inf"),
        ("\"theta\"", "radius uses the coordinate `theta`"),
    ] {
        let error = refused("radius = \"r\"", &format!("radius = {radius}"));
        assert_eq!(error.key(), Some("drawing.circles[0].radius"), "{error}");
        assert!(error.message.contains(message), "{radius}: {error}");
    }
}

#[test]
fn duplicate_point_names() {
    // The TOML reader refuses the second key, at its place.
    let error = refused("marker = [", "bob = [");
    let text = source();
    let line_text = text.lines().nth(points_line() - 1).unwrap();
    // The second `bob` is where `marker` was.
    let second = column_of(line_text, "marker = [");
    assert_eq!(error.position(), Some((points_line(), second)), "{error}");
    assert!(error.message.contains("duplicate key"), "{error}");
}

#[test]
fn other_mistakes() {
    let error = refused("trace = \"bob\"", "trace = \"bob\"\ncolour = \"red\"");
    assert_eq!(error.key(), Some("drawing.colour"));
    assert!(error.help.as_ref().unwrap().contains("`points`"));
    let error = refused(
        "segments = [[\"pivot\", \"bob\"]]",
        "segments = [[\"pivot\", \"bob\", \"left\"]]",
    );
    assert!(error.message.contains("joins 2 points, not 3"), "{error}");
    let error = refused(
        "segments = [[\"pivot\", \"bob\"]]",
        "segments = [[\"pivot\"]]",
    );
    assert!(error.message.contains("1 point given"), "{error}");
    let error = refused("closed = true", "closed = 1");
    assert_eq!(error.key(), Some("drawing.polylines[0].closed"));
    let error = refused("pivot = [\"x\", 0]", "pivot = \"x\"");
    assert!(
        error.message.contains("expected a pair or a triple"),
        "{error}"
    );
    let error = refused("pivot = [\"x\", 0]", "2pivot = [\"x\", 0]");
    assert!(error.message.contains("cannot name a point"), "{error}");
    let error = refused(
        "through = [\"left\", \"right\"] }",
        "through = [\"left\", \"right\"], curve = [\"s\", 0], s = [0, 1] }",
    );
    assert!(error.message.contains("both through and curve"), "{error}");
    let error = refused(
        "through = [\"left\", \"right\"] }",
        "curve = [\"s\", 0], s = [0, 1], samples = 1 }",
    );
    assert!(error.message.contains("samples must be"), "{error}");
    let error = refused("through = [\"left\", \"right\"] }", "curve = [\"s\", 0] }");
    assert_eq!(
        error.location,
        Location::Missing("drawing.surfaces[0].s".into())
    );
    let error = refused(
        "through = [\"left\", \"right\"] }",
        "curve = [\"s\"], s = [0, 1] }",
    );
    assert!(
        error.message.contains("but the drawing's points have 2"),
        "{error}"
    );
    let error = refused(
        "through = [\"left\", \"right\"] }",
        "curve = [\"s\", \"q\"], s = [0, 1] }",
    );
    assert!(
        error
            .message
            .contains("unknown name `q` in the curve of `ground`"),
        "{error}"
    );
    // Without points.
    let error = refused("points = { pivot", "dots = { pivot");
    assert_eq!(error.key(), Some("drawing.dots"));
}

#[test]
fn drawing_formulas_count_against_the_operation_budget() {
    let text = source();
    let needed = |limits: Limits| parse_model_with("case.toml", &text, &[], limits);
    // Find the smallest budget the model loads with, and check that the drawing counts in it:
    // the same model without the drawing loads with less.
    let end = text.find("[drawing]").unwrap();
    let bare = &text[..end];
    let loads = |source: &str, ops: usize| {
        parse_model_with(
            "case.toml",
            source,
            &[],
            Limits {
                max_operations: ops,
                ..Limits::default()
            },
        )
        .is_ok()
    };
    let smallest = |source: &str| {
        let (mut lo, mut hi) = (1, 1_000_000);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if loads(source, mid) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        lo
    };
    let with = smallest(&text);
    let without = smallest(bare);
    let drawing = needed(Limits::default()).unwrap().drawing.unwrap();
    assert_eq!(with - without, drawing.operations(), "{with} vs {without}");
    assert!(drawing.operations() >= 10, "{}", drawing.operations());
    let error = parse_model_with(
        "case.toml",
        &text,
        &[],
        Limits {
            max_operations: with - 1,
            ..Limits::default()
        },
    )
    .unwrap_err();
    assert_eq!(error.key(), Some("drawing"), "{error}");
    assert!(
        error.message.contains("the drawing's points take"),
        "{error}"
    );

    // A curve sampled 1000 times costs 1000 times its formulas.
    let hostile = format!(
        "{bare}[drawing]\npoints = {{ a = [0, 0] }}\nsurfaces = [{{ constraint = \"ground\", curve = [\"{0}\", \"{0}\"], s = [0, 1], samples = 1000 }}]\n",
        vec!["sin(s)"; 200].join("+")
    );
    let error = parse_model("case.toml", &hostile, &[]);
    let operations = error
        .as_ref()
        .map(|f| f.drawing.as_ref().unwrap().operations());
    assert!(matches!(operations, Ok(n) if n > 400_000), "{operations:?}");
    assert!(!loads(&hostile, 300_000));
}

/// The coordinates `q` whose configuration a drawing point `p` of a surface stands for, in the
/// models drawn in their own coordinates (a dot at `(x, y)`, say); `None` for the models drawn
/// as a mechanism (pendulums, blocks, arms), whose drawn points are not coordinates.
fn configuration(model: &str, p: &[f64]) -> Option<Vec<f64>> {
    match model {
        "bouncing-ball" | "dragged-ball" | "vibrating-table" => Some(vec![p[1]]),
        "damped-oscillator" => Some(vec![p[0]]),
        "corner" | "floor-and-wall" | "ball-off-cylinder" | "v-groove" => Some(vec![p[0], p[1]]),
        "ball-on-sine" | "ball-on-sine-demo" => Some(vec![0.0, p[0], p[1]]),
        _ => None,
    }
}

#[test]
fn every_shipped_model_draws_every_constraint() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 25, "{files:?}");
    let mut checked_on_surface = 0;
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(path).unwrap();
        let file = parse_model(&name, &text, &[]).unwrap_or_else(|e| panic!("{e}"));
        let drawing = file
            .drawing
            .as_ref()
            .unwrap_or_else(|| panic!("{name} has no [drawing]"));
        assert_eq!(drawing.dimension(), 2, "{name}");
        let d = drawing.dimension();
        let mut out = vec![f64::NAN; drawing.points().len() * d];
        drawing
            .evaluate(0.0, &file.initial.q, &mut out)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(out.iter().all(|v| v.is_finite()), "{name}: {out:?}");
        let constraints: Vec<&str> = file
            .model
            .constraints()
            .iter()
            .map(|c| c.name.as_str())
            .collect();
        let mut drawn = vec![false; constraints.len()];
        for shape in drawing.shapes() {
            let Shape::Surface { constraint, points } = shape else {
                continue;
            };
            drawn[*constraint] = true;
            for &k in points {
                let p = &out[k * d..(k + 1) * d];
                let Some(q) = configuration(&name, p) else {
                    continue;
                };
                let h: f64 = file
                    .model
                    .constraint_formula(*constraint)
                    .eval_at(&q, &[], 0.0);
                assert!(
                    h.abs() < 1e-9,
                    "{name}: point `{}` of the surface of `{}` is at h = {h}",
                    drawing.points()[k],
                    constraints[*constraint]
                );
                checked_on_surface += 1;
            }
        }
        assert!(
            drawn.iter().all(|&d| d),
            "{name}: some constraint has no surface: {drawn:?}"
        );
    }
    // 2 each for the 3 balls on a line and the oscillator, 3 + 4 + 4 for the corner, the floor
    // and wall and the floor of the cylinder, 97 on the cylinder, 121 on each sine, 4 for the
    // groove's two walls.
    assert_eq!(checked_on_surface, 4 * 2 + 4 + 4 + 2 + 97 + 2 * 121 + 4);
}
