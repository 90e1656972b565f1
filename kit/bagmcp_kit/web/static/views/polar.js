/* Laser scans in polar form: the robot at the centre, forward (angle 0) up, counter-clockwise positive as
   in ROS, invalid ranges left out, an optional "within" circle, and a slider across the scans given.
   view = {title, range_max_m, within_m, scans: [{t: s, angle_min, angle_increment, ranges: [m|null]}]} */
(function (ns) {
  "use strict";
  const { el } = ns;

  function points(scan) {
    const out = [];
    scan.ranges.forEach((r, i) => {
      if (r === null || !Number.isFinite(r)) return;
      const a = scan.angle_min + i * scan.angle_increment;
      out.push({ a, r, x: -Math.sin(a) * r, y: Math.cos(a) * r });
    });
    return out;
  }

  function paint(fit, view, scan) {
    const colors = ns.palette();
    const { ctx, width, height } = fit();
    const pts = points(scan);
    const far = view.range_max_m || Math.max(1, ...pts.map((p) => p.r));
    const radius = Math.min(width, height) / 2 - 24;
    const k = radius / far, cx = width / 2, cy = height / 2;
    ctx.clearRect(0, 0, width, height);
    ctx.strokeStyle = colors.grid; ctx.fillStyle = colors.muted; ctx.font = "11px system-ui, sans-serif";
    for (let ring = 1; ring <= 4; ring++) {
      const r = (far * ring) / 4;
      ctx.beginPath(); ctx.arc(cx, cy, r * k, 0, 2 * Math.PI); ctx.stroke();
      ctx.fillText(ns.fmt.num(r, 3) + " m", cx + 3, cy - r * k - 2);
    }
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx, cy - radius); ctx.stroke();
    if (view.within_m) {
      ctx.strokeStyle = "#d62728"; ctx.setLineDash([4, 4]);
      ctx.beginPath(); ctx.arc(cx, cy, view.within_m * k, 0, 2 * Math.PI); ctx.stroke(); ctx.setLineDash([]);
    }
    ctx.fillStyle = colors.series[0];
    let closest = null;
    pts.forEach((p) => {
      ctx.fillRect(cx + p.x * k - 1.5, cy - p.y * k - 1.5, 3, 3);
      if (!closest || p.r < closest.r) closest = p;
    });
    if (closest) { ctx.strokeStyle = "#d62728"; ctx.beginPath(); ctx.arc(cx + closest.x * k, cy - closest.y * k, 6, 0, 2 * Math.PI); ctx.stroke(); }
    ctx.fillStyle = colors.ink; ctx.beginPath(); ctx.moveTo(cx, cy - 8); ctx.lineTo(cx - 5, cy + 5); ctx.lineTo(cx + 5, cy + 5); ctx.fill();
    return { pts, closest };
  }

  function draw(container, view, options) {
    const height = (options && options.heightPx) || 380;
    const scans = view.scans || [];
    const readout = el("output", { class: "bv-readout", "aria-live": "polite" });
    const slider = el("input", { type: "range", min: 0, max: Math.max(0, scans.length - 1), step: 1, value: 0,
      "aria-label": "scan", class: "bv-slider", disabled: scans.length < 2 });
    const figure = el("figure", { class: "bv-figure bv-polar" }, view.title ? el("figcaption", {}, view.title) : null);
    container.appendChild(figure);
    const plot = ns.canvasFor(figure, height, "lidar scan: " + (view.title || "") + ", " + scans.length + " scans");
    figure.appendChild(el("div", { class: "bv-tools" }, el("label", {}, "scan ", slider), readout));
    const drawn = { kind: "scan", scans: scans.length, index: 0, points: [] };
    function update() {
      if (!scans.length) { readout.textContent = "no scans"; return; }
      const i = Number(slider.value);
      const { pts, closest } = paint(plot.fit, view, scans[i]);
      drawn.index = i; drawn.points = pts;
      readout.textContent = (i + 1) + "/" + scans.length + " at " + ns.fmt.seconds(scans[i].t) + ": " + pts.length +
        " valid ranges" + (closest ? ", closest " + ns.fmt.num(closest.r, 3) + " m at " + ns.fmt.num((closest.a * 180) / Math.PI, 3) + "°" : "");
    }
    slider.addEventListener("input", update);
    update();
    ns.onResize(container, update);
    (ns.drawn = ns.drawn || []).push(drawn);
    return { drawn, slider };
  }

  ns.polar = draw;
})(window.BagViews = window.BagViews || {});
