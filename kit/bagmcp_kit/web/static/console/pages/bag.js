/* One bag: its facts and topics, and tabs for a field over time, the trajectory, a scan, logs, the TF
   tree and an image. Each tab asks the server (MCP tools) when it is first opened; the drawings are the
   shared views the MCP Apps viewers use, fed the same tool results. */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;
  const TABS = [
    ["topics", "Topics"], ["plot", "Plot a field"], ["trajectory", "Trajectory"], ["scan", "Lidar scan"],
    ["logs", "Logs"], ["tf", "TF tree"], ["image", "Image"],
  ];

  function facts(bag) {
    const s = bag.summary || {};
    const rows = [
      ["Status", bag.status + (bag.error ? ": " + bag.error : "")], ["Format", s.format], ["Duration", fmt.duration(s.duration_s)],
      ["Start", s.start_ns ? fmt.date(s.start_ns / 1e9) : null], ["Messages", s.message_count], ["Size", fmt.bytes(bag.size_bytes)],
      ["Id", bag.id], ["Tags", (bag.tags || []).join(", ") || null],
    ];
    return el("dl", { class: "facts" }, rows.filter((r) => r[1] !== null && r[1] !== undefined).map(([k, v]) => [el("dt", {}, k), el("dd", {}, String(v))]));
  }

  function topicsTab(panel, bag, open) {
    const topics = (bag.summary && bag.summary.topics) || [];
    ns.table(panel, [
      { key: "name", label: "Topic" },
      { key: "type", label: "Type" },
      { key: "count", label: "Messages", numeric: true },
      { key: "rate_hz", label: "Rate [Hz]", numeric: true, format: (v) => fmt.num(v) },
      { key: "name", label: "", format: (name) => el("button", { type: "button", onclick: () => open("plot", { topic: name }), "aria-label": "plot a field of " + name }, "Plot") },
    ], topics, { caption: topics.length + " topics" });
  }

  ns.shell.page("bag", async (main, args) => {
    const ref = args[0] || "";
    const bag = await ns.api.get("/api/v1/bags/" + encodeURIComponent(ref));
    main.appendChild(el("p", {}, el("a", { href: "#/bags" }, "← All bags")));
    main.appendChild(el("h1", {}, bag.name));
    main.appendChild(facts(bag));
    if (bag.status !== "ready") {
      main.appendChild(el("p", { class: "muted" }, "This bag is " + bag.status + "; its views open when ingest is done."));
      return ns.shell.every(2000, async () => { const now = await ns.api.get("/api/v1/bags/" + encodeURIComponent(ref)); if (now.status !== bag.status) ns.shell.show(); });
    }
    const tablist = el("div", { class: "tabs", role: "tablist", "aria-label": "Views of this bag" });
    const panels = {};
    const buttons = {};
    const done = {};
    main.appendChild(tablist);
    function open(name, options) {
      Object.entries(buttons).forEach(([key, b]) => { b.setAttribute("aria-selected", String(key === name)); b.tabIndex = key === name ? 0 : -1; panels[key].hidden = key !== name; });
      if (!done[name] || options) {
        done[name] = true;
        ns.clear(panels[name]);
        const render = name === "topics" ? topicsTab : ns.bagViews[name];
        Promise.resolve(render(panels[name], bag, open, options || {})).catch((err) => ns.replace(panels[name], ns.shell.errorBox(err)));
      }
    }
    TABS.forEach(([key, label]) => {
      buttons[key] = el("button", { type: "button", role: "tab", id: "tab-" + key, "aria-controls": "panel-" + key, onclick: () => open(key) }, label);
      panels[key] = el("section", { role: "tabpanel", id: "panel-" + key, "aria-labelledby": "tab-" + key, hidden: true });
      tablist.appendChild(buttons[key]);
      main.appendChild(panels[key]);
    });
    open("topics");
  });
})(window.BagViews = window.BagViews || {});
