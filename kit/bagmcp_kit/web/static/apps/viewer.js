/* An MCP Apps viewer: draws the view data a bagmcp tool result carries in _meta["bagmcp/view"] with the
   same views as the web console; a result without it (an error, a job still running) shows its text. */
(function (ns) {
  "use strict";
  const { el } = ns;
  const VIEW_KEY = "bagmcp/view";
  const root = document.getElementById("view");
  let input = null;

  function textOf(result) {
    return (result.content || []).filter((b) => b.type === "text").map((b) => b.text).join("\n");
  }

  function render(view, container) {
    const draw = {
      timeseries: ns.timeseries, xy: ns.trajectory, trajectory: ns.trajectory, scan: ns.polar, histogram: ns.histogram,
    }[view.kind];
    if (!draw) throw new Error("this viewer cannot draw a " + view.kind + " view");
    draw(container, view, {});
    if (view.notes && view.notes.length) container.appendChild(el("ul", { class: "bv-notes" }, view.notes.map((n) => el("li", {}, n))));
  }

  function show(result) {
    ns.clear(root);
    const view = result && result._meta && result._meta[VIEW_KEY];
    if (result && result.isError) {
      root.appendChild(el("p", { class: "bv-error", role: "alert" }, textOf(result) || "the tool failed"));
    } else if (view) {
      render(view, root);
    } else {
      root.appendChild(el("p", { class: "bv-muted" }, textOf(result) || "nothing to draw in this result"));
    }
    ns.apps.reportSize();
  }

  function applyTheme(context) {
    if (context && context.theme) document.documentElement.dataset.theme = context.theme;
  }

  ns.apps.on("ui/notifications/tool-input", (params) => { input = params.arguments || {}; ns.viewerInput = input; });
  ns.apps.on("ui/notifications/tool-result", (params) => {
    try { show(params); } catch (err) { ns.replace(root, el("p", { class: "bv-error", role: "alert" }, String(err.message || err))); }
  });
  ns.apps.on("ui/notifications/host-context-changed", applyTheme);
  ns.apps.on("ui/resource-teardown", () => ({}));
  ns.apps.connect({ name: "bagmcp-viewer", version: "1" }).then((init) => applyTheme(init.hostContext)).catch((err) => {
    ns.replace(root, el("p", { class: "bv-error", role: "alert" }, "could not connect to the host: " + err.message));
  });
})(window.BagViews = window.BagViews || {});
