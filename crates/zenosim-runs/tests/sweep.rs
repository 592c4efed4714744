//! Sweeps of the shipped models, against closed forms and against themselves (shards, workers,
//! zipped and product points).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use zenosim::ZenoStrategy;
use zenosim_runs::sweep::{Axis, Combine, Points, Row, RunSettings, Shard, Sweep, SweepError};
use zenosim_runs::Status;

const BALL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../models/bouncing-ball.toml"
);

fn source(path: &str) -> String {
    std::fs::read_to_string(path).unwrap()
}

fn axis(spec: &str) -> Axis {
    spec.parse().unwrap()
}

fn sweep(path: &str, axes: &[&str], combine: Combine, settings: RunSettings) -> Sweep {
    let points = Points::new(axes.iter().map(|a| axis(a)).collect(), combine).unwrap();
    Sweep::new(path, &source(path), Default::default(), points, settings).unwrap()
}

fn run(sweep: &Sweep, shard: Shard, workers: Option<usize>) -> Vec<Row> {
    let table = sweep
        .run(shard, workers, |_, _| {}, &AtomicBool::new(false))
        .unwrap();
    assert!(!table.interrupted);
    assert_eq!(table.rows.len(), table.total);
    table.rows
}

/// Rows compared to the last bit (NaN included), through their `Debug` text.
fn text(rows: &[Row]) -> Vec<String> {
    rows.iter().map(|r| format!("{r:?}")).collect()
}

/// A parameter of the model file, by name (the test fails if the file renames it).
fn parameter(path: &str, name: &str) -> f64 {
    let file = zenosim_model::parse_model(path, &source(path), &[]).unwrap();
    file.parameters
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{path} has no parameter {name}"))
        .1
}

/// The Zeno time of a ball dropped from rest at `h0` with restitution `e`: it falls for
/// `t₁ = √(2h₀/g)` and hits at `v₁ = g t₁`; the k-th flight after lasts `2 eᵏ v₁ / g`, so
/// `τ∞ = t₁ + 2 e v₁ / (g (1 − e))`.
fn zeno_time(g: f64, h0: f64, e: f64) -> f64 {
    let t1 = (2.0 * h0 / g).sqrt();
    let v1 = g * t1;
    t1 + 2.0 * e * v1 / (g * (1.0 - e))
}

#[test]
fn the_bouncing_ball_s_zeno_time_follows_its_closed_form_over_restitutions_and_heights() {
    let g = parameter(BALL, "g");
    let sweep = sweep(
        BALL,
        &["e=0.1:0.9:17", "h0=0.5,1,2"],
        Combine::Product,
        RunSettings {
            // Past the latest Zeno time, 12.1 (e = 0.9, h0 = 2).
            t_end: Some(15.0),
            ..Default::default()
        },
    );
    assert_eq!(sweep.points().len(), 51);
    assert_eq!(
        sweep.columns().join(","),
        "index,e,h0,status,impacts,t_zeno,t_switch,t_final,final_y,final_y_dot,message"
    );
    let rows = run(&sweep, Shard::WHOLE, None);
    let columns = sweep.columns();
    let column = |name: &str| columns.iter().position(|c| c == name).unwrap();
    let last = &rows[50];
    assert_eq!(last.number(column("index")), Some(50.0));
    assert_eq!(last.number(column("h0")), Some(2.0));
    assert_eq!(last.number(column("status")), None);
    assert_eq!(last.number(column("impacts")), Some(last.impacts as f64));
    assert_eq!(last.number(column("t_zeno")), Some(last.t_zeno));
    assert_eq!(last.number(column("t_final")), Some(last.t_final));
    assert_eq!(last.number(column("final_y")), Some(last.q[0]));
    assert_eq!(last.number(column("final_y_dot")), Some(last.q_dot[0]));
    assert_eq!(last.number(column("message")), None);
    for (i, row) in rows.iter().enumerate() {
        let [e, h0] = row.values[..] else { panic!() };
        // The first axis varies slowest.
        assert_eq!(row.index, i);
        assert_eq!(h0, [0.5, 1.0, 2.0][i % 3]);
        let tau = zeno_time(g, h0, e);
        assert_eq!(row.status, Status::Finished, "{row:?}");
        assert!(
            (row.t_zeno - tau).abs() <= 1e-8 * tau,
            "e = {e}, h0 = {h0}: τ∞ = {} against {tau}",
            row.t_zeno
        );
        // The switch comes at most a few flights before τ∞, which the remaining ones add up to.
        assert!(
            row.t_switch <= row.t_zeno && row.t_zeno - row.t_switch < 1e-3,
            "{row:?}"
        );
        assert!(row.impacts >= 2, "{row:?}");
        // At rest on the floor at the end.
        assert_eq!(row.t_final, 15.0);
        assert!(
            row.q[0].abs() < 1e-9 && row.q_dot[0].abs() < 1e-9,
            "{row:?}"
        );
        assert!(
            row.message.starts_with("finished at t = 15 after "),
            "{row:?}"
        );
    }
}

#[test]
fn zipped_points_are_the_diagonal_of_the_product() {
    let axes = ["e=0.2,0.5,0.8", "h0=1,2,3"];
    let settings = RunSettings::default();
    let zipped = run(
        &sweep(BALL, &axes, Combine::Zip, settings),
        Shard::WHOLE,
        None,
    );
    let product = run(
        &sweep(BALL, &axes, Combine::Product, settings),
        Shard::WHOLE,
        None,
    );
    assert_eq!((zipped.len(), product.len()), (3, 9));
    for (k, row) in zipped.iter().enumerate() {
        let mut diagonal = product[4 * k].clone();
        assert_eq!(diagonal.index, 4 * k);
        diagonal.index = k;
        assert_eq!(format!("{row:?}"), format!("{diagonal:?}"));
    }
}

#[test]
fn shards_together_are_the_whole_sweep_and_workers_change_nothing() {
    let sweep = sweep(
        BALL,
        &["e=0.3:0.8:4", "h0=0.5:2:5"],
        Combine::Product,
        RunSettings::default(),
    );
    let whole = run(&sweep, Shard::WHOLE, Some(2));
    assert_eq!(whole.len(), 20);
    let mut parts = Vec::new();
    for k in 1..=3 {
        let shard = Shard::new(k, 3).unwrap();
        let rows = run(&sweep, shard, Some(1));
        assert_eq!(rows.len(), shard.len_of(20));
        assert!(rows.iter().all(|r| shard.contains(r.index)));
        parts.extend(rows);
    }
    parts.sort_by_key(|r| r.index);
    assert_eq!(text(&parts), text(&whole));
    assert_eq!(text(&run(&sweep, Shard::WHOLE, Some(1))), text(&whole));
    assert_eq!(text(&run(&sweep, Shard::WHOLE, None)), text(&whole));
}

#[test]
fn points_the_model_refuses_are_invalid_rows_and_the_others_run() {
    let sweep = sweep(
        BALL,
        &["e=0.5,1.5", "h0=1,-1"],
        Combine::Product,
        RunSettings::default(),
    );
    let rows = run(&sweep, Shard::WHOLE, None);
    let status: Vec<Status> = rows.iter().map(|r| r.status).collect();
    assert_eq!(
        status,
        [
            Status::Finished,
            Status::Invalid,
            Status::Invalid,
            Status::Invalid
        ]
    );
    let restitution = &rows[2].message;
    assert!(restitution.starts_with("invalid: "), "{restitution}");
    assert!(
        restitution.contains("restitution of `floor` is 1.5, outside [0, 1]"),
        "{restitution}"
    );
    assert!(!restitution.contains('\n'), "{restitution}");
    // Dropped from below the floor.
    assert!(
        rows[1].message.starts_with("invalid: "),
        "{}",
        rows[1].message
    );
    for row in &rows[1..] {
        assert!(row.t_final.is_nan() && row.q[0].is_nan() && row.q_dot[0].is_nan());
        assert!(row.t_zeno.is_nan() && row.t_switch.is_nan());
        assert_eq!(row.impacts, 0);
    }
}

#[test]
fn settings_change_every_run() {
    let sweep = sweep(
        BALL,
        &["e=0.5"],
        Combine::Product,
        RunSettings {
            t_end: Some(5.0),
            zeno: Some(ZenoStrategy::Off),
            rtol: Some(1e-8),
            atol: Some(1e-8),
        },
    );
    let row = &run(&sweep, Shard::WHOLE, None)[0];
    // With zeno = off the run stalls at the Zeno point, which it still reports.
    assert_eq!(row.status, Status::ZenoStalled, "{row:?}");
    let tau = zeno_time(parameter(BALL, "g"), parameter(BALL, "h0"), 0.5);
    assert!((row.t_zeno - tau).abs() < 1e-6 * tau, "{row:?}");
    assert!(row.t_final < 5.0);
}

#[test]
fn mistakes_are_named_before_anything_runs() {
    let points = |axes: &[&str]| Points::new(axes.iter().map(|a| axis(a)).collect(), Combine::Zip);
    let new = |axes: &[&str], settings| {
        Sweep::new(
            BALL,
            &source(BALL),
            Default::default(),
            points(axes).unwrap(),
            settings,
        )
        .unwrap_err()
        .to_string()
    };
    let unknown = new(&["restitution=0.5"], RunSettings::default());
    assert!(
        unknown.contains("`restitution` is not a parameter"),
        "{unknown}"
    );
    assert!(unknown.contains("m, g, e, h0, y, y_dot"), "{unknown}");
    assert!(unknown.contains("bouncing-ball.toml"), "{unknown}");
    let settings = RunSettings {
        rtol: Some(-1.0),
        ..Default::default()
    };
    let refused = new(&["e=0.5"], settings);
    assert!(
        refused.contains("the run settings are refused"),
        "{refused}"
    );
    let bad_model = Sweep::new(
        "bad.toml",
        "name = 3",
        Default::default(),
        points(&["e=0.5"]).unwrap(),
        RunSettings::default(),
    )
    .unwrap_err();
    assert!(matches!(bad_model, SweepError::Model(_)), "{bad_model}");
    assert!(
        bad_model.to_string().starts_with("bad.toml:1:"),
        "{bad_model}"
    );
    let sweep = sweep(BALL, &["e=0.5"], Combine::Zip, RunSettings::default());
    let no_workers = sweep.run(Shard::WHOLE, Some(0), |_, _| {}, &AtomicBool::new(false));
    assert!(matches!(no_workers, Err(SweepError::NoWorkers)));
}

#[test]
fn progress_counts_every_row() {
    let sweep = sweep(BALL, &["e=0.2:0.8:7"], Combine::Zip, RunSettings::default());
    let seen = Mutex::new(Vec::new());
    let table = sweep
        .run(
            Shard::new(1, 2).unwrap(),
            Some(2),
            |done, total| seen.lock().unwrap().push((done, total)),
            &AtomicBool::new(false),
        )
        .unwrap();
    let mut seen = seen.into_inner().unwrap();
    seen.sort();
    assert_eq!(seen, [(1, 4), (2, 4), (3, 4), (4, 4)]);
    assert_eq!(table.total, 4);
}

#[test]
fn a_cancelled_sweep_keeps_the_rows_it_made() {
    let sweep = sweep(BALL, &["e=0.2:0.8:7"], Combine::Zip, RunSettings::default());
    // Cancelled once the second row is made, on one thread: nothing more starts.
    let cancel = AtomicBool::new(false);
    let calls = AtomicUsize::new(0);
    let table = sweep
        .run(
            Shard::WHOLE,
            Some(1),
            |done, _| {
                calls.fetch_add(1, Ordering::Relaxed);
                if done == 2 {
                    cancel.store(true, Ordering::Relaxed);
                }
            },
            &cancel,
        )
        .unwrap();
    assert!(table.interrupted);
    assert_eq!((table.rows.len(), table.total), (2, 7));
    assert_eq!(calls.load(Ordering::Relaxed), 2);
    assert_eq!(
        table.rows.iter().map(|r| r.index).collect::<Vec<_>>(),
        [0, 1]
    );
    assert!(table.rows.iter().all(|r| r.status == Status::Finished));
    // A run under way when the flag is set stops at its next step, its row saying so.
    let row = sweep.run_point(3, &AtomicBool::new(true));
    assert_eq!(row.status, Status::Interrupted, "{row:?}");
    assert_eq!(row.t_final, 0.0);
    assert!(row.message.starts_with("interrupted at t = 0"), "{row:?}");
}

/// Parameters may be named like the table's result columns (`status`, `impacts`, `t_final`,
/// `final_<coordinate>`, `index`, `message`, `t_zeno`): sweeping one wrote two columns of that
/// name (pandas read the second as `status.1`), and Python's table replaced the swept values
/// by the results. A varied name that clashes with a result column is now refused, naming it.
#[test]
fn a_varied_name_that_is_also_a_result_column_is_refused() {
    for name in [
        "status",
        "impacts",
        "t_zeno",
        "t_switch",
        "t_final",
        "final_y",
        "final_y_dot",
        "index",
        "message",
    ] {
        let model = source(BALL).replace("h0 = 1.0", &format!("h0 = 1.0\n{name} = 2.0"));
        let points = Points::new(vec![axis(&format!("{name}=1,2"))], Combine::Product).unwrap();
        let error = Sweep::new(
            "ball.toml",
            &model,
            Default::default(),
            points,
            RunSettings::default(),
        )
        .err()
        .unwrap_or_else(|| panic!("`{name}` was accepted"));
        assert!(
            matches!(&error, SweepError::ColumnClash { name: n, .. } if n == name),
            "{name}: {error}"
        );
        let message = error.to_string();
        // One sentence, no run of spaces from a broken line continuation.
        assert!(!message.contains("  "), "{message}");
        assert!(
            message.contains(&format!("`{name}`"))
                && message.contains("ball.toml")
                && message.contains("Rename"),
            "{message}"
        );
    }
    // Other names are as before.
    let model = source(BALL).replace("h0 = 1.0", "h0 = 1.0\nstatus_ = 2.0");
    let points = Points::new(vec![axis("status_=1,2")], Combine::Product).unwrap();
    assert!(Sweep::new(
        "ball.toml",
        &model,
        Default::default(),
        points,
        RunSettings::default()
    )
    .is_ok());
}
