// The plan page's 3D view: the garment on its wearer with its seams, drawn
// with WebGL (own shaders, an orbit camera) or, where the browser has no
// WebGL or the page's URL has ?gl=0, on a 2D canvas in painter's order over a
// decimated copy of the meshes. y is up, as in the planner's pictures.
"use strict";

wk.mat4 = {
  multiply(a, b) {
    const o = new Float32Array(16);
    for (let c = 0; c < 4; ++c) {
      for (let r = 0; r < 4; ++r) {
        let s = 0;
        for (let k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
        o[c * 4 + r] = s;
      }
    }
    return o;
  },
  perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2);
    const o = new Float32Array(16);
    o[0] = f / aspect;
    o[5] = f;
    o[10] = (far + near) / (near - far);
    o[11] = -1;
    o[14] = (2 * far * near) / (near - far);
    return o;
  },
  lookAt(eye, target, up) {
    const z = wk.vec3.normalize(wk.vec3.sub(eye, target));
    const x = wk.vec3.normalize(wk.vec3.cross(up, z));
    const y = wk.vec3.cross(z, x);
    return new Float32Array([
      x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -wk.vec3.dot(x, eye), -wk.vec3.dot(y, eye), -wk.vec3.dot(z, eye), 1,
    ]);
  },
};

wk.vec3 = {
  sub: (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
  add: (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
  scale: (a, s) => [a[0] * s, a[1] * s, a[2] * s],
  dot: (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2],
  cross: (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]],
  normalize(a) {
    const l = Math.hypot(a[0], a[1], a[2]) || 1;
    return [a[0] / l, a[1] / l, a[2] / l];
  },
};

// Colours as [r, g, b] in 0..1 from "#rrggbb".
wk.rgb = function (hex) {
  const v = parseInt(hex.slice(1), 16);
  return [((v >> 16) & 255) / 255, ((v >> 8) & 255) / 255, (v & 255) / 255];
};

// Per-vertex normals (area-weighted) of an indexed triangle mesh.
wk.vertexNormals = function (pos, tri) {
  const n = new Float32Array(pos.length);
  for (let t = 0; t < tri.length; t += 3) {
    const a = tri[t] * 3, b = tri[t + 1] * 3, c = tri[t + 2] * 3;
    const ux = pos[b] - pos[a], uy = pos[b + 1] - pos[a + 1], uz = pos[b + 2] - pos[a + 2];
    const vx = pos[c] - pos[a], vy = pos[c + 1] - pos[a + 1], vz = pos[c + 2] - pos[a + 2];
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (const i of [a, b, c]) {
      n[i] += nx;
      n[i + 1] += ny;
      n[i + 2] += nz;
    }
  }
  for (let i = 0; i < n.length; i += 3) {
    const l = Math.hypot(n[i], n[i + 1], n[i + 2]) || 1;
    n[i] /= l;
    n[i + 1] /= l;
    n[i + 2] /= l;
  }
  return n;
};

// Vertex clustering: the mesh's vertices snapped to a grid fine enough to
// keep at most `target` triangles; degenerate and repeated triangles dropped.
// Returns {pos, tri, map} (map: triangle -> a triangle of the input).
wk.decimate = function (pos, tri, target) {
  if (tri.length / 3 <= target) return { pos, tri, map: null };
  let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < pos.length; i += 3) {
    for (let k = 0; k < 3; ++k) {
      lo[k] = Math.min(lo[k], pos[i + k]);
      hi[k] = Math.max(hi[k], pos[i + k]);
    }
  }
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  let grid = Math.max(8, Math.round(Math.sqrt(target) * 1.2));
  for (;;) {
    const cell = size / grid;
    const ids = new Map();
    const sums = [];
    const vertexCell = new Int32Array(pos.length / 3);
    for (let v = 0; v < pos.length / 3; ++v) {
      const key = Math.floor((pos[3 * v] - lo[0]) / cell) +
        (grid + 1) * (Math.floor((pos[3 * v + 1] - lo[1]) / cell) +
        (grid + 1) * Math.floor((pos[3 * v + 2] - lo[2]) / cell));
      let id = ids.get(key);
      if (id === undefined) {
        id = sums.length / 4;
        ids.set(key, id);
        sums.push(0, 0, 0, 0);
      }
      vertexCell[v] = id;
      sums[4 * id] += pos[3 * v];
      sums[4 * id + 1] += pos[3 * v + 1];
      sums[4 * id + 2] += pos[3 * v + 2];
      sums[4 * id + 3] += 1;
    }
    const out = [];
    const map = [];
    const seen = new Set();
    for (let t = 0; t < tri.length; t += 3) {
      const a = vertexCell[tri[t]], b = vertexCell[tri[t + 1]], c = vertexCell[tri[t + 2]];
      if (a === b || b === c || a === c) continue;
      const key = [a, b, c].sort((x, y) => x - y).join(",");
      if (seen.has(key)) continue;
      seen.add(key);
      out.push(a, b, c);
      map.push(t / 3);
    }
    if (out.length / 3 <= target || grid <= 8) {
      const p = new Float32Array(sums.length / 4 * 3);
      for (let i = 0; i < sums.length / 4; ++i) {
        for (let k = 0; k < 3; ++k) p[3 * i + k] = sums[4 * i + k] / sums[4 * i + 3];
      }
      return { pos: p, tri: Uint32Array.from(out), map: Int32Array.from(map) };
    }
    grid = Math.max(8, Math.floor(grid * 0.75));
  }
};

// An orbit camera around `target`: yaw about y, pitch about x, distance.
wk.OrbitCamera = class {
  constructor(centre, radius) {
    this.target = centre.slice();
    this.radius = radius;
    this.distance = radius * 3.2;
    this.yaw = 0.5;
    this.pitch = 0.35;
    this.fovy = (35 * Math.PI) / 180;
  }
  eye() {
    const cp = Math.cos(this.pitch);
    return wk.vec3.add(this.target, wk.vec3.scale(
      [cp * Math.sin(this.yaw), Math.sin(this.pitch), cp * Math.cos(this.yaw)], this.distance));
  }
  rotate(dx, dy) {
    this.yaw -= dx * 0.01;
    this.pitch = Math.max(-1.5, Math.min(1.5, this.pitch + dy * 0.01));
  }
  zoom(factor) {
    this.distance = Math.max(this.radius * 0.05, Math.min(this.radius * 40, this.distance * factor));
  }
  // Moves the target by a drag of (dx, dy) pixels of a view `height` pixels high.
  pan(dx, dy, height) {
    const view = wk.mat4.lookAt(this.eye(), this.target, [0, 1, 0]);
    const right = [view[0], view[4], view[8]];
    const up = [view[1], view[5], view[9]];
    const perPixel = (2 * this.distance * Math.tan(this.fovy / 2)) / height;
    this.target = wk.vec3.add(this.target, wk.vec3.add(
      wk.vec3.scale(right, -dx * perPixel), wk.vec3.scale(up, dy * perPixel)));
  }
  // Looks at `point` from the side `normal` points to.
  face(point, normal) {
    const n = wk.vec3.normalize(normal);
    if (Math.hypot(normal[0], normal[1], normal[2]) < 1e-6) return;
    this.yaw = Math.atan2(n[0], n[2]);
    this.pitch = Math.max(-1.2, Math.min(1.2, Math.asin(Math.max(-1, Math.min(1, n[1])))));
  }
  matrices(width, height) {
    const eye = this.eye();
    const near = Math.max(this.distance - this.radius * 2, this.distance * 0.02);
    const far = this.distance + this.radius * 3;
    const proj = wk.mat4.perspective(this.fovy, width / Math.max(1, height), near, far);
    const view = wk.mat4.lookAt(eye, this.target, [0, 1, 0]);
    return { eye, mvp: wk.mat4.multiply(proj, view) };
  }
};

// The scene: meshes {pos, tri, colour(s)}, seam segments, and the renderer.
// meshes: [{name, pos: Float32Array, tri: Uint32Array, colours: Float32Array
// per triangle (r, g, b), visible}]; seams: [{index, colour, segments:
// Float32Array (ax ay az bx by bz nx ny nz)*}].
wk.Scene3D = class {
  constructor(container, options) {
    this.container = container;
    this.canvas = wk.el("canvas", { class: "view3d" });
    this.overlay = wk.el("canvas", { class: "view3d-overlay" });
    container.append(this.canvas, this.overlay);
    this.meshes = [];
    this.lines = null;  // {pos: Float32Array pairs, colour, visible}
    this.seams = [];
    this.labels = [];  // {text, colour, at: [x y z], normal: [x y z], index}
    this.selected = -1;
    this.seamWidth = 3;
    this.gl = null;
    if (!options.forceCanvas) {
      this.gl = wk.glContext(this.canvas, true);
      // A software renderer (no GPU) multisamples on the CPU, several times
      // slower: there the canvas gets a context without antialiasing.
      const info = this.gl && this.gl.getExtension("WEBGL_debug_renderer_info");
      const renderer = info ? String(this.gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
      if (/swiftshader|llvmpipe|software/i.test(renderer)) {
        this.canvas.remove();
        this.canvas = wk.el("canvas", { class: "view3d" });
        container.prepend(this.canvas);
        this.gl = wk.glContext(this.canvas, false);
      }
      this.glRenderer = renderer;
    }
    this.kind = this.gl ? "webgl" : "canvas";
    // Drawn on the CPU: many small paths are slower through a software GPU.
    if (!this.gl) this.ctx = this.canvas.getContext("2d", { willReadFrequently: true });
    this.pending = false;
  }

  // Sets the camera around the meshes' bounding box.
  fit() {
    let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const m of this.meshes) {
      for (let i = 0; i < m.pos.length; i += 3) {
        for (let k = 0; k < 3; ++k) {
          lo[k] = Math.min(lo[k], m.pos[i + k]);
          hi[k] = Math.max(hi[k], m.pos[i + k]);
        }
      }
    }
    if (!Number.isFinite(lo[0])) lo = [-1, -1, -1], hi = [1, 1, 1];
    const centre = wk.vec3.scale(wk.vec3.add(lo, hi), 0.5);
    const radius = Math.max(1e-3, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
    this.camera = new wk.OrbitCamera(centre, radius);
  }

  upload() {
    if (this.gl) this.uploadGl();
    else this.prepareCanvas();
  }

  size() {
    const rect = this.container.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(rect.width * dpr)), h = Math.max(1, Math.round(rect.height * dpr));
    for (const c of [this.canvas, this.overlay]) {
      if (c.width !== w || c.height !== h) {
        c.width = w;
        c.height = h;
      }
    }
    return { w, h, dpr, rect };
  }

  // Draws on the next animation frame (several requests, one frame).
  requestDraw() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.draw();
    });
  }

  draw() {
    const s = this.size();
    this.rect = s.rect;
    this.frameMatrices = this.camera.matrices(s.w, s.h);
    if (this.gl) this.drawGl(s);
    else this.drawCanvas(s);
    this.drawLabels(s);
  }

  // Client coordinates of world point p, with its clip w (w <= 0: behind).
  project(p) {
    const m = this.frameMatrices.mvp;
    const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    const z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
    const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    const rect = this.rect || this.canvas.getBoundingClientRect();
    return {
      x: rect.left + ((x / w + 1) / 2) * rect.width,
      y: rect.top + ((1 - y / w) / 2) * rect.height,
      z: z / w,
      w,
    };
  }

  // A point with normal n at p faces the eye (a zero normal always does).
  facing(p, n) {
    if (n[0] === 0 && n[1] === 0 && n[2] === 0) return true;
    const e = this.frameMatrices.eye;
    return (e[0] - p[0]) * n[0] + (e[1] - p[1]) * n[1] + (e[2] - p[2]) * n[2] > 0;
  }

  // The seam index nearest to client point (x, y) within `tolerance` pixels,
  // on a segment that faces the viewer, or -1.
  pick(x, y, tolerance) {
    if (!this.frameMatrices) return -1;
    let best = -1, bestD = tolerance;
    for (const seam of this.seams) {
      const s = seam.segments;
      for (let i = 0; i < s.length; i += 9) {
        const a = [s[i], s[i + 1], s[i + 2]], b = [s[i + 3], s[i + 4], s[i + 5]];
        if (!this.facing(a, [s[i + 6], s[i + 7], s[i + 8]])) continue;
        const pa = this.project(a), pb = this.project(b);
        if (pa.w <= 0 || pb.w <= 0) continue;
        const d = wk.segmentDistance(x, y, pa.x, pa.y, pb.x, pb.y);
        if (d < bestD) {
          bestD = d;
          best = seam.index;
        }
      }
    }
    return best;
  }

  // A client point on seam `index` facing the viewer (the middle of its
  // middle facing segment), or null.
  seamPoint(index) {
    const seam = this.seams.find((s) => s.index === index);
    if (!seam || !this.frameMatrices) return null;
    const s = seam.segments;
    const facing = [];
    for (let i = 0; i < s.length; i += 9) {
      const a = [s[i], s[i + 1], s[i + 2]], b = [s[i + 3], s[i + 4], s[i + 5]];
      if (this.facing(a, [s[i + 6], s[i + 7], s[i + 8]])) facing.push(i);
    }
    if (!facing.length) return null;
    const i = facing[Math.floor(facing.length / 2)];
    const p = this.project([(s[i] + s[i + 3]) / 2, (s[i + 1] + s[i + 4]) / 2, (s[i + 2] + s[i + 5]) / 2]);
    const rect = this.canvas.getBoundingClientRect();
    if (p.w <= 0 || p.x < rect.left || p.y < rect.top || p.x > rect.right || p.y > rect.bottom) return null;
    return { x: p.x, y: p.y };
  }

  drawLabels(s) {
    const ctx = this.overlay.getContext("2d");
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.overlay.width, this.overlay.height);
    if (!this.showLabels) return;
    ctx.scale(s.dpr, s.dpr);
    ctx.font = "bold 11px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    const rect = this.canvas.getBoundingClientRect();
    const placed = [];
    // The selected seam's number last, on top.
    const order = this.labels.slice().sort((a, b) => (a.index === this.selected) - (b.index === this.selected));
    for (const label of order) {
      if (!this.facing(label.at, label.normal)) continue;
      const p = this.project(label.at);
      if (p.w <= 0) continue;
      const x = p.x - rect.left, y = p.y - rect.top;
      const r = label.text.length > 2 ? 9 : 7.5;
      const selected = label.index === this.selected;
      if (!selected && placed.some((q) => Math.hypot(q[0] - x, q[1] - y) < r * 1.6)) continue;
      placed.push([x, y]);
      ctx.beginPath();
      ctx.arc(x, y, selected ? r + 2 : r, 0, 2 * Math.PI);
      ctx.fillStyle = selected ? label.colour : "#fff";
      ctx.fill();
      ctx.lineWidth = 1.3;
      ctx.strokeStyle = label.colour;
      ctx.stroke();
      ctx.fillStyle = selected ? "#fff" : label.colour;
      ctx.fillText(label.text, x, y + 0.5);
    }
  }

  // ---- WebGL ----------------------------------------------------------------

  program(vertexSource, fragmentSource) {
    const gl = this.gl;
    const compile = (type, source) => {
      const shader = gl.createShader(type);
      gl.shaderSource(shader, source);
      gl.compileShader(shader);
      if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
      return shader;
    };
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vertexSource));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fragmentSource));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    return p;
  }

  buffer(data) {
    const gl = this.gl;
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return b;
  }

  uploadGl() {
    const gl = this.gl;
    if (!this.surfaceProgram) {
      this.surfaceProgram = this.program(
        `attribute vec3 position; attribute vec3 normal; attribute vec3 colour;
         uniform mat4 mvp; uniform vec3 eye; varying vec3 v_colour; varying vec3 v_normal; varying vec3 v_to_eye;
         void main() { v_colour = colour; v_normal = normal; v_to_eye = eye - position;
           gl_Position = mvp * vec4(position, 1.0); }`,
        `precision mediump float; varying vec3 v_colour; varying vec3 v_normal; varying vec3 v_to_eye;
         void main() { float d = abs(dot(normalize(v_normal), normalize(v_to_eye)));
           gl_FragColor = vec4(v_colour * (0.38 + 0.62 * d), 1.0); }`);
      this.lineProgram = this.program(
        `attribute vec3 position; uniform mat4 mvp;
         void main() { gl_Position = mvp * vec4(position, 1.0); gl_Position.z -= 0.0004 * gl_Position.w; }`,
        `precision mediump float; uniform vec3 colour; void main() { gl_FragColor = vec4(colour, 1.0); }`);
      this.seamProgram = this.program(
        `attribute vec3 a; attribute vec3 b; attribute float side; attribute vec3 colour; attribute float seam;
         uniform mat4 mvp; uniform vec2 viewport; uniform float width; uniform float selected;
         varying vec3 v_colour;
         void main() {
           vec4 ca = mvp * vec4(a, 1.0); vec4 cb = mvp * vec4(b, 1.0);
           vec2 sa = ca.xy / ca.w * viewport * 0.5; vec2 sb = cb.xy / cb.w * viewport * 0.5;
           vec2 d = sb - sa; if (dot(d, d) < 1e-6) d = vec2(1.0, 0.0);
           d = normalize(d);
           bool on = abs(seam - selected) < 0.5;
           float w = on ? width * 2.2 : width;
           ca.xy += vec2(-d.y, d.x) * side * w / (viewport * 0.5) * ca.w;
           ca.z -= (on ? 0.004 : 0.002) * ca.w;
           v_colour = colour;
           gl_Position = ca; }`,
        `precision mediump float; varying vec3 v_colour; void main() { gl_FragColor = vec4(v_colour, 1.0); }`);
    }
    for (const m of this.meshes) {
      // Expanded per triangle corner, so that a face's colour is its own.
      const n = wk.vertexNormals(m.pos, m.tri);
      const count = m.tri.length;
      const p = new Float32Array(count * 3), nn = new Float32Array(count * 3);
      for (let i = 0; i < count; ++i) {
        const v = m.tri[i] * 3;
        p[3 * i] = m.pos[v];
        p[3 * i + 1] = m.pos[v + 1];
        p[3 * i + 2] = m.pos[v + 2];
        nn[3 * i] = n[v];
        nn[3 * i + 1] = n[v + 1];
        nn[3 * i + 2] = n[v + 2];
      }
      m.gl = { position: this.buffer(p), normal: this.buffer(nn), count };
      this.uploadColours(m);
    }
    if (this.lines) this.lines.gl = { position: this.buffer(this.lines.pos), count: this.lines.pos.length / 3 };
    this.uploadSeams();
  }

  // A mesh's triangle colours, after they changed.
  uploadColours(m) {
    if (!this.gl) return;
    const count = m.tri.length;
    const c = new Float32Array(count * 3);
    for (let t = 0; t < count / 3; ++t) {
      for (let k = 0; k < 3; ++k) {
        c[9 * t + 3 * k] = m.colours[3 * t];
        c[9 * t + 3 * k + 1] = m.colours[3 * t + 1];
        c[9 * t + 3 * k + 2] = m.colours[3 * t + 2];
      }
    }
    if (m.gl.colour) this.gl.deleteBuffer(m.gl.colour);
    m.gl.colour = this.buffer(c);
  }

  uploadSeams() {
    let count = 0;
    for (const seam of this.seams) count += (seam.segments.length / 9) * 6;
    const a = new Float32Array(count * 3), b = new Float32Array(count * 3);
    const side = new Float32Array(count), colour = new Float32Array(count * 3), id = new Float32Array(count);
    let v = 0;
    for (const seam of this.seams) {
      const s = seam.segments;
      for (let i = 0; i < s.length; i += 9) {
        // Two triangles over the segment, widened on screen by the shader.
        const ends = [[0, 3, 1], [0, 3, -1], [3, 0, -1], [0, 3, -1], [3, 0, 1], [3, 0, -1]];
        for (const [from, to, sign] of ends) {
          for (let k = 0; k < 3; ++k) {
            a[3 * v + k] = s[i + from + k];
            b[3 * v + k] = s[i + to + k];
            colour[3 * v + k] = seam.colour[k];
          }
          side[v] = sign;
          id[v] = seam.index;
          ++v;
        }
      }
    }
    this.seamGl = {
      a: this.buffer(a), b: this.buffer(b), side: this.buffer(side), colour: this.buffer(colour),
      seam: this.buffer(id), count,
    };
  }

  attribute(program, name, buffer, size) {
    const gl = this.gl;
    const location = gl.getAttribLocation(program, name);
    if (location < 0) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
  }

  drawGl(s) {
    const gl = this.gl;
    const { eye, mvp } = this.frameMatrices;
    gl.viewport(0, 0, s.w, s.h);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const maxAttributes = gl.getParameter(gl.MAX_VERTEX_ATTRIBS);
    const reset = () => {
      for (let i = 0; i < Math.min(8, maxAttributes); ++i) gl.disableVertexAttribArray(i);
    };
    gl.useProgram(this.surfaceProgram);
    gl.uniformMatrix4fv(gl.getUniformLocation(this.surfaceProgram, "mvp"), false, mvp);
    gl.uniform3fv(gl.getUniformLocation(this.surfaceProgram, "eye"), eye);
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    for (const m of this.meshes) {
      if (!m.visible) continue;
      // The wearer is pushed further back than the garment, so that a
      // garment lying on its wearer stays in front of it (as in assembly-3d.png).
      if (m.name === "wearer") gl.polygonOffset(4, 16);
      else gl.polygonOffset(1, 1);
      reset();
      this.attribute(this.surfaceProgram, "position", m.gl.position, 3);
      this.attribute(this.surfaceProgram, "normal", m.gl.normal, 3);
      this.attribute(this.surfaceProgram, "colour", m.gl.colour, 3);
      gl.drawArrays(gl.TRIANGLES, 0, m.gl.count);
    }
    gl.disable(gl.POLYGON_OFFSET_FILL);
    if (this.lines && this.lines.visible) {
      reset();
      gl.useProgram(this.lineProgram);
      gl.uniformMatrix4fv(gl.getUniformLocation(this.lineProgram, "mvp"), false, mvp);
      gl.uniform3fv(gl.getUniformLocation(this.lineProgram, "colour"), this.lines.colour);
      this.attribute(this.lineProgram, "position", this.lines.gl.position, 3);
      gl.drawArrays(gl.LINES, 0, this.lines.gl.count);
    }
    if (this.seamGl.count && this.showSeams) {
      reset();
      const p = this.seamProgram;
      gl.useProgram(p);
      gl.uniformMatrix4fv(gl.getUniformLocation(p, "mvp"), false, mvp);
      gl.uniform2f(gl.getUniformLocation(p, "viewport"), s.w, s.h);
      gl.uniform1f(gl.getUniformLocation(p, "width"), (this.seamWidth * s.dpr) / 2);
      gl.uniform1f(gl.getUniformLocation(p, "selected"), this.selected);
      this.attribute(p, "a", this.seamGl.a, 3);
      this.attribute(p, "b", this.seamGl.b, 3);
      this.attribute(p, "side", this.seamGl.side, 1);
      this.attribute(p, "colour", this.seamGl.colour, 3);
      this.attribute(p, "seam", this.seamGl.seam, 1);
      gl.drawArrays(gl.TRIANGLES, 0, this.seamGl.count);
    }
    reset();
  }

  // ---- 2D canvas --------------------------------------------------------------

  prepareCanvas() {
    // At most about 16,000 triangles in all, shared by the visible meshes:
    // a software-drawn canvas fills some 20,000 small paths a second.
    const total = this.meshes.reduce((n, m) => n + m.tri.length / 3, 0);
    for (const m of this.meshes) {
      const share = Math.max(2000, Math.round((16000 * (m.tri.length / 3)) / Math.max(1, total)));
      m.flat = wk.decimate(m.pos, m.tri, share);
      this.canvasColours(m);
    }
  }

  canvasColours(m) {
    if (!m.flat) return;
    const map = m.flat.map;
    const c = new Float32Array(m.flat.tri.length);
    for (let t = 0; t < m.flat.tri.length / 3; ++t) {
      const source = map ? map[t] : t;
      for (let k = 0; k < 3; ++k) c[3 * t + k] = m.colours[3 * source + k];
    }
    m.flat.colours = c;
  }

  drawCanvas(s) {
    const ctx = this.ctx;
    const { eye, mvp } = this.frameMatrices;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, s.w, s.h);
    const faces = [];
    for (const m of this.meshes) {
      if (!m.visible) continue;
      const { pos, tri, colours } = m.flat;
      const n = pos.length / 3;
      const sx = new Float32Array(n), sy = new Float32Array(n), sz = new Float32Array(n);
      for (let v = 0; v < n; ++v) {
        const x = pos[3 * v], y = pos[3 * v + 1], z = pos[3 * v + 2];
        const w = mvp[3] * x + mvp[7] * y + mvp[11] * z + mvp[15];
        sx[v] = ((mvp[0] * x + mvp[4] * y + mvp[8] * z + mvp[12]) / w + 1) * 0.5 * s.w;
        sy[v] = (1 - (mvp[1] * x + mvp[5] * y + mvp[9] * z + mvp[13]) / w) * 0.5 * s.h;
        sz[v] = w;
      }
      for (let t = 0; t < tri.length; t += 3) {
        const a = tri[t], b = tri[t + 1], c = tri[t + 2];
        if (sz[a] <= 0 || sz[b] <= 0 || sz[c] <= 0) continue;
        // Flat shading by the face's normal towards the eye.
        const ux = pos[3 * b] - pos[3 * a], uy = pos[3 * b + 1] - pos[3 * a + 1], uz = pos[3 * b + 2] - pos[3 * a + 2];
        const vx = pos[3 * c] - pos[3 * a], vy = pos[3 * c + 1] - pos[3 * a + 1], vz = pos[3 * c + 2] - pos[3 * a + 2];
        const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const ex = eye[0] - pos[3 * a], ey = eye[1] - pos[3 * a + 1], ez = eye[2] - pos[3 * a + 2];
        const d = Math.abs(nx * ex + ny * ey + nz * ez) /
          ((Math.hypot(nx, ny, nz) || 1) * (Math.hypot(ex, ey, ez) || 1));
        const light = 0.38 + 0.62 * Math.round(d * 24) / 24;
        faces.push({
          depth: sz[a] + sz[b] + sz[c] + (m.bias || 0),
          x: [sx[a], sx[b], sx[c]], y: [sy[a], sy[b], sy[c]],
          fill: `rgb(${Math.round(colours[t] * light * 255)},${Math.round(colours[t + 1] * light * 255)},${Math.round(colours[t + 2] * light * 255)})`,
        });
      }
    }
    faces.sort((p, q) => q.depth - p.depth);
    // Runs of faces of one shade (shades are quantised) are filled as one
    // path; a stroke in the same shade closes the hairline gaps between them
    // where there are few enough faces to afford it.
    const stroke = faces.length < 6000;
    ctx.lineWidth = 0.7;
    for (let i = 0; i < faces.length;) {
      const fill = faces[i].fill;
      ctx.beginPath();
      for (; i < faces.length && faces[i].fill === fill; ++i) {
        const f = faces[i];
        ctx.moveTo(f.x[0], f.y[0]);
        ctx.lineTo(f.x[1], f.y[1]);
        ctx.lineTo(f.x[2], f.y[2]);
        ctx.closePath();
      }
      ctx.fillStyle = fill;
      ctx.fill();
      if (stroke) {
        ctx.strokeStyle = fill;
        ctx.stroke();
      }
    }
    if (!this.showSeams) return;
    // Seams that face the viewer, over the surfaces.
    const rect = this.canvas.getBoundingClientRect();
    const k = s.w / Math.max(1, rect.width);
    ctx.lineCap = "round";
    const order = this.seams.slice().sort((a, b) => (a.index === this.selected) - (b.index === this.selected));
    for (const seam of order) {
      const on = seam.index === this.selected;
      ctx.strokeStyle = seam.css;
      ctx.lineWidth = this.seamWidth * s.dpr * (on ? 2.2 : 1);
      ctx.beginPath();
      const g = seam.segments;
      for (let i = 0; i < g.length; i += 9) {
        const a = [g[i], g[i + 1], g[i + 2]], b = [g[i + 3], g[i + 4], g[i + 5]];
        if (!this.facing(a, [g[i + 6], g[i + 7], g[i + 8]])) continue;
        const pa = this.project(a), pb = this.project(b);
        if (pa.w <= 0 || pb.w <= 0) continue;
        ctx.moveTo((pa.x - rect.left) * k, (pa.y - rect.top) * k);
        ctx.lineTo((pb.x - rect.left) * k, (pb.y - rect.top) * k);
      }
      ctx.stroke();
    }
  }
};

// A WebGL 2 (else 1) context of `canvas`, or null.
wk.glContext = function (canvas, antialias) {
  const attributes = { antialias, preserveDrawingBuffer: true };
  try {
    return canvas.getContext("webgl2", attributes) || canvas.getContext("webgl", attributes);
  } catch (error) {
    return null;
  }
};

// Distance from (px, py) to the segment (ax, ay)-(bx, by).
wk.segmentDistance = function (px, py, ax, ay, bx, by) {
  const dx = bx - ax, dy = by - ay;
  const l2 = dx * dx + dy * dy;
  let t = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0;
  t = Math.max(0, Math.min(1, t));
  return Math.hypot(px - ax - t * dx, py - ay - t * dy);
};
