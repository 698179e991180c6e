// The page: loads the file, sends each edit for analysis (debounced; a newer request
// supersedes an older one), draws the last good analysis, saves, polls the file on disk.
"use strict";

const $ = (id) => document.getElementById(id);
const DEBOUNCE_MS = 300;
const POLL_MS = 1000;

const state = {
  doc: null, k: 0, lang: "en", texts: { en: {}, zh: {} }, schema: null,
  generation: 0, shown: 0, mtime: null, savedText: "", timer: null, playing: null,
  chosen: new Set(), reaction: null, problems: [], warnings: [], timing: null, sentAt: 0,
  busySince: null,
};
window.editorState = state;

const T = (key) => state.texts[state.lang][key] || state.texts.en[key] || key;

async function api(path, body) {
  const opts = body === undefined ? {} : { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) };
  const r = await fetch(path, opts);
  if (!r.ok && r.headers.get("Content-Type")?.startsWith("application/json")) return r.json();
  if (!r.ok) throw new Error(`${path}: ${r.status}`);
  return r.json();
}

function translate() {
  document.documentElement.lang = state.lang;
  for (const el of document.querySelectorAll("[data-t]")) el.textContent = T(el.dataset.t);
  $("play").textContent = state.playing ? T("pause") : T("play");
  markDirty(editor.text);
  status();
}

const editor = new CodeEditor($("editor"), {
  onChange: (text) => { markDirty(text); schedule(); },
  onCaret: (path) => showHelp(path),
});

function markDirty(text) {
  if (!state.texts.en.saved) return;
  const dirty = text !== state.savedText;
  $("saved").textContent = dirty ? T("unsaved") : T("saved");
  $("saved").classList.toggle("dirty", dirty);
}

function showHelp(path) {
  if (!state.schema) return;
  const here = schemaAt(state.schema, path);
  const parent = schemaAt(state.schema, path.slice(0, -1));
  const keys = (n) => (n && n.properties ? Object.keys(n.properties) : (n && n.propertyNames && n.propertyNames.enum) || []);
  const inside = keys(here), beside = keys(parent);
  const parts = [`<b>${escapeHtml(path.join(".") || "(top)")}</b>`];
  if (describeSchema(here)) parts.push(escapeHtml(describeSchema(here)));
  const list = inside.length ? inside : beside;
  if (list.length) parts.push(`${T("keys_here")}: ` + list.map((k) => `<code class="key">${escapeHtml(k)}</code>`).join(" "));
  $("help").innerHTML = parts.join(" — ");
  for (const el of $("help").querySelectorAll("code.key")) {  // completion: a click inserts the key
    el.addEventListener("mousedown", (e) => { e.preventDefault(); editor.insert(`${el.textContent}: `); });
  }
}

function schedule() {
  clearTimeout(state.timer);
  state.timer = setTimeout(analyse, DEBOUNCE_MS);
}

async function analyse() {
  const generation = ++state.generation;
  const t0 = performance.now();
  state.busySince = t0;
  status();
  let answer;
  try {
    answer = await api("api/analyse", { text: editor.text, generation, lang: state.lang });
  } catch (e) {
    state.busySince = null;
    state.problems = [{ text: String(e), message: String(e), line: null, col: null }];
    return show();
  }
  if (answer.superseded || generation < state.generation) return;  // a newer one is on its way
  state.busySince = null;
  state.shown = generation;
  state.problems = answer.problems || [];
  state.warnings = answer.warnings || [];
  if (answer.ok) {
    const keep = state.doc ? state.doc.angle[state.k] : null;
    state.doc = answer.analysis;
    state.k = keep === null ? 0 : nearestIndex(state.doc, keep);
    if (!state.chosen.size || ![...state.chosen].every((p) => state.doc.points.some((q) => q.name === p))) {
      state.chosen = new Set(defaultPaths(state.doc));
    }
  }
  const t1 = performance.now();
  show();
  const t2 = performance.now();
  state.timing = { request_ms: t1 - t0, draw_ms: t2 - t1, total_ms: t2 - t0, server_s: answer.seconds ?? null, generation };
  status();
}

function nearestIndex(doc, angle) {
  let best = 0;
  doc.angle.forEach((a, k) => { if (Math.abs(a - angle) < Math.abs(doc.angle[best] - angle)) best = k; });
  return best;
}

function defaultPaths(doc) {  // the pins that are not on the frame
  const names = new Set();
  for (const j of doc.joints) if (j.pin && !j.ground) {
    const p = doc.points.find((q) => q.link === j.links[1] && q.xy[0][0] === j.xy[0][0] && q.xy[0][1] === j.xy[0][1]);
    if (p) names.add(p.name);
  }
  return names;
}

function show() {
  editor.setProblems(state.problems);
  const bad = state.problems.length > 0;
  $("drawing").classList.toggle("stale", bad);
  $("curves").classList.toggle("stale", bad);
  const list = [];
  for (const p of state.problems) {
    list.push(`<div class="bad" data-line="${p.line ?? ""}" data-col="${p.col ?? ""}">${escapeHtml(p.text)}</div>`);
  }
  if (!bad) list.push(`<div class="ok">${T("no_problems")}</div>`);
  for (const w of state.warnings) list.push(`<div class="warn">${escapeHtml(w)}</div>`);
  if (bad && state.doc) list.push(`<div class="warn">${T("stale")}</div>`);
  $("problems").innerHTML = list.join("");
  for (const el of $("problems").querySelectorAll(".bad[data-line]")) {
    if (el.dataset.line) el.addEventListener("click", () => editor.goTo(+el.dataset.line, +el.dataset.col));
  }
  if (state.doc) {
    const pick = $("reaction-pick"), joints = state.doc.curves.reactions.map((r) => r.joint);
    if (pick.dataset.joints !== joints.join(",")) {
      pick.innerHTML = state.doc.curves.reactions.map((r) => `<option value="${r.joint}">${r.joint} (${r.symbol})</option>`).join("");
      pick.dataset.joints = joints.join(",");
      if (!joints.includes(state.reaction)) state.reaction = joints[0];
      pick.value = state.reaction;
    }
    const s = $("slider");
    s.max = state.doc.rows - 1;
    s.value = state.k;
  }
  redraw();
}

function redraw() {  // a drawing that fails says so in the status line; the page goes on
  try {
    draw();
  } catch (e) {
    $("status").textContent = `drawing failed: ${e}`;
    $("status").className = "bad";
  }
}

function draw() {
  const doc = state.doc;
  if (!doc) return;
  const k = Math.min(state.k, doc.rows - 1);
  const opt = {
    forces: $("show-forces").checked, friction: $("show-friction").checked,
    circles: $("show-circles").checked, paths: $("show-paths").checked,
    sketch: $("show-sketch").checked, chosen: state.chosen,
  };
  drawMechanism($("drawing"), doc, k, opt, state.texts[state.lang]);
  $("angle-out").textContent = `${(+doc.angle[k]).toFixed(2)}${doc.driver.angular ? "°" : " mm"}  (${doc.driver.name})`;
  $("angle-out").dataset.angle = doc.angle[k];
  const c = doc.curves;
  plotCurves($("curve-effort"), doc.x, c.effort.series, { title: `${T("torque")} ${c.effort.name}, ${c.effort.unit}`, xlabel: doc.xlabel, k });
  const r = c.reactions.find((q) => q.joint === state.reaction) || c.reactions[0];
  if (r) plotCurves($("curve-reaction"), doc.x, r.series, { title: `${T("reaction")} ${r.joint} |${r.symbol}|, N`, xlabel: doc.xlabel, k });
  const o = c.output;
  ["s", "v", "a"].forEach((id, i) => {
    const svg = $(`curve-${id}`);
    if (!o || !o.series[i]) { svg.innerHTML = ""; return; }
    const s = o.series[i];
    plotCurves(svg, doc.x, [{ label: s.label, y: s.y }], { title: `${T("output")} ${o.name}: ${s.label}, ${s.unit}`, xlabel: doc.xlabel, k });
  });
}

function status() {
  const el = $("status"), doc = state.doc;
  const bits = [];
  if (state.busySince !== null) bits.push(`${T("analysing")} ${((performance.now() - state.busySince) / 1000).toFixed(1)} s`);
  if (state.problems.length) bits.push(`${state.problems.length} ${T("problems")}`);
  if (doc) bits.push(doc.checks.line);
  for (const w of state.warnings) bits.push(w);
  if (state.timing && state.timing.server_s !== null) bits.push(T("seconds").replace("{s}", (state.timing.total_ms / 1000).toFixed(2)));
  el.textContent = bits.join("  ·  ");
  el.className = state.problems.length ? "bad" : (doc && !doc.checks.ok) || state.warnings.length ? "warn" : "";
}
setInterval(() => { if (state.busySince !== null) status(); }, 200);

function setRow(k) {
  if (!state.doc) return;
  state.k = Math.max(0, Math.min(state.doc.rows - 1, k));
  $("slider").value = state.k;
  redraw();
}

$("slider").addEventListener("input", (e) => setRow(+e.target.value));
for (const id of ["show-forces", "show-friction", "show-circles", "show-paths", "show-sketch"]) $(id).addEventListener("change", redraw);
$("reaction-pick").addEventListener("change", (e) => { state.reaction = e.target.value; redraw(); });
$("play").addEventListener("click", () => {
  if (state.playing) { clearInterval(state.playing); state.playing = null; }
  else state.playing = setInterval(() => state.doc && setRow((state.k + 1) % state.doc.rows), 40);
  translate();
});

// dragging the driving link (or clicking a point to trace its path)
function modelXY(svg, ev) {
  const p = svg.createSVGPoint();
  p.x = ev.clientX; p.y = ev.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return [q.x / 1000, -q.y / 1000];
}
let dragging = false;
$("drawing").addEventListener("pointerdown", (ev) => {
  const t = ev.target;
  if (t.dataset && t.dataset.point) {
    const n = t.dataset.point;
    state.chosen.has(n) ? state.chosen.delete(n) : state.chosen.add(n);
    return redraw();
  }
  if (!state.doc || !(t.dataset && t.dataset.link === state.doc.driver.link)) return;
  dragging = true;
  $("drawing").setPointerCapture(ev.pointerId);
});
$("drawing").addEventListener("pointermove", (ev) => {
  if (!dragging) return;
  const [x, y] = modelXY($("drawing"), ev);
  const k = rowNearest(state.doc, x, y);
  if (k !== null) setRow(k);
});
$("drawing").addEventListener("pointerup", () => { dragging = false; });

// saving, and the file on disk
async function save() {
  const text = editor.text;
  const r = await api("api/save", { text });
  if (r.error) { $("saved").textContent = r.error; return; }
  state.savedText = text;
  state.mtime = r.mtime;
  markDirty(editor.text);
}
$("save").addEventListener("click", save);
document.addEventListener("keydown", (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key === "s") { e.preventDefault(); save(); }
});

async function load(notice) {
  const typed = editor.text;
  const f = await api("api/file");
  if (notice && editor.text !== typed) {  // typed while the file came: the typing stays
    $("disk").hidden = false;
    return;
  }
  state.mtime = f.mtime;
  editor.setText(f.text);
  state.savedText = editor.text;  // as the text area holds it (CRLF read as LF)
  $("file").textContent = f.file;
  markDirty(f.text);
  if (notice) $("saved").textContent = T("reloaded");
  $("disk").hidden = true;
  analyse();
}

async function poll() {
  try {
    const known = state.mtime;
    const s = await api("api/stat");
    if (state.mtime !== known) return;  // a save or a load answered meanwhile: s is older
    if (s.mtime !== null && s.mtime !== state.mtime) {
      if (editor.text === state.savedText) await load(true);
      else $("disk").hidden = false;
    }
  } catch (e) { /* the server has stopped: keep the page as it is */ }
}
$("disk-reload").addEventListener("click", () => load(true));
$("disk-keep").addEventListener("click", async () => { state.mtime = (await api("api/stat")).mtime; $("disk").hidden = true; });

// downloads: the files of the last good analysis, made by the server
for (const a of document.querySelectorAll("a.dl")) {
  a.addEventListener("click", () => { a.href = `api/download/${a.dataset.name}?lang=${state.lang}`; });
  a.href = `api/download/${a.dataset.name}`;
  a.setAttribute("download", a.dataset.name);
}

$("lang").addEventListener("change", (e) => { state.lang = e.target.value; translate(); analyse(); });

(async function start() {
  const [texts, schema] = await Promise.all([api("api/texts"), api("api/schema")]);
  state.texts = texts;
  state.schema = schema;
  translate();
  await load(false);
  setInterval(poll, POLL_MS);
  window.addEventListener("resize", redraw);
})();
