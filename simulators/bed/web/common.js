// Helpers every page written by wearknit shares: the page's embedded data,
// number formatting, and errors shown on the page as well as the console.
"use strict";

const wk = {};

// The bytes of <script type="application/octet-stream" id=ID>: base64 text,
// gzip-compressed when it starts with gzip's magic bytes (decompressed with
// the browser's own DecompressionStream). Resolves to a Uint8Array.
wk.dataBytes = async function (id) {
  const element = document.getElementById(id);
  if (!element) throw new Error("the page has no data block '" + id + "'");
  const text = element.textContent.replace(/\s+/g, "");
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  if (bytes.length < 2 || bytes[0] !== 0x1f || bytes[1] !== 0x8b) return bytes;
  if (typeof DecompressionStream === "undefined") {
    throw new Error("this browser cannot decompress the page's data (no DecompressionStream)");
  }
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
  // Read chunk by chunk into one buffer of the size gzip's trailer gives
  // (ISIZE, the size modulo 2^32), which is quicker than Response.arrayBuffer
  // on large blocks; grown if the trailer understates it.
  const n = bytes.length;
  const size = (bytes[n - 4] | (bytes[n - 3] << 8) | (bytes[n - 2] << 16) | (bytes[n - 1] << 24)) >>> 0;
  let out = new Uint8Array(size);
  let used = 0;
  const reader = stream.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    if (used + value.length > out.length) {
      const grown = new Uint8Array(Math.max(2 * out.length, used + value.length));
      grown.set(out.subarray(0, used));
      out = grown;
    }
    out.set(value, used);
    used += value.length;
  }
  return used === out.length ? out : out.slice(0, used);
};

// The JSON object of data block ID.
wk.dataJson = async function (id) {
  return JSON.parse(new TextDecoder().decode(await wk.dataBytes(id)));
};

// n with `digits` decimals, thousands separated by a thin space.
wk.fmt = function (n, digits) {
  if (n === undefined || n === null || Number.isNaN(n)) return "—";
  const fixed = Number(n).toFixed(digits || 0);
  const [whole, frac] = fixed.split(".");
  const grouped = whole.replace(/\B(?=(\d{3})+(?!\d))/g, "\u2009");
  return frac ? grouped + "." + frac : grouped;
};

// Seconds as "1 h 02 min", "3 min 05 s" or "12.3 s".
wk.duration = function (s) {
  if (s === undefined || s === null || Number.isNaN(s)) return "—";
  if (s >= 3600) {
    const h = Math.floor(s / 3600);
    return h + " h " + String(Math.round((s - 3600 * h) / 60)).padStart(2, "0") + " min";
  }
  if (s >= 60) {
    const m = Math.floor(s / 60);
    return m + " min " + String(Math.round(s - 60 * m)).padStart(2, "0") + " s";
  }
  return s.toFixed(1) + " s";
};

// An element with attributes and children (strings become text).
wk.el = function (tag, attributes, ...children) {
  const element = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes || {})) {
    if (key === "class") element.className = value;
    else if (key.startsWith("on")) element.addEventListener(key.slice(2), value);
    else element.setAttribute(key, value);
  }
  for (const child of children) {
    if (child === null || child === undefined) continue;
    element.append(child instanceof Node ? child : String(child));
  }
  return element;
};

// Shows an error in the page's error bar as well as the console.
wk.showError = function (message) {
  let bar = document.getElementById("wk-error");
  if (!bar) {
    bar = wk.el("div", { id: "wk-error", class: "wk-error" });
    document.body.prepend(bar);
  }
  bar.textContent = message;
  console.error(message);
};

// Runs the page's start function, showing what went wrong if it throws.
wk.start = function (main) {
  const run = async () => {
    try {
      await main();
      document.body.dataset.ready = "1";
    } catch (error) {
      wk.showError("wearknit: " + (error && error.message ? error.message : error));
      document.body.dataset.ready = "error";
    }
  };
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", run);
  else run();
};
