// The mechanism at one row of the analysis's document, in SVG at true proportions.
// Model lengths are in m; the SVG's user unit is the mm (X = 1000 x, Y = -1000 y).
// Every joint, point, link, force and sketch target carries data-* attributes with its
// model values (data-x, data-y in m; data-fx, data-fy in N) so that tests can read them.
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
const X = (x) => 1000 * x;
const Y = (y) => -1000 * y;
const fmt = (v) => (v === null || v === undefined ? "" : String(v));

function niceStep(x) {
  const k = Math.floor(Math.log10(x));
  for (const m of [1, 2, 2.5, 5, 10]) if (m * 10 ** k >= x) return m * 10 ** k;
  return 10 ** (k + 1);
}

// the view box that holds the drawing and every force arrow of the cycle
function viewOf(doc) {
  let [x0, y0, x1, y1] = doc.bounds;
  const mu = doc.loads.mu;
  for (const key of ["plain", "friction"]) {
    const rows = doc.loads[key];
    if (!rows) continue;
    for (const a of rows) if (a.force) a.force.forEach((f, k) => {
      if (!a.active[k] || f[0] === null) return;
      const ex = a.at[k][0] + f[0] / mu / 1000, ey = a.at[k][1] + f[1] / mu / 1000;
      x0 = Math.min(x0, ex); x1 = Math.max(x1, ex); y0 = Math.min(y0, ey); y1 = Math.max(y1, ey);
    });
  }
  const pad = 0.06 * Math.max(x1 - x0, y1 - y0);
  return [X(x0 - pad), Y(y1 + pad), X(x1 - x0 + 2 * pad), X(y1 - y0 + 2 * pad)];
}

function arrow(x, y, fx, fy, mu, size, color) {  // a force at (x, y) m, to mu N/mm
  const X0 = X(x), Y0 = Y(y), X1 = X0 + fx / mu, Y1 = Y0 - fy / mu;
  const L = Math.hypot(X1 - X0, Y1 - Y0);
  if (!(L > 1e-9)) return "";
  const ux = (X1 - X0) / L, uy = (Y1 - Y0) / L, h = Math.min(size, 0.4 * L);
  const hx = X1 - ux * h, hy = Y1 - uy * h, w = 0.35 * h;
  return `<line x1="${X0}" y1="${Y0}" x2="${hx}" y2="${hy}" stroke="${color}" stroke-width="1.6" vector-effect="non-scaling-stroke"/>` +
    `<polygon points="${X1},${Y1} ${hx - uy * w},${hy + ux * w} ${hx + uy * w},${hy - ux * w}" fill="${color}"/>`;
}

function couple(x, y, m, r, color) {  // a couple: an arc with its head in its sense
  const X0 = X(x), Y0 = Y(y), s = m > 0 ? 1 : -1;
  const a0 = -0.9 * s, a1 = 1.6 * s;  // radians, counter-clockwise positive in the model
  const p = (a) => [X0 + r * Math.cos(a), Y0 - r * Math.sin(a)];
  const [sx, sy] = p(a0), [ex, ey] = p(a1);
  const tx = -Math.sin(a1) * s, ty = -Math.cos(a1) * s, h = 0.5 * r;
  return `<path d="M${sx},${sy} A${r},${r} 0 0 ${s > 0 ? 0 : 1} ${ex},${ey}" fill="none" stroke="${color}" stroke-width="1.4" vector-effect="non-scaling-stroke"/>` +
    `<polygon points="${ex + tx * h},${ey + ty * h} ${ex - ty * 0.35 * h},${ey + tx * 0.35 * h} ${ex + ty * 0.35 * h},${ey - tx * 0.35 * h}" fill="${color}"/>`;
}

function drawMechanism(svg, doc, k, opt, texts) {
  const span = X(doc.span), pin = 0.012 * span, font = 0.028 * span;
  const view = viewOf(doc);
  svg.setAttribute("viewBox", view.join(" "));
  svg.dataset.row = doc.row[k];
  svg.dataset.index = k;
  svg.dataset.angle = doc.angle[k];
  svg.dataset.scale = doc.span;
  svg.dataset.mu = doc.loads.mu;
  const out = [];
  // the frame: guides with hatching, pivots
  for (const g of doc.guides) {
    const dx = g.end[0] - g.start[0], dy = g.end[1] - g.start[1], L = Math.hypot(dx, dy);
    const nx = -dy / L * g.half, ny = dx / L * g.half;
    for (const s of [-1, 1]) {
      out.push(`<line class="guide" data-guide="${g.joint}" x1="${X(g.start[0] + s * nx)}" y1="${Y(g.start[1] + s * ny)}" x2="${X(g.end[0] + s * nx)}" y2="${Y(g.end[1] + s * ny)}" stroke="#444" stroke-width="1.2" vector-effect="non-scaling-stroke"/>`);
    }
  }
  for (const [name, p] of Object.entries(doc.pivots)) {
    const x = X(p[0]), y = Y(p[1]);
    out.push(`<polygon class="pivot" data-pivot="${name}" points="${x},${y} ${x - 1.6 * pin},${y + 2.6 * pin} ${x + 1.6 * pin},${y + 2.6 * pin}" fill="#ddd" stroke="#444" stroke-width="1" vector-effect="non-scaling-stroke"/>`);
    out.push(`<line x1="${x - 2.4 * pin}" y1="${y + 2.6 * pin}" x2="${x + 2.4 * pin}" y2="${y + 2.6 * pin}" stroke="#444" stroke-width="1.4" vector-effect="non-scaling-stroke"/>`);
  }
  // paths of the chosen points
  if (opt.paths) for (const p of doc.points) if (opt.chosen.has(p.name)) {
    const pts = p.xy.map((q) => `${X(q[0])},${Y(q[1])}`).join(" ");
    out.push(`<polyline class="path" data-path="${p.name}" points="${pts}" fill="none" stroke="#999" stroke-dasharray="4 3" stroke-width="1" vector-effect="non-scaling-stroke"/>`);
  }
  // links
  for (const l of doc.links) {
    const o = l.outline[k];
    const pts = o.map((q) => `${X(q[0])},${Y(q[1])}`).join(" ");
    if (o.length === 1) continue;
    const tag = l.plate ? "polygon" : "polyline";
    out.push(`<${tag} class="link" data-link="${l.name}" points="${pts}" fill="${l.plate ? l.color + "33" : "none"}" stroke="${l.color}" stroke-width="5" stroke-linecap="round" stroke-linejoin="round" vector-effect="non-scaling-stroke"/>`);
    if (l.number !== null && l.number !== undefined && o.length >= 2) {
      const cx = o.reduce((s, q) => s + q[0], 0) / o.length, cy = o.reduce((s, q) => s + q[1], 0) / o.length;
      out.push(`<text class="number" x="${X(cx)}" y="${Y(cy) - 0.6 * font}" font-size="${font}" fill="${l.color}" text-anchor="middle">${l.number}</text>`);
    }
  }
  for (const w of doc.wheels) {
    if (w.kind === "circle") {
      out.push(`<circle class="wheel" data-joint="${w.joint}" cx="${X(w.a[k][0])}" cy="${Y(w.a[k][1])}" r="${X(w.b)}" fill="none" stroke="#777" stroke-dasharray="6 3" vector-effect="non-scaling-stroke"/>`);
    } else if (w.kind === "curve") {  // a cam's profile: its link's frame, turned by the pose
      const [px, py, th] = w.b[k], c = Math.cos(th), s = Math.sin(th);
      const pts = w.a.map((q) => `${X(px + c * q[0] - s * q[1])},${Y(py + s * q[0] + c * q[1])}`).join(" ");
      out.push(`<${w.closed ? "polygon" : "polyline"} class="wheel cam" data-joint="${w.joint}" points="${pts}" fill="${w.closed ? "#f4f0e6" : "none"}" stroke="#555" stroke-width="1.2" vector-effect="non-scaling-stroke"/>`);
    } else if (w.kind === "line") {
      out.push(`<line class="wheel" data-joint="${w.joint}" x1="${X(w.a[k][0])}" y1="${Y(w.a[k][1])}" x2="${X(w.b[k][0])}" y2="${Y(w.b[k][1])}" stroke="#777" stroke-dasharray="6 3" vector-effect="non-scaling-stroke"/>`);
    }
  }
  for (const b of doc.blocks) {
    const c = b.centre[k], d = b.direction[k], hl = X(b.length) / 2, hh = X(b.height) / 2;
    const ux = d[0], uy = -d[1], nx = -uy, ny = ux, cx = X(c[0]), cy = Y(c[1]);
    const pts = [[1, 1], [-1, 1], [-1, -1], [1, -1]].map(([s, t]) => `${cx + s * hl * ux + t * hh * nx},${cy + s * hl * uy + t * hh * ny}`).join(" ");
    out.push(`<polygon class="block" data-block="${b.joint}" points="${pts}" fill="${b.color}22" stroke="${b.color}" stroke-width="1.5" vector-effect="non-scaling-stroke"/>`);
  }
  // friction circles
  if (opt.circles) for (const f of doc.friction_circles) {
    const r = f.radius[k];
    if (r === null || !(r > 0)) continue;
    out.push(`<circle class="friction-circle" data-joint="${f.joint}" data-radius="${r}" cx="${X(f.xy[k][0])}" cy="${Y(f.xy[k][1])}" r="${X(r)}" fill="none" stroke="#c0392b" stroke-dasharray="2 2" stroke-width="1" vector-effect="non-scaling-stroke"/>`);
  }
  // joints and points
  for (const p of doc.points) {
    const q = p.xy[k];
    out.push(`<circle class="point" data-point="${p.name}" data-x="${q[0]}" data-y="${q[1]}" cx="${X(q[0])}" cy="${Y(q[1])}" r="${0.45 * pin}" fill="#333"><title>${p.name}</title></circle>`);
  }
  for (const j of doc.joints) {
    const q = j.xy[k];
    if (j.pin) {
      out.push(`<circle class="joint" data-joint="${j.name}" data-x="${q[0]}" data-y="${q[1]}" cx="${X(q[0])}" cy="${Y(q[1])}" r="${pin}" fill="#fff" stroke="#222" stroke-width="1.4" vector-effect="non-scaling-stroke"><title>${j.name}</title></circle>`);
    } else {
      out.push(`<circle class="joint slide" data-joint="${j.name}" data-x="${q[0]}" data-y="${q[1]}" cx="${X(q[0])}" cy="${Y(q[1])}" r="${0.35 * pin}" fill="#222"><title>${j.name}</title></circle>`);
    }
    out.push(`<text class="label" x="${X(q[0]) + 1.2 * pin}" y="${Y(q[1]) - 1.2 * pin}" font-size="${0.8 * font}" fill="#333">${j.name}</text>`);
  }
  // the sketch's targets: red where a sketched point is far from where it assembled
  if (opt.sketch) for (const s of doc.sketch) {
    const x = X(s.xy[0]), y = Y(s.xy[1]), r = 1.3 * pin, c = s.far ? "#d11" : "#2a9d8f";
    out.push(`<g class="sketch" data-sketch="${s.key}" data-far="${s.far}" data-x="${s.xy[0]}" data-y="${s.xy[1]}" data-distance="${fmt(s.distance)}">` +
      `<line x1="${x - r}" y1="${y - r}" x2="${x + r}" y2="${y + r}" stroke="${c}" stroke-width="${s.far ? 2.5 : 1.2}" vector-effect="non-scaling-stroke"/>` +
      `<line x1="${x - r}" y1="${y + r}" x2="${x + r}" y2="${y - r}" stroke="${c}" stroke-width="${s.far ? 2.5 : 1.2}" vector-effect="non-scaling-stroke"/>` +
      `<title>sketch ${s.key}${s.far ? ": " + texts.sketch_far : ""}</title></g>`);
  }
  // loads (free-body view) to the force scale mu (N per mm of the drawing)
  const loads = opt.friction && doc.loads.friction ? doc.loads.friction : doc.loads.plain;
  if (opt.forces) for (const a of loads) {
    if (!a.active[k]) continue;
    const { kind, label } = a, [x, y] = a.at[k], f = a.force && a.force[k], m = a.moment && a.moment[k];
    if (f && (f[0] === null || f[1] === null)) continue;
    const color = doc.loads.kinds[kind] || "#333";
    if (f) {
      const body = arrow(x, y, f[0], f[1], doc.loads.mu, 1.6 * pin, color);
      if (!body) continue;
      const tx = X(x) + f[0] / doc.loads.mu, ty = Y(y) - f[1] / doc.loads.mu;
      out.push(`<g class="force" data-kind="${kind}" data-label="${label}" data-x="${x}" data-y="${y}" data-fx="${f[0]}" data-fy="${f[1]}">${body}` +
        `<text x="${tx}" y="${ty}" font-size="${0.7 * font}" fill="${color}">${label}</text></g>`);
    } else if (m) {
      out.push(`<g class="force couple" data-kind="${kind}" data-label="${label}" data-x="${x}" data-y="${y}" data-m="${m}">${couple(x, y, m, 2.2 * pin, color)}` +
        `<text x="${X(x) + 2.6 * pin}" y="${Y(y) - 2.2 * pin}" font-size="${0.7 * font}" fill="${color}">${label} ${(+m).toPrecision(3)} N·m</text></g>`);
    }
  }
  // the scales: a length bar and the force scale
  const lstep = niceStep(0.25 * span), fx0 = view[0] + 0.04 * view[2], fy0 = view[1] + view[3] - 0.05 * view[3];
  out.push(`<g class="scale" data-length-mm="${lstep}"><line x1="${fx0}" y1="${fy0}" x2="${fx0 + lstep}" y2="${fy0}" stroke="#222" stroke-width="2" vector-effect="non-scaling-stroke"/>` +
    `<text x="${fx0}" y="${fy0 - 0.4 * font}" font-size="${0.75 * font}">${lstep} mm</text></g>`);
  out.push(`<text class="legend" x="${view[0] + 0.02 * view[2]}" y="${view[1] + 0.04 * view[3]}" font-size="${0.7 * font}" fill="#444">` +
    `${escapeHtml(doc.name)}: ${(+doc.angle[k]).toFixed(2)}°${opt.forces ? "  ·  " + escapeHtml(texts.legend || "") + (opt.friction ? "  (" + escapeHtml(texts.friction || "") + ")" : "") : ""}</text>`);
  if (opt.forces) {
    const fstep = niceStep(0.2 * span) , fy1 = fy0 - 1.8 * font;
    out.push(`<g class="force-scale" data-mu="${doc.loads.mu}"><line x1="${fx0}" y1="${fy1}" x2="${fx0 + fstep}" y2="${fy1}" stroke="#1f5fa8" stroke-width="2" vector-effect="non-scaling-stroke"/>` +
      `<text x="${fx0}" y="${fy1 - 0.4 * font}" font-size="${0.75 * font}" fill="#1f5fa8">${+(fstep * doc.loads.mu).toPrecision(3)} N  (μF = ${doc.loads.mu} N/mm)</text></g>`);
  }
  svg.innerHTML = out.join("");
}

// the row whose driving link points nearest the angle of (x, y) from its pivot
function rowNearest(doc, x, y) {
  const d = doc.driver, link = doc.links.find((l) => l.name === d.link);
  if (!d.pivot || !link) return null;
  const far = (o) => o.reduce((b, q) => (Math.hypot(q[0] - d.pivot[0], q[1] - d.pivot[1]) > Math.hypot(b[0] - d.pivot[0], b[1] - d.pivot[1]) ? q : b), o[0]);
  const want = Math.atan2(y - d.pivot[1], x - d.pivot[0]);
  let best = null, bestD = Infinity;
  link.outline.forEach((o, k) => {
    const q = far(o), a = Math.atan2(q[1] - d.pivot[1], q[0] - d.pivot[0]);
    const dist = Math.abs(Math.atan2(Math.sin(a - want), Math.cos(a - want)));
    if (dist < bestD) { bestD = dist; best = k; }
  });
  return best;
}

window.drawMechanism = drawMechanism;
window.rowNearest = rowNearest;
