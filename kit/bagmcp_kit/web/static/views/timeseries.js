/* Time series with uPlot: drag across the plot to zoom, the wheel zooms around the cursor, the arrow
   buttons (or ←/→ with the plot focused) pan, double-click or Reset shows everything; the legend gives
   each series' value under the cursor. Series of different units get their own axis (two at most shown;
   more share the left one). view = {title, style: line|step|scatter, series: [{name, unit, t: [s], v: []}]} */
(function (ns) {
  "use strict";
  const { el } = ns;

  function aligned(series) {
    if (series.length === 1) return [series[0].t, series[0].v];
    return window.uPlot.join(series.map((s) => [s.t, s.v]));
  }

  function scalesOf(series) {
    const units = [];
    series.forEach((s) => { const u = s.unit || "value"; if (!units.includes(u)) units.push(u); });
    return units;
  }

  function wheelZoom(factor) {
    return {
      hooks: {
        ready: (u) => {
          u.over.addEventListener("wheel", (event) => {
            event.preventDefault();
            const x = u.posToVal(u.cursor.left >= 0 ? u.cursor.left : u.over.clientWidth / 2, "x");
            const { min, max } = u.scales.x;
            const k = event.deltaY < 0 ? factor : 1 / factor;
            u.setScale("x", { min: x - (x - min) * k, max: x + (max - x) * k });
          }, { passive: false });
        },
      },
    };
  }

  function pan(u, fraction) {
    const { min, max } = u.scales.x;
    const step = (max - min) * fraction;
    u.setScale("x", { min: min + step, max: max + step });
  }

  function pathsFor(style) {
    if (style === "step") return window.uPlot.paths.stepped({ align: 1 });
    if (style === "scatter") return () => null;
    return undefined;
  }

  function draw(container, view, options) {
    const colors = ns.palette();
    const units = scalesOf(view.series);
    const data = aligned(view.series);
    const height = (options && options.heightPx) || 320;
    const box = el("div", { class: "bv-plot", tabindex: "0", "aria-label": "plot: " + (view.title || "time series") });
    const tools = el("div", { class: "bv-tools" },
      el("button", { type: "button", onclick: () => pan(chart, -0.25), "aria-label": "pan left" }, "◀"),
      el("button", { type: "button", onclick: () => pan(chart, 0.25), "aria-label": "pan right" }, "▶"),
      el("button", { type: "button", onclick: () => chart.setScale("x", { min: data[0][0], max: data[0][data[0].length - 1] }) }, "Reset zoom"));
    container.appendChild(el("figure", { class: "bv-figure bv-timeseries" },
      view.title ? el("figcaption", {}, view.title) : null, tools, box));
    const series = [{ label: "time [s]", value: (u, v) => (v === null ? "–" : v.toFixed(3)) }].concat(view.series.map((s, i) => ({
      label: ns.fmt.withUnit(s.name, s.unit),
      scale: s.unit || "value",
      stroke: colors.series[i % colors.series.length],
      width: 1.5,
      spanGaps: true,
      paths: pathsFor(view.style),
      points: { show: view.style === "scatter" ? true : undefined, size: 4 },
      value: (u, v) => ns.fmt.num(v),
    })));
    const axis = (scale, side) => ({
      scale, side, label: scale === "value" ? "" : scale, stroke: colors.ink,
      grid: { show: side === 3, stroke: colors.grid }, ticks: { stroke: colors.grid },
    });
    const axes = [{ label: "time from bag start [s]", stroke: colors.ink, grid: { stroke: colors.grid }, ticks: { stroke: colors.grid } },
      axis(units[0], 3)];
    if (units.length > 1) axes.push(axis(units[1], 1));
    const scales = { x: { time: false } };
    units.forEach((u, i) => { scales[u] = { auto: true }; if (i > 1) series.forEach((s) => { if (s.scale === u) s.scale = units[0]; }); });
    const opts = {
      width: Math.max(260, box.clientWidth || container.clientWidth || 600), height,
      scales, series, axes,
      cursor: { drag: { x: true, y: false }, focus: { prox: 16 } },
      legend: { live: true },
      plugins: [wheelZoom(0.8)],
    };
    const chart = new window.uPlot(opts, data, box);
    box.addEventListener("keydown", (e) => {
      if (e.key === "ArrowLeft") pan(chart, -0.1);
      if (e.key === "ArrowRight") pan(chart, 0.1);
    });
    ns.onResize(container, () => chart.setSize({ width: Math.max(260, box.clientWidth), height }));
    const drawn = { kind: "timeseries", names: view.series.map((s) => s.name), data: chart.data };
    (ns.drawn = ns.drawn || []).push(drawn);
    return { chart, drawn };
  }

  ns.timeseries = draw;
})(window.BagViews = window.BagViews || {});
