// The YAML editor: a textarea over a highlighted copy of its text, line numbers, the
// problems written at their lines, and the keys the schema allows where the caret is.
"use strict";

const LINE_PX = 18;
const PAD_PX = 4;

function escapeHtml(s) {
  return s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

// the index of a comment's '#' on a line (outside quotes), or -1
function commentAt(line) {
  let quote = null;
  for (let i = 0; i < line.length; i++) {
    const ch = line[i];
    if (quote) { if (ch === quote) quote = null; continue; }
    if (ch === '"' || ch === "'") quote = ch;
    else if (ch === "#" && (i === 0 || /\s/.test(line[i - 1]))) return i;
  }
  return -1;
}

const TOKEN = /("(?:[^"\\]|\\.)*"|'[^']*')|([A-Za-z_\u00c0-\uffff][\w.\u00c0-\uffff]*)(\s*:)(?=\s|$)|(-?\b\d+(?:\.\d+)?(?:[eE][-+]?\d+)?\b)|([{}\[\],])/g;

function highlightCode(code) {
  let out = "", last = 0, m;
  TOKEN.lastIndex = 0;
  while ((m = TOKEN.exec(code))) {
    out += escapeHtml(code.slice(last, m.index));
    if (m[1]) out += `<span class="s">${escapeHtml(m[1])}</span>`;
    else if (m[2]) out += `<span class="k">${escapeHtml(m[2])}</span>${escapeHtml(m[3])}`;
    else if (m[4]) out += `<span class="n">${m[4]}</span>`;
    else out += `<span class="p">${escapeHtml(m[5])}</span>`;
    last = TOKEN.lastIndex;
  }
  return out + escapeHtml(code.slice(last));
}

function highlightLine(line, badCol) {
  const c = commentAt(line);
  const code = c < 0 ? line : line.slice(0, c);
  const note = c < 0 ? "" : `<span class="c">${escapeHtml(line.slice(c))}</span>`;
  let html;
  const key = /^(\s*(?:-\s+)?)([^\s#:{}\[\],'"][^:#]*?)(\s*:)(?=\s|$)/.exec(code);
  if (key) {
    html = escapeHtml(key[1]) + `<span class="k">${escapeHtml(key[2])}</span>` +
      escapeHtml(key[3]) + highlightCode(code.slice(key[0].length));
  } else {
    html = highlightCode(code);
  }
  html += note;
  if (badCol) html = `<span class="err">${html || " "}</span>`;
  return html;
}

// the chain of block keys that holds the caret's line: ["links", "crank", "points"]
function keyPath(lines, row) {
  const path = [];
  let indent = Infinity;
  for (let i = row; i >= 0; i--) {
    const line = lines[i];
    const c = commentAt(line);
    const code = (c < 0 ? line : line.slice(0, c)).replace(/\s+$/, "");
    if (!code.trim()) continue;
    const ind = code.length - code.trimStart().length;
    const m = /^\s*(?:-\s+)?([^\s:#{}\[\],]+)\s*:/.exec(code);
    if (i === row) {
      if (m) path.unshift(m[1]);
      indent = ind;
      continue;
    }
    if (ind < indent && m) { path.unshift(m[1]); indent = ind; }
    if (ind === 0) break;
  }
  return path;
}

// the schema's node for a key path, and the keys it names
function schemaAt(schema, path) {
  let node = schema;
  const merged = (n) => {
    if (!n) return n;
    const alts = [...(n.oneOf || []), ...(n.anyOf || []), ...(n.allOf || [])];
    if (!alts.length) return n;
    const props = Object.assign({}, n.properties || {});
    for (const a of alts) Object.assign(props, (a && a.properties) || {});
    return Object.assign({}, n, { properties: props });
  };
  for (const key of path) {
    node = merged(node);
    if (!node) return null;
    if (node.properties && key in node.properties) node = node.properties[key];
    else if (node.additionalProperties && typeof node.additionalProperties === "object") node = node.additionalProperties;
    else return null;
  }
  return merged(node);
}

function describe(node) {
  if (!node) return "";
  const bits = [];
  if (node.type) bits.push([].concat(node.type).join(" | "));
  if (node.enum) bits.push("one of " + node.enum.join(", "));
  if (node.description) bits.push(node.description);
  return bits.join("; ");
}

class CodeEditor {
  constructor(root, { onChange, onCaret } = {}) {
    this.root = root;
    this.onChange = onChange || (() => {});
    this.onCaret = onCaret || (() => {});
    this.problems = [];
    root.innerHTML = '<div class="wrap"><div class="gutter"></div><div class="code">' +
      '<pre class="hl" aria-hidden="true"></pre><textarea spellcheck="false" wrap="off" ' +
      'autocapitalize="off" autocomplete="off" aria-label="YAML"></textarea><div class="msgs"></div></div></div>';
    this.gutter = root.querySelector(".gutter");
    this.hl = root.querySelector("pre.hl");
    this.area = root.querySelector("textarea");
    this.msgs = root.querySelector(".msgs");
    this.area.addEventListener("input", () => { this.render(); this.onChange(this.area.value); });
    for (const ev of ["keyup", "click", "focus"]) this.area.addEventListener(ev, () => this.caret());
    this.area.addEventListener("mousemove", (e) => {  // hover: the key path of the line under the pointer
      const box = this.area.getBoundingClientRect();
      const row = Math.floor((e.clientY - box.top - PAD_PX) / LINE_PX);
      const lines = this.area.value.split("\n");
      if (row >= 0 && row < lines.length && row !== this.hovered) {
        this.hovered = row;
        this.onCaret(keyPath(lines, row), row);
      }
    });
    this.area.addEventListener("keydown", (e) => {
      if (e.key === "Tab") {  // two spaces, never a tab (YAML)
        e.preventDefault();
        document.execCommand("insertText", false, "  ");
      }
    });
  }
  get text() { return this.area.value; }
  insert(text) {  // at the caret, as typing would (undo keeps it)
    this.area.focus();
    document.execCommand("insertText", false, text);
  }
  setText(text) { this.area.value = text; this.render(); }
  setProblems(problems) { this.problems = problems || []; this.render(); }
  caret() {
    const before = this.area.value.slice(0, this.area.selectionStart);
    const row = before.split("\n").length - 1;
    this.onCaret(keyPath(this.area.value.split("\n"), row), row);
  }
  goTo(line, col) {
    const lines = this.area.value.split("\n");
    let pos = 0;
    for (let i = 0; i < Math.min(line - 1, lines.length); i++) pos += lines[i].length + 1;
    pos += Math.max(0, (col || 1) - 1);
    this.area.focus();
    this.area.setSelectionRange(pos, pos);
    this.root.scrollTop = Math.max(0, (line - 5) * LINE_PX);
  }
  render() {
    const lines = this.area.value.split("\n");
    const bad = new Map();
    for (const p of this.problems) if (p.line) {
      if (!bad.has(p.line)) bad.set(p.line, []);
      bad.get(p.line).push(p);
    }
    this.hl.innerHTML = lines.map((l, i) => highlightLine(l, bad.has(i + 1))).join("\n") + "\n";
    this.gutter.innerHTML = lines.map((_, i) =>
      bad.has(i + 1) ? `<span class="bad">${i + 1}</span>` : `${i + 1}`).join("\n");
    const widest = lines.reduce((w, l) => Math.max(w, l.length), 0);
    this.area.style.height = (lines.length * LINE_PX + 2 * PAD_PX + LINE_PX) + "px";
    this.area.style.minWidth = `calc(${widest + 4}ch + 16px)`;
    let html = "";
    for (const [line, ps] of bad) {
      const text = ps.map((p) => `${p.line}:${p.col}: ${p.message}`).join("  ·  ");
      html += `<div class="msg" data-problem-line="${line}" title="${escapeHtml(text)}" ` +
        `style="top:${PAD_PX + (line - 1) * LINE_PX}px">${escapeHtml(text)}</div>`;
    }
    this.msgs.innerHTML = html;
  }
}

window.CodeEditor = CodeEditor;
window.schemaAt = schemaAt;
window.describeSchema = describe;
window.escapeHtml = escapeHtml;
