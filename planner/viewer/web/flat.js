// The plan page's flat view: every piece laid flat as in the assembly guide
// (left to right the needles, bottom to top the rows, in the stitch size of
// the gauge), packed in shelves, with its open edges and its seams, the
// selected seam drawn thick on both its sides. Drag to pan, wheel to zoom,
// click a seam to select it.
"use strict";

wk.FlatView = class {
  // pieces: meta pieces ({number, width_mm, height_mm, quads: [first, n],
  // edges: [first, n]}); quads: Float32Array (4 corners x, y per stitch);
  // edges: Float32Array (x0 y0 x1 y1 per open edge); seams: meta seams.
  constructor(container, pieces, quads, edges, seams, onSelect) {
    this.container = container;
    this.canvas = wk.el("canvas", { class: "flat" });
    container.append(this.canvas);
    this.pieces = pieces;
    this.quads = quads;
    this.edges = edges;
    this.seams = seams;
    this.onSelect = onSelect;
    this.selected = -1;
    this.layOut();
    this.view = null;
    this.listen();
  }

  // Shelves about as wide as a square of all the pieces' area allows.
  layOut() {
    const gap = 12;
    let area = 0;
    for (const p of this.pieces) area += (p.width_mm + gap) * (p.height_mm + gap + 8);
    const rowWidth = Math.max(Math.sqrt(area) * 1.4, ...this.pieces.map((p) => p.width_mm));
    let x = 0, y = 0, shelf = 0;
    this.origin = [];
    for (const p of this.pieces) {
      if (x > 0 && x + p.width_mm > rowWidth) {
        x = 0;
        y += shelf + gap + 8;
        shelf = 0;
      }
      // Origin of the piece's (mm) frame: y grows upwards in the piece.
      this.origin.push([x + 1.5, y + 8 + p.height_mm]);
      x += p.width_mm + gap;
      shelf = Math.max(shelf, p.height_mm);
    }
    this.extent = [rowWidth, y + shelf + 8];
  }

  fitView(w, h) {
    const s = Math.min(w / (this.extent[0] + 20), h / (this.extent[1] + 20));
    this.view = { scale: s, x: 10 * s, y: 10 * s };
  }

  // Page coordinates (CSS pixels in the canvas) of point q of piece p.
  toScreen(p, qx, qy) {
    const o = this.origin[p - 1];
    return [this.view.x + (o[0] + qx) * this.view.scale, this.view.y + (o[1] - qy) * this.view.scale];
  }

  draw() {
    const rect = this.container.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(rect.width * dpr)), h = Math.max(1, Math.round(rect.height * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    if (!this.view) this.fitView(rect.width, rect.height);
    const ctx = this.canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, rect.width, rect.height);
    const style = getComputedStyle(document.documentElement);
    const sew = style.getPropertyValue("--sew").trim() || "#1f9d55";
    const lace = style.getPropertyValue("--lace").trim() || "#d64545";
    ctx.font = "bold 11px system-ui, sans-serif";
    for (const p of this.pieces) {
      const [tx, ty] = this.toScreen(p.number, 0, p.height_mm);
      ctx.fillStyle = "#1d2330";
      ctx.textBaseline = "bottom";
      ctx.textAlign = "left";
      ctx.fillText("piece " + p.number, tx, ty - 2);
      // Stitches.
      ctx.beginPath();
      const [first, count] = p.quads;
      for (let i = first; i < first + count; ++i) {
        for (let k = 0; k < 4; ++k) {
          const [x, y] = this.toScreen(p.number, this.quads[8 * i + 2 * k], this.quads[8 * i + 2 * k + 1]);
          if (k === 0) ctx.moveTo(x, y);
          else ctx.lineTo(x, y);
        }
        ctx.closePath();
      }
      ctx.fillStyle = "#f3e3b5";
      ctx.fill();
      if (this.view.scale > 3) {
        ctx.strokeStyle = "rgba(120, 100, 60, 0.35)";
        ctx.lineWidth = 0.5;
        ctx.stroke();
      }
      // Open edges.
      ctx.beginPath();
      const [e0, en] = p.edges;
      for (let i = e0; i < e0 + en; ++i) {
        const a = this.toScreen(p.number, this.edges[4 * i], this.edges[4 * i + 1]);
        const b = this.toScreen(p.number, this.edges[4 * i + 2], this.edges[4 * i + 3]);
        ctx.moveTo(a[0], a[1]);
        ctx.lineTo(b[0], b[1]);
      }
      ctx.strokeStyle = "#1d2330";
      ctx.lineWidth = 0.8;
      ctx.stroke();
    }
    // Seams, the selected one last and thick, with a halo.
    const order = this.seams.map((s, i) => i).sort((a, b) => (a === this.selected) - (b === this.selected));
    const numbers = [];
    for (const i of order) {
      const seam = this.seams[i];
      const on = i === this.selected;
      const colour = seam.labelled === false ? "#7a8191" : seam.label === "lace" ? lace : sew;
      for (const side of seam.sides) {
        const f = side.flat;
        if (!f.length) continue;
        const path = () => {
          ctx.beginPath();
          for (let k = 0; k < f.length; k += 5) {
            const a = this.toScreen(f[k], f[k + 1], f[k + 2]);
            const b = this.toScreen(f[k], f[k + 3], f[k + 4]);
            ctx.moveTo(a[0], a[1]);
            ctx.lineTo(b[0], b[1]);
          }
        };
        ctx.setLineDash(seam.label === "lace" && !on ? [5, 3] : []);
        if (on) {
          path();
          ctx.strokeStyle = "rgba(47, 111, 214, 0.35)";
          ctx.lineWidth = 10;
          ctx.lineCap = "round";
          ctx.stroke();
        }
        path();
        ctx.strokeStyle = colour;
        ctx.lineWidth = on ? 4 : 2;
        ctx.stroke();
        ctx.setLineDash([]);
        // The number at the middle of the stretch.
        const k = 5 * Math.floor(f.length / 10);
        const m = this.toScreen(f[k], (f[k + 1] + f[k + 3]) / 2, (f[k + 2] + f[k + 4]) / 2);
        numbers.push({ x: m[0], y: m[1], text: seam.name || String(seam.number), colour, on });
      }
    }
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    const placed = [];
    for (const n of numbers) {
      const r = n.text.length > 2 ? 9 : 7.5;
      if (!n.on && placed.some((q) => Math.hypot(q[0] - n.x, q[1] - n.y) < r * 1.6)) continue;
      placed.push([n.x, n.y]);
      ctx.beginPath();
      ctx.arc(n.x, n.y, n.on ? r + 2 : r, 0, 2 * Math.PI);
      ctx.fillStyle = n.on ? n.colour : "#fff";
      ctx.fill();
      ctx.strokeStyle = n.colour;
      ctx.lineWidth = 1.3;
      ctx.stroke();
      ctx.fillStyle = n.on ? "#fff" : n.colour;
      ctx.fillText(n.text, n.x, n.y + 0.5);
    }
  }

  // The seam index nearest to canvas point (x, y) within `tolerance` pixels, or -1.
  pick(x, y, tolerance) {
    let best = -1, bestD = tolerance;
    this.seams.forEach((seam, i) => {
      for (const side of seam.sides) {
        const f = side.flat;
        for (let k = 0; k < f.length; k += 5) {
          const a = this.toScreen(f[k], f[k + 1], f[k + 2]);
          const b = this.toScreen(f[k], f[k + 3], f[k + 4]);
          const d = wk.segmentDistance(x, y, a[0], a[1], b[0], b[1]);
          if (d < bestD) {
            bestD = d;
            best = i;
          }
        }
      }
    });
    return best;
  }

  listen() {
    let drag = null;
    this.canvas.addEventListener("mousedown", (e) => {
      drag = { x: e.clientX, y: e.clientY, moved: 0 };
    });
    window.addEventListener("mousemove", (e) => {
      if (!drag || !this.view) return;
      this.view.x += e.clientX - drag.x;
      this.view.y += e.clientY - drag.y;
      drag.moved += Math.abs(e.clientX - drag.x) + Math.abs(e.clientY - drag.y);
      drag.x = e.clientX;
      drag.y = e.clientY;
      this.draw();
    });
    window.addEventListener("mouseup", (e) => {
      if (!drag) return;
      const click = drag.moved < 4;
      drag = null;
      if (!click) return;
      const rect = this.canvas.getBoundingClientRect();
      const hit = this.pick(e.clientX - rect.left, e.clientY - rect.top, 8);
      if (hit >= 0) this.onSelect(hit);
    });
    this.canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      if (!this.view) return;
      const rect = this.canvas.getBoundingClientRect();
      const mx = e.clientX - rect.left, my = e.clientY - rect.top;
      const f = Math.exp(-e.deltaY * 0.0015);
      this.view.x = mx - (mx - this.view.x) * f;
      this.view.y = my - (my - this.view.y) * f;
      this.view.scale *= f;
      this.draw();
    }, { passive: false });
  }
};
