/* The benchmark tab: starts a run of the paper's tasks (or all) on a bag, then follows it, filling the table
   (one row per task: success, the tools called, the judge's reason) and the figures as runs finish. */
(function (ns) {
  "use strict";
  const { el } = ns;
  const POLL_MS = 700;
  let current = null;

  function cell(records) {
    if (!records.length) return el("td", { class: "muted" }, "…");
    const wins = records.filter((r) => r.success).length;
    const tools = [...new Set(records.flatMap((r) => r.tool_calls.map((c) => c.name)))].join(" ");
    const mark = records.length === 1 ? (wins ? "✓" : "✗") : wins + "/" + records.length;
    return el("td", { class: wins === records.length ? "lab-ok" : "lab-fail", title: records.map((r) => r.reason).join("\n") },
      mark + " " + tools);
  }

  function table(status) {
    const model = status.model + " (" + status.provider + ")";
    const rows = status.tasks.map((task, index) => {
      const records = status.records.filter((r) => r.task === task.id);
      const reason = records.length ? records.map((r) => r.reason).join("; ") : "";
      return el("tr", { dataset: { task: task.id } }, el("td", {}, String(index + 1)), el("td", { title: task.prompt }, task.title),
        cell(records), el("td", { class: "lab-reason" }, reason));
    });
    return el("table", { class: "bv-table", id: "bench-results" },
      el("caption", {}, "Tasks × " + model + " on " + status.bag),
      el("thead", {}, el("tr", {}, el("th", { scope: "col" }, "#"), el("th", { scope: "col" }, "Task"),
        el("th", { scope: "col" }, model), el("th", { scope: "col" }, "Judge"))),
      el("tbody", {}, rows));
  }

  async function figures(runId) {
    const box = ns.clear(document.getElementById("bench-figures"));
    for (const [name, label] of [["latency", "Response time per task"], ["calls", "Tool calls per task"]]) {
      box.appendChild(el("img", { src: await ns.lab.blobUrl("/api/v1/lab/" + runId + "/" + name), alt: label, class: "lab-figure" }));
    }
  }

  async function follow(runId) {
    current = runId;
    let shown = -1;
    while (current === runId) {
      const status = await ns.api.get("/api/v1/lab/" + runId);
      const done = status.done + " of " + (status.planned || "?") + " runs done, " + status.succeeded + " succeeded";
      document.getElementById("bench-status").textContent =
        status.state === "running" ? "Running: " + done : "Finished (" + status.state + "): " + done + (status.error ? ". " + status.error : "");
      ns.replace(document.getElementById("bench-table"), table(status));
      if (status.done !== shown && status.done > 0) { shown = status.done; await figures(runId); }
      if (status.state !== "running") break;
      await new Promise((resolve) => setTimeout(resolve, POLL_MS));
    }
    document.getElementById("bench-download").hidden = false;
    document.getElementById("bench-start").disabled = false;
  }

  async function bags() {
    const select = ns.clear(document.getElementById("bench-bag"));
    try {
      const listing = await ns.api.get("/api/v1/bags?limit=500");
      listing.bags.filter((b) => b.status === "ready").forEach((b) => select.appendChild(el("option", { value: b.name }, b.name)));
    } catch (err) {
      document.getElementById("bench-status").textContent = err.message;
    }
  }

  ns.labBench = function setUpBench() {
    document.getElementById("tab-bench").addEventListener("click", bags);
    document.getElementById("bench-form").addEventListener("submit", async (event) => {
      event.preventDefault();
      const button = document.getElementById("bench-start");
      try {
        const body = Object.assign(ns.lab.choice(), {
          bag: document.getElementById("bench-bag").value,
          tasks: document.getElementById("bench-suite").value,
          repeat: Number(document.getElementById("bench-repeat").value || 1),
        });
        button.disabled = true;
        document.getElementById("bench-download").hidden = true;
        const started = await ns.api.post("/api/v1/lab/runs", body);
        await follow(started.run_id);
      } catch (err) {
        document.getElementById("bench-status").textContent = err.message;
        button.disabled = false;
      }
    });
    document.getElementById("bench-download").addEventListener("click", async () => {
      const link = el("a", { href: await ns.lab.blobUrl("/api/v1/lab/" + current + "/results"), download: current + "-results.json" });
      document.body.appendChild(link);
      link.click();
      link.remove();
    });
  };
})(window.BagViews = window.BagViews || {});
