// The page of wearknit simulate --html: mounts the bed view on the page's
// timeline and source text, as window.wkBedView for scripts and tests;
// window.wkBedTimings says how long reading the data and mounting took (ms,
// and the time since navigation started when the page became interactive).
"use strict";

wk.start(async () => {
  const started = performance.now();
  const hasSource = document.getElementById("bed-source") !== null;
  const [bytes, source] = await Promise.all([
    wk.dataBytes("bed-timeline"),
    hasSource ? wk.dataBytes("bed-source") : Promise.resolve(null),
  ]);
  const read = performance.now();
  const container = document.getElementById("bed-view");
  window.wkBedView = wk.mountBedView(container, bytes, source);
  container.querySelector(".bv-stage").focus();
  const mounted = performance.now();
  window.wkBedTimings = {
    script_start_ms: started,
    data_ms: read - started,
    mount_ms: mounted - read,
    interactive_ms: mounted,
  };
});
