// The report of a zenosim run: the animation of the mechanism, the plots, the events, the
// Zeno points and the energy balance, drawn on canvases from the JSON in #zenosim-data (written
// by `zenosim report`); with friction, the contacts' stick and slip states over time too.
// No library: everything here is plain DOM and canvas.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("zenosim-data").textContent);
  const frames = data.frames;
  const frameCount = frames.t.length;
  const n = data.coordinates.length;
  const [tStart, tEnd] = data.span;
  const palette = ["#1f5fbf", "#d9822b", "#2e8b57", "#8e44ad", "#c0392b", "#16a2b8",
    "#7f6a00", "#e84393", "#34495e", "#6d8c00"];
  // The constraints with friction (none in a frictionless run), and the colours of their
  // states: sticking, slipping (as the plots mark a change to each).
  const friction = data.friction || [];
  const STICK = "#aa00dc";
  const SLIP = "#e3b3f0";
  const $ = (id) => document.getElementById(id);

  // ---- Numbers -------------------------------------------------------------------------------

  // A number for a reader: `digits` significant digits, no trailing noise.
  function fmt(x, digits) {
    if (x === null || x === undefined || !isFinite(x)) return "—";
    if (x === 0) return "0";
    const a = Math.abs(x);
    if (a >= 1e-4 && a < 1e7) return String(Number(x.toPrecision(digits || 6)));
    return x.toExponential((digits || 6) - 1).replace(/\.?0+e/, "e");
  }

  // Round tick values covering [lo, hi], about `count` of them.
  function ticks(lo, hi, count) {
    const span = hi - lo;
    if (!(span > 0) || !isFinite(span)) return [lo];
    const raw = span / Math.max(1, count);
    const power = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw) || 10 * power;
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
      out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
      if (out.length > 100) break;
    }
    return out;
  }

  // The last index i with values[i] <= x (-1 if none), values sorted.
  function lastAtOrBefore(values, x) {
    let lo = 0;
    let hi = values.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (values[mid] <= x) lo = mid + 1; else hi = mid;
    }
    return lo - 1;
  }

  // A canvas sized to its box in device pixels; its context drawing in CSS pixels.
  function fit(canvas) {
    const ratio = window.devicePixelRatio || 1;
    const width = Math.max(1, canvas.clientWidth);
    const height = Math.max(1, canvas.clientHeight);
    if (canvas.width !== Math.round(width * ratio) || canvas.height !== Math.round(height * ratio)) {
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(height * ratio);
    }
    const ctx = canvas.getContext("2d");
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, width, height);
    return { ctx, width, height };
  }

  // ---- The run's state at a time ---------------------------------------------------------------

  // The frame before or at t and the fraction of the way to the next: at an event's time, the
  // row after the event (the later of its two rows).
  function locate(t) {
    const i = Math.max(0, lastAtOrBefore(frames.t, t));
    if (i >= frameCount - 1) return { i: frameCount - 1, s: 0 };
    const t0 = frames.t[i];
    const t1 = frames.t[i + 1];
    const s = t1 > t0 ? Math.min(1, Math.max(0, (t - t0) / (t1 - t0))) : 0;
    return { i, s };
  }

  function modeAt(i) {
    return data.modes[frames.mode[i]] || "";
  }

  // The constraints held in a mode `constrained:a+b`, or `constrained:a+b;stick:a;slip:b`
  // with friction (the contacts' states after the first `;` are left aside).
  function held(mode) {
    const semicolon = mode.indexOf(";");
    const heldPart = semicolon < 0 ? mode : mode.slice(0, semicolon);
    const colon = heldPart.indexOf(":");
    return colon < 0 ? [] : heldPart.slice(colon + 1).split("+").filter((c) => c.length > 0);
  }

  // The contacts that stick and those that slip in a mode `…;stick:a+b;slip:c`.
  function grips(mode) {
    const out = { stick: [], slip: [] };
    mode.split(";").slice(1).forEach((part) => {
      const colon = part.indexOf(":");
      const label = part.slice(0, colon);
      if (label !== "stick" && label !== "slip") return;
      part.slice(colon + 1).split("+").forEach((c) => { if (c.length > 0) out[label].push(c); });
    });
    return out;
  }
  const modeGrips = data.modes.map(grips);

  // How the timeline and the plots mark an event of `kind`: its colour and its height.
  function eventMark(kind) {
    if (kind === "liftoff") return { color: "#2e8b57", height: 14 };
    if (kind === "stick") return { color: STICK, height: 12 };
    if (kind === "slip") return { color: "#c77ddb", height: 12 };
    return { color: "#5b6575", height: 10 };
  }

  function qAt(at) {
    const q = [];
    for (let k = 0; k < n; k++) {
      const a = frames.q[at.i * n + k];
      const b = at.s > 0 ? frames.q[(at.i + 1) * n + k] : a;
      q.push(a + at.s * (b - a));
    }
    return q;
  }

  // ---- The mechanism -------------------------------------------------------------------------

  const mech = data.mechanism;
  const mechCanvas = $("mechanism");
  let points = null; // the points' x, y at the current time
  let bounds = null;

  if (mech) {
    const count = mech.points.length;
    points = new Float64Array(2 * count);
    // The box of every position the points take over the run.
    let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
    const grow = (x, y) => {
      if (!isFinite(x) || !isFinite(y)) return;
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
    };
    mech.fixed.forEach((p) => { if (p) grow(p[0], p[1]); });
    const moving = mech.moving.length;
    for (let f = 0; f < frameCount; f++) {
      for (let m = 0; m < moving; m++) {
        grow(mech.positions[(f * moving + m) * 2], mech.positions[(f * moving + m) * 2 + 1]);
      }
    }
    // Circles reach out by their radius.
    let reach = 0;
    mech.shapes.forEach((s) => { if (s.circle !== undefined) reach = Math.max(reach, s.radius); });
    if (!isFinite(x0)) { x0 = -1; x1 = 1; y0 = -1; y1 = 1; }
    bounds = { x0: x0 - reach, x1: x1 + reach, y0: y0 - reach, y1: y1 + reach };
    if (mech.dimension === 3) {
      $("mechanism-note").hidden = false;
      $("mechanism-note").textContent = "A 3-D drawing, shown in its x–y projection.";
      $("mechanism-note").style.top = "auto";
      $("mechanism-note").style.bottom = "1rem";
    }
  } else {
    $("mechanism-note").hidden = false;
    $("mechanism-note").textContent = data.note || "No drawing of the mechanism.";
  }

  function placePoints(at) {
    if (!mech) return;
    const moving = mech.moving.length;
    mech.fixed.forEach((p, k) => {
      if (p) { points[2 * k] = p[0]; points[2 * k + 1] = p[1]; }
    });
    const next = at.s > 0 ? at.i + 1 : at.i;
    for (let m = 0; m < moving; m++) {
      const k = mech.moving[m];
      for (let j = 0; j < 2; j++) {
        const a = mech.positions[(at.i * moving + m) * 2 + j];
        const b = mech.positions[(next * moving + m) * 2 + j];
        points[2 * k + j] = a + at.s * (b - a);
      }
    }
  }

  // The position of point k at frame f.
  function pointAtFrame(k, f) {
    const fixed = mech.fixed[k];
    if (fixed) return fixed;
    const m = mech.movingIndex[k];
    const moving = mech.moving.length;
    return [mech.positions[(f * moving + m) * 2], mech.positions[(f * moving + m) * 2 + 1]];
  }

  if (mech) {
    mech.movingIndex = {};
    mech.moving.forEach((k, m) => { mech.movingIndex[k] = m; });
  }

  function drawMechanism(at, heldNow, gripNow) {
    const { ctx, width, height } = fit(mechCanvas);
    if (!mech) return;
    const pad = 24;
    const spanX = Math.max(bounds.x1 - bounds.x0, 1e-12);
    const spanY = Math.max(bounds.y1 - bounds.y0, 1e-12);
    const scale = Math.min((width - 2 * pad) / spanX, (height - 2 * pad) / spanY);
    const ox = (width - scale * spanX) / 2 - scale * bounds.x0;
    const oy = (height + scale * spanY) / 2 + scale * bounds.y0;
    const X = (x) => ox + scale * x;
    const Y = (y) => oy - scale * y;
    const P = (k) => [X(points[2 * k]), Y(points[2 * k + 1])];
    ctx.lineJoin = "round";
    ctx.lineCap = "round";

    // The trace of the chosen point, up to now.
    if (trace >= 0) {
      ctx.strokeStyle = "rgba(31, 95, 191, 0.55)";
      ctx.lineWidth = 1.2;
      ctx.beginPath();
      for (let f = 0; f <= at.i; f++) {
        const p = pointAtFrame(trace, f);
        if (f === 0) ctx.moveTo(X(p[0]), Y(p[1])); else ctx.lineTo(X(p[0]), Y(p[1]));
      }
      const [cx, cy] = P(trace);
      ctx.lineTo(cx, cy);
      ctx.stroke();
    }

    const inShape = new Uint8Array(mech.points.length);
    mech.shapes.forEach((shape) => {
      ctx.lineWidth = 2;
      ctx.strokeStyle = "#1d2430";
      ctx.fillStyle = "rgba(31, 95, 191, 0.25)";
      if (shape.segment) {
        const [a, b] = shape.segment;
        inShape[a] = inShape[b] = 1;
        ctx.beginPath();
        ctx.moveTo(...P(a));
        ctx.lineTo(...P(b));
        ctx.stroke();
      } else if (shape.polyline || shape.surface) {
        const list = shape.polyline || shape.surface;
        list.forEach((k) => { inShape[k] = 1; });
        // A surface held is red, dashed in orange where its contact slips.
        let slipping = false;
        if (shape.surface) {
          const name = data.constraints[shape.constraint];
          const isHeld = heldNow.indexOf(name) >= 0;
          slipping = isHeld && gripNow.slip.indexOf(name) >= 0;
          ctx.strokeStyle = slipping ? "#d9822b" : isHeld ? "#c0392b" : "#6b7280";
          ctx.lineWidth = isHeld ? 3.5 : 2;
        }
        ctx.beginPath();
        list.forEach((k, j) => { if (j === 0) ctx.moveTo(...P(k)); else ctx.lineTo(...P(k)); });
        if (shape.closed) ctx.closePath();
        if (slipping) ctx.setLineDash([8, 5]);
        ctx.stroke();
        ctx.setLineDash([]);
      } else if (shape.circle !== undefined) {
        inShape[shape.circle] = 1;
        const [cx, cy] = P(shape.circle);
        ctx.beginPath();
        ctx.arc(cx, cy, Math.max(2, scale * shape.radius), 0, 2 * Math.PI);
        ctx.fill();
        ctx.stroke();
      }
    });
    // Points no shape draws: dots.
    ctx.fillStyle = "#1d2430";
    for (let k = 0; k < mech.points.length; k++) {
      if (inShape[k]) continue;
      const [cx, cy] = P(k);
      ctx.beginPath();
      ctx.arc(cx, cy, 3, 0, 2 * Math.PI);
      ctx.fill();
    }
    if (trace >= 0) {
      const [cx, cy] = P(trace);
      ctx.fillStyle = "#1f5fbf";
      ctx.beginPath();
      ctx.arc(cx, cy, 3, 0, 2 * Math.PI);
      ctx.fill();
    }
  }

  // ---- The trace selector -----------------------------------------------------------------------

  let trace = -1;
  const traceSelect = $("trace");
  if (mech) {
    const none = document.createElement("option");
    none.value = "-1";
    none.textContent = "none";
    traceSelect.appendChild(none);
    mech.points.forEach((name, k) => {
      if (name.indexOf("#") >= 0) return; // a surface's sampled points
      const option = document.createElement("option");
      option.value = String(k);
      option.textContent = name;
      traceSelect.appendChild(option);
    });
    trace = mech.trace === null || mech.trace === undefined ? -1 : mech.trace;
    traceSelect.value = String(trace);
    traceSelect.addEventListener("change", () => { trace = Number(traceSelect.value); render(); });
  } else {
    $("trace-label").hidden = true;
  }

  // ---- The state readout ---------------------------------------------------------------------

  const stateTable = $("state");
  const stateCells = data.coordinates.map((name) => {
    const row = stateTable.insertRow();
    row.insertCell().textContent = name;
    return row.insertCell();
  });

  // ---- Playing -------------------------------------------------------------------------------

  let time = tStart;
  let playing = false;
  let lastWall = null;
  const scrubber = $("scrubber");
  scrubber.min = String(tStart);
  scrubber.max = String(tEnd > tStart ? tEnd : tStart + 1);
  scrubber.value = String(tStart);
  const playButton = $("play");
  const speedSelect = $("speed");
  const slowBox = $("slow");
  // Within this time of a Zeno point the animation slows in proportion to the time left.
  const slowWindow = Math.min(0.25, 0.05 * Math.max(tEnd - tStart, 1e-9));
  const slowest = 1e-5;

  function rate(t) {
    let factor = 1;
    if (slowBox.checked) {
      data.zeno.forEach((z) => {
        const left = z.t_switch - t;
        if (left > 0 && left < slowWindow) factor = Math.min(factor, Math.max(slowest, left / slowWindow));
      });
    }
    return Number(speedSelect.value) * factor;
  }

  function step(wall) {
    if (!playing) return;
    if (lastWall !== null) {
      const elapsed = Math.min(0.1, (wall - lastWall) / 1000);
      let next = time + elapsed * rate(time);
      // Never jump over a Zeno point's switch: stop on it, then go on.
      data.zeno.forEach((z) => { if (time < z.t_switch && next > z.t_switch) next = z.t_switch; });
      time = Math.min(next, tEnd);
    }
    lastWall = wall;
    if (time >= tEnd) setPlaying(false);
    render();
    if (playing) requestAnimationFrame(step);
  }

  function setPlaying(on) {
    if (on && time >= tEnd) time = tStart;
    playing = on;
    lastWall = null;
    playButton.textContent = on ? "Pause" : "Play";
    if (on) requestAnimationFrame(step);
  }

  function seek(t) {
    time = Math.min(Math.max(Number(t), tStart), tEnd);
    render();
  }

  playButton.addEventListener("click", () => setPlaying(!playing));
  // The scrubber moves by pixels (and a range input keeps fewer digits than a time needs):
  // within half a pixel of a Zeno point's switch it lands exactly on it, where the state after
  // the switch is shown.
  scrubber.addEventListener("input", () => {
    let t = Number(scrubber.value);
    const pixel = (tEnd - tStart) / Math.max(1, scrubber.clientWidth);
    data.zeno.forEach((z) => { if (Math.abs(z.t_switch - t) <= 0.5 * pixel) t = z.t_switch; });
    seek(t);
  });

  // ---- The timeline's marks ------------------------------------------------------------------

  const marks = $("marks");
  function drawMarks() {
    const { ctx, width, height } = fit(marks);
    // The range input's thumb travels its width less about its own width.
    const inset = 8;
    const X = (t) => inset + (width - 2 * inset) * (t - tStart) / Math.max(tEnd - tStart, 1e-300);
    const kinds = data.events.kinds;
    ctx.lineWidth = 1;
    for (let e = 0; e < data.events.t.length; e++) {
      const mark = eventMark(kinds[data.events.kind[e]]);
      const x = X(data.events.t[e]);
      ctx.strokeStyle = mark.color;
      ctx.beginPath();
      ctx.moveTo(x, height - mark.height);
      ctx.lineTo(x, height);
      ctx.stroke();
    }
    ctx.font = "11px system-ui, sans-serif";
    // Each Zeno point a red line, labelled where there is room (a run of thousands of them
    // draws a line per pixel at most).
    let drawn = -Infinity;
    let labelled = -Infinity;
    ctx.strokeStyle = "#c0392b";
    ctx.fillStyle = "#c0392b";
    ctx.lineWidth = data.zeno.length > 50 ? 1 : 2;
    data.zeno.forEach((z, k) => {
      const x = X(z.t_switch);
      if (x - drawn < 1) return;
      drawn = x;
      ctx.beginPath();
      ctx.moveTo(x, 12);
      ctx.lineTo(x, height);
      ctx.stroke();
      const at = Math.min(x + 3, width - 60);
      if (at - labelled > 60) {
        ctx.fillText("Zeno " + (k + 1), at, 11);
        labelled = at;
      }
    });
    const x = X(time);
    ctx.fillStyle = "#1f5fbf";
    ctx.beginPath();
    ctx.moveTo(x - 5, 0);
    ctx.lineTo(x + 5, 0);
    ctx.lineTo(x, 7);
    ctx.fill();
  }
  marks.addEventListener("click", (e) => {
    const box = marks.getBoundingClientRect();
    seek(tStart + (tEnd - tStart) * (e.clientX - box.left - 8) / Math.max(1, box.width - 16));
  });

  // ---- The contacts' friction states over time -------------------------------------------------

  // Under the scrubber, a row per constraint with friction: where it is held sticking, where
  // slipping (blank where not held), from the frames' modes. Each row's spans of one state.
  const gripsCanvas = $("grips");
  const gripRow = 14;
  const gripSpans = friction.map((name) => {
    const spans = [];
    for (let f = 0; f < frameCount; f++) {
      const g = modeGrips[frames.mode[f]];
      const state = g.stick.indexOf(name) >= 0 ? "stick" : g.slip.indexOf(name) >= 0 ? "slip" : null;
      const last = spans[spans.length - 1];
      if (last && last.state === state) continue;
      if (last) last.to = frames.t[f];
      spans.push({ state, from: frames.t[f], to: tEnd });
    }
    return spans.filter((s) => s.state !== null);
  });
  if (friction.length) {
    gripsCanvas.hidden = false;
    gripsCanvas.style.height = (friction.length * gripRow + 2) + "px";
    $("grips-legend").hidden = false;
    $("grip-row").hidden = false;
  }

  function drawGrips() {
    if (!friction.length) return;
    const { ctx, width, height } = fit(gripsCanvas);
    const inset = 8;
    const X = (t) => inset + (width - 2 * inset) * (t - tStart) / Math.max(tEnd - tStart, 1e-300);
    ctx.font = "10px system-ui, sans-serif";
    friction.forEach((name, r) => {
      const y = 1 + r * gripRow;
      ctx.fillStyle = "#f1f3f6";
      ctx.fillRect(inset, y, width - 2 * inset, gripRow - 2);
      gripSpans[r].forEach((s) => {
        ctx.fillStyle = s.state === "stick" ? STICK : SLIP;
        ctx.fillRect(X(s.from), y, Math.max(X(s.to) - X(s.from), 1), gripRow - 2);
      });
      ctx.lineWidth = 3;
      ctx.strokeStyle = "rgba(255, 255, 255, 0.85)";
      ctx.strokeText(name, inset + 3, y + 10);
      ctx.fillStyle = "#1d2430";
      ctx.fillText(name, inset + 3, y + 10);
    });
    ctx.strokeStyle = "#1f5fbf";
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(X(time), 0);
    ctx.lineTo(X(time), height);
    ctx.stroke();
  }
  gripsCanvas.addEventListener("click", (e) => {
    const box = gripsCanvas.getBoundingClientRect();
    seek(tStart + (tEnd - tStart) * (e.clientX - box.left - 8) / Math.max(1, box.width - 16));
  });

  // ---- The plots -----------------------------------------------------------------------------

  const charts = [];
  const groups = [];
  data.series.forEach((s, k) => {
    let group = groups.find((g) => g.name === s.group);
    if (!group) { group = { name: s.group, series: [] }; groups.push(group); }
    group.series.push({ name: s.name, t: s.t, y: s.y, color: palette[k % palette.length], on: true });
  });

  function Chart(group) {
    const box = document.createElement("div");
    box.className = "chart";
    const title = document.createElement("h3");
    title.textContent = group.name;
    const legend = document.createElement("div");
    legend.className = "legend";
    const canvas = document.createElement("canvas");
    const value = document.createElement("div");
    value.className = "value";
    box.append(title, legend, canvas, value);
    $("charts").appendChild(box);
    this.group = group;
    this.canvas = canvas;
    this.value = value;
    this.x = [tStart, tEnd > tStart ? tEnd : tStart + 1];
    this.y = null; // null: fitted to what is shown
    this.hover = null;
    group.series.forEach((s) => {
      const label = document.createElement("label");
      const box = document.createElement("input");
      box.type = "checkbox";
      box.checked = true;
      box.addEventListener("change", () => { s.on = box.checked; this.draw(); });
      const swatch = document.createElement("span");
      swatch.className = "swatch";
      swatch.style.background = s.color;
      label.append(box, swatch, document.createTextNode(s.name));
      legend.appendChild(label);
    });
    this.listen();
  }

  Chart.prototype.layout = function () {
    const { ctx, width, height } = fit(this.canvas);
    return { ctx, width, height, left: 64, right: width - 12, top: 10, bottom: height - 26 };
  };

  // The value range of the series shown, over the time range shown.
  Chart.prototype.fitY = function () {
    let [lo, hi] = [Infinity, -Infinity];
    this.group.series.forEach((s) => {
      if (!s.on) return;
      const a = Math.max(0, lastAtOrBefore(s.t, this.x[0]));
      const b = Math.min(s.t.length - 1, lastAtOrBefore(s.t, this.x[1]) + 1);
      for (let i = a; i <= b; i++) {
        const v = s.y[i];
        if (v === null || !isFinite(v)) continue;
        lo = Math.min(lo, v); hi = Math.max(hi, v);
      }
    });
    if (!isFinite(lo)) return [-1, 1];
    if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) {
      const d = Math.max(Math.abs(hi) * 0.05, 1e-9);
      return [lo - d, hi + d];
    }
    const pad = 0.05 * (hi - lo);
    return [lo - pad, hi + pad];
  };

  Chart.prototype.draw = function () {
    const L = this.layout();
    const { ctx } = L;
    const [x0, x1] = this.x;
    const [y0, y1] = this.y || this.fitY();
    this.current = { L, x0, x1, y0, y1 };
    const X = (t) => L.left + (L.right - L.left) * (t - x0) / (x1 - x0);
    const Y = (v) => L.bottom - (L.bottom - L.top) * (v - y0) / (y1 - y0);
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillStyle = "#5b6575";
    ctx.strokeStyle = "#e6e9ef";
    ctx.lineWidth = 1;
    ctx.textAlign = "center";
    ticks(x0, x1, 8).forEach((t) => {
      const x = X(t);
      ctx.beginPath(); ctx.moveTo(x, L.top); ctx.lineTo(x, L.bottom); ctx.stroke();
      ctx.fillText(fmt(t, 6), x, L.bottom + 14);
    });
    ctx.textAlign = "right";
    ticks(y0, y1, 5).forEach((v) => {
      const y = Y(v);
      ctx.beginPath(); ctx.moveTo(L.left, y); ctx.lineTo(L.right, y); ctx.stroke();
      ctx.fillText(fmt(v, 5), L.left - 4, y + 4);
    });
    ctx.textAlign = "left";
    ctx.save();
    ctx.beginPath();
    ctx.rect(L.left, L.top, L.right - L.left, L.bottom - L.top);
    ctx.clip();
    // The events: impacts and lift-offs along the time axis, the Zeno points as lines.
    for (let e = 0; e < data.events.t.length; e++) {
      const t = data.events.t[e];
      if (t < x0 || t > x1) continue;
      const kind = data.events.kinds[data.events.kind[e]];
      ctx.strokeStyle = kind === "impact" || kind === "zeno" ? "#9aa3b2" : eventMark(kind).color;
      ctx.beginPath(); ctx.moveTo(X(t), L.bottom); ctx.lineTo(X(t), L.bottom - 6); ctx.stroke();
    }
    ctx.setLineDash([5, 4]);
    ctx.strokeStyle = "#c0392b";
    let drawn = -Infinity;
    data.zeno.forEach((z) => {
      const x = X(z.t_switch);
      if (x < L.left || x > L.right || x - drawn < 4) return;
      drawn = x;
      ctx.beginPath(); ctx.moveTo(x, L.top); ctx.lineTo(x, L.bottom); ctx.stroke();
    });
    ctx.setLineDash([]);
    ctx.lineWidth = 1.5;
    this.group.series.forEach((s) => {
      if (!s.on) return;
      ctx.strokeStyle = s.color;
      ctx.beginPath();
      const a = Math.max(0, lastAtOrBefore(s.t, x0));
      const b = Math.min(s.t.length - 1, lastAtOrBefore(s.t, x1) + 1);
      let pen = false;
      for (let i = a; i <= b; i++) {
        const v = s.y[i];
        if (v === null || !isFinite(v)) { pen = false; continue; }
        if (pen) ctx.lineTo(X(s.t[i]), Y(v)); else ctx.moveTo(X(s.t[i]), Y(v));
        pen = true;
      }
      ctx.stroke();
    });
    // The animation's time.
    ctx.strokeStyle = "#1f5fbf";
    ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(X(time), L.top); ctx.lineTo(X(time), L.bottom); ctx.stroke();
    // The value under the pointer.
    if (this.hover !== null) {
      const t = x0 + (x1 - x0) * (this.hover - L.left) / (L.right - L.left);
      ctx.strokeStyle = "#5b6575";
      ctx.setLineDash([2, 3]);
      ctx.beginPath(); ctx.moveTo(this.hover, L.top); ctx.lineTo(this.hover, L.bottom); ctx.stroke();
      ctx.setLineDash([]);
      const parts = ["t = " + fmt(t, 8)];
      this.group.series.forEach((s) => {
        if (!s.on || s.t.length === 0) return;
        let i = Math.max(0, lastAtOrBefore(s.t, t));
        if (i + 1 < s.t.length && Math.abs(s.t[i + 1] - t) < Math.abs(s.t[i] - t)) i += 1;
        const v = s.y[i];
        if (v === null) return;
        ctx.fillStyle = s.color;
        ctx.beginPath(); ctx.arc(X(s.t[i]), Y(v), 3.5, 0, 2 * Math.PI); ctx.fill();
        parts.push(s.name + " = " + fmt(v, 8));
      });
      this.value.textContent = parts.join("   ");
    }
    ctx.restore();
    ctx.strokeStyle = "#9aa3b2";
    ctx.strokeRect(L.left, L.top, L.right - L.left, L.bottom - L.top);
  };

  Chart.prototype.listen = function () {
    const canvas = this.canvas;
    let drag = null;
    const local = (e) => e.clientX - canvas.getBoundingClientRect().left;
    const localY = (e) => e.clientY - canvas.getBoundingClientRect().top;
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      const c = this.current;
      if (!c) return;
      const factor = Math.pow(1.0015, e.deltaY);
      if (e.shiftKey) {
        const [y0, y1] = this.y || [c.y0, c.y1];
        const at = y1 - (y1 - y0) * (localY(e) - c.L.top) / (c.L.bottom - c.L.top);
        this.y = [at + (y0 - at) * factor, at + (y1 - at) * factor];
      } else {
        const at = c.x0 + (c.x1 - c.x0) * (local(e) - c.L.left) / (c.L.right - c.L.left);
        const lo = at + (this.x[0] - at) * factor;
        const hi = at + (this.x[1] - at) * factor;
        if (hi - lo > 1e-12 * Math.max(1, Math.abs(at))) this.x = [lo, hi];
      }
      this.draw();
    }, { passive: false });
    canvas.addEventListener("pointerdown", (e) => {
      const c = this.current;
      if (!c) return;
      drag = { x: e.clientX, y: e.clientY, x0: this.x.slice(), y0: [c.y0, c.y1], moved: false };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", (e) => {
      this.hover = local(e);
      if (drag) {
        const c = this.current;
        const dx = e.clientX - drag.x;
        const dy = e.clientY - drag.y;
        if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
        if (drag.moved) {
          const per = (drag.x0[1] - drag.x0[0]) / (c.L.right - c.L.left);
          this.x = [drag.x0[0] - dx * per, drag.x0[1] - dx * per];
          if (Math.abs(dy) > 3 || this.y) {
            const perY = (drag.y0[1] - drag.y0[0]) / (c.L.bottom - c.L.top);
            this.y = [drag.y0[0] + dy * perY, drag.y0[1] + dy * perY];
          }
        }
      }
      this.draw();
    });
    canvas.addEventListener("pointerup", (e) => {
      if (drag && !drag.moved) {
        const c = this.current;
        seek(c.x0 + (c.x1 - c.x0) * (local(e) - c.L.left) / (c.L.right - c.L.left));
      }
      drag = null;
    });
    canvas.addEventListener("pointerleave", () => { this.hover = null; this.value.textContent = ""; this.draw(); });
    canvas.addEventListener("dblclick", () => {
      this.x = [tStart, tEnd > tStart ? tEnd : tStart + 1];
      this.y = null;
      this.draw();
    });
  };

  groups.forEach((g) => charts.push(new Chart(g)));

  // ---- The tables ----------------------------------------------------------------------------

  // A link that moves the animation to t.
  function seekLink(t) {
    const a = document.createElement("a");
    a.className = "seek";
    a.href = "#animation";
    a.textContent = fmt(t, 12);
    a.addEventListener("click", (e) => {
      e.preventDefault();
      setPlaying(false);
      seek(t);
      $("animation").scrollIntoView({ behavior: "smooth" });
    });
    return a;
  }

  function table(parent, headings, count, cells, shownFirst) {
    if (count === 0) return false;
    const t = document.createElement("table");
    t.className = "list";
    const head = t.createTHead().insertRow();
    headings.forEach((h) => {
      const th = document.createElement("th");
      th.textContent = h;
      head.appendChild(th);
    });
    const body = t.createTBody();
    const add = (from, to) => {
      for (let i = from; i < to; i++) {
        const row = body.insertRow();
        cells(i).forEach((c) => {
          const td = row.insertCell();
          if (c instanceof Node) td.appendChild(c); else td.textContent = c;
        });
      }
    };
    const first = Math.min(count, shownFirst);
    add(0, first);
    parent.appendChild(t);
    if (first < count) {
      const more = document.createElement("button");
      more.type = "button";
      more.textContent = "Show all " + count;
      more.addEventListener("click", () => { add(first, count); more.remove(); });
      parent.appendChild(more);
    }
    return true;
  }

  if (!table($("zeno-table"), ["", "constraints", "kind", "switch at", "τ∞ (estimate)", "impacts", "ratio"],
    data.zeno.length, (i) => {
      const z = data.zeno[i];
      return [String(i + 1), z.constraints.join(", "), z.kind, seekLink(z.t_switch), fmt(z.t_zeno, 12),
        String(z.impacts), fmt(z.ratio, 6)];
    }, 1000)) {
    $("zeno-table").textContent = "None in this run.";
  }

  const ev = data.events;
  // With friction, each impact's normal and tangential impulses: a number for an impact on one
  // contact, `name value` for each of several.
  const imp = ev.impulses;
  function impulses(i, values) {
    if (!values || values.length === 0) return "";
    if (values.length === 1) return fmt(values[0], 6);
    return values.map((v, k) => (ev.names[imp.contacts[i][k]] || "?") + " " + fmt(v, 6)).join(", ");
  }
  const eventHeadings = ["", "kind", "t", "constraint"].concat(imp ? ["impulse", "tangential impulse"] : []);
  if (!table($("events-table"), eventHeadings, ev.t.length, (i) => [
    String(i + 1), ev.kinds[ev.kind[i]], seekLink(ev.t[i]), ev.names[ev.constraint[i]] || ""]
    .concat(imp ? [impulses(i, imp.normal[i]), impulses(i, imp.tangential[i])] : []), 1000)) {
    $("events-table").textContent = "None in this run.";
  }

  // The energy balance: E(end) − E(0) = the works − the impact loss + the residual; the work of
  // friction only for a model with friction.
  const balance = data.balance;
  if (balance) {
    const terms = [
      ["E(0)", balance.energy_start],
      ["work of the forces", balance.work_forces],
      ["work of the time dependence (drive)", balance.work_drive],
      ["work of the moving constraints", balance.work_constraints],
    ];
    if ("work_friction" in balance) terms.push(["work of friction", balance.work_friction]);
    terms.push(["impact loss (taken out)", balance.impact_loss], ["E(end)", balance.energy_end],
      ["residual", balance.residual]);
    table($("balance-table"), ["", "energy"], terms.length, (i) => [terms[i][0], fmt(terms[i][1], 10)], 100);
  } else {
    $("balance-table").textContent = "Not in this summary.json (written before the energy balance was).";
  }

  // ---- The page ------------------------------------------------------------------------------

  document.title = data.model + " — zenosim report";
  $("title").textContent = data.model;
  $("description").textContent = data.description || "";
  $("outcome").textContent = "Status: " + data.status + (data.message ? " (" + data.message + ")" : "") +
    ". From t = " + fmt(tStart, 8) + " to " + fmt(tEnd, 8) + ": " + data.events.t.length + " event" +
    (data.events.t.length === 1 ? "" : "s") + ", " + data.zeno.length + " Zeno point" +
    (data.zeno.length === 1 ? "" : "s") + ".";

  function render() {
    const at = locate(time);
    const mode = modeAt(at.i);
    const heldNow = held(mode);
    const gripNow = modeGrips[frames.mode[at.i]] || { stick: [], slip: [] };
    placePoints(at);
    drawMechanism(at, heldNow, gripNow);
    $("time").textContent = fmt(time, 12);
    $("mode").textContent = mode.split(";")[0].split(":")[0];
    $("held").textContent = heldNow.length ? heldNow.join(", ") : "none";
    if (friction.length) {
      const states = gripNow.stick.map((c) => c + " sticks").concat(gripNow.slip.map((c) => c + " slips"));
      $("grip").textContent = states.length ? states.join(", ") : "none held";
    }
    const q = qAt(at);
    stateCells.forEach((cell, k) => { cell.textContent = fmt(q[k], 10); });
    if (document.activeElement !== scrubber) scrubber.value = String(time);
    drawMarks();
    drawGrips();
    charts.forEach((c) => c.draw());
  }

  window.addEventListener("resize", render);

  // What the tests (and a curious reader, from the console) can ask of the page.
  window.zenosimReport = {
    state: function () {
      const at = locate(time);
      const mode = modeAt(at.i);
      const g = grips(mode);
      const out = { t: time, playing, mode, held: held(mode), stick: g.stick, slip: g.slip, q: qAt(at),
        points: null, names: null };
      if (mech) {
        placePoints(at);
        out.points = [];
        out.names = mech.points.slice();
        for (let k = 0; k < mech.points.length; k++) out.points.push([points[2 * k], points[2 * k + 1]]);
      }
      return out;
    },
    // Each plot's name, time range shown, and which series are on.
    charts: () => charts.map((c) => ({
      name: c.group.name,
      x: c.x.slice(),
      on: c.group.series.map((s) => s.on),
      value: c.value.textContent,
    })),
    seek,
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    zeno: data.zeno,
    span: data.span,
  };

  // A link to a time: report.html#t=2.04 opens there.
  const linked = /^#t=([-+0-9.eE]+)$/.exec(window.location.hash);
  if (linked && isFinite(Number(linked[1]))) time = Math.min(Math.max(Number(linked[1]), tStart), tEnd);
  render();
  if (window.zenosimErrors.length) {
    $("errors").hidden = false;
    $("errors").textContent = window.zenosimErrors.join("; ");
  }
})();
