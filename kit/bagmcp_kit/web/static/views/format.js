/* Numbers, times and sizes as people read them. */
(function (ns) {
  "use strict";
  function num(value, digits) {
    if (value === null || value === undefined || Number.isNaN(value)) return "–";
    const d = digits === undefined ? 4 : digits;
    const abs = Math.abs(value);
    if (abs !== 0 && (abs >= 1e6 || abs < 1e-3)) return value.toExponential(2);
    return Number(value.toPrecision(d)).toString();
  }
  function seconds(value) { return value === null || value === undefined ? "–" : value.toFixed(2) + " s"; }
  function bytes(n) {
    if (n === null || n === undefined) return "–";
    const units = ["B", "KB", "MB", "GB", "TB"];
    let i = 0; let v = n;
    while (v >= 1024 && i < units.length - 1) { v /= 1024; i += 1; }
    return (i === 0 ? v : v.toFixed(1)) + " " + units[i];
  }
  function date(epochS) {
    if (!epochS) return "–";
    return new Date(epochS * 1000).toISOString().replace("T", " ").replace(/\.\d+Z$/, " UTC");
  }
  function duration(s) {
    if (s === null || s === undefined) return "–";
    if (s < 60) return s.toFixed(1) + " s";
    const m = Math.floor(s / 60);
    return m < 60 ? m + " min " + Math.round(s % 60) + " s" : Math.floor(m / 60) + " h " + (m % 60) + " min";
  }
  function withUnit(name, unit) { return unit ? name + " [" + unit + "]" : name; }
  ns.fmt = { num, seconds, bytes, date, duration, withUnit };
})(window.BagViews = window.BagViews || {});
