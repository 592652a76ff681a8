// jointplay explore: the page. Its state is the URL query; every change asks the server for
// the view of the new settings (GET /api/view), aborting the request before it. A reply
// that is not the newest is dropped; a bad value shows the server's message and keeps the
// last good view.
"use strict";

const SVG = "http://www.w3.org/2000/svg";
const PROGRESS_AFTER_MS = 300;
const PERIOD_MS = 3000; // one animated revolution
const UNITS = { omega: "rad/s", alpha: "rad/s²", F: "N", torque: "N·m", slider_v: "m/s", slider_a: "m/s²" };
const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

let spec = null;
let state = {};
let sequence = 0;
let controller = null;
let animation = null;
let views = 0;
let notice = ""; // said with the first view

function $(id) { return document.getElementById(id); }

function unitOf(key) {
  for (const [prefix, unit] of Object.entries(UNITS)) { if (key.startsWith(prefix)) return unit; }
  return "";
}

function query() {
  const params = new URLSearchParams();
  for (const [key, value] of Object.entries(state)) { if (value !== "") params.set(key, value); }
  return params.toString();
}

function showMessage(text) {
  const box = $("message");
  box.textContent = text || "";
  box.hidden = !text;
}

function setStatus(kind, text) {
  document.body.dataset.state = kind;
  $("status").textContent = text;
}

// --- controls -----------------------------------------------------------------------------

function option(select, value, text) {
  const item = document.createElement("option");
  item.value = value;
  item.textContent = text || value;
  select.appendChild(item);
}

function pair(label, id, key, min, max, step) {
  const wrap = document.createElement("label");
  wrap.textContent = label;
  const row = document.createElement("span");
  row.className = "pair";
  row.innerHTML = `<input type="range" id="${id}-range" min="${min}" max="${max}" step="${step}" data-for="${key}">` +
    `<input type="text" id="${id}" data-key="${key}" inputmode="decimal">`;
  wrap.appendChild(row);
  return wrap;
}

function buildControls() {
  $("name").textContent = `${spec.name} (${spec.source})`;
  for (const name of spec.contacts) {
    option($("contact"), name, name === "physical" ? "physical default (docs/contact.md)" : name);
  }
  for (const name of spec.starts) option($("start"), name);
  $("settle").max = spec.max_settle;
  const joints = $("joints");
  for (const joint of spec.joints) {
    const box = document.createElement("div");
    box.className = "joint";
    box.dataset.joint = joint.name;
    const mode = document.createElement("select");
    mode.id = `mode-${joint.name}`;
    option(mode, "um", "µm");
    for (const pick of ["min", "mean", "max"]) option(mode, pick, `ISO 286 fit, ${pick}`);
    option(mode, "off", "ideal joint");
    const fit = document.createElement("input");
    fit.type = "text";
    fit.id = `fit-${joint.name}`;
    fit.size = 7;
    fit.value = joint.fit || "H8/g7";
    fit.title = "ISO 286 fit at the joint's diameter, e.g. H7/g6";
    const title = document.createElement("label");
    title.textContent = `${joint.name} (Ø${joint.diameter_mm} mm${joint.fit ? ", fit " + joint.fit + ": " + joint.fit_range_um.map((v) => v.toFixed(1)).join("–") + " µm" : ""}) `;
    title.append(mode, " ", fit);
    box.appendChild(title);
    box.appendChild(pair("clearance (µm)", `clr-${joint.name}`, `c.${joint.name}`, 1, joint.slider_max_um, 0.5));
    // the joint's own contact and friction; blank: the common ones above
    const own = document.createElement("label");
    own.className = "own";
    own.textContent = "contact ";
    const law = document.createElement("select");
    law.id = `contact-${joint.name}`;
    law.dataset.key = `contact.${joint.name}`;
    option(law, "", "as above");
    for (const name of spec.contacts) option(law, name);
    const mu = document.createElement("input");
    mu.type = "text";
    mu.id = `mu-${joint.name}`;
    mu.dataset.key = `mu.${joint.name}`;
    mu.placeholder = "as above";
    mu.size = 6;
    own.append(law, " friction ", mu);
    box.appendChild(own);
    joints.appendChild(box);
    const choose = () => {
      const number = $(`clr-${joint.name}`);
      if (mode.value === "um") {
        const range = $(`clr-${joint.name}-range`);
        state[`c.${joint.name}`] = number.value && !number.value.includes(":") && number.value !== "off" ? number.value : range.value;
      } else if (mode.value === "off") {
        state[`c.${joint.name}`] = "off";
      } else {
        state[`c.${joint.name}`] = `${fit.value.trim()}:${mode.value}`;
      }
      changed();
    };
    mode.addEventListener("change", choose);
    fit.addEventListener("change", () => { if (!["um", "off"].includes(mode.value)) choose(); });
  }
  const lengths = $("lengths");
  for (const length of spec.lengths) {
    const item = pair(`${length.name} (${length.tolerance}: ${length.min_mm.toFixed(2)}–${length.max_mm.toFixed(2)})`,
      `len-${length.name}`, `L.${length.name}`, length.min_mm, length.max_mm, 0.01);
    lengths.appendChild(item);
  }
  $("rpm-range").min = Math.max(spec.rpm_range[0], 10);
  for (const input of document.querySelectorAll("[data-key]")) {
    input.addEventListener(input.tagName === "SELECT" ? "change" : "input", () => {
      state[input.dataset.key] = input.value.trim();
      const range = document.querySelector(`[data-for="${input.dataset.key}"]`);
      if (range && input.value.trim() !== "" && isFinite(Number(input.value))) range.value = input.value;
      changed();
    });
  }
  for (const range of document.querySelectorAll("[data-for]")) {
    range.addEventListener("input", () => {
      state[range.dataset.for] = range.value;
      const text = document.querySelector(`[data-key="${range.dataset.for}"]`);
      if (text) text.value = range.value;
      changed();
    });
  }
}

function showState() {
  for (const input of document.querySelectorAll("[data-key]")) {
    const value = state[input.dataset.key] ?? "";
    input.value = value;
    const range = document.querySelector(`[data-for="${input.dataset.key}"]`);
    if (range && value !== "" && isFinite(Number(value))) range.value = value;
  }
  for (const joint of spec.joints) {
    const value = state[`c.${joint.name}`] ?? "";
    const mode = $(`mode-${joint.name}`);
    const number = $(`clr-${joint.name}`);
    const range = $(`clr-${joint.name}-range`);
    let kind = "um";
    if (value === "off") kind = "off";
    else if (value.includes(":")) {
      kind = value.slice(value.lastIndexOf(":") + 1);
      $(`fit-${joint.name}`).value = value.slice(0, value.lastIndexOf(":"));
    }
    if (![...mode.options].some((o) => o.value === kind)) kind = "um";
    mode.value = kind;
    const own = kind === "um";
    number.disabled = !own;
    range.disabled = !own;
    $(`fit-${joint.name}`).disabled = own || kind === "off";
    if (!own) number.value = value;
  }
}

function changed() {
  history.replaceState(null, "", "?" + query());
  showState();
  update();
}

// --- the view -----------------------------------------------------------------------------

async function update() {
  sequence += 1;
  const mine = sequence;
  pauseAnimation(); // the browser's drawing would compete with the simulation for the CPU
  if (controller) controller.abort();
  controller = new AbortController();
  $("download").href = "/api/download?" + query();
  const started = performance.now();
  // past PROGRESS_AFTER_MS: "computing…" with the seconds so far, until the answer
  let ticker = null;
  const timer = setTimeout(() => {
    const tick = () => setStatus("busy", `computing… ${((performance.now() - started) / 1000).toFixed(1)} s`);
    tick();
    ticker = setInterval(tick, 100);
  }, PROGRESS_AFTER_MS);
  const stopTimer = () => { clearTimeout(timer); clearInterval(ticker); };
  let reply;
  let body;
  try {
    reply = await fetch("/api/view?" + query(), { signal: controller.signal });
    body = await reply.json();
  } catch (error) {
    stopTimer(); // aborted by a newer change, or no answer
    if (mine === sequence) { resumeAnimation(); setStatus("error", "the server did not answer"); showMessage(String(error)); }
    return;
  }
  stopTimer();
  if (mine !== sequence) return; // a newer change is on its way: drop this one
  if (reply.status === 409) { update(); return; } // superseded by another tab's change: again
  if (!reply.ok) {
    resumeAnimation();
    const error = body.error || `error ${reply.status}`;
    if (views === 0 && reply.status === 400) { showDefaults(mine, error); return; }
    setStatus("error", "last good view kept");
    showMessage(error);
    return;
  }
  showMessage(notice);
  notice = "";
  delete document.body.dataset.shown;
  const received = performance.now();
  render(body);
  views += 1;
  const done = performance.now();
  const seconds = (done - started) / 1000;
  // what the update took: in all, on the server (simulation and view), and drawing here
  Object.assign(document.body.dataset, {
    lastUpdateS: seconds.toFixed(3),
    lastServerS: body.server_s.toFixed(3),
    lastDrawS: ((done - received) / 1000).toFixed(3),
    views: String(views),
  });
  setStatus("ready", `updated in ${seconds.toFixed(2)} s (server ${body.server_s.toFixed(2)} s, of which integration ${body.solver.wall_s.toFixed(2)} s, ${body.solver.steps} steps)`);
}

// A bad first query (a shared link with a value this server refuses): the view of the
// defaults, under the server's message, rather than an empty page; the controls keep the
// link's values, so that the bad one can be corrected.
async function showDefaults(mine, error) {
  setStatus("error", "the link was refused: the defaults are shown");
  showMessage(`${error} (the view shows the defaults until this is corrected)`);
  const params = new URLSearchParams();
  for (const [key, value] of Object.entries(spec.defaults)) params.set(key, value);
  let reply;
  let body;
  try {
    reply = await fetch("/api/view?" + params.toString(), { signal: controller.signal });
    body = await reply.json();
  } catch (failure) {
    return; // aborted by a newer change, or no answer: the message stays
  }
  if (mine !== sequence || !reply.ok) return;
  render(body);
  views += 1;
  document.body.dataset.views = String(views);
  document.body.dataset.shown = "defaults";
}

function render(view) {
  drawMechanism(view.mechanism);
  drawOrbits(view.orbits);
  drawCurves(view.curves);
  drawPeaks(view);
  drawDiagnostics(view);
}

function svgElement(name, attributes) {
  const item = document.createElementNS(SVG, name);
  for (const [key, value] of Object.entries(attributes)) item.setAttribute(key, value);
  return item;
}

let animate = null; // draws the current frame and asks for the next one

function pauseAnimation() {
  if (animation) cancelAnimationFrame(animation);
  animation = null;
}

function resumeAnimation() {
  if (animate && !animation) animation = requestAnimationFrame(animate);
}

function drawMechanism(mechanism) {
  const svg = $("mechanism");
  svg.replaceChildren();
  pauseAnimation();
  const xs = [];
  const ys = [];
  for (const link of mechanism.links) for (const [x, y] of link) { xs.push(...x); ys.push(...y); }
  for (const [x, y] of mechanism.ground) { xs.push(x); ys.push(y); }
  const margin = 0.08 * (Math.max(...xs) - Math.min(...xs) + 1);
  const left = Math.min(...xs) - margin;
  const top = -Math.max(...ys) - margin;
  const width = Math.max(...xs) - Math.min(...xs) + 2 * margin;
  const height = Math.max(...ys) - Math.min(...ys) + 2 * margin;
  svg.setAttribute("viewBox", `${left} ${top} ${width} ${height}`);
  const stroke = width / 250;
  const root = svgElement("g", { transform: "scale(1,-1)" });
  svg.appendChild(root);
  for (const [x, y] of mechanism.ground) {
    root.appendChild(svgElement("path", { d: `M${x - 4 * stroke},${y - 5 * stroke} L${x},${y} L${x + 4 * stroke},${y - 5 * stroke} Z`, fill: "#999" }));
  }
  const lines = mechanism.links.map((link, k) => {
    const line = svgElement("polygon", { fill: "none", stroke: COLOURS[k % COLOURS.length], "stroke-width": 2 * stroke, "stroke-linejoin": "round" });
    root.appendChild(line);
    return line;
  });
  const M = mechanism.magnification;
  const bearings = mechanism.bearings.map((bearing) => {
    const r = (bearing.clearance_um * 1e-3) * M;
    const circle = svgElement("circle", { r, fill: "white", stroke: "#444", "stroke-width": stroke / 2, "stroke-dasharray": `${stroke} ${stroke}` });
    const trace = svgElement("polyline", { fill: "none", stroke: "#bbb", "stroke-width": stroke / 3 });
    const pin = svgElement("circle", { r: 1.2 * stroke, fill: "#111" });
    root.append(circle, trace, pin);
    return { bearing, circle, trace, pin, M };
  });
  $("mechanism-caption").textContent =
    `The links at their true positions over revolution ${mechanism.revolution ?? "(part)"}; ` +
    `clearance circles and pin offsets magnified ×${M} (pin centre = bearing centre + ${M} × eccentricity).`;
  const frames = mechanism.frames;
  const t0 = performance.now();
  let shown = -1;
  function frame(now) {
    const i = Math.floor(((now - t0) % PERIOD_MS) / PERIOD_MS * frames) % frames;
    animation = requestAnimationFrame(frame);
    if (i === shown) return; // 30 frames a second at most: no work between frames
    shown = i;
    mechanism.links.forEach((link, k) => {
      lines[k].setAttribute("points", link.map(([x, y]) => `${x[i]},${y[i]}`).join(" "));
    });
    for (const { bearing, circle, trace, pin, M } of bearings) {
      const cx = bearing.centre_mm[0][i];
      const cy = bearing.centre_mm[1][i];
      circle.setAttribute("cx", cx);
      circle.setAttribute("cy", cy);
      pin.setAttribute("cx", cx + M * bearing.eccentricity_um[0][i] * 1e-3);
      pin.setAttribute("cy", cy + M * bearing.eccentricity_um[1][i] * 1e-3);
      trace.setAttribute("points", bearing.eccentricity_um[0].map((ex, j) =>
        `${cx + M * ex * 1e-3},${cy + M * bearing.eccentricity_um[1][j] * 1e-3}`).join(" "));
    }
    svg.dataset.frame = String(i);
  }
  animate = frame;
  resumeAnimation();
}

const CONFIG = { displaylogo: false, responsive: true };
// The top margin of the figures, px: Plotly's toolbar (the modebar, about 30 px high, at the
// top right) above the titles of the first row, not over them.
const TOP = 62;

// One figure of every joint's orbit (a subplot each, equal axes) and one of the curves:
// Plotly's cost is mostly per figure, and the page must redraw within ~0.1 s.
function drawOrbits(orbits) {
  const joints = Object.keys(orbits);
  const columns = Math.min(joints.length, 4);
  const rows = Math.ceil(joints.length / columns);
  const traces = [];
  const layout = { showlegend: false, margin: { l: 40, r: 10, t: TOP, b: 35 }, annotations: [], height: 270 * rows + TOP - 25 };
  const angles = Array.from({ length: 121 }, (_, k) => (2 * Math.PI * k) / 120);
  joints.forEach((joint, k) => {
    const orbit = orbits[joint];
    const c = orbit.clearance_um;
    const n = k === 0 ? "" : String(k + 1);
    const column = k % columns;
    const row = Math.floor(k / columns);
    const gap = 0.06;
    const x0 = column / columns + (column ? gap / 2 : 0);
    const x1 = (column + 1) / columns - (column < columns - 1 ? gap / 2 : 0);
    const y1 = 1 - row / rows - (row ? 0.06 : 0);
    const y0 = 1 - (row + 1) / rows + (row < rows - 1 ? 0.06 : 0);
    const reach = Math.max(c, ...orbit.x_um.map(Math.abs), ...orbit.y_um.map(Math.abs)) * 1.1;
    traces.push(
      { x: angles.map((a) => c * Math.cos(a)), y: angles.map((a) => c * Math.sin(a)), xaxis: "x" + n, yaxis: "y" + n, mode: "lines", line: { dash: "dash", color: "#888" }, name: `${joint} clearance`, meta: [joint, "clearance"], hoverinfo: "skip" },
      { x: orbit.x_um, y: orbit.y_um, xaxis: "x" + n, yaxis: "y" + n, mode: "lines", line: { color: "#1f77b4" }, name: `${joint} pin centre`, meta: [joint, "orbit"] },
    );
    layout["xaxis" + n] = { domain: [x0, x1], range: [-reach, reach], anchor: "y" + n, title: { text: "ex (µm)" }, zeroline: false };
    layout["yaxis" + n] = { domain: [y0, y1], range: [-reach, reach], anchor: "x" + n, scaleanchor: "x" + n, title: { text: "ey (µm)" }, zeroline: false };
    layout.annotations.push({ text: `${joint}: c = ${c.toPrecision(3)} µm`, x: (x0 + x1) / 2, y: y1, xref: "paper", yref: "paper", yanchor: "bottom", showarrow: false, font: { size: 13 } });
  });
  const box = $("orbits");
  box.style.height = `${layout.height}px`;
  Plotly.react(box, traces, layout, CONFIG);
}

function drawCurves(curves) {
  const keys = Object.keys(curves.series);
  const forces = keys.filter((k) => k.startsWith("F_"));
  const omegas = keys.filter((k) => k.startsWith("omega") || k === "slider_v");
  const output = omegas.length ? [omegas[omegas.length - 1]] : [];
  const panels = [
    ["Joint forces (N)", forces],
    [`Output link speed${output.length ? " " + output[0] + " (" + unitOf(output[0]) + ")" : ""}`, output],
    ["Driving torque (N·m)", keys.filter((k) => k === "torque")],
  ];
  const traces = [];
  const layout = {
    height: 760 + TOP - 25, margin: { l: 55, r: 10, t: TOP, b: 40 }, annotations: [],
    legend: { orientation: "v", x: 1.01, y: 1 },
  };
  let colour = 0;
  panels.forEach(([title, names], k) => {
    const n = k === 0 ? "" : String(k + 1);
    const top = 1 - k / 3 - (k ? 0.03 : 0);
    const bottom = 1 - (k + 1) / 3 + (k < 2 ? 0.05 : 0);
    layout["xaxis" + n] = { anchor: "y" + n, matches: k ? "x" : undefined, showticklabels: k === 2, title: k === 2 ? { text: "crank angle in the analysed revolution (deg); dotted: ideal joints" } : undefined };
    layout["yaxis" + n] = { domain: [bottom, top], anchor: "x" + n };
    layout.annotations.push({ text: title, x: 0.5, y: top, xref: "paper", yref: "paper", yanchor: "bottom", showarrow: false, font: { size: 13 } });
    for (const key of names) {
      const series = curves.series[key];
      traces.push({ x: curves.crank_deg, y: series.values, xaxis: "x" + n, yaxis: "y" + n, mode: "lines", name: key, meta: [key, "run"], showlegend: k === 0, line: { color: COLOURS[colour++ % COLOURS.length], width: 1.5 } });
      if (series.nominal.length) {
        traces.push({ x: curves.nominal_crank_deg, y: series.nominal, xaxis: "x" + n, yaxis: "y" + n, mode: "lines", name: `${key} ideal`, meta: [key, "ideal"], showlegend: false, line: { color: "#111", dash: "dot", width: 1.5 } });
      }
    }
  });
  Plotly.react($("curves"), traces, layout, CONFIG);
}

function format(value, digits) {
  if (value === null || value === undefined || Number.isNaN(value)) return "";
  return Number(value).toPrecision(digits);
}

function drawPeaks(view) {
  const body = $("peaks").querySelector("tbody");
  body.replaceChildren();
  for (const [key, peak] of Object.entries(view.peaks)) {
    const row = document.createElement("tr");
    row.dataset.key = key;
    const increase = view.increase_percent[key];
    const cells = [
      `${key} (${unitOf(key)})`,
      format(peak.value, 5),
      String(peak.revolution),
      format(peak.revolution_deg, 4),
      format(view.nominal_peaks[key], 5),
      increase === undefined || increase === null ? "" : (increase >= 0 ? "+" : "") + increase.toFixed(1),
    ];
    for (const text of cells) {
      const cell = document.createElement("td");
      cell.textContent = text;
      row.appendChild(cell);
    }
    row.children[1].dataset.value = String(peak.value);
    body.appendChild(row);
  }
}

function drawDiagnostics(view) {
  const list = $("diagnostics");
  list.replaceChildren();
  const lines = [
    ["info", `contact: ${view.contact}`],
    ["info", `periodicity: ${view.periodicity}`],
    ["info", "deepest penetration over the analysed revolution: " +
      Object.entries(view.max_penetration_um).map(([j, v]) => `${j} ${v.toPrecision(3)} µm`).join(", ")],
  ];
  if (view.status !== "success" && view.message) lines.push(["warning", view.message]);
  for (const finding of view.diagnostics) {
    lines.push([finding.level, `${finding.level}: ${finding.code}${finding.joint ? " [" + finding.joint + "]" : ""}: ${finding.message}`]);
  }
  for (const [level, text] of lines) {
    const item = document.createElement("li");
    item.className = level;
    item.textContent = text;
    list.appendChild(item);
  }
}

// The download: fetched first, so that a refusal (joints of their own contact, a bad value)
// is the page's message rather than a saved error file.
async function download(event) {
  event.preventDefault();
  const link = $("download");
  const label = link.textContent;
  link.textContent = "running jointplay simulate…";
  try {
    const reply = await fetch(link.href);
    if (!reply.ok) {
      showMessage((await reply.json()).error || `error ${reply.status}`);
      return;
    }
    const name = (reply.headers.get("Content-Disposition") || "").match(/filename="([^"]+)"/);
    const url = URL.createObjectURL(await reply.blob());
    const save = document.createElement("a");
    save.href = url;
    save.download = name ? name[1] : "jointplay.zip";
    document.body.appendChild(save);
    save.click();
    save.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
  } catch (error) {
    showMessage(String(error));
  } finally {
    link.textContent = label;
  }
}

async function start() {
  try {
    const reply = await fetch("/api/spec");
    spec = await reply.json();
  } catch (error) {
    setStatus("error", "the server did not answer");
    return;
  }
  buildControls();
  $("download").addEventListener("click", download);
  state = { ...spec.defaults };
  // a link may carry what this mechanism has no control for (another mechanism's joint, an
  // old parameter): it is left out, and said, rather than refused on every change
  const known = new Set([...Object.keys(spec.defaults), "mu",
    ...spec.joints.flatMap((j) => [`contact.${j.name}`, `mu.${j.name}`])]);
  const ignored = [];
  for (const [key, value] of new URLSearchParams(location.search)) {
    if (known.has(key)) state[key] = value;
    else ignored.push(key);
  }
  if (ignored.length) notice = `left out of the link, as this page has no control for it: ${ignored.join(", ")}`;
  history.replaceState(null, "", "?" + query());
  showState();
  update();
}

start();
