/* The report of a run (scriptc.views.report): reads the run's data from the page, draws the
   room from above, the flow, the tracks, the velocity and the events, and moves one cursor
   through all of them. Every text of the run is written with textContent, never as markup.
   window.scriptcReport is what a test (or a curious reader) can look at. */
"use strict";
(function () {
  const SYNC = "scriptc-run";
  const STYLE_COLOURS = ["#555b66", "#2a9d3a", "#8a8fa0", "#c99700", "#e07b00", "#d62728"];
  const CLASS_COLOURS = { Human: "#d62728", Object: "#2ca02c", Obstacle: "#555555" };
  const ROBOT = "#1f77b4";
  const ISSUED = 0, JUMP_TRUE = 1, JUMP_FALSE = 2, DONE = 5;
  const status = document.getElementById("status");

  function fail(err) {
    status.textContent = "The report cannot be shown: " + (err && err.message ? err.message : err);
    status.className = "status error";
    status.hidden = false;
    console.error(err);
  }

  // -- the data -----------------------------------------------------------------------------

  let loadStarted = 0;

  async function load() {
    loadStarted = performance.now();
    const text = document.getElementById("run").textContent.trim();
    const bin = atob(text);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    if (typeof DecompressionStream === "undefined") {
      throw new Error("this browser cannot inflate the run's data (no DecompressionStream): " +
                      "open the page in a current Chrome, Edge, Firefox or Safari");
    }
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    const buf = await new Response(stream).arrayBuffer();
    const n = new DataView(buf).getUint32(0, true);
    const model = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 4, n)));
    const start = 4 + n + ((4 - ((4 + n) % 4)) % 4);
    const floats = new Float32Array(buf, start, (buf.byteLength - start) / 4);
    return resolve(model, floats);
  }

  function resolve(value, floats) {
    if (Array.isArray(value)) return value.map(v => resolve(v, floats));
    if (value && typeof value === "object") {
      const ref = value["@"];
      if (Array.isArray(ref) && Object.keys(value).length === 1) {
        return floats.subarray(ref[0], ref[0] + ref[1]);
      }
      const out = {};
      for (const key of Object.keys(value)) out[key] = resolve(value[key], floats);
      return out;
    }
    return value;
  }

  // The last index i with a[i] <= x (-1: none); a sorted ascending.
  function lastAtOrBefore(a, x) {
    let lo = 0, hi = a.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (a[mid] <= x) lo = mid + 1; else hi = mid;
    }
    return lo - 1;
  }

  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const key in attrs || {}) e.setAttribute(key, attrs[key]);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function svg(tag, attrs, text) {
    const e = document.createElementNS("http://www.w3.org/2000/svg", tag);
    for (const key in attrs || {}) e.setAttribute(key, attrs[key]);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  const seconds = ms => (ms / 1000).toFixed(3) + " s";
  const fixed = (v, d) => (Math.abs(v) < 0.5 * Math.pow(10, -d) ? 0 : v).toFixed(d);
  const rgb = (r, g, b) => "rgb(" + Math.round(r * 255) + "," + Math.round(g * 255) + "," +
                           Math.round(b * 255) + ")";

  // -- the page -----------------------------------------------------------------------------

  function start(model) {
    const started = performance.now();
    const end = Math.max(model.end, 1);
    const texts = model.texts;
    const path = model.path;
    const report = { model: model, charts: [], ready: false, time: 0, highlighted: null,
                     flow: null };
    window.scriptcReport = report;
    status.hidden = true;
    document.getElementById("views").hidden = false;

    // The pose of the robot at t (ms), interpolated along the path.
    function poseAt(t) {
      const n = path.t.length;
      if (!n) return [0, 0, 0];
      const i = lastAtOrBefore(path.t, t);
      if (i < 0) return [path.x[0], path.y[0], path.h[0]];
      if (i >= n - 1) return [path.x[n - 1], path.y[n - 1], path.h[n - 1]];
      const f = (t - path.t[i]) / (path.t[i + 1] - path.t[i]);
      return [path.x[i] + f * (path.x[i + 1] - path.x[i]), path.y[i] + f * (path.y[i + 1] - path.y[i]),
              path.h[i] + f * (path.h[i + 1] - path.h[i])];
    }

    // The segment of a track running at t (its index, or -1).
    function segmentAt(track, t) {
      const i = lastAtOrBefore(track.s, t);
      return i >= 0 && t < track.e[i] ? i : (i >= 0 && t === track.e[i] && track.s[i] === t ? i : -1);
    }

    const timings = report.timings = { data: started - loadStarted };
    const lap = (() => { let last = performance.now(); return name => {
      const now = performance.now(); timings[name] = now - last; last = now; }; })();
    const room = makeRoom(model, poseAt, setTime);
    lap("room");
    report.roomPoint = room.toPage;
    const flow = makeFlow(model, texts);
    lap("flow");
    const readout = document.getElementById("readout");
    const here = document.getElementById("here");

    // -- the charts over time -------------------------------------------------------------

    const box = document.querySelector("section.time");
    const width = () => Math.max(400, box.clientWidth);
    let scaling = false;

    function common(height, extra) {
      const opts = {
        width: width(), height: height,
        legend: { show: false },
        cursor: { sync: { key: SYNC, setSeries: false }, drag: { x: true, y: false },
                  points: { show: false }, y: false },
        scales: { x: { time: false } },
        axes: [{ values: (u, ticks) => ticks.map(v => v + " s"), size: 34 }, {}],
        hooks: {
          setCursor: [u => onCursor(u)],
          setScale: [(u, key) => {
            if (key !== "x" || scaling) return;
            scaling = true;
            const min = u.scales.x.min, max = u.scales.x.max;
            for (const c of report.charts) {
              if (c !== u && (c.scales.x.min !== min || c.scales.x.max !== max)) {
                c.setScale("x", { min: min, max: max });
              }
            }
            scaling = false;
          }],
        },
      };
      return Object.assign(opts, extra);
    }

    function lanes(names) {
      const n = names.length;
      return {
        scales: { x: { time: false }, y: { auto: false, range: [0, n] } },
        axes: [{ values: (u, ticks) => ticks.map(v => v + " s"), size: 34 },
               { splits: () => names.map((_, i) => n - i - 0.5), values: () => names.slice(),
                 grid: { show: false }, ticks: { show: false }, size: 76, gap: 4 }],
        series: [{}, { stroke: "transparent", points: { show: false } }],
      };
    }

    // Tracks: move, LEDs, audio, as segments.
    const trackNames = ["move", "LEDs", "audio"];
    const tracks = new uPlot(common(150, Object.assign(lanes(trackNames), {
      hooks: Object.assign({}, common(0).hooks, { draw: [u => drawTracks(u)] }),
    })), [[0, end / 1000], [null, null]], document.getElementById("tracks"));

    function laneBox(u, lane, n) {
      const top = u.valToPos(n - lane, "y", true), bottom = u.valToPos(n - lane - 1, "y", true);
      const pad = (bottom - top) * 0.14;
      return [top + pad, bottom - top - 2 * pad];
    }

    function drawTracks(u) {
      const ctx = u.ctx, bb = u.bbox;
      ctx.save();
      ctx.beginPath();
      ctx.rect(bb.left, bb.top, bb.width, bb.height);
      ctx.clip();
      ctx.font = Math.round(10 * devicePixelRatio) + "px system-ui, sans-serif";
      ctx.textBaseline = "middle";
      ctx.textAlign = "left";
      const tr = model.tracks;
      const outlines = new Path2D();  // every segment's outline, stroked once
      const draw = (track, lane, paint) => {
        const [y, h] = laneBox(u, lane, 3);
        const first = Math.max(0, lastAtOrBefore(track.s, u.scales.x.min * 1000 - 1) - 1);
        for (let i = first; i < track.s.length; i++) {
          const x0 = u.valToPos(track.s[i] / 1000, "x", true);
          if (x0 > bb.left + bb.width) break;
          const x1 = Math.max(x0 + 1, u.valToPos(track.e[i] / 1000, "x", true));
          if (x1 < bb.left) continue;
          const label = paint(i);
          ctx.fillRect(x0, y, x1 - x0, h);
          outlines.rect(x0, y, x1 - x0, h);
          if (label && x1 - x0 > 24 * devicePixelRatio && ctx.measureText(label).width + 6 < x1 - x0) {
            ctx.fillStyle = label.dark ? "#fff" : "#111";
            ctx.fillText(label, Math.max(x0, bb.left) + 3, y + h / 2);
          }
        }
      };
      draw(tr.move, 0, i => {
        const vx = tr.move.vx[i], vy = tr.move.vy[i], vw = tr.move.vw[i];
        const speed = Math.hypot(vx, vy);
        const moving = speed > 0 || vw !== 0;
        ctx.fillStyle = moving ? "rgba(31,119,180," + (0.35 + Math.min(0.6, speed)) + ")" : "#dfe7f1";
        if (!moving) return "still";
        return fixed(speed, 2) + " m/s" + (vw ? ", " + fixed(vw, 2) + " rad/s" : "");
      });
      draw(tr.led, 1, i => {
        const lit = tr.led.lit[i];
        if (lit === 1) {
          ctx.fillStyle = rgb(tr.led.r[i], tr.led.g[i], tr.led.b[i]);
          return null;
        }
        ctx.fillStyle = lit === 2 ? "#3b1010" : "#2b2b2b";
        const label = new String(lit === 2 ? "held dark" : "off");
        label.dark = true;
        return label;
      });
      draw(tr.audioout, 2, i => {
        const name = texts[tr.audioout.name[i]];
        ctx.fillStyle = name === "Silence" ? "#eeeeee" : "#ffb347";
        return name;
      });
      ctx.strokeStyle = "rgba(40,40,40,0.55)";
      ctx.lineWidth = 1;
      ctx.stroke(outlines);
      // the blocks issued: a dotted line each
      ctx.strokeStyle = "rgba(90,90,90,0.55)";
      ctx.setLineDash([2, 3]);
      const v = model.visits;
      ctx.beginPath();
      let lastX = -1;
      for (let i = 0; i < v.t.length; i++) {
        if (v.kind[i] !== ISSUED) continue;
        const x = Math.round(u.valToPos(v.t[i] / 1000, "x", true)) + 0.5;
        if (x === lastX || x < bb.left || x > bb.left + bb.width) continue;
        lastX = x;
        ctx.moveTo(x, bb.top);
        ctx.lineTo(x, bb.top + bb.height);
      }
      ctx.stroke();
      ctx.restore();
    }

    // Velocity: the commanded steps and the speed along the path.
    lap("tracks");
    // Velocity: the commanded steps, each at its millisecond, and the speed along the path,
    // over stretches of the path (at most SPEED_POINTS of them: a chart is not wider).
    const vel = model.velocity;
    const SPEED_POINTS = 2500;
    const n = path.t.length;
    const cum = new Float64Array(n);  // the distance along the path up to each sample
    for (let i = 1; i < n; i++) {
      cum[i] = cum[i - 1] + Math.hypot(path.x[i] - path.x[i - 1], path.y[i] - path.y[i - 1]);
    }
    const every = Math.max(1, Math.ceil(n / SPEED_POINTS));
    const marks = [];  // the samples that end the stretches
    for (let i = 0; i < n; i += every) marks.push(i);
    if (n && marks[marks.length - 1] !== n - 1) marks.push(n - 1);
    const markT = marks.map(i => path.t[i]);
    const xs = [];
    {
      let i = 0, j = 0;
      while (i < markT.length || j < vel.t.length) {
        const a = i < markT.length ? markT[i] : Infinity, b = j < vel.t.length ? vel.t[j] : Infinity;
        const t = Math.min(a, b);
        if (!xs.length || xs[xs.length - 1] !== t) xs.push(t);
        if (a === t) i++;
        if (b === t) j++;
      }
      if (!xs.length || xs[xs.length - 1] < end) xs.push(end);
    }
    const vx = [], vy = [], vw = [], along = [];
    for (const t of xs) {
      const k = lastAtOrBefore(vel.t, t);
      vx.push(k >= 0 ? vel.vx[k] : 0);
      vy.push(k >= 0 ? vel.vy[k] : 0);
      vw.push(k >= 0 ? vel.vw[k] : 0);
      // along the path: the mean speed over the stretch that ends at or after t (drawn as a
      // step back to the point before)
      let p = lastAtOrBefore(markT, t);
      if (p >= 0 && markT[p] === t && p > 0) p--;
      if (p < 0 || p + 1 >= marks.length) { along.push(0); continue; }
      const dt = (markT[p + 1] - markT[p]) / 1000;
      along.push(dt > 0 ? (cum[marks[p + 1]] - cum[marks[p]]) / dt : 0);
    }
    lap("series");
    const stepped = uPlot.paths.stepped({ align: 1 });
    const speed = new uPlot(common(170, {
      legend: { show: true, live: true },
      series: [
        { label: "time", value: (u, v) => v == null ? "-" : v.toFixed(3) + " s" },
        { label: "v_x (m/s)", stroke: "#1f77b4", paths: stepped, points: { show: false } },
        { label: "v_y (m/s)", stroke: "#17becf", paths: stepped, points: { show: false } },
        { label: "v_θ (rad/s)", stroke: "#9467bd", paths: stepped, points: { show: false } },
        { label: "along the path (m/s)", stroke: "#222", width: 1, points: { show: false },
          paths: uPlot.paths.stepped({ align: -1 }) },
      ],
      axes: [{ values: (u, ticks) => ticks.map(v => v + " s"), size: 34 }, { size: 50 }],
    }), [xs.map(t => t / 1000), vx, vy, vw, along], document.getElementById("speed"));

    lap("speed");
    // Events: a lane each (script, jumps, rules, operator, governor, errors).
    const laneNames = model.lanes;
    const mk = model.markers;
    const events = new uPlot(common(40 + 24 * laneNames.length, Object.assign(lanes(laneNames), {
      hooks: Object.assign({}, common(0).hooks, { draw: [u => drawMarkers(u)] }),
    })), [[0, end / 1000], [null, null]], document.getElementById("events"));

    function drawMarkers(u) {
      const ctx = u.ctx, bb = u.bbox, r = 4 * devicePixelRatio, n = laneNames.length;
      ctx.save();
      ctx.beginPath();
      ctx.rect(bb.left - r, bb.top, bb.width + 2 * r, bb.height);
      ctx.clip();
      for (let i = 0; i < mk.t.length; i++) {
        const x = u.valToPos(mk.t[i] / 1000, "x", true);
        if (x < bb.left - r || x > bb.left + bb.width + r) continue;
        const lane = mk.lane[i], style = mk.style[i];
        const y = u.valToPos(n - lane - 0.5, "y", true);
        ctx.fillStyle = ctx.strokeStyle = STYLE_COLOURS[style] || STYLE_COLOURS[0];
        ctx.lineWidth = 1.5 * devicePixelRatio;
        ctx.beginPath();
        if (lane === 1 && style === 1) {  // a jump whose condition held: up
          ctx.moveTo(x, y - r); ctx.lineTo(x + r, y + r); ctx.lineTo(x - r, y + r); ctx.closePath(); ctx.fill();
        } else if (lane === 1 && style === 2) {  // one that did not: down, hollow
          ctx.moveTo(x - r, y - r); ctx.lineTo(x + r, y - r); ctx.lineTo(x, y + r); ctx.closePath(); ctx.stroke();
        } else if (style >= 4) {  // a warning or an error: a diamond
          ctx.moveTo(x, y - r * 1.2); ctx.lineTo(x + r, y); ctx.lineTo(x, y + r * 1.2); ctx.lineTo(x - r, y); ctx.closePath(); ctx.fill();
        } else {
          ctx.arc(x, y, r * 0.8, 0, 2 * Math.PI); ctx.fill();
        }
      }
      ctx.restore();
    }

    report.charts.push(tracks, speed, events);
    lap("events");

    // -- the cursor -----------------------------------------------------------------------

    function setTime(t) {
      // move the cursor of one chart: uPlot's sync moves the others, and onCursor the views
      const u = speed;
      const s = Math.min(Math.max(t, 0), end) / 1000;
      if (s < u.scales.x.min || s > u.scales.x.max) {
        for (const c of report.charts) c.setScale("x", { min: 0, max: end / 1000 });
      }
      u.setCursor({ left: u.valToPos(s, "x"), top: u.bbox.height / devicePixelRatio / 2 }, true, true);
    }

    let lastLeft = null;
    function onCursor(u) {
      const left = u.cursor.left;
      if (left == null || left < 0) return;
      const t = Math.max(0, Math.min(end, u.posToVal(left, "x") * 1000));
      // the events near the cursor: within 5 pixels of it on this chart
      const tolerance = Math.abs(u.posToVal(left + 5, "x") * 1000 - t);
      if (lastLeft === t) return;
      lastLeft = t;
      show(t, tolerance);
    }

    function show(t, tolerance) {
      report.time = t;
      const pose = poseAt(t);
      room.draw(t, pose);
      const block = flow.highlight(t);
      report.highlighted = block;
      report.flow = flow.shown();
      // the readout
      readout.textContent = "";
      const row = (name, value) => {
        readout.appendChild(el("dt", {}, name));
        const dd = el("dd");
        if (value instanceof Node) dd.appendChild(value); else dd.textContent = value;
        readout.appendChild(dd);
      };
      row("time", seconds(t));
      row("robot", "x " + fixed(pose[0], 3) + " m, y " + fixed(pose[1], 3) + " m, θ " +
                   fixed(pose[2], 3) + " rad");
      row("block", flow.describe());
      const tr = model.tracks;
      const m = segmentAt(tr.move, t);
      row("move", m < 0 ? "-" : "(" + fixed(tr.move.vx[m], 3) + ", " + fixed(tr.move.vy[m], 3) +
                  ", " + fixed(tr.move.vw[m], 3) + ") from " + seconds(tr.move.s[m]));
      const l = segmentAt(tr.led, t);
      const leds = el("span");
      if (l < 0 || tr.led.lit[l] !== 1) {
        leds.textContent = l < 0 ? "-" : tr.led.lit[l] === 2 ? "held dark by the governor" : "off";
      } else {
        const colour = rgb(tr.led.r[l], tr.led.g[l], tr.led.b[l]);
        const sw = el("span", { class: "swatch" });
        sw.style.background = colour;
        leds.appendChild(sw);
        leds.appendChild(document.createTextNode(fixed(tr.led.r[l], 2) + ", " + fixed(tr.led.g[l], 2) +
                                                 ", " + fixed(tr.led.b[l], 2)));
      }
      row("LEDs", leds);
      const a = segmentAt(tr.audioout, t);
      row("audio", a < 0 ? "-" : texts[tr.audioout.name[a]]);
      // the events at the cursor
      here.textContent = "";
      const lo = lastAtOrBefore(mk.t, t - tolerance - 1e-9) + 1;
      let shown = 0;
      for (let i = lo; i < mk.t.length && mk.t[i] <= t + tolerance && shown < 40; i++, shown++) {
        here.appendChild(el("li", { class: "s" + mk.style[i] },
                            seconds(mk.t[i]) + " " + texts[mk.text[i]]));
      }
    }

    window.addEventListener("resize", () => {
      for (const c of report.charts) c.setSize({ width: width(), height: c.height });
      room.resize();
      room.draw(report.time, poseAt(report.time));
    });

    show(0, 0);
    lap("cursor");
    report.readyMs = performance.now() - started;  // drawing, after the data was read
    report.readyAt = performance.now();  // since the page began to load
    report.ready = true;
  }

  // -- the room from above ------------------------------------------------------------------

  function makeRoom(model, poseAt, setTime) {
    const canvas = document.getElementById("room");
    const path = model.path, radius = model.robot.radius;
    const ends = model.robot.end && model.robot.gap != null && model.robot.gap >= 0.01
      ? model.robot.end : null;
    let minX = -radius, maxX = radius, minY = -radius, maxY = radius;
    const grow = (x, y) => {
      if (x - radius < minX) minX = x - radius;
      if (x + radius > maxX) maxX = x + radius;
      if (y - radius < minY) minY = y - radius;
      if (y + radius > maxY) maxY = y + radius;
    };
    for (let i = 0; i < path.t.length; i++) grow(path.x[i], path.y[i]);
    for (const e of model.entities) for (let i = 0; i < e.t.length; i++) grow(e.x[i], e.y[i]);
    if (ends) grow(ends[0], ends[1]);
    const pad = 0.4;
    minX -= pad; maxX += pad; minY -= pad; maxY += pad;
    let scale = 1, ox = 0, oy = 0, css = 480;
    const layer = document.createElement("canvas");

    function resize() {
      css = Math.max(240, Math.min(560, canvas.parentElement.clientWidth || 480));
      const dpr = devicePixelRatio || 1;
      canvas.width = layer.width = Math.round(css * dpr);
      canvas.height = layer.height = Math.round(css * dpr);
      canvas.style.height = css + "px";
      scale = Math.min(canvas.width / (maxX - minX), canvas.height / (maxY - minY));
      ox = (canvas.width - scale * (maxX - minX)) / 2;
      oy = (canvas.height - scale * (maxY - minY)) / 2;
      paintStatic();
    }
    const X = x => ox + (x - minX) * scale;
    const Y = y => canvas.height - (oy + (y - minY) * scale);

    function paintStatic() {
      const ctx = layer.getContext("2d"), dpr = devicePixelRatio || 1;
      ctx.clearRect(0, 0, layer.width, layer.height);
      ctx.fillStyle = "#fff";
      ctx.fillRect(0, 0, layer.width, layer.height);
      // a grid of whole metres (5 or 10 in a large room), numbered
      const span = Math.max(maxX - minX, maxY - minY);
      const step = span > 60 ? 10 : span > 15 ? 5 : span > 4 ? 1 : 0.5;
      ctx.strokeStyle = "#eceff3";
      ctx.fillStyle = "#9aa3ad";
      ctx.lineWidth = 1;
      ctx.font = Math.round(10 * dpr) + "px system-ui, sans-serif";
      for (let x = Math.ceil(minX / step) * step; x <= maxX; x += step) {
        ctx.beginPath(); ctx.moveTo(X(x), 0); ctx.lineTo(X(x), layer.height); ctx.stroke();
        ctx.fillText(+x.toFixed(1) + " m", X(x) + 2, layer.height - 4 * dpr);
      }
      for (let y = Math.ceil(minY / step) * step; y <= maxY; y += step) {
        ctx.beginPath(); ctx.moveTo(0, Y(y)); ctx.lineTo(layer.width, Y(y)); ctx.stroke();
        ctx.fillText(+y.toFixed(1) + " m", 3 * dpr, Y(y) - 2);
      }
      // the people, objects and obstacles: their path, hollow at the first point
      for (const e of model.entities) {
        const colour = CLASS_COLOURS[e.cls] || "#9467bd";
        ctx.strokeStyle = colour;
        ctx.globalAlpha = 0.5;
        ctx.lineWidth = dpr;
        ctx.setLineDash([4 * dpr, 3 * dpr]);
        ctx.beginPath();
        for (let i = 0; i < e.t.length; i++) {
          if (i) ctx.lineTo(X(e.x[i]), Y(e.y[i])); else ctx.moveTo(X(e.x[i]), Y(e.y[i]));
        }
        ctx.stroke();
        ctx.setLineDash([]);
        ctx.globalAlpha = 1;
        if (e.t.length) {
          ctx.beginPath();
          ctx.arc(X(e.x[0]), Y(e.y[0]), 4 * dpr, 0, 2 * Math.PI);
          ctx.stroke();
        }
      }
      // the robot's path, and its footprint at the start (dotted)
      ctx.strokeStyle = ROBOT;
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      for (let i = 0; i < path.t.length; i++) {
        if (i) ctx.lineTo(X(path.x[i]), Y(path.y[i])); else ctx.moveTo(X(path.x[i]), Y(path.y[i]));
      }
      ctx.stroke();
      ctx.lineWidth = dpr;
      ctx.setLineDash([2 * dpr, 3 * dpr]);
      ctx.beginPath();
      ctx.arc(X(path.x[0] || 0), Y(path.y[0] || 0), radius * scale, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.setLineDash([]);
      if (ends) {  // where the run ended, when the path drawn does not end there
        const x = X(ends[0]), y = Y(ends[1]), r = 5 * dpr;
        ctx.strokeStyle = "#d62728";
        ctx.lineWidth = 2 * dpr;
        ctx.beginPath();
        ctx.moveTo(x - r, y - r); ctx.lineTo(x + r, y + r); ctx.moveTo(x + r, y - r); ctx.lineTo(x - r, y + r);
        ctx.stroke();
      }
    }

    function draw(t, pose) {
      const ctx = canvas.getContext("2d"), dpr = devicePixelRatio || 1;
      ctx.clearRect(0, 0, canvas.width, canvas.height);
      ctx.drawImage(layer, 0, 0);
      // each entity where the map last put it
      ctx.font = Math.round(11 * dpr) + "px system-ui, sans-serif";
      for (const e of model.entities) {
        const i = lastAtOrBefore(e.t, t);
        if (i < 0) continue;
        const colour = CLASS_COLOURS[e.cls] || "#9467bd";
        const x = X(e.x[i]), y = Y(e.y[i]);
        ctx.fillStyle = colour;
        ctx.beginPath();
        ctx.arc(x, y, 6 * dpr, 0, 2 * Math.PI);
        ctx.fill();
        ctx.fillStyle = "#333";
        ctx.fillText(e.id, x + 8 * dpr, y - 6 * dpr);
      }
      // the robot: footprint and heading
      const x = X(pose[0]), y = Y(pose[1]), r = Math.max(radius * scale, 4 * dpr);
      ctx.fillStyle = "rgba(31,119,180,0.18)";
      ctx.strokeStyle = ROBOT;
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      ctx.arc(x, y, r, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      ctx.beginPath();
      ctx.moveTo(x, y);
      ctx.lineTo(x + Math.cos(pose[2]) * r * 1.6, y - Math.sin(pose[2]) * r * 1.6);
      ctx.stroke();
    }

    // hovering (or dragging) over the room moves the cursor to the nearest point of the path
    function hover(ev) {
      if (!path.t.length) return;
      const rect = canvas.getBoundingClientRect(), k = canvas.width / rect.width;
      const px = (ev.clientX - rect.left) * k, py = (ev.clientY - rect.top) * k;
      let best = -1, bestD = Infinity;
      for (let i = 0; i < path.t.length; i++) {
        const d = Math.hypot(X(path.x[i]) - px, Y(path.y[i]) - py);
        if (d < bestD) { bestD = d; best = i; }
      }
      if (best >= 0 && bestD <= 30 * k) setTime(path.t[best]);
    }
    canvas.addEventListener("mousemove", hover);

    const legend = document.getElementById("room-legend");
    const item = (colour, text) => {
      const s = el("span");
      const dot = el("i");
      dot.style.background = colour;
      s.appendChild(dot);
      s.appendChild(document.createTextNode(text));
      legend.appendChild(s);
    };
    item(ROBOT, "the robot (" + (model.robot.recorded ? "its path as the physics ran it"
                                 : "its path from the trace's velocity changes") + ")");
    const classes = [];
    for (const e of model.entities) if (!classes.includes(e.cls)) classes.push(e.cls);
    for (const c of classes) item(CLASS_COLOURS[c] || "#9467bd", c);
    if (ends) item("#d62728", "✕ where the run ended");

    // where a point of the room is on the page (client coordinates): for tests and tools
    function toPage(x, y) {
      const rect = canvas.getBoundingClientRect(), k = canvas.width / rect.width;
      return [rect.left + X(x) / k, rect.top + Y(y) / k];
    }

    resize();
    return { draw: draw, resize: resize, toPage: toPage };
  }

  // -- the flow -----------------------------------------------------------------------------

  // The flow of a script: its blocks in order (a box each, grouped by goal), each jump's true
  // edge on the right and false edge on the left, the next block below. The boxes near the
  // scrolled view are drawn (a script of thousands of blocks stays quick); the edges always.
  function makeFlow(model, texts) {
    const box = document.getElementById("flow");
    const pick = document.getElementById("flow-pick");
    const visits = model.visits;
    const W = 300, H = 36, GAP = 16, LEFT = 96, TOP = 10, MARGIN = 700;
    let current = -1, edges = [], marked = [], lastKey = null, lastText = "-";
    let ys = [], layer = null, drawn = [-1, -1], nodes = new Map(), classes = new Map();

    model.flows.forEach((f, i) => pick.appendChild(el("option", { value: String(i) },
                                                      f.script + (f.path ? " (" + f.path + ")" : ""))));
    pick.addEventListener("change", () => { render(Number(pick.value)); lastKey = null; });
    if (!model.flows.length) pick.hidden = true;
    let pending = false;
    box.addEventListener("scroll", () => {
      if (pending) return;
      pending = true;
      requestAnimationFrame(() => { pending = false; drawBoxes(); });
    });

    function clip(text, n) { return text.length > n ? text.slice(0, n - 1) + "…" : text; }

    function render(i) {
      current = i;
      pick.value = String(i);
      box.textContent = "";
      edges = []; marked = []; ys = []; layer = null; drawn = [-1, -1];
      nodes = new Map(); classes = new Map();
      const f = model.flows[i];
      if (!f) { box.appendChild(el("p", {}, "No script was loaded.")); return; }
      if (!f.blocks.length) {
        box.appendChild(el("p", {}, "No flow for " + f.script + ": " + (f.problem || "it has no block") + "."));
        return;
      }
      const blocks = f.blocks, n = blocks.length;
      let y = TOP, goal = -1, action = -1;
      const heads = [];
      for (let b = 0; b < n; b++) {
        const [, , , , g, a] = blocks[b];
        if (g !== goal) { heads.push([y, "goal " + (f.goals[g] || g)]); y += 20; goal = g; action = a; }
        else if (a !== action) { heads.push([y, null]); y += 8; action = a; }
        ys.push(y);
        y += H + GAP;
      }
      const endY = y;
      const height = endY + H + TOP;
      const s = svg("svg", { class: "flow", width: W + 2 * LEFT, height: height,
                             viewBox: "0 0 " + (W + 2 * LEFT) + " " + height });
      const defs = svg("defs");
      for (const [id, colour] of [["a", "#9aa5b1"], ["t", "#2a9d3a"], ["f", "#bb5555"]]) {
        const m = svg("marker", { id: "arrow-" + id, viewBox: "0 0 10 10", refX: "9", refY: "5",
                                  markerWidth: "7", markerHeight: "7", orient: "auto-start-reverse" });
        m.appendChild(svg("path", { d: "M0,0 L10,5 L0,10 z", fill: colour }));
        defs.appendChild(m);
      }
      s.appendChild(defs);
      for (const [hy, text] of heads) {
        if (text) s.appendChild(svg("text", { class: "goal", x: LEFT, y: hy + 13 }, text));
        else s.appendChild(svg("line", { x1: LEFT, x2: LEFT + W, y1: hy + 3, y2: hy + 3,
                                         stroke: "#c5ccd4", "stroke-dasharray": "4 3" }));
      }
      const yOf = j => (j >= n ? endY : ys[j]);
      const edge = (from, to, kind, cls) => {
        let d;
        const y0 = ys[from] + H / 2, y1 = yOf(to) + H / 2;
        if (to === from + 1 && kind !== "f") {
          d = "M" + (LEFT + W / 2) + "," + (ys[from] + H) + " L" + (LEFT + W / 2) + "," + yOf(to);
        } else {
          const right = kind !== "f", span = Math.abs(to - from);
          const off = 14 + 9 * Math.min(7, Math.ceil(Math.log2(1 + span)));
          const x = right ? LEFT + W : LEFT, out = right ? x + off : x - off;
          d = "M" + x + "," + y0 + " C" + out + "," + y0 + " " + out + "," + y1 + " " + x + "," + y1;
        }
        const p = svg("path", { d: d, class: "edge " + cls, "marker-end": "url(#arrow-" + kind + ")" });
        s.appendChild(p);
        return p;
      };
      for (let b = 0; b < n; b++) {
        const [, kind, , , , , tt, tf, , never] = blocks[b];
        const out = [];
        if (kind === "jump") {
          out.push(tt >= 0 ? edge(b, tt, "t", "true") : null);
          out.push(tf >= 0 ? edge(b, tf, "f", never ? "false never" : "false") : null);
        } else if (kind !== "terminus") {
          out.push(edge(b, b + 1, "a", "next"));
        }
        edges.push(out);
      }
      layer = svg("g", { class: "boxes" });
      s.appendChild(layer);
      s.appendChild(svg("rect", { class: "block end", x: LEFT + W / 2 - 40, y: endY, width: 80, height: H * 0.7, rx: 10 }));
      s.appendChild(svg("text", { x: LEFT + W / 2, y: endY + H * 0.45, "text-anchor": "middle", class: "kind" }, "past the end"));
      box.appendChild(s);
      drawBoxes();
    }

    // The boxes of the blocks within MARGIN pixels of the view.
    function drawBoxes() {
      if (!layer) return;
      const blocks = model.flows[current].blocks;
      const lo = Math.max(0, lastAtOrBefore(ys, box.scrollTop - MARGIN));
      const hi = Math.min(ys.length - 1, lastAtOrBefore(ys, box.scrollTop + box.clientHeight + MARGIN));
      if (lo === drawn[0] && hi === drawn[1]) return;
      drawn = [lo, hi];
      for (const [b, g] of nodes) if (b < lo || b > hi) { g.parentNode.remove(); nodes.delete(b); }
      for (let b = lo; b <= hi; b++) {
        if (nodes.has(b)) continue;
        const [where, kind, label, text, , , , , reachable, never, detail, colours] = blocks[b];
        const g = svg("g", reachable ? {} : { class: "unreachable" });
        const rect = svg("rect", { class: "block " + kind, x: LEFT, y: ys[b], width: W, height: H, rx: kind === "jump" ? 10 : 3 });
        g.appendChild(svg("title", {}, where + (label ? " #" + label : "") + " (" + kind + ")" +
                                      (reachable ? "" : ", which no path from the start reaches") +
                                      (never ? ", whose condition cannot be false" : "") +
                                      "\n" + (detail || text)));
        g.appendChild(rect);
        g.appendChild(svg("text", { class: "label", x: LEFT + 6, y: ys[b] + 14 }, clip(label ? "#" + label : kind, 30)));
        g.appendChild(svg("text", { class: "kind", x: LEFT + W - 6, y: ys[b] + 14, "text-anchor": "end" }, where));
        const room = 52 - Math.ceil(colours.length * 2.2);
        g.appendChild(svg("text", { x: LEFT + 6, y: ys[b] + 29 }, clip(text, room)));
        colours.forEach((colour, k) => {  // the colours of the block's lights
          g.appendChild(svg("rect", { class: "light", x: LEFT + W - 6 - 12 * (colours.length - k), y: ys[b] + 21,
                                      width: 10, height: 10, rx: 2, fill: colour }));
        });
        for (const cls of classes.get(b) || []) rect.classList.add(cls);
        layer.appendChild(g);
        nodes.set(b, rect);
      }
    }

    function clear() {
      for (const [node, cls] of marked) node.classList.remove(cls);
      marked = [];
      for (const [b, list] of classes) {
        const node = nodes.get(b);
        if (node) for (const cls of list) node.classList.remove(cls);
      }
      classes = new Map();
    }
    function markEdge(node, cls) {
      if (!node) return;
      node.classList.add(cls);
      marked.push([node, cls]);
    }
    function markBlock(b, cls) {
      if (!classes.has(b)) classes.set(b, []);
      classes.get(b).push(cls);
      const node = nodes.get(b);
      if (node) node.classList.add(cls);
    }

    // Highlight the block running at t: the last instruction block issued at or before t (of
    // the script then loaded), and the jumps read at the instant it was issued, or since.
    function highlight(t) {
      const i = lastAtOrBefore(visits.t, t);
      if (i < 0) {
        const key = "none";
        if (key !== lastKey) { clear(); lastKey = key; if (current < 0 && model.flows.length) render(0); }
        lastText = "-";
        return null;
      }
      const load = visits.load[i];
      const f = model.loads[load] ? model.loads[load].flow : -1;
      // the latest issue of that load at or before t, and whether it is done
      let issue = -1, done = false;
      for (let k = i; k >= 0; k--) {
        if (visits.load[k] !== load) continue;
        if (visits.kind[k] === DONE && issue < 0) done = true;
        if (visits.kind[k] === ISSUED) { issue = k; break; }
      }
      // the jumps of the last read: from the last instant with a jump, back while the instant holds
      const jumps = [];
      for (let k = i; k >= 0 && visits.t[k] === visits.t[i]; k--) {
        if (visits.load[k] === load && (visits.kind[k] === JUMP_TRUE || visits.kind[k] === JUMP_FALSE)) jumps.push(k);
      }
      const key = f + ":" + issue + ":" + done + ":" + jumps.join(",");
      const flow = model.flows[f];
      const block = issue >= 0 && flow ? visits.block[issue] : -1;
      const where = block >= 0 ? flow.blocks[block] : null;
      lastText = where ? (where[2] ? "#" + where[2] + " " : "") + where[0] + " (" + flow.script + ")" +
                         (done ? ", done" : ", issued at " + seconds(visits.t[issue])) : "-";
      if (key === lastKey) return where ? where[0] : null;
      lastKey = key;
      if (f >= 0 && f !== current) render(f);
      clear();
      if (where) markBlock(block, done ? "was" : "running");
      for (const k of jumps) {
        const b = visits.block[k];
        if (b < 0) continue;
        const value = visits.kind[k] === JUMP_TRUE;
        markBlock(b, value ? "jumped-true" : "jumped-false");
        if (edges[b]) markEdge(edges[b][value ? 0 : 1], "taken");
      }
      if (where) scrollTo(block);
      return where ? where[0] : null;
    }

    function scrollTo(b) {
      const y = ys[b];
      if (y === undefined) return;
      if (y < box.scrollTop + 10 || y + H > box.scrollTop + box.clientHeight - 10) {
        box.scrollTop = Math.max(0, y - box.clientHeight / 3);
      }
      drawBoxes();
    }

    if (model.flows.length) render(0);
    return { highlight: highlight, describe: () => lastText, shown: () => current };
  }

  load().then(start).catch(fail);
})();
