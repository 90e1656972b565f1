/* Building DOM without markup strings: text always goes in through textContent, so a bag, topic or log
   line named "<img src=x onerror=...>" shows as those characters. Every view and page uses el(). */
(function (ns) {
  "use strict";
  const SAFE_URL = /^(\/|#|blob:|data:image\/)/;

  function append(node, child) {
    if (child === null || child === undefined || child === false) return;
    if (Array.isArray(child)) { child.forEach((c) => append(node, c)); return; }
    node.appendChild(child instanceof Node ? child : document.createTextNode(String(child)));
  }

  /* el("div", {class: "x", onclick: fn, "aria-label": "y"}, "text", otherNode, [more]) */
  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [key, value] of Object.entries(attrs || {})) {
      if (value === null || value === undefined || value === false) continue;
      if (key.startsWith("on") && typeof value === "function") node.addEventListener(key.slice(2), value);
      else if (key === "dataset") Object.assign(node.dataset, value);
      else if ((key === "href" || key === "src") && !SAFE_URL.test(String(value))) continue;
      else if (key === "value") node.value = value;
      else node.setAttribute(key, value === true ? "" : String(value));
    }
    append(node, children);
    return node;
  }

  function clear(node) { while (node.firstChild) node.removeChild(node.firstChild); return node; }

  function replace(node, ...children) { clear(node); append(node, children); return node; }

  /* A canvas sized to its box in CSS pixels, drawn at the screen's pixel density. */
  function canvasFor(parent, heightPx, label) {
    const canvas = el("canvas", { role: "img", "aria-label": label, class: "bv-canvas" });
    parent.appendChild(canvas);
    const fit = () => {
      const ratio = window.devicePixelRatio || 1;
      const width = Math.max(200, parent.clientWidth || 600);
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(heightPx * ratio);
      canvas.style.width = width + "px";
      canvas.style.height = heightPx + "px";
      const ctx = canvas.getContext("2d");
      ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
      return { ctx, width, height: heightPx };
    };
    return { canvas, fit };
  }

  function palette() {
    const dark = window.matchMedia && window.matchMedia("(prefers-color-scheme: dark)").matches;
    return {
      dark,
      ink: dark ? "#e8e8e8" : "#1d1d1f",
      muted: dark ? "#9a9a9a" : "#5f6368",
      grid: dark ? "#3a3a3a" : "#e3e3e3",
      series: ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"],
    };
  }

  /* Redraw on container resize (phones turn; panels open). */
  function onResize(node, redraw) {
    if (!window.ResizeObserver) return;
    let last = node.clientWidth;
    new ResizeObserver(() => {
      if (Math.abs(node.clientWidth - last) > 2) { last = node.clientWidth; redraw(); }
    }).observe(node);
  }

  Object.assign(ns, { el, clear, replace, canvasFor, palette, onResize });
})(window.BagViews = window.BagViews || {});
