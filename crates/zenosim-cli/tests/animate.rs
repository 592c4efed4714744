//! `zenosim animate`: the GIF of a run decodes, has the frames and size asked for, moves, and
//! shows the bouncing ball on its floor once it has come to rest; its errors name the file and
//! say what to do, and leave no file behind.

mod common;

use std::path::Path;

use common::*;

/// The colours `zenosim animate` draws in (src/plot/animation_render.rs): the inside of
/// circles, and a surface held.
const FILL: [u8; 3] = [185, 210, 240];
const HELD: [u8; 3] = [215, 50, 30];

fn bouncing_ball() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/bouncing-ball.toml");
    std::fs::read_to_string(path).unwrap()
}

/// A decoded GIF: its size and every frame composed over the ones before, as RGB.
struct Gif {
    width: usize,
    height: usize,
    frames: Vec<Vec<[u8; 3]>>,
    delays: Vec<u16>,
}

fn decode(path: &Path) -> Gif {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options
        .read_info(std::fs::File::open(path).expect("the GIF exists"))
        .expect("a GIF");
    let (width, height) = (decoder.width() as usize, decoder.height() as usize);
    let palette: Vec<[u8; 3]> = decoder
        .global_palette()
        .expect("a global palette")
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let mut canvas = vec![[0u8; 3]; width * height];
    let mut frames = Vec::new();
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().expect("a frame") {
        let (left, top) = (frame.left as usize, frame.top as usize);
        for y in 0..frame.height as usize {
            for x in 0..frame.width as usize {
                let index = frame.buffer[y * frame.width as usize + x];
                if Some(index) != frame.transparent {
                    canvas[(top + y) * width + left + x] = palette[index as usize];
                }
            }
        }
        frames.push(canvas.clone());
        delays.push(frame.delay);
    }
    Gif {
        width,
        height,
        frames,
        delays,
    }
}

/// The rows where `colour` appears in `frame`, first and last, and how many pixels have it.
fn rows_of(gif: &Gif, frame: usize, colour: [u8; 3]) -> Option<(usize, usize, usize)> {
    let pixels = &gif.frames[frame];
    let rows: Vec<usize> = (0..pixels.len())
        .filter(|&i| pixels[i] == colour)
        .map(|i| i / gif.width)
        .collect();
    Some((*rows.iter().min()?, *rows.iter().max()?, rows.len()))
}

fn run_and_animate(scratch: &Scratch, run: &[&str], animate: &[&str]) -> String {
    assert_exit(&scratch.run(run), 0);
    let mut args = vec!["animate", "out", "--out", "ball.gif"];
    args.extend_from_slice(animate);
    let output = scratch.zenosim(&args);
    assert_exit(&output, 0);
    stdout(&output)
}

#[test]
fn the_bouncing_ball_comes_to_rest_on_its_floor() {
    let scratch = Scratch::new(&bouncing_ball());
    let report = run_and_animate(&scratch, &[], &["--size", "320x240"]);
    assert!(report.contains("151 frames of 320x240, 25 fps"), "{report}");
    // The run keeps its model beside its results, as written.
    assert_eq!(
        std::fs::read_to_string(scratch.path("out/model.toml")).unwrap(),
        bouncing_ball()
    );
    let gif = decode(&scratch.path("ball.gif"));
    // 3 s at the default half speed and 25 frames a second: 0.02 s apart, 151 frames.
    assert_eq!((gif.width, gif.height), (320, 240));
    assert_eq!(gif.frames.len(), 151);
    assert!(gif.delays.iter().all(|&d| d == 4), "{:?}", gif.delays);
    assert!(gif.frames[0] != gif.frames[10], "frames differ");
    assert_ne!(
        rows_of(&gif, 0, FILL),
        rows_of(&gif, 10, FILL),
        "the ball falls"
    );
    assert_eq!(
        rows_of(&gif, 140, FILL),
        rows_of(&gif, 150, FILL),
        "the ball rests"
    );
    assert!(files(scratch.dir.path())
        .iter()
        .all(|f| !f.ends_with(".partial")));

    // Frame 75 is at t = 1.5, after the Zeno point τ∞ = 1.3546 (t1 (1+e)/(1−e) with
    // t1 = √(2 h0/g), e = 0.5): the ball rests on the floor, which is held (in colour). The
    // lowest pixel of the ball's inside is its 2-pixel outline and a pixel of rounding above
    // the floor's top.
    let (floor_top, _, floor_pixels) = rows_of(&gif, 75, HELD).expect("the floor is held");
    assert!(floor_pixels > 100, "{floor_pixels}");
    let (ball_top, ball_bottom, _) = rows_of(&gif, 75, FILL).expect("the ball");
    assert!(
        (floor_top as i64 - ball_bottom as i64 - 1).abs() <= 3,
        "ball's inside ends at row {ball_bottom}, the floor starts at row {floor_top}"
    );
    // At t = 0 the ball is 1 m up, in a box 1.1 m tall: far above the floor, which is not
    // held (drawn grey).
    assert!(rows_of(&gif, 0, HELD).is_none());
    let (_, start_bottom, _) = rows_of(&gif, 0, FILL).expect("the ball");
    let metre = (floor_top - start_bottom) as f64;
    assert!(metre > 150.0, "{start_bottom} vs the floor at {floor_top}");
    // Its size: 0.1 m across, in pixels of that metre.
    let across = (ball_bottom - ball_top + 1) as f64;
    assert!(
        (across / metre - 0.1).abs() < 0.03,
        "{across} px in {metre}"
    );
}

#[test]
fn set_values_of_the_run_hold() {
    // The floor's half-width is a parameter: set to 5, the box is ten times wider, the ball
    // ten times smaller.
    let source = bouncing_ball()
        .replace("h0 = 1.0", "h0 = 1.0\nwide = 0.5")
        .replace(
            "left = [-0.5, 0], right = [0.5, 0]",
            "left = [\"-wide\", 0], right = [\"wide\", 0]",
        );
    let scratch = Scratch::new(&source);
    run_and_animate(&scratch, &[], &["--size", "320x240", "--max-frames", "2"]);
    let narrow = rows_of(&decode(&scratch.path("ball.gif")), 0, FILL)
        .unwrap()
        .2;
    run_and_animate(
        &scratch,
        &["--set", "wide=5"],
        &["--size", "320x240", "--max-frames", "2"],
    );
    let gif = decode(&scratch.path("ball.gif"));
    assert_eq!(gif.frames.len(), 2, "capped by --max-frames");
    let wide = rows_of(&gif, 0, FILL).map_or(0, |r| r.2);
    assert!(wide * 20 < narrow, "{wide} vs {narrow} pixels");
}

#[test]
fn a_model_without_a_drawing_is_refused() {
    let source = bouncing_ball();
    let end = source.find("\n# The mechanism as").unwrap();
    let scratch = Scratch::new(&source[..end]);
    assert_exit(&scratch.run(&[]), 0);
    let output = scratch.zenosim(&["animate", "out", "--out", "ball.gif"]);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(
        err.starts_with("error: out/model.toml: the model has no [drawing]")
            && err.contains("docs/drawing.md"),
        "{err}"
    );
    assert!(!scratch.path("ball.gif").exists());
    assert!(files(scratch.dir.path())
        .iter()
        .all(|f| !f.ends_with(".partial")));
}

#[test]
fn an_older_run_needs_the_model() {
    let scratch = Scratch::new(&bouncing_ball());
    assert_exit(&scratch.run(&[]), 0);
    std::fs::remove_file(scratch.path("out/model.toml")).unwrap();
    let output = scratch.zenosim(&["animate", "out", "--out", "ball.gif"]);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(
        err.contains("out: no model.toml") && err.contains("--model"),
        "{err}"
    );
    let output = scratch.zenosim(&[
        "animate",
        "out",
        "--out",
        "ball.gif",
        "--model",
        "model.toml",
        "--max-frames",
        "3",
    ]);
    assert_exit(&output, 0);
    assert_eq!(decode(&scratch.path("ball.gif")).frames.len(), 3);
}

#[test]
fn bad_arguments_are_refused() {
    let scratch = Scratch::new(&bouncing_ball());
    for args in [
        ["--size", "10x10"],
        ["--size", "640"],
        ["--speed", "0"],
        ["--speed", "nan"],
        ["--fps", "0"],
        ["--max-frames", "1"],
    ] {
        let mut all = vec!["animate", "out", "--out", "a.gif"];
        all.extend_from_slice(&args);
        assert_exit(&scratch.zenosim(&all), 2);
    }
    let output = scratch.zenosim(&["animate", "nowhere", "--out", "a.gif"]);
    assert_exit(&output, 2);
    assert!(
        stderr(&output).contains("nowhere/summary.json"),
        "{}",
        stderr(&output)
    );
}

/// Regression (review of issue 24): `--out x.png` wrote a GIF under a PNG's name.
#[test]
fn a_gif_was_written_under_a_png_name() {
    let scratch = Scratch::new(&bouncing_ball());
    assert_exit(&scratch.run(&[]), 0);
    let output = scratch.zenosim(&["animate", "out", "--out", "x.png"]);
    assert_exit(&output, 2);
    assert!(
        stderr(&output).contains("give the file a .gif name"),
        "{}",
        stderr(&output)
    );
    assert!(!scratch.path("x.png").exists());
    assert_exit(&scratch.zenosim(&["animate", "out", "--out", "x.GIF"]), 0);
}

#[test]
fn a_drawing_too_large_to_animate_is_refused() {
    // A curve of 1000 points of a long formula: 1.6 million operations per frame, too many
    // for 2000 frames.
    let formula = vec!["sin(s)"; 400].join("+");
    let source = bouncing_ball().replace(
        "surfaces = [{ constraint = \"floor\", through = [\"left\", \"right\"] }]",
        &format!(
            "surfaces = [{{ constraint = \"floor\", curve = [\"s\", \"0*({formula})\"], s = [-1, 1], samples = 1000 }}]"
        ),
    );
    let scratch = Scratch::new(&source);
    assert_exit(&scratch.run(&[]), 0);
    let output = scratch.zenosim(&[
        "animate",
        "out",
        "--out",
        "a.gif",
        "--speed",
        "0.01",
        "--max-frames",
        "2000",
    ]);
    assert_exit(&output, 2);
    let err = stderr(&output);
    assert!(err.contains("lower --max-frames"), "{err}");
    assert!(!scratch.path("a.gif").exists());
}

/// `animate --speed 1e-20` asked for more frames than a number of frames can count: the count
/// wrapped to none, and the failure blamed trajectory.csv. A speed that slow is capped by
/// `--max-frames` like any other, and says so.
#[test]
fn a_speed_too_slow_to_count_its_frames_is_capped() {
    let scratch = Scratch::new(&bouncing_ball());
    let out = run_and_animate(
        &scratch,
        &[],
        &["--size", "320x240", "--max-frames", "3", "--speed", "1e-20"],
    );
    assert!(out.contains("--max-frames 3 caps it"), "{out}");
    assert_eq!(decode(&scratch.path("ball.gif")).frames.len(), 3);
}
