//! Every way a model file can be refused: each message names the file and the line and column
//! (syntax and formulas) or the key (meaning), and says what to do.

use zenosim_model::{parse_model, Location, ModelError, Override};

/// A valid model; the cases below break one thing in it.
const GOOD: &str = r#"name = "ball"
coordinates = ["x", "y"]
lagrangian = "0.5*m*(x_dot^2 + y_dot^2) - m*g*y"

[parameters]
m = 1.0
g = 9.81
e = 0.5

[[constraint]]
name = "floor"
h = "y"
restitution = "e"

[initial]
y = 1.0
x_dot = 0.5

[simulation]
t_end = 2.0
"#;

fn load(source: &str) -> Result<zenosim_model::ModelFile, ModelError> {
    parse_model("case.toml", source, &[])
}

fn error(source: &str) -> ModelError {
    match load(source) {
        Ok(_) => panic!("accepted:\n{source}"),
        Err(e) => e,
    }
}

/// `GOOD` with `from` replaced by `to` (which must occur).
fn with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from:?} is not in the model");
    GOOD.replacen(from, to, 1)
}

/// The error names the file, says `fragment`, and gives help.
fn says(e: &ModelError, fragment: &str) {
    let text = e.to_string();
    assert!(text.starts_with("case.toml:"), "no file name: {text}");
    assert!(text.contains(fragment), "expected {fragment:?} in:\n{text}");
    assert!(text.contains("= help: "), "no help in:\n{text}");
}

/// The error points at `(line, column)`, under `key` when given.
fn at(e: &ModelError, line: usize, column: usize, key: Option<&str>) {
    assert_eq!(e.position(), Some((line, column)), "{e}");
    assert_eq!(e.key(), key, "{e}");
    let text = e.to_string();
    assert!(
        text.starts_with(&format!("case.toml:{line}:{column}: ")),
        "{text}"
    );
    // The offending line is shown with a caret.
    assert!(text.contains(&format!("\n{line} | ")), "{text}");
}

fn missing(e: &ModelError, key: &str) {
    assert_eq!(e.location, Location::Missing(key.to_string()), "{e}");
    assert!(
        e.to_string().contains(&format!("missing key `{key}`")),
        "{e}"
    );
}

#[test]
fn the_good_model_loads() {
    let file = load(GOOD).unwrap();
    assert_eq!(file.name, "ball");
    assert_eq!(file.initial.q, [0.0, 1.0]);
    assert_eq!(file.initial.q_dot, [0.5, 0.0]);
    assert_eq!(file.settings.t_end, 2.0);
    assert_eq!(
        file.parameters,
        [("m".into(), 1.0), ("g".into(), 9.81), ("e".into(), 0.5)]
    );
}

#[test]
fn toml_syntax_errors_point_at_the_place() {
    let e = error(&with("name = \"ball\"", "name = \"ball"));
    says(&e, "invalid TOML");
    assert_eq!(e.position().map(|p| p.0), Some(1), "{e}");
    let e = error(&with("g = 9.81", "g = = 9.81"));
    says(&e, "invalid TOML");
    assert_eq!(e.position().map(|p| p.0), Some(7), "{e}");
    // A key given twice is a TOML error.
    let e = error(&with("g = 9.81", "g = 9.81\ng = 9.8"));
    says(&e, "invalid TOML");
    assert_eq!(e.position().map(|p| p.0), Some(8), "{e}");
}

#[test]
fn missing_required_keys_are_named() {
    let e = error(&with("name = \"ball\"\n", ""));
    missing(&e, "name");
    says(&e, "add name = ");
    let e = error(&with("coordinates = [\"x\", \"y\"]\n", ""));
    missing(&e, "coordinates");
    let e = error(&with(
        "lagrangian = \"0.5*m*(x_dot^2 + y_dot^2) - m*g*y\"\n",
        "",
    ));
    missing(&e, "lagrangian");
    says(&e, "add lagrangian = ");
    let e = error(&GOOD.replace(
        "[[constraint]]\nname = \"floor\"\nh = \"y\"\nrestitution = \"e\"\n",
        "",
    ));
    missing(&e, "constraint");
    let e = error(&with("h = \"y\"\n", ""));
    missing(&e, "constraint[1].h");
    let e = error(&with("restitution = \"e\"\n", ""));
    missing(&e, "constraint[1].restitution");
    let e = error(&with("name = \"floor\"\n", ""));
    missing(&e, "constraint[1].name");
}

#[test]
fn wrong_types_name_the_key() {
    let e = error(&with("coordinates = [\"x\", \"y\"]", "coordinates = \"x\""));
    says(&e, "expected a list of names, found a string");
    at(&e, 2, 15, Some("coordinates"));
    let e = error(&with(
        "coordinates = [\"x\", \"y\"]",
        "coordinates = [\"x\", 2]",
    ));
    says(&e, "expected a string");
    at(&e, 2, 21, Some("coordinates[1]"));
    let e = error(&with("restitution = \"e\"", "restitution = true"));
    says(
        &e,
        "expected a number or a formula in quotes, found a boolean",
    );
    at(&e, 13, 15, Some("constraint[1].restitution"));
    let e = error(
        &GOOD
            .replace("[parameters]\nm = 1.0\ng = 9.81\ne = 0.5\n", "")
            .replace("name = \"ball\"\n", "name = \"ball\"\nparameters = 3\n"),
    );
    says(&e, "expected a table, found an integer");
    at(&e, 2, 14, Some("parameters"));
    let e = error(&with("t_end = 2.0", "t_end = [2.0]"));
    says(&e, "found a list");
}

#[test]
fn unknown_keys_are_refused_with_a_suggestion() {
    let e = error(&GOOD.replace("[[constraint]]", "[[constraints]]"));
    says(&e, "unknown key `constraints`");
    says(&e, "did you mean `constraint`?");
    at(&e, 10, 3, Some("constraints"));
    let e = error(&with(
        "restitution = \"e\"",
        "restitution = \"e\"\nrestitutoin = 0.5",
    ));
    says(&e, "did you mean `restitution`?");
    assert_eq!(e.key(), Some("constraint[1].restitutoin"));
    let e = error(&with("t_end = 2.0", "tend = 2.0"));
    says(&e, "did you mean `t_end`?");
    let e = error(&with("x_dot = 0.5", "z_dot = 0.5"));
    says(&e, "`z_dot` is not a coordinate or a velocity");
    assert_eq!(e.key(), Some("initial.z_dot"));
}

#[test]
fn unknown_names_point_at_the_column_in_the_formula() {
    let e = error(&with("0.5*m*(", "0.5*mm*("));
    says(&e, "unknown name `mm` in the Lagrangian");
    says(&e, "did you mean `m`?");
    // `lagrangian = "` is 14 characters: the formula's column 5 is the file's column 19.
    at(&e, 3, 19, Some("lagrangian"));
    let e = error(&with("0.5*m*(", "0.5*mass*("));
    says(
        &e,
        "the names here are `x`, `y`, `x_dot`, `y_dot`, `m`, `g`, `e` and pi",
    );
    let e = error(&with("h = \"y\"", "h = \"y - bump\""));
    says(&e, "unknown name `bump` in h of constraint `floor`");
    at(&e, 12, 10, Some("constraint[1].h"));
}

#[test]
fn names_used_where_they_do_not_belong() {
    let e = error(&with("h = \"y\"", "h = \"y + y_dot\""));
    says(&e, "uses the velocity `y_dot`");
    says(&e, "depends on the coordinates only");
    let e = error(&with("e = 0.5", "e = \"0.5 + x\""));
    says(&e, "parameter `e` uses the coordinate `x`");
    // The time is a variable of the formulas of the motion, not of the constants.
    let e = error(&with("e = 0.5", "e = \"0.5 + 0*t\""));
    says(&e, "parameter `e` uses the time `t`");
    says(&e, "fixed before the run starts");
    at(&e, 8, 14, Some("parameters.e"));
    let e = error(&with("y = 1.0", "y = \"1 + t\""));
    says(&e, "the initial value of `y` uses the time `t`");
    at(&e, 16, 10, Some("initial.y"));
    let e = error(&with("restitution = \"e\"", "restitution = \"e*t\""));
    says(&e, "uses the time `t`");
    let e = error(&with("t_end = 2.0", "t_end = \"2*t\""));
    says(&e, "uses the time `t`");
    let e = error(&with("y = 1.0", "y = \"y_dot\""));
    says(&e, "uses the velocity `y_dot`");
}

#[test]
fn names_defined_twice() {
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"x\"]"));
    says(&e, "coordinate `x` is defined twice");
    at(&e, 2, 21, Some("coordinates[1]"));
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"x_dot\"]"));
    says(&e, "clashes with the velocity name of `x`");
    let e = error(&with("g = 9.81", "g = 9.81\ny = 2.0"));
    says(&e, "`y` is defined twice");
    assert_eq!(e.key(), Some("parameters.y"));
    let e = error(&with("g = 9.81", "g = 9.81\nx_dot = 2.0"));
    says(&e, "`x_dot` is defined twice");
    let e = error(&format!(
        "{GOOD}\n[[constraint]]\nname = \"floor\"\nh = \"x\"\nrestitution = 0.1\n"
    ));
    says(&e, "constraint `floor` is defined twice");
    assert_eq!(e.key(), Some("constraint[2].name"));
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"sin\"]"));
    says(&e, "`sin` is a built-in function or constant");
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"t\"]"));
    says(&e, "`t` is the time");
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"2y\"]"));
    says(&e, "`2y` cannot name a coordinate");
    let e = error(&with("name = \"floor\"", "name = \"the floor\""));
    says(&e, "cannot name a constraint");
}

#[test]
fn cyclic_parameters_show_the_cycle() {
    let e = error(&with("g = 9.81", "g = \"k*2\"\nk = \"w + 1\"\nw = \"g\""));
    says(&e, "depends on itself: g → k → w → g");
    assert_eq!(e.key(), Some("parameters.g"));
    let e = error(&with("g = 9.81", "g = \"g\""));
    says(&e, "parameter `g` depends on itself: g → g");
    // Any order is fine without a cycle.
    let file = load(&with("g = 9.81", "g = \"2*k\"\nk = 4.905")).unwrap();
    assert_eq!(file.parameters[1], ("g".to_string(), 9.81));
}

#[test]
fn formula_syntax_errors_point_at_the_column() {
    let e = error(&with("h = \"y\"", "h = \"y +\""));
    says(
        &e,
        "in h of constraint `floor`: the expression ends after '+'",
    );
    at(&e, 12, 8, Some("constraint[1].h"));
    let e = error(&with("h = \"y\"", "h = \"(y\""));
    says(&e, "never closed");
    at(&e, 12, 6, Some("constraint[1].h"));
    let e = error(&with("h = \"y\"", "h = \"y # floor\""));
    says(&e, "unexpected character '#'");
    at(&e, 12, 8, Some("constraint[1].h"));
    let e = error(&with("h = \"y\"", "h = \"\""));
    says(&e, "the expression is empty");
}

#[test]
fn positions_in_multi_line_formulas_and_escaped_strings() {
    let source = with(
        "lagrangian = \"0.5*m*(x_dot^2 + y_dot^2) - m*g*y\"",
        "lagrangian = \"\"\"\n  0.5*m*(x_dot^2 + y_dot^2)\n  - m*g*yy\n\"\"\"",
    );
    let e = error(&source);
    says(&e, "unknown name `yy`");
    at(&e, 5, 9, Some("lagrangian"));
    // With an escape the text differs from the file: the error points at the string.
    let e = error(&with("h = \"y\"", "h = \"y\\t+ q\""));
    says(&e, "unknown name `q`");
    at(&e, 12, 5, Some("constraint[1].h"));
}

#[test]
fn unknown_functions_and_wrong_arity() {
    let e = error(&with("h = \"y\"", "h = \"y - sine(x)\""));
    says(&e, "unknown function 'sine'");
    says(&e, "did you mean 'sin'?");
    at(&e, 12, 10, Some("constraint[1].h"));
    let e = error(&with("h = \"y\"", "h = \"atan2(y)\""));
    says(&e, "'atan2' takes 2 arguments but is given 1");
    at(&e, 12, 6, Some("constraint[1].h"));
}

#[test]
fn parameters_that_are_not_numbers() {
    let e = error(&with("g = 9.81", "g = \"1/(m - 1)\""));
    says(&e, "parameter `g` evaluates to inf");
    says(&e, "division by zero");
    assert_eq!(e.key(), Some("parameters.g"));
    let e = error(&with("g = 9.81", "g = \"sqrt(-m)\""));
    says(&e, "evaluates to NaN");
    says(&e, "not a number");
    let e = error(&with("g = 9.81", "g = nan"));
    says(&e, "is NaN");
    let e = error(&with("y = 1.0", "y = \"ln(0)\""));
    says(&e, "the initial value of `y` evaluates to -inf");
    assert_eq!(e.key(), Some("initial.y"));
}

#[test]
fn restitution_outside_the_unit_interval() {
    for bad in ["1.5", "-0.1", "\"e + 1\""] {
        let e = error(&with(
            "restitution = \"e\"",
            &format!("restitution = {bad}"),
        ));
        says(&e, "outside [0, 1]");
        at(&e, 13, 15, Some("constraint[1].restitution"));
    }
    for good in ["0", "1", "0.0", "\"e*2\""] {
        load(&with(
            "restitution = \"e\"",
            &format!("restitution = {good}"),
        ))
        .unwrap();
    }
}

#[test]
fn an_inadmissible_initial_state() {
    let e = error(&with("y = 1.0", "y = -0.25"));
    says(&e, "violates constraint `floor`: h(q0) = -0.25");
    says(&e, "start on the admissible side");
    at(&e, 15, 1, Some("initial"));
    // Without [initial] the state is 0, on the floor: admissible.
    load(&GOOD.replace("[initial]\ny = 1.0\nx_dot = 0.5\n", "")).unwrap();
    let e = error(&GOOD.replace("[initial]\ny = 1.0\nx_dot = 0.5\n", "[initial]\ny = -1.0\n"));
    says(&e, "violates");
    let e = error(
        &GOOD
            .replace("[initial]\ny = 1.0\nx_dot = 0.5\n", "")
            .replace("h = \"y\"", "h = \"y - 1\""),
    );
    missing(&e, "initial");
}

#[test]
fn a_singular_mass_matrix_names_the_coordinate() {
    let e = error(&with("(x_dot^2 + y_dot^2)", "(y_dot^2)"));
    says(&e, "not positive definite");
    says(&e, "no kinetic term in `x_dot`");
    at(&e, 3, 14, Some("lagrangian"));
    // A negative kinetic term.
    let e = error(&with("(x_dot^2 + y_dot^2)", "(x_dot^2 - y_dot^2)"));
    says(&e, "not positive definite");
}

#[test]
fn a_constraint_that_does_not_depend_on_q() {
    for h in ["h = 1", "h = \"m + 1\"", "h = \"e\""] {
        let e = error(&with("h = \"y\"", h));
        says(&e, "does not depend on any coordinate");
        at(&e, 12, 5, Some("constraint[1].h"));
    }
}

#[test]
fn bad_simulation_settings() {
    for (line, fragment) in [
        ("t_end = 0", "t_end is 0; it must be > 0"),
        ("t_end = -1.0", "t_end is -1"),
        ("t_end = inf", "is inf"),
        ("rtol = -1e-8", "rtol is -1e-8"),
        ("atol = 0.0", "atol is 0"),
        ("rtol = 1e-20", "below what f64 resolves"),
        ("zeno = \"sometimes\"", "unknown Zeno strategy `sometimes`"),
        ("zeno = { epsilon = -1 }", "epsilon is -1"),
        ("zeno = { eps = 1e-3 }", "did you mean `epsilon`?"),
        ("zeno = 3", "expected a string or a table"),
        ("method = \"euler\"", "unknown method `euler`"),
        ("max_events = 0", "max_events must be a whole number > 0"),
        ("max_steps = 1.5", "expected a whole number"),
        ("dt = -0.1", "dt is -0.1"),
    ] {
        let e = error(&with("t_end = 2.0", line));
        says(&e, fragment);
        assert!(e.key().unwrap().starts_with("simulation."), "{e}");
        assert_eq!(e.position().map(|p| p.0), Some(20), "{e}");
    }
}

#[test]
fn good_settings_are_read() {
    let file = load(&with(
        "t_end = 2.0",
        "t_end = \"2*pi\"\nrtol = 1e-8\natol = 1e-9\nzeno = { epsilon = 1e-3 }\nmethod = \"dopri5\"\ndt = 0.01\nmax_events = 500\nmax_steps = 1_000",
    ))
    .unwrap();
    let s = file.settings;
    assert_eq!(s.t_end, 2.0 * std::f64::consts::PI);
    assert_eq!((s.tolerances.rtol, s.tolerances.atol), (1e-8, 1e-9));
    assert_eq!(s.zeno, zenosim::ZenoStrategy::Epsilon(1e-3));
    assert_eq!(s.method, zenosim::Method::Dopri5);
    assert_eq!(s.dt, Some(0.01));
    assert_eq!((s.max_events, s.max_steps), (500, 1000));
    let options = file.options();
    assert_eq!(options.output, zenosim::OutputGrid::Uniform(0.01));
    assert_eq!(options.completion, zenosim::Completion::Projection);
}

#[test]
fn overrides() {
    let set = |args: &[&str]| -> Result<zenosim_model::ModelFile, ModelError> {
        let overrides: Vec<Override> = args.iter().map(|a| a.parse().unwrap()).collect();
        parse_model("case.toml", GOOD, &overrides)
    };
    // A parameter, and what depends on it follows.
    let file = set(&["e=0.8", "m=2"]).unwrap();
    assert_eq!(file.model_restitution(), 0.8);
    // An initial value, by a formula of the parameters.
    let file = set(&["x=g/2", "y_dot=-1"]).unwrap();
    assert_eq!(file.initial.q, [9.81 / 2.0, 1.0]);
    assert_eq!(file.initial.q_dot, [0.5, -1.0]);
    // Errors name the override.
    let e = set(&["ee=2"]).unwrap_err();
    assert_eq!(e.location, Location::Override("ee=2".into()));
    let text = e.to_string();
    assert!(text.starts_with("case.toml: --set ee=2: "), "{text}");
    assert!(text.contains("did you mean `e`?"), "{text}");
    let e = set(&["e=1.5"]).unwrap_err();
    assert!(e.to_string().contains("outside [0, 1]"), "{e}");
    // The value is refused where it is used.
    assert_eq!(e.key(), Some("constraint[1].restitution"));
    let e = set(&["y=-1"]).unwrap_err();
    assert!(e.to_string().contains("violates"), "{e}");
    let e = set(&["g=1/(m-1)"]).unwrap_err();
    assert!(e.to_string().contains("evaluates to inf"), "{e}");
    let e = set(&["g=2*"]).unwrap_err();
    assert!(e.to_string().contains("the expression ends"), "{e}");
    assert!("m".parse::<Override>().unwrap_err().contains("NAME=VALUE"));
    assert!("=2".parse::<Override>().is_err());
}

#[test]
fn hostile_input_fails_fast_without_overflowing_the_stack() {
    // 100 000 nested parentheses in a formula: longer than a formula may be.
    let deep = format!("{}y{}", "(".repeat(100_000), ")".repeat(100_000));
    let e = error(&with("h = \"y\"", &format!("h = \"{deep}\"")));
    says(&e, "characters long, more than the limit of 100000");
    assert_eq!(e.key(), Some("constraint[1].h"));
    // 40 000 nested parentheses: short enough, but too deep.
    let deep = format!("{}y{}", "(".repeat(40_000), ")".repeat(40_000));
    let e = error(&with("h = \"y\"", &format!("h = \"{deep}\"")));
    says(&e, "nests more than 256 levels");
    at(&e, 12, 5 + 257, Some("constraint[1].h"));
    // Deeply nested TOML arrays.
    let e = error(&with(
        "[parameters]",
        &format!(
            "junk = {}{}\n[parameters]",
            "[".repeat(100_000),
            "]".repeat(100_000)
        ),
    ));
    says(&e, "invalid TOML");
    // A formula longer than the limit.
    let long = vec!["y"; 60_000].join("+");
    let e = error(&with("h = \"y\"", &format!("h = \"{long}\"")));
    says(&e, "characters long, more than the limit");
}

trait Restitution {
    fn model_restitution(&self) -> f64;
}

impl Restitution for zenosim_model::ModelFile {
    fn model_restitution(&self) -> f64 {
        use zenosim::HybridLagrangian;
        self.model.constraints()[0].restitution
    }
}

#[test]
fn names_that_would_repeat_a_column_of_the_trajectory() {
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"energy\"]"));
    says(&e, "it is a column of trajectory.csv");
    let e = error(
        &with("[\"x\", \"y\"]", "[\"h_floor\", \"y\"]")
            .replace("x_dot", "h_floor_dot")
            .replace("x = 0", ""),
    );
    says(&e, "has the name of constraint `floor`'s column");
}

#[test]
fn non_finite_values_at_the_initial_state() {
    let e = error(&with("h = \"y\"", "h = \"y/x\""));
    says(&e, "is not finite at the initial state");
    assert_eq!(e.key(), Some("constraint[1].h"));
    let e = error(&with("- m*g*y\"", "- m*g*y + ln(x)\""));
    says(&e, "not finite at the initial state");
    assert_eq!(e.key(), Some("lagrangian"));
}

#[test]
fn a_parameter_given_as_an_initial_value() {
    let e = error(&with("x_dot = 0.5", "g = 3"));
    says(&e, "`g` is a parameter, not a coordinate or a velocity");
    assert_eq!(e.key(), Some("initial.g"));
}

#[test]
fn formula_limits_can_be_raised_and_lowered() {
    use zenosim_model::{parse_model_with, Limits};
    // 120 000 characters: refused by default, saying how to raise the limit.
    let long = vec!["y"; 60_000].join("+");
    let source = with("h = \"y\"", &format!("h = \"{long}\""));
    let e = error(&source);
    says(&e, "more than the limit of 100000");
    says(&e, "--max-formula-length");
    let raised = Limits {
        max_length: 200_000,
        ..Limits::default()
    };
    let file = parse_model_with("case.toml", &source, &[], raised).unwrap();
    // h = 60 000 y at the initial y = 1.
    use zenosim::HybridLagrangian;
    assert_eq!(file.model.constraint::<f64>(0, &file.initial.q), 60_000.0);
    // Lowered: even the good model's Lagrangian is too deep at a depth of 2.
    let shallow = Limits {
        max_depth: 2,
        ..Limits::default()
    };
    let e = parse_model_with("case.toml", GOOD, &[], shallow).unwrap_err();
    says(&e, "nests more than 2 levels");
    says(&e, "--max-formula-depth");
    assert_eq!(e.key(), Some("lagrangian"));
}

#[test]
fn a_long_chain_of_parameters_is_evaluated_without_deep_recursion() {
    // g = p0, p0 = p1, …, p19999 = 9.81: evaluated depth first on the loader's own stack (it
    // recursed once per link, and overflowed the test thread's stack long before the end).
    let links = 20_000;
    let mut chain = String::from("g = \"p0\"\n");
    for i in 0..links - 1 {
        chain += &format!("p{i} = \"p{}\"\n", i + 1);
    }
    chain += &format!("p{} = 9.81\n", links - 1);
    let file = load(&with("g = 9.81\n", &chain)).unwrap();
    let g = file
        .parameters
        .iter()
        .find(|(name, _)| name == "g")
        .unwrap();
    assert_eq!(g.1, 9.81);
    // Closed into a cycle at the far end, it names the whole cycle.
    let cyclic = chain.replace(
        &format!("p{} = 9.81", links - 1),
        &format!("p{} = \"g\"", links - 1),
    );
    let e = error(&with("g = 9.81\n", &cyclic));
    says(&e, "parameter `g` depends on itself: g → p0 → p1 → ");
    says(&e, &format!("p{} → g", links - 1));
}

#[test]
fn toml_nested_past_the_readers_limit_points_at_the_deepest_line() {
    // The TOML reader stops at its recursion limit without saying where.
    let dotted = vec!["a"; 200].join(".");
    let e = error(&with(
        "[parameters]",
        &format!("[parameters]\n{dotted} = 1"),
    ));
    says(&e, "invalid TOML");
    says(&e, "most deeply nested");
    assert_eq!(e.position(), Some((6, 1)), "{e}");
}

/// `GOOD` with a `[forces]` table of `lines` at its end, from line 23 on.
fn with_forces(lines: &str) -> String {
    format!("{GOOD}\n[forces]\n{lines}\n")
}

/// `GOOD` with `dissipation = VALUE` on line 4 (a top-level key: before the first table).
fn with_dissipation(value: &str) -> String {
    with(
        "\n[parameters]",
        &format!("dissipation = {value}\n\n[parameters]"),
    )
}

#[test]
fn the_time_cannot_name_a_coordinate_or_a_parameter() {
    let e = error(&with("[\"x\", \"y\"]", "[\"x\", \"t\"]"));
    says(&e, "`t` is the time and cannot name a coordinate");
    says(&e, "choose another name");
    at(&e, 2, 21, Some("coordinates[1]"));
    let e = error(&with("g = 9.81", "g = 9.81\nt = 2.0"));
    says(&e, "`t` is the time and cannot name a parameter");
    says(&e, "choose another name: `t` is the time in lagrangian");
    at(&e, 8, 1, Some("parameters.t"));
    // Nor is it part of the state to start from or to reset.
    let e = error(&with("x_dot = 0.5", "x_dot = 0.5\nt = 1.0"));
    says(&e, "`t` is the time, not a coordinate or a velocity");
    says(&e, "[initial] gives the state at t = 0");
    at(&e, 18, 1, Some("initial.t"));
    let e = error(&with(
        "restitution = \"e\"",
        "restitution = \"e\"\nzeno_reset = { t = \"0\" }",
    ));
    says(&e, "`t` is not a coordinate or a velocity");
    assert_eq!(e.key(), Some("constraint[1].zeno_reset.t"));
    let e = parse_model("case.toml", GOOD, &["t=1".parse().unwrap()]).unwrap_err();
    assert!(
        e.to_string()
            .contains("`t` is neither a parameter nor a coordinate or velocity"),
        "{e}"
    );
}

#[test]
fn the_time_is_a_variable_of_the_motion() {
    let file = load(&with_forces("x = \"sin(t)*x_dot\"")).unwrap();
    assert!(!zenosim::HybridLagrangian::is_autonomous(&file.model));
    let source = with("- m*g*y\"", "- m*g*y*(1 + 0.1*sin(t))\"").replace(
        "h = \"y\"",
        "h = \"y - 0.1*t\"\nzeno_reset = { y = \"0.1*t\" }",
    );
    assert!(!zenosim::HybridLagrangian::is_autonomous(
        &load(&source).unwrap().model
    ));
    // The time alone is not a constraint.
    let e = error(&with("h = \"y\"", "h = \"1 + t\""));
    says(
        &e,
        "h of constraint `floor` does not depend on any coordinate",
    );
    assert_eq!(e.key(), Some("constraint[1].h"));
}

#[test]
fn a_force_on_something_that_is_not_a_coordinate() {
    let e = error(&with_forces("xx = \"-x_dot\""));
    says(&e, "`xx` is not a coordinate");
    says(
        &e,
        "did you mean `x`? [forces] gives the generalized force on a coordinate (`x`, `y`)",
    );
    says(&e, "the coordinates not listed get 0");
    at(&e, 23, 1, Some("forces.xx"));
    let e = error(&with_forces("y = \"-y\"\nx_dot = \"-x_dot\""));
    says(&e, "`x_dot` is a velocity, not a coordinate");
    says(&e, "write the force on `x` as x = ");
    at(&e, 24, 1, Some("forces.x_dot"));
    let e = error(&with_forces("m = 1"));
    says(&e, "`m` is a parameter, not a coordinate");
    at(&e, 23, 1, Some("forces.m"));
    let e = error(&with_forces("t = 1"));
    says(&e, "`t` is the time, not a coordinate");
    // `forces` is a table.
    let e = error(&with(
        "\n[parameters]",
        "forces = \"-x_dot\"\n\n[parameters]",
    ));
    says(&e, "expected a table, found a string");
    says(&e, "[forces] with lines x = ");
    at(&e, 4, 10, Some("forces"));
    let e = error(&with_forces("x = true"));
    says(
        &e,
        "expected a number or a formula in quotes, found a boolean",
    );
    at(&e, 23, 5, Some("forces.x"));
}

#[test]
fn a_force_formula_with_a_syntax_error_points_at_the_column() {
    let e = error(&with_forces("x = \"-m*x_dot +\""));
    says(&e, "in the force on `x`: the expression ends after '+'");
    // `x = "` is 5 characters: the formula's column 10 is the file's column 15.
    at(&e, 23, 15, Some("forces.x"));
    let e = error(&with_forces("x = \"sine(t)\""));
    says(&e, "did you mean 'sin'?");
    at(&e, 23, 6, Some("forces.x"));
    let e = error(&with_forces("x = \"-c*x_dot\""));
    says(&e, "unknown name `c` in the force on `x`");
    at(&e, 23, 7, Some("forces.x"));
    let e = error(&with_dissipation("\"0.5*m*x_dot^\""));
    says(
        &e,
        "in the dissipation function: the expression ends after '^'",
    );
    at(&e, 4, 27, Some("dissipation"));
}

#[test]
fn a_dissipation_function_without_velocity() {
    let e = error(&with_dissipation("\"0.5*m*x^2 + t\""));
    says(
        &e,
        "the dissipation function does not depend on any velocity: its force −∂D/∂q̇ would be zero",
    );
    says(&e, "a formula of the velocities `x_dot`, `y_dot`");
    says(&e, "dissipation = \"0.5*c*x_dot^2\"");
    says(&e, "under [forces]");
    at(&e, 4, 15, Some("dissipation"));
    let e = error(&with_dissipation("0"));
    says(&e, "does not depend on any velocity");
    at(&e, 4, 15, Some("dissipation"));
    // With a velocity it loads.
    let file = load(&with_dissipation("\"0.5*m*(1 + x^2)*x_dot^2\"")).unwrap();
    assert!(file.model.dissipation_formula().is_some());
}

#[test]
fn forces_that_are_not_finite_at_the_start() {
    let e = error(&with_forces("y = \"1/t\""));
    says(&e, "the force on `y` is inf at the initial state");
    says(&e, "at the initial state (t = 0)");
    at(&e, 23, 5, Some("forces.y"));
    let e = error(&with_dissipation("\"sqrt(x_dot - 1)\""));
    says(&e, "the dissipation function is NaN at the initial state");
    at(&e, 4, 15, Some("dissipation"));
}

/// A Lagrangian not quadratic in the velocities (`0.5*y_dot^2 + 0.1*y_dot^4 − 9.81*y`) was
/// run with mechanics that assume one: the impact loss reported (14.2) exceeded the whole
/// starting energy (9.81). It is refused now, naming a column of its mass matrix that changes;
/// Lagrangians with terms linear in the velocities, and mass matrices that depend on the
/// positions, load as before.
#[test]
fn a_lagrangian_not_quadratic_in_the_velocities_is_refused() {
    for (lagrangian, velocity) in [
        ("0.5*m*(x_dot^2 + y_dot^2) + 0.1*y_dot^4 - m*g*y", "y_dot"),
        ("0.5*m*(x_dot^2 + y_dot^2)*(1 + 0.1*x_dot) - m*g*y", "x_dot"),
        (
            "0.5*m*(x_dot^2 + y_dot^2) + exp(0.01*x_dot*y_dot) - m*g*y",
            "x_dot",
        ),
        ("m*(sqrt(1 + x_dot^2) - 1) + 0.5*m*y_dot^2 - m*g*y", "x_dot"),
    ] {
        let e = error(&with("0.5*m*(x_dot^2 + y_dot^2) - m*g*y", lagrangian));
        says(&e, "not quadratic in the velocities");
        says(&e, &format!("in its column of {velocity}"));
        assert_eq!(e.key(), Some("lagrangian"), "{e}");
    }
    for fine in [
        "0.5*m*(x_dot^2 + y_dot^2) + 0.3*x_dot*y - m*g*y",
        "0.5*m*(x_dot^2 + (1 + y^2)*y_dot^2) - m*g*y",
    ] {
        load(&with("0.5*m*(x_dot^2 + y_dot^2) - m*g*y", fine))
            .unwrap_or_else(|e| panic!("{fine}: {e}"));
    }
}
