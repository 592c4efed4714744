//! A run's summary as the Python package takes it: its `events` and `zeno` lists serialised on
//! their own with exactly summary.json's keys, in its order (docs/output.md).

use zenosim::Simulation;
use zenosim_runs::message::message;
use zenosim_runs::summary::{constraint_names, Record, TrajectoryJson};

const BALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../models/bouncing-ball.toml"
);

/// The keys of the JSON object `text`, in order.
fn keys(text: &str) -> Vec<String> {
    let value: serde_json::Value = serde_json::from_str(text).unwrap();
    let object = value.as_object().expect("an object");
    // serde_json's map keeps no order: read the keys' places in the text instead.
    let mut keys: Vec<(usize, String)> = object
        .keys()
        .map(|k| (text.find(&format!("\"{k}\":")).unwrap(), k.clone()))
        .collect();
    keys.sort();
    keys.into_iter().map(|(_, k)| k).collect()
}

#[test]
fn events_and_zeno_points_serialise_with_summary_json_s_keys() {
    let source = std::fs::read_to_string(BALL).unwrap();
    let file = zenosim_model::parse_model(BALL, &source, &[]).unwrap();
    let options = file.options();
    let run = Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)
        .unwrap()
        .run(&mut ());
    let constraints = constraint_names(&file);
    let summary = Record {
        file: &file,
        options: &options,
        run: &run,
        constraint_names: &constraints,
        message: message(&run, &constraints),
        trajectory: TrajectoryJson { file: "", rows: 0 },
    }
    .summary();
    assert_eq!(summary.status, "finished");
    assert!(summary.message.starts_with("finished at t = 3 after "));

    let events: Vec<serde_json::Value> =
        serde_json::from_str(&serde_json::to_string(&summary.events).unwrap()).unwrap();
    assert_eq!(events.len(), run.events.len());
    assert_eq!(events[0]["kind"], "impact");
    assert_eq!(events[0]["contacts"], serde_json::json!(["floor"]));
    let first = serde_json::to_string(&summary.events.collect()[0]).unwrap();
    assert_eq!(
        keys(&first),
        [
            "kind",
            "t",
            "constraint",
            "contacts",
            "impulses",
            "before",
            "after"
        ],
        "{first}"
    );

    let zeno = serde_json::to_string(&summary.zeno).unwrap();
    let points: Vec<serde_json::Value> = serde_json::from_str(&zeno).unwrap();
    assert_eq!(points.len(), 1);
    assert_eq!(
        keys(&zeno[1..zeno.len() - 1]),
        [
            "constraint",
            "constraints",
            "kind",
            "t_switch",
            "t_zeno",
            "impacts",
            "ratio",
            "event"
        ]
    );
    // Schema 4: the point's state is its event's `after`, not written again; an impact's
    // `after` leaves out the unchanged `q`.
    let k = points[0]["event"].as_u64().unwrap() as usize;
    assert_eq!(events[k]["kind"], "zeno");
    assert!(
        events[0]["after"].get("q").is_none(),
        "{}",
        events[0]["after"]
    );
    assert!(events[0]["after"]["q_dot"].is_array());
    // τ∞ = t₁ (1 + e)/(1 − e), t₁ = √(2 h0/g), for the file's h0 = 1, g = 9.81, e = 0.5.
    let tau = (2.0f64 / 9.81).sqrt() * 3.0;
    let t_zeno = points[0]["t_zeno"].as_f64().unwrap();
    assert!((t_zeno - tau).abs() < 1e-8, "{t_zeno} against {tau}");
}
