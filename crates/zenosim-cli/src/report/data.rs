//! The data the page draws, one JSON blob: the run's record, the animation's frames, the
//! mechanism's points at each frame, the plots' decimated series, the events (with friction,
//! their normal and tangential impulses), the Zeno points and the energy balance.
//!
//! Sizes: times are kept exact (events near a Zeno point are microseconds apart), the plotted
//! values and the drawn positions to single precision (seven digits, finer than a pixel);
//! lists are written column by column (one array per field) rather than as objects.

use serde::Serialize;

use super::frames::Frames;
use super::mechanism::Drawn;
use crate::plot::record::{EnergyBalanceRecord, Record};
use crate::plot::trajectory_file::Trajectory;

/// The page's data.
#[derive(Serialize)]
pub struct Data<'a> {
    model: &'a str,
    description: Option<&'a str>,
    status: &'a str,
    message: Option<&'a str>,
    /// The animation's and the plots' span of time.
    span: [f64; 2],
    coordinates: &'a [String],
    constraints: &'a [String],
    /// The constraints with friction, whose tangential forces are plotted and whose states
    /// (`;stick:`, `;slip:` in the modes) are shown; left out for a frictionless run.
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    friction: &'a [String],
    modes: &'a [String],
    frames: FramesJson<'a>,
    /// The mechanism, or `null` and [`Data::note`] saying why not.
    mechanism: Option<Drawn>,
    note: Option<String>,
    series: Vec<Series>,
    events: Events,
    zeno: Vec<Zeno<'a>>,
    /// The energy balance of the whole run (`null` for a summary older than schema 3).
    balance: Option<&'a EnergyBalanceRecord>,
}

#[derive(Serialize)]
struct FramesJson<'a> {
    t: &'a [f64],
    mode: &'a [u32],
    /// `q` of each frame, one after the other.
    q: &'a [f64],
}

/// A plotted series, in its group (a plot).
#[derive(Serialize)]
struct Series {
    name: String,
    group: &'static str,
    t: Vec<f32>,
    y: Vec<f32>,
}

/// The events, a field per array; `kind` and `constraint` index `kinds` and `names`.
#[derive(Serialize)]
struct Events {
    t: Vec<f64>,
    kind: Vec<u32>,
    kinds: Vec<String>,
    constraint: Vec<u32>,
    names: Vec<String>,
    /// In a run with friction, each event's impulses; left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    impulses: Option<Impulses>,
}

/// The impulses of each event (empty lists but for impacts): on each of its contacts (indices
/// into the events' `names`), the normal impulse and the tangential one (along increasing
/// slip; empty for an impact on contacts without friction).
#[derive(Serialize)]
struct Impulses {
    contacts: Vec<Vec<u32>>,
    normal: Vec<Vec<Option<f64>>>,
    tangential: Vec<Vec<Option<f64>>>,
}

#[derive(Serialize)]
struct Zeno<'a> {
    constraints: Vec<&'a str>,
    kind: &'a str,
    t_switch: f64,
    t_zeno: Option<f64>,
    impacts: u64,
    ratio: Option<f64>,
}

impl<'a> Data<'a> {
    /// The data of the run `record`, its trajectory decimated for the plots and thinned into
    /// `frames`, its mechanism `drawn` at those frames (or the note saying why there is none).
    pub fn new(
        record: &'a Record,
        trajectory: &Trajectory,
        frames: &'a Frames,
        drawn: Result<Drawn, String>,
    ) -> Self {
        let first = frames.t.first().copied().unwrap_or(0.0);
        let last = frames.t.last().copied().unwrap_or(first);
        let (mechanism, note) = match drawn {
            Ok(drawn) => (Some(drawn), None),
            Err(note) => (None, Some(note)),
        };
        Self {
            model: &record.model,
            description: record.description.as_deref(),
            status: &record.status,
            message: record.message.as_deref(),
            span: [first, last],
            coordinates: &record.coordinates,
            constraints: &record.constraints,
            friction: &record.friction,
            modes: &frames.modes,
            frames: FramesJson {
                t: &frames.t,
                mode: &frames.mode,
                q: &frames.q,
            },
            mechanism,
            note,
            series: series(record, trajectory),
            events: events(record),
            zeno: record
                .zeno
                .iter()
                .map(|z| Zeno {
                    constraints: if z.constraints.is_empty() {
                        vec![&z.constraint]
                    } else {
                        z.constraints.iter().map(String::as_str).collect()
                    },
                    kind: &z.kind,
                    t_switch: z.t_switch,
                    t_zeno: z.t_zeno,
                    impacts: z.impacts,
                    ratio: z.ratio,
                })
                .collect(),
            balance: record.energy_balance.as_ref(),
        }
    }
}

/// The plotted series: the coordinates, the velocities, the energy (and its balance), and the
/// tangential forces of a run with friction.
fn series(record: &Record, trajectory: &Trajectory) -> Vec<Series> {
    let n = record.coordinates.len();
    let energy = ["energy".to_string()]
        .into_iter()
        .chain(trajectory.balance.then(|| crate::plot::BALANCE.to_string()));
    let forces = record
        .force_columns()
        .into_iter()
        .map(|(c, k)| crate::trajectory::force_column(c, k));
    let names = record.columns().cloned().chain(energy).chain(forces);
    names
        .zip(&trajectory.lines)
        .enumerate()
        .map(|(k, (name, line))| Series {
            name,
            group: if k < n {
                "Displacements"
            } else if k < 2 * n {
                "Velocities"
            } else if trajectory.friction.contains(&k) {
                "Tangential forces"
            } else {
                "Energy"
            },
            t: line.iter().map(|p| p.0 as f32).collect(),
            y: line.iter().map(|p| p.1 as f32).collect(),
        })
        .collect()
}

fn events(record: &Record) -> Events {
    let count = record.events.len();
    let mut events = Events {
        t: Vec::with_capacity(count),
        kind: Vec::with_capacity(count),
        kinds: Vec::new(),
        constraint: Vec::with_capacity(count),
        names: record.constraints.clone(),
        impulses: (!record.friction.is_empty()).then(|| Impulses {
            contacts: Vec::with_capacity(count),
            normal: Vec::with_capacity(count),
            tangential: Vec::with_capacity(count),
        }),
    };
    let index = |list: &mut Vec<String>, name: &str| match list.iter().position(|x| x == name) {
        Some(k) => k as u32,
        None => {
            list.push(name.to_string());
            (list.len() - 1) as u32
        }
    };
    for event in &record.events {
        events.t.push(event.t);
        events.kind.push(index(&mut events.kinds, &event.kind));
        events
            .constraint
            .push(index(&mut events.names, &event.constraint));
        if let Some(impulses) = &mut events.impulses {
            let contacts = event.contacts.iter();
            let contacts = contacts.map(|c| index(&mut events.names, c)).collect();
            impulses.contacts.push(contacts);
            impulses.normal.push(event.impulses.clone());
            impulses.tangential.push(event.tangential_impulses.clone());
        }
    }
    events
}
