/* Jobs: the long work this console started in this tab (plots, scans, analyses that outlived their time
   budget), followed with get_job until they end; any other job id can be looked up too. */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;
  const KEY = "bagmcp.jobs";
  const PERIOD_MS = 1500;

  ns.rememberJob = function rememberJob(job, what) {
    const jobs = JSON.parse(sessionStorage.getItem(KEY) || "[]");
    if (!jobs.some((j) => j.id === job.job_id)) jobs.unshift({ id: job.job_id, what });
    sessionStorage.setItem(KEY, JSON.stringify(jobs.slice(0, 50)));
  };

  ns.shell.page("jobs", async (main) => {
    main.appendChild(el("h1", {}, "Jobs"));
    const input = el("input", { id: "job-id", type: "text", autocomplete: "off", spellcheck: "false" });
    const form = el("form", { class: "row" }, el("div", { class: "field" }, el("label", { for: "job-id" }, "Follow a job by id"), input),
      el("button", { type: "submit" }, "Follow"));
    const box = el("div", { id: "job-list" });
    main.append(form, box);
    form.addEventListener("submit", (e) => { e.preventDefault(); if (input.value.trim()) { ns.rememberJob({ job_id: input.value.trim() }, "looked up"); input.value = ""; refresh(); } });
    let table = null;
    async function refresh() {
      const jobs = JSON.parse(sessionStorage.getItem(KEY) || "[]");
      const rows = await Promise.all(jobs.map(async (j) => {
        try {
          const answer = await ns.api.callToolOk("get_job", { job_id: j.id });
          return Object.assign({ what: j.what }, answer.structuredContent);
        } catch (err) { return { job_id: j.id, what: j.what, state: "unknown", message: err.message, progress: 0 }; }
      }));
      const columns = [
        { key: "job_id", label: "Job" }, { key: "kind", label: "Kind" }, { key: "state", label: "State" },
        { key: "progress", label: "Progress", format: (v, row) => el("span", {}, el("progress", { max: 1, value: v || 0, "aria-label": "progress of " + row.job_id }), " " + Math.round((v || 0) * 100) + "%") },
        { key: "message", label: "Message", format: (v, row) => row.error || v },
        { key: "updated_at", label: "Updated", format: (v) => fmt.date(v) },
      ];
      if (!rows.length) { ns.replace(box, el("p", { class: "muted" }, "No jobs yet in this tab. Work that outlives its time budget (a long plot, a scan of a big bag) shows here.")); table = null; return; }
      if (!table) { ns.clear(box); table = ns.table(box, columns, rows, { caption: "Jobs started from this tab" }); } else table.update(rows);
    }
    await refresh();
    return ns.shell.every(PERIOD_MS, refresh);
  });
})(window.BagViews = window.BagViews || {});
