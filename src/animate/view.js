"use strict";
// The view of `telescopic animate` and `telescopic modes --animate`: draws the telescope in
// the plane of the motion on canvases from the JSON document in #data. No library, no
// network: everything it needs is in this file and that document.
//
// For tests and for scripts, window.telescopic answers queries: seek(t), step(n), play(),
// pause(), state(), layout() and drawn() (the pixel positions of the last frame drawn, in
// CSS pixels of its canvas). The URL fragment #at=T pauses at T; #probe=T1,T2,... writes
// {layout, results: [{t, state, drawn}], errors} as JSON into <pre id="probe">. In the
// modes view T is a mode number (1-based) drawn at its largest deflection.
(function () {
  const errors = [];
  window.addEventListener("error", (e) => {
    const target = e.target && (e.target.src || e.target.href);
    errors.push(e.message || ("could not load " + target));
  }, true);
  document.addEventListener("securitypolicyviolation", (e) => {
    errors.push("blocked by the page's policy: " + e.blockedURI);
  });

  const data = JSON.parse(document.getElementById("data").textContent);
  const SECTION_COLORS = ["#4a6fa5", "#5f9e3f", "#c27c2c", "#8e5ea2", "#3a9ea5", "#a54a4a"];
  const LOAD_COLOR = "#cc00cc";
  const OPEN_COLOR = "#2ca02c";
  const CLOSED_COLOR = "#d62728";
  const GUIDE_COLOR = "#777777";
  const STAGE = { width: 460, height: 520, top: 64, bottom: 46 };

  function element(tag, attributes, parent) {
    const e = document.createElement(tag);
    Object.entries(attributes || {}).forEach(([k, v]) => {
      if (k === "text") e.textContent = v; else e.setAttribute(k, v);
    });
    if (parent) parent.appendChild(e);
    return e;
  }

  // A canvas of w x h CSS pixels, sharp on high-density screens.
  function canvas(parent, w, h) {
    const ratio = window.devicePixelRatio || 1;
    const c = element("canvas", {}, parent);
    c.width = Math.round(w * ratio);
    c.height = Math.round(h * ratio);
    c.style.width = w + "px";
    c.style.height = h + "px";
    const g = c.getContext("2d");
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    return { c, g, w, h };
  }

  // w = r . z over the coordinates; `absolute` keeps the vehicle's translation (index 0).
  function deflection(row, z, absolute) {
    let w = absolute ? row[0] * z[0] : 0;
    for (let i = 1; i < row.length; i++) w += row[i] * z[i];
    return w;
  }

  // Where the telescope stands: the vehicle's centre at cx, the rail's top at groundY,
  // ppm pixels per metre along the telescope and the rail.
  function stageLayout(heightM) {
    const groundY = STAGE.height - STAGE.bottom;
    return { cx: STAGE.width / 2, groundY, ppm: (groundY - STAGE.top) / (1.06 * heightM) };
  }

  // The value at x of a section's polyline (points at x_m with values w): linear between
  // drawing points, for the guides, which move along the section.
  function along(xs, ws, x) {
    let i = 1;
    while (i < xs.length - 1 && xs[i] < x) i++;
    const u = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return ws[i - 1] + Math.min(1, Math.max(0, u)) * (ws[i] - ws[i - 1]);
  }

  function polyline(g, points, color, width) {
    g.strokeStyle = color;
    g.lineWidth = width;
    g.lineJoin = "round";
    g.lineCap = "round";
    g.beginPath();
    points.forEach((p, i) => (i ? g.lineTo(p.x, p.y) : g.moveTo(p.x, p.y)));
    g.stroke();
  }

  // Draws the telescope of `frame` {z, feet, gaps, forces}; returns what it drew. A contact
  // is closed when its gap is beyond the band edge.
  function drawTelescope(g, L, tel, frame, scale, absolute) {
    const px = (w) => L.cx + L.ppm * scale * w;
    const deflections = tel.shapes.map((rows) => rows.map((r) => deflection(r, frame.z, absolute)));
    const sections = tel.points_m.map((xs, k) =>
      xs.map((x, p) => ({ x: px(deflections[k][p]), y: L.groundY - L.ppm * (frame.feet[k] + x) })));
    sections.forEach((pts, k) =>
      polyline(g, pts, SECTION_COLORS[k % SECTION_COLORS.length], Math.max(3, 11 - 3 * k)));
    const contacts = tel.contacts.map((site, c) => {
      const inner = site.overlap - 1;
      const outer = inner - 1;
      const a = frame.feet[inner] - frame.feet[outer];
      const xOut = a + site.fraction * (tel.lengths_m[outer] - a);
      const guide = along(tel.points_m[outer], deflections[outer], xOut);
      const y = L.groundY - L.ppm * (frame.feet[outer] + xOut);
      const band = L.ppm * scale * tel.half_band_m;
      const gx = px(guide);
      g.strokeStyle = GUIDE_COLOR;
      g.lineWidth = 2;
      [-1, 1].forEach((side) => {
        g.beginPath();
        g.moveTo(gx + side * (band + 4), y - 7);
        g.lineTo(gx + side * (band + 4), y + 7);
        g.stroke();
      });
      // closed outside the free band, and always without clearance (the Rust rule, gap_closed)
      const closed = frame.gaps ? tel.half_band_m === 0 || Math.abs(frame.gaps[c]) > tel.half_band_m : false;
      const x = frame.gaps ? px(guide + frame.gaps[c]) : px(along(tel.points_m[inner], deflections[inner], xOut - a));
      g.fillStyle = closed ? CLOSED_COLOR : OPEN_COLOR;
      g.beginPath();
      g.arc(x, y, 4.5, 0, 2 * Math.PI);
      g.fill();
      const force = frame.forces ? frame.forces[c] : 0;
      if (closed) {
        g.font = "11px sans-serif";
        g.fillText(Math.abs(force).toFixed(0) + " N", x + 9, y + 4);
      }
      return { x, y, guide_x: gx, closed, force };
    });
    const tops = sections.map((pts) => pts[pts.length - 1]);
    const load = tops[tops.length - 1];
    g.fillStyle = LOAD_COLOR;
    g.fillRect(load.x - 8, load.y - 16, 16, 16);
    const vehicle = px(absolute ? frame.z[0] : 0);
    g.fillStyle = "#444";
    g.fillRect(vehicle - 34, L.groundY, 68, 14);
    g.fillStyle = "#222";
    [-22, 22].forEach((dx) => { g.beginPath(); g.arc(vehicle + dx, L.groundY + 17, 5, 0, 2 * Math.PI); g.fill(); });
    return { sections, tops, load: { x: load.x, y: load.y }, vehicle_x: vehicle, contacts };
  }

  function text(g, s, x, y, align, size) {
    g.font = (size || 12) + "px sans-serif";
    g.textAlign = align || "left";
    g.fillStyle = "#222";
    g.fillText(s, x, y);
    g.textAlign = "left";
  }

  // Index of the frame of `times` nearest to t.
  function nearest(times, t) {
    let lo = 0, hi = times.length - 1;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid;
    }
    return Math.abs(times[hi] - t) < Math.abs(t - times[lo]) ? hi : lo;
  }

  function fmt(v) {
    const a = Math.abs(v);
    if (a !== 0 && (a < 1e-3 || a >= 1e4)) return v.toExponential(2);
    return v.toFixed(a < 1 ? 4 : a < 100 ? 2 : 0);
  }

  // ----- the run view -------------------------------------------------------------------

  // The strip on top: the vehicle's whole travel [r.lo, r.hi] (m) and where it is now.
  function overview(g, r, vehicle) {
    const x0 = 24, x1 = STAGE.width - 24, y = 30;
    g.strokeStyle = "#999"; g.lineWidth = 2;
    g.beginPath(); g.moveTo(x0, y); g.lineTo(x1, y); g.stroke();
    text(g, fmt(r.lo) + " m", x0, y + 16, "left", 10);
    text(g, fmt(r.hi) + " m", x1, y + 16, "right", 10);
    const x = x0 + (x1 - x0) * (vehicle - r.lo) / (r.hi - r.lo);
    g.fillStyle = "#444"; g.fillRect(x - 5, y - 6, 10, 12);
    return { x, scale: { x0, x1, lo: r.lo, hi: r.hi } };
  }

  // The rail under the vehicle with its metre marks; returns the pixel of the rail's zero.
  function rail(g, L, vehicle) {
    const y = L.groundY + 24;
    g.strokeStyle = "#888"; g.lineWidth = 3;
    g.beginPath(); g.moveTo(0, y); g.lineTo(STAGE.width, y); g.stroke();
    const halfWidth = STAGE.width / 2 / L.ppm;
    const step = halfWidth > 4 ? 1 : 0.5;
    g.lineWidth = 1;
    // counted, not stepped: far out (1e17 m) adding a step to a mark leaves it where it was
    const first = Math.floor((vehicle - halfWidth) / step) * step;
    const count = first + step > first ? Math.min(1000, Math.floor((vehicle + halfWidth - first) / step) + 1) : 0;
    for (let i = 0; i < count; i++) {
      const m = first + i * step;
      const x = L.cx + L.ppm * (m - vehicle);
      g.beginPath(); g.moveTo(x, y); g.lineTo(x, y + 6); g.stroke();
      text(g, m.toFixed(step < 1 ? 1 : 0), x, y + 18, "center", 10);
    }
    return L.cx - L.ppm * vehicle;
  }

  // Track k's frame nearest to the time S.t on its canvas; returns what it drew.
  function drawTrack(S, k) {
    const tr = data.tracks[k], v = S.views[k], g = v.g;
    const i = nearest(tr.t, S.t);
    g.clearRect(0, 0, v.w, v.h);
    const frame = { z: tr.z[i], feet: tr.feet[i], gaps: tr.gaps[i], forces: tr.forces[i] };
    const strip = overview(g, S.ranges[k], tr.vehicle[i]);
    const railZero = rail(g, S.layout, tr.vehicle[i]);
    const d = drawTelescope(g, S.layout, tr.telescope, frame, data.scale, false);
    text(g, tr.label, 8, 58, "left", 13);
    text(g, "transverse deflection \u00d7 " + data.scale, v.w - 8, 58, "right", 12);
    text(g, "t = " + tr.t[i].toFixed(3) + " s", v.w - 8, 76, "right", 12);
    return Object.assign(d, {
      frame: i, time: tr.t[i], vehicle_overview_x: strip.x, overview: strip.scale, rail_zero_x: railZero,
    });
  }

  // Chart j (tip_rel, vehicle, drive force) of every track with the cursor at S.t; returns
  // the cursor's pixel.
  function drawChart(S, j) {
    const ch = S.charts[j], g = ch.g, left = 64, right = ch.w - 8, top = 8, bottom = ch.h - 22;
    g.clearRect(0, 0, ch.w, ch.h);
    let lo = Infinity, hi = -Infinity;
    data.tracks.forEach((tr) => tr.charts[j].v.forEach((v) => { lo = Math.min(lo, v); hi = Math.max(hi, v); }));
    if (!(hi > lo)) { lo -= 1; hi += 1; }
    const X = (s) => left + (right - left) * (s - S.t0) / (S.t1 - S.t0);
    const Y = (v) => bottom - (bottom - top) * (v - lo) / (hi - lo);
    if (S.loop.on) {
      g.fillStyle = "rgba(120,120,120,0.15)";
      g.fillRect(X(S.loop.from), top, X(S.loop.to) - X(S.loop.from), bottom - top);
    }
    g.strokeStyle = "#ccc"; g.lineWidth = 1; g.strokeRect(left, top, right - left, bottom - top);
    data.tracks.forEach((tr) => {
      const s = tr.charts[j];
      polyline(g, s.t.map((tt, n) => ({ x: X(tt), y: Y(s.v[n]) })), tr.color, 1);
    });
    text(g, CHART_NAMES[j], left + 4, top + 12, "left", 11);
    text(g, fmt(hi), left - 4, top + 8, "right", 10);
    text(g, fmt(lo), left - 4, bottom, "right", 10);
    text(g, fmt(S.t0) + " s", left, ch.h - 6, "left", 10);
    text(g, fmt(S.t1) + " s", right, ch.h - 6, "right", 10);
    g.strokeStyle = "#000"; g.lineWidth = 1.5;
    g.beginPath(); g.moveTo(X(S.t), top); g.lineTo(X(S.t), bottom); g.stroke();
    return X(S.t);
  }

  const CHART_NAMES = ["tip_rel [m]", "vehicle [m]", "drive force [N]"];

  // The control bar of the run view: play, step, speed, scrub, clock and loop window.
  function runControls(S, api) {
    const bar = document.getElementById("controls");
    const play = element("button", { text: "\u275a\u275a", title: "play / pause (space)" }, bar);
    const back = element("button", { text: "\u25c0|", title: "previous frame" }, bar);
    const next = element("button", { text: "|\u25b6", title: "next frame" }, bar);
    const speed = element("select", { title: "playback speed" }, bar);
    [2, 1, 0.5, 0.25, 0.1, 0.05, 0.02, 0.01].forEach((s) => {
      const o = element("option", { value: s, text: s + "\u00d7" }, speed);
      if (s === 1) o.selected = true;
    });
    const slider = element("input", { type: "range", min: 0, max: 10000, value: 0, title: "scrub" }, bar);
    const clock = element("span", { id: "clock" }, bar);
    const loopLabel = element("label", { text: " loop " }, bar);
    const loopBox = element("input", { type: "checkbox" }, loopLabel);
    const from = element("input", { type: "number", step: "any", value: fmt(S.t0), title: "loop from (s)" }, bar);
    element("span", { text: "to" }, bar);
    const to = element("input", { type: "number", step: "any", value: fmt(S.t1), title: "loop to (s)" }, bar);
    element("span", { text: "s" }, bar);
    play.onclick = () => (S.playing ? api.pause() : api.play());
    back.onclick = () => api.step(-1);
    next.onclick = () => api.step(1);
    speed.onchange = () => (S.speed = Number(speed.value));
    slider.oninput = () => api.seek(S.t0 + (S.t1 - S.t0) * slider.value / 10000);
    loopBox.onchange = from.onchange = to.onchange = () => {
      const a = Number(from.value), b = Number(to.value);
      S.loop.on = loopBox.checked && b > a;
      S.loop.from = Math.max(S.t0, a); S.loop.to = Math.min(S.t1, b);
      if (!S.playing) api.render();
    };
    document.addEventListener("keydown", (e) => {
      if (e.key === " ") { e.preventDefault(); S.playing ? api.pause() : api.play(); }
      if (e.key === "ArrowRight") api.step(1);
      if (e.key === "ArrowLeft") api.step(-1);
    });
    return () => {
      play.textContent = S.playing ? "\u275a\u275a" : "\u25b6";
      slider.value = Math.round(10000 * (S.t - S.t0) / (S.t1 - S.t0));
      clock.textContent = "t = " + S.t.toFixed(3) + " s";
    };
  }

  // The run view's state: its canvases, time span, clock, speed and loop window.
  function runState() {
    const stage = document.getElementById("stage");
    const t0 = Math.min(...data.tracks.map((tr) => tr.t[0]));
    const t1 = Math.max(...data.tracks.map((tr) => tr.t[tr.t.length - 1]));
    return {
      layout: stageLayout(data.height_m),
      views: data.tracks.map(() => canvas(stage, STAGE.width, STAGE.height)),
      charts: CHART_NAMES.map(() => canvas(document.getElementById("charts"), 440, 160)),
      ranges: data.tracks.map((tr) => {
        const lo = Math.min(...tr.vehicle), hi = Math.max(...tr.vehicle);
        const pad = Math.max(0.5, 0.05 * (hi - lo));
        return { lo: lo - pad, hi: hi + pad };
      }),
      t0, t1, t: t0, playing: true, speed: 1, last: null, drawn: [],
      loop: { on: false, from: t0, to: t1 },
    };
  }

  function runView() {
    const S = runState();
    let showControls = () => {};
    const api = {
      render() {
        S.drawn = data.tracks.map((_, k) => drawTrack(S, k));
        const cursors = S.charts.map((_, j) => drawChart(S, j));
        S.drawn.forEach((d) => (d.cursor_x = cursors));
        showControls();
      },
      seek(time) { S.playing = false; S.t = Math.min(S.t1, Math.max(S.t0, Number(time))); api.render(); return api.state(); },
      step(n) {
        const tr = data.tracks[0];
        const i = Math.min(tr.t.length - 1, Math.max(0, nearest(tr.t, S.t) + n));
        return api.seek(tr.t[i]);
      },
      play() { S.playing = true; return api.state(); },
      pause() { S.playing = false; api.render(); return api.state(); },
      state() { return { t: S.t, playing: S.playing, speed: S.speed, loop: Object.assign({}, S.loop), frames: S.drawn.map((d) => d.frame) }; },
      layout() { return Object.assign({ scale: data.scale, width: STAGE.width, height: STAGE.height }, S.layout); },
      drawn() { return JSON.parse(JSON.stringify(S.drawn)); },
      errors,
    };
    showControls = runControls(S, api);
    function frame(now) {
      if (S.playing) {
        if (S.last !== null) {
          S.t += (now - S.last) / 1000 * S.speed;
          const end = S.loop.on ? S.loop.to : S.t1;
          if (S.t > end) S.t = S.loop.on ? S.loop.from : S.t0;
        }
        S.last = now;
        api.render();
      } else {
        S.last = null;
      }
      requestAnimationFrame(frame);
    }
    document.getElementById("note").textContent =
      data.tracks[0].t.length + " frames at " + data.fps + " per second of simulation; transverse deflection \u00d7 " +
      data.scale + ", lengths along the telescope true. Space plays and pauses, arrows step.";
    api.render();
    requestAnimationFrame(frame);
    return api;
  }

  // ----- the modes view -----------------------------------------------------------------

  function modesView() {
    const stage = document.getElementById("stage");
    const list = element("div", { class: "modes" }, stage);
    const L = stageLayout(data.height_m);
    const view = canvas(stage, STAGE.width, STAGE.height);
    const tel = data.telescope;
    const DISPLAY_HZ = 0.5;
    let selected = 0, phase = 0, playing = true, last = null, drawn = null;
    // each mode's deflection at the drawing points, normalized to a largest |w| of 1
    const peaks = data.modes.map((m) => {
      let peak = 0;
      tel.shapes.forEach((rows) => rows.forEach((r) => (peak = Math.max(peak, Math.abs(deflection(r, m.vector, true))))));
      return peak > 0 ? peak : 1;
    });
    const buttons = data.modes.map((m, i) => {
      const b = element("button", { text: "f" + (i + 1) + " = " + fmt(m.frequency_hz) + " Hz, " + m.kind }, list);
      b.onclick = () => { selected = i; render(); };
      return b;
    });
    const feet = data.feet;

    function render() {
      const m = data.modes[selected], g = view.g;
      const amplitude = Math.cos(phase);
      const z = m.vector.map((v) => amplitude * v / peaks[selected]);
      g.clearRect(0, 0, view.w, view.h);
      g.strokeStyle = "#888"; g.lineWidth = 3;
      g.beginPath(); g.moveTo(0, L.groundY + 24); g.lineTo(view.w, L.groundY + 24); g.stroke();
      const d = drawTelescope(g, L, tel, { z, feet }, data.scale, true);
      const slower = m.frequency_hz / DISPLAY_HZ;
      text(g, "mode " + (selected + 1) + ": " + fmt(m.frequency_hz) + " Hz (" + m.kind + ")", 8, 20, "left", 14);
      text(g, "damping ratio " + m.damping_ratio.toExponential(2) + "; shown " +
        (slower >= 1 ? fmt(slower) + "\u00d7 slower" : fmt(1 / slower) + "\u00d7 faster"), 8, 40, "left", 12);
      text(g, "largest deflection drawn as " + fmt(data.scale) + " m", view.w - 8, view.h - 4, "right", 11);
      buttons.forEach((b, i) => b.classList.toggle("on", i === selected));
      drawn = Object.assign(d, { mode: selected + 1, phase, amplitude });
    }

    function frame(now) {
      if (playing && last !== null) phase = (phase + 2 * Math.PI * DISPLAY_HZ * (now - last) / 1000) % (2 * Math.PI);
      last = playing ? now : null;
      if (playing) render();
      requestAnimationFrame(frame);
    }

    const api = {
      seek(mode) { playing = false; selected = Math.min(data.modes.length, Math.max(1, Math.round(Number(mode)))) - 1; phase = 0; render(); return api.state(); },
      step(n) { return api.seek(selected + 1 + n); },
      play() { playing = true; return api.state(); },
      pause() { playing = false; return api.state(); },
      state() { return { mode: selected + 1, phase, playing }; },
      layout() { return Object.assign({ scale: data.scale, width: STAGE.width, height: STAGE.height }, L); },
      drawn() { return JSON.parse(JSON.stringify(drawn)); },
      errors,
    };
    document.getElementById("note").textContent = data.modes.length +
      " modes at t = " + data.time_s + " s (contacts closed); each shown at one cycle per " + (1 / DISPLAY_HZ) +
      " s, its largest deflection at a fifth of the height.";
    const bar = document.getElementById("controls");
    const play = element("button", { text: "play / pause" }, bar);
    play.onclick = () => (playing = !playing);
    render();
    requestAnimationFrame(frame);
    return api;
  }

  const api = data.kind === "modes" ? modesView() : runView();
  window.telescopic = api;

  const hash = decodeURIComponent(location.hash.slice(1));
  if (hash.startsWith("at=")) api.seek(Number(hash.slice(3)));
  if (hash.startsWith("probe=")) {
    const results = hash.slice(6).split(",").map((v) => {
      const state = api.seek(Number(v));
      return { t: Number(v), state, drawn: api.drawn() };
    });
    const probe = document.getElementById("probe");
    probe.textContent = JSON.stringify({ layout: api.layout(), results, errors });
  }
})();
