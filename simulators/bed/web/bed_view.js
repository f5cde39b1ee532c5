// The interactive bed view of one knitout program: needles across, carriage
// sweeps upward, the front and the back bed side by side, each needle
// coloured by the carrier of its top loop and darker when it holds more
// loops. A scrubber (and the arrow keys) picks a sweep; the wheel zooms,
// dragging pans; the pointer shows the needle, the sweep and the source line
// that last changed the needle. Racking changes and transfers are thin marks
// in the left margin, the machine's errors and warnings ticks in the right
// margin and a list below.
//
// The data is a BedTimeline (simulators/bed/bed_timeline.hpp has the
// layout): one record per change of a needle, grouped by sweep. The state of
// a needle at a sweep is its last record at or before the sweep, found in a
// per-needle index, so drawing any region at any zoom walks only the records
// of the needles drawn and nothing is stored per sweep x needle.
//
//   wk.parseBedTimeline(bytes) -> the timeline as typed arrays
//   wk.mountBedView(container, bytes, sourceText) -> viewer (sourceText: the
//   program's text as a string or UTF-8 bytes, or null):
//     goToSweep(i), currentSweep(), currentLine(), currentSourceText(),
//     sweeps(), lineText(n), sweepAt(line), resetZoom(), destroy()
"use strict";

wk.BED_TIMELINE_MAGIC = 0x54424b57;

wk.parseBedTimeline = function (bytes) {
  if (new Uint8Array(new Uint32Array([1]).buffer)[0] !== 1) {
    throw new Error("the bed view needs a little-endian machine");
  }
  let buffer = bytes.buffer;
  let base = bytes.byteOffset;
  if (base % 4 !== 0) {
    const copy = bytes.slice();
    buffer = copy.buffer;
    base = 0;
    bytes = copy;
  }
  const view = new DataView(buffer, base, bytes.byteLength);
  if (bytes.byteLength < 48 || view.getUint32(0, true) !== wk.BED_TIMELINE_MAGIC) {
    throw new Error("the bed timeline data is not a wearknit bed timeline");
  }
  const version = view.getUint32(4, true);
  if (version !== 1) throw new Error("bed timeline version " + version + " is not known (1 is)");
  const S = view.getUint32(8, true);
  const R = view.getUint32(12, true);
  const t = {
    sweepCount: S,
    recordCount: R,
    needleMin: view.getInt32(16, true),
    width: view.getUint32(20, true),
    lastLine: view.getUint32(24, true),
    truncated: (view.getUint32(28, true) & 1) !== 0,
    carriers: [],
    diagnostics: [],
  };
  const C = view.getUint32(32, true);
  const D = view.getUint32(36, true);
  const decoder = new TextDecoder();
  let at = 48;
  const align = () => { at = (at + 3) & ~3; };
  for (let c = 0; c < C; ++c) {
    const n = bytes[at];
    t.carriers.push(decoder.decode(bytes.subarray(at + 1, at + 1 + n)));
    at += 1 + n;
  }
  align();
  const need = (n) => {
    if (at + n > bytes.byteLength) throw new Error("the bed timeline data is cut short");
  };
  const u32s = (n) => { need(4 * n); const a = new Uint32Array(buffer, base + at, n); at += 4 * n; return a; };
  const i32s = (n) => { need(4 * n); const a = new Int32Array(buffer, base + at, n); at += 4 * n; return a; };
  const u16s = (n) => { need(2 * n); const a = new Uint16Array(buffer, base + at, n); at += 2 * n; return a; };
  const u8s = (n) => { need(n); const a = new Uint8Array(buffer, base + at, n); at += n; return a; };
  t.sweepFirst = u32s(S);
  t.sweepLast = u32s(S);
  t.recordBegin = u32s(S + 1);
  t.sweepTransfers = u32s(S);
  t.sweepRackQ = i32s(S);
  t.sweepCarrier = u8s(S);
  t.sweepFlags = u8s(S);
  align();
  const flags = view.getUint32(28, true);
  t.recCell = flags & 2 ? u16s(R) : u32s(R);
  align();
  t.recLineDelta = flags & 4 ? u16s(R) : u32s(R);
  align();
  t.recCarrier = u8s(R);
  t.recCount = u8s(R);
  t.recFlags = u8s(R);
  align();
  for (let d = 0; d < D; ++d) {
    need(12);
    const codeLength = bytes[at + 9];
    const messageLength = view.getUint16(at + 10, true);
    need(12 + codeLength + messageLength);
    t.diagnostics.push({
      line: view.getUint32(at, true),
      sweep: view.getUint32(at + 4, true),
      severity: ["error", "warning", "note"][Math.min(bytes[at + 8], 2)],
      code: decoder.decode(bytes.subarray(at + 12, at + 12 + codeLength)),
      message: decoder.decode(bytes.subarray(at + 12 + codeLength, at + 12 + codeLength + messageLength)),
    });
    at += 12 + codeLength + messageLength;
    align();
  }
  // Derived: the sweep of every record, and every needle's records in
  // sweep order (a counting sort by cell, stable).
  t.recSweep = new Uint32Array(R);
  for (let s = 0; s < S; ++s) t.recSweep.fill(s, t.recordBegin[s], t.recordBegin[s + 1]);
  const cells = 2 * t.width;
  t.cellStart = new Uint32Array(cells + 1);
  for (let r = 0; r < R; ++r) ++t.cellStart[t.recCell[r] + 1];
  for (let c = 0; c < cells; ++c) t.cellStart[c + 1] += t.cellStart[c];
  t.cellRecords = new Uint32Array(R);
  const fill = t.cellStart.slice(0, cells);
  for (let r = 0; r < R; ++r) t.cellRecords[fill[t.recCell[r]]++] = r;
  return t;
};

// The record holding needle cell `cell`'s state at sweep `s`, or -1.
wk.bedRecordAt = function (t, cell, s) {
  let lo = t.cellStart[cell];
  let hi = t.cellStart[cell + 1];
  // Last k in [lo, hi) with recSweep[cellRecords[k]] <= s.
  while (lo < hi) {
    const mid = (lo + hi) >>> 1;
    if (t.recSweep[t.cellRecords[mid]] <= s) lo = mid + 1;
    else hi = mid;
  }
  return lo > t.cellStart[cell] ? t.cellRecords[lo - 1] : -1;
};

// Colours of carriers 1-10 (as the static bed view draws them).
wk.BED_PALETTE = [[31, 120, 181], [227, 26, 28], [51, 160, 44], [255, 127, 0], [106, 61, 154],
  [166, 86, 41], [247, 129, 191], [102, 102, 102], [188, 189, 34], [23, 190, 207]];

wk.bedColour = function (carrier, count, back) {
  const p = wk.BED_PALETTE[(Math.max(carrier, 1) - 1) % wk.BED_PALETTE.length];
  const f = count > 2 ? 0.55 : count > 1 ? 0.75 : 1;
  // The back bed a little lighter, so that the two panels read apart.
  const w = back ? 0.22 : 0;
  return p.map((v) => Math.round((v * f) * (1 - w) + 255 * w));
};

wk.mountBedView = function (container, bytes, sourceText) {
  const t = wk.parseBedTimeline(bytes);
  const S = t.sweepCount;
  const W = Math.max(t.width, 1);

  // Source lines: the offset of every line's start (line n is
  // [starts[n-1], starts[n] - 1) ). The source is a string or its UTF-8
  // bytes; bytes are decoded a line at a time, when shown.
  let lineStarts = null;
  let lineText = () => null;
  if (sourceText instanceof Uint8Array) {
    const src = sourceText;
    let n = 1;
    for (let i = 0; i < src.length; ++i) if (src[i] === 10) ++n;
    lineStarts = new Uint32Array(n + 1);
    let k = 1;
    for (let i = 0; i < src.length; ++i) if (src[i] === 10) lineStarts[k++] = i + 1;
    lineStarts[k] = src.length + 1;
    const decoder = new TextDecoder();
    lineText = (line) => {
      if (line < 1 || line >= lineStarts.length) return null;
      return decoder.decode(src.subarray(lineStarts[line - 1], lineStarts[line] - 1)).replace(/\r$/, "");
    };
  } else if (typeof sourceText === "string") {
    const src = sourceText;
    let n = 1;
    for (let i = src.indexOf("\n"); i !== -1; i = src.indexOf("\n", i + 1)) ++n;
    lineStarts = new Uint32Array(n + 1);
    let k = 1;
    for (let i = src.indexOf("\n"); i !== -1; i = src.indexOf("\n", i + 1)) lineStarts[k++] = i + 1;
    lineStarts[k] = src.length + 1;
    lineText = (line) => {
      if (line < 1 || line >= lineStarts.length) return null;
      return src.slice(lineStarts[line - 1], lineStarts[line] - 1).replace(/\r$/, "");
    };
  }
  const recordLine = (r) => t.sweepFirst[t.recSweep[r]] + t.recLineDelta[r];
  const carrierName = (code) => (code > 0 ? (t.carriers[code - 1] ?? String(code - 1)) : "—");
  const rackingOf = (s) => t.sweepRackQ[s] / 4;
  // RGB of every (carrier code, loops held 0-3, bed), computed once.
  const colours = new Uint8Array(256 * 4 * 2 * 3);
  for (let code = 0; code < 256; ++code) {
    for (let count = 1; count < 4; ++count) {
      for (let b = 0; b < 2; ++b) colours.set(wk.bedColour(code, count, b === 1), ((code * 4 + count) * 2 + b) * 3);
    }
  }

  // ------------------------------------------------------------ the page parts
  container.classList.add("bv");
  container.textContent = "";
  const scrubber = wk.el("input", { type: "range", min: "0", max: String(Math.max(S - 1, 0)),
    value: "0", step: "1", class: "bv-scrubber", "aria-label": "sweep" });
  const sweepLabel = wk.el("span", { class: "bv-sweep-label" });
  const resetButton = wk.el("button", { type: "button", title: "show the whole bed" }, "whole bed");
  const toolbar = wk.el("div", { class: "bv-toolbar" },
    wk.el("button", { type: "button", title: "previous sweep (←)", onclick: () => step(-1) }, "◀"),
    scrubber,
    wk.el("button", { type: "button", title: "next sweep (→)", onclick: () => step(1) }, "▶"),
    sweepLabel, resetButton);
  const base = wk.el("canvas", { class: "bv-base" });
  const overlay = wk.el("canvas", { class: "bv-overlay" });
  const stage = wk.el("div", { class: "bv-stage", tabindex: "0" }, base, overlay);
  const info = wk.el("div", { class: "bv-info" });
  const hoverLine = wk.el("div", { class: "bv-hover wk-muted" }, "Point at a needle to see its source line.");
  const legend = wk.el("div", { class: "bv-legend" });
  const notes = wk.el("div", { class: "bv-notes wk-muted" });
  const diagList = wk.el("div", { class: "bv-diagnostics" });
  container.append(toolbar, stage, hoverLine, info, legend, notes, diagList);

  // Legend: the carriers that appear, then the marks.
  const seen = new Set();
  for (let s = 0; s < S; ++s) if (t.sweepCarrier[s]) seen.add(t.sweepCarrier[s]);
  for (const code of [...seen].sort((a, b) => a - b)) {
    const [r, g, b] = wk.bedColour(code, 1, false);
    legend.append(wk.el("span", { class: "bv-key" },
      wk.el("i", { style: `background: rgb(${r},${g},${b})` }), "carrier " + carrierName(code)));
  }
  const [dr, dg, db] = wk.bedColour(1, 3, false);
  legend.append(
    wk.el("span", { class: "bv-key" }, wk.el("i", { style: `background: rgb(${dr},${dg},${db})` }), "darker: 2+ loops held"),
    wk.el("span", { class: "bv-key" }, wk.el("i", { class: "bv-mark-rack" }), "racking change (left margin)"),
    wk.el("span", { class: "bv-key" }, wk.el("i", { class: "bv-mark-xfer" }), "transfers (left margin; greyed cells got loops by transfer)"),
    wk.el("span", { class: "bv-key" }, wk.el("i", { class: "bv-mark-error" }), "error"),
    wk.el("span", { class: "bv-key" }, wk.el("i", { class: "bv-mark-warning" }), "warning (right margin)"));
  notes.textContent = wk.fmt(S) + " sweeps, " + wk.fmt(t.width) + " needles from " +
    (t.width ? "needle " + t.needleMin : "—") + ", " + wk.fmt(t.recordCount) + " needle changes, " +
    wk.fmt(t.lastLine) + " source lines" + (lineStarts ? "" : " (the source text is not in this page)") +
    ". Wheel: zoom (shift: needles only, alt: sweeps only); drag: pan; click: go to that sweep; " +
    "arrow keys: previous and next sweep." +
    (t.truncated ? " The program changes the bed more often than the view records: the bed is drawn up to its last recorded change." : "");

  // Diagnostics list.
  if (t.diagnostics.length) {
    const errors = t.diagnostics.filter((d) => d.severity === "error").length;
    const table = wk.el("table", { class: "wk-table" },
      wk.el("tr", {}, wk.el("th", {}, ""), wk.el("th", { class: "num" }, "line"),
        wk.el("th", { class: "num" }, "sweep"), wk.el("th", {}, "code"), wk.el("th", {}, "message")));
    for (const d of t.diagnostics.slice(0, 2000)) {
      table.append(wk.el("tr", { class: "bv-diag bv-" + d.severity, title: "go to this sweep",
        onclick: () => { goToSweep(d.sweep); stage.focus(); } },
      wk.el("td", {}, d.severity), wk.el("td", { class: "num" }, d.line || ""),
      wk.el("td", { class: "num" }, d.sweep + 1), wk.el("td", {}, d.code), wk.el("td", {}, d.message)));
    }
    diagList.append(wk.el("h3", {}, errors + " error(s), " + (t.diagnostics.length - errors) +
      " warning(s) of the virtual machine"), table);
  }

  // ------------------------------------------------------------ geometry
  const M = { left: 86, right: 30, top: 20, bottom: 30, gap: 26 };
  const view = { n0: 0, n1: W, s0: 0, s1: Math.max(S, 1) };
  let current = 0;
  let hover = null;
  let cssW = 0;
  let cssH = 0;
  let dpr = 1;

  const panelWidth = () => Math.max((cssW - M.left - M.right - M.gap) / 2, 10);
  const panelX = (b) => M.left + b * (panelWidth() + M.gap);
  const plotTop = () => M.top;
  const plotHeight = () => Math.max(cssH - M.top - M.bottom, 10);
  const xOfNeedle = (b, n) => panelX(b) + ((n - view.n0) / (view.n1 - view.n0)) * panelWidth();
  const yOfSweep = (s) => plotTop() + plotHeight() - ((s - view.s0) / (view.s1 - view.s0)) * plotHeight();
  // What is under client point (x, y) of the stage: {bed, needle, sweep} or null.
  const hit = (x, y) => {
    for (let b = 0; b < 2; ++b) {
      const px = panelX(b);
      if (x < px || x >= px + panelWidth()) continue;
      if (y < plotTop() || y >= plotTop() + plotHeight()) return null;
      const needle = Math.floor(view.n0 + ((x - px) / panelWidth()) * (view.n1 - view.n0));
      const sweep = Math.floor(view.s0 + ((plotTop() + plotHeight() - y) / plotHeight()) * (view.s1 - view.s0));
      if (needle < 0 || needle >= t.width || sweep < 0 || sweep >= S) return null;
      return { bed: b, needle, sweep };
    }
    return null;
  };

  // ------------------------------------------------------------ drawing
  const scratch = document.createElement("canvas");

  function drawBase() {
    const ctx = base.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, cssW, cssH);
    ctx.font = "11px system-ui, sans-serif";
    const pw = panelWidth();
    const ph = plotHeight();
    const top = plotTop();
    const ni0 = Math.max(0, Math.floor(view.n0));
    const ni1 = Math.min(t.width, Math.ceil(view.n1));
    const si0 = Math.max(0, Math.floor(view.s0));
    const si1 = Math.min(S, Math.ceil(view.s1));
    const cols = ni1 - ni0;
    const rows = si1 - si0;
    for (let b = 0; b < 2; ++b) {
      const px = panelX(b);
      ctx.fillStyle = b === 0 ? "#f1f2f5" : "#f4f6f9";
      ctx.fillRect(px, top, pw, ph);
      ctx.fillStyle = "#1d2330";
      ctx.fillText(b === 0 ? "front bed" : "back bed", px, top - 6);
      if (cols <= 0 || rows <= 0) continue;
      // One image pixel per cell, or per screen pixel when cells are smaller.
      const iw = Math.max(1, Math.min(cols, Math.ceil(pw * dpr)));
      const ih = Math.max(1, Math.min(rows, Math.ceil(ph * dpr)));
      const exactRows = ih === rows;
      const image = new ImageData(iw, ih);
      const data = image.data;
      const rowSweep = new Uint32Array(ih);  // the sweep each image row shows (from the bottom)
      for (let iy = 0; iy < ih; ++iy) rowSweep[iy] = si0 + Math.floor(((iy + 1) * rows) / ih) - 1;
      for (let ix = 0; ix < iw; ++ix) {
        const needle = ni0 + Math.floor((ix * cols) / iw);
        const cell = needle * 2 + b;
        const end = t.cellStart[cell + 1];
        let k = t.cellStart[cell];
        // Skip to the first record after sweep rowSweep[0], then walk up.
        let lo = k;
        let hi = end;
        while (lo < hi) {
          const mid = (lo + hi) >>> 1;
          if (t.recSweep[t.cellRecords[mid]] <= rowSweep[0]) lo = mid + 1;
          else hi = mid;
        }
        k = lo;
        let rec = k > t.cellStart[cell] ? t.cellRecords[k - 1] : -1;
        for (let iy = 0; iy < ih; ++iy) {
          const s = rowSweep[iy];
          while (k < end && t.recSweep[t.cellRecords[k]] <= s) rec = t.cellRecords[k++];
          if (rec < 0 || t.recCount[rec] === 0) continue;
          const c = ((t.recCarrier[rec] * 4 + Math.min(t.recCount[rec], 3)) * 2 + b) * 3;
          let r = colours[c];
          let g = colours[c + 1];
          let bl = colours[c + 2];
          if (exactRows && (t.recFlags[rec] & 1) && t.recSweep[rec] === s) {
            // Loops that arrived by transfer in this sweep: greyed.
            const grey = (r + g + bl) / 3;
            r = (r + grey * 2) / 3; g = (g + grey * 2) / 3; bl = (bl + grey * 2) / 3;
          }
          const o = ((ih - 1 - iy) * iw + ix) * 4;
          data[o] = r; data[o + 1] = g; data[o + 2] = bl; data[o + 3] = 255;
        }
      }
      scratch.width = iw;
      scratch.height = ih;
      scratch.getContext("2d").putImageData(image, 0, 0);
      ctx.save();
      ctx.beginPath();
      ctx.rect(px, top, pw, ph);
      ctx.clip();
      ctx.imageSmoothingEnabled = false;
      const x0 = xOfNeedle(b, ni0);
      const x1 = xOfNeedle(b, ni1);
      const y1 = yOfSweep(si0);
      const y0 = yOfSweep(si1);
      ctx.drawImage(scratch, 0, 0, iw, ih, x0, y0, x1 - x0, y1 - y0);
      ctx.restore();
      ctx.strokeStyle = "#9aa2b1";
      ctx.lineWidth = 1;
      ctx.strokeRect(px + 0.5, top + 0.5, pw - 1, ph - 1);
      // Needle axis.
      ctx.fillStyle = "#5b6475";
      ctx.textAlign = "center";
      const span = view.n1 - view.n0;
      const stepN = niceStep(span / Math.max(pw / 70, 1));
      for (let n = Math.ceil(view.n0 / stepN) * stepN; n < view.n1; n += stepN) {
        const x = xOfNeedle(b, n + 0.5);
        ctx.fillRect(x, top + ph, 1, 4);
        ctx.fillText(String(t.needleMin + n), x, top + ph + 15);
      }
      ctx.textAlign = "left";
    }
    // Left margin: sweep numbers, then racking changes and transfers as
    // short ticks beside the plot, so the fabric stays what one sees first.
    ctx.fillStyle = "#5b6475";
    ctx.textAlign = "right";
    const stepS = niceStep((view.s1 - view.s0) / Math.max(ph / 50, 1));
    for (let s = Math.ceil(view.s0 / stepS) * stepS; s < view.s1; s += stepS) {
      const y = yOfSweep(s + 0.5);
      ctx.fillText(String(s + 1), M.left - 24, y + 4);
    }
    ctx.textAlign = "left";
    ctx.fillText("sweep", 4, top - 6);
    const perSweep = ph / (view.s1 - view.s0);
    const tickH = Math.max(1, Math.min(perSweep, 3));
    for (let s = si0; s < si1; ++s) {
      const flags = t.sweepFlags[s];
      if (!flags) continue;
      const y = yOfSweep(s + 1);
      if (flags & 1) {
        ctx.fillStyle = "#d13b3b";
        ctx.fillRect(M.left - 9, y, 7, tickH);
        if (perSweep >= 13) {
          ctx.font = "10px system-ui, sans-serif";
          ctx.fillText("r" + rackingOf(s), M.left - 10 - 26, y + 9);
          ctx.font = "11px system-ui, sans-serif";
        }
      }
      if (flags & 2) {
        ctx.fillStyle = "#7d8595";
        ctx.fillRect(M.left - 18, y, 6, tickH);
      }
    }
    // Right margin: the machine's warnings, then errors over them.
    const xr = panelX(1) + pw + 6;
    for (const severity of ["warning", "error"]) {
      ctx.fillStyle = severity === "error" ? "#d12f2f" : "#e88a1a";
      for (const d of t.diagnostics) {
        if (d.severity !== severity || d.sweep < view.s0 - 1 || d.sweep > view.s1) continue;
        const y = yOfSweep(d.sweep + 0.5);
        ctx.fillRect(xr, y - 1.5, 12, 3);
      }
    }
  }

  function niceStep(raw) {
    const p = Math.pow(10, Math.floor(Math.log10(Math.max(raw, 1))));
    for (const m of [1, 2, 5, 10]) if (m * p >= raw) return Math.max(1, m * p);
    return 10 * p;
  }

  function drawOverlay() {
    const ctx = overlay.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, cssW, cssH);
    const pw = panelWidth();
    if (S > 0 && current >= view.s0 - 1 && current <= view.s1) {
      const y0 = yOfSweep(current + 1);
      const y1 = yOfSweep(current);
      const h = Math.max(y1 - y0, 1);
      ctx.fillStyle = "rgba(47, 111, 214, 0.16)";
      for (let b = 0; b < 2; ++b) ctx.fillRect(panelX(b), y0, pw, h);
      ctx.fillStyle = "#2f6fd6";
      for (let b = 0; b < 2; ++b) {
        ctx.fillRect(panelX(b), y0 + h / 2 - 0.5, pw, 1);
      }
      ctx.beginPath();
      const ym = y0 + h / 2;
      ctx.moveTo(M.left - 1, ym);
      ctx.lineTo(M.left - 8 - 14, ym - 5);
      ctx.lineTo(M.left - 8 - 14, ym + 5);
      ctx.closePath();
      ctx.globalAlpha = 0.85;
      ctx.fill();
      ctx.globalAlpha = 1;
    }
    if (hover) {
      const x0 = xOfNeedle(hover.bed, hover.needle);
      const x1 = xOfNeedle(hover.bed, hover.needle + 1);
      const y0 = yOfSweep(hover.sweep + 1);
      const y1 = yOfSweep(hover.sweep);
      ctx.strokeStyle = "#1d2330";
      ctx.lineWidth = 1;
      if (x1 - x0 >= 3 && y1 - y0 >= 3) {
        ctx.strokeRect(x0 - 0.5, y0 - 0.5, x1 - x0 + 1, y1 - y0 + 1);
      } else {
        const xc = (x0 + x1) / 2;
        const yc = (y0 + y1) / 2;
        ctx.beginPath();
        ctx.moveTo(xc - 6, yc); ctx.lineTo(xc - 2, yc);
        ctx.moveTo(xc + 2, yc); ctx.lineTo(xc + 6, yc);
        ctx.moveTo(xc, yc - 6); ctx.lineTo(xc, yc - 2);
        ctx.moveTo(xc, yc + 2); ctx.lineTo(xc, yc + 6);
        ctx.stroke();
      }
    }
  }

  let pending = 0;
  let baseDirty = true;
  function redraw(all) {
    if (all) baseDirty = true;
    if (pending) return;
    pending = requestAnimationFrame(() => {
      pending = 0;
      if (baseDirty) drawBase();
      baseDirty = false;
      drawOverlay();
    });
  }
  // Draws at once (the tests read the canvas right after goToSweep).
  function drawNow() {
    if (pending) cancelAnimationFrame(pending);
    pending = 0;
    if (baseDirty) drawBase();
    baseDirty = false;
    drawOverlay();
  }

  function resize() {
    const w = stage.clientWidth;
    const h = stage.clientHeight;
    if (w === 0 || h === 0) return;
    dpr = window.devicePixelRatio || 1;
    cssW = w;
    cssH = h;
    for (const c of [base, overlay]) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(h * dpr);
      c.style.width = w + "px";
      c.style.height = h + "px";
    }
    baseDirty = true;
    drawNow();
  }

  // ------------------------------------------------------------ the current sweep
  function describeSweep() {
    if (S === 0) {
      sweepLabel.textContent = "no sweeps";
      info.textContent = "The program makes no carriage sweep.";
      return;
    }
    const s = current;
    const from = s > 0 ? t.sweepLast[s - 1] + 1 : 1;
    sweepLabel.textContent = "sweep " + wk.fmt(s + 1) + " of " + wk.fmt(S) + " · line " +
      wk.fmt(t.sweepFirst[s]);
    const facts = [
      "lines " + wk.fmt(from) + "–" + wk.fmt(t.sweepLast[s]),
      "racking " + rackingOf(s) + ((t.sweepFlags[s] & 1) ? " (changed)" : ""),
      "carrier " + carrierName(t.sweepCarrier[s]),
      t.sweepTransfers[s] ? wk.fmt(t.sweepTransfers[s]) + " transfer(s)" : null,
      wk.fmt(t.recordBegin[s + 1] - t.recordBegin[s]) + " needle change(s)",
    ].filter(Boolean);
    info.textContent = "";
    info.append(wk.el("div", { class: "bv-facts" }, facts.join(" · ")));
    const diags = t.diagnostics.filter((d) => d.sweep === s);
    for (const d of diags.slice(0, 10)) {
      info.append(wk.el("div", { class: "bv-" + d.severity },
        "line " + d.line + ": " + d.severity + ": [" + d.code + "] " + d.message));
    }
    if (lineStarts) {
      const first = t.sweepFirst[s];
      const last = Math.min(t.sweepLast[s], first + 5);
      const pre = wk.el("pre", { class: "bv-source" });
      for (let n = first; n <= last; ++n) {
        pre.append(wk.el("span", { class: "bv-lineno" }, String(n).padStart(7) + "  "), (lineText(n) ?? "") + "\n");
      }
      if (t.sweepLast[s] > last) pre.append(wk.el("span", { class: "wk-muted" }, "         … to line " + t.sweepLast[s]));
      info.append(pre);
    }
  }

  function goToSweep(i) {
    if (S === 0) return current;
    current = Math.max(0, Math.min(S - 1, Math.round(Number(i) || 0)));
    scrubber.value = String(current);
    // Keep the sweep in view.
    if (current < view.s0 || current + 1 > view.s1) {
      const span = view.s1 - view.s0;
      let s0 = current + 0.5 - span / 2;
      s0 = Math.max(0, Math.min(S - span, s0));
      view.s0 = s0;
      view.s1 = s0 + span;
      baseDirty = true;
    }
    describeSweep();
    drawNow();
    return current;
  }
  const step = (d) => goToSweep(current + d);

  // ------------------------------------------------------------ pointer and keys
  function describeHover(e) {
    const rect = stage.getBoundingClientRect();
    hover = hit(e.clientX - rect.left, e.clientY - rect.top);
    if (!hover) {
      hoverLine.textContent = "Point at a needle to see its source line.";
      hoverLine.classList.add("wk-muted");
      redraw(false);
      return;
    }
    hoverLine.classList.remove("wk-muted");
    const { bed, needle, sweep } = hover;
    const name = (bed === 0 ? "f" : "b") + (t.needleMin + needle);
    const rec = wk.bedRecordAt(t, needle * 2 + bed, sweep);
    let what = "empty";
    let line = 0;
    if (rec >= 0) {
      line = recordLine(rec);
      const count = t.recCount[rec];
      what = count === 0 ? "empty since line " + line
        : count + (count === 1 ? " loop" : " loops") + ", carrier " + carrierName(t.recCarrier[rec]) +
          ((t.recFlags[rec] & 1) ? ", moved here" : "") + ", line " + line;
    }
    hoverLine.textContent = "";
    hoverLine.append(wk.el("b", {}, name), " · sweep " + wk.fmt(sweep + 1) + " · " + what);
    const text = line ? lineText(line) : null;
    if (text !== null) hoverLine.append(wk.el("code", {}, text));
    redraw(false);
  }

  let drag = null;
  stage.addEventListener("mousedown", (e) => {
    if (e.button !== 0) return;
    drag = { x: e.clientX, y: e.clientY, v: { ...view }, moved: false };
    e.preventDefault();
    stage.focus();
  });
  const onMove = (e) => {
    if (drag) {
      const dx = e.clientX - drag.x;
      const dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
      if (drag.moved) {
        const dn = (-dx / panelWidth()) * (drag.v.n1 - drag.v.n0);
        const ds = (dy / plotHeight()) * (drag.v.s1 - drag.v.s0);
        setView(drag.v.n0 + dn, drag.v.n1 + dn, drag.v.s0 + ds, drag.v.s1 + ds);
      }
    }
    if (e.target === overlay || e.target === base) describeHover(e);
  };
  const onUp = (e) => {
    if (!drag) return;
    const moved = drag.moved;
    drag = null;
    if (!moved) {
      const rect = stage.getBoundingClientRect();
      const h = hit(e.clientX - rect.left, e.clientY - rect.top);
      if (h) goToSweep(h.sweep);
    }
  };
  window.addEventListener("mousemove", onMove);
  window.addEventListener("mouseup", onUp);
  stage.addEventListener("mouseleave", () => { hover = null; redraw(false); });
  stage.addEventListener("wheel", (e) => {
    e.preventDefault();
    const rect = stage.getBoundingClientRect();
    const x = e.clientX - rect.left;
    const y = e.clientY - rect.top;
    const f = Math.exp(Math.max(-300, Math.min(300, e.deltaY)) * 0.0022);
    const b = x >= panelX(1) ? 1 : 0;
    const an = view.n0 + ((x - panelX(b)) / panelWidth()) * (view.n1 - view.n0);
    const as = view.s0 + ((plotTop() + plotHeight() - y) / plotHeight()) * (view.s1 - view.s0);
    let { n0, n1, s0, s1 } = view;
    if (!e.altKey) { n0 = an + (n0 - an) * f; n1 = an + (n1 - an) * f; }
    if (!e.shiftKey) { s0 = as + (s0 - as) * f; s1 = as + (s1 - as) * f; }
    setView(n0, n1, s0, s1);
  }, { passive: false });
  stage.addEventListener("keydown", (e) => {
    const big = Math.max(1, Math.round((view.s1 - view.s0) / 10));
    const moves = { ArrowUp: 1, ArrowRight: 1, ArrowDown: -1, ArrowLeft: -1, PageUp: big, PageDown: -big };
    if (e.key in moves) step(moves[e.key]);
    else if (e.key === "Home") goToSweep(0);
    else if (e.key === "End") goToSweep(S - 1);
    else if (e.key === "0" || e.key === "Escape") resetZoom();
    else return;
    e.preventDefault();
  });
  scrubber.addEventListener("input", () => goToSweep(Number(scrubber.value)));
  resetButton.addEventListener("click", () => resetZoom());

  // The visible region, clamped to the bed and to at least 4 needles and sweeps.
  function setView(n0, n1, s0, s1) {
    const fit = (a, b, total) => {
      const span = Math.max(Math.min(4, total), Math.min(total, b - a));
      let lo = span === b - a ? a : (a + b) / 2 - span / 2;
      lo = Math.max(0, Math.min(total - span, lo));
      return [lo, lo + span];
    };
    [view.n0, view.n1] = fit(n0, n1, W);
    [view.s0, view.s1] = fit(s0, s1, Math.max(S, 1));
    redraw(true);
  }
  function resetZoom() {
    setView(0, W, 0, Math.max(S, 1));
  }

  let observer = null;
  if (typeof ResizeObserver !== "undefined") {
    observer = new ResizeObserver(() => resize());
    observer.observe(stage);
  } else {
    window.addEventListener("resize", resize);
  }
  resize();
  goToSweep(0);

  return {
    timeline: t,
    goToSweep,
    currentSweep: () => current,
    // The source line of the current sweep's first recorded change.
    currentLine: () => (S ? t.sweepFirst[current] : 0),
    currentSourceText: () => (S ? lineText(t.sweepFirst[current]) : null),
    sweeps: () => S,
    sweepLines: (s) => ({ first: t.sweepFirst[s], last: t.sweepLast[s] }),
    // The sweep whose lines hold line n (the last sweep past the end).
    sweepAt: (n) => {
      let lo = 0;
      let hi = S;
      while (lo < hi) {
        const mid = (lo + hi) >>> 1;
        if (t.sweepLast[mid] < n) lo = mid + 1;
        else hi = mid;
      }
      return Math.min(lo, S - 1);
    },
    // The state of needle `name` ("f12", "b3") at sweep s.
    needleAt: (name, s) => {
      const m = /^([fb])(-?\d+)$/.exec(name);
      if (!m) return null;
      const needle = Number(m[2]) - t.needleMin;
      if (needle < 0 || needle >= t.width) return { loops: 0, line: 0 };
      const rec = wk.bedRecordAt(t, needle * 2 + (m[1] === "b" ? 1 : 0), s);
      if (rec < 0) return { loops: 0, line: 0 };
      return { loops: t.recCount[rec], carrier: carrierName(t.recCarrier[rec]), line: recordLine(rec) };
    },
    lineText,
    view: () => ({ ...view }),
    setView,
    resetZoom,
    // Redraws everything now (the bench times it).
    redraw: () => { baseDirty = true; drawNow(); },
    destroy: () => {
      window.removeEventListener("mousemove", onMove);
      window.removeEventListener("mouseup", onUp);
      if (observer) observer.disconnect();
      else window.removeEventListener("resize", resize);
      container.textContent = "";
    },
  };
};
