//! The report in a real browser: headless Chromium driven by chromedriver over the W3C
//! WebDriver protocol (HTTP and JSON, spoken here over a plain TCP stream). The report of the
//! paper's ball loads with no error, its animation advances when played, moving the scrubber
//! to the Zeno point puts the ball on the surface, and a screenshot is not blank (saved under
//! target/tmp/report-browser/ to look at). The report of the block on a belt (friction) shows
//! its stick and slip states, its tangential force, its impulses' columns and the work of
//! friction.
//!
//! Needs /usr/bin/chromium and /usr/bin/chromedriver (Debian's `chromium` and
//! `chromium-driver`). Without them the test is skipped with a note, unless
//! ZENOSIM_BROWSER_TEST=required (as CI sets it), where their absence fails it.

mod common;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::*;
use serde_json::{json, Value};

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

/// The paper's ball as shipped, with its drawing: the ball touching the surface x3 = sin(x2)
/// at the point `contact` = (x2, x3).
fn paper_ball() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/ball-on-sine.toml");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_report_plays_in_a_browser() {
    if !browser_available() {
        return;
    }
    let started = Instant::now();
    let scratch = Scratch::new(&paper_ball());
    assert_exit(&scratch.run(&["--report"]), 0);
    let out = scratch.path("out");
    let summary = summary(&out);
    let t_switch = summary["zeno"][0]["t_switch"]
        .as_f64()
        .expect("a Zeno point");
    let first_impact = summary["events"][0]["t"].as_f64().expect("an impact");

    let driver = Driver::start();
    let session = driver.session();
    let url = format!("file://{}", out.join("report.html").display());
    session.post("url", json!({ "url": url }));

    // Loaded, with no error.
    let errors = session.script("return window.zenosimErrors;", json!([]));
    assert_eq!(errors, json!([]), "the page reported errors");
    let ready = session.script("return typeof window.zenosimReport;", json!([]));
    assert_eq!(ready, json!("object"), "the page's script ran to its end");
    let severe: Vec<Value> = session
        .browser_log()
        .into_iter()
        .filter(|entry| entry["level"] == "SEVERE")
        .collect();
    assert!(severe.is_empty(), "the browser logged errors: {severe:?}");
    let shots = screenshots_dir();
    let start = session.screenshot(&shots.join("report-start.png"));
    // Frictionless: no friction states (their strip takes no room), no impulses' columns.
    let frictionless = session.script(
        "return [document.getElementById('grips').offsetHeight, \
           document.getElementById('grips-legend').offsetHeight, \
           document.getElementById('grip-row').offsetHeight, \
           document.querySelectorAll('#events-table th').length];",
        json!([]),
    );
    assert_eq!(frictionless, json!([0, 0, 0, 4]));

    // The plots: the wheel zooms in time, the pointer reads the values, a box hides a series.
    let charts = session.script(
        "const c = document.querySelector('.chart canvas'); const r = c.getBoundingClientRect(); \
         const at = { clientX: r.left + r.width / 2, clientY: r.top + r.height / 2, bubbles: true }; \
         c.dispatchEvent(new WheelEvent('wheel', Object.assign({ deltaY: -500, cancelable: true }, at))); \
         c.dispatchEvent(new PointerEvent('pointermove', at)); \
         document.querySelector('.chart .legend input').click(); \
         return window.zenosimReport.charts();",
        json!([]),
    );
    let first = &charts[0];
    assert_eq!(first["name"], "Displacements");
    let (x0, x1) = (
        first["x"][0].as_f64().unwrap(),
        first["x"][1].as_f64().unwrap(),
    );
    assert!(
        x0 > 0.0 && x1 < 6.0 && x1 - x0 < 3.0,
        "zoomed to [{x0}, {x1}]"
    );
    assert_eq!(first["on"], json!([false, true, true]));
    let value = first["value"].as_str().unwrap();
    assert!(value.contains("t = ") && value.contains("x2 = "), "{value}");
    session.script(
        "document.querySelector('.chart canvas').dispatchEvent(new MouseEvent('dblclick'));",
        json!([]),
    );

    // Played, the animation advances.
    let state = session.state();
    assert_eq!(state["t"].as_f64(), Some(0.0));
    assert_eq!(state["playing"], json!(false));
    session.click("#play");
    std::thread::sleep(Duration::from_millis(600));
    let state = session.state();
    let t = state["t"].as_f64().unwrap();
    assert_eq!(state["playing"], json!(true));
    assert!(
        t > 0.05 && t < 5.0,
        "after 0.6 s of play at real speed, t = {t}"
    );
    session.click("#play");
    assert_eq!(session.state()["playing"], json!(false));

    // Near the Zeno point it slows down: 0.1 s before it, 0.6 s of play at real speed do not
    // reach it (the last 0.25 s before it take about 3 s).
    let before = t_switch - 0.1;
    session.script("window.zenosimReport.seek(arguments[0]);", json!([before]));
    session.click("#play");
    std::thread::sleep(Duration::from_millis(600));
    let t = session.state()["t"].as_f64().unwrap();
    session.click("#play");
    assert!(
        t > before && t < t_switch,
        "t = {t}, the Zeno point at {t_switch}"
    );

    // Before the first impact the ball is well above the surface.
    let contact = |state: &Value| {
        let names = state["names"].as_array().expect("the drawing's points");
        let k = names
            .iter()
            .position(|n| n == "contact")
            .expect("the contact point");
        let p = &state["points"][k];
        (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
    };
    let state = session.scrub(first_impact - 0.2);
    let (x, y) = contact(&state);
    assert!(y - x.sin() > 0.05, "before the first impact: {x}, {y}");

    // The scrubber moved to the Zeno point: the ball on the surface, the constraint held.
    let state = session.scrub(t_switch);
    assert!((state["t"].as_f64().unwrap() - t_switch).abs() < 1e-12);
    assert_eq!(state["held"], json!(["surface"]));
    let (x, y) = contact(&state);
    assert!(
        (y - x.sin()).abs() < 1e-6,
        "the ball at ({x}, {y}), {} from the surface",
        y - x.sin()
    );
    let q = state["q"].as_array().unwrap();
    let (q2, q3) = (q[1].as_f64().unwrap(), q[2].as_f64().unwrap());
    assert!((q3 - q2.sin()).abs() < 1e-9, "q = {q:?}");
    assert!((x - q2).abs() < 1e-6 && (y - q3).abs() < 1e-6);
    let zeno = session.screenshot(&shots.join("report-zeno.png"));

    // The screenshots show something: many colours, much of the page not white.
    for (name, image) in [("start", &start), ("zeno", &zeno)] {
        assert!(image.colours > 20, "{name}: {} colours", image.colours);
        assert!(
            image.inked > 0.02,
            "{name}: {:.1}% of the pixels not white",
            100.0 * image.inked
        );
    }
    let errors = session.script("return window.zenosimErrors;", json!([]));
    assert_eq!(errors, json!([]), "the page reported errors");
    eprintln!(
        "report_browser: checked in {:.1} s; screenshots in {}",
        started.elapsed().as_secs_f64(),
        shots.display()
    );
}

/// The report of a run with friction (the block on the belt: stick-slip) in the browser: no
/// error; the readout says whether the belt sticks or slips at the time shown, as the mode of
/// the run says; the strip of friction states under the scrubber is shown; the tangential
/// force has its plot; the events' table has the impulses' columns and the energy balance the
/// work of friction. Screenshots under target/tmp/report-browser/report-friction-*.png.
#[test]
fn the_report_of_a_run_with_friction_shows_its_states_in_a_browser() {
    if !browser_available() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/belt-stick-slip.toml");
    let model = std::fs::read_to_string(&path).expect("the shipped belt");
    let scratch = Scratch::new(&model);
    assert_exit(&scratch.run(&["--report"]), 0);
    let out = scratch.path("out");
    let summary = summary(&out);
    let events = summary["events"].as_array().expect("events");
    let time_of = |kind: &str| {
        events
            .iter()
            .find(|e| e["kind"] == kind)
            .and_then(|e| e["t"].as_f64())
            .unwrap_or_else(|| panic!("a {kind} event"))
    };
    let (stick, slip) = (time_of("stick"), time_of("slip"));
    assert!(
        stick < slip,
        "the block sticks first ({stick}), then slips ({slip})"
    );

    let driver = Driver::start();
    let session = driver.session();
    let url = format!("file://{}", out.join("report.html").display());
    session.post("url", json!({ "url": url }));
    let errors = session.script("return window.zenosimErrors;", json!([]));
    assert_eq!(errors, json!([]), "the page reported errors");

    // Between its first stick and its first slip the block rides the belt; after the slip it
    // slips. The readout says so, and so does the state.
    let grip = |t: f64| {
        let state = session.scrub(t);
        let text = session.script(
            "return document.getElementById('grip').textContent;",
            json!([]),
        );
        (state, text)
    };
    let (state, text) = grip(0.5 * (stick + slip));
    assert_eq!(state["stick"], json!(["belt"]), "{state}");
    assert_eq!(state["slip"], json!([]), "{state}");
    assert_eq!(text, json!("belt sticks"));
    let shots = screenshots_dir();
    let sticking = session.screenshot(&shots.join("report-friction-stick.png"));
    let (state, text) = grip(slip + 0.1);
    assert_eq!(state["slip"], json!(["belt"]), "{state}");
    assert_eq!(text, json!("belt slips"));
    let _ = session.screenshot(&shots.join("report-friction-slip.png"));

    let page = session.script(
        "const shown = (id) => !document.getElementById(id).hidden; \
         const headings = (id) => Array.from(document.querySelectorAll('#' + id + ' th')) \
           .map((th) => th.textContent); \
         const cells = (id) => Array.from(document.querySelectorAll('#' + id + ' td')) \
           .map((td) => td.textContent); \
         return { strip: shown('grips') && document.getElementById('grips').clientHeight > 0, \
           legend: shown('grips-legend'), row: shown('grip-row'), \
           charts: window.zenosimReport.charts().map((c) => c.name), \
           events: headings('events-table'), balance: cells('balance-table') };",
        json!([]),
    );
    assert_eq!(page["strip"], json!(true), "{page}");
    assert_eq!(page["legend"], json!(true), "{page}");
    assert_eq!(page["row"], json!(true), "{page}");
    assert_eq!(
        page["charts"],
        json!(["Displacements", "Velocities", "Energy", "Tangential forces"])
    );
    assert_eq!(
        page["events"],
        json!([
            "",
            "kind",
            "t",
            "constraint",
            "impulse",
            "tangential impulse"
        ])
    );
    let balance: Vec<&str> = page["balance"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    let at = balance
        .iter()
        .position(|c| *c == "work of friction")
        .expect("the work of friction in the balance");
    let work: f64 = balance[at + 1].parse().expect("a number");
    let expected = summary["energy_balance"]["work_friction"].as_f64().unwrap();
    assert!(
        (work - expected).abs() <= 1e-8 * expected.abs(),
        "{work} vs {expected}"
    );
    assert!(sticking.colours > 20 && sticking.inked > 0.02);
    let errors = session.script("return window.zenosimErrors;", json!([]));
    assert_eq!(errors, json!([]), "the page reported errors");
}

/// Whether Chromium and its driver are installed; their absence fails the test when
/// ZENOSIM_BROWSER_TEST=required, and skips it with a note otherwise.
fn browser_available() -> bool {
    let present = Path::new(CHROMIUM).exists() && Path::new(CHROMEDRIVER).exists();
    let required = std::env::var("ZENOSIM_BROWSER_TEST").is_ok_and(|v| v == "required");
    if !present {
        assert!(
            !required,
            "ZENOSIM_BROWSER_TEST=required, but {CHROMIUM} or {CHROMEDRIVER} is missing: \
             install Debian's chromium and chromium-driver"
        );
        eprintln!(
            "note: report_browser skipped: {CHROMIUM} or {CHROMEDRIVER} is missing (install \
             Debian's chromium and chromium-driver to run it)"
        );
    }
    present
}

/// Where the screenshots go: target/tmp/report-browser/.
fn screenshots_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-browser");
    std::fs::create_dir_all(&dir).expect("the screenshots' directory");
    dir
}

/// chromedriver, on a free port of this machine; killed when dropped.
struct Driver {
    child: Child,
    port: u16,
}

impl Driver {
    fn start() -> Self {
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let child = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let driver = Self { child, port };
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            if let Ok((200, status)) = driver.request("GET", "/status", None) {
                if status["value"]["ready"] == json!(true) {
                    return driver;
                }
            }
            assert!(
                Instant::now() < deadline,
                "chromedriver is not ready after 20 s"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// A new session of headless Chromium, on a profile of its own.
    fn session(&self) -> Session<'_> {
        let profile = tempfile::tempdir().expect("a profile directory");
        let args = [
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-dev-shm-usage",
            "--window-size=1200,1500",
            &format!("--user-data-dir={}", profile.path().display()),
        ];
        let capabilities = json!({ "capabilities": { "alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": { "binary": CHROMIUM, "args": args },
            "goog:loggingPrefs": { "browser": "ALL" },
        }}});
        let (status, reply) = self
            .request("POST", "/session", Some(&capabilities))
            .expect("chromedriver answers");
        assert_eq!(status, 200, "a session: {reply}");
        let id = reply["value"]["sessionId"]
            .as_str()
            .expect("a session id")
            .to_string();
        Session {
            driver: self,
            id,
            _profile: profile,
        }
    }

    /// One HTTP request: the status and the JSON reply.
    fn request(
        &self,
        method: &str,
        path: &str,
        body: Option<&Value>,
    ) -> std::io::Result<(u16, Value)> {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port))?;
        stream.set_read_timeout(Some(Duration::from_secs(60)))?;
        let body = body.map(Value::to_string).unwrap_or_default();
        write!(
            stream,
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nContent-Type: application/json; \
             charset=utf-8\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.port,
            body.len()
        )?;
        // chromedriver keeps the connection open: read the head, then the body's length.
        let mut reply = Vec::new();
        let mut buffer = [0u8; 1 << 16];
        let head_end = loop {
            if let Some(end) = reply.windows(4).position(|w| w == b"\r\n\r\n") {
                break end + 4;
            }
            let read = stream.read(&mut buffer)?;
            if read == 0 {
                break reply.len();
            }
            reply.extend_from_slice(&buffer[..read]);
        };
        let head = String::from_utf8_lossy(&reply[..head_end]).to_ascii_lowercase();
        let status = head
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        let header = |name: &str| {
            head.lines()
                .find_map(|line| line.strip_prefix(name))
                .map(|v| v.trim().to_string())
        };
        let chunked = header("transfer-encoding:").is_some_and(|v| v == "chunked");
        let length: Option<usize> = header("content-length:").and_then(|v| v.parse().ok());
        loop {
            let body = &reply[head_end..];
            let complete = match length {
                Some(length) => body.len() >= length,
                None if chunked => body.ends_with(b"0\r\n\r\n"),
                None => false,
            };
            if complete {
                break;
            }
            let read = stream.read(&mut buffer)?;
            if read == 0 {
                break;
            }
            reply.extend_from_slice(&buffer[..read]);
        }
        let body = String::from_utf8_lossy(&reply[head_end..]).into_owned();
        let body = if chunked { dechunk(&body) } else { body };
        let value = serde_json::from_str(&body).unwrap_or(Value::Null);
        Ok((status, value))
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An HTTP body sent in chunks, joined.
fn dechunk(mut body: &str) -> String {
    let mut out = String::new();
    while let Some((size, rest)) = body.split_once("\r\n") {
        let size = usize::from_str_radix(size.trim(), 16).unwrap_or(0);
        if size == 0 || rest.len() < size {
            break;
        }
        out.push_str(&rest[..size]);
        body = rest[size..].trim_start_matches("\r\n");
    }
    out
}

/// A browser session; closed (the browser ended) when dropped.
struct Session<'a> {
    driver: &'a Driver,
    id: String,
    _profile: tempfile::TempDir,
}

/// What a screenshot shows: how many colours, and the fraction of pixels not white.
struct Image {
    colours: usize,
    inked: f64,
}

impl Session<'_> {
    fn post(&self, command: &str, body: Value) -> Value {
        let path = format!("/session/{}/{command}", self.id);
        let (status, reply) = self
            .driver
            .request("POST", &path, Some(&body))
            .unwrap_or_else(|e| panic!("{command}: {e}"));
        assert_eq!(status, 200, "{command}: {reply}");
        reply["value"].clone()
    }

    fn script(&self, script: &str, args: Value) -> Value {
        self.post("execute/sync", json!({ "script": script, "args": args }))
    }

    fn state(&self) -> Value {
        self.script("return window.zenosimReport.state();", json!([]))
    }

    /// Moves the scrubber to `t`, as a pointer would (an `input` event), and returns the state.
    fn scrub(&self, t: f64) -> Value {
        self.script(
            "const s = document.getElementById('scrubber'); s.value = String(arguments[0]); \
             s.dispatchEvent(new Event('input', { bubbles: true })); \
             return window.zenosimReport.state();",
            json!([t]),
        )
    }

    fn click(&self, selector: &str) {
        let element = self.post(
            "element",
            json!({ "using": "css selector", "value": selector }),
        );
        let id = element
            .as_object()
            .and_then(|o| o.values().next())
            .and_then(Value::as_str)
            .expect("the element")
            .to_string();
        self.post(&format!("element/{id}/click"), json!({}));
    }

    /// The browser's log since the last call (chromedriver's extension; empty if it has none).
    fn browser_log(&self) -> Vec<Value> {
        let path = format!("/session/{}/se/log", self.id);
        match self
            .driver
            .request("POST", &path, Some(&json!({ "type": "browser" })))
        {
            Ok((200, reply)) => reply["value"].as_array().cloned().unwrap_or_default(),
            _ => Vec::new(),
        }
    }

    /// A screenshot of the window, saved to `path` and measured.
    fn screenshot(&self, path: &Path) -> Image {
        let (status, reply) = self
            .driver
            .request("GET", &format!("/session/{}/screenshot", self.id), None)
            .expect("a screenshot");
        assert_eq!(status, 200, "screenshot: {reply}");
        let bytes = base64(reply["value"].as_str().expect("base64 PNG"));
        std::fs::write(path, &bytes).expect("the screenshot is saved");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut pixels).expect("its pixels");
        let channels = info.color_type.samples();
        let pixels = &pixels[..info.buffer_size()];
        let mut colours = std::collections::HashSet::new();
        let mut inked = 0usize;
        for p in pixels.chunks(channels) {
            let rgb = [p[0], p[1 % channels], p[2 % channels]];
            colours.insert(rgb);
            inked += usize::from(rgb != [255, 255, 255]);
        }
        Image {
            colours: colours.len(),
            inked: inked as f64 / (pixels.len() / channels).max(1) as f64,
        }
    }
}

impl Drop for Session<'_> {
    fn drop(&mut self) {
        let _ = self
            .driver
            .request("DELETE", &format!("/session/{}", self.id), None);
    }
}

/// Standard base64 (RFC 4648), decoded.
fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut bits, mut count) = (0u32, 0);
    for v in text.bytes().filter_map(value) {
        bits = (bits << 6) | u32::from(v);
        count += 6;
        if count >= 8 {
            count -= 8;
            out.push((bits >> count) as u8);
        }
    }
    out
}

#[test]
fn base64_decodes() {
    assert_eq!(base64("aGVsbG8="), b"hello");
    assert_eq!(base64("aGVsbG8gd29ybGQ"), b"hello world");
    assert_eq!(base64(""), b"");
}
