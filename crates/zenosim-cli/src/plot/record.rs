//! What the plots read of `summary.json`: the names, the events, the Zeno points, the time span
//! and the constraints' formulas.

use std::collections::HashMap;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use anyhow::{anyhow, Context};
use serde::{Deserialize, Serialize};
use zenosim_model::expr::{Bindings, Expression};

use super::trajectory_file::quote;

/// A run's record, as `summary.json` holds it (the fields the plots use).
#[derive(Debug, Deserialize)]
pub struct Record {
    /// The model's name.
    pub model: String,
    /// The model's description, if it has one.
    #[serde(default)]
    pub description: Option<String>,
    /// `finished`, `zeno_stalled` or `failed`.
    pub status: String,
    /// What happened, in words.
    #[serde(default)]
    pub message: Option<String>,
    /// The coordinates' names.
    pub coordinates: Vec<String>,
    /// The velocities' names.
    pub velocities: Vec<String>,
    /// The constraints' names.
    pub constraints: Vec<String>,
    /// The names of the constraints with friction, each a column `f_<name>` of the trajectory
    /// (absent where there are none, and from summaries of older versions).
    #[serde(default)]
    pub friction: Vec<String>,
    /// Those of them whose contact is in space: a second column `f2_<name>` each, after its
    /// `f_<name>` (absent where there are none).
    #[serde(default)]
    pub friction_in_space: Vec<String>,
    /// The constraints' formulas `h`, by name (absent from summaries of older versions).
    #[serde(default)]
    pub h: HashMap<String, String>,
    /// The constraints' restitutions, by name.
    #[serde(default)]
    pub restitutions: HashMap<String, Option<f64>>,
    /// The parameters, by name.
    #[serde(default)]
    pub parameters: HashMap<String, Option<f64>>,
    /// The run's settings.
    pub settings: SettingsRecord,
    /// Where the run ended.
    #[serde(rename = "final")]
    pub final_: FinalRecord,
    /// The energy balance of the whole run (absent from summaries before schema 3).
    #[serde(default)]
    pub energy_balance: Option<EnergyBalanceRecord>,
    /// The Zeno points.
    pub zeno: Vec<ZenoRecord>,
    /// Every event, in time order.
    pub events: Vec<EventRecord>,
    /// The hybrid time domain.
    pub intervals: Vec<IntervalRecord>,
    /// The trajectory file's size.
    pub trajectory: TrajectoryRecord,
}

/// The settings the plots use.
#[derive(Debug, Deserialize)]
pub struct SettingsRecord {
    /// The stop time.
    pub t_end: f64,
}

/// Where the run ended.
#[derive(Debug, Deserialize)]
pub struct FinalRecord {
    /// When.
    pub t: Option<f64>,
}

/// The energy balance of a run, `E(end) − E(0) = work_forces + work_drive + work_constraints
/// + work_friction − impact_loss` to the integration tolerance; `None` stands for a number
/// that is not finite (`null`).
#[derive(Debug, Deserialize, Serialize)]
pub struct EnergyBalanceRecord {
    /// `E(0)`.
    pub energy_start: Option<f64>,
    /// `E` at the end.
    pub energy_end: Option<f64>,
    /// The generalized forces' work.
    pub work_forces: Option<f64>,
    /// The work of the Lagrangian's explicit time dependence.
    pub work_drive: Option<f64>,
    /// The work of the constraints on surfaces that move.
    pub work_constraints: Option<f64>,
    /// The work of friction at slipping contacts: only in a model with friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub work_friction: Option<f64>,
    /// The energy taken out by impacts and Zeno switches.
    pub impact_loss: Option<f64>,
    /// What the terms leave unexplained.
    pub residual: Option<f64>,
}

/// A Zeno point.
#[derive(Debug, Deserialize)]
pub struct ZenoRecord {
    /// The constraint of the accumulation's last impact.
    pub constraint: String,
    /// Every constraint of the accumulation (schema 2; empty in older summaries).
    #[serde(default)]
    pub constraints: Vec<String>,
    /// `genuine` or `chattering`.
    pub kind: String,
    /// The switch to the constrained motion (or the stop, when stalled).
    pub t_switch: f64,
    /// The estimate of `τ∞`.
    pub t_zeno: Option<f64>,
    /// The impacts of the sequence.
    pub impacts: u64,
    /// The ratio of successive flight times.
    pub ratio: Option<f64>,
    /// Its event's index in `events` (schema 4), whose `after` is its state.
    #[serde(default)]
    pub event: Option<usize>,
    /// The state after `R∞` (the last state, when stalled): written before schema 4, and in
    /// schema 4 for a point without an event; filled from its event on reading.
    #[serde(default)]
    point: Option<StateRecord>,
}

impl ZenoRecord {
    /// The state after `R∞` (the last state, when stalled).
    pub fn point(&self) -> &StateRecord {
        static NONE: StateRecord = StateRecord {
            q: Vec::new(),
            q_dot: Vec::new(),
        };
        self.point.as_ref().unwrap_or(&NONE)
    }
}

/// An event.
#[derive(Debug, Deserialize)]
pub struct EventRecord {
    /// `impact`, `zeno`, `liftoff`, and with friction `stick` or `slip`.
    pub kind: String,
    /// When.
    pub t: f64,
    /// The constraint involved.
    pub constraint: String,
    /// Every constraint involved (schema 2; empty in older summaries).
    #[serde(default)]
    pub contacts: Vec<String>,
    /// For an impact, the impulse on each of `contacts` (schema 2); else empty.
    #[serde(default)]
    pub impulses: Vec<Option<f64>>,
    /// For an impact on contacts with friction, the tangential impulse on each of `contacts`;
    /// else empty.
    #[serde(default)]
    pub tangential_impulses: Vec<Option<f64>>,
    /// The state just before.
    pub before: StateRecord,
    /// The state just after: without `q` where it is `before`'s (schema 4).
    #[serde(default)]
    pub after: Option<AfterRecord>,
}

/// The state just after an event.
#[derive(Debug, Deserialize)]
pub struct AfterRecord {
    /// The configuration, if it changed (always, before schema 4).
    #[serde(default)]
    pub q: Option<Vec<Option<f64>>>,
    /// The velocities.
    pub q_dot: Vec<Option<f64>>,
}

/// A state; `null` stands for a non-finite number.
#[derive(Clone, Debug, Deserialize)]
pub struct StateRecord {
    /// The configuration.
    pub q: Vec<Option<f64>>,
    /// The velocities.
    pub q_dot: Vec<Option<f64>>,
}

impl StateRecord {
    /// Value `column` of `(q, q̇)`, `NaN` if absent.
    pub fn value(&self, column: usize) -> f64 {
        let n = self.q.len();
        let value = if column < n {
            self.q.get(column)
        } else {
            self.q_dot.get(column - n)
        };
        value.copied().flatten().unwrap_or(f64::NAN)
    }
}

/// An interval of the hybrid time domain.
#[derive(Debug, Deserialize)]
pub struct IntervalRecord {
    /// Its start.
    pub start: Option<f64>,
}

/// The trajectory file.
#[derive(Debug, Deserialize)]
pub struct TrajectoryRecord {
    /// Its data rows.
    pub rows: u64,
}

impl Record {
    /// The trajectory's columns of tangential force, `(constraint, component)` in order: each
    /// constraint with friction's first component, and a contact in space's second after it
    /// ([`crate::trajectory::force_column`]).
    pub fn force_columns(&self) -> Vec<(&str, usize)> {
        self.friction
            .iter()
            .flat_map(|name| {
                let two = self.friction_in_space.contains(name);
                (0..1 + usize::from(two)).map(move |k| (name.as_str(), k))
            })
            .collect()
    }

    /// Reads `path`; errors name the file and the line and column.
    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let display = path.display();
        let file = File::open(path).with_context(|| {
            format!(
                "cannot read {display}: give a directory that `zenosim run` wrote (it writes \
                 summary.json last, once the run is complete)"
            )
        })?;
        let mut record: Self = serde_json::from_reader(BufReader::new(file)).map_err(|error| {
            let text = error.to_string();
            let message = text.rfind(" at line ").map_or(&*text, |end| &text[..end]);
            // serde quotes a string of the wrong type whole: a name of a megabyte.
            anyhow!(
                "{display}:{}:{}: {}; is it a summary.json written by `zenosim run`?",
                error.line(),
                error.column(),
                quote(message)
            )
        })?;
        record.check().map_err(|problem| {
            anyhow!("{display}: {problem}; run the model again to write a new one")
        })?;
        record.resolve_points().map_err(|problem| {
            anyhow!("{display}: {problem}; run the model again to write a new one")
        })?;
        Ok(record)
    }

    /// Each Zeno point's state: its own (`point`), or its event's `after` (schema 4).
    fn resolve_points(&mut self) -> Result<(), String> {
        for (k, z) in self.zeno.iter_mut().enumerate() {
            if z.point.is_some() {
                continue;
            }
            let event = z.event.and_then(|i| self.events.get(i));
            let Some((event, after)) = event.and_then(|e| Some((e, e.after.as_ref()?))) else {
                return Err(format!(
                    "Zeno point {} has no state: neither a point nor an event with one",
                    k + 1
                ));
            };
            z.point = Some(StateRecord {
                q: after.q.clone().unwrap_or_else(|| event.before.q.clone()),
                q_dot: after.q_dot.clone(),
            });
        }
        Ok(())
    }

    /// The consistency the plots rely on.
    fn check(&self) -> Result<(), String> {
        let n = self.coordinates.len();
        if n == 0 || self.velocities.len() != n {
            return Err(format!(
                "{n} coordinates and {} velocities: expected as many of each, at least one",
                self.velocities.len()
            ));
        }
        if let Some(name) = self.friction.iter().find(|f| !self.constraints.contains(f)) {
            return Err(format!(
                "`friction` lists {}, which is not one of the constraints",
                quote(name)
            ));
        }
        if let Some(name) = self
            .friction_in_space
            .iter()
            .find(|f| !self.friction.contains(f))
        {
            return Err(format!(
                "`friction_in_space` lists {}, which is not one of those with friction",
                quote(name)
            ));
        }
        if !self.settings.t_end.is_finite() {
            return Err("settings.t_end is not a number".to_string());
        }
        let t = self.events.iter().map(|e| e.t);
        let times: Vec<f64> = t.chain(self.zeno.iter().map(|z| z.t_switch)).collect();
        if let Some(bad) = times.iter().find(|t| !t.is_finite()) {
            return Err(format!("an event time is {bad}"));
        }
        if self.events.windows(2).any(|w| w[1].t < w[0].t) {
            return Err("the events are not in time order".to_string());
        }
        // Marks far outside the time axis would overflow the plots' pixel coordinates.
        if let Some(bad) = times.iter().find(|&&t| !self.within_span(t)) {
            let (start, end) = self.time_span();
            return Err(format!(
                "an event at t = {bad} is outside the run, from t = {start} to {end}"
            ));
        }
        Ok(())
    }

    /// Whether `t` lies in the plotted [`Record::time_span`], to a billionth of its size: every
    /// time of the run's files does.
    pub fn within_span(&self, t: f64) -> bool {
        let (start, end) = self.time_span();
        let slack = 1e-9 * (end - start).max(start.abs()).max(end.abs());
        t >= start - slack && t <= end + slack
    }

    /// The plotted span of time: from the start to the stop time (or the end, if later).
    pub fn time_span(&self) -> (f64, f64) {
        let start = self
            .intervals
            .first()
            .and_then(|i| i.start)
            .filter(|t| t.is_finite())
            .unwrap_or(0.0);
        let end = self.final_.t.filter(|t| t.is_finite()).unwrap_or(start);
        (start, self.settings.t_end.max(end))
    }

    /// The coordinates and velocities: the columns of `(q, q̇)`.
    pub fn columns(&self) -> impl Iterator<Item = &String> {
        self.coordinates.iter().chain(&self.velocities)
    }

    /// The times of the events of `kind`.
    /// The impact times of each constraint that was reached, in the constraints' order, with
    /// the constraint's name; constraints never reached are left out.
    pub fn impacts_by_constraint(&self) -> Vec<(&str, Vec<f64>)> {
        let mut by: Vec<(&str, Vec<f64>)> = Vec::new();
        for e in self.events.iter().filter(|e| e.kind == "impact") {
            match by.iter_mut().find(|(name, _)| *name == e.constraint) {
                Some((_, times)) => times.push(e.t),
                None => by.push((&e.constraint, vec![e.t])),
            }
        }
        let order = |name: &str| self.constraints.iter().position(|c| c == name);
        by.sort_by_key(|(name, _)| order(name));
        by
    }

    pub fn times(&self, kind: &str) -> Vec<f64> {
        self.events
            .iter()
            .filter(|e| e.kind == kind)
            .map(|e| e.t)
            .collect()
    }

    /// Whether the run stopped at its last Zeno point (`--zeno off`) rather than passing it.
    pub fn stalled(&self) -> bool {
        self.status == "zeno_stalled"
    }

    /// Constraint `name`'s function `h(q)`, compiled with the run's parameters; `None` when the
    /// summary does not hold it (or it does not compile).
    pub fn constraint_function(&self, name: &str) -> Option<Expression> {
        let source = self.h.get(name)?;
        let slots = self.coordinates.iter().enumerate().map(|(i, c)| (c, i));
        let constants = self
            .parameters
            .iter()
            .filter_map(|(p, v)| v.map(|v| (p.clone(), v)));
        Expression::parse(source, &Bindings::from_parts(slots, constants)).ok()
    }
}
