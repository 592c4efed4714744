//! Reading `[drawing]`: the points' formulas, the shapes between them, every name checked.

use std::collections::HashMap;

use toml::de::DeValue;

use super::{join, kind, list, Cx, Item, Names, Table};
use crate::drawing::{Drawing, Point, Shape};
use crate::error::did_you_mean;
use crate::expr::{Expression, Scope};
use crate::ModelError;

/// The keys of `[drawing]`.
const DRAWING_KEYS: [&str; 6] = [
    "points",
    "segments",
    "polylines",
    "circles",
    "surfaces",
    "trace",
];

/// The keys of a surface.
const SURFACE_KEYS: [&str; 5] = ["constraint", "through", "curve", "s", "samples"];

/// The most points a surface's curve may be sampled at.
const MAX_SAMPLES: i64 = 1000;

/// The samples of a surface's curve when `samples` is not given.
const DEFAULT_SAMPLES: usize = 64;

/// Where the docs describe `[drawing]`, for messages.
const SEE: &str = "see docs/drawing.md";

/// The names a curve's formulas read: the drawing's, and the curve's parameter `s` (slot
/// `2n + 1`), which hides a parameter of that name.
struct CurveNames<'a, 'n> {
    names: &'a Names<'n>,
}

impl Scope for CurveNames<'_, '_> {
    fn resolve(&self, name: &str) -> Option<usize> {
        if name == "s" {
            return Some(self.names.time_slot() + 1);
        }
        self.names.resolve(name)
    }

    fn constant(&self, name: &str) -> Option<f64> {
        if name == "s" {
            return None;
        }
        self.names.constant(name)
    }
}

/// The drawing being read.
struct Parts {
    names: Vec<String>,
    index: HashMap<String, usize>,
    dimension: Option<usize>,
    formulas: Vec<Expression>,
    points: Vec<Point>,
}

impl<'s> Cx<'s> {
    /// `[drawing]`, if the file has one; `names` binds the coordinates, `t` and the
    /// parameters (as constants), `constraints` are the constraints' names.
    pub(super) fn drawing(
        &self,
        root: &Table<'s>,
        names: &Names<'_>,
        constants: &Names<'_>,
        constraints: &[String],
    ) -> Result<Option<Drawing>, ModelError> {
        let Some(item) = root.get("drawing") else {
            return Ok(None);
        };
        let table = self.table(
            item,
            "drawing",
            "[drawing] with points = { ball = [\"0\", \"y\"] }",
        )?;
        self.known_keys(table, "drawing", &DRAWING_KEYS)?;
        let mut parts = Parts {
            names: Vec::new(),
            index: HashMap::new(),
            dimension: None,
            formulas: Vec::new(),
            points: Vec::new(),
        };
        self.points(table, names, &mut parts)?;

        // The shapes, key by key in the file's order, each list in its order.
        let mut keys: Vec<_> = table
            .iter()
            .filter(|(k, _)| k.get_ref() != "points" && k.get_ref() != "trace")
            .collect();
        keys.sort_by_key(|(k, _)| k.span().start);
        let mut shapes = Vec::new();
        for (key, value) in keys {
            let key = key.get_ref().as_ref();
            let path = join("drawing", key);
            let entries = self.list(value, &path, shape_example(key))?;
            for (i, entry) in entries.iter().enumerate() {
                let path = format!("{path}[{i}]");
                let shape = match key {
                    "segments" => self.segment(entry, &path, &parts)?,
                    "polylines" => self.polyline(entry, &path, &parts)?,
                    "circles" => self.circle(entry, &path, &parts, constants)?,
                    _ => self.surface(entry, &path, &mut parts, names, constants, constraints)?,
                };
                shapes.push(shape);
            }
        }
        let trace = match table.get("trace") {
            Some(item) => Some(self.point_ref(item, "drawing.trace", &parts)?),
            None => None,
        };
        let Some(dimension) = parts.dimension else {
            return Err(self.at(
                item.span().start,
                "drawing",
                "the drawing has no points",
                format!(
                    "add points = {{ ball = [\"x\", \"y\"] }}, each point a pair (or triple) of \
                     formulas of the coordinates, the parameters and t; {SEE}"
                ),
            ));
        };
        Ok(Some(Drawing::new(
            parts.names,
            dimension,
            parts.formulas,
            parts.points,
            shapes,
            trace,
            names.coordinates.len(),
        )))
    }

    /// `points = { name = ["x", "y"], … }`.
    fn points(
        &self,
        table: &Table<'s>,
        names: &Names<'_>,
        parts: &mut Parts,
    ) -> Result<(), ModelError> {
        let Some(item) = table.get("points") else {
            return Err(self.missing(
                "drawing.points",
                "the drawing has no points",
                format!(
                    "add points = {{ ball = [\"x\", \"y\"] }}, each point a pair (or triple) of \
                     formulas of the coordinates, the parameters and t; {SEE}"
                ),
            ));
        };
        let points = self.table(
            item,
            "drawing.points",
            "points = { ball = [\"x\", \"y\"], pivot = [0, 0] }",
        )?;
        let mut entries: Vec<_> = points.iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        let mut first: Option<String> = None;
        for (key, value) in entries {
            let name = key.get_ref().as_ref();
            let path = join("drawing.points", name);
            let identifier = name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !identifier {
                return Err(self.at(
                    key.span().start,
                    &path,
                    format!("`{name}` cannot name a point"),
                    "point names start with a letter or _ and hold only ASCII letters, digits \
                     and _",
                ));
            }
            let DeValue::Array(array) = value.get_ref() else {
                return Err(self.at(
                    value.span().start,
                    &path,
                    format!(
                        "expected a pair or a triple of formulas, found {}",
                        kind(value.get_ref())
                    ),
                    format!("write {name} = [\"x\", \"y\"] (or [\"x\", \"y\", \"z\"])"),
                ));
            };
            if !(2..=3).contains(&array.len()) {
                return Err(self.at(
                    value.span().start,
                    &path,
                    format!(
                        "point `{name}` has {} formula{}",
                        array.len(),
                        if array.len() == 1 { "" } else { "s" }
                    ),
                    format!(
                        "a point is a pair [\"x\", \"y\"] or a triple [\"x\", \"y\", \"z\"] of \
                         formulas; {SEE}"
                    ),
                ));
            }
            match (parts.dimension, &first) {
                (Some(d), Some(other)) if d != array.len() => {
                    return Err(self.at(
                        value.span().start,
                        &path,
                        format!(
                            "point `{name}` has {} formulas, but point `{other}` has {d}",
                            array.len()
                        ),
                        "a drawing's points are all pairs (x, y) or all triples (x, y, z)",
                    ));
                }
                _ => {
                    parts.dimension = Some(array.len());
                    first.get_or_insert_with(|| name.to_string());
                }
            }
            let start = parts.formulas.len();
            for (j, entry) in array.iter().enumerate() {
                let key = format!("{path}[{j}]");
                let formula = self.formula(entry, &key)?;
                let what = format!("the drawing's point `{name}`");
                parts.formulas.push(self.compile(&formula, names, &what)?);
            }
            parts.index.insert(name.to_string(), parts.names.len());
            parts.names.push(name.to_string());
            parts.points.push(Point {
                first: start,
                s: 0.0,
            });
        }
        Ok(())
    }

    /// A list, or an error saying how to write `example`.
    fn list<'t>(
        &self,
        item: &'t Item<'s>,
        key: &str,
        example: &str,
    ) -> Result<&'t [Item<'s>], ModelError> {
        match item.get_ref() {
            DeValue::Array(array) => Ok(array),
            other => Err(self.at(
                item.span().start,
                key,
                format!("expected a list, found {}", kind(other)),
                format!("write {example}; {SEE}"),
            )),
        }
    }

    /// The index of the point a string names.
    fn point_ref(&self, item: &Item<'s>, key: &str, parts: &Parts) -> Result<usize, ModelError> {
        let name = self.string(item, key)?;
        parts.index.get(name).copied().ok_or_else(|| {
            let hint = did_you_mean(name, parts.index.keys().map(String::as_str));
            let defined: Vec<&str> = parts
                .names
                .iter()
                .filter(|n| !n.contains('#'))
                .map(String::as_str)
                .collect();
            self.at(
                item.span().start,
                key,
                format!("unknown point `{name}`"),
                format!(
                    "{hint}the drawing's points are {}; define it under points",
                    list(&defined)
                ),
            )
        })
    }

    /// A list of point names, at least `least` long.
    fn point_list(
        &self,
        item: &Item<'s>,
        key: &str,
        parts: &Parts,
        least: usize,
    ) -> Result<Vec<usize>, ModelError> {
        let array = self.list(item, key, "[\"a\", \"b\"], names of points")?;
        if array.len() < least {
            return Err(self.at(
                item.span().start,
                key,
                format!("{} point{} given", array.len(), plural(array.len())),
                format!("give at least {least} points"),
            ));
        }
        array
            .iter()
            .enumerate()
            .map(|(i, p)| self.point_ref(p, &format!("{key}[{i}]"), parts))
            .collect()
    }

    /// `["a", "b"]`.
    fn segment(&self, item: &Item<'s>, key: &str, parts: &Parts) -> Result<Shape, ModelError> {
        let points = self.point_list(item, key, parts, 2)?;
        if points.len() != 2 {
            return Err(self.at(
                item.span().start,
                key,
                format!("a segment joins 2 points, not {}", points.len()),
                "write [\"a\", \"b\"], or list more points under polylines",
            ));
        }
        Ok(Shape::Segment {
            from: points[0],
            to: points[1],
        })
    }

    /// `{ through = ["a", "b", "c"], closed = true }`.
    fn polyline(&self, item: &Item<'s>, key: &str, parts: &Parts) -> Result<Shape, ModelError> {
        let table = self.table(
            item,
            key,
            "{ through = [\"a\", \"b\", \"c\"], closed = true }",
        )?;
        self.known_keys(table, key, &["through", "closed"])?;
        let through = table.get("through").ok_or_else(|| {
            self.missing(
                &join(key, "through"),
                "the polyline has no points",
                "add through = [\"a\", \"b\", \"c\"], the names of its points",
            )
        })?;
        let points = self.point_list(through, &join(key, "through"), parts, 2)?;
        let closed = match table.get("closed") {
            None => false,
            Some(item) => match item.get_ref() {
                DeValue::Boolean(b) => *b,
                other => {
                    return Err(self.at(
                        item.span().start,
                        &join(key, "closed"),
                        format!("expected true or false, found {}", kind(other)),
                        "write closed = true to join the last point to the first",
                    ))
                }
            },
        };
        Ok(Shape::Polyline { points, closed })
    }

    /// `{ at = "ball", radius = "r" }`.
    fn circle(
        &self,
        item: &Item<'s>,
        key: &str,
        parts: &Parts,
        constants: &Names<'_>,
    ) -> Result<Shape, ModelError> {
        let table = self.table(item, key, "{ at = \"ball\", radius = 0.1 }")?;
        self.known_keys(table, key, &["at", "radius"])?;
        let at = table.get("at").ok_or_else(|| {
            self.missing(
                &join(key, "at"),
                "the circle has no centre",
                "add at = \"…\", the name of its centre point",
            )
        })?;
        let center = self.point_ref(at, &join(key, "at"), parts)?;
        let radius_key = join(key, "radius");
        let radius_item = table.get("radius").ok_or_else(|| {
            self.missing(
                &radius_key,
                "the circle has no radius",
                "add radius = 0.1, a number or a formula of the parameters",
            )
        })?;
        let formula = self.formula(radius_item, &radius_key)?;
        let radius = self.constant(&formula, constants, "the circle's radius")?;
        if radius <= 0.0 {
            return Err(self.formula_error(
                &formula,
                None,
                format!("the circle's radius is {radius}; it must be > 0"),
                "give a positive radius, a number or a formula of the parameters".to_string(),
            ));
        }
        Ok(Shape::Circle { center, radius })
    }

    /// `{ constraint = "floor", through = ["a", "b"] }` or
    /// `{ constraint = "floor", curve = ["s", "sin(s)"], s = [-3, 3], samples = 64 }`.
    fn surface(
        &self,
        item: &Item<'s>,
        key: &str,
        parts: &mut Parts,
        names: &Names<'_>,
        constants: &Names<'_>,
        constraints: &[String],
    ) -> Result<Shape, ModelError> {
        let example = "{ constraint = \"floor\", through = [\"left\", \"right\"] }";
        let table = self.table(item, key, example)?;
        self.known_keys(table, key, &SURFACE_KEYS)?;
        let constraint_key = join(key, "constraint");
        let constraint_item = table.get("constraint").ok_or_else(|| {
            self.missing(
                &constraint_key,
                "the surface names no constraint",
                format!(
                    "add constraint = \"…\", one of {}: the surface is highlighted while it \
                     holds",
                    list(constraints)
                ),
            )
        })?;
        let name = self.string(constraint_item, &constraint_key)?;
        let Some(constraint) = constraints.iter().position(|c| c == name) else {
            let hint = did_you_mean(name, constraints.iter().map(String::as_str));
            return Err(self.at(
                constraint_item.span().start,
                &constraint_key,
                format!("unknown constraint `{name}`"),
                format!("{hint}the model's constraints are {}", list(constraints)),
            ));
        };
        match (table.get("through"), table.get("curve")) {
            (Some(through), None) => {
                for extra in ["s", "samples"] {
                    if let Some(item) = table.get(extra) {
                        return Err(self.at(
                            item.span().start,
                            &join(key, extra),
                            format!("`{extra}` belongs to a curve, and this surface has points"),
                            "remove it, or give curve = [\"s\", \"sin(s)\"] instead of through",
                        ));
                    }
                }
                let points = self.point_list(through, &join(key, "through"), parts, 2)?;
                Ok(Shape::Surface { constraint, points })
            }
            (None, Some(curve)) => {
                let points = self.curve(table, curve, key, name, parts, names, constants)?;
                Ok(Shape::Surface { constraint, points })
            }
            (Some(_), Some(curve)) => Err(self.at(
                curve.span().start,
                &join(key, "curve"),
                "the surface has both through and curve",
                "give one of them: through = [points] or curve = [formulas of s]",
            )),
            (None, None) => Err(self.missing(
                &join(key, "through"),
                format!("the surface of `{name}` has no points"),
                format!(
                    "add through = [\"a\", \"b\"] (points on h = 0), or curve = [\"s\", \
                     \"sin(s)\"] with s = [-3, 3]; {SEE}"
                ),
            )),
        }
    }

    /// A surface's curve: its formulas of `s` sampled at `samples` values evenly spaced over
    /// `s = [from, to]`, each sample a new point `<constraint>#<k>`.
    #[allow(clippy::too_many_arguments)]
    fn curve(
        &self,
        table: &Table<'s>,
        curve: &Item<'s>,
        key: &str,
        constraint: &str,
        parts: &mut Parts,
        names: &Names<'_>,
        constants: &Names<'_>,
    ) -> Result<Vec<usize>, ModelError> {
        let curve_key = join(key, "curve");
        let array = self.list(curve, &curve_key, "curve = [\"s\", \"sin(s)\"]")?;
        let dimension = parts.dimension.unwrap_or(array.len());
        if array.len() != dimension {
            return Err(self.at(
                curve.span().start,
                &curve_key,
                format!(
                    "the curve has {} formula{}, but the drawing's points have {dimension}",
                    array.len(),
                    plural(array.len())
                ),
                "give the curve as many formulas (of s) as the points have",
            ));
        }
        let s_key = join(key, "s");
        let s_item = table.get("s").ok_or_else(|| {
            self.missing(
                &s_key,
                "the curve has no range",
                "add s = [-3, 3], the range of the curve's parameter s",
            )
        })?;
        let range = self.list(s_item, &s_key, "s = [-3, 3]")?;
        let [from, to] = range else {
            return Err(self.at(
                s_item.span().start,
                &s_key,
                format!("expected [from, to], found {} values", range.len()),
                "write s = [-3, 3], the range of the curve's parameter s",
            ));
        };
        let from = self.formula(from, &format!("{s_key}[0]"))?;
        let from = self.constant(&from, constants, "the curve's first s")?;
        let to = self.formula(to, &format!("{s_key}[1]"))?;
        let to = self.constant(&to, constants, "the curve's last s")?;
        let samples = match table.get("samples") {
            None => DEFAULT_SAMPLES,
            Some(item) => match item.get_ref() {
                DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                    Ok(v) if (2..=MAX_SAMPLES).contains(&v) => v as usize,
                    _ => return Err(self.samples_error(item, key)),
                },
                _ => return Err(self.samples_error(item, key)),
            },
        };
        let start = parts.formulas.len();
        let scope = CurveNames { names };
        for (j, entry) in array.iter().enumerate() {
            let formula = self.formula(entry, &format!("{curve_key}[{j}]"))?;
            let what = format!("the curve of `{constraint}`");
            // Compiled against the names with `s`, errors described as the drawing's.
            parts
                .formulas
                .push(self.compile_in(&formula, &scope, names, &what)?);
        }
        parts.dimension = Some(dimension);
        let mut points = Vec::with_capacity(samples);
        for k in 0..samples {
            let s = from + (to - from) * k as f64 / (samples - 1) as f64;
            points.push(parts.names.len());
            parts.names.push(format!("{constraint}#{k}"));
            parts.points.push(Point { first: start, s });
        }
        Ok(points)
    }

    fn samples_error(&self, item: &Item<'s>, key: &str) -> ModelError {
        self.at(
            item.span().start,
            &join(key, "samples"),
            "samples must be a whole number from 2 to 1000",
            "write e.g. samples = 64, the points the curve is drawn through",
        )
    }
}

/// The example of a shape list, for messages.
fn shape_example(key: &str) -> &'static str {
    match key {
        "segments" => "segments = [[\"a\", \"b\"]]",
        "polylines" => "polylines = [{ through = [\"a\", \"b\", \"c\"], closed = true }]",
        "circles" => "circles = [{ at = \"ball\", radius = 0.1 }]",
        _ => "surfaces = [{ constraint = \"floor\", through = [\"left\", \"right\"] }]",
    }
}

fn plural(count: usize) -> &'static str {
    if count == 1 {
        ""
    } else {
        "s"
    }
}
