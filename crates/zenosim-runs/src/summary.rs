//! `summary.json`: the record of a run, as serde structures with exactly its keys and order
//! (docs/output.md). Non-finite numbers (which JSON cannot hold) are written as `null`, as
//! serde_json does; so is `max_step` when there is none.

use serde::ser::{Serialize, SerializeMap, Serializer};
use serde::Serialize as DeriveSerialize;
use zenosim::{
    ActiveSet, Completion, Derived, Event, Execution, Grips, HybridInterval, HybridLagrangian,
    Method, Mode, Outcome, SimulationOptions, State, ZenoPoint, ZenoStrategy,
};
use zenosim_model::ModelFile;

/// The version of `summary.json`'s layout, documented in docs/output.md. 2: events list
/// their `contacts` and `impulses`, Zeno points their `constraints`. 3: `energy_balance`.
/// 4: no state written twice: a Zeno point names its event (`event`) instead of repeating its
/// state (`point` only for a point with no event, a stall), and an event's `after` leaves out
/// `q` where it is `before`'s.
pub const SCHEMA_VERSION: u32 = 4;

/// The whole summary.
#[derive(DeriveSerialize)]
pub struct Summary<'a> {
    /// The version of this layout ([`SCHEMA_VERSION`]; docs/output.md).
    pub schema_version: u32,
    /// The model's name.
    pub model: &'a str,
    /// Its description, if any.
    pub description: Option<&'a str>,
    /// [`status`]'s word for the outcome.
    pub status: &'static str,
    /// What happened, in a sentence.
    pub message: String,
    /// The coordinates' names.
    pub coordinates: Vec<String>,
    /// The velocities' names.
    pub velocities: Vec<String>,
    /// The constraints' names.
    pub constraints: Vec<&'a str>,
    /// The names of the constraints with friction ([`zenosim::Constraint::has_friction`]), in
    /// the model's order; left out where there are none (`trajectory.csv` has a column
    /// `f_<name>` for each).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub friction: Vec<&'a str>,
    /// Those of them whose contact is in space (two slip components, docs/friction.md), in
    /// the same order; left out where there are none (`trajectory.csv` has a second column
    /// `f2_<name>` for each, after its `f_<name>`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub friction_in_space: Vec<&'a str>,
    /// The constraints' restitutions, by name.
    pub restitutions: Pairs<'a>,
    /// The constraints' functions `h`, as the model file writes them, by name (the plots
    /// draw `h = 0` from them and the parameters).
    pub h: Pairs<'a, &'a str>,
    /// The parameters after `--set`, in the file's order.
    pub parameters: Pairs<'a>,
    /// The initial state after `--set`.
    pub initial: StateJson<'a>,
    /// The settings the run used (the file's, overridden by the command line).
    pub settings: SettingsJson,
    /// Where the run ended.
    #[serde(rename = "final")]
    pub final_: FinalJson<'a>,
    /// The energy balance from the start to the end.
    pub energy_balance: EnergyBalanceJson,
    /// The Zeno points reached.
    pub zeno: Lazy<'a, ZenoPoint, ZenoJson<'a>>,
    /// Every event.
    pub events: Lazy<'a, Event, EventJson<'a>>,
    /// The hybrid time domain.
    pub intervals: Lazy<'a, HybridInterval, IntervalJson<'a>>,
    /// Work counters.
    pub stats: StatsJson,
    /// The trajectory file and its number of data rows.
    pub trajectory: TrajectoryJson,
    /// Where the output cap (`--max-output`) cut the lists above: how many Zeno points, events
    /// and intervals the run had (the lists hold the first of each). Left out where nothing
    /// was cut.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub truncated: Option<TruncatedJson>,
}

/// How many items the lists cut by the output cap had ([`Summary::truncated`]).
#[derive(DeriveSerialize, Clone, Copy, Debug)]
pub struct TruncatedJson {
    /// The Zeno points.
    pub zeno: usize,
    /// The events.
    pub events: usize,
    /// The intervals of the hybrid time domain.
    pub intervals: usize,
}

/// A sequence serialised item by item as it is written, never held whole (a run may have
/// 100 000 events).
pub struct Lazy<'a, T, U> {
    items: &'a [T],
    map: Box<dyn Fn(usize, &'a T) -> U + 'a>,
    /// How many of the items are written (all unless [`Lazy::keep`] cut them).
    kept: usize,
}

impl<'a, T, U> Lazy<'a, T, U> {
    /// `items`, each serialised as `map` makes it.
    pub fn new(items: &'a [T], map: impl Fn(&'a T) -> U + 'a) -> Self {
        Self {
            items,
            map: Box::new(move |_, item| map(item)),
            kept: items.len(),
        }
    }

    /// `items`, each serialised as `map` makes it from its index and itself.
    pub fn indexed(items: &'a [T], map: impl Fn(usize, &'a T) -> U + 'a) -> Self {
        Self {
            items,
            map: Box::new(map),
            kept: items.len(),
        }
    }
}

impl<T, U> Lazy<'_, T, U> {
    /// How many items there are.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Writes only the first `count` items (all of them where there are fewer).
    pub fn keep(&mut self, count: usize) {
        self.kept = count.min(self.items.len());
    }

    /// How many items are written.
    pub fn kept(&self) -> usize {
        self.kept
    }
}

impl<'a, T, U> Lazy<'a, T, U> {
    /// Every item, mapped.
    pub fn collect(self) -> Vec<U> {
        let map = &self.map;
        self.items[..self.kept]
            .iter()
            .enumerate()
            .map(|(k, item)| map(k, item))
            .collect()
    }
}

impl<T, U: Serialize> Serialize for Lazy<'_, T, U> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let map = &self.map;
        serializer.collect_seq(
            self.items[..self.kept]
                .iter()
                .enumerate()
                .map(|(k, item)| map(k, item)),
        )
    }
}

/// Name → value pairs, serialised as a JSON object in their order.
pub struct Pairs<'a, V = f64>(pub Vec<(&'a str, V)>);

impl<'a> Pairs<'a> {
    /// The parameters of `file` (after `--set`), in the file's order.
    pub fn parameters(file: &'a ModelFile) -> Self {
        Self(
            file.parameters
                .iter()
                .map(|(n, v)| (n.as_str(), *v))
                .collect(),
        )
    }
}

impl<V: Serialize> Serialize for Pairs<'_, V> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, value) in &self.0 {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

/// A state `(q, q̇)`.
#[derive(DeriveSerialize)]
pub struct StateJson<'a> {
    /// The coordinates.
    pub q: &'a [f64],
    /// The velocities.
    pub q_dot: &'a [f64],
}

impl<'a> From<&'a State> for StateJson<'a> {
    fn from(state: &'a State) -> Self {
        Self {
            q: &state.q,
            q_dot: &state.q_dot,
        }
    }
}

/// The Zeno strategy: `"auto"`, `"off"` or `{"epsilon": ε}`.
#[derive(DeriveSerialize)]
#[serde(untagged)]
pub enum ZenoSetting {
    /// `"auto"` or `"off"`.
    Name(&'static str),
    /// The paper's rule with its threshold.
    Epsilon {
        /// The threshold ε.
        epsilon: f64,
    },
}

impl From<ZenoStrategy> for ZenoSetting {
    fn from(zeno: ZenoStrategy) -> Self {
        match zeno {
            ZenoStrategy::Auto => Self::Name("auto"),
            ZenoStrategy::Off => Self::Name("off"),
            ZenoStrategy::Epsilon(epsilon) => Self::Epsilon { epsilon },
        }
    }
}

/// The run's settings.
#[derive(DeriveSerialize)]
pub struct SettingsJson {
    /// The stop time.
    pub t_end: f64,
    /// The relative tolerance.
    pub rtol: f64,
    /// The absolute tolerance.
    pub atol: f64,
    /// How Zeno points are passed.
    pub zeno: ZenoSetting,
    /// The sampling interval, or `null` for every step.
    pub dt: Option<f64>,
    /// The Runge–Kutta pair ([`method_name`]).
    pub method: &'static str,
    /// `projection` or `model_map`: how a Zeno point's state is completed (`R∞`).
    pub completion: &'static str,
    /// The largest step, or `null` for none.
    pub max_step: Option<f64>,
    /// The most events before the run fails.
    pub max_events: u64,
    /// The most accepted steps before the run fails.
    pub max_steps: u64,
}

impl From<&SimulationOptions> for SettingsJson {
    fn from(o: &SimulationOptions) -> Self {
        Self {
            t_end: o.t_end,
            rtol: o.tolerances.rtol,
            atol: o.tolerances.atol,
            zeno: o.zeno.into(),
            dt: match o.output {
                zenosim::OutputGrid::Steps => None,
                zenosim::OutputGrid::Uniform(dt) => Some(dt),
            },
            method: method_name(o.method),
            completion: match o.completion {
                Completion::Projection => "projection",
                Completion::ModelMap => "model_map",
            },
            max_step: o.max_step.is_finite().then_some(o.max_step),
            max_events: o.max_events,
            max_steps: o.max_steps,
        }
    }
}

/// The name a model file gives a Runge–Kutta pair.
pub fn method_name(method: Method) -> &'static str {
    match method {
        Method::Dop853 => "dop853",
        Method::Dopri5 => "dopri5",
    }
}

/// Where the run ended.
#[derive(DeriveSerialize)]
pub struct FinalJson<'a> {
    /// The final time.
    pub t: f64,
    /// The final mode's name (`free` or `constrained`).
    pub mode: &'static str,
    /// The constraints held at the end.
    pub active: Vec<&'a str>,
    /// The final coordinates.
    pub q: &'a [f64],
    /// The final velocities.
    pub q_dot: &'a [f64],
    /// The energy of the final state at the final time.
    pub energy: f64,
}

/// The energy balance of the run, `E(end) − E(0) = work_forces + work_drive + work_constraints
/// − impact_loss` to the integration tolerance (docs/output.md, [`zenosim::Work`]).
#[derive(Clone, Copy, Debug, DeriveSerialize)]
pub struct EnergyBalanceJson {
    /// `E(0)`, of the initial state.
    pub energy_start: f64,
    /// `E` of the final state, at the final time.
    pub energy_end: f64,
    /// `∫ Q·q̇ dt`: the generalized forces' work, the dissipation's included.
    pub work_forces: f64,
    /// `−∫ ∂L/∂t dt`: put in by the Lagrangian's explicit time dependence.
    pub work_drive: f64,
    /// The work of the constraints on surfaces that move.
    pub work_constraints: f64,
    /// The energy taken out by impacts and Zeno switches (≥ 0), their tangential impulses'
    /// included.
    pub impact_loss: f64,
    /// `∫ Σ fₜ s dt ≤ 0`: the work of friction at slipping contacts; only for a model with
    /// friction (docs/friction.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub work_friction: Option<f64>,
    /// `energy_end − energy_start − (work_forces + work_drive + work_constraints +
    /// work_friction − impact_loss)`: 0 but for the integration error.
    pub residual: f64,
}

impl EnergyBalanceJson {
    /// The balance of `run` of `model` from `initial` (at `t = 0`, where every run starts).
    /// The energies are `NaN` for a model of a dimension zenosim refuses (never simulated).
    pub fn of<L: HybridLagrangian>(model: &L, initial: &State, run: &Execution) -> Self {
        let energy = |t: f64, state: &State| {
            Derived::new(model).map_or(f64::NAN, |d| d.at_time(t).energy(&state.q, &state.q_dot))
        };
        let (energy_start, energy_end) =
            (energy(0.0, initial), energy(run.t_final, &run.final_state));
        let work = &run.work;
        Self {
            energy_start,
            energy_end,
            work_forces: work.forces,
            work_drive: work.drive,
            work_constraints: work.constraints,
            impact_loss: work.impact_loss,
            work_friction: model
                .constraints()
                .iter()
                .any(|c| c.friction.is_some())
                .then_some(work.friction),
            residual: energy_end - energy_start - work.balance(),
        }
    }
}

/// A Zeno point.
#[derive(DeriveSerialize)]
pub struct ZenoJson<'a> {
    /// The constraint of the accumulation's last impact.
    pub constraint: &'a str,
    /// Every constraint of the accumulation: `R∞` puts the state onto all of them.
    pub constraints: Vec<&'a str>,
    /// `genuine` or `chattering`.
    pub kind: &'static str,
    /// When the run switched to the constrained motion (or stalled).
    pub t_switch: f64,
    /// The estimate of τ∞.
    pub t_zeno: f64,
    /// The impacts of the accumulation.
    pub impacts: usize,
    /// The measured ratio of successive flight times, if measured.
    pub ratio: Option<f64>,
    /// The index in `events` of its `zeno` event, whose `after` is the state after R∞; `null`
    /// for a point with no event (a stall, where the run stopped).
    pub event: Option<usize>,
    /// The state reached, for a point with no event only (else its event's `after`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub point: Option<StateJson<'a>>,
}

/// The state just after an event: `q` left out where it is the state's before (an impact,
/// a lift-off).
#[derive(DeriveSerialize)]
pub struct AfterJson<'a> {
    /// The coordinates, if they changed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q: Option<&'a [f64]>,
    /// The velocities.
    pub q_dot: &'a [f64],
}

impl<'a> AfterJson<'a> {
    /// The state `after` an event from `before`.
    pub fn of(before: &State, after: &'a State) -> Self {
        let same = before.q.len() == after.q.len()
            && before
                .q
                .iter()
                .zip(&after.q)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        Self {
            q: (!same).then_some(&after.q[..]),
            q_dot: &after.q_dot,
        }
    }
}

/// An event.
#[derive(DeriveSerialize)]
pub struct EventJson<'a> {
    /// `impact`, `zeno`, `liftoff`, `stick` or `slip`.
    pub kind: &'static str,
    /// When.
    pub t: f64,
    /// The constraint reached, whose accumulation ended, or that let go.
    pub constraint: &'a str,
    /// The constraints involved (for an impact, every constraint of the impact law).
    pub contacts: Vec<&'a str>,
    /// For an impact, the impulse on each of `contacts` (pushing, ≥ 0); else empty.
    pub impulses: &'a [f64],
    /// For an impact on contacts with friction, the tangential impulse on each of `contacts`
    /// (along increasing slip; docs/friction.md); absent otherwise.
    #[serde(skip_serializing_if = "<[f64]>::is_empty")]
    pub tangential_impulses: &'a [f64],
    /// For an impact on a contact in space, the second component of each tangential impulse
    /// (the first is in `tangential_impulses`); absent otherwise.
    #[serde(skip_serializing_if = "<[f64]>::is_empty")]
    pub tangential_impulses_across: &'a [f64],
    /// The state just before.
    pub before: StateJson<'a>,
    /// The state just after (without `q` where it is `before`'s).
    pub after: AfterJson<'a>,
}

/// An interval of the hybrid time domain.
#[derive(DeriveSerialize)]
pub struct IntervalJson<'a> {
    /// Its start time.
    pub start: f64,
    /// Its end time.
    pub end: f64,
    /// Its mode's name.
    pub mode: &'static str,
    /// The constraints held.
    pub active: Vec<&'a str>,
}

/// The work counters.
#[derive(DeriveSerialize)]
pub struct StatsJson {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Evaluations of the right-hand side.
    pub rhs_evals: u64,
    /// Impacts.
    pub impacts: u64,
    /// Guard crossings found not to be events.
    pub spurious_events: u64,
    /// Events of every kind.
    pub events: usize,
}

/// The trajectory file.
#[derive(DeriveSerialize)]
pub struct TrajectoryJson {
    /// Its file name (empty where no trajectory was written).
    pub file: &'static str,
    /// Its number of data rows.
    pub rows: u64,
}

/// The word for `outcome` in `summary.json` and in a sweep's rows: `finished`, `zeno_stalled`,
/// `failed` or `interrupted`.
pub fn status(outcome: &Outcome) -> &'static str {
    crate::Status::of(outcome).word()
}

/// The summary of `run` of the model `file` with `options`.
pub struct Record<'a> {
    /// The model file (after its overrides).
    pub file: &'a ModelFile,
    /// The options the run used.
    pub options: &'a SimulationOptions,
    /// The run.
    pub run: &'a Execution,
    /// The constraints' names ([`constraint_names`]).
    pub constraint_names: &'a [String],
    /// What happened ([`crate::message::message`]).
    pub message: String,
    /// The trajectory file written beside the summary.
    pub trajectory: TrajectoryJson,
}

impl<'a> Record<'a> {
    /// The summary, borrowing from the record.
    pub fn summary(self) -> Summary<'a> {
        let names = self.constraint_names;
        let name = move |index: usize| names.get(index).map_or("?", String::as_str);
        let run = self.run;
        let file = self.file;
        let energy_balance = EnergyBalanceJson::of(&file.model, &file.initial, run);
        // The events of the Zeno points, in order: the k-th `zeno` event is the k-th point's
        // (a point with none, a stall or a run failed at its switch, is the last).
        let zeno_events: Vec<usize> = run
            .events
            .iter()
            .enumerate()
            .filter(|(_, e)| e.kind == zenosim::EventKind::Zeno)
            .map(|(k, _)| k)
            .collect();
        Summary {
            schema_version: SCHEMA_VERSION,
            model: &file.name,
            description: file.description.as_deref(),
            status: status(&run.outcome),
            message: self.message,
            coordinates: file.model.coordinate_names(),
            velocities: file.velocity_names(),
            constraints: names.iter().map(String::as_str).collect(),
            friction: friction_indices(&file.model)
                .into_iter()
                .map(name)
                .collect(),
            friction_in_space: friction_columns(&file.model)
                .into_iter()
                .filter(|&(_, component)| component == 1)
                .map(|(i, _)| name(i))
                .collect(),
            restitutions: Pairs(
                file.model
                    .constraints()
                    .iter()
                    .map(|c| (c.name.as_str(), c.restitution))
                    .collect(),
            ),
            h: Pairs(
                file.model
                    .constraints()
                    .iter()
                    .enumerate()
                    .map(|(i, c)| (c.name.as_str(), file.model.constraint_formula(i).source()))
                    .collect(),
            ),
            parameters: Pairs::parameters(file),
            initial: (&file.initial).into(),
            settings: self.options.into(),
            final_: FinalJson {
                t: run.t_final,
                mode: run.final_mode.name(),
                active: active_of(run.final_mode, names),
                q: &run.final_state.q,
                q_dot: &run.final_state.q_dot,
                energy: energy_balance.energy_end,
            },
            energy_balance,
            zeno: Lazy::indexed(&run.zeno, move |k, z| {
                let event = zeno_events.get(k).copied();
                ZenoJson {
                    constraint: name(z.constraint),
                    constraints: active_names(z.constraints, names),
                    kind: z.kind.name(),
                    t_switch: z.t_switch,
                    t_zeno: z.t_zeno,
                    impacts: z.impacts,
                    ratio: z.ratio,
                    event,
                    point: event.is_none().then(|| (&z.point).into()),
                }
            }),
            events: Lazy::new(&run.events, move |e| EventJson {
                kind: e.kind.name(),
                t: e.t,
                constraint: name(e.constraint),
                contacts: active_names(e.contacts, names),
                impulses: &e.impulses,
                tangential_impulses: &e.tangential,
                tangential_impulses_across: &e.tangential_across,
                before: (&e.before).into(),
                after: AfterJson::of(&e.before, &e.after),
            }),
            intervals: Lazy::new(&run.intervals, move |i| IntervalJson {
                start: i.start,
                end: i.end,
                mode: i.mode.name(),
                active: active_of(i.mode, names),
            }),
            stats: StatsJson {
                steps: run.stats.steps,
                rejected_steps: run.stats.rejected_steps,
                rhs_evals: run.stats.rhs_evals,
                impacts: run.stats.impacts,
                spurious_events: run.stats.spurious_events,
                events: run.events.len(),
            },
            trajectory: self.trajectory,
            truncated: None,
        }
    }
}

/// The names of `file`'s constraints, in order.
pub fn constraint_names(file: &ModelFile) -> Vec<String> {
    file.model
        .constraints()
        .iter()
        .map(|c| c.name.clone())
        .collect()
}

/// The name of the column of component `component` of constraint `name`'s tangential force in
/// `trajectory.csv` (and Python's `Run.friction_columns`): `f_<name>`, and for the second
/// component of a contact in space `f2_<name>`.
pub fn force_column(name: &str, component: usize) -> String {
    if component == 0 {
        format!("f_{name}")
    } else {
        format!("f2_{name}")
    }
}

/// The columns of tangential force of `trajectory.csv`, `(constraint index, component)`: for
/// each constraint with friction in the model's order ([`friction_indices`]), its first
/// component (`f_<name>`) and, for a contact in space, its second (`f2_<name>`).
pub fn friction_columns<L: HybridLagrangian>(model: &L) -> Vec<(usize, usize)> {
    friction_indices(model)
        .into_iter()
        .flat_map(|i| (0..model.slip_components(i).clamp(1, 2)).map(move |k| (i, k)))
        .collect()
}

/// The indices of `model`'s constraints with friction ([`zenosim::Constraint::has_friction`]),
/// in order: those listed in `summary.json`'s `friction`.
pub fn friction_indices<L: HybridLagrangian>(model: &L) -> Vec<usize> {
    model
        .constraints()
        .iter()
        .enumerate()
        .filter(|(_, c)| c.has_friction())
        .map(|(i, _)| i)
        .collect()
}

/// Writes into `out` (cleared first) the `mode` of `trajectory.csv` (docs/output.md): `free`, or
/// `constrained:` and the names of the constraints held joined by `+`; then, where held
/// contacts stick or slip (`grips`), `;stick:` and `;slip:` and their names joined by `+`,
/// each only where not empty: `constrained:left+right;stick:left;slip:right`.
pub fn mode_label(out: &mut String, mode: Mode, grips: Grips, names: &[String]) {
    out.clear();
    let list = |out: &mut String, label: &str, set: ActiveSet| {
        for (k, index) in set.iter().enumerate() {
            out.push_str(if k == 0 { label } else { "+" });
            out.push_str(names.get(index).map_or("?", String::as_str));
        }
    };
    out.push_str(mode.name());
    if let Mode::Constrained(set) = mode {
        list(out, ":", set);
    }
    list(out, ";stick:", grips.stick);
    list(out, ";slip:", grips.slipping());
}

/// The names of the constraints active in `mode`.
pub fn active_of(mode: Mode, names: &[String]) -> Vec<&str> {
    match mode {
        Mode::Free => Vec::new(),
        Mode::Constrained(set) => active_names(set, names),
    }
}

/// The names of the constraints in `set`.
pub fn active_names(set: ActiveSet, names: &[String]) -> Vec<&str> {
    set.iter()
        .filter_map(|i| names.get(i).map(String::as_str))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_numbers_are_null() {
        let json = serde_json::to_string(&FinalJson {
            t: f64::NAN,
            mode: "free",
            active: vec![],
            q: &[f64::INFINITY, 1.5],
            q_dot: &[],
            energy: f64::NEG_INFINITY,
        })
        .unwrap();
        assert_eq!(
            json,
            r#"{"t":null,"mode":"free","active":[],"q":[null,1.5],"q_dot":[],"energy":null}"#
        );
    }

    /// The size of the energies and works involved: the scale of the residual.
    fn scale(b: &EnergyBalanceJson) -> f64 {
        [
            b.energy_start,
            b.energy_end,
            b.work_forces,
            b.work_drive,
            b.work_constraints,
            b.impact_loss,
        ]
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f64::max)
    }

    /// The balance of a run of `example`'s model, checked to close to `1e-8` of its size.
    fn balance_of<L: HybridLagrangian>(
        example: &zenosim::models::Example<L>,
        t_end: f64,
    ) -> EnergyBalanceJson {
        let options = SimulationOptions {
            t_end,
            ..Default::default()
        };
        let run = zenosim::Simulation::new(&example.model, &example.q0, &example.q_dot0, options)
            .unwrap()
            .run(&mut ());
        assert_eq!(run.outcome, Outcome::Finished);
        let initial = State {
            q: example.q0.clone(),
            q_dot: example.q_dot0.clone(),
        };
        let balance = EnergyBalanceJson::of(&example.model, &initial, &run);
        assert!(balance.impact_loss > 0.0, "{balance:?}");
        assert!(
            balance.residual.abs() <= 1e-8 * scale(&balance),
            "{balance:?}"
        );
        balance
    }

    #[test]
    fn the_energy_balance_closes() {
        use zenosim::models::{BouncingBall, DraggedBall, VibratingTable};
        // Dropped from 1 (E(0) = m g), at rest on the floor at the end (E = 0): the drag and
        // the impacts took it all.
        let dragged = balance_of(&DraggedBall::example(), 2.5);
        assert_eq!(dragged.energy_start, 9.81);
        assert!(dragged.energy_end.abs() < 1e-9, "{dragged:?}");
        assert!(dragged.work_forces < 0.0, "{dragged:?}");
        assert_eq!((dragged.work_drive, dragged.work_constraints), (0.0, 0.0));
        // The table moves: its constraint works.
        let table = balance_of(&VibratingTable::example(), 1.0);
        assert!(table.work_constraints.abs() > 1e-6, "{table:?}");
        // An autonomous model: only the impacts change the energy.
        let ball = zenosim::models::Example {
            model: BouncingBall::new(1.0, 9.81, 0.5),
            q0: vec![1.0],
            q_dot0: vec![0.0],
            t_end: 2.0,
        };
        let ball = balance_of(&ball, 2.0);
        assert_eq!(
            (ball.work_forces, ball.work_drive, ball.work_constraints),
            (0.0, 0.0, 0.0)
        );
        assert!((ball.impact_loss - 9.81).abs() < 1e-8, "{ball:?}");
        // The keys docs/output.md lists, in its order.
        let json = serde_json::to_string(&ball).unwrap();
        let at = |key: &str| json.find(&format!("\"{key}\":")).expect(key);
        let keys = [
            "energy_start",
            "energy_end",
            "work_forces",
            "work_drive",
            "work_constraints",
            "impact_loss",
            "residual",
        ];
        assert!(keys.windows(2).all(|w| at(w[0]) < at(w[1])), "{json}");
    }

    #[test]
    fn zeno_settings_are_named() {
        let s = |z| serde_json::to_string(&ZenoSetting::from(z)).unwrap();
        assert_eq!(s(ZenoStrategy::Auto), r#""auto""#);
        assert_eq!(s(ZenoStrategy::Off), r#""off""#);
        assert_eq!(s(ZenoStrategy::Epsilon(1e-3)), r#"{"epsilon":0.001}"#);
    }

    #[test]
    fn pairs_keep_their_order() {
        let json = serde_json::to_string(&Pairs(vec![("m", 1.0), ("g", 9.81), ("a", 2.0)]));
        assert_eq!(json.unwrap(), r#"{"m":1.0,"g":9.81,"a":2.0}"#);
        let json = serde_json::to_string(&Pairs(vec![("wall", "x - 1"), ("floor", "y")]));
        assert_eq!(json.unwrap(), r#"{"wall":"x - 1","floor":"y"}"#);
    }
}
