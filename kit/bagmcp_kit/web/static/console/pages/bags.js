/* The bag list: status and ingest progress refreshed every 1.5 s while the page is open, the upload box,
   and delete (the server refuses it without the delete scope, and the page says so). */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;
  const PERIOD_MS = 1500;

  function statusCell(bag) {
    const label = bag.status === "ingesting" && bag.progress !== null && bag.progress !== undefined
      ? "ingesting " + Math.round(bag.progress * 100) + "%" : bag.status;
    const badge = el("span", { class: "status status-" + bag.status }, label);
    if (bag.status === "ingesting") {
      return el("span", {}, badge, " ", el("progress", { max: 1, value: bag.progress || 0, "aria-label": "ingest of " + bag.name }));
    }
    return bag.status === "failed" ? el("span", {}, badge, " ", el("span", { class: "error" }, bag.error || "")) : badge;
  }

  async function remove(bag, refresh) {
    if (!window.confirm("Delete the bag “" + bag.name + "”? This cannot be undone.")) return;
    try {
      await ns.api.del("/api/v1/bags/" + encodeURIComponent(bag.id));
      ns.shell.toast("Deleted " + bag.name);
      refresh();
    } catch (err) {
      ns.shell.toast(err.status === 403 ? "This token may not delete bags (it needs the delete scope)." : err.message);
    }
  }

  function columns(refresh) {
    return [
      { key: "name", label: "Bag", format: (name, bag) => el("a", { href: "#/bag/" + encodeURIComponent(bag.id) }, name) },
      { key: "status", label: "Status", format: (_, bag) => statusCell(bag) },
      { key: "format", label: "Format" },
      { key: "duration_s", label: "Duration", numeric: true, format: (v) => fmt.duration(v) },
      { key: "topic_count", label: "Topics", numeric: true },
      { key: "size_bytes", label: "Size", numeric: true, format: (v) => fmt.bytes(v) },
      { key: "id", label: "", format: (_, bag) => el("button", { type: "button", class: "danger", onclick: () => remove(bag, refresh),
        "aria-label": "delete " + bag.name }, "Delete") },
    ];
  }

  ns.shell.page("bags", async (main) => {
    const count = el("p", { class: "muted", id: "bag-count", "aria-live": "polite" });
    const listBox = el("div", { id: "bag-list" });
    const problem = el("div", { role: "alert" });
    main.appendChild(el("h1", {}, "Bags"));
    const uploadBox = el("section", { class: "card", "aria-labelledby": "upload-title" });
    main.append(uploadBox, count, problem, listBox);
    let view = null;
    async function refresh() {
      try {
        const page = await ns.api.get("/api/v1/bags?limit=200");
        ns.clear(problem);
        count.textContent = page.total + (page.total === 1 ? " bag" : " bags") +
          (page.bags.length < page.total ? " (showing " + page.bags.length + ")" : "");
        if (!view) view = ns.table(listBox, columns(refresh), page.bags, { caption: "Bags in this store" });
        else view.update(page.bags);
      } catch (err) {
        ns.replace(problem, ns.shell.errorBox(err));
        if (err.status === 401) throw err;
      }
    }
    ns.uploadBox(uploadBox, refresh);
    await refresh();
    ns.consoleAdmin().catch(() => { /* the menu stays as it is */ });
    return ns.shell.every(PERIOD_MS, refresh);
  });
})(window.BagViews = window.BagViews || {});
