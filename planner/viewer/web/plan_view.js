// The plan page (DIR/index.html, planner/viewer/plan_page.hpp): tabs for
// the garment in 3D, the pieces laid flat, the pieces' figures and bed views,
// and report.json; one seam selection shared by the 3D and flat views.
// window.wkPlan is the page's interface for tests and benches.
"use strict";

wk.FACE_TYPES = [
  ["knit", "#e9c46a"],
  ["increase", "#2a9d8f"],
  ["decrease", "#e76f51"],
  ["short-row", "#7b61c9"],
];

wk.start(async function main() {
  const meta = await wk.dataJson("plan");
  const blocks = {};
  const typed = { f32: Float32Array, u32: Uint32Array, u8: Uint8Array };
  for (const [id, info] of Object.entries(meta.blocks || {})) {
    const bytes = await wk.dataBytes(id);
    const T = typed[info.type];
    blocks[id] = new T(bytes.buffer, bytes.byteOffset, bytes.byteLength / T.BYTES_PER_ELEMENT);
  }
  const style = getComputedStyle(document.documentElement);
  const css = (name, fallback) => style.getPropertyValue(name).trim() || fallback;
  const sewCss = css("--sew", "#1f9d55"), laceCss = css("--lace", "#d64545");
  // A seam's colour: sew, lace, or grey before the wearability stage has labelled it.
  const seamCss = (s) => (s.labelled === false ? "#7a8191" : s.label === "lace" ? laceCss : sewCss);
  const seams = meta.seams || [];
  const pieces = meta.pieces || [];
  const report = meta.report || {};
  const plan = (meta.plan && meta.plan.plan) || report.plan || null;
  const seamWord = meta.seam_kind === "cut-arc" ? "cut-arc" : "seam";
  // A seam's name as the guide draws it: its number, and its part (4.2) for a seam in parts.
  const seamName = (s) => s.name || String(s.number);

  // ---- Layout ----------------------------------------------------------------
  const app = document.getElementById("app");
  const summary = [];
  if (meta.garment) summary.push(wk.fmt(meta.garment.faces) + " " + (meta.garment.kind === "stitch mesh" ? "stitches" : "faces"));
  if (pieces.length) summary.push(pieces.length + " piece" + (pieces.length === 1 ? "" : "s"));
  if (seams.length) {
    // A seam in parts (4.1, 4.2, ...) counts once.
    const whole = seams.filter((s) => !s.part || s.part[0] === 1);
    const open = whole.filter((s) => s.labelled === false).length;
    const laced = whole.filter((s) => s.labelled !== false && s.label === "lace").length;
    const sewn = whole.length - laced - open;
    summary.push(whole.length + " " + seamWord + "s (" + sewn + " sew, " + laced + " lace" + (open ? ", " + open + " not labelled: no wearability stage" : "") + ")");
  }
  app.append(wk.el("header", { class: "wk-top" },
    wk.el("h1", {}, "wearknit plan: " + meta.folder),
    wk.el("span", { class: "wk-sub" }, summary.join(" · "))));
  for (const n of meta.notes || []) app.append(wk.el("div", { class: "wk-note" }, n));
  const tabs = wk.el("nav", { class: "wk-tabs" });
  const panes = wk.el("main", { class: "plan-panes" });
  app.append(tabs, panes);
  const tabList = [];
  // Each tab also has an address: index.html#garment, #flat, #pieces, #report.
  const addTab = (name, key, pane, onShow) => {
    const button = wk.el("button", { type: "button" }, name);
    tabs.append(button);
    panes.append(pane);
    tabList.push({ name, key, button, pane, onShow });
    button.addEventListener("click", () => {
      history.replaceState(null, "", "#" + key);
      showTab(key);
    });
  };
  const showTab = (key) => {
    for (const t of tabList) {
      const on = t.key === key;
      t.button.classList.toggle("active", on);
      t.pane.hidden = !on;
      if (on && t.onShow) t.onShow();
    }
  };

  // The seam info panel, moved to the visible tab's side bar.
  const info = wk.el("div", { class: "wk-panel seam-info", id: "seam-info" },
    wk.el("div", { class: "wk-muted" }, seams.length ? "Hover or click a " + seamWord + " to see it here." : "No seams yet."));
  const seamList = wk.el("div", { class: "seam-list" });
  let selected = -1;

  // ---- 3D ---------------------------------------------------------------------
  const forceCanvas = new URLSearchParams(location.search).get("gl") === "0";
  const view3d = wk.el("div", { class: "view3d-box" });
  const side3d = wk.el("aside", { class: "plan-side" });
  const pane3d = wk.el("section", { class: "plan-pane plan-split" }, view3d, side3d);
  addTab("Garment in 3D", "garment", pane3d, () => {
    side3d.prepend(info);
    scene && scene.requestDraw();
  });
  let scene = null;
  const garmentColour = wk.rgb("#f2d48a");
  const wearerColour = wk.rgb("#9eadc6");
  let garmentMesh = null, wearerMesh = null;
  if (meta.garment || meta.wearer) {
    scene = new wk.Scene3D(view3d, { forceCanvas });
    const solid = (tri, rgb) => {
      const c = new Float32Array(tri.length);
      for (let i = 0; i < c.length; i += 3) c.set(rgb, i);
      return c;
    };
    if (meta.wearer) {
      const tri = blocks["wearer-tri"];
      wearerMesh = { name: "wearer", pos: blocks["wearer-pos"], tri, colours: solid(tri, wearerColour), visible: true, bias: 0 };
      scene.meshes.push(wearerMesh);
    }
    if (meta.garment) {
      const tri = blocks["garment-tri"];
      garmentMesh = { name: "garment", pos: blocks["garment-pos"], tri, colours: solid(tri, garmentColour), visible: true, bias: -1e-3 };
      garmentMesh.plain = garmentMesh.colours;
      if (blocks["garment-type"]) {
        const types = blocks["garment-type"];
        const c = new Float32Array(tri.length);
        const palette = wk.FACE_TYPES.map(([, hex]) => wk.rgb(hex));
        for (let t = 0; t < types.length; ++t) c.set(palette[types[t]] || garmentColour, 3 * t);
        garmentMesh.typed = c;
      }
      scene.meshes.push(garmentMesh);
      if (blocks["garment-edges"]) {
        const e = blocks["garment-edges"], pos = blocks["garment-pos"];
        const p = new Float32Array(e.length * 3);
        for (let i = 0; i < e.length; ++i) p.set(pos.subarray(3 * e[i], 3 * e[i] + 3), 3 * i);
        scene.lines = { pos: p, colour: wk.rgb("#6b5a3a"), visible: false };
      }
    }
    scene.seams = seams.map((s, i) => {
      const css = seamCss(s);
      return { index: i, colour: wk.rgb(css), css, segments: Float32Array.from(s.p3 || []) };
    });
    scene.labels = seams.filter((s) => s.at).map((s) => ({
      index: seams.indexOf(s), text: seamName(s), colour: seamCss(s),
      at: s.at.slice(0, 3), normal: s.at.slice(3, 6),
    }));
    scene.showSeams = true;
    scene.showLabels = true;
    scene.fit();
    scene.upload();
    listen3d(scene);
  } else {
    view3d.append(wk.el("p", { class: "wk-muted pad" }, "Nothing to draw yet: the folder has no cut."));
  }

  // Controls beside the 3D view.
  const controls = wk.el("div", { class: "wk-panel controls" });
  const checkbox = (label, checked, onChange) => {
    const input = wk.el("input", { type: "checkbox" });
    input.checked = checked;
    input.addEventListener("change", () => onChange(input.checked));
    return wk.el("label", {}, input, " " + label);
  };
  if (scene) {
    controls.append(wk.el("div", { class: "wk-muted" }, "Drag: rotate · right-drag or shift-drag: pan · wheel: zoom"));
    if (wearerMesh) controls.append(checkbox("wearer", true, (on) => { wearerMesh.visible = on; scene.requestDraw(); }));
    controls.append(checkbox("seams", true, (on) => { scene.showSeams = on; scene.requestDraw(); }));
    controls.append(checkbox("seam numbers", true, (on) => { scene.showLabels = on; scene.requestDraw(); }));
    if (garmentMesh && garmentMesh.typed) {
      const legend = wk.el("div", { class: "legend", hidden: "" }, ...wk.FACE_TYPES.map(([name, hex]) =>
        wk.el("span", {}, wk.el("i", { style: "background:" + hex }), name + " " +
          wk.fmt((meta.garment.face_types || {})[name]))));
      controls.append(checkbox("stitch mesh: face types", false, (on) => {
        garmentMesh.colours = on ? garmentMesh.typed : garmentMesh.plain;
        if (scene.gl) scene.uploadColours(garmentMesh);
        else scene.canvasColours(garmentMesh);
        if (scene.lines) scene.lines.visible = on;
        legend.hidden = !on;
        scene.requestDraw();
      }), legend);
    }
    controls.append(wk.el("div", { class: "wk-muted small" }, "renderer: " + scene.kind));
  }
  side3d.append(controls, seamList);

  function listen3d(s) {
    const canvas = s.overlay;
    const tip = wk.el("div", { class: "wk-tip", hidden: "" });
    document.body.append(tip);
    let drag = null;
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("mousedown", (e) => {
      drag = { x: e.clientX, y: e.clientY, moved: 0, pan: e.button === 2 || e.shiftKey };
    });
    window.addEventListener("mousemove", (e) => {
      if (drag) {
        const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
        drag.moved += Math.abs(dx) + Math.abs(dy);
        if (drag.pan) s.camera.pan(dx, dy, canvas.getBoundingClientRect().height);
        else s.camera.rotate(dx, dy);
        drag.x = e.clientX;
        drag.y = e.clientY;
        s.requestDraw();
        return;
      }
      if (e.target !== canvas) return;
      const hit = s.pick(e.clientX, e.clientY, 7);
      if (hit >= 0) {
        const seam = seams[hit];
        tip.textContent = seamTitle(seam) + "\n" + (seam.text || "");
        tip.style.left = e.clientX + 14 + "px";
        tip.style.top = e.clientY + 10 + "px";
        tip.hidden = false;
        canvas.style.cursor = "pointer";
      } else {
        tip.hidden = true;
        canvas.style.cursor = "";
      }
    });
    window.addEventListener("mouseup", (e) => {
      if (!drag) return;
      const click = drag.moved < 4;
      drag = null;
      if (!click || e.target !== canvas) return;
      const hit = s.pick(e.clientX, e.clientY, 8);
      if (hit >= 0) select(hit);
    });
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      s.camera.zoom(Math.exp(e.deltaY * 0.0012));
      s.requestDraw();
    }, { passive: false });
    window.addEventListener("resize", () => s.requestDraw());
  }

  // ---- Seams ------------------------------------------------------------------
  const seamTitle = (s) => (seamWord === "cut-arc" ? "cut-arc " : "seam ") + seamName(s) + ": " +
    (s.labelled === false ? "not labelled" : s.label);
  const listRows = seams.map((s, i) => {
    const row = wk.el("button", { type: "button", class: "seam-row " + s.label },
      wk.el("b", {}, seamName(s)), " " + (s.labelled === false ? "—" : s.label) + " · " +
      wk.fmt(s.length_mm, 0) + " mm" + (s.sides && s.sides.length ? " · piece " + s.sides[0].piece + " / " + s.sides[1].piece : ""));
    row.addEventListener("click", () => select(i, true));
    seamList.append(row);
    return row;
  });

  function describe(s) {
    const lines = [wk.el("h3", { class: s.label }, seamTitle(s))];
    if (s.text) lines.push(wk.el("div", { class: "mono" }, s.text));
    lines.push(wk.el("div", {}, "length " + wk.fmt(s.length_mm, 1) + " mm · " + s.kind +
      (s.part ? " part " + s.part[0] + " of " + s.part[1] : "")));
    if (s.sides && s.sides.length === 2) {
      const table = wk.el("table", { class: "wk-table" },
        wk.el("tr", {}, wk.el("th", {}, "side"), wk.el("th", {}, "piece"), wk.el("th", { class: "num" }, "stitch sides"),
          wk.el("th", {}, "needles"), wk.el("th", {}, "rows")));
      s.sides.forEach((side, k) => table.append(wk.el("tr", {},
        wk.el("td", {}, k === 0 ? "A" : "B"), wk.el("td", {}, "piece " + side.piece),
        wk.el("td", { class: "num" }, String(side.stitch_sides)),
        wk.el("td", {}, side.needles ? side.needles[0] + "–" + side.needles[1] : "—"),
        wk.el("td", {}, side.rows ? side.rows[0] + "–" + side.rows[1] : "—"))));
      lines.push(wk.el("div", {}, "joins piece " + s.sides[0].piece + " to piece " + s.sides[1].piece + ":"), table);
    }
    return lines;
  }

  function select(i, focus) {
    if (!(i >= 0 && i < seams.length)) i = -1;
    selected = i;
    info.replaceChildren(...(i >= 0 ? describe(seams[i]) : [wk.el("div", { class: "wk-muted" }, "No " + seamWord + " selected.")]));
    listRows.forEach((row, k) => row.classList.toggle("active", k === i));
    if (i >= 0 && listRows[i]) listRows[i].scrollIntoView({ block: "nearest" });
    if (scene) {
      scene.selected = i;
      if (focus && i >= 0) focusSeam(i);
      scene.requestDraw();
    }
    if (flat) {
      flat.selected = i;
      if (!flatPane.hidden) flat.draw();
    }
  }

  // Turns the camera so that seam i faces the viewer.
  function focusSeam(i) {
    const s = seams[i];
    if (!scene || !s || !s.at) return;
    const n = s.at.slice(3, 6);
    if (n[0] || n[1] || n[2]) scene.camera.face(s.at.slice(0, 3), n);
  }

  // ---- Flat pieces ------------------------------------------------------------
  const flatBox = wk.el("div", { class: "flat-box" });
  const sideFlat = wk.el("aside", { class: "plan-side" });
  const flatPane = wk.el("section", { class: "plan-pane plan-split" }, flatBox, sideFlat);
  let flat = null;
  if (blocks["flat-quads"] && pieces.length) {
    flat = new wk.FlatView(flatBox, pieces, blocks["flat-quads"], blocks["flat-edges"], seams, (i) => select(i));
    sideFlat.append(wk.el("div", { class: "wk-panel wk-muted" },
      "Pieces as they come off the machine: left to right the needles, bottom to top the rows, " +
      "in the stitch size of the gauge. Drag: pan · wheel: zoom · click a seam."));
  } else {
    flatBox.append(wk.el("p", { class: "wk-muted pad" }, "No pieces yet: the folder has no schedule."));
  }
  addTab("Pieces laid flat", "flat", flatPane, () => {
    sideFlat.prepend(info);
    if (flat) flat.draw();
  });

  // ---- Pieces -----------------------------------------------------------------
  const piecesPane = wk.el("section", { class: "plan-pane pad" });
  // The first piece's bed view is made when the tab is first shown.
  addTab("Pieces", "pieces", piecesPane, () => {
    if (!bedShown && pieces.length) bedShown = showBed(0);
  });
  const bedBox = wk.el("div", { class: "bed-box" });
  if (pieces.length) {
    const table = wk.el("table", { class: "wk-table pieces" },
      wk.el("tr", {}, ...["piece", "stitches", "rows", "passes", "needles", "transfers", "est. knit time", "knitout"].map(
        (h, k) => wk.el("th", { class: k && k < 7 ? "num" : "" }, h))));
    pieces.forEach((p, k) => {
      const f = p.figures || {};
      const row = wk.el("tr", { class: "clickable" },
        wk.el("td", {}, "piece " + p.number),
        wk.el("td", { class: "num" }, wk.fmt(f.stitches !== undefined ? f.stitches : p.stitches)),
        wk.el("td", { class: "num" }, wk.fmt(f.rows !== undefined ? f.rows : p.rows)),
        wk.el("td", { class: "num" }, wk.fmt(f.passes)),
        wk.el("td", { class: "num" }, wk.fmt(f.width_needles !== undefined ? f.width_needles : p.needles)),
        wk.el("td", { class: "num" }, wk.fmt(f.transfers)),
        wk.el("td", { class: "num" }, wk.duration(f.estimated_knit_time_s)),
        wk.el("td", { class: "mono" }, f.knitout || ""));
      row.addEventListener("click", () => showBed(k));
      table.append(row);
    });
    piecesPane.append(table, wk.el("h3", {}, "Bed view"), bedBox);
  } else {
    piecesPane.append(wk.el("p", { class: "wk-muted" }, "No pieces yet: the folder has no schedule."));
  }
  const bedUrls = {};
  let bedView = null;
  let bedShown = null;
  let showBed = async function (k) {
    const p = pieces[k];
    if (bedView) {
      bedView.destroy();
      bedView = null;
    }
    if (p.bed_timeline) {
      bedBox.replaceChildren(wk.el("div", { class: "wk-muted" }, "piece " + p.number + " on the needle bed (pieces/piece-" + p.number + ".k" + (p.bed_source ? "" : "; its source is not in the page, line numbers only") + ")"));
      const [bytes, source] = await Promise.all([wk.dataBytes(p.bed_timeline), p.bed_source ? wk.dataBytes(p.bed_source) : Promise.resolve(null)]);
      const box = wk.el("div", { class: "plan-bed" });
      bedBox.append(box);
      bedView = wk.mountBedView(box, bytes, source);
      window.wkPlanBedView = bedView;
      return;
    }
    bedBox.replaceChildren(wk.el("div", { class: "wk-muted" }, "piece " + p.number + " on the needle bed (pieces/piece-" + p.number + ".svg)"));
    if (!p.bed_svg) {
      bedBox.append(wk.el("p", { class: "wk-muted" }, "no bed view in the folder"));
      return;
    }
    if (!bedUrls[k]) {
      const bytes = await wk.dataBytes(p.bed_svg);
      bedUrls[k] = URL.createObjectURL(new Blob([bytes], { type: "image/svg+xml" }));
    }
    bedBox.append(wk.el("img", { src: bedUrls[k], alt: "piece " + p.number + " on the needle bed", class: "bed-img" }));
  }
  // Errors of an asynchronous bed view are shown on the page.
  const showBedReported = showBed;
  showBed = (k) => showBedReported(k).catch((error) => wk.showError("wearknit: bed view: " + (error && error.message ? error.message : error)));

  // ---- Report -----------------------------------------------------------------
  const reportPane = wk.el("section", { class: "plan-pane pad" });
  addTab("Report", "report", reportPane);
  if (plan && plan.stages) {
    const t = wk.el("table", { class: "wk-table" },
      wk.el("tr", {}, wk.el("th", {}, "stage"), wk.el("th", {}, "branch"), wk.el("th", { class: "num" }, "time"),
        wk.el("th", { class: "num" }, "exit"), wk.el("th", {}, "message")));
    for (const s of plan.stages) {
      t.append(wk.el("tr", {}, wk.el("td", {}, s.name), wk.el("td", {}, s.branch || ""),
        wk.el("td", { class: "num" }, wk.duration(s.time_s)), wk.el("td", { class: "num" }, String(s.exit)),
        wk.el("td", {}, s.message || "")));
    }
    if (plan.total_s !== undefined) t.append(wk.el("tr", {}, wk.el("th", {}, "total"), wk.el("td"), wk.el("th", { class: "num" }, wk.duration(plan.total_s))));
    reportPane.append(wk.el("h3", {}, "Stages"), t);
  }
  if (plan && plan.summary) reportPane.append(wk.el("h3", {}, "Summary"), figures(plan.summary));
  if (Object.keys(report).length) {
    reportPane.append(wk.el("h3", {}, "report.json"));
    for (const [key, value] of Object.entries(report)) {
      const d = wk.el("details", {}, wk.el("summary", {}, key));
      d.append(value !== null && typeof value === "object" ? figures(value) : wk.el("div", { class: "mono" }, JSON.stringify(value)));
      reportPane.append(d);
    }
  } else {
    reportPane.append(wk.el("p", { class: "wk-muted" }, "The folder has no report.json."));
  }
  function figures(object) {
    const t = wk.el("table", { class: "wk-table figures" });
    for (const [key, value] of Object.entries(object)) {
      let cell;
      if (value !== null && typeof value === "object") {
        const text = JSON.stringify(value);
        cell = text.length < 120 ? wk.el("span", { class: "mono" }, text) : wk.el("details", {}, wk.el("summary", {}, Array.isArray(value) ? value.length + " entries" : "…"), figures(value));
      } else {
        cell = typeof value === "number" ? (Number.isInteger(value) ? wk.fmt(value) : wk.fmt(value, 3)) : String(value);
      }
      t.append(wk.el("tr", {}, wk.el("th", {}, key), wk.el("td", {}, cell)));
    }
    return t;
  }

  const first = location.hash.slice(1);
  showTab(tabList.some((t) => t.key === first) ? first : "garment");
  if (scene) scene.draw();

  // ---- For tests and benches ---------------------------------------------------
  window.wkPlan = {
    selectSeam(n) {
      const i = seams.findIndex((s) => s.number === n);
      select(i, true);
      if (scene) scene.draw();
      return i >= 0;
    },
    selectedSeam: () => (selected >= 0 ? seams[selected].number : null),
    seamInfoText: () => info.textContent,
    seamScreenPoint(n) {
      const i = seams.findIndex((s) => s.number === n);
      if (i < 0 || !scene) return null;
      showTab("garment");
      scene.draw();
      let p = scene.seamPoint(i);
      if (!p) {
        focusSeam(i);
        scene.draw();
        p = scene.seamPoint(i);
      }
      return p;
    },
    renderer: () => (scene ? scene.kind : "none"),
    seams: () => seams.map((s) => ({ number: s.number, label: s.label })),
    frame() {
      if (!scene) return;
      scene.draw();
      if (scene.gl) scene.gl.finish();
    },
    // Frames per second while turning the garment `frames` steps.
    bench(frames) {
      if (!scene) return 0;
      const t0 = performance.now();
      for (let i = 0; i < (frames || 60); ++i) {
        scene.camera.rotate(6, 0);
        this.frame();
        if (scene.gl) scene.gl.readPixels(0, 0, 1, 1, scene.gl.RGBA, scene.gl.UNSIGNED_BYTE, new Uint8Array(4));
      }
      return ((frames || 60) * 1000) / (performance.now() - t0);
    },
  };
});
