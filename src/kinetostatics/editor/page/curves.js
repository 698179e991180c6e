// Curves over the driver's travel, in SVG, with the current row marked.
"use strict";

const CURVE_COLORS = ["#1f5fa8", "#c0392b", "#2e8b57", "#8e44ad"];

function ticks(lo, hi, n) {
  const step = niceStep((hi - lo) / n || 1), out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push(+v.toPrecision(12));
  return out;
}

// plot(svg, x, series, {title, xlabel, k}): series = [{label, y}], nulls are gaps
function plotCurves(svg, x, series, opt) {
  const W = svg.clientWidth || 400, H = svg.clientHeight || 170;
  const L = 52, R = 8, T = 20, B = 30;
  svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
  let lo = Infinity, hi = -Infinity;
  for (const s of series) for (const v of s.y) if (v !== null && isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!isFinite(lo)) { lo = -1; hi = 1; }
  if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { lo -= 1; hi += 1; }
  const pad = 0.05 * (hi - lo); lo -= pad; hi += pad;
  const x0 = x[0], x1 = x[x.length - 1] === x0 ? x0 + 1 : x[x.length - 1];
  const px = (v) => L + (v - x0) / (x1 - x0) * (W - L - R);
  const py = (v) => T + (hi - v) / (hi - lo) * (H - T - B);
  const out = [`<text x="${L}" y="13" font-size="11" font-weight="600">${escapeHtml(opt.title)}</text>`];
  for (const t of ticks(lo, hi, 4)) {
    out.push(`<line x1="${L}" x2="${W - R}" y1="${py(t)}" y2="${py(t)}" stroke="#eee"/>` +
      `<text x="${L - 4}" y="${py(t) + 3}" font-size="9" text-anchor="end">${+t.toPrecision(6)}</text>`);
  }
  for (const t of ticks(x0, x1, 6)) {
    out.push(`<line y1="${T}" y2="${H - B}" x1="${px(t)}" x2="${px(t)}" stroke="#f3f3f3"/>` +
      `<text x="${px(t)}" y="${H - B + 11}" font-size="9" text-anchor="middle">${+t.toPrecision(6)}</text>`);
  }
  out.push(`<text x="${(L + W - R) / 2}" y="${H - 4}" font-size="9" text-anchor="middle" fill="#555">${escapeHtml(opt.xlabel)}</text>`);
  if (lo < 0 && hi > 0) out.push(`<line x1="${L}" x2="${W - R}" y1="${py(0)}" y2="${py(0)}" stroke="#999"/>`);
  series.forEach((s, i) => {
    let d = "", pen = false;
    s.y.forEach((v, k) => {
      if (v === null || !isFinite(v)) { pen = false; return; }
      d += `${pen ? "L" : "M"}${px(x[k]).toFixed(2)},${py(v).toFixed(2)}`;
      pen = true;
    });
    const c = CURVE_COLORS[i % CURVE_COLORS.length];
    out.push(`<path class="series" data-series="${i}" data-label="${escapeHtml(s.label)}" d="${d}" fill="none" stroke="${c}" stroke-width="1.5"/>`);
    out.push(`<text x="${W - R - 4}" y="${T + 10 + 11 * i}" font-size="9.5" text-anchor="end" fill="${c}">${escapeHtml(s.label)}</text>`);
  });
  const k = opt.k;
  out.push(`<line class="marker" data-index="${k}" data-x="${x[k]}" x1="${px(x[k])}" x2="${px(x[k])}" y1="${T}" y2="${H - B}" stroke="#d11" stroke-width="1"/>`);
  series.forEach((s, i) => {
    const v = s.y[k];
    if (v === null || !isFinite(v)) return;
    out.push(`<circle class="marker-value" data-series="${i}" data-value="${v}" cx="${px(x[k])}" cy="${py(v)}" r="3" fill="${CURVE_COLORS[i % CURVE_COLORS.length]}"/>`);
  });
  svg.innerHTML = out.join("");
}

window.plotCurves = plotCurves;
