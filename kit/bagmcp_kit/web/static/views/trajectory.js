/* A path in the plane (trajectory or any XY pair): equal aspect when both axes are metres, start and end
   marked, stops as rings, and a time slider that puts the robot (a dot) where it was at that time.
   view = {title, x: [], y: [], t: [s], x_label, y_label, equal_aspect, stops: [{x, y, start_s, end_s}]} */
(function (ns) {
  "use strict";
  const { el } = ns;
  const PAD = 44;

  function bounds(xs, ys, equal, width, height) {
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (let i = 0; i < xs.length; i++) {
      if (!Number.isFinite(xs[i]) || !Number.isFinite(ys[i])) continue;
      x0 = Math.min(x0, xs[i]); x1 = Math.max(x1, xs[i]); y0 = Math.min(y0, ys[i]); y1 = Math.max(y1, ys[i]);
    }
    if (!Number.isFinite(x0)) { x0 = -1; x1 = 1; y0 = -1; y1 = 1; }
    const spanX = Math.max(x1 - x0, 1e-6), spanY = Math.max(y1 - y0, 1e-6);
    let sx = (width - 2 * PAD) / spanX, sy = (height - 2 * PAD) / spanY;
    if (equal) { sx = sy = Math.min(sx, sy); }
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    return {
      px: (x) => width / 2 + (x - cx) * sx,
      py: (y) => height / 2 - (y - cy) * sy,
      x0, x1, y0, y1,
    };
  }

  function indexAt(ts, t) {
    let lo = 0, hi = ts.length - 1;
    while (lo < hi) { const mid = (lo + hi) >> 1; if (ts[mid] < t) lo = mid + 1; else hi = mid; }
    return lo;
  }

  function marker(ctx, x, y, radius, fill, stroke) {
    ctx.beginPath(); ctx.arc(x, y, radius, 0, 2 * Math.PI);
    if (fill) { ctx.fillStyle = fill; ctx.fill(); }
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = 2; ctx.stroke(); }
  }

  function paint(fit, view, at) {
    const colors = ns.palette();
    const { ctx, width, height } = fit();
    const b = bounds(view.x, view.y, view.equal_aspect, width, height);
    ctx.clearRect(0, 0, width, height);
    ctx.strokeStyle = colors.grid; ctx.strokeRect(PAD, PAD, width - 2 * PAD, height - 2 * PAD);
    ctx.fillStyle = colors.muted; ctx.font = "12px system-ui, sans-serif";
    ctx.fillText(ns.fmt.num(b.x0, 3) + " … " + ns.fmt.num(b.x1, 3) + "  " + (view.x_label || "x"), PAD, height - 14);
    ctx.save(); ctx.translate(14, height - PAD); ctx.rotate(-Math.PI / 2);
    ctx.fillText(ns.fmt.num(b.y0, 3) + " … " + ns.fmt.num(b.y1, 3) + "  " + (view.y_label || "y"), 0, 0); ctx.restore();
    ctx.beginPath(); ctx.strokeStyle = colors.series[0]; ctx.lineWidth = 1.5;
    let pen = false;
    for (let i = 0; i < view.x.length; i++) {
      if (!Number.isFinite(view.x[i]) || !Number.isFinite(view.y[i])) { pen = false; continue; }
      const X = b.px(view.x[i]), Y = b.py(view.y[i]);
      if (pen) ctx.lineTo(X, Y); else ctx.moveTo(X, Y);
      pen = true;
    }
    ctx.stroke();
    (view.stops || []).forEach((s) => marker(ctx, b.px(s.x), b.py(s.y), 7, null, "#ff7f0e"));
    const n = view.x.length;
    if (n) {
      marker(ctx, b.px(view.x[0]), b.py(view.y[0]), 5, "#2ca02c");
      marker(ctx, b.px(view.x[n - 1]), b.py(view.y[n - 1]), 5, "#d62728");
      marker(ctx, b.px(view.x[at]), b.py(view.y[at]), 6, colors.ink);
    }
    return b;
  }

  function draw(container, view, options) {
    const height = (options && options.heightPx) || 360;
    const n = view.x.length;
    const t = view.t && view.t.length === n ? view.t : view.x.map((_, i) => i);
    const readout = el("output", { class: "bv-readout", "aria-live": "polite" });
    const slider = el("input", { type: "range", min: 0, max: Math.max(0, n - 1), step: 1, value: n ? n - 1 : 0,
      "aria-label": "time along the path", class: "bv-slider" });
    const stops = (view.stops || []).map((s, i) => el("li", {},
      el("button", { type: "button", class: "bv-link", onclick: () => { slider.value = indexAt(t, s.start_s); update(); } },
        "stop " + (i + 1)), " at " + ns.fmt.seconds(s.start_s) + "–" + ns.fmt.seconds(s.end_s) +
        " (" + ns.fmt.num(s.x, 3) + ", " + ns.fmt.num(s.y, 3) + ")"));
    const figure = el("figure", { class: "bv-figure bv-trajectory" }, view.title ? el("figcaption", {}, view.title) : null);
    container.appendChild(figure);
    const plot = ns.canvasFor(figure, height, "path: " + (view.title || "trajectory") + ", " + n + " points");
    figure.appendChild(el("div", { class: "bv-tools" }, el("label", {}, "time ", slider), readout));
    figure.appendChild(el("p", { class: "bv-legend" },
      el("span", { class: "bv-key bv-start" }, "start"), el("span", { class: "bv-key bv-end" }, "end"),
      el("span", { class: "bv-key bv-stop" }, "stop"), el("span", { class: "bv-key bv-now" }, "at the slider's time")));
    if (stops.length) figure.appendChild(el("ul", { class: "bv-stops", "aria-label": "stops" }, stops));
    function update() {
      const i = Number(slider.value);
      paint(plot.fit, view, i);
      readout.textContent = n ? ns.fmt.seconds(t[i]) + ": x " + ns.fmt.num(view.x[i], 4) + ", y " + ns.fmt.num(view.y[i], 4) : "no points";
    }
    slider.addEventListener("input", update);
    update();
    ns.onResize(container, update);
    const drawn = { kind: "trajectory", x: view.x, y: view.y, t, stops: view.stops || [] };
    (ns.drawn = ns.drawn || []).push(drawn);
    return { drawn, slider };
  }

  ns.trajectory = draw;
})(window.BagViews = window.BagViews || {});
