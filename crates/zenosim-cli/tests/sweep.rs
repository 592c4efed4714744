//! `zenosim sweep` and `zenosim merge`: the file a sweep writes, shards merged into exactly the
//! file of the whole sweep, the refusals of parts that do not belong together, the map, and bad
//! arguments.

mod common;

use common::*;
use roxmltree::Document;

/// The ball of `common` (dropped from x = 1, g = 9.81, t_end = 2) over restitutions and
/// heights: the Zeno time √(2x/g)(1+e)/(1−e) is past t_end = 2 for e = 0.9 from all three
/// heights and for e = 0.7 from x = 1 (2.56) and 1.5 (3.13): five runs without a Zeno point
/// (NaN); before it for the others (e = 0.7 from 0.5: 1.81).
const AXES: [&str; 4] = ["--vary", "e=0.3:0.9:4", "--vary", "x=0.5,1,1.5"];

fn sweep(scratch: &Scratch, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["sweep", "model.toml"];
    args.extend_from_slice(&AXES);
    args.extend_from_slice(extra);
    scratch.zenosim(&args)
}

fn read(path: &std::path::Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The data rows of a sweep file (after its first line and its header), as fields.
fn rows(text: &str) -> Vec<Vec<String>> {
    let (_, csv) = text.split_once('\n').expect("a first line");
    csv::Reader::from_reader(csv.as_bytes())
        .records()
        .map(|r| r.expect("a CSV row").iter().map(str::to_string).collect())
        .collect()
}

#[test]
fn shards_merged_are_the_whole_sweep_byte_for_byte() {
    let s = Scratch::new(BALL);
    assert_exit(&sweep(&s, &["--out", "whole.csv"]), 0);
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let out = format!("part{k}.csv");
        let output = sweep(&s, &["--shard", &shard, "--out", &out, "--workers", "1"]);
        assert_exit(&output, 0);
        assert!(stdout(&output).contains(&format!("(shard {k}/3 of 12 points)")));
    }
    // In any order.
    let merged = s.zenosim(&[
        "merge",
        "part3.csv",
        "part1.csv",
        "part2.csv",
        "--out",
        "merged.csv",
    ]);
    assert_exit(&merged, 0);
    assert!(
        stdout(&merged).contains("merged 3 shards"),
        "{}",
        stdout(&merged)
    );
    let whole = read(&s.path("whole.csv"));
    assert_eq!(read(&s.path("merged.csv")), whole);

    // The file: which sweep and shard, the header, a row per point in order.
    let mut lines = whole.lines();
    let first = lines.next().unwrap();
    assert!(
        first.starts_with("# zenosim sweep v1 zenosim=")
            && first.contains(" points=12 shard=1/1 model=ball"),
        "{first}"
    );
    assert_eq!(
        lines.next().unwrap(),
        "index,e,x,status,impacts,t_zeno,t_switch,t_final,final_x,final_x_dot,message"
    );
    let table = rows(&whole);
    assert_eq!(table.len(), 12);
    for (i, row) in table.iter().enumerate() {
        assert_eq!(row[0], i.to_string());
        assert_eq!(row.len(), 11, "{row:?}");
        let (e, x): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        // The first axis varies slowest.
        assert_eq!(e, [0.3, 0.5, 0.7000000000000001, 0.9][i / 3]);
        assert_eq!(x, [0.5, 1.0, 1.5][i % 3]);
        assert_eq!(row[3], "finished");
        let tau = (2.0 * x / 9.81f64).sqrt() * (1.0 + e) / (1.0 - e);
        if tau < 2.0 {
            let t_zeno: f64 = row[5].parse().unwrap();
            assert!((t_zeno - tau).abs() < 1e-8 * tau, "{row:?} against {tau}");
        } else {
            assert_eq!((row[5].as_str(), row[6].as_str()), ("NaN", "NaN"));
        }
        assert_eq!(row[7], "2");
    }
    // The parts are what they say.
    let part2 = read(&s.path("part2.csv"));
    assert!(part2.lines().next().unwrap().contains(" shard=2/3 "));
    let indices: Vec<String> = rows(&part2).into_iter().map(|r| r[0].clone()).collect();
    assert_eq!(indices, ["1", "4", "7", "10"]);
}

#[test]
fn merge_refuses_parts_that_are_not_one_whole_sweep() {
    let s = Scratch::new(BALL);
    for k in 1..=3 {
        let (shard, out) = (format!("{k}/3"), format!("p{k}.csv"));
        assert_exit(&sweep(&s, &["--shard", &shard, "--out", &out]), 0);
    }
    // Another sweep: another value of e.
    let other = s.zenosim(&[
        "sweep",
        "model.toml",
        "--vary",
        "e=0.3:0.9:5",
        "--vary",
        "x=0.5,1,1.5",
        "--shard",
        "2/3",
        "--out",
        "other.csv",
    ]);
    assert_exit(&other, 0);
    let merge = |parts: &[&str]| {
        let mut args = vec!["merge"];
        args.extend_from_slice(parts);
        args.extend_from_slice(&["--out", "m.csv"]);
        let output = s.zenosim(&args);
        assert_exit(&output, 2);
        assert!(!s.path("m.csv").exists());
        stderr(&output)
    };
    let missing = merge(&["p1.csv", "p3.csv"]);
    assert!(missing.contains("shard 2/3 of the sweep"), "{missing}");
    assert!(missing.contains("is missing"), "{missing}");
    let twice = merge(&["p1.csv", "p2.csv", "p3.csv", "p2.csv"]);
    assert!(
        twice.contains("p2.csv: shard 2/3 is given twice"),
        "{twice}"
    );
    let foreign = merge(&["p1.csv", "other.csv", "p3.csv"]);
    assert!(
        foreign.contains("other.csv: not a shard of the same sweep"),
        "{foreign}"
    );
    // Not a sweep file at all.
    std::fs::write(s.path("t.csv"), "t,mode,x\n0,free,1\n").unwrap();
    let stranger = merge(&["p1.csv", "t.csv"]);
    assert!(
        stranger.contains("t.csv: not a zenosim sweep file"),
        "{stranger}"
    );
    // A part that lost its last row.
    let text = read(&s.path("p3.csv"));
    let cut = &text[..text[..text.len() - 1].rfind('\n').unwrap() + 1];
    std::fs::write(s.path("p3.csv"), cut).unwrap();
    let short = merge(&["p1.csv", "p2.csv", "p3.csv"]);
    assert!(short.contains("p3.csv:"), "{short}");
    assert!(short.contains("the file ends where shard 3/3"), "{short}");
    let absent = merge(&["p1.csv", "nowhere.csv"]);
    assert!(absent.contains("nowhere.csv"), "{absent}");
}

#[test]
fn the_map_has_a_cell_per_run_and_grey_cells_for_runs_without_a_zeno_point() {
    let s = Scratch::new(BALL);
    let output = sweep(&s, &["--out", "maps/ball.csv", "--plot", "e,x,t_zeno"]);
    assert_exit(&output, 0);
    assert!(
        stdout(&output).contains("maps/ball.svg"),
        "{}",
        stdout(&output)
    );
    let rows = rows(&read(&s.path("maps/ball.csv")));
    let svg = read(&s.path("maps/ball.svg"));
    let doc = Document::parse(&svg).expect("the map is SVG");
    let group = |class: &str, index: &str| {
        doc.descendants()
            .filter(|n| n.has_tag_name("g") && n.attribute("class") == Some(class))
            .filter(|n| n.attribute("data-name") == Some(index))
            .count()
    };
    for row in &rows {
        let no_value = row[5] == "NaN";
        let (class, other) = if no_value {
            ("no-value", "cell")
        } else {
            ("cell", "no-value")
        };
        assert_eq!(group(class, &row[0]), 1, "row {}", row[0]);
        assert_eq!(group(other, &row[0]), 0, "row {}", row[0]);
    }
    let grey: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("g") && n.attribute("class") == Some("no-value"))
        .collect();
    assert_eq!(
        grey.len(),
        5,
        "e = 0.9 from the three heights, e = 0.7 from 1 and 1.5"
    );
    for g in &grey {
        let rect = g.children().find(|n| n.has_tag_name("rect")).unwrap();
        assert_eq!(rect.attribute("fill"), Some("#cdcdcd"));
    }
    assert!(svg.contains("no Zeno point (5)"), "the legend says so");
    assert!(svg.contains("ball: t_zeno over e and x"));
    // PNG on request.
    let output = sweep(
        &s,
        &["--out", "b.csv", "--plot", "x,e,impacts", "--format", "png"],
    );
    assert_exit(&output, 0);
    let png = std::fs::read(s.path("b.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}

#[test]
fn maps_that_cannot_be_drawn_are_refused_before_anything_runs() {
    let s = Scratch::new(BALL);
    for (extra, why) in [
        (&["--plot", "e,m,t_zeno"][..], "`m` is not varied"),
        (&["--plot", "e,x,tau"], "`tau` is not a column"),
        (&["--plot", "e,x,t_zeno", "--zip"], "drop --zip"),
        (
            &["--plot", "e,x,t_zeno", "--shard", "1/2"],
            "draw the map from an unsharded",
        ),
        (&["--format", "png"], "add --plot"),
        (
            &["--plot", "e,x,t_zeno", "--out", "s.svg"],
            "written over the sweep's file",
        ),
    ] {
        let mut args = extra.to_vec();
        if !extra.contains(&"--out") {
            args.extend_from_slice(&["--out", "s.csv"]);
        }
        let output = if extra.contains(&"--zip") {
            s.zenosim(
                &[
                    &[
                        "sweep",
                        "model.toml",
                        "--vary",
                        "e=0.3,0.5",
                        "--vary",
                        "x=1,2",
                    ][..],
                    &args[..],
                ]
                .concat(),
            )
        } else {
            sweep(&s, &args)
        };
        assert_exit(&output, 2);
        assert!(
            stderr(&output).contains(why),
            "{extra:?}: {}",
            stderr(&output)
        );
        assert!(!s.path("s.csv").exists() && !s.path("s.svg").exists());
    }
    // Three axes that vary: a cell would hold several runs.
    let output = sweep(&s, &["--vary", "m=1,2", "--plot", "e,x,t_zeno"]);
    assert_exit(&output, 2);
    assert!(
        stderr(&output).contains("`m` takes 2 values"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn bad_axes_are_named_and_nothing_is_written() {
    let s = Scratch::new(BALL);
    for (vary, why) in [
        ("e", "`e`: there is no `=`"),
        ("e=0.1:0.9", "three parts START:STOP:COUNT, not 2"),
        (
            "e=0.1:0.9:0",
            "the count `0` is not a whole number from 1 to",
        ),
        ("e=0.1,abc", "`abc` is not a number"),
        (
            "restitution=0.5",
            "`restitution` is not a parameter or an initial value",
        ),
    ] {
        let output = s.zenosim(&["sweep", "model.toml", "--vary", vary]);
        assert_exit(&output, 2);
        assert!(stderr(&output).contains(why), "{vary}: {}", stderr(&output));
        assert!(!s.path("out").exists());
    }
    let unknown = stderr(&s.zenosim(&["sweep", "model.toml", "--vary", "y=1"]));
    assert!(unknown.contains("m, g, e, x, x_dot"), "{unknown}");
    let zip = s.zenosim(&[
        "sweep",
        "model.toml",
        "--vary",
        "e=0.1,0.2",
        "--vary",
        "x=1",
        "--zip",
    ]);
    assert_exit(&zip, 2);
    assert!(
        stderr(&zip).contains("e has 2, x has 1"),
        "{}",
        stderr(&zip)
    );
    let twice = s.zenosim(&["sweep", "model.toml", "--vary", "e=0.1", "--vary", "e=0.2"]);
    assert_exit(&twice, 2);
    assert!(stderr(&twice).contains("`e` is varied twice"));
    let shard = s.zenosim(&["sweep", "model.toml", "--vary", "e=0.1", "--shard", "4/3"]);
    assert_exit(&shard, 2);
    assert!(stderr(&shard).contains("K must be between 1 and N"));
    let none = s.zenosim(&["sweep", "model.toml"]);
    assert_exit(&none, 2);
    assert!(stderr(&none).contains("--vary"));
}

#[test]
fn invalid_points_are_rows_and_exit_1() {
    let s = Scratch::new(BALL);
    let output = s.zenosim(&["sweep", "model.toml", "--vary", "e=0.5,1.5"]);
    assert_exit(&output, 1);
    assert!(
        stderr(&output).contains("1 point invalid"),
        "{}",
        stderr(&output)
    );
    // The default file: out/<model>/sweep.csv.
    let text = read(&s.path("out/ball/sweep.csv"));
    let rows = rows(&text);
    assert_eq!(
        (rows[0][2].as_str(), rows[1][2].as_str()),
        ("finished", "invalid")
    );
    assert!(
        rows[1][9].contains("restitution of `floor` is 1.5"),
        "{:?}",
        rows[1]
    );
    assert_eq!((rows[1][4].as_str(), rows[1][6].as_str()), ("NaN", "NaN"));
    assert!(
        stdout(&output).contains("1 finished, 1 invalid"),
        "{}",
        stdout(&output)
    );
    // With --shard, the default name says which.
    let output = s.zenosim(&[
        "sweep",
        "model.toml",
        "--vary",
        "e=0.5,0.6",
        "--shard",
        "2/2",
    ]);
    assert_exit(&output, 0);
    assert!(s.path("out/ball/sweep-2-of-2.csv").exists());
}

#[test]
fn settings_reach_every_run() {
    let s = Scratch::new(BALL);
    let output = s.zenosim(&[
        "sweep",
        "model.toml",
        "--vary",
        "e=0.5",
        "--zeno",
        "off",
        "--t-end",
        "5",
        "--rtol",
        "1e-8",
        "--atol",
        "1e-8",
        "--out",
        "s.csv",
    ]);
    // A run stopped at its Zeno point is no failure for a sweep.
    assert_exit(&output, 0);
    let rows = rows(&read(&s.path("s.csv")));
    assert_eq!(rows[0][2], "zeno_stalled");
    let t_final: f64 = rows[0][6].parse().unwrap();
    let tau = (2.0 / 9.81f64).sqrt() * 3.0;
    assert!(
        t_final < 5.0 && (t_final - tau).abs() < 1e-3,
        "{:?}",
        rows[0]
    );
}

/// Ctrl-C stops a sweep: the runs under way stop at their next step, the rows done are written
/// (status `interrupted` for the stopped ones), and the exit status is 130. The file says how
/// many points the sweep has, so `zenosim merge` refuses it as incomplete.
#[cfg(unix)]
#[test]
fn sigint_stops_a_sweep_and_writes_the_rows_done() {
    // 4000 runs of an elastic ball (e = 1: it bounces for ever) to t = 1e4, about 10⁴ impacts
    // each: minutes of work.
    let scratch = Scratch::new(&BALL.replace("e = 0.5", "e = 1.0"));
    let mut child = std::process::Command::new(binary())
        .args([
            "sweep",
            "model.toml",
            "--vary",
            "x=1:2:4000",
            "--t-end",
            "1e4",
        ])
        .args(["--out", "s.csv", "--workers", "2"])
        .current_dir(scratch.dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the sweep ended before the signal"
    );
    let status = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130));
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(err.contains("interrupted by SIGINT"), "{err}");
    let text = read(&scratch.path("s.csv"));
    assert!(text.starts_with("# zenosim sweep v1") && text.contains("points=4000"));
    let done = rows(&text);
    assert!(!done.is_empty() && done.len() < 4000, "{} rows", done.len());
    let merged = scratch.zenosim(&["merge", "s.csv", "--out", "m.csv"]);
    assert_exit(&merged, 2);
}

/// Issue 25: the sweep's file is capped by `--max-output` too. A sweep whose rows cannot fit
/// even at a character a field is refused before it runs (exit 2, nothing written); one whose
/// rows turn out longer keeps the rows that fit, whole, and exits 1 naming the cap, the file
/// and what to do; `zenosim merge` refuses such a file as incomplete.
#[test]
fn the_output_cap_bounds_the_sweeps_file() {
    let s = Scratch::new(BALL);
    let many = [
        "sweep",
        "model.toml",
        "--vary",
        "e=0.1:0.9:1000",
        "--t-end",
        "0.5",
    ];
    let refused = s.zenosim(&[&many[..], &["--out", "r.csv", "--max-output", "10K"]].concat());
    assert_exit(&refused, 2);
    let err = stderr(&refused);
    for part in ["--max-output 10 KiB", "1000 rows", "r.csv", "--shard K/N"] {
        assert!(err.contains(part), "{part}: {err}");
    }
    assert!(!s.path("r.csv").exists());

    let whole = sweep(&s, &["--out", "whole.csv"]);
    assert_exit(&whole, 0);
    let whole = read(&s.path("whole.csv"));
    assert_eq!(rows(&whole).len(), 12);
    // Room for about half of the rows.
    let cap = whole.len() / 2;
    let capped = sweep(&s, &["--out", "c.csv", "--max-output", &cap.to_string()]);
    assert_exit(&capped, 1);
    let text = read(&s.path("c.csv"));
    assert!(text.len() <= cap, "{} bytes", text.len());
    let kept = rows(&text).len();
    assert!((3..12).contains(&kept), "{kept} rows");
    // The rows kept are the whole sweep's first rows, byte for byte.
    assert!(whole.starts_with(&text));
    let err = stderr(&capped);
    for part in [
        "c.csv reached the output cap of",
        &format!("the first {kept} runs of 12"),
        "--max-output",
        "--shard K/N",
    ] {
        assert!(err.contains(part), "{part}: {err}");
    }
    let merged = s.zenosim(&["merge", "c.csv", "--out", "m.csv"]);
    assert_exit(&merged, 2);
    assert!(
        stderr(&merged).contains("incomplete"),
        "{}",
        stderr(&merged)
    );
}

/// Regressions from review: counts that allocate without bound (an axis of 10¹⁴ values, a
/// product of 10¹⁰ runs in one process, a part claiming 10¹¹ shards) were aborts; a part cut
/// inside its last row merged (exit 0); a bad --out was found only after every run; a map of
/// values near 1.8e308 never finished drawing.
#[test]
fn hostile_sizes_truncated_parts_and_bad_outputs_are_refused_at_once() {
    let s = Scratch::new(BALL);
    let huge = s.zenosim(&["sweep", "model.toml", "--vary", "e=0:1:100000000000000"]);
    assert_exit(&huge, 2);
    assert!(
        stderr(&huge).contains("from 1 to 10000000"),
        "{}",
        stderr(&huge)
    );
    let product = [
        "sweep",
        "model.toml",
        "--vary",
        "e=0:1:100000",
        "--vary",
        "x=1:2:100000",
    ];
    let product = s.zenosim(&product);
    assert_exit(&product, 2);
    assert!(
        stderr(&product).contains("--shard K/5000"),
        "{}",
        stderr(&product)
    );

    // The output is opened before the runs: an elastic ball (it never rests) to t = 1e6 from
    // 1000 heights would run for hours.
    let elastic = Scratch::new(&BALL.replace("e = 0.5", "e = 1.0"));
    let args = [
        "sweep",
        "model.toml",
        "--vary",
        "x=1:2:1000",
        "--t-end",
        "1e6",
    ];
    let plain = elastic.path("plain");
    std::fs::write(&plain, "").unwrap();
    let under_a_file = elastic.zenosim(&[&args[..], &["--out", "plain/s.csv"]].concat());
    assert_exit(&under_a_file, 1);
    assert!(
        stderr(&under_a_file).contains("plain"),
        "{}",
        stderr(&under_a_file)
    );

    // Parts: cut inside the last row (its newline gone), and a first line claiming 10¹¹ shards.
    for k in 1..=2 {
        let (shard, out) = (format!("{k}/2"), format!("p{k}.csv"));
        assert_exit(&sweep(&s, &["--shard", &shard, "--out", &out]), 0);
    }
    let text = read(&s.path("p2.csv"));
    std::fs::write(s.path("cut.csv"), &text[..text.len() - 5]).unwrap();
    let cut = s.zenosim(&["merge", "p1.csv", "cut.csv", "--out", "m.csv"]);
    assert_exit(&cut, 2);
    assert!(stderr(&cut).contains("cut.csv: does not end with a newline"));
    let liar = read(&s.path("p1.csv")).replacen("shard=1/2", "shard=1/100000000000", 1);
    std::fs::write(s.path("liar.csv"), liar).unwrap();
    let liar = s.zenosim(&["merge", "liar.csv", "--out", "m.csv"]);
    assert_exit(&liar, 2);
    assert!(stderr(&liar).contains("missing"), "{}", stderr(&liar));
    assert!(!s.path("m.csv").exists());

    // A map over values near f64's limit ends (the runs from 1.7e308 are invalid: no value).
    let map = [
        "--vary",
        "x=1.7e308",
        "--vary",
        "e=0.5,0.6",
        "--plot",
        "e,x,t_zeno",
    ];
    let map = s.zenosim(&[&["sweep", "model.toml"][..], &map, &["--out", "y.csv"]].concat());
    assert!(map.status.code().is_some());
    assert!(s.path("y.svg").exists());
}

/// `--out` naming a FIFO: `sweep` and `merge` renamed their file over it, replacing the FIFO
/// (as root, `--out /dev/null` replaced the device by a regular file). A final name that is
/// not a regular file (nor a symlink, which is replaced, never followed) is now refused before
/// anything runs, and left as it was; a directory too.
#[cfg(unix)]
#[test]
fn an_out_that_is_a_fifo_or_a_directory_is_refused_and_left_alone() {
    use std::os::unix::fs::FileTypeExt;
    let s = Scratch::new(BALL);
    let fifo = s.path("pipe.csv");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|status| status.success()), "mkfifo");
    std::fs::create_dir(s.path("folder.csv")).unwrap();
    assert_exit(&sweep(&s, &["--shard", "1/1", "--out", "part.csv"]), 0);
    for (target, kind) in [("pipe.csv", "a FIFO"), ("folder.csv", "a directory")] {
        for command in [
            sweep(&s, &["--out", target]),
            s.zenosim(&["merge", "part.csv", "--out", target]),
        ] {
            assert_exit(&command, 1);
            let error = stderr(&command);
            assert!(error.contains(target) && error.contains(kind), "{error}");
        }
    }
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    assert!(s.path("folder.csv").is_dir());
}

/// Every writing command removed any `.*.partial` file in its output folder, another
/// program's `.thesis.docx.partial` included. Only names of zenosim's own form,
/// `.<name>.<pid>-<n>.partial`, are its stale temporary files now.
#[test]
fn another_programs_partial_files_are_left_alone() {
    let s = Scratch::new(BALL);
    let theirs = s.path(".thesis.docx.partial");
    std::fs::write(&theirs, "chapter 1").unwrap();
    let stale = s.path(".sweep.csv.4000000-7.partial");
    std::fs::write(&stale, "a killed sweep's rows").unwrap();
    assert_exit(&sweep(&s, &["--out", "sweep.csv"]), 0);
    assert_eq!(std::fs::read_to_string(&theirs).unwrap(), "chapter 1");
    assert!(!stale.exists());
}

/// A shard interrupted after every point had started keeps a row for each, the stopped ones
/// with status `interrupted`: `merge` accepted it, though the docs say it refuses an
/// interrupted shard. A row of status `interrupted` now makes the shard incomplete.
#[test]
fn merge_refuses_a_shard_with_an_interrupted_run_even_if_every_row_is_there() {
    let s = Scratch::new(BALL);
    assert_exit(&sweep(&s, &["--shard", "1/1", "--out", "part.csv"]), 0);
    let text = read(&s.path("part.csv"));
    // The first row's status, as a run stopped by Ctrl-C writes it.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header: Vec<&str> = lines[1].split(',').collect();
    let column = header.iter().position(|&h| h == "status").unwrap();
    let mut fields: Vec<String> = lines[2].split(',').map(str::to_string).collect();
    fields[column] = "interrupted".to_string();
    lines[2] = fields.join(",");
    std::fs::write(s.path("part.csv"), lines.join("\n") + "\n").unwrap();
    let merged = s.zenosim(&["merge", "part.csv", "--out", "m.csv"]);
    assert_exit(&merged, 2);
    let error = stderr(&merged);
    assert!(
        error.contains("part.csv:3")
            && error.contains("interrupted")
            && error.contains("run this shard again"),
        "{error}"
    );
    assert!(!s.path("m.csv").exists());
}
