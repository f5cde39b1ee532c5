// The page of wearknit simulate --html: mounts the bed view on the page's
// timeline and source text, as window.wkBedView for scripts and tests.
"use strict";

wk.start(async () => {
  const hasSource = document.getElementById("bed-source") !== null;
  const [bytes, source] = await Promise.all([
    wk.dataBytes("bed-timeline"),
    hasSource ? wk.dataBytes("bed-source") : Promise.resolve(null),
  ]);
  const container = document.getElementById("bed-view");
  window.wkBedView = wk.mountBedView(container, bytes, source);
  container.querySelector(".bv-stage").focus();
});
