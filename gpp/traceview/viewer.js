// The gpp trace viewer: draws the run in the page's embedded data (gpp/traceview/html.py) as
// an SVG timeline (lanes of activities, exogenous events, plans, fluent changes, waits, numeric
// series, bands of the values of the other fluents), with zoom, pan and tooltips; below it the
// activities that did not end final, with why. Vanilla JS, no dependencies, no network.
(function () {
  "use strict";

  const D = JSON.parse(document.getElementById("gpp-data").textContent);
  const svg = document.getElementById("chart");
  const tip = document.getElementById("tooltip");

  // ------------------------------------------------------------------ helpers

  const ESC = { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" };
  const esc = (s) => String(s).replace(/[&<>"']/g, (c) => ESC[c]);
  const CHAR_W = 6.6; // approximate width of a character of the 11px labels
  const SERIES_COLORS = ["#0969da", "#bf3989", "#1a7f37", "#9a6700", "#8250df", "#cf222e", "#0e8a9e"];

  function fmtTime(t, digits) {
    return t.toFixed(digits === undefined ? 3 : digits) + " s";
  }
  function fmtNum(v) {
    if (Number.isInteger(v)) return String(v);
    return String(Number(v.toPrecision(6)));
  }
  function plural(n, word, many) {
    return n + " " + (n === 1 ? word : many || word + "s");
  }
  function niceStep(raw) {
    if (!(raw > 0)) return 1;
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    for (const f of [1, 2, 5, 10]) if (f * p >= raw) return f * p;
    return 10 * p;
  }
  function stepDigits(step) {
    return step >= 1 ? 0 : Math.min(6, Math.ceil(-Math.log10(step) - 1e-9));
  }
  function fitText(text, width) {
    const n = Math.floor((width - 8) / CHAR_W);
    if (n >= text.length) return text;
    if (n < 4) return "";
    return text.slice(0, n - 1) + "…";
  }

  // ------------------------------------------------------------------ the page around the chart

  const program = D.program || "trace";
  const slash = program.lastIndexOf("/");
  document.getElementById("title").innerHTML =
    (slash >= 0 ? '<span class="dim">' + esc(program.slice(0, slash + 1)) + "</span>" : "") +
    esc(program.slice(slash + 1));
  const status = document.getElementById("status");
  status.textContent = D.status;
  status.className = "status " + D.status;
  const meta = [];
  if (D.platform) meta.push("platform <b>" + esc(D.platform) + "</b>");
  if (D.world) meta.push("world <b>" + esc(D.world) + "</b>");
  if (D.scenario) meta.push("scenario <b>" + esc(D.scenario) + "</b>");
  if (D.seed !== null && D.seed !== undefined) meta.push("seed <b>" + esc(D.seed) + "</b>");
  meta.push("<b>" + esc(fmtTime(D.end - D.start)) + "</b> platform time");
  const failed = D.activities.filter((a) => a.status !== "final").length;
  meta.push(
    "<b>" + D.activities.length + "</b> " + (D.activities.length === 1 ? "activity" : "activities") +
      (failed ? " (" + failed + " not final)" : "") + " in " + plural(D.lanes.length, "lane")
  );
  meta.push("<b>" + D.exog.length + "</b> exogenous " + (D.exog.length === 1 ? "event" : "events"));
  meta.push("<b>" + D.plans.length + "</b> " + (D.plans.length === 1 ? "plan" : "plans"));
  if (D.started) meta.push("started " + esc(D.started));
  document.getElementById("meta").innerHTML = meta.map((m) => "<span>" + m + "</span>").join("");
  document.getElementById("notes").innerHTML = D.notes.map((n) => "<div>" + esc(n) + "</div>").join("");
  document.getElementById("footer").textContent =
    "Made by gpp " + D.gppVersion + " from " + D.traceFile + " (" + plural(D.records, "record") + ").";

  // ------------------------------------------------------------------ geometry

  const ROW = 26; // an activity row
  const BAR = 18;
  const MARK = 30; // a row of marks
  const PLOT = 78; // a series panel
  const AXIS = 30;
  const PAD_R = 18;
  const longest = Math.max(
    14,
    ...D.lanes.map((l) => l.name.length + 4),
    ...D.series.map((s) => s.name.length),
    ...D.states.map((s) => s.name.length)
  );
  const GUTTER = Math.min(280, Math.max(150, Math.round(longest * 7.4 + 28)));

  const t0 = D.start;
  const t1 = D.end > D.start ? D.end : D.start + 1;
  const pad = (t1 - t0) * 0.015;
  const FULL = [t0 - pad, t1 + pad];
  let view = FULL.slice();
  let plotW = 800;

  const x = (t) => GUTTER + ((t - view[0]) / (view[1] - view[0])) * plotW;
  const timeAt = (px) => view[0] + ((px - GUTTER) / plotW) * (view[1] - view[0]);

  // The rows of the chart, top to bottom: {kind, y, h, ...}.
  const rows = [];
  let height = 0;
  function addRow(row) {
    row.y = height;
    rows.push(row);
    height += row.h;
  }
  addRow({ kind: "axis", h: AXIS, top: true });
  // Exogenous events: a row per action name (the first MAX_EXOG_ROWS names), then the rest.
  const MAX_EXOG_ROWS = 6;
  const exogRows = [];
  const exogRowOf = new Map();
  D.exog.forEach((e, i) => {
    const name = e.action.split("(")[0];
    let row = exogRowOf.get(name);
    if (row === undefined) {
      if (exogRows.length < MAX_EXOG_ROWS) {
        row = { name: name, items: [] };
        exogRows.push(row);
      } else {
        row = exogRows.find((r) => r.other) || (exogRows.push({ name: "other", other: true, items: [] }), exogRows[exogRows.length - 1]);
      }
      exogRowOf.set(name, row);
    }
    row.items.push(i);
  });
  if (exogRows.length) addRow({ kind: "group", h: 22, label: "exogenous events" });
  for (const row of exogRows) addRow({ kind: "exog", h: MARK, label: row.name, count: row.items.length, items: row.items, other: !!row.other });
  const operator = D.operator || []; // traces written before schema 1.8 have none
  if (operator.length) addRow({ kind: "operator", h: MARK, label: "operator", count: operator.length });
  if (D.plans.length || D.changes.length || D.waits.length || D.problems.length) addRow({ kind: "group", h: 22, label: "program" });
  if (D.plans.length) addRow({ kind: "plans", h: MARK, label: "plans", count: D.plans.length });
  if (D.changes.length) addRow({ kind: "changes", h: MARK + 14, label: "fluent changes", count: D.changes.length });
  if (D.waits.length || D.problems.length) {
    const label = D.waits.length ? (D.problems.length ? "waiting · stop" : "waiting") : "stop";
    addRow({ kind: "program", h: MARK, label: label });
  }
  if (D.lanes.length) addRow({ kind: "group", h: 22, label: "activities" });
  D.lanes.forEach((lane, i) => addRow({ kind: "lane", h: lane.rows * ROW + 4, lane: i }));
  if (D.series.length) addRow({ kind: "group", h: 22, label: "values over time" });
  D.series.forEach((s, i) => addRow({ kind: "series", h: PLOT, series: i }));
  if (D.states.length) addRow({ kind: "group", h: 22, label: "states over time" });
  D.states.forEach((s, i) => addRow({ kind: "state", h: ROW + 4, state: i }));
  addRow({ kind: "axis", h: AXIS, top: false });

  // ------------------------------------------------------------------ drawing

  let frame = 0;
  let hidden = 0; // activities left out of the last drawing (too dense to tell apart)
  function schedule() {
    if (!frame) frame = requestAnimationFrame(() => ((frame = 0), render()));
  }

  function render() {
    const W = Math.max(480, svg.clientWidth || svg.parentNode.clientWidth || 1000);
    plotW = W - GUTTER - PAD_R;
    const out = [];
    out.push(
      "<defs>" +
        '<clipPath id="plot-clip"><rect x="' + GUTTER + '" y="0" width="' + plotW + '" height="' + height + '"/></clipPath>' +
        '<pattern id="stripes" width="8" height="8" patternUnits="userSpaceOnUse" patternTransform="rotate(45)">' +
        '<rect width="8" height="8" fill="var(--running)" opacity="0.35"/><rect width="4" height="8" fill="var(--running)"/></pattern>' +
        '<pattern id="hatch" width="6" height="6" patternUnits="userSpaceOnUse" patternTransform="rotate(45)">' +
        '<rect width="6" height="6" fill="var(--wait)" opacity="0.15"/><rect width="2" height="6" fill="var(--wait)" opacity="0.6"/></pattern>' +
        "</defs>"
    );
    // Backgrounds and gutter labels.
    let stripe = 0;
    for (const row of rows) {
      if (row.kind === "axis") continue;
      if (row.kind === "group") {
        out.push('<line class="separator" x1="0" x2="' + W + '" y1="' + (row.y + 0.5) + '" y2="' + (row.y + 0.5) + '"/>');
        out.push('<text class="group-label" x="8" y="' + (row.y + 15) + '">' + esc(row.label) + "</text>");
        stripe = 0;
        continue;
      }
      out.push('<rect class="' + (stripe++ % 2 ? "row-b" : "row-a") + '" x="0" y="' + row.y + '" width="' + W + '" height="' + row.h + '"/>');
      if (row.kind === "lane") {
        const lane = D.lanes[row.lane];
        out.push(
          '<text class="lane-label" x="10" y="' + (row.y + ROW / 2 + 6) + '">' + esc(lane.name) +
            ' <tspan class="lane-count">×' + lane.count + "</tspan></text>"
        );
      } else if (row.kind === "state") {
        out.push('<text class="lane-label" x="10" y="' + (row.y + ROW / 2 + 6) + '">' + esc(D.states[row.state].name) + "</text>");
      } else if (row.kind === "series") {
        const s = D.series[row.series];
        out.push('<text class="lane-label" x="10" y="' + (row.y + 20) + '">' + esc(s.name) + "</text>");
        out.push('<text class="series-kind" x="10" y="' + (row.y + 35) + '">' + esc(s.kind) + "</text>");
      } else {
        out.push(
          '<text class="lane-label" x="10" y="' + (row.y + row.h / 2 + 4) + '">' + esc(row.label) +
            (row.count ? ' <tspan class="lane-count">×' + row.count + "</tspan>" : "") + "</text>"
        );
      }
    }
    // Grid and axes.
    const step = niceStep(((view[1] - view[0]) / plotW) * 90);
    const digits = stepDigits(step);
    const ticks = [];
    for (let t = Math.ceil(view[0] / step) * step; t <= view[1] + step * 1e-9; t += step) ticks.push(t);
    for (const t of ticks) {
      const px = x(t).toFixed(1);
      out.push('<line class="gridline" x1="' + px + '" x2="' + px + '" y1="' + AXIS + '" y2="' + (height - AXIS) + '"/>');
    }
    for (const row of rows) {
      if (row.kind !== "axis") continue;
      const base = row.top ? row.y + row.h - 0.5 : row.y + 0.5;
      out.push('<line class="separator" x1="' + GUTTER + '" x2="' + (GUTTER + plotW) + '" y1="' + base + '" y2="' + base + '"/>');
      for (const t of ticks) {
        const px = x(t).toFixed(1);
        const y2 = row.top ? base - 5 : base + 5;
        out.push('<line class="tick" x1="' + px + '" x2="' + px + '" y1="' + base + '" y2="' + y2 + '"/>');
        out.push(
          '<text class="axis-label" text-anchor="middle" x="' + px + '" y="' + (row.top ? base - 9 : base + 18) + '">' +
            esc(fmtTime(Math.abs(t) < step * 1e-6 ? 0 : t, digits)) + "</text>"
        );
      }
      out.push('<text class="axis-title" x="10" y="' + (row.top ? base - 9 : base + 18) + '">platform time</text>');
    }
    // Content, clipped to the plot area.
    hidden = 0;
    out.push('<g clip-path="url(#plot-clip)">');
    for (const row of rows) {
      if (row.kind === "exog") drawExog(out, row);
      else if (row.kind === "plans") drawPlans(out, row);
      else if (row.kind === "operator") drawOperator(out, row);
      else if (row.kind === "changes") drawChanges(out, row);
      else if (row.kind === "program") drawProgram(out, row);
      else if (row.kind === "lane") drawLane(out, row);
      else if (row.kind === "series") drawSeries(out, row);
      else if (row.kind === "state") drawState(out, row);
    }
    out.push("</g>");
    // Each series' lowest and highest value, at their heights in the gutter's right edge.
    for (const row of rows) {
      if (row.kind !== "series") continue;
      const s = D.series[row.series];
      const values = s.samples.map((p) => p.v);
      const lo = Math.min(...values);
      const hi = Math.max(...values);
      const y = seriesY(s, row);
      for (const v of lo === hi ? [lo] : [lo, hi]) {
        out.push('<line class="tick" x1="' + (GUTTER - 4) + '" x2="' + GUTTER + '" y1="' + y(v).toFixed(1) + '" y2="' + y(v).toFixed(1) + '"/>');
        out.push('<text class="series-y" text-anchor="end" x="' + (GUTTER - 7) + '" y="' + (y(v) + 3.5).toFixed(1) + '">' + esc(fmtNum(v)) + "</text>");
      }
    }
    out.push('<g id="crosshair" visibility="hidden"><line class="crosshair" x1="0" x2="0" y1="' + AXIS + '" y2="' + (height - AXIS) + '"/>' +
      '<rect class="crosshair-bg" x="0" y="' + (AXIS - 22) + '" width="70" height="18" rx="4"/>' +
      '<text class="crosshair-label" text-anchor="middle" x="0" y="' + (AXIS - 9) + '"></text></g>');
    svg.setAttribute("viewBox", "0 0 " + W + " " + height);
    svg.setAttribute("width", W);
    svg.setAttribute("height", height);
    svg.innerHTML = out.join("");
    document.getElementById("range").textContent =
      "showing " + fmtTime(Math.max(view[0], t0), digits + 1) + " – " + fmtTime(Math.min(view[1], t1), digits + 1) +
      " of " + fmtTime(t0, 0) + " – " + fmtTime(D.end, 3) +
      (hidden ? " · " + plural(hidden, "activity", "activities") + " too short to draw at this zoom" : "");
    // What this drawing shows, for tests and tools that drive the page (the view changes at
    // once, the drawing at the next frame): data-view is the time window drawn ("start end",
    // seconds, margins included) and data-plot the plot area in the chart's pixels ("left
    // width"), so a pixel px of the chart is at time start + (px - left) / width * (end - start).
    svg.setAttribute("data-view", view[0] + " " + view[1]);
    svg.setAttribute("data-plot", GUTTER + " " + plotW);
  }

  // Labels right of marks, cut short before the next mark and skipped where they would not
  // fit. `marks` are the marks' x positions in order. With `whole`, a label that would be cut
  // is not drawn (the caller tries another line); the result says whether one was drawn.
  function labeller(marks) {
    let free = -Infinity;
    let next = 0;
    return function (out, px, y, text, cls, shorter, whole) {
      while (next < marks.length && marks[next] <= px + 1) next++;
      if (!text || px + 8 < free) return false;
      const limit = Math.min(next < marks.length ? marks[next] - 8 : Infinity, GUTTER + plotW) - (px + 8);
      let shown = text.length * CHAR_W <= limit ? text : "";
      if (!shown && shorter) shown = shorter.length * CHAR_W <= limit ? shorter : "";
      if (!shown && !whole) shown = fitText(text, limit + 8);
      if (!shown) return false;
      out.push('<text class="' + (cls || "mark-label") + '" x="' + (px + 8).toFixed(1) + '" y="' + y + '">' + esc(shown) + "</text>");
      free = px + 8 + shown.length * CHAR_W + 10;
      return true;
    };
  }

  // Marks that would overlap (closer than `gap` pixels to the first of them), as one: [{px,
  // items}] (items in time order). Simultaneous events get one mark, one label and one tooltip
  // listing them all.
  function together(items, pxOf, gap) {
    const out = [];
    for (const i of items) {
      const px = pxOf(i);
      const last = out[out.length - 1];
      if (last && px - last.px < gap) last.items.push(i);
      else out.push({ px: px, items: [i] });
    }
    return out;
  }

  const times = (n) => (n > 1 ? "×" + n + " " : "");

  function visible(px) {
    return px > GUTTER - 20 && px < GUTTER + plotW + 20;
  }

  function drawExog(out, row) {
    const cy = row.y + row.h / 2;
    const marks = together(row.items, (i) => x(D.exog[i].t), 12);
    const label = labeller(marks.map((m) => m.px));
    for (const m of marks) {
      if (!visible(m.px)) continue;
      const events = m.items.map((i) => D.exog[i]);
      const silent = events.every((e) => e.silent);
      const r = silent ? 4.5 : 6;
      const cls = "exog-mark" + (events.every((e) => e.precondition) ? "" : " false-pre") + (silent ? " silent" : "");
      out.push(
        '<g class="exog" data-tip="exog:' + m.items.join(",") + '" data-action="' + esc(events.map((e) => e.action).join("; ")) +
          '" data-count="' + events.length + '" data-t="' + events[0].t + '">' +
          '<path class="' + cls + '" d="M' + m.px.toFixed(1) + " " + (cy - r) + " l" + r + " " + r + " l" + -r + " " + r + " l" + -r + " " + -r + 'z"/>' +
          "</g>"
      );
      // The row names the action: its arguments are the label (all of it in the row of the rest).
      const texts = events.map((e) => (row.other ? e.action : e.action.slice(e.action.indexOf("(")))).filter((t) => t.length > 2);
      label(out, m.px, cy + 4, times(events.length) + texts.join(", "), null, events.length > 1 ? "×" + events.length : "");
    }
  }

  // What operators did at the console: a square per request, labelled with the command.
  function drawOperator(out, row) {
    const cy = row.y + row.h / 2;
    const label = labeller(operator.map((o) => x(o.t)));
    operator.forEach((o, i) => {
      const px = x(o.t);
      if (!visible(px)) return;
      out.push(
        '<g class="operator" data-tip="operator:' + i + '" data-command="' + esc(o.command) + '" data-t="' + o.t + '">' +
          '<rect class="operator-mark" x="' + (px - 5).toFixed(1) + '" y="' + (cy - 5) + '" width="10" height="10"/></g>'
      );
      label(out, px + 2, cy + 4, o.command + (o.action ? " " + o.action : ""));
    });
  }

  function drawPlans(out, row) {
    const cy = row.y + row.h / 2;
    const label = labeller(D.plans.map((p) => x(p.t)));
    D.plans.forEach((p, i) => {
      const px = x(p.t);
      if (!visible(px)) return;
      const cls = "plan-mark" + (p.event === "replan" ? " replan" : "") + (p.feasible ? "" : " infeasible");
      out.push(
        '<g class="plan" data-tip="plan:' + i + '" data-t="' + p.t + '" data-value="' + p.value + '">' +
          '<path class="' + cls + '" d="M' + (px - 7).toFixed(1) + " " + (cy + 6) + " L" + px.toFixed(1) + " " + (cy - 7) + " L" + (px + 7).toFixed(1) + " " + (cy + 6) + 'z"/>' +
          "</g>"
      );
      label(out, px + 2, cy + 4, p.feasible ? p.kind + " · value " + fmtNum(p.value) + " · h " + p.horizon : p.kind + ": no plan");
    });
  }

  // Fluent changes: one mark for those at one time, its label on the first of two lines where
  // it fits whole (beside the marks, or below them where only other labels are in the way).
  function drawChanges(out, row) {
    const cy = row.y + 11;
    const marks = together(D.changes.map((c, i) => i), (i) => x(D.changes[i].t), 9);
    const beside = labeller(marks.map((m) => m.px));
    const below = labeller([]);
    for (const m of marks) {
      if (!visible(m.px)) continue;
      const changes = m.items.map((i) => D.changes[i]);
      out.push(
        '<g class="change" data-tip="change:' + m.items.join(",") + '" data-fluent="' + esc(changes.map((c) => c.fluent).join("; ")) +
          '" data-count="' + changes.length + '"><circle class="change-mark ' + changes[0].event + '" cx="' + m.px.toFixed(1) + '" cy="' + cy + '" r="4.5"/></g>'
      );
      const text = times(changes.length) + changes.map((c) => c.fluent + " = " + c.value).join(", ");
      const shorter = changes.length > 1 ? "×" + changes.length + " changes" : "";
      if (!beside(out, m.px, cy + 4, text, null, null, true) && !below(out, m.px - 8, cy + 19, text, null, null, true))
        beside(out, m.px, cy + 4, text, null, shorter, false);
    }
  }

  function drawProgram(out, row) {
    const cy = row.y + row.h / 2;
    D.waits.forEach((w, i) => {
      const a = x(w.start);
      const b = x(w.stop === null ? D.end : w.stop);
      out.push(
        '<g class="wait-span" data-tip="wait:' + i + '"><rect class="wait" x="' + a.toFixed(1) + '" y="' + (cy - 8) +
          '" width="' + Math.max(3, b - a).toFixed(1) + '" height="16" rx="3"/></g>'
      );
    });
    const label = labeller(D.problems.map((p) => x(p.t)));
    D.problems.forEach((p, i) => {
      const px = x(p.t);
      out.push(
        '<g class="problem" data-tip="problem:' + i + '"><circle class="problem-mark" cx="' + px.toFixed(1) + '" cy="' + cy + '" r="7"/>' +
          '<text x="' + px.toFixed(1) + '" y="' + (cy + 4) + '" text-anchor="middle" fill="#fff" font-size="11" font-weight="700" pointer-events="none">!</text></g>'
      );
      const text = p.event + (p.code ? " " + p.code : "");
      if (px + 12 + text.length * CHAR_W > GUTTER + plotW) {
        // At the end of the run (where a run stops): the label goes left of the mark.
        out.push('<text class="problem-label" text-anchor="end" x="' + (px - 11).toFixed(1) + '" y="' + (cy + 4) + '">' + esc(text) + "</text>");
      } else {
        label(out, px + 2, cy + 4, text, "problem-label");
      }
    });
  }

  function drawLane(out, row) {
    const lane = D.lanes[row.lane];
    const covered = [];
    // Activities that did not end final are drawn over the final ones: a failed attempt that
    // took no time stays visible beside its retry.
    const onTop = [];
    let previous = -1;
    let alt = false;
    for (const id of lane.activities) {
      const a = D.activities[id];
      const top = row.y + 2 + a.row * ROW + (ROW - BAR) / 2;
      const px0 = x(a.start);
      const px1 = x(a.stop);
      if (previous >= 0 && a.row === 0) alt = !alt;
      previous = id;
      const w = Math.max(3, px1 - px0);
      if (px0 + w < GUTTER - 50 || px0 > GUTTER + plotW + 50) continue; // off screen
      // A final activity that would be drawn inside the pixels already drawn in its row (a dense
      // run seen whole) is left out: zooming in shows it.
      const drawn = covered[a.row] === undefined ? -Infinity : covered[a.row];
      if (a.status === "final" && px1 <= drawn) {
        hidden++;
        continue;
      }
      covered[a.row] = Math.max(drawn, px0 + w);
      let cls = "bar " + a.status + (alt && a.status === "final" ? " alt" : "") + (a.silent ? " silent" : "") + (a.unhandled ? " unhandled" : "");
      let inner = '<rect class="' + cls + '" x="' + px0.toFixed(1) + '" y="' + top + '" width="' + w.toFixed(1) + '" height="' + BAR + '" rx="3"/>';
      if (a.consumedAt !== null && a.consumedAt > a.stop) {
        const cx = x(a.consumedAt);
        inner += '<line class="tail" x1="' + (px0 + w).toFixed(1) + '" x2="' + cx.toFixed(1) + '" y1="' + (top + BAR / 2) + '" y2="' + (top + BAR / 2) + '"/>';
      }
      if (a.cancelledAt !== null) {
        const cx = x(a.cancelledAt).toFixed(1);
        inner += '<line class="cancel-tick" x1="' + cx + '" x2="' + cx + '" y1="' + (top - 3) + '" y2="' + (top + BAR + 3) + '"/>';
      }
      // The label: the whole action where it fits (with why it failed or was cancelled), else
      // its arguments.
      const visibleW = Math.min(px0 + w, GUTTER + plotW) - Math.max(px0, GUTTER);
      const args = a.action.slice(lane.name.length);
      const why = a.status === "final" ? "" : whyNotFinal(a);
      const text =
        (why && (a.action + " · " + why).length * CHAR_W + 8 <= visibleW ? a.action + " · " + why : "") ||
        fitText(a.action, visibleW) || (args.length > 2 ? fitText(args, visibleW) : "");
      if (text) {
        inner += '<text class="bar-label ' + a.status + '" x="' + (Math.max(px0, GUTTER) + 5).toFixed(1) + '" y="' + (top + BAR / 2 + 4) + '">' + esc(text) + "</text>";
      }
      (a.status === "final" ? out : onTop).push(barGroup(a, id, inner));
    }
    out.push(...onTop);
  }

  // Why an activity did not end final: the platform's reason, the cancel's, and whether the
  // program handled it.
  function whyNotFinal(a) {
    const parts = [];
    if (a.reason) parts.push(a.reason);
    if (a.cancelReason && a.cancelReason !== a.reason) parts.push(a.cancelReason);
    if (a.status === "running") parts.push("still running at the end of the trace");
    if (a.unhandled) parts.push("not handled by the program");
    return parts.join("; ");
  }

  function barGroup(a, id, inner) {
    return (
      '<g class="activity" data-tip="activity:' + id + '" data-id="' + a.id + '" data-action="' + esc(a.action) +
        '" data-status="' + a.status + '" data-lane="' + esc(D.lanes[a.lane].name) + '">' + inner + "</g>"
    );
  }

  function seriesRange(s) {
    let lo = Infinity;
    let hi = -Infinity;
    for (const p of s.samples) {
      lo = Math.min(lo, p.v);
      hi = Math.max(hi, p.v);
    }
    if (lo === hi) {
      const d = Math.abs(lo) > 0 ? Math.abs(lo) * 0.1 : 1;
      return [lo - d, hi + d];
    }
    return [lo, hi];
  }

  // The y position of a value in a series' panel.
  function seriesY(s, row) {
    const [lo, hi] = seriesRange(s);
    const top = row.y + 12;
    const bottom = row.y + row.h - 12;
    return (v) => bottom - ((v - lo) / (hi - lo)) * (bottom - top);
  }

  function drawSeries(out, row) {
    const s = D.series[row.series];
    const color = SERIES_COLORS[row.series % SERIES_COLORS.length];
    const y = seriesY(s, row);
    const bottom = row.y + row.h - 2;
    // A step line: each value holds until the next sample, the last until the end of the run.
    let d = "";
    s.samples.forEach((p, i) => {
      const px = x(p.t).toFixed(1);
      const py = y(p.v).toFixed(1);
      d += i === 0 ? "M" + px + " " + py : "H" + px + "V" + py;
    });
    d += "H" + x(D.end).toFixed(1);
    const first = x(s.samples[0].t).toFixed(1);
    out.push(
      '<g class="series" data-name="' + esc(s.name) + '" data-samples="' + s.samples.length + '">' +
        '<path class="series-area" fill="' + color + '" d="' + d + "V" + bottom + "H" + first + 'Z"/>' +
        '<path class="series-line" stroke="' + color + '" d="' + d + '"/>'
    );
    s.samples.forEach((p, i) => {
      const px = x(p.t);
      if (!visible(px)) return;
      out.push(
        '<circle class="series-dot" data-tip="sample:' + row.series + ":" + i + '" fill="' + color + '" cx="' + px.toFixed(1) +
          '" cy="' + y(p.v).toFixed(1) + '" r="4"/>'
      );
    });
    out.push("</g>");
  }

  // The bands of a fluent's values: one colour per value, the value written where it fits.
  function drawState(out, row) {
    const s = D.states[row.state];
    const top = row.y + 2 + (ROW - BAR) / 2;
    s.segments.forEach((g, j) => {
      const a = x(g.start);
      const w = Math.max(2, x(g.stop) - a);
      if (a + w < GUTTER - 50 || a > GUTTER + plotW + 50) return;
      const color = SERIES_COLORS[s.values.indexOf(g.value) % SERIES_COLORS.length];
      const text = fitText(g.value, Math.min(a + w, GUTTER + plotW) - Math.max(a, GUTTER));
      out.push(
        '<g class="state" data-tip="state:' + row.state + ":" + j + '" data-fluent="' + esc(s.name) + '" data-value="' + esc(g.value) + '">' +
          '<rect class="state-band" fill="' + color + '" stroke="' + color + '" x="' + a.toFixed(1) + '" y="' + top + '" width="' + w.toFixed(1) +
          '" height="' + BAR + '" rx="2"/>' +
          (text ? '<text class="state-label" x="' + (Math.max(a, GUTTER) + 5).toFixed(1) + '" y="' + (top + BAR / 2 + 4) + '">' + esc(text) + "</text>" : "") +
          "</g>"
      );
    });
  }

  // ------------------------------------------------------------------ tooltips

  function sourceHtml(at) {
    if (!at) return "";
    const m = /^(.*):(\d+):(\d+)$/.exec(at);
    let html = '<div class="loc">' + esc(at) + "</div>";
    if (!m) return html;
    const file = D.sources[m[1]];
    const line = Number(m[2]);
    const col = Number(m[3]);
    if (!file || file[line] === undefined) {
      return html + '<div class="nosrc">source line not embedded (the file was not found when the page was made)</div>';
    }
    html += '<pre class="src">';
    for (let l = line - 1; l <= line + 1; l++) {
      if (file[l] === undefined) continue;
      const text = file[l];
      let shown = esc(text);
      if (l === line && col >= 1 && col <= text.length) {
        // Underline the statement from the column the location names to its `;` (or the line's end).
        const rest = text.slice(col - 1);
        const semi = rest.indexOf(";");
        const span = (semi >= 0 ? rest.slice(0, semi + 1) : rest).replace(/\s+$/, "");
        shown = esc(text.slice(0, col - 1)) + '<span class="at">' + esc(span) + "</span>" + esc(rest.slice(span.length));
      }
      html += '<span class="line' + (l === line ? " hl" : "") + '"><span class="ln">' + l + "</span>" + shown + "</span>";
    }
    return html + "</pre>";
  }

  function table(rows) {
    return "<table>" + rows.filter((r) => r && r[1] !== "" && r[1] !== null && r[1] !== undefined)
      .map((r) => "<tr><td>" + esc(r[0]) + "</td><td>" + r[1] + "</td></tr>").join("") + "</table>";
  }

  function pill(statusText) {
    return '<span class="pill ' + esc(statusText) + '">' + esc(statusText) + "</span>";
  }

  function tipHtml(key) {
    const [kind, a, b] = key.split(":");
    if (a.includes(",")) return a.split(",").map((i) => tipHtml(kind + ":" + i)).join('<hr class="tip-rule">');
    const i = Number(a);
    if (kind === "activity") {
      const act = D.activities[i];
      const end = act.status === "running" ? "still running at the end of the trace" : fmtTime(act.stop);
      return (
        '<div class="kind">activity #' + act.id + (act.silent ? " · silent" : "") + "</div>" +
        '<div class="head">' + esc(act.action) + "</div>" +
        table([
          ["status", pill(act.status) + (act.unhandled ? " <b>not handled by the program</b>" : "")],
          ["started", esc(fmtTime(act.start))],
          ["terminated", esc(end) + (act.status === "running" ? "" : " (" + esc(fmtTime(act.stop - act.start)) + ")")],
          ["why", act.status === "final" ? "" : esc(whyNotFinal(act))],
          ["cancelled", act.cancelledAt === null ? "" : esc(fmtTime(act.cancelledAt)) + (act.cancelReason ? " (" + esc(act.cancelReason) + ")" : "")],
          ["taken", act.consumedAt === null ? "" : esc(fmtTime(act.consumedAt)) + " by " + esc(act.hook)],
          ["platform", '<span class="policy">' + esc(act.mapped) + (act.args.length ? " { " + esc(act.args.join(", ")) + " }" : "") + "</span>"],
          ["result", act.result === null ? "" : '<span class="policy">' + esc(act.result) + "</span>"],
        ]) + sourceHtml(act.at)
      );
    }
    if (kind === "operator") {
      const o = operator[i];
      return (
        '<div class="kind">operator at the console</div>' +
        '<div class="head">' + esc(o.command + (o.action ? " " + o.action : "")) + "</div>" +
        table([
          ["at", esc(fmtTime(o.t))],
          ["who", o.client ? esc(o.client) : ""],
        ])
      );
    }
    if (kind === "exog") {
      const e = D.exog[i];
      return (
        '<div class="kind">exogenous event' + (e.silent ? " · silent" : "") + "</div>" +
        '<div class="head">' + esc(e.action) + "</div>" +
        table([
          ["at", esc(fmtTime(e.t))],
          ["precondition", e.precondition ? "" : "<b>false</b> (its effects were applied anyway)"],
          ["effect", e.failed ? "<b>failed</b> (the run stopped: see the error)" : ""],
        ])
      );
    }
    if (kind === "plan") {
      const p = D.plans[i];
      const policy = p.policy.length
        ? p.policy.map((s) => '<span class="step">' + esc(s) + "</span>").join('<span class="arrow">→</span>')
        : "(nothing to do)";
      return (
        '<div class="kind">' + esc(p.event) + " · " + esc(p.kind) + "</div>" +
        '<div class="head">' + (p.feasible ? "value " + esc(fmtNum(p.value)) : "no feasible plan") + "</div>" +
        table([
          ["at", esc(fmtTime(p.t))],
          ["horizon", esc(p.horizon)],
          ["policy", p.feasible ? policy : ""],
          ["nodes", esc(p.nodes) + " expanded, " + esc(p.cacheHits) + " cache hits, " + esc(p.pruned) + " pruned"],
          ["rewards", esc(p.rewardEvaluations) + " evaluations"],
          ["planning", esc(p.seconds.toFixed(3)) + " s wall clock"],
        ])
      );
    }
    if (kind === "change") {
      const c = D.changes[i];
      return (
        '<div class="kind">' + (c.event === "sense" ? "sensed" : "assigned") + "</div>" +
        '<div class="head">' + esc(c.fluent) + " = " + esc(c.value) + "</div>" +
        table([["at", esc(fmtTime(c.t))], ["by", c.action ? esc(c.action) : ""]]) + sourceHtml(c.at)
      );
    }
    if (kind === "wait") {
      const w = D.waits[i];
      return (
        '<div class="kind">waiting</div><div class="head">' + esc(w.statement) + "</div>" +
        table([
          ["waits for", '<span class="policy">' + esc(w.condition) + "</span>"],
          ["from", esc(fmtTime(w.start))],
          ["until", w.stop === null ? "the end of the trace" : esc(fmtTime(w.stop))],
        ]) + sourceHtml(w.at)
      );
    }
    if (kind === "problem") {
      const p = D.problems[i];
      return (
        '<div class="kind">' + esc(p.event) + (p.code ? " · " + esc(p.code) : "") + "</div>" +
        '<div class="head">' + esc(p.message) + "</div>" + table([["at", esc(fmtTime(p.t))]]) + sourceHtml(p.at)
      );
    }
    if (kind === "state") {
      const s = D.states[i];
      const g = s.segments[Number(b)];
      return (
        '<div class="kind">state</div>' +
        '<div class="head">' + esc(s.name) + " = " + esc(g.value) + "</div>" +
        table([
          ["from", esc(fmtTime(g.start))],
          ["until", esc(fmtTime(g.stop)) + " (" + esc(fmtTime(g.stop - g.start)) + ")"],
          ["by", esc(g.label)],
        ])
      );
    }
    if (kind === "sample") {
      const s = D.series[i];
      const p = s.samples[Number(b)];
      return (
        '<div class="kind">' + esc(s.kind) + "</div>" +
        '<div class="head">' + esc(s.name) + " = " + esc(fmtNum(p.v)) + "</div>" +
        table([["at", esc(fmtTime(p.t))], ["by", esc(p.label)]]) + sourceHtml(p.at)
      );
    }
    return "";
  }

  let tipKey = null;
  let highlighted = null;
  function showTip(el, key, ev) {
    if (key !== tipKey) {
      tip.innerHTML = tipHtml(key);
      tip.hidden = false;
      tipKey = key;
      if (highlighted) highlighted.classList.remove("hover-hl");
      highlighted = el;
      el.classList.add("hover-hl");
    }
    const margin = 14;
    const r = tip.getBoundingClientRect();
    let left = ev.clientX + margin;
    let top = ev.clientY + margin;
    if (left + r.width > window.innerWidth - 4) left = Math.max(4, ev.clientX - margin - r.width);
    if (top + r.height > window.innerHeight - 4) top = Math.max(4, ev.clientY - margin - r.height);
    tip.style.left = left + "px";
    tip.style.top = top + "px";
  }
  function hideTip() {
    tip.hidden = true;
    tipKey = null;
    if (highlighted) highlighted.classList.remove("hover-hl");
    highlighted = null;
  }

  function svgPoint(ev) {
    const r = svg.getBoundingClientRect();
    return [ev.clientX - r.left, ev.clientY - r.top];
  }

  function moveCrosshair(ev) {
    const cross = document.getElementById("crosshair");
    if (!cross) return;
    const [px] = svgPoint(ev);
    if (px < GUTTER || px > GUTTER + plotW) {
      cross.setAttribute("visibility", "hidden");
      return;
    }
    cross.setAttribute("visibility", "visible");
    cross.setAttribute("transform", "translate(" + px.toFixed(1) + ",0)");
    const label = cross.querySelector("text");
    const text = fmtTime(timeAt(px), stepDigits(niceStep(((view[1] - view[0]) / plotW) * 90)) + 1);
    label.textContent = text;
    const bg = cross.querySelector("rect");
    const w = text.length * CHAR_W + 10;
    bg.setAttribute("width", w.toFixed(0));
    bg.setAttribute("x", (-w / 2).toFixed(0));
  }

  // ------------------------------------------------------------------ zoom and pan

  function setView(a, b) {
    const total = FULL[1] - FULL[0];
    const minSpan = Math.max(total * 1e-5, 1e-6);
    let span = Math.min(Math.max(b - a, minSpan), total);
    let lo = a;
    if (b - a !== span) lo = (a + b) / 2 - span / 2;
    lo = Math.min(Math.max(lo, FULL[0]), FULL[1] - span);
    view = [lo, lo + span];
    schedule();
  }
  function zoomAt(t, factor) {
    setView(t - (t - view[0]) * factor, t + (view[1] - t) * factor);
  }

  let drag = null;
  svg.addEventListener("wheel", (ev) => {
    ev.preventDefault();
    const [px] = svgPoint(ev);
    if (Math.abs(ev.deltaX) > Math.abs(ev.deltaY)) {
      const dt = (ev.deltaX / plotW) * (view[1] - view[0]);
      setView(view[0] + dt, view[1] + dt);
    } else {
      const t = px < GUTTER ? (view[0] + view[1]) / 2 : timeAt(px);
      zoomAt(t, Math.exp(ev.deltaY * (ev.deltaMode === 1 ? 0.05 : 0.0015)));
    }
  }, { passive: false });
  svg.addEventListener("pointerdown", (ev) => {
    if (ev.button !== 0) return;
    drag = { x: ev.clientX, view: view.slice(), moved: false };
    svg.setPointerCapture(ev.pointerId);
  });
  svg.addEventListener("pointermove", (ev) => {
    if (drag) {
      const dx = ev.clientX - drag.x;
      if (Math.abs(dx) > 2) {
        drag.moved = true;
        svg.classList.add("dragging");
        hideTip();
      }
      const dt = (dx / plotW) * (drag.view[1] - drag.view[0]);
      setView(drag.view[0] - dt, drag.view[1] - dt);
      return;
    }
    moveCrosshair(ev);
    const el = ev.target.closest ? ev.target.closest("[data-tip]") : null;
    if (el) showTip(el, el.getAttribute("data-tip"), ev);
    else hideTip();
  });
  const endDrag = () => {
    drag = null;
    svg.classList.remove("dragging");
  };
  svg.addEventListener("pointerup", endDrag);
  svg.addEventListener("pointercancel", endDrag);
  svg.addEventListener("pointerleave", () => {
    hideTip();
    const cross = document.getElementById("crosshair");
    if (cross) cross.setAttribute("visibility", "hidden");
  });
  svg.addEventListener("dblclick", () => setView(FULL[0], FULL[1]));
  document.getElementById("zoom-in").addEventListener("click", () => zoomAt((view[0] + view[1]) / 2, 0.5));
  document.getElementById("zoom-out").addEventListener("click", () => zoomAt((view[0] + view[1]) / 2, 2));
  document.getElementById("zoom-fit").addEventListener("click", () => setView(FULL[0], FULL[1]));
  document.addEventListener("keydown", (ev) => {
    if (ev.target && /INPUT|TEXTAREA|SELECT/.test(ev.target.tagName)) return;
    const span = view[1] - view[0];
    if (ev.key === "+" || ev.key === "=") zoomAt((view[0] + view[1]) / 2, 0.5);
    else if (ev.key === "-" || ev.key === "_") zoomAt((view[0] + view[1]) / 2, 2);
    else if (ev.key === "0") setView(FULL[0], FULL[1]);
    else if (ev.key === "ArrowLeft") setView(view[0] - span * 0.2, view[1] - span * 0.2);
    else if (ev.key === "ArrowRight") setView(view[0] + span * 0.2, view[1] + span * 0.2);
  });
  window.addEventListener("resize", schedule);

  function focus(a, b) {
    const span = Math.max(b - a, (FULL[1] - FULL[0]) * 0.02);
    setView(a - span * 0.5, b + span * 0.5);
  }

  // ------------------------------------------------------------------ legend and tables

  const legend = [];
  const swatch = (cls, extra) =>
    '<svg width="22" height="12"><rect class="bar ' + cls + '" x="0" y="1" width="22" height="10" rx="2"' + (extra || "") + "/></svg>";
  const statuses = new Set(D.activities.map((a) => a.status));
  legend.push("<span>" + swatch("final") + "final</span>");
  if (statuses.has("failed")) legend.push("<span>" + swatch("failed") + "failed</span>");
  if (statuses.has("cancelled")) legend.push("<span>" + swatch("cancelled") + "cancelled</span>");
  if (statuses.has("running")) legend.push("<span>" + swatch("running") + "running at the end</span>");
  if (D.activities.some((a) => a.cancelledAt !== null))
    legend.push('<span><svg width="6" height="14"><line class="cancel-tick" x1="3" x2="3" y1="0" y2="14"/></svg>cancel requested</span>');
  if (D.activities.some((a) => a.consumedAt !== null && a.consumedAt > a.stop))
    legend.push('<span><svg width="22" height="12"><line class="tail" x1="0" x2="22" y1="6" y2="6"/></svg>until the program took the outcome</span>');
  if (D.exog.length)
    legend.push('<span><svg width="12" height="12"><path class="exog-mark" d="M6 0 l6 6 l-6 6 l-6 -6z"/></svg>exogenous event</span>');
  if (D.exog.some((e) => !e.precondition))
    legend.push('<span><svg width="12" height="12"><path class="exog-mark false-pre" d="M6 0 l6 6 l-6 6 l-6 -6z"/></svg>precondition false</span>');
  if (D.plans.length)
    legend.push('<span><svg width="14" height="12"><path class="plan-mark" d="M0 12 L7 0 L14 12z"/></svg>plan</span>');
  if (D.plans.some((p) => p.event === "replan"))
    legend.push('<span><svg width="14" height="12"><path class="plan-mark replan" d="M1 11 L7 1 L13 11z"/></svg>replan</span>');
  if (D.changes.length)
    legend.push('<span><svg width="10" height="10"><circle class="change-mark" cx="5" cy="5" r="4.5"/></svg>assigned</span>');
  if (D.changes.some((c) => c.event === "sense"))
    legend.push('<span><svg width="10" height="10"><circle class="change-mark sense" cx="5" cy="5" r="4"/></svg>sensed</span>');
  if (D.waits.length) legend.push('<span><svg width="22" height="12"><rect class="wait" x="0" y="1" width="22" height="10" rx="2"/></svg>waiting</span>');
  if (D.problems.length) legend.push('<span><svg width="12" height="12"><circle class="problem-mark" cx="6" cy="6" r="6"/></svg>error / blocked</span>');
  document.getElementById("legend").innerHTML = legend.join("");

  if (D.plans.length) {
    document.getElementById("plans-card").hidden = false;
    document.getElementById("plans-count").textContent = "(" + D.plans.length + ")";
    const head =
      "<tr><th>time</th><th>kind</th><th>value</th><th>horizon</th><th>nodes</th><th>cache hits</th>" +
      "<th>pruned</th><th>rewards</th><th>took</th><th>policy</th></tr>";
    const body = D.plans.map((p, i) => {
      const policy = p.feasible
        ? p.policy.map((s) => '<span class="step">' + esc(s) + "</span>").join('<span class="arrow">→</span>') || "(nothing to do)"
        : "<b>no feasible plan</b>";
      return (
        '<tr data-plan="' + i + '"><td class="num">' + esc(fmtTime(p.t)) + "</td><td>" + esc(p.kind) +
          (p.event === "replan" ? " (replan)" : "") + '</td><td class="num">' + esc(fmtNum(p.value)) +
          '</td><td class="num">' + p.horizon + '</td><td class="num">' + p.nodes + '</td><td class="num">' +
          p.cacheHits + '</td><td class="num">' + p.pruned + '</td><td class="num">' + p.rewardEvaluations +
          '</td><td class="num">' + esc(p.seconds.toFixed(3)) + " s</td><td>" + policy + "</td></tr>"
      );
    });
    const tableEl = document.getElementById("plans-table");
    tableEl.className = "data";
    tableEl.innerHTML = "<thead>" + head + "</thead><tbody>" + body.join("") + "</tbody>";
    tableEl.addEventListener("click", (ev) => {
      const tr = ev.target.closest("tr[data-plan]");
      if (!tr) return;
      const p = D.plans[Number(tr.getAttribute("data-plan"))];
      const end = D.activities.filter((a) => a.start >= p.t).slice(0, Math.max(1, p.policy.length)).reduce((m, a) => Math.max(m, a.stop), p.t);
      focus(p.t, end);
    });
  }

  // A click on a row of an activity table shows that activity on the timeline.
  function showsActivityOnClick(tableEl) {
    tableEl.addEventListener("click", (ev) => {
      const tr = ev.target.closest("tr[data-activity]");
      if (!tr) return;
      const a = D.activities[Number(tr.getAttribute("data-activity"))];
      focus(a.start, a.stop);
      document.getElementById("timeline-card").scrollIntoView({ behavior: "smooth", block: "start" });
    });
  }

  // What did not end final, with why, on the page (not only in a tooltip).
  const troubles = D.activities.map((a, i) => i).filter((i) => D.activities[i].status !== "final");
  if (troubles.length) {
    document.getElementById("failures-card").hidden = false;
    document.getElementById("failures-count").textContent = "(" + troubles.length + ")";
    const failTable = document.getElementById("failures-table");
    failTable.className = "data";
    failTable.innerHTML =
      "<thead><tr><th>started</th><th>activity</th><th>status</th><th>why</th><th>source</th></tr></thead><tbody>" +
      troubles.map((i) => {
        const a = D.activities[i];
        return (
          '<tr data-activity="' + i + '"><td class="num">' + esc(fmtTime(a.start)) + '</td><td class="code">' + esc(a.action) +
            "</td><td>" + pill(a.status) + '</td><td class="why">' + esc(whyNotFinal(a)) + '</td><td class="code">' + esc(a.at || "") + "</td></tr>"
        );
      }).join("") + "</tbody>";
    showsActivityOnClick(failTable);
  }

  document.getElementById("activities-count").textContent = "(" + D.activities.length + ")";
  const actTable = document.getElementById("activities-table");
  actTable.className = "data";
  // Filled when first opened (a long run has many).
  const details = document.querySelector("#activities-card details");
  details.addEventListener("toggle", function fill() {
    details.removeEventListener("toggle", fill);
    fillActivities();
  });
  const fillActivities = () => (actTable.innerHTML =
    "<thead><tr><th>#</th><th>activity</th><th>status</th><th>start</th><th>end</th><th>duration</th><th>taken by</th><th>source</th></tr></thead><tbody>" +
    D.activities.map((a, i) =>
      '<tr data-activity="' + i + '"><td class="num">' + a.id + '</td><td class="code">' + esc(a.action) + "</td><td>" + pill(a.status) +
        '</td><td class="num">' + esc(fmtTime(a.start)) + '</td><td class="num">' + (a.status === "running" ? "—" : esc(fmtTime(a.stop))) +
        '</td><td class="num">' + esc(fmtTime(a.stop - a.start)) + "</td><td>" + esc(a.hook || "") + '</td><td class="code">' + esc(a.at || "") + "</td></tr>"
    ).join("") + "</tbody>");
  showsActivityOnClick(actTable);

  render();
  document.body.setAttribute("data-ready", "true");
})();
