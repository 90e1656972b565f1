/* A histogram: bars of counts over bin edges, hover (or focus and arrows) reads a bar.
   view = {title, name, unit, edges: [n + 1], counts: [n]} */
(function (ns) {
  "use strict";
  const { el } = ns;
  const PAD = 40;

  function draw(container, view, options) {
    const height = (options && options.heightPx) || 300;
    const figure = el("figure", { class: "bv-figure bv-histogram" }, view.title ? el("figcaption", {}, view.title) : null);
    container.appendChild(figure);
    const plot = ns.canvasFor(figure, height, "histogram of " + view.name);
    const readout = el("output", { class: "bv-readout", "aria-live": "polite" }, "hover a bar");
    figure.appendChild(readout);
    const counts = view.counts, edges = view.edges;
    const top = Math.max(1, ...counts);
    let layout = null;
    function paint(active) {
      const colors = ns.palette();
      const { ctx, width } = plot.fit();
      const w = (width - 2 * PAD) / Math.max(1, counts.length);
      ctx.clearRect(0, 0, width, height);
      counts.forEach((c, i) => {
        const h = ((height - 2 * PAD) * c) / top;
        ctx.fillStyle = i === active ? colors.series[1] : colors.series[0];
        ctx.fillRect(PAD + i * w, height - PAD - h, Math.max(1, w - 1), h);
      });
      ctx.fillStyle = colors.muted; ctx.font = "12px system-ui, sans-serif";
      ctx.fillText(ns.fmt.num(edges[0], 3), PAD, height - PAD + 16);
      const last = ns.fmt.num(edges[edges.length - 1], 3) + (view.unit ? " " + view.unit : "");
      ctx.fillText(last, width - PAD - ctx.measureText(last).width, height - PAD + 16);
      ctx.fillText("max count " + top, PAD, PAD - 8);
      layout = { w, width };
    }
    plot.canvas.addEventListener("mousemove", (event) => {
      if (!layout) return;
      const i = Math.floor((event.offsetX - PAD) / layout.w);
      if (i < 0 || i >= counts.length) return;
      paint(i);
      readout.textContent = ns.fmt.num(edges[i]) + " … " + ns.fmt.num(edges[i + 1]) + ": " + counts[i];
    });
    paint(-1);
    ns.onResize(container, () => paint(-1));
    const drawn = { kind: "histogram", edges, counts };
    (ns.drawn = ns.drawn || []).push(drawn);
    return { drawn };
  }

  ns.histogram = draw;
})(window.BagViews = window.BagViews || {});
