// pkm explore: the atlas on the left, the design under the cursor (or the last click) on the right.
// Every number comes from the JSON API of the server that serves this page, or, in a static export,
// from the answers embedded in it (the element #pkm-static).
(function () {
  "use strict";

  const embedded = document.getElementById("pkm-static");
  const offline = embedded ? JSON.parse(embedded.textContent) : null;
  const HOVER_DELAY = 120; // ms the cursor rests on a design before its map is asked for
  const RETURN_DELAY = 400; // ms after the cursor leaves the atlas before the clicked design returns
  const PLOT = { displaylogo: false, responsive: true };
  // the top margin holds plotly's mode bar (its top 25 px or so) and below it the title, above the plotting area
  const MARGIN = { l: 60, r: 20, t: 64, b: 50 };

  // The page's state, read by the tests and the benchmark: the answers as drawn, and the time from each
  // click on the atlas to its map drawn (ms).
  const state = {
    static: offline !== null, stopped: false, meta: null, atlas: null, optimum: null, mode: null, clicked: null,
    shown: null, design: null, map: null, card: null, linkage: null, pose: null, followed: false, certified: null,
    timings: [], errors: [], drawn: { atlas: 0, map: 0, card: 0, certified: 0 }, seq: { atlas: 0, map: 0, card: 0 },
  };
  window.pkmExplore = state;

  const $ = (id) => document.getElementById(id);
  const controllers = {};
  let hoverTimer = null;
  let returnTimer = null;
  let linkageBusy = false;
  let linkagePending = null;

  function fmt(x) {
    return x === null || x === undefined || !Number.isFinite(x) ? "NaN" : String(Number(x.toPrecision(6)));
  }

  function escape(text) {
    return String(text).replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
  }

  function status(text, error) {
    const el = $("status");
    el.textContent = text;
    el.classList.toggle("error", Boolean(error));
    if (error) state.errors.push(text);
  }

  function unit(u) {
    return u && u !== "-" ? ` [${u}]` : "";
  }

  // the API: one request of each kind in flight, an older one aborted; none once the server is stopped
  async function api(endpoint, fields, kind) {
    if (state.stopped) throw new DOMException("the server has stopped", "AbortError");
    const query = new URLSearchParams();
    for (const [k, v] of Object.entries(fields)) if (v !== undefined && v !== null && v !== "") query.set(k, v);
    if (kind) {
      if (controllers[kind]) controllers[kind].abort();
      controllers[kind] = new AbortController();
    }
    const response = await fetch(`/api/${endpoint}?${query}`, kind ? { signal: controllers[kind].signal } : {});
    const data = await response.json();
    if (!response.ok) {
      const error = new Error(data.error + (data.field ? ` (field ${data.field})` : ""));
      error.field = data.field;
      error.cancelled = response.status === 409;
      throw error;
    }
    return data;
  }

  // the Cancel button, shown while the server computes an atlas or a certification for this page
  const running = new Set();
  function computing(kind, on) {
    if (on) running.add(kind);
    else running.delete(kind);
    $("cancel").hidden = Boolean(offline) || running.size === 0;
  }

  function failed(error) {
    if (error.name !== "AbortError" && !state.stopped) status(error.message, !error.cancelled);
  }

  // arrays: nested lists (null for NaN) or base64 of little-endian float64, row-major
  function decode(array) {
    if (array === null || array === undefined) return null;
    if (Array.isArray(array)) return array.map((row) => row.map((x) => (x === null ? NaN : x)));
    const text = atob(array.data);
    const bytes = new Uint8Array(text.length);
    for (let k = 0; k < text.length; k++) bytes[k] = text.charCodeAt(k);
    const flat = new Float64Array(bytes.buffer);
    const [n, m] = array.shape;
    const rows = [];
    for (let i = 0; i < n; i++) rows.push(Array.from(flat.subarray(i * m, (i + 1) * m)));
    return rows;
  }

  // rows[i][j] over (u[i], v[j]) -> plotly's z[j][i], NaN as a gap
  function transpose(rows) {
    if (!rows) return null;
    const z = [];
    for (let j = 0; j < rows[0].length; j++) {
      const row = new Array(rows.length);
      for (let i = 0; i < rows.length; i++) row[i] = Number.isFinite(rows[i][j]) ? rows[i][j] : null;
      z.push(row);
    }
    return z;
  }

  // each cell's tooltip over z (as transpose gives it): the index's value, or what a gap means (gap(i, j) of the
  // cell at (u[i], v[j])), never a number where there is none
  function cellText(z, name, gap) {
    return z.map((row, j) => row.map((x, i) => (x === null ? gap(i, j) : `${name} ${fmt(x)}`)));
  }

  function plotTitle(text) {
    return { text, font: { size: 14 }, y: 1, yref: "paper", yanchor: "bottom", pad: { b: 12 } };
  }

  // the plots' legends in the page, so that a plot's area does not move when a legend entry comes or goes
  const SYMBOLS = { star: "\u2605", diamond: "\u25c6", "square-open": "\u25a1", "x-thin": "\u00d7",
    "circle-open": "\u25cb", "cross-thin": "+" };

  function legend(traces) {
    return traces.filter((t) => t.type !== "heatmap" && t.name && t.showlegend !== false).map((t) => {
      const marker = t.mode === "markers";
      const symbol = marker ? SYMBOLS[t.marker.symbol] || "\u25cf" : t.line.dash ? "\u254c\u254c" : "\u2501\u2501";
      const color = marker ? t.marker.color || t.marker.line.color : t.line.color;
      const shown = ["white", "#ffffff"].includes(color) ? "#777777" : color;
      return `<span class="key"><span style="color:${shown}">${symbol}</span> ${escape(t.name)}</span>`;
    }).join(" ");
  }

  // curves [[[u, v], ...], ...] as one line trace, the curves apart
  function polyline(curves) {
    const x = [];
    const y = [];
    for (const curve of curves) {
      for (const [a, b] of curve) { x.push(a); y.push(b); }
      x.push(null);
      y.push(null);
    }
    return { type: "scatter", mode: "lines", x, y, hoverinfo: "skip", showlegend: true };
  }

  // a linkage as curves: each leg from its base joint, then the platform's joints joined
  function outline(legs) {
    const ends = legs.map((leg) => leg[leg.length - 1]);
    return [...legs, [...ends, ends[0]]];
  }

  function nearest(values, x) {
    let best = 0;
    values.forEach((value, k) => { if (Math.abs(value - x) < Math.abs(values[best] - x)) best = k; });
    return best;
  }

  function designText(design) {
    return Object.entries(design).map(([k, v]) => `${k}=${v}`).join(",");
  }

  function localIndex() {
    const name = state.atlas ? state.atlas.index : $("index").value;
    const found = state.meta.global_indices.find((i) => i.name === name);
    return found ? found.local : name;
  }

  // fields of the requests

  function heldText() {
    const inputs = Array.from(document.querySelectorAll("#held input"));
    if (!inputs.length) return state.meta.defaults.design || "";
    return inputs.filter((el) => el.value !== "").map((el) => `${el.dataset.param}=${el.value}`).join(",");
  }

  function atlasFields() {
    const d = state.meta.defaults;
    const fields = { index: $("index").value, region: $("region").value, design: heldText() };
    if (d.space) fields.space = d.space;
    else fields.axes = d.axes;
    return fields;
  }

  function designFields() {
    return { design: designText(state.design), mode: state.mode, region: state.atlas.region, index: localIndex() };
  }

  function mapFields() {
    const fields = { ...designFields(), resolution: state.meta.defaults.map_resolution, arrays: "base64" };
    return $("plane").value ? { ...fields, plane: $("plane").value } : fields;
  }

  // static export: the precomputed entry nearest a chart node answers for every design near it
  function entryNear(node) {
    let best = null;
    let distance = Infinity;
    for (const entry of offline.entries) {
      const d = Math.hypot(entry.node[0] - node[0], entry.node[1] - node[1]);
      if (d < distance) { best = entry; distance = d; }
    }
    return best;
  }

  function offlineAnswer(endpoint) {
    const entry = entryNear(state.shown.node);
    return entry.modes[state.mode][endpoint];
  }

  // the atlas

  function atlasTraces() {
    const a = state.atlas;
    const mode = state.mode;
    const z = transpose(decode(a.values[mode]));
    const gap = (i, j) => (a.designs[i][j] ? "infeasible: no value" : "outside the design space");
    const traces = [{
      type: "heatmap", x: a.u, y: a.v, z, text: cellText(z, a.index, gap), colorscale: "Viridis",
      zmin: a.limits ? a.limits.min : undefined, zmax: a.limits ? a.limits.max : undefined,
      colorbar: { title: { text: a.index + unit(a.unit) } }, name: a.index,
      hovertemplate: `${a.chart_axes[0]} %{x:.4g}, ${a.chart_axes[1]} %{y:.4g}<br>%{text}<extra></extra>`,
    }];
    const excluded = { x: [], y: [] };
    a.u.forEach((u, i) => a.v.forEach((v, j) => {
      if (a.inside[i][j] && !a.admissible[i][j]) { excluded.x.push(u); excluded.y.push(v); }
    }));
    if (excluded.x.length) {
      traces.push({ type: "scatter", mode: "markers", ...excluded, name: "not admissible (space requirements)",
        marker: { symbol: "x-thin", size: 6, line: { color: "rgba(80,80,80,0.7)", width: 1 } }, hoverinfo: "skip" });
    }
    if (offline) {
      traces.push({ type: "scatter", mode: "markers", name: "precomputed designs", hoverinfo: "skip",
        x: offline.entries.map((e) => a.u[e.node[0]]), y: offline.entries.map((e) => a.v[e.node[1]]),
        marker: { symbol: "circle-open", size: 9, color: "white", line: { width: 2 } } });
    }
    const best = a.best[mode];
    if (best && best.found) {
      traces.push({ type: "scatter", mode: "markers", x: [best.u], y: [best.v], name: `best converged ${a.index} = ${fmt(best.value)}`,
        marker: { symbol: "star", size: 16, color: "#e4002b", line: { color: "white", width: 1 } }, hoverinfo: "name" });
    }
    const o = state.optimum;
    if (o && o.problem && o.mode === mode && o.on_chart) {
      traces.push({ type: "scatter", mode: "markers", x: [o.u], y: [o.v], meta: "optimum", hoverinfo: "name",
        name: `optimum of ${o.problem} = ${fmt(o.verified_objective)}`,
        marker: { symbol: "diamond", size: 13, color: "#ff7f0e", line: { color: "white", width: 1 } } });
    }
    if (state.clicked && state.clicked.node) {
      const [i, j] = state.clicked.node;
      traces.push({ type: "scatter", mode: "markers", x: [a.u[i]], y: [a.v[j]], name: "clicked", hoverinfo: "skip",
        marker: { symbol: "square-open", size: 14, color: "white", line: { width: 3 } } });
    }
    return traces;
  }

  function atlasLayout() {
    const a = state.atlas;
    const space = a.axes ? a.axes.map((x) => x[0]).join(", ") : `space ${a.space}`;
    return {
      title: plotTitle(`${a.index} over ${a.region} (${space}), mode ${state.mode}`),
      xaxis: { title: { text: a.chart_labels[0] }, zeroline: false },
      yaxis: { title: { text: a.chart_labels[1] }, zeroline: false },
      showlegend: false, margin: MARGIN, hovermode: "closest",
      uirevision: `${a.index}/${a.region}/${space}`,
    };
  }

  async function drawAtlas() {
    const traces = atlasTraces();
    await Plotly.react("atlas", traces, atlasLayout(), PLOT);
    state.drawn.atlas += 1;
    const a = state.atlas;
    const best = a.best[state.mode];
    const lines = [best && best.found
      ? `best converged design: ${a.varied.map((p) => `${p} = ${fmt(best.design[p])}`).join(", ")} (${best.reason})`
      : `no best design: ${best ? best.reason : "not checked"}`];
    const o = state.optimum;
    if (o && o.problem) {
      const where = o.on_chart ? "" : " (off this chart)";
      const apart = Object.entries(a.held).filter(([k, v]) => Math.abs(o.design[k] - v) > 1e-9 * Math.max(1, Math.abs(v)))
        .map(([k]) => `${k} = ${fmt(o.design[k])}`);
      const off = apart.length ? `, at ${apart.join(", ")} where the atlas holds other values` : "";
      lines.push(`optimum of ${o.problem}, mode ${o.mode}${where}${off}: ${o.status}, verified ${fmt(o.verified_objective)}`);
    } else if (o && o.reason) {
      lines.push(o.reason);
    }
    if (offline) lines.push(`static export: a click shows the nearest of ${offline.entries.length} precomputed designs`);
    $("atlas-note").innerHTML = `${legend(traces)}<br>${escape(lines.join(" · "))}`;
  }

  function bindAtlas() {
    const gd = $("atlas");
    gd.on("plotly_hover", (event) => {
      const target = targetOf(event);
      if (!target) return;
      clearTimeout(hoverTimer);
      clearTimeout(returnTimer);
      hoverTimer = setTimeout(() => select(target, false), HOVER_DELAY);
    });
    gd.on("plotly_unhover", () => {
      clearTimeout(hoverTimer);
      clearTimeout(returnTimer);
      returnTimer = setTimeout(() => { if (state.clicked && state.shown !== state.clicked) select(state.clicked, false); },
        RETURN_DELAY);
    });
    gd.on("plotly_click", (event) => {
      const t0 = event.event && event.event.timeStamp ? event.event.timeStamp : performance.now();
      const target = targetOf(event);
      clearTimeout(hoverTimer);
      clearTimeout(returnTimer);
      if (target) select(target, true, t0);
    });
  }

  // the design a hover or click on the atlas means: the optimum's on its marker, else the node of the cell under
  // the cursor (the best design's star and the other markers cover parts of their neighbours' cells)
  function targetOf(event) {
    const a = state.atlas;
    const point = event.points[0];
    if (point.data.meta === "optimum" && !offline) return { design: state.optimum.design, label: "optimum" };
    let [x, y] = [point.x, point.y];
    const mouse = event.event;
    if (mouse && mouse.clientX !== undefined) {
      const gd = $("atlas");
      const layout = gd._fullLayout;
      const box = gd.getBoundingClientRect();
      x = layout.xaxis.p2l(mouse.clientX - box.left - layout._size.l);
      y = layout.yaxis.p2l(mouse.clientY - box.top - layout._size.t);
    }
    const node = [nearest(a.u, x), nearest(a.v, y)];
    if (!a.designs[node[0]][node[1]]) return null;
    if (offline) return { node: entryNear(node).node };
    return { node };
  }

  async function loadAtlas() {
    const seq = ++state.seq.atlas;
    status("computing the atlas ...");
    computing("atlas", true);
    let atlas;
    try {
      atlas = offline ? offline.atlas : await api("atlas", atlasFields(), "atlas");
    } catch (error) {
      failed(error);
      return;
    } finally {
      if (seq === state.seq.atlas) computing("atlas", false);
    }
    if (seq !== state.seq.atlas) return;
    state.atlas = atlas;
    state.optimum = offline ? offline.optimum : null;
    const modes = $("mode");
    const previous = state.mode;
    modes.innerHTML = atlas.modes.map((m) => `<option value="${escape(m)}">${escape(m)}</option>`).join("");
    state.mode = atlas.modes.includes(previous) ? previous : atlas.modes[0];
    modes.value = state.mode;
    buildHeld();
    await drawAtlas();
    status(`atlas: ${atlas.u.length} x ${atlas.v.length} designs, ${atlas.modes.length} modes, ${fmt(atlas.wall_time)} s`);
    const target = state.clicked || initialTarget();
    if (target) await select(target, true);
    if (!offline && atlas.problem) loadOptimum(seq);
  }

  async function loadOptimum(seq) {
    const fields = atlasFields();
    try {
      const optimum = await api("optimum", fields, "optimum");
      if (seq !== state.seq.atlas) return;
      state.optimum = optimum;
      await drawAtlas();
    } catch (error) {
      failed(error);
    }
  }

  function initialTarget() {
    const a = state.atlas;
    const best = a.best[state.mode];
    if (best && best.found) {
      const node = [nearest(a.u, best.u), nearest(a.v, best.v)];
      return offline ? { node: entryNear(node).node } : { node };
    }
    if (offline && offline.entries.length) return { node: offline.entries[0].node };
    const values = decode(a.values[state.mode]);
    for (let i = 0; i < a.u.length; i++) for (let j = 0; j < a.v.length; j++) {
      if (a.designs[i][j] && Number.isFinite(values[i][j])) return { node: [i, j] };
    }
    return null;
  }

  function buildHeld() {
    const a = state.atlas;
    const box = $("held");
    if (box.children.length) return;
    const chart = new Set(a.varied);
    box.innerHTML = state.meta.parameters.filter((p) => !chart.has(p.name)).map((p) => {
      const value = p.name in a.held ? String(a.held[p.name]) : "";
      return `<label title="${escape(p.doc)}">${escape(p.name)}
        <input type="number" step="any" data-param="${escape(p.name)}" value="${value}"
        placeholder="follows the chart"${offline ? " disabled" : ""}> ${escape(p.unit)}</label>`;
    }).join("");
    for (const input of box.querySelectorAll("input")) input.addEventListener("change", () => loadAtlas());
  }

  // the design on the right

  async function select(target, locked, t0) {
    const a = state.atlas;
    const design = target.design ? target.design : { ...a.held, ...a.designs[target.node[0]][target.node[1]] };
    if (locked) state.clicked = target;
    state.shown = target;
    state.design = design;
    await loadMap(t0);
    await loadCard();
    if (locked) await drawAtlas();
  }

  // the map first, then the card: the server computes one request at a time, and the page draws one thing at a
  // time
  async function loadMap(t0) {
    const seq = ++state.seq.map;
    let answer;
    try {
      answer = offline ? offlineAnswer("map") : await api("map", mapFields(), "map");
    } catch (error) {
      failed(error);
      return;
    }
    if (seq !== state.seq.map) return;
    const values = decode(answer.values);
    const z = transpose(values);
    state.map = { ...answer, values, z, text: cellText(z, answer.index, () => "out of reach") };
    state.linkage = offline ? offlineAnswer("linkage") : null;
    state.pose = null;
    state.followed = false;
    await drawMap();
    await new Promise((resolve) => requestAnimationFrame(() => resolve()));
    if (t0 !== undefined) state.timings.push(performance.now() - t0);
    state.drawn.map += 1;
  }

  function middlePose() {
    const m = state.map;
    const pose = state.card && state.card.pose;
    if (pose) return m.pose_names.map((n) => pose[n]);
    return m.pose_names.map((n) => (n === m.axes[0] ? m.u[m.u.length >> 1] : n === m.axes[1] ? m.v[m.v.length >> 1] : m.held[n]));
  }

  function mapTraces() {
    const m = state.map;
    const traces = [{
      type: "heatmap", x: m.u, y: m.v, z: m.z, text: m.text, colorscale: "Viridis", name: m.index,
      zmin: m.limits ? m.limits.min : undefined, zmax: m.limits ? m.limits.max : undefined,
      colorbar: { title: { text: m.index + unit(m.unit) } },
      hovertemplate: `${m.axes[0]} %{x:.4g}, ${m.axes[1]} %{y:.4g}<br>%{text}<extra></extra>`,
    }];
    const styles = { det_type1: ["#000000", "type I singularity"], det_type2: ["#d62728", "type II singularity"] };
    for (const [key, curves] of Object.entries(m.curves)) {
      const [color, name] = styles[key] || ["#ff7f0e", key];
      if (curves.length) traces.push({ ...polyline(curves), name, line: { color, width: 2 } });
    }
    if (m.region_outline && m.region_outline.length) {
      traces.push({ ...polyline(m.region_outline), name: `region ${m.region}`,
        line: { color: "#ffffff", width: 2, dash: "dash" } });
    }
    if (!(m.region_outline && m.region_outline.length) && m.region_points && m.region_points.length) {
      traces.push({ type: "scatter", mode: "markers", name: `region ${m.region} nodes`, hoverinfo: "skip",
        x: m.region_points.map((p) => p[0]), y: m.region_points.map((p) => p[1]),
        marker: { color: "white", size: 4, line: { color: "black", width: 0.5 } } });
    }
    traces.push(...certifiedTraces());
    const link = state.linkage;
    const every = link && link.mode === m.mode && link.assemblies;
    if (every && every.projected) {
      // the other assemblies at the same actuated joints, faint behind the one at the pose
      const others = every.projected.filter((legs, k) => k !== every.current && legs.length);
      const lines = others.flatMap((legs) => outline(legs));
      if (lines.length) {
        traces.push({ ...polyline(lines), name: "other assemblies at these joints", legendgroup: "assemblies",
          line: { color: "#111", width: 1.5, dash: "dot" }, opacity: 0.45 });
      }
    }
    if (link && link.projected && link.projected.length && link.mode === m.mode) {
      link.projected.forEach((leg, k) => traces.push({ type: "scatter", mode: "lines+markers", hoverinfo: "skip",
        x: leg.map((p) => p[0]), y: leg.map((p) => p[1]), name: "linkage", showlegend: k === 0, legendgroup: "linkage",
        line: { color: "#111", width: 3 }, marker: { color: "white", size: 7, line: { color: "#111", width: 1.5 } } }));
      const ends = link.projected.map((leg) => leg[leg.length - 1]);
      ends.push(ends[0]);
      traces.push({ type: "scatter", mode: "lines", x: ends.map((p) => p[0]), y: ends.map((p) => p[1]), hoverinfo: "skip",
        showlegend: false, legendgroup: "linkage", line: { color: "#111", width: 1.5 } });
    }
    if (state.pose) {
      const at = m.axes.map((n) => state.pose[m.pose_names.indexOf(n)]);
      traces.push({ type: "scatter", mode: "markers", x: [at[0]], y: [at[1]], name: "pose", hoverinfo: "skip",
        showlegend: false, marker: { symbol: "cross-thin", size: 12, line: { color: "#e4002b", width: 2 } } });
    }
    return traces;
  }

  // the certification of the map's design, mode and region, where the map's plane is the pose's first two
  // coordinates: its boxes outlined (proved green, undecided orange) and its witnesses
  function shownCertificate() {
    const c = state.certified;
    const m = state.map;
    return c && m && c.key === certifyKey() && m.axes.join(",") === c.answer.plane.join(",") ? c.answer : null;
  }

  function certifiedTraces() {
    const c = shownCertificate();
    if (!c) return [];
    const traces = [];
    const colours = { proved: ["#2ca02c", "rgba(44, 160, 44, 0.3)"], undecided: ["#ff7f0e", "rgba(255, 127, 14, 0.5)"] };
    for (const [cell, [colour, fill]] of Object.entries(colours)) {
      const boxes = c.cells[cell].map((corners) => [...corners, corners[0]]);
      if (boxes.length) {
        traces.push({ ...polyline(boxes), name: `${cell} (${boxes.length} boxes)`, fill: "toself", fillcolor: fill,
          line: { color: colour, width: 0.5 } });
      }
    }
    if (c.points.length) {
      traces.push({ type: "scatter", mode: "markers", name: "witness (refuted)", hoverinfo: "skip",
        x: c.points.map((p) => p[0]), y: c.points.map((p) => p[1]),
        marker: { symbol: "x", size: 11, color: "#d62728" } });
    }
    return traces;
  }

  function certifyKey() {
    return state.design && state.atlas ? `${designText(state.design)}|${state.mode}|${state.atlas.region}` : null;
  }

  async function certify() {
    const key = certifyKey();
    if (!key) return;
    status(`certifying region ${state.atlas.region} ...`);
    $("certify").disabled = true;
    computing("certify", true);
    let answer;
    try {
      answer = await api("certify", { design: designText(state.design), mode: state.mode, region: state.atlas.region },
        "certify");
    } catch (error) {
      failed(error);
      return;
    } finally {
      $("certify").disabled = false;
      computing("certify", false);
    }
    state.certified = { key, answer };
    const volume = answer.undecided > 0 ? `, undecided volume ${fmt(answer.undecided)} of the reference box` : "";
    const stopped = answer.stopped ? ` (stopped at ${answer.stopped})` : "";
    status(`region ${answer.region} in mode ${answer.mode}: ${answer.verdict} (${answer.boxes} boxes, depth
      ${answer.depth}${volume}, ${fmt(answer.seconds)} s${stopped})`.replace(/\s+/g, " "));
    if (state.map) await drawMap();
    state.drawn.certified += 1;
  }

  async function drawMap() {
    const m = state.map;
    const sameUnits = m.axis_units[0] === m.axis_units[1];
    const held = Object.entries(m.held).map(([k, v]) => `${k} = ${fmt(v)}`).join(", ");
    const layout = {
      title: plotTitle(`${state.meta.name}, mode ${m.mode}${held ? `; ${held}` : ""}`),
      xaxis: { title: { text: m.axes[0] + unit(m.axis_units[0]) }, zeroline: false },
      yaxis: { title: { text: m.axes[1] + unit(m.axis_units[1]) }, zeroline: false, ...(sameUnits ? { scaleanchor: "x" } : {}) },
      showlegend: false, margin: MARGIN, hovermode: "closest",
      uirevision: `${m.axes.join(",")}`,
    };
    const traces = mapTraces();
    await Plotly.react("map", traces, layout, PLOT);
    const link = state.linkage;
    const notes = [`${m.index}${unit(m.unit)} over ${m.u.length} x ${m.v.length} poses`];
    if (link && link.reason) notes.push(link.reason);
    if (link && link.reachable) notes.push(`pose ${Object.values(link.pose).map(fmt).join(", ")}`);
    if (link && link.assemblies && link.assemblies.count !== null) {
      const every = link.assemblies;
      const failed = every.failed ? ` (${every.failed} ${every.failures})` : "";
      notes.push(`${every.count} real assemblies at these joints${failed}`);
    }
    const c = shownCertificate();
    if (c) {
      notes.push(`certified: ${c.verdict}, ${c.cells.proved.length} boxes proved, ${c.cells.undecided.length} undecided, `
        + `${c.points.length} witnesses`);
    } else if (state.certified && state.certified.key === certifyKey()) {
      notes.push(`the certification's boxes are drawn in the plane ${state.certified.answer.plane.join(", ")}`);
    }
    if (link && link.singular && link.singular.length) {
      notes.push(`SINGULAR (${link.singular.join(" and ")}): the indices there are their limits`);
    }
    $("map-note").innerHTML = `${legend(traces)}<br>${escape(notes.join(" · "))}`;
  }

  function bindMap() {
    if (offline) return;
    $("map").on("plotly_hover", (event) => {
      const point = event.points[0];
      const m = state.map;
      state.followed = true;
      followPose(m.pose_names.map((n) => (n === m.axes[0] ? point.x : n === m.axes[1] ? point.y : m.held[n])));
    });
  }

  // the linkage follows the cursor over the map: one request in flight, the latest pose next
  async function followPose(pose) {
    if (linkageBusy) {
      linkagePending = pose;
      return;
    }
    linkageBusy = true;
    try {
      const m = state.map;
      const answer = await api("linkage", { design: designText(state.design), mode: m.mode, pose: pose.join(","),
        plane: m.axes.join(",") });
      if (state.map === m) {
        state.linkage = answer;
        state.pose = pose;
        await drawMap();
      }
    } catch (error) {
      failed(error);
    } finally {
      linkageBusy = false;
    }
    if (linkagePending) {
      const next = linkagePending;
      linkagePending = null;
      followPose(next);
    }
  }

  async function loadCard() {
    const seq = ++state.seq.card;
    let card;
    try {
      card = offline ? offlineAnswer("card") : await api("card", designFields(), "card");
    } catch (error) {
      failed(error);
      return;
    }
    if (seq !== state.seq.card) return;
    state.card = card;
    drawCard();
    state.drawn.card += 1;
    if (!offline && state.map && !state.followed) followPose(middlePose());
  }

  function drawCard() {
    const c = state.card;
    const varied = new Set(state.atlas.varied);
    const rows = c.design.map((p) => `<tr class="${varied.has(p.name) ? "varied" : ""}"><td>${escape(p.name)}</td>
      <td class="number" data-param="${escape(p.name)}" data-value="${p.value}">${fmt(p.value)}</td>
      <td>${escape(p.unit)}</td><td class="doc">${escape(p.doc)}</td></tr>`).join("");
    const placed = c.placement
      ? `<p>region ${escape(c.region)}: ${escape(c.placement.shape)} at (${c.placement.centre.map(fmt).join(", ")}), size
         (${c.placement.size.map(fmt).join(", ")})</p>` : "";
    const indices = c.global_indices.map((r) => `<tr><td>${escape(r.index)}</td>
      <td class="number" data-index="${escape(r.index)}" data-value="${r.value}">${fmt(r.value)}</td>
      <td>${escape(r.unit)}</td><td class="number">${r.resolution}</td><td class="number">${r.points}</td>
      <td class="number">${r.accuracy === null ? "NaN" : r.accuracy.toExponential(1)}</td></tr>`).join("");
    const label = state.shown && state.shown.label ? ` (${escape(state.shown.label)})` : "";
    $("card").innerHTML = `<h2>design${label}, mode ${escape(c.mode)}</h2>
      <table id="card-design"><thead><tr><th>parameter</th><th>value</th><th>unit</th><th>meaning</th></tr></thead>
      <tbody>${rows}</tbody></table>${placed}
      <h2>global indices over ${escape(c.region)}</h2>
      <table id="card-indices"><thead><tr><th>index</th><th>value</th><th>unit</th><th>resolution</th><th>points</th>
      <th>accuracy</th></tr></thead><tbody>${indices || "<tr><td colspan=6>none in this mode</td></tr>"}</tbody></table>`;
  }

  // controls

  function options(select, names, chosen) {
    select.innerHTML = names.map((n) => `<option value="${escape(n)}">${escape(n)}</option>`).join("");
    select.value = chosen;
  }

  // the server cancels the computation in flight (the atlas's) and serves the next request
  async function cancel() {
    $("cancel").hidden = true;
    try {
      const response = await fetch("/api/cancel", { method: "POST", headers: { "Content-Type": "application/json" },
        body: "{}" });
      if (!response.ok) throw new Error((await response.json()).error);
    } catch (error) {
      status(`the computation was not cancelled: ${error.message}`, true);
    }
  }

  // the server cancels its computation in flight; the page aborts its requests in flight and makes none after
  async function stop() {
    state.stopped = true;
    for (const controller of Object.values(controllers)) controller.abort();
    try {
      const response = await fetch("/api/stop", { method: "POST", headers: { "Content-Type": "application/json" },
        body: "{}" });
      if (!response.ok && response.status !== 503) throw new Error((await response.json()).error);
    } catch (error) {
      state.stopped = false;
      status(`the server did not stop: ${error.message}`, true);
      return;
    }
    clearTimeout(hoverTimer);
    clearTimeout(returnTimer);
    for (const el of document.querySelectorAll("header select, header button, #held input")) el.disabled = true;
    status("the server has stopped; close this page");
  }

  async function start() {
    try {
      state.meta = offline ? offline.mechanism : await api("mechanism", {});
    } catch (error) {
      failed(error);
      return;
    }
    const meta = state.meta;
    const atlas = offline ? offline.atlas : null;
    document.title = `pkm explore: ${meta.name}`;
    $("title").textContent = `pkm explore: ${meta.name}`;
    options($("index"), meta.global_indices.map((i) => i.name), atlas ? atlas.index : meta.defaults.index);
    options($("region"), meta.regions.map((r) => r.name), atlas ? atlas.region : meta.defaults.region);
    const names = meta.pose.map((p) => p.name);
    options($("plane"), names.flatMap((a, k) => names.slice(k + 1).map((b) => `${a},${b}`)), names.slice(0, 2).join(","));
    if (offline) {
      $("index").disabled = true;
      $("region").disabled = true;
      $("plane").disabled = true;
      $("stop").hidden = true;
      $("certify").hidden = true;
    }
    $("index").addEventListener("change", () => loadAtlas());
    $("region").addEventListener("change", () => loadAtlas());
    $("mode").addEventListener("change", async () => {
      state.mode = $("mode").value;
      await drawAtlas();
      if (state.clicked) await select(state.clicked, true);
    });
    $("plane").addEventListener("change", () => { if (state.shown) select(state.shown, false); });
    $("stop").addEventListener("click", stop);
    $("cancel").addEventListener("click", cancel);
    $("certify").addEventListener("click", certify);
    await Plotly.newPlot("atlas", [], {}, PLOT);
    await Plotly.newPlot("map", [], {}, PLOT);
    bindAtlas();
    bindMap();
    await loadAtlas();
  }

  start();
})();
