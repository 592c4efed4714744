//! Reading a model file: TOML to a checked [`ModelFile`], every mistake reported with its place.

use std::collections::{HashMap, HashSet};
use std::ops::Range;
use std::str::FromStr;

use toml::de::{DeTable, DeValue};
use toml::Spanned;
use zenosim::{
    ActiveSet, Compiled, Completion, Constraint, Derived, Friction, HybridLagrangian, Method,
    OutputGrid, Readable, SimulationOptions, State, Tolerances, ZenoStrategy, MAX_DIMENSION,
};

use crate::error::{did_you_mean, Lines, Location, ModelError};
use crate::expr::{is_reserved, ExprError, Expression, Limits, Scope};
use crate::file_model::{FileModel, Formula as ModelFormula};

mod drawing;

/// The keys a model file may have at its top level.
const TOP_KEYS: [&str; 11] = [
    "name",
    "description",
    "coordinates",
    "lagrangian",
    "parameters",
    "constraint",
    "forces",
    "dissipation",
    "initial",
    "simulation",
    "drawing",
];

/// The formulas where the time `t` may appear, for messages.
const TIME_USES: &str = "lagrangian, each constraint's h and zeno_reset, [forces] and dissipation";

/// The keys of a `[[constraint]]`.
const CONSTRAINT_KEYS: [&str; 6] = ["name", "h", "restitution", "zeno_reset", "friction", "slip"];

/// The keys of `[simulation]`.
const SIMULATION_KEYS: [&str; 9] = [
    "t_end",
    "rtol",
    "atol",
    "zeno",
    "method",
    "dt",
    "max_step",
    "max_events",
    "max_steps",
];

/// What a model file sets under `[simulation]`, with zenosim's defaults for the rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// `t_end` (default 10).
    pub t_end: f64,
    /// `rtol`, `atol` (default 1e-10 each).
    pub tolerances: Tolerances,
    /// `zeno`: `"auto"` (default), `"off"` or `{ epsilon = ε }`.
    pub zeno: ZenoStrategy,
    /// `method`: `"dop853"` (default) or `"dopri5"`.
    pub method: Method,
    /// `dt`: sample the trajectory every `dt` instead of at every step.
    pub dt: Option<f64>,
    /// `max_step` (default: none).
    pub max_step: f64,
    /// `max_events` (default 100 000; a file may lower it, not raise it: [`ModelFile::options`]).
    pub max_events: u64,
    /// `max_steps` (default 10 000 000; a file may lower it, not raise it).
    pub max_steps: u64,
}

impl Default for Settings {
    fn default() -> Self {
        let defaults = SimulationOptions::default();
        Self {
            t_end: defaults.t_end,
            tolerances: defaults.tolerances,
            zeno: defaults.zeno,
            method: defaults.method,
            dt: None,
            max_step: defaults.max_step,
            max_events: defaults.max_events,
            max_steps: defaults.max_steps,
        }
    }
}

impl Settings {
    /// The engine's options for these settings, with the default completion map. The limits
    /// that bound a run's time and memory (`max_events`, `max_steps`) may be lowered by the
    /// file, never raised past the engine's defaults: only the caller raises them
    /// (`--max-events`, `max_events=`), so that a model file cannot make a run hold more than
    /// its caller allows.
    fn options(&self) -> SimulationOptions {
        let defaults = SimulationOptions::default();
        SimulationOptions {
            t_end: self.t_end,
            tolerances: self.tolerances,
            method: self.method,
            zeno: self.zeno,
            completion: Completion::Projection,
            output: self.dt.map_or(OutputGrid::Steps, OutputGrid::Uniform),
            max_step: self.max_step,
            max_events: self.max_events.min(defaults.max_events),
            max_steps: self.max_steps.min(defaults.max_steps),
        }
    }
}

/// A model file, read and checked: the model, its initial state and its run settings.
#[derive(Clone, Debug)]
pub struct ModelFile {
    /// `name`.
    pub name: String,
    /// `description`, if given.
    pub description: Option<String>,
    /// The hybrid Lagrangian.
    pub model: FileModel,
    /// The parameters and their values (after `--set`), in the order of the file.
    pub parameters: Vec<(String, f64)>,
    /// The initial state (after `--set`).
    pub initial: State,
    /// `[simulation]`.
    pub settings: Settings,
    /// `[drawing]`, if the file has one.
    pub drawing: Option<crate::Drawing>,
}

impl ModelFile {
    /// Runs the model from its `[initial]` state with its own options, keeping the trajectory;
    /// an error where the engine refuses the start.
    pub fn run_keeping(&self) -> Result<(zenosim::Execution, zenosim::Trajectory), zenosim::Error> {
        let mut trajectory = zenosim::Trajectory::default();
        let simulation = zenosim::Simulation::new(
            &self.model,
            &self.initial.q,
            &self.initial.q_dot,
            self.options(),
        )?;
        let run = simulation.run(&mut trajectory);
        Ok((run, trajectory))
    }

    /// The engine's options for these settings. A model with a `zeno_reset` uses it as `R∞`.
    pub fn options(&self) -> SimulationOptions {
        let any_reset = (0..self.model.constraints().len()).any(|i| self.model.has_zeno_reset(i));
        SimulationOptions {
            completion: if any_reset {
                Completion::ModelMap
            } else {
                Completion::Projection
            },
            ..self.settings.options()
        }
    }

    /// The velocity names, `<coordinate>_dot`.
    pub fn velocity_names(&self) -> Vec<String> {
        self.model
            .coordinate_names()
            .iter()
            .map(|c| format!("{c}_dot"))
            .collect()
    }
}

/// A command-line override `NAME=VALUE` of a parameter or an initial value; `VALUE` is a number
/// or a formula of the parameters, as in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Override {
    /// The name set.
    pub name: String,
    /// Its new value, as written.
    pub value: String,
}

impl FromStr for Override {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.split_once('=') {
            Some((name, value)) if !name.trim().is_empty() && !value.trim().is_empty() => {
                Ok(Self {
                    name: name.trim().to_string(),
                    value: value.trim().to_string(),
                })
            }
            _ => Err(format!(
                "`{s}` is not NAME=VALUE: write e.g. --set e=0.8 or --set x2_dot=1.5"
            )),
        }
    }
}

impl std::fmt::Display for Override {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.name, self.value)
    }
}

/// Reads the model file `source`; `file` is its name as the user gave it (for messages).
/// `overrides` replace parameters or initial values.
///
/// Everything is checked before the model is returned: the TOML, every key and name, every
/// formula, the parameters (no cycles, finite values), the restitutions (in `[0, 1]`), the
/// forces (on coordinates) and the dissipation function (of the velocities), the settings, and
/// the initial state at `t = 0` (admissible, `h ≥ 0`, with a positive definite mass matrix and
/// finite forces).
pub fn parse_model(
    file: &str,
    source: &str,
    overrides: &[Override],
) -> Result<ModelFile, ModelError> {
    parse_model_with(file, source, overrides, Limits::default())
}

/// [`parse_model`], with the formulas bounded by `limits` instead of the default
/// [`Limits`] (at most 100 000 characters, nested at most 256 deep): generated models with
/// very long formulas raise them; a loader of untrusted files may lower them.
pub fn parse_model_with(
    file: &str,
    source: &str,
    overrides: &[Override],
    limits: Limits,
) -> Result<ModelFile, ModelError> {
    let cx = Cx {
        file,
        source,
        lines: Lines::new(source),
        limits,
    };
    let document = DeTable::parse(source).map_err(|error| cx.toml_error(&error))?;
    cx.model(document.get_ref(), overrides)
}

/// A number or a formula, with where it came from.
#[derive(Clone, Debug)]
struct Formula {
    /// Its key path (`parameters.m`) or the override (`--set m=2`).
    key: String,
    origin: Origin,
    body: Body,
}

#[derive(Clone, Debug)]
enum Origin {
    /// In the file: the value's byte span, and where the string's text starts when it is
    /// written without escapes (so positions inside it map to the file exactly).
    File {
        span: Range<usize>,
        text_start: Option<usize>,
    },
    /// A `--set` argument.
    Override(String),
}

#[derive(Clone, Debug)]
enum Body {
    Number(f64),
    Text(String),
}

/// The byte offset of the first non-blank character of the most deeply nested line of a TOML
/// source (dots in its key or header, brackets and braces after its `=`), if any line nests.
fn deepest_line(source: &str) -> Option<usize> {
    let mut best: Option<(usize, usize)> = None;
    let mut offset = 0;
    for line in source.split_inclusive('\n') {
        let text = line.trim_start();
        let (key, value) = if text.starts_with('[') {
            (text, "")
        } else {
            text.split_once('=').unwrap_or((text, ""))
        };
        let depth = key.matches('.').count()
            + value.matches(['[', '{']).count()
            + usize::from(key.starts_with('['));
        if depth > best.map_or(0, |(d, _)| d) {
            best = Some((depth, offset + line.len() - text.len()));
        }
        offset += line.len();
    }
    best.map(|(_, at)| at)
}

/// What a formula may read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Reads {
    /// Parameters only, bound to slots (to evaluate the parameters in dependency order).
    ParameterSlots,
    /// Parameters only, as constants.
    Constants,
    /// Coordinates (slots `0..n`), the time `t` (slot `2n`) and parameters.
    Coordinates,
    /// Coordinates, velocities (slots `n..2n`), the time `t` (slot `2n`) and parameters.
    State,
    /// What a drawing's points read: as [`Reads::Coordinates`], with messages about drawings.
    Drawing,
}

/// The names a formula is parsed against.
struct Names<'a> {
    coordinates: &'a [String],
    velocities: &'a [String],
    parameters: &'a [(String, f64)],
    /// Each parameter's index in `parameters`: a file may define tens of thousands, and every
    /// name in every formula is looked up.
    index: &'a ParameterIndex<'a>,
    reads: Reads,
}

/// The parameters' indices by name.
type ParameterIndex<'a> = HashMap<&'a str, usize>;

/// The index of `parameters` (the first of a repeated name: the TOML reader refuses repeats).
fn parameter_index(parameters: &[(String, f64)]) -> ParameterIndex<'_> {
    let mut index = HashMap::with_capacity(parameters.len());
    for (k, (name, _)) in parameters.iter().enumerate() {
        index.entry(name.as_str()).or_insert(k);
    }
    index
}

impl Names<'_> {
    /// The slot of the time `t`: `2n`, after the coordinates and the velocities (the
    /// [`FileModel::time_slot`]).
    fn time_slot(&self) -> usize {
        2 * self.coordinates.len()
    }

    /// The slot of a coordinate (`0..n`) or a velocity (`n..2n`), whatever the formula reads.
    fn state_slot(&self, name: &str) -> Option<usize> {
        let n = self.coordinates.len();
        self.coordinates.iter().position(|c| c == name).or_else(|| {
            self.velocities
                .iter()
                .position(|v| v == name)
                .map(|i| n + i)
        })
    }
}

impl Scope for Names<'_> {
    fn resolve(&self, name: &str) -> Option<usize> {
        let time = || (name == "t").then(|| self.time_slot());
        match self.reads {
            Reads::ParameterSlots => self.index.get(name).copied(),
            Reads::Constants => None,
            Reads::Coordinates | Reads::Drawing => self
                .coordinates
                .iter()
                .position(|c| c == name)
                .or_else(time),
            Reads::State => self.state_slot(name).or_else(time),
        }
    }

    fn constant(&self, name: &str) -> Option<f64> {
        if self.reads == Reads::ParameterSlots {
            return None;
        }
        self.index.get(name).map(|&k| self.parameters[k].1)
    }
}

/// The file being read.
struct Cx<'s> {
    file: &'s str,
    source: &'s str,
    lines: Lines<'s>,
    /// The bounds on every formula.
    limits: Limits,
}

type Table<'s> = DeTable<'s>;
type Item<'s> = Spanned<DeValue<'s>>;

impl<'s> Cx<'s> {
    fn at(
        &self,
        offset: usize,
        key: &str,
        message: impl Into<String>,
        help: impl Into<String>,
    ) -> ModelError {
        self.lines
            .error_at(self.file, offset, Some(key), message, Some(help.into()))
    }

    fn missing(
        &self,
        key: &str,
        message: impl Into<String>,
        help: impl Into<String>,
    ) -> ModelError {
        ModelError {
            file: self.file.into(),
            location: Location::Missing(key.to_string()),
            message: message.into(),
            help: Some(help.into()),
            snippet: None,
        }
    }

    fn toml_error(&self, error: &toml::de::Error) -> ModelError {
        let message = error.message().trim_end().to_string();
        let help = "fix the TOML: `key = value` pairs, strings in double quotes, tables as \
                    [name] and [[constraint]] (see models/ for complete examples)";
        match error.span() {
            Some(span) => self.lines.error_at(
                self.file,
                span.start,
                None,
                format!("invalid TOML: {message}"),
                Some(help.to_string()),
            ),
            // The TOML reader gives no place for some errors (its recursion limit): point at
            // the most deeply nested line, where such an error comes from.
            None => match deepest_line(self.source) {
                Some(offset) => self.lines.error_at(
                    self.file,
                    offset,
                    None,
                    format!("invalid TOML: {message}"),
                    Some(
                        "nest dotted keys, tables, arrays and inline tables less deeply (this \
                         line is the most deeply nested)"
                            .to_string(),
                    ),
                ),
                None => ModelError::file(self.file, format!("invalid TOML: {message}"), help),
            },
        }
    }

    /// Refuses keys of `table` not in `allowed`, suggesting the closest allowed one.
    fn known_keys(
        &self,
        table: &Table<'s>,
        prefix: &str,
        allowed: &[&str],
    ) -> Result<(), ModelError> {
        let mut unknown: Vec<_> = table
            .iter()
            .filter(|(k, _)| !allowed.contains(&k.get_ref().as_ref()))
            .collect();
        unknown.sort_by_key(|(k, _)| k.span().start);
        if let Some((key, _)) = unknown.first() {
            let name = key.get_ref().as_ref();
            let hint = did_you_mean(name, allowed.iter().copied());
            return Err(self.at(
                key.span().start,
                &join(prefix, name),
                format!("unknown key `{name}`"),
                format!("{hint}the keys here are {}", list(allowed)),
            ));
        }
        Ok(())
    }

    fn model(&self, root: &Table<'s>, overrides: &[Override]) -> Result<ModelFile, ModelError> {
        self.known_keys(root, "", &TOP_KEYS)?;

        let name = self.required_string(
            root,
            "",
            "name",
            "a short name for the model, e.g. name = \"ball-on-sine\"",
        )?;
        if name.trim().is_empty() {
            let item = root.get("name").expect("present");
            return Err(self.at(
                item.span().start,
                "name",
                "the name is empty",
                "give the model a short name",
            ));
        }
        let description = match root.get("description") {
            Some(item) => Some(self.string(item, "description")?.to_string()),
            None => None,
        };

        let coordinates = self.coordinates(root)?;
        let velocities: Vec<String> = coordinates.iter().map(|c| format!("{c}_dot")).collect();
        let parameters = self.parameters(root, &coordinates, &velocities, overrides)?;
        let index = parameter_index(&parameters);
        let names = |reads| Names {
            coordinates: &coordinates,
            velocities: &velocities,
            parameters: &parameters,
            index: &index,
            reads,
        };

        let lagrangian_item = root.get("lagrangian").ok_or_else(|| {
            self.missing(
                "lagrangian",
                "the model has no Lagrangian",
                format!(
                    "add lagrangian = \"…\", L(q, q_dot) as a formula of the coordinates {} and \
                     their velocities {}",
                    list(&coordinates),
                    list(&velocities)
                ),
            )
        })?;
        let lagrangian = self.formula(lagrangian_item, "lagrangian")?;
        let lagrangian = self.compile(&lagrangian, &names(Reads::State), "the Lagrangian")?;

        let constraints = self.constraints(root, &names)?;
        // The trajectory's columns h_<constraint>, lambda_<constraint> and, with friction,
        // f_<constraint> (and f2_<constraint> in space) must not repeat a coordinate's or a
        // velocity's.
        for c in &constraints {
            let rough = c
                .friction
                .as_ref()
                .filter(|(f, _)| f.static_coefficient > 0.0 || f.kinetic_coefficient > 0.0);
            let friction = rough.into_iter().flat_map(|(_, slip)| {
                let second = (slip.len() == 2).then(|| format!("f2_{}", c.name));
                std::iter::once(format!("f_{}", c.name)).chain(second)
            });
            for column in [format!("h_{}", c.name), format!("lambda_{}", c.name)]
                .into_iter()
                .chain(friction)
            {
                if let Some(i) = coordinates.iter().position(|q| *q == column) {
                    let item = root.get("coordinates").expect("checked");
                    return Err(self.at(
                        item.span().start,
                        &format!("coordinates[{i}]"),
                        format!("coordinate `{column}` has the name of constraint `{}`'s column in trajectory.csv", c.name),
                        "rename the coordinate or the constraint",
                    ));
                }
            }
        }

        let forces = self.forces(root, &names(Reads::State))?;
        let dissipation = self.dissipation(root, &names(Reads::State))?;

        let initial = self.initial(
            root,
            &coordinates,
            &velocities,
            &names(Reads::Constants),
            overrides,
        )?;
        let settings = self.settings(root, &names(Reads::Constants))?;
        let constraint_names: Vec<String> = constraints.iter().map(|c| c.name.clone()).collect();
        let drawing = self.drawing(
            root,
            &names(Reads::Drawing),
            &names(Reads::Constants),
            &constraint_names,
        )?;

        let constraints = constraints
            .into_iter()
            .map(|c| {
                let (constraint, slip) = match c.friction {
                    Some((friction, slip)) => (
                        Constraint::new(c.name, c.restitution).with_friction(friction),
                        Some(slip),
                    ),
                    None => (Constraint::new(c.name, c.restitution), None),
                };
                (constraint, c.h, c.reset, slip)
            })
            .collect();
        let mut model = FileModel::new(coordinates, lagrangian, constraints, forces, dissipation);
        self.check_initial_state(root, &model, &initial)?;
        self.check_initial_forces(root, &model, &initial)?;
        let compiled = Compiled::trace_bounded(&model, self.limits.max_operations as u64);
        if compiled.exhausted() {
            let limit = self.limits.max_operations;
            // Named where the limit was crossed; when that was after the formulas (making the
            // programs), the longest formula is named, as the likeliest to shorten.
            let (place, reached) = match model.over_budget_in.get().copied() {
                Some(formula) => (formula_place(root, &model, formula), "it was reached in"),
                None => {
                    let longest = std::iter::once(ModelFormula::Lagrangian)
                        .chain((0..model.h.len()).map(ModelFormula::Constraint))
                        .chain(model.forces.iter().map(|&(i, _)| ModelFormula::Force(i)))
                        .chain(model.dissipation.iter().map(|_| ModelFormula::Dissipation))
                        .map(|formula| formula_place(root, &model, formula))
                        .max_by_key(|place| place.span.len())
                        .expect("the Lagrangian is there");
                    (longest, "its longest formula is")
                }
            };
            let (at, key, what) = (place.span.start, place.key, place.what);
            return Err(self.at(
                at,
                &key,
                format!(
                    "differentiating the model's formulas takes more than the limit of {limit} \
                     operations ({reached} {what})"
                ),
                "the shipped models need a few thousand, a 20-link pendulum chain written out \
                 in full 3.7 million: shorten the formulas, or, if the model is right as it is, \
                 raise the limit: `zenosim run --max-derivative-operations N` (Limits in the \
                 library)",
            ));
        }
        // The drawing's points are evaluated at every frame of an animation: their operations
        // count against the same limit.
        if let Some(drawing) = &drawing {
            let limit = self.limits.max_operations as u64;
            let used = compiled.operations_traced();
            let needed = drawing.operations() as u64;
            if used.saturating_add(needed) > limit {
                let item = root.get("drawing").expect("the drawing is there");
                return Err(self.at(
                    item.span().start,
                    "drawing",
                    format!(
                        "the drawing's points take {needed} operations to evaluate; with the \
                         {used} that differentiating the model takes, that is more than the \
                         limit of {limit} operations"
                    ),
                    "shorten the drawing's formulas or sample its curves at fewer points, or, \
                     if it is right as it is, raise the limit: `zenosim run \
                     --max-derivative-operations N` (Limits in the library)",
                ));
            }
        }
        // A constant traced free motion is a parabola only where the forces it leaves out are
        // constant too.
        model.parabolic = compiled.constant_free_motion() && model.forces_are_constant();
        model.compiled = Some(compiled);

        Ok(ModelFile {
            name: name.to_string(),
            description,
            model,
            parameters,
            initial,
            settings,
            drawing,
        })
    }

    fn required_string<'t>(
        &self,
        table: &'t Table<'s>,
        prefix: &str,
        key: &str,
        what: &str,
    ) -> Result<&'t str, ModelError> {
        let path = join(prefix, key);
        match table.get(key) {
            Some(item) => self.string(item, &path),
            None => Err(self.missing(
                &path,
                format!("`{path}` is required"),
                format!("add {key} = …: {what}"),
            )),
        }
    }

    fn string<'t>(&self, item: &'t Item<'s>, key: &str) -> Result<&'t str, ModelError> {
        match item.get_ref() {
            DeValue::String(s) => Ok(s.as_ref()),
            other => Err(self.at(
                item.span().start,
                key,
                format!("expected a string in double quotes, found {}", kind(other)),
                format!("write {} = \"…\"", last(key)),
            )),
        }
    }

    fn table<'t>(
        &self,
        item: &'t Item<'s>,
        key: &str,
        example: &str,
    ) -> Result<&'t Table<'s>, ModelError> {
        match item.get_ref() {
            DeValue::Table(t) => Ok(t),
            other => Err(self.at(
                item.span().start,
                key,
                format!("expected a table, found {}", kind(other)),
                format!("write it as a table: {example}"),
            )),
        }
    }

    /// A number or a formula in a string.
    fn formula(&self, item: &Item<'s>, key: &str) -> Result<Formula, ModelError> {
        let span = item.span();
        let body = match item.get_ref() {
            DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                Ok(v) => Body::Number(v as f64),
                Err(_) => {
                    return Err(self.at(
                        span.start,
                        key,
                        "integer out of range",
                        "write it as a float, e.g. 1e20",
                    ))
                }
            },
            DeValue::Float(f) => Body::Number(f.as_str().parse::<f64>().unwrap_or(f64::NAN)),
            DeValue::String(s) => Body::Text(s.to_string()),
            other => {
                return Err(self.at(
                    span.start,
                    key,
                    format!(
                        "expected a number or a formula in quotes, found {}",
                        kind(other)
                    ),
                    format!("write e.g. {} = 1.5 or {} = \"2*pi\"", last(key), last(key)),
                ))
            }
        };
        let text_start = match &body {
            Body::Text(text) => self.text_start(&span, text),
            Body::Number(_) => None,
        };
        Ok(Formula {
            key: key.to_string(),
            origin: Origin::File { span, text_start },
            body,
        })
    }

    /// Where the text of the string at `span` starts in the file, if the string holds `text`
    /// verbatim (no escapes), so that positions inside it map to the file.
    fn text_start(&self, span: &Range<usize>, text: &str) -> Option<usize> {
        let raw = self.source.get(span.clone())?;
        let quote = if raw.starts_with("\"\"\"") || raw.starts_with("'''") {
            3
        } else {
            1
        };
        let inner = raw.get(quote..raw.len().checked_sub(quote)?)?;
        // A newline right after an opening triple quote is not part of the string.
        let skip = if quote == 3 {
            if inner.starts_with("\r\n") {
                2
            } else {
                usize::from(inner.starts_with('\n'))
            }
        } else {
            0
        };
        (inner.get(skip..)? == text).then_some(span.start + quote + skip)
    }

    /// Compiles `formula` against `names`, reporting problems at their place in the file.
    fn compile(
        &self,
        formula: &Formula,
        names: &Names<'_>,
        what: &str,
    ) -> Result<Expression, ModelError> {
        self.compile_in(formula, names, names, what)
    }

    /// [`Cx::compile`], with the names resolved through `scope` and errors described by
    /// `names`.
    fn compile_in(
        &self,
        formula: &Formula,
        scope: &impl Scope,
        names: &Names<'_>,
        what: &str,
    ) -> Result<Expression, ModelError> {
        let text = match &formula.body {
            Body::Number(v) => {
                if !v.is_finite() {
                    return Err(self.formula_error(
                        formula,
                        None,
                        format!("{what} is {}", Readable(*v)),
                        "give a finite number".to_string(),
                    ));
                }
                // A number is the formula of its shortest exact decimal form.
                format!("{v:?}")
            }
            Body::Text(text) => text.clone(),
        };
        Expression::parse_with(&text, scope, &self.limits).map_err(|error| {
            let (message, help) = describe(&error, names, what);
            self.formula_error(
                formula,
                error.position().map(|p| offset_in(&text, p)),
                message,
                help,
            )
        })
    }

    /// An error in `formula`, at byte `offset` of its text when known.
    fn formula_error(
        &self,
        formula: &Formula,
        offset: Option<usize>,
        message: String,
        help: String,
    ) -> ModelError {
        match &formula.origin {
            Origin::File { span, text_start } => {
                let place = match (text_start, offset) {
                    (Some(start), Some(offset)) => start + offset,
                    _ => span.start,
                };
                self.at(place, &formula.key, message, help)
            }
            Origin::Override(arg) => ModelError {
                file: self.file.into(),
                location: Location::Override(arg.clone()),
                message,
                help: Some(help),
                snippet: None,
            },
        }
    }

    /// A formula of the parameters, evaluated.
    fn constant(
        &self,
        formula: &Formula,
        names: &Names<'_>,
        what: &str,
    ) -> Result<f64, ModelError> {
        let expression = self.compile(formula, names, what)?;
        let value = expression.eval::<f64>(&[]);
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.formula_error(
                formula,
                None,
                format!("{what} evaluates to {}", Readable(value)),
                not_finite_help(value),
            ))
        }
    }

    fn coordinates(&self, root: &Table<'s>) -> Result<Vec<String>, ModelError> {
        let item = root.get("coordinates").ok_or_else(|| {
            self.missing(
                "coordinates",
                "the model has no coordinates",
                "add coordinates = [\"x\", \"y\"], the names of the generalised coordinates q \
                 (their velocities are then x_dot, y_dot)",
            )
        })?;
        let DeValue::Array(array) = item.get_ref() else {
            return Err(self.at(
                item.span().start,
                "coordinates",
                format!("expected a list of names, found {}", kind(item.get_ref())),
                "write coordinates = [\"x\", \"y\"]",
            ));
        };
        if array.is_empty() || array.len() > MAX_DIMENSION {
            return Err(self.at(
                item.span().start,
                "coordinates",
                format!("the model has {} coordinates", array.len()),
                format!("zenosim simulates models with 1 to {MAX_DIMENSION} coordinates"),
            ));
        }
        let mut names: Vec<String> = Vec::new();
        for (i, entry) in array.iter().enumerate() {
            let key = format!("coordinates[{i}]");
            let name = self.string(entry, &key)?;
            let offset = entry.span().start;
            self.check_name(name, offset, &key, "a coordinate")?;
            if name == "mode" || name == "energy" {
                return Err(self.at(
                    offset,
                    &key,
                    format!("`{name}` cannot name a coordinate: it is a column of trajectory.csv"),
                    "choose another name",
                ));
            }
            if names.iter().any(|c| c == name) {
                return Err(self.at(
                    offset,
                    &key,
                    format!("coordinate `{name}` is defined twice"),
                    "give each coordinate its own name",
                ));
            }
            if let Some(other) = names
                .iter()
                .find(|c| format!("{c}_dot") == name || format!("{name}_dot") == **c)
            {
                return Err(self.at(
                    offset,
                    &key,
                    format!("coordinate `{name}` clashes with the velocity name of `{other}`"),
                    "a coordinate's velocity is named <coordinate>_dot: rename one of them",
                ));
            }
            names.push(name.to_string());
        }
        Ok(names)
    }

    /// Checks that `name` can name something: a plain identifier that is neither a built-in
    /// nor the time `t`.
    fn check_name(
        &self,
        name: &str,
        offset: usize,
        key: &str,
        what: &str,
    ) -> Result<(), ModelError> {
        let mut chars = name.chars();
        let identifier = chars
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !identifier {
            return Err(self.at(
                offset,
                key,
                format!("`{name}` cannot name {what}"),
                "names start with a letter or _ and hold only ASCII letters, digits and _",
            ));
        }
        if is_reserved(name) {
            return Err(self.at(
                offset,
                key,
                format!("`{name}` is a built-in function or constant and cannot name {what}"),
                "choose another name",
            ));
        }
        if name == "t" {
            return Err(self.at(
                offset,
                key,
                format!("`t` is the time and cannot name {what}"),
                format!("choose another name: `t` is the time in {TIME_USES}"),
            ));
        }
        Ok(())
    }

    /// `[parameters]` with the overrides applied, evaluated in dependency order.
    fn parameters(
        &self,
        root: &Table<'s>,
        coordinates: &[String],
        velocities: &[String],
        overrides: &[Override],
    ) -> Result<Vec<(String, f64)>, ModelError> {
        let mut formulas: Vec<(String, Formula)> = Vec::new();
        if let Some(item) = root.get("parameters") {
            let table = self.table(item, "parameters", "[parameters] with lines m = 1.0")?;
            let mut entries: Vec<_> = table.iter().collect();
            entries.sort_by_key(|(k, _)| k.span().start);
            for (key, value) in entries {
                let name = key.get_ref().as_ref();
                let path = format!("parameters.{name}");
                self.check_name(name, key.span().start, &path, "a parameter")?;
                if coordinates.iter().chain(velocities).any(|c| c == name) {
                    return Err(self.at(
                        key.span().start,
                        &path,
                        format!(
                            "`{name}` is defined twice: it is already a coordinate, a velocity or the time"
                        ),
                        "give the parameter another name",
                    ));
                }
                formulas.push((name.to_string(), self.formula(value, &path)?));
            }
        }
        for o in overrides {
            if let Some((_, formula)) = formulas.iter_mut().find(|(p, _)| *p == o.name) {
                *formula = override_formula(o);
            } else if !coordinates.iter().chain(velocities).any(|c| *c == o.name) {
                let known: Vec<&str> = formulas
                    .iter()
                    .map(|(p, _)| p.as_str())
                    .chain(coordinates.iter().chain(velocities).map(String::as_str))
                    .collect();
                let hint = did_you_mean(&o.name, known.iter().copied());
                return Err(ModelError {
                    file: self.file.into(),
                    location: Location::Override(o.to_string()),
                    message: format!(
                        "`{}` is neither a parameter nor a coordinate or velocity of this model",
                        o.name
                    ),
                    help: Some(format!("{hint}--set takes one of {}", list(&known))),
                    snippet: None,
                });
            }
        }

        // Each parameter's formula, over the parameters as slots, to find the dependencies.
        let slots: Vec<(String, f64)> = formulas.iter().map(|(p, _)| (p.clone(), 0.0)).collect();
        let index = parameter_index(&slots);
        let names = Names {
            coordinates,
            velocities,
            parameters: &slots,
            index: &index,
            reads: Reads::ParameterSlots,
        };
        let compiled = formulas
            .iter()
            .map(|(p, f)| self.compile(f, &names, &format!("parameter `{p}`")))
            .collect::<Result<Vec<_>, _>>()?;

        let values = self.evaluate_parameters(&formulas, &compiled)?;
        Ok(formulas
            .into_iter()
            .zip(values)
            .map(|((p, _), v)| (p, v))
            .collect())
    }

    /// Every parameter's value, each evaluated once its own parameters are, depth first; a
    /// parameter met again while it is being evaluated closes a cycle. The depth-first search
    /// keeps its own stack (a chain of 100 000 parameters must not overflow the thread's), and
    /// every formula reads the one vector of values, indexed by slot.
    fn evaluate_parameters(
        &self,
        formulas: &[(String, Formula)],
        compiled: &[Expression],
    ) -> Result<Vec<f64>, ModelError> {
        #[derive(Clone, Copy, PartialEq)]
        enum State {
            New,
            Evaluating,
            Done,
        }
        let count = formulas.len();
        let mut values = vec![0.0_f64; count];
        let mut state = vec![State::New; count];
        // The path being evaluated: each parameter with how many of its slots are done.
        let mut path: Vec<(usize, usize)> = Vec::new();
        for start in 0..count {
            if state[start] != State::New {
                continue;
            }
            state[start] = State::Evaluating;
            path.push((start, 0));
            while let Some(&mut (index, ref mut next)) = path.last_mut() {
                let slots = compiled[index].slots();
                if let Some(&slot) = slots.get(*next) {
                    *next += 1;
                    match state[slot] {
                        State::Done => {}
                        State::New => {
                            state[slot] = State::Evaluating;
                            path.push((slot, 0));
                        }
                        State::Evaluating => return Err(self.cycle(formulas, &path, slot)),
                    }
                    continue;
                }
                path.pop();
                let value: f64 = compiled[index].eval(&values);
                if !value.is_finite() {
                    let (name, formula) = &formulas[index];
                    return Err(self.formula_error(
                        formula,
                        None,
                        format!("parameter `{name}` evaluates to {}", Readable(value)),
                        not_finite_help(value),
                    ));
                }
                values[index] = value;
                state[index] = State::Done;
            }
        }
        Ok(values)
    }

    /// The error of a cycle: `slot` is met again on `path`.
    fn cycle(
        &self,
        formulas: &[(String, Formula)],
        path: &[(usize, usize)],
        slot: usize,
    ) -> ModelError {
        let at = path.iter().position(|&(p, _)| p == slot).unwrap_or(0);
        let cycle: Vec<&str> = path[at..]
            .iter()
            .map(|&(p, _)| p)
            .chain([slot])
            .map(|p| formulas[p].0.as_str())
            .collect();
        let (name, formula) = &formulas[slot];
        self.formula_error(
            formula,
            None,
            format!(
                "parameter `{name}` depends on itself: {}",
                cycle.join(" → ")
            ),
            "parameters may refer to each other in any order, but not in a cycle: give one of \
             them a value"
                .to_string(),
        )
    }

    fn constraints<'n>(
        &self,
        root: &Table<'s>,
        names: &impl Fn(Reads) -> Names<'n>,
    ) -> Result<Vec<ParsedConstraint>, ModelError> {
        let help = "add one [[constraint]] per unilateral constraint, with name = \"…\", \
                    h = \"…\" (the admissible side is h >= 0) and restitution = 0.5";
        let item = root
            .get("constraint")
            .ok_or_else(|| self.missing("constraint", "the model has no constraint", help))?;
        let DeValue::Array(array) = item.get_ref() else {
            return Err(self.at(
                item.span().start,
                "constraint",
                format!(
                    "expected [[constraint]] tables, found {}",
                    kind(item.get_ref())
                ),
                help,
            ));
        };
        if array.is_empty() || array.len() > ActiveSet::CAPACITY {
            return Err(self.at(
                item.span().start,
                "constraint",
                format!("the model has {} constraints", array.len()),
                format!("zenosim needs 1 to {} constraints", ActiveSet::CAPACITY),
            ));
        }
        let mut parsed: Vec<ParsedConstraint> = Vec::new();
        let mut seen = HashSet::new();
        for (i, entry) in array.iter().enumerate() {
            let prefix = format!("constraint[{}]", i + 1);
            let table = self.table(entry, &prefix, "[[constraint]] followed by its keys")?;
            self.known_keys(table, &prefix, &CONSTRAINT_KEYS)?;
            let name = self.required_string(
                table,
                &prefix,
                "name",
                "a name for the constraint, e.g. name = \"floor\"",
            )?;
            let name_item = table.get("name").expect("present");
            let valid = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if !valid {
                return Err(self.at(
                    name_item.span().start,
                    &join(&prefix, "name"),
                    format!("`{name}` cannot name a constraint"),
                    "constraint names hold only ASCII letters, digits, _ and - (they become \
                     column names such as h_floor)",
                ));
            }
            if !seen.insert(name.to_string()) {
                return Err(self.at(
                    name_item.span().start,
                    &join(&prefix, "name"),
                    format!("constraint `{name}` is defined twice"),
                    "give each constraint its own name",
                ));
            }
            let what = format!("h of constraint `{name}`");
            let h_key = join(&prefix, "h");
            let h_item = table.get("h").ok_or_else(|| {
                self.missing(
                    &h_key,
                    format!("constraint `{name}` has no h"),
                    "add h = \"…\", a formula of the coordinates; the admissible side is h >= 0",
                )
            })?;
            let h_formula = self.formula(h_item, &h_key)?;
            let h_names = names(Reads::Coordinates);
            let h = self.compile(&h_formula, &h_names, &what)?;
            if !h
                .slots()
                .iter()
                .any(|&slot| slot < h_names.coordinates.len())
            {
                return Err(self.formula_error(
                    &h_formula,
                    None,
                    format!("{what} does not depend on any coordinate"),
                    "a unilateral constraint h(t, q) >= 0 must depend on the coordinates, e.g. h = \"y\" for a floor at y = 0, or h = \"y - a*sin(w*t)\" for a floor that moves".to_string(),
                ));
            }

            let e_key = join(&prefix, "restitution");
            let e_item = table.get("restitution").ok_or_else(|| {
                self.missing(&e_key, format!("constraint `{name}` has no restitution"), "add restitution = 0.5, the coefficient of restitution in [0, 1] (0 plastic, 1 elastic)")
            })?;
            let e_formula = self.formula(e_item, &e_key)?;
            let what_e = format!("the restitution of `{name}`");
            let restitution = self.constant(&e_formula, &names(Reads::Constants), &what_e)?;
            if !(0.0..=1.0).contains(&restitution) {
                return Err(self.formula_error(
                    &e_formula,
                    None,
                    format!("{what_e} is {restitution}, outside [0, 1]"),
                    "a coefficient of restitution lies between 0 (perfectly plastic) and 1 (elastic)".to_string(),
                ));
            }

            let reset = match table.get("zeno_reset") {
                Some(item) => self.zeno_reset(item, &join(&prefix, "zeno_reset"), name, names)?,
                None => Vec::new(),
            };
            let friction = match table.get("friction") {
                Some(item) => Some(self.friction(item, &join(&prefix, "friction"), name, names)?),
                None => None,
            };
            let slip =
                match (table.get("slip"), friction) {
                    (Some(item), Some(_)) => {
                        Some(self.slip(item, &join(&prefix, "slip"), name, names)?)
                    }
                    (Some(item), None) => {
                        return Err(self.at(
                            item.span().start,
                            &join(&prefix, "slip"),
                            format!("constraint `{name}` has a slip but no friction"),
                            "add friction = 0.5 (Coulomb's coefficient), or remove slip",
                        ))
                    }
                    (None, Some(_)) => return Err(self.missing(
                        &join(&prefix, "slip"),
                        format!("constraint `{name}` has friction but no slip"),
                        "add slip = [\"…\"], the contact points' relative tangential velocity, \
                         e.g. slip = [\"x_dot + r*th_dot\"] for a ball rolling on a floor",
                    )),
                    (None, None) => None,
                };
            parsed.push(ParsedConstraint {
                name: name.to_string(),
                h,
                restitution,
                reset,
                friction: friction.zip(slip),
            });
        }
        Ok(parsed)
    }

    /// A constraint's `friction`: Coulomb's coefficient (a number or a formula of the
    /// parameters), or `{ static = …, kinetic = … }` with `kinetic <= static`.
    fn friction<'n>(
        &self,
        item: &Item<'s>,
        key: &str,
        constraint: &str,
        names: &impl Fn(Reads) -> Names<'n>,
    ) -> Result<Friction, ModelError> {
        let coefficient = |item: &Item<'s>, key: &str, what: &str| -> Result<f64, ModelError> {
            let formula = self.formula(item, key)?;
            let value = self.constant(&formula, &names(Reads::Constants), what)?;
            if value < 0.0 {
                return Err(self.formula_error(
                    &formula,
                    None,
                    format!("{what} is {value}, below 0"),
                    "a friction coefficient is 0 (frictionless) or more".to_string(),
                ));
            }
            Ok(value)
        };
        if let DeValue::Table(table) = item.get_ref() {
            self.known_keys(table, key, &["static", "kinetic"])?;
            let get = |which: &str| -> Result<f64, ModelError> {
                let sub = table.get(which).ok_or_else(|| {
                    self.missing(
                        &join(key, which),
                        format!("the friction of `{constraint}` has no {which} coefficient"),
                        "write friction = { static = 0.6, kinetic = 0.5 }, or one number for both",
                    )
                })?;
                coefficient(
                    sub,
                    &join(key, which),
                    &format!("the {which} friction of `{constraint}`"),
                )
            };
            let (static_coefficient, kinetic_coefficient) = (get("static")?, get("kinetic")?);
            if kinetic_coefficient > static_coefficient {
                return Err(self.at(
                    item.span().start,
                    key,
                    format!(
                        "the kinetic friction of `{constraint}` ({kinetic_coefficient}) is above its static friction ({static_coefficient})"
                    ),
                    "Coulomb's kinetic coefficient is at most the static one: swap them, or give one number for both",
                ));
            }
            return Ok(Friction {
                static_coefficient,
                kinetic_coefficient,
            });
        }
        let mu = coefficient(item, key, &format!("the friction of `{constraint}`"))?;
        Ok(Friction::coulomb(mu))
    }

    /// A constraint's `slip`: one formula (a contact in a plane) or two (a contact in space,
    /// along two orthonormal tangent directions) of `t`, the coordinates, the velocities and
    /// the parameters, each affine in the velocities.
    fn slip<'n>(
        &self,
        item: &Item<'s>,
        key: &str,
        constraint: &str,
        names: &impl Fn(Reads) -> Names<'n>,
    ) -> Result<Vec<Expression>, ModelError> {
        let example = "slip = [\"x_dot + r*th_dot\"]";
        let DeValue::Array(array) = item.get_ref() else {
            return Err(self.at(
                item.span().start,
                key,
                format!("the slip of `{constraint}` must be a list of formulas"),
                format!("write {example}: the contact points' relative tangential velocity"),
            ));
        };
        if !(1..=2).contains(&array.len()) {
            return Err(self.at(
                item.span().start,
                key,
                format!("the slip of `{constraint}` has {} formulas", array.len()),
                format!(
                    "a contact in a plane has one slip formula, e.g. {example}; a contact in \
                     space two, its slip along two orthonormal tangent directions, e.g. \
                     slip = [\"x_dot - r*wy\", \"y_dot + r*wx\"]"
                ),
            ));
        }
        let state = names(Reads::State);
        let n = state.coordinates.len();
        let mut formulas = Vec::with_capacity(array.len());
        for (i, entry) in array.iter().enumerate() {
            let entry_key = format!("{key}[{}]", i + 1);
            let formula = self.formula(entry, &entry_key)?;
            let what = if array.len() == 1 {
                format!("the slip of `{constraint}`")
            } else {
                format!("component {} of the slip of `{constraint}`", i + 1)
            };
            let expression = self.compile(&formula, &state, &what)?;
            if !expression
                .slots()
                .iter()
                .any(|&slot| (n..2 * n).contains(&slot))
            {
                return Err(self.formula_error(
                    &formula,
                    None,
                    format!("{what} does not depend on any velocity"),
                    format!("the slip is a velocity, affine in the velocities: {example}"),
                ));
            }
            if let Some(pair) = not_affine(&expression, n) {
                return Err(self.formula_error(
                    &formula,
                    None,
                    format!(
                        "{what} is not affine in the velocities: its derivative along {}_dot changes with {}_dot",
                        state.coordinates[pair.0], state.coordinates[pair.1]
                    ),
                    format!("the slip is the contact points' relative velocity, of the form a(t, q)·q̇ + b(t, q): {example}"),
                ));
            }
            formulas.push(expression);
        }
        Ok(formulas)
    }

    fn zeno_reset<'n>(
        &self,
        item: &Item<'s>,
        key: &str,
        constraint: &str,
        names: &impl Fn(Reads) -> Names<'n>,
    ) -> Result<Vec<(usize, Expression)>, ModelError> {
        let table = self.table(
            item,
            key,
            "zeno_reset = { x3 = \"sin(x2)\", x3_dot = \"cos(x2)*x2_dot\" }",
        )?;
        let state = names(Reads::State);
        let mut entries: Vec<_> = table.iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        let mut reset = Vec::new();
        for (target, value) in entries {
            let target_name = target.get_ref().as_ref();
            let path = join(key, target_name);
            let Some(slot) = state.state_slot(target_name) else {
                return Err(self.at(
                    target.span().start,
                    &path,
                    format!("`{target_name}` is not a coordinate or a velocity"),
                    format!(
                        "zeno_reset sets coordinates ({}) and velocities ({})",
                        list(state.coordinates),
                        list(state.velocities)
                    ),
                ));
            };
            let formula = self.formula(value, &path)?;
            let what = format!("zeno_reset of `{constraint}`");
            reset.push((slot, self.compile(&formula, &state, &what)?));
        }
        Ok(reset)
    }

    /// `[forces]`: the generalized force on each coordinate it names, a formula of the time,
    /// the coordinates, the velocities and the parameters; (coordinate index, formula) in the
    /// file's order.
    fn forces(
        &self,
        root: &Table<'s>,
        state: &Names<'_>,
    ) -> Result<Vec<(usize, Expression)>, ModelError> {
        let Some(item) = root.get("forces") else {
            return Ok(Vec::new());
        };
        let example = state
            .coordinates
            .first()
            .map_or_else(String::new, |c| format!("{c} = \"-c*{c}_dot\""));
        let table = self.table(item, "forces", &format!("[forces] with lines {example}"))?;
        let mut entries: Vec<_> = table.iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        let mut forces = Vec::with_capacity(entries.len());
        for (key, value) in entries {
            let name = key.get_ref().as_ref();
            let path = join("forces", name);
            let Some(index) = state.coordinates.iter().position(|c| c == name) else {
                return Err(self.not_a_coordinate_force(key.span().start, &path, name, state));
            };
            let formula = self.formula(value, &path)?;
            let what = format!("the force on `{name}`");
            forces.push((index, self.compile(&formula, state, &what)?));
        }
        Ok(forces)
    }

    /// The error of a `[forces]` key `name` (at `offset`) that is not a coordinate.
    fn not_a_coordinate_force(
        &self,
        offset: usize,
        path: &str,
        name: &str,
        state: &Names<'_>,
    ) -> ModelError {
        let coordinates = list(state.coordinates);
        let rule = format!(
            "[forces] gives the generalized force on a coordinate ({coordinates}), as a formula \
             of t, the coordinates, the velocities and the parameters; the coordinates not \
             listed get 0"
        );
        if let Some(coordinate) = name
            .strip_suffix("_dot")
            .filter(|c| state.coordinates.iter().any(|q| q == c))
        {
            return self.at(
                offset,
                path,
                format!("`{name}` is a velocity, not a coordinate"),
                format!("write the force on `{coordinate}` as {coordinate} = \"…\" (it may depend on {name}); {rule}"),
            );
        }
        let what = if name == "t" {
            "`t` is the time, not a coordinate".to_string()
        } else if state.index.contains_key(name) {
            format!("`{name}` is a parameter, not a coordinate")
        } else {
            format!("`{name}` is not a coordinate")
        };
        let hint = did_you_mean(name, state.coordinates.iter().map(String::as_str));
        self.at(offset, path, what, format!("{hint}{rule}"))
    }

    /// `dissipation`: a Rayleigh dissipation function `D(t, q, q̇)`, which must depend on a
    /// velocity (its force `−∂D/∂q̇` is zero otherwise).
    fn dissipation(
        &self,
        root: &Table<'s>,
        state: &Names<'_>,
    ) -> Result<Option<Expression>, ModelError> {
        let Some(item) = root.get("dissipation") else {
            return Ok(None);
        };
        let formula = self.formula(item, "dissipation")?;
        let expression = self.compile(&formula, state, "the dissipation function")?;
        let n = state.coordinates.len();
        if !expression
            .slots()
            .iter()
            .any(|slot| (n..2 * n).contains(slot))
        {
            let example = state.velocities.first().map_or_else(String::new, |v| {
                format!(" (dissipation = \"0.5*c*{v}^2\" is a damper c)")
            });
            return Err(self.formula_error(
                &formula,
                None,
                "the dissipation function does not depend on any velocity: its force −∂D/∂q̇ would be zero".to_string(),
                format!(
                    "a Rayleigh dissipation function D(t, q, q_dot) is a formula of the velocities {}{example}; give a force that does not depend on them under [forces] instead",
                    list(state.velocities)
                ),
            ));
        }
        Ok(Some(expression))
    }

    fn initial(
        &self,
        root: &Table<'s>,
        coordinates: &[String],
        velocities: &[String],
        constants: &Names<'_>,
        overrides: &[Override],
    ) -> Result<State, ModelError> {
        let n = coordinates.len();
        let mut formulas: Vec<Option<Formula>> = vec![None; 2 * n];
        // The slot of a coordinate or velocity, as formulas of the state bind them.
        let state = Names {
            reads: Reads::State,
            ..*constants
        };
        let slot = |name: &str| state.state_slot(name);
        if let Some(item) = root.get("initial") {
            let table = self.table(item, "initial", "[initial] with lines x = 1.0, x_dot = 0.5")?;
            for (key, value) in table {
                let name = key.get_ref().as_ref();
                let path = format!("initial.{name}");
                let Some(index) = slot(name) else {
                    if name == "t" {
                        return Err(self.at(
                            key.span().start,
                            &path,
                            "`t` is the time, not a coordinate or a velocity",
                            "[initial] gives the state at t = 0, where every run starts; it sets coordinates and velocities",
                        ));
                    }
                    if constants.index.contains_key(name) {
                        return Err(self.at(
                            key.span().start,
                            &path,
                            format!("`{name}` is a parameter, not a coordinate or a velocity"),
                            "set parameters under [parameters]; [initial] sets coordinates and velocities",
                        ));
                    }
                    let known: Vec<&str> = coordinates
                        .iter()
                        .chain(velocities)
                        .map(String::as_str)
                        .collect();
                    let hint = did_you_mean(name, known.iter().copied());
                    return Err(self.at(
                        key.span().start,
                        &path,
                        format!("`{name}` is not a coordinate or a velocity"),
                        format!(
                            "{hint}[initial] sets {}; the ones not given start at 0",
                            list(&known)
                        ),
                    ));
                };
                formulas[index] = Some(self.formula(value, &path)?);
            }
        }
        for o in overrides {
            if let Some(index) = slot(&o.name) {
                formulas[index] = Some(override_formula(o));
            }
        }
        let mut values = vec![0.0; 2 * n];
        for (index, formula) in formulas.iter().enumerate() {
            if let Some(formula) = formula {
                let name = if index < n {
                    &coordinates[index]
                } else {
                    &velocities[index - n]
                };
                values[index] = self.constant(
                    formula,
                    constants,
                    &format!("the initial value of `{name}`"),
                )?;
            }
        }
        let q_dot = values.split_off(n);
        Ok(State { q: values, q_dot })
    }

    fn settings(&self, root: &Table<'s>, constants: &Names<'_>) -> Result<Settings, ModelError> {
        let mut settings = Settings::default();
        let Some(item) = root.get("simulation") else {
            return Ok(settings);
        };
        let table = self.table(item, "simulation", "[simulation] with lines t_end = 6.0")?;
        self.known_keys(table, "simulation", &SIMULATION_KEYS)?;
        let positive = |key: &str, what: &str| -> Result<Option<f64>, ModelError> {
            let Some(item) = table.get(key) else {
                return Ok(None);
            };
            let path = format!("simulation.{key}");
            let formula = self.formula(item, &path)?;
            let value = self.constant(&formula, constants, &path)?;
            if value > 0.0 {
                Ok(Some(value))
            } else {
                Err(self.at(
                    item.span().start,
                    &path,
                    format!("{key} is {}; it must be > 0", Readable(value)),
                    what,
                ))
            }
        };
        if let Some(t_end) = positive("t_end", "give the stop time, > 0")? {
            settings.t_end = t_end;
        }
        if let Some(rtol) = positive("rtol", "give a relative tolerance > 0, e.g. 1e-10")? {
            if rtol < 1e-15 {
                let item = table.get("rtol").expect("present");
                return Err(self.at(
                    item.span().start,
                    "simulation.rtol",
                    format!("rtol = {rtol} is below what f64 resolves"),
                    "give rtol >= 1e-15",
                ));
            }
            settings.tolerances.rtol = rtol;
        }
        if let Some(atol) = positive("atol", "give an absolute tolerance > 0, e.g. 1e-10")? {
            settings.tolerances.atol = atol;
        }
        settings.dt = positive(
            "dt",
            "give a sampling interval > 0, or leave dt out to sample every step",
        )?;
        if let Some(max_step) =
            positive("max_step", "give a largest step > 0, or leave max_step out")?
        {
            settings.max_step = max_step;
        }
        for (key, target) in [
            ("max_events", &mut settings.max_events),
            ("max_steps", &mut settings.max_steps),
        ] {
            if let Some(item) = table.get(key) {
                match item.get_ref() {
                    DeValue::Integer(i) => match u64::from_str_radix(i.as_str(), i.radix()) {
                        Ok(v) if v > 0 => *target = v,
                        _ => {
                            return Err(self.at(
                                item.span().start,
                                &format!("simulation.{key}"),
                                format!("{key} must be a whole number > 0"),
                                format!("write e.g. {key} = 100000"),
                            ))
                        }
                    },
                    other => {
                        return Err(self.at(
                            item.span().start,
                            &format!("simulation.{key}"),
                            format!("expected a whole number, found {}", kind(other)),
                            format!("write e.g. {key} = 100000"),
                        ))
                    }
                }
            }
        }
        if let Some(item) = table.get("zeno") {
            settings.zeno = self.zeno(item, constants)?;
        }
        if let Some(item) = table.get("method") {
            settings.method = match self.string(item, "simulation.method")? {
                "dop853" => Method::Dop853,
                "dopri5" => Method::Dopri5,
                other => {
                    return Err(self.at(
                        item.span().start,
                        "simulation.method",
                        format!("unknown method `{other}`"),
                        "method is \"dop853\" (the default) or \"dopri5\"",
                    ))
                }
            };
        }
        // What is left to check involves several keys at once (a sampling grid denser than
        // the step limit, say): the engine's own check, placed at the key it names.
        if let Err(zenosim::Error::Option {
            option, expected, ..
        }) = settings.options().validate()
        {
            let at = table.get(option).unwrap_or(item);
            return Err(self.at(
                at.span().start,
                &format!("simulation.{option}"),
                format!("{option} is invalid: {expected}"),
                "change it, or the settings it depends on",
            ));
        }
        Ok(settings)
    }

    fn zeno(&self, item: &Item<'s>, constants: &Names<'_>) -> Result<ZenoStrategy, ModelError> {
        let help =
            "write zeno = \"auto\" (detect Zeno points and go on past them), zeno = \"off\" \
                    (stop at them) or zeno = { epsilon = 1e-3 } (the paper's ε rule)";
        match item.get_ref() {
            DeValue::String(s) => match parse_zeno(s) {
                Some(z) => Ok(z),
                None => Err(self.at(
                    item.span().start,
                    "simulation.zeno",
                    format!("unknown Zeno strategy `{s}`"),
                    help,
                )),
            },
            DeValue::Table(t) => {
                self.known_keys(t, "simulation.zeno", &["epsilon"])?;
                let Some(eps_item) = t.get("epsilon") else {
                    return Err(self.missing(
                        "simulation.zeno.epsilon",
                        "the ε rule needs its threshold",
                        help,
                    ));
                };
                let formula = self.formula(eps_item, "simulation.zeno.epsilon")?;
                let eps = self.constant(&formula, constants, "epsilon")?;
                if eps > 0.0 {
                    Ok(ZenoStrategy::Epsilon(eps))
                } else {
                    Err(self.at(
                        eps_item.span().start,
                        "simulation.zeno.epsilon",
                        format!("epsilon is {eps}; it must be > 0"),
                        "the paper uses epsilon = 1e-3",
                    ))
                }
            }
            other => Err(self.at(
                item.span().start,
                "simulation.zeno",
                format!("expected a string or a table, found {}", kind(other)),
                help,
            )),
        }
    }

    /// The checks at the initial state: admissible, and a positive definite mass matrix.
    fn check_initial_state(
        &self,
        root: &Table<'s>,
        model: &FileModel,
        initial: &State,
    ) -> Result<(), ModelError> {
        let initial_at = |message: String, help: &str| match root.get("initial") {
            Some(item) => self.at(item.span().start, "initial", message, help),
            None => self.missing("initial", message, help),
        };
        let derived = Derived::new(model)
            .map_err(|e| ModelError::file(self.file, e.to_string(), "check the coordinates"))?;
        for (index, c) in model.constraints().iter().enumerate() {
            let (h, gradient) = derived.constraint(index, &initial.q);
            if !h.is_finite() || gradient.iter().any(|a| !a.is_finite()) {
                let h_item = root.get("constraint").expect("checked");
                return Err(self.at(
                    h_item.span().start,
                    &format!("constraint[{}].h", index + 1),
                    format!(
                        "h of constraint `{}` or its gradient is not finite at the initial state (h(q0) = {h}, A(q0) = {gradient:?})",
                        c.name
                    ),
                    "look for a division by zero or a square root of 0 in h at the initial state, or start elsewhere",
                ));
            }
            if h == 0.0 && gradient.iter().all(|&a| a == 0.0) {
                let h_item = root.get("constraint").expect("checked");
                return Err(self.at(
                    h_item.span().start,
                    &format!("constraint[{}].h", index + 1),
                    format!(
                        "the initial state is on constraint `{}` (h(q0) = 0) where its gradient \
                         ∂h/∂q vanishes: there is no direction for it to act in",
                        c.name
                    ),
                    "write h so that its gradient does not vanish on h = 0 (y, not y^2), or \
                     start elsewhere",
                ));
            }
            if !zenosim::admissible_start(h, &gradient, &initial.q) {
                return Err(initial_at(
                    format!(
                        "the initial state violates constraint `{}`: h(q0) = {}, but the admissible side is h >= 0",
                        c.name,
                        Readable(h)
                    ),
                    "start on the admissible side: change [initial] (or --set) so that every h is >= 0",
                ));
            }
        }
        let (mass, positive) = derived.mass_matrix(&initial.q, &initial.q_dot);
        let energy = derived.energy(&initial.q, &initial.q_dot);
        if !energy.is_finite() || mass.iter().any(|m| !m.is_finite()) {
            let lagrangian = root.get("lagrangian").expect("checked");
            return Err(self.at(
                lagrangian.span().start,
                "lagrangian",
                format!("the Lagrangian's energy or mass matrix is not finite at the initial state (energy {energy})"),
                "look for a division by zero, or a logarithm or square root of 0, at the initial state, or start elsewhere",
            ));
        }
        if !positive {
            let n = model.dimension();
            let lagrangian = root.get("lagrangian").expect("checked");
            let flat: Vec<&str> = (0..n)
                .filter(|&i| mass[i * n + i] == 0.0)
                .map(|i| model.coordinates[i].as_str())
                .collect();
            let detail = if flat.is_empty() {
                String::new()
            } else {
                format!(
                    "; the Lagrangian has no kinetic term in {}",
                    list(&flat.iter().map(|c| format!("{c}_dot")).collect::<Vec<_>>())
                )
            };
            let rows: Vec<String> = mass.chunks(n).map(|r| format!("{r:?}")).collect();
            return Err(self.at(
                lagrangian.span().start,
                "lagrangian",
                format!(
                    "the mass matrix ∂²L/∂q̇² is not positive definite at the initial state (M = [{}]){detail}",
                    rows.join(", ")
                ),
                "every coordinate needs a kinetic term with a positive coefficient (e.g. 0.5*m*x_dot^2), and the initial state must avoid coordinate singularities such as sin(theta) = 0",
            ));
        }
        if let Some(velocity) = not_quadratic(&derived, &initial.q, &initial.q_dot, &mass) {
            let lagrangian = root.get("lagrangian").expect("checked");
            return Err(self.at(
                lagrangian.span().start,
                "lagrangian",
                format!(
                    "the Lagrangian is not quadratic in the velocities: its mass matrix ∂²L/∂q̇² changes with the velocities (in its column of {}_dot). zenosim's mechanics (the energy q̇·∂L/∂q̇ − L as ½ q̇ᵀMq̇ plus potential, the impact laws, the contact forces) hold for L = ½ q̇ᵀM(q)q̇ + b(q)·q̇ − V(q)",
                    model.coordinates[velocity]
                ),
                "write the kinetic energy as a quadratic form in the velocities (e.g. 0.5*m*x_dot^2), with terms linear in them where the model needs them",
            ));
        }
        Ok(())
    }

    /// The forces and the dissipation function at the initial state, at `t = 0`: finite.
    fn check_initial_forces(
        &self,
        root: &Table<'s>,
        model: &FileModel,
        initial: &State,
    ) -> Result<(), ModelError> {
        let (q, q_dot) = (initial.q.as_slice(), initial.q_dot.as_slice());
        let help = |value: f64| {
            format!(
                "{} at the initial state (t = 0), or start elsewhere",
                not_finite_help(value)
            )
        };
        for (index, formula) in &model.forces {
            let value: f64 = formula.eval_at(q, q_dot, 0.0);
            if !value.is_finite() {
                let name = &model.coordinates[*index];
                let place = formula_place(root, model, ModelFormula::Force(*index));
                return Err(self.at(
                    place.span.start,
                    &place.key,
                    format!(
                        "the force on `{name}` is {} at the initial state",
                        Readable(value)
                    ),
                    help(value),
                ));
            }
        }
        if let Some(formula) = &model.dissipation {
            let value: f64 = formula.eval_at(q, q_dot, 0.0);
            if !value.is_finite() {
                let place = formula_place(root, model, ModelFormula::Dissipation);
                return Err(self.at(
                    place.span.start,
                    &place.key,
                    format!(
                        "the dissipation function is {} at the initial state",
                        Readable(value)
                    ),
                    help(value),
                ));
            }
        }
        Ok(())
    }
}

/// Where one of a model's formulas is in its file: its text's span, its key, and what it is.
struct Place {
    span: Range<usize>,
    key: String,
    what: String,
}

/// The [`Place`] of `formula` in the file `root` that `model` was read from.
fn formula_place(root: &Table<'_>, model: &FileModel, formula: ModelFormula) -> Place {
    let span = |item: Option<&Item<'_>>| item.map_or(0..0, Spanned::span);
    match formula {
        ModelFormula::Lagrangian => Place {
            span: span(root.get("lagrangian")),
            key: "lagrangian".to_string(),
            what: "the Lagrangian".to_string(),
        },
        ModelFormula::Constraint(i) => {
            let h = root
                .get("constraint")
                .and_then(|array| match array.get_ref() {
                    DeValue::Array(array) => array.get(i)?.get_ref().as_table()?.get("h"),
                    _ => None,
                });
            Place {
                span: span(h),
                key: format!("constraint[{}].h", i + 1),
                what: format!("constraint `{}`'s h", model.constraints[i].name),
            }
        }
        ModelFormula::Force(i) => {
            let name = &model.coordinates[i];
            let item = root
                .get("forces")
                .and_then(|forces| forces.get_ref().as_table()?.get(name.as_str()));
            Place {
                span: span(item),
                key: join("forces", name),
                what: format!("the force on `{name}`"),
            }
        }
        ModelFormula::Dissipation => Place {
            span: span(root.get("dissipation")),
            key: "dissipation".to_string(),
            what: "the dissipation function".to_string(),
        },
    }
}

/// A `[[constraint]]`, compiled.
struct ParsedConstraint {
    name: String,
    h: Expression,
    restitution: f64,
    reset: Vec<(usize, Expression)>,
    /// Coulomb friction and the slip formula, where the constraint has them.
    friction: Option<(Friction, Vec<Expression>)>,
}

/// A column of the mass matrix `M = ∂²L/∂q̇²` of `derived` that changes with the velocities: `M` at the
/// positions `q` (and at two others nearby) with the velocities `q̇` and with two other sets of
/// velocities differs beyond `10⁻⁹` of its size (`mass` is `M(q, q̇)`). For a Lagrangian
/// quadratic in the velocities `M` depends on the positions alone, exactly: its second
/// derivatives are sums of products of the velocities' coefficients. `None` where it is, or
/// where `M` is not finite away from the initial state (a singular position: nothing to
/// compare).
fn not_quadratic(
    derived: &Derived<'_, FileModel>,
    q: &[f64],
    q_dot: &[f64],
    mass: &[f64],
) -> Option<usize> {
    let n = q.len();
    let shifted = |x: &[f64], by: f64| -> Vec<f64> {
        x.iter()
            .enumerate()
            .map(|(i, v)| v + by * (1.0 + 0.37 * i as f64))
            .collect()
    };
    for (k, by) in [0.0, 0.013, -0.021].into_iter().enumerate() {
        let positions = shifted(q, by);
        let reference = if k == 0 {
            mass.to_vec()
        } else {
            derived.mass_matrix(&positions, q_dot).0
        };
        if reference.iter().any(|m| !m.is_finite()) {
            continue;
        }
        let size = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for step in [0.7, -1.3] {
            let (other, _) = derived.mass_matrix(&positions, &shifted(q_dot, step));
            if other.iter().any(|m| !m.is_finite()) {
                continue;
            }
            if let Some(entry) = (0..n * n).find(|&e| (other[e] - reference[e]).abs() > 1e-9 * size)
            {
                return Some(entry % n);
            }
        }
    }
    None
}

/// A pair of velocities `(i, j)` along which `expression`'s second derivative is not 0 at one
/// of a few sample states: the slip is then not affine in the velocities. Hyper-dual numbers
/// give the second derivatives exactly; the states are spread so that a product of velocities
/// or a nonlinear function of one shows at one of them.
fn not_affine(expression: &Expression, n: usize) -> Option<(usize, usize)> {
    use num_dual::HyperDual64;
    let samples = [0.0, 0.7, -1.3, 2.9];
    for (k, &base) in samples.iter().enumerate() {
        let value = |slot: usize| base + 0.37 * slot as f64 + 0.11 * k as f64;
        for i in 0..n {
            for j in i..n {
                let vars: Vec<HyperDual64> = (0..=2 * n)
                    .map(|slot| {
                        let mut x = HyperDual64::from(value(slot));
                        if slot == n + i {
                            x.eps1 = 1.0;
                        }
                        if slot == n + j {
                            x.eps2 = 1.0;
                        }
                        x
                    })
                    .collect();
                let second = expression.eval(&vars).eps1eps2;
                if second != 0.0 && second.is_finite() {
                    return Some((i, j));
                }
            }
        }
    }
    None
}

/// `"auto"`, `"off"` or a number (the ε rule), as the command line writes a Zeno strategy.
pub fn parse_zeno(text: &str) -> Option<ZenoStrategy> {
    match text {
        "auto" => Some(ZenoStrategy::Auto),
        "off" => Some(ZenoStrategy::Off),
        _ => text
            .parse::<f64>()
            .ok()
            .filter(|e| *e > 0.0 && e.is_finite())
            .map(ZenoStrategy::Epsilon),
    }
}

fn override_formula(o: &Override) -> Formula {
    Formula {
        key: format!("--set {o}"),
        origin: Origin::Override(o.to_string()),
        body: match o.value.parse::<f64>() {
            Ok(v) => Body::Number(v),
            Err(_) => Body::Text(o.value.clone()),
        },
    }
}

/// What an expression error means here, and what to do.
fn describe(error: &ExprError, names: &Names<'_>, what: &str) -> (String, String) {
    let limit = match error {
        ExprError::TooLong { .. } => Some("length"),
        ExprError::TooDeep { .. } => Some("depth"),
        _ => None,
    };
    if let Some(limit) = limit {
        return (
            format!("in {what}: {error}"),
            format!(
                "split the formula into parameters, or, if it is right as it is, raise the \
                 limit: `zenosim run --max-formula-{limit} N` (Limits in the library)"
            ),
        );
    }
    let ExprError::UnknownName { name, .. } = error else {
        return (
            format!("in {what}: {error}"),
            "fix the formula; the README's \"Model files\" section lists what formulas may hold"
                .to_string(),
        );
    };
    let is = |list: &[String]| list.iter().any(|c| c == name);
    let parameter = names.index.contains_key(name.as_str());
    let (message, help) = if name == "t" && names.reads.rank() < Reads::Coordinates.rank() {
        (
            format!("{what} uses the time `t`"),
            format!(
                "this value is a constant, fixed before the run starts (at t = 0): use numbers \
                 and parameters only; the time `t` may appear in {TIME_USES}"
            ),
        )
    } else if is(names.coordinates) && names.reads.rank() < Reads::Coordinates.rank() {
        (
            format!("{what} uses the coordinate `{name}`"),
            "this value is a constant, fixed before the run: use numbers and parameters only"
                .to_string(),
        )
    } else if is(names.velocities) && names.reads.rank() < Reads::State.rank() {
        let help = if names.reads == Reads::Coordinates {
            "a constraint h(q) depends on the coordinates only, not on velocities".to_string()
        } else if names.reads == Reads::Drawing {
            "a drawing shows positions: its points are formulas of the coordinates, the \
             parameters and the time t, not of velocities"
                .to_string()
        } else {
            "this value is a constant, fixed before the run: use numbers and parameters only"
                .to_string()
        };
        (format!("{what} uses the velocity `{name}`"), help)
    } else if parameter && names.reads == Reads::ParameterSlots {
        unreachable!("parameters resolve among parameters")
    } else {
        let mut known: Vec<&str> = Vec::new();
        if names.reads.rank() >= Reads::Coordinates.rank() {
            known.extend(names.coordinates.iter().map(String::as_str));
        }
        if names.reads == Reads::State {
            known.extend(names.velocities.iter().map(String::as_str));
        }
        known.extend(names.parameters.iter().map(|(p, _)| p.as_str()));
        let hint = did_you_mean(name, known.iter().copied().chain(["pi"]));
        let available = if known.is_empty() {
            "no names are defined here except pi".to_string()
        } else {
            format!("the names here are {} and pi", list(&known))
        };
        (
            format!("unknown name `{name}` in {what}"),
            format!("{hint}{available}; define new constants under [parameters]"),
        )
    };
    (message, help)
}

impl Reads {
    fn rank(self) -> u8 {
        match self {
            Reads::ParameterSlots | Reads::Constants => 0,
            Reads::Coordinates | Reads::Drawing => 1,
            Reads::State => 2,
        }
    }
}

/// The byte offset of the 1-based `(line, column)` (column in characters) in `text`.
fn offset_in(text: &str, (line, column): (usize, usize)) -> usize {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let rest = &text[line_start.min(text.len())..];
    line_start
        + rest
            .char_indices()
            .nth(column.saturating_sub(1))
            .map_or(rest.len(), |(i, _)| i)
}

fn not_finite_help(value: f64) -> String {
    if value.is_nan() {
        "the result is not a number (NaN): look for 0/0, sqrt or ln of a negative number, or \
         asin/acos outside [-1, 1]"
            .to_string()
    } else {
        "the result is infinite: look for a division by zero or an overflow".to_string()
    }
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

fn last(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

fn list<S: AsRef<str>>(items: &[S]) -> String {
    items
        .iter()
        .map(|s| format!("`{}`", s.as_ref()))
        .collect::<Vec<_>>()
        .join(", ")
}

fn kind(value: &DeValue<'_>) -> &'static str {
    match value {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a number",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date",
        DeValue::Array(_) => "a list",
        DeValue::Table(_) => "a table",
    }
}
