/* The bag page's tabs after Topics. Each calls one MCP tool and draws its answer: the drawings use the
   view data a tool result carries (_meta["bagmcp/view"]), exactly as the MCP Apps viewer does. */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;
  const VIEW_KEY = "bagmcp/view";
  const LEVELS = ["DEBUG", "INFO", "WARN", "ERROR", "FATAL"];
  const IMAGE_TYPES = /sensor_msgs\/(msg\/)?(Image|CompressedImage)$/;
  const LOG_TYPES = /(rosgraph_msgs|rcl_interfaces)\/(msg\/)?Log$/;
  const SCAN_TYPES = /sensor_msgs\/(msg\/)?LaserScan$/;

  const topicsOf = (bag, pattern) => ((bag.summary && bag.summary.topics) || []).filter((t) => !pattern || pattern.test(t.type));
  const result = (answer) => (answer.structuredContent && answer.structuredContent.result) || answer.structuredContent || {};
  const viewOf = (answer) => (answer._meta && answer._meta[VIEW_KEY]) || null;
  /* A tool answer. Work that outlives its time budget becomes a job: it is listed on the Jobs page and
     followed here (get_job each second) until it ends; then a plot is asked again (it is stored, so it
     answers at once, with its view), and an analysis answers with the job's result (numbers, no drawing). */
  async function call(name, args, onProgress) {
    const answer = await ns.api.callToolOk(name, args);
    const job = answer.structuredContent && answer.structuredContent.job;
    if (!job) return answer;
    ns.rememberJob(job, name + " on " + args.bag);
    for (;;) {
      await new Promise((resolve) => setTimeout(resolve, 1000));
      const now = (await ns.api.callToolOk("get_job", { job_id: job.job_id })).structuredContent;
      if (onProgress) onProgress(now);
      if (now.state === "succeeded") {
        return name.startsWith("plot_") ? ns.api.callToolOk(name, args) : { structuredContent: { result: now.result }, content: [] };
      }
      if (now.state === "failed" || now.state === "cancelled") throw new Error("job " + job.job_id + " " + now.state + ": " + (now.error || now.message));
    }
  }
  const busy = (box, text) => ns.replace(box, el("p", { class: "muted", role: "status" }, text));

  function select(id, label, options, chosen) {
    const node = el("select", { id }, options.map((o) => el("option", { value: o.value, selected: o.value === chosen }, o.label)));
    return { node, field: el("div", { class: "field" }, el("label", { for: id }, label), node) };
  }

  async function plot(panel, bag, open, options) {
    const topics = topicsOf(bag).filter((t) => !/Log|TFMessage|tfMessage|Image|PointCloud|String/.test(t.type));
    if (!topics.length) { panel.appendChild(el("p", { class: "muted" }, "No topic with numeric fields.")); return; }
    const topic = select("plot-topic", "Topic", topics.map((t) => ({ value: t.name, label: t.name + " (" + t.type + ")" })), options.topic || topics[0].name);
    const field = select("plot-field", "Field", [], null);
    const out = el("div", { id: "plot-out" });
    const go = el("button", { type: "button", class: "primary" }, "Plot");
    panel.append(el("div", { class: "row" }, topic.field, field.field, go), out);
    let asked = 0;
    /* Fields of the topic chosen last: the first topic's answer, if slower, must not replace them. */
    async function fields() {
      const mine = ++asked;
      const answer = await ns.api.callToolOk("describe_topic", { bag: bag.id, topic: topic.node.value });
      if (mine !== asked) return;
      const numeric = (answer.structuredContent.fields || []).filter((f) => /^(float|int|uint|bool|byte|char)/.test(f.type));
      ns.replace(field.node, numeric.map((f) => el("option", { value: f.path }, f.path + (f.unit ? " [" + f.unit + "]" : ""))));
    }
    let latest = 0;
    /* Only the latest request's answer is drawn (an earlier, slower one must not replace it). */
    async function draw() {
      const mine = ++latest;
      const path = topic.node.value + "." + field.node.value;
      busy(out, "Reading " + path + "…");
      let answer;
      try {
        answer = await call("plot_timeseries", { bag: bag.id, paths: [path] },
          (now) => busy(out, "Reading " + path + " as job " + now.job_id + ": " + Math.round(now.progress * 100) + "%"));
      } catch (err) {
        if (mine === latest) throw err;
        return;
      }
      if (mine !== latest) return;
      const view = viewOf(answer);
      ns.clear(out);
      if (view) ns.timeseries(out, view, {}); else out.appendChild(el("p", {}, ns.api.resultText(answer)));
    }
    /* A failure shows beside the controls, which stay usable. */
    const guard = (fn) => () => fn().catch((err) => ns.replace(out, ns.shell.errorBox(err)));
    topic.node.addEventListener("change", guard(fields));
    go.addEventListener("click", guard(draw));
    await guard(fields)();
    if (field.node.options.length) await guard(draw)();
  }

  function numbersTable(panel, rows) {
    panel.appendChild(el("dl", { class: "facts" }, rows.filter((r) => r[1] !== null && r[1] !== undefined).map(([k, v]) => [el("dt", {}, k), el("dd", {}, v)])));
  }

  async function trajectory(panel, bag) {
    busy(panel, "Analysing the trajectory…");
    const answer = await call("analyze_trajectory", { bag: bag.id });
    const r = result(answer);
    ns.clear(panel);
    if (r.job) { panel.appendChild(el("p", {}, ns.api.resultText(answer))); return; }
    numbersTable(panel, [
      ["Topic", r.topic], ["Distance", fmt.num(r.distance_2d_m) + " m"], ["Duration", fmt.duration(r.duration_s)],
      ["Mean speed", fmt.num(r.mean_speed_mps) + " m/s"], ["Max speed", fmt.num(r.max_speed_mps) + " m/s"], ["Stops", String((r.stops || []).length)],
    ]);
    const view = viewOf(answer);
    if (view) ns.trajectory(panel, view, {});
  }

  async function scan(panel, bag) {
    const scans = topicsOf(bag, SCAN_TYPES);
    if (!scans.length) { panel.appendChild(el("p", { class: "muted" }, "This bag has no LaserScan topic.")); return; }
    busy(panel, "Reading scans…");
    const answer = await call("analyze_lidar_scan", { bag: bag.id, topic: scans[0].name });
    const r = result(answer);
    ns.clear(panel);
    numbersTable(panel, [["Topic", r.topic], ["Scans", String(r.scans)], ["Closest", r.closest ? fmt.num(r.closest.range_m) + " m at " + fmt.seconds(r.closest.time.offset_s) : "–"]]);
    const view = viewOf(answer);
    if (view) ns.polar(panel, view, {}); else panel.appendChild(el("p", {}, ns.api.resultText(answer)));
  }

  async function logs(panel, bag) {
    if (!topicsOf(bag, LOG_TYPES).length) { panel.appendChild(el("p", { class: "muted" }, "This bag has no log topic (rosgraph_msgs/Log or rcl_interfaces/Log).")); return; }
    busy(panel, "Reading logs…");
    const answer = await call("analyze_logs", { bag: bag.id, limit: 500 });
    const r = result(answer);
    const entries = r.entries || [];
    ns.clear(panel);
    const shown = new Set(LEVELS);
    const list = el("ol", { class: "logs", "aria-label": "log records" });
    const count = el("p", { class: "muted", "aria-live": "polite" });
    const boxes = LEVELS.map((level) => {
      const box = el("input", { type: "checkbox", id: "level-" + level, checked: true, onchange: () => { if (box.checked) shown.add(level); else shown.delete(level); render(); } });
      return el("label", { for: "level-" + level }, box, " " + level);
    });
    function render() {
      const kept = entries.filter((e) => shown.has(e.level));
      count.textContent = kept.length + " of " + r.total + " records" + (r.total > entries.length ? " (first " + entries.length + " read)" : "");
      ns.replace(list, kept.map((e) => el("li", { class: "logline level-" + e.level },
        fmt.seconds(e.time.offset_s) + " [" + e.level + "] " + (e.node || "") + ": " + e.text)));
    }
    panel.append(el("fieldset", { class: "row" }, el("legend", {}, "Levels"), boxes), count, list);
    render();
  }

  function edgeNote(edge) {
    if (!edge) return "";
    return edge.static ? " (static)" : edge.rate_hz ? " (" + fmt.num(edge.rate_hz, 3) + " Hz)" : "";
  }

  function subtree(frame, children, edges) {
    const kids = children[frame] || [];
    return el("li", {}, frame + edgeNote(edges[frame]), kids.length ? el("ul", { class: "tree" }, kids.map((c) => subtree(c, children, edges))) : null);
  }

  async function tf(panel, bag) {
    busy(panel, "Reading TF…");
    const answer = await call("get_tf_tree", { bag: bag.id });
    const r = result(answer);
    ns.clear(panel);
    if (!(r.frames || []).length) { panel.appendChild(el("p", { class: "muted" }, ns.api.resultText(answer))); return; }
    const children = {}, edges = {};
    (r.edges || []).forEach((e) => { (children[e.parent] = children[e.parent] || []).push(e.child); edges[e.child] = e; });
    panel.appendChild(el("p", { class: "muted" }, r.frames.length + " frames from " + (r.topics || []).join(", ")));
    panel.appendChild(el("ul", { class: "tree", id: "tf-tree" }, (r.roots || []).map((root) => subtree(root, children, edges))));
  }

  async function image(panel, bag) {
    const topics = topicsOf(bag, IMAGE_TYPES);
    if (!topics.length) { panel.appendChild(el("p", { class: "muted" }, "This bag has no image topic.")); return; }
    const duration = (bag.summary && bag.summary.duration_s) || 0;
    const topic = select("image-topic", "Topic", topics.map((t) => ({ value: t.name, label: t.name })), topics[0].name);
    const time = el("input", { type: "range", id: "image-time", min: 0, max: duration, step: Math.max(duration / 200, 0.001), value: 0, class: "bv-slider" });
    const when = el("output", { for: "image-time" }, fmt.seconds(0));
    const out = el("div", { id: "image-out" });
    panel.append(el("div", { class: "row" }, topic.field, el("div", { class: "field" }, el("label", { for: "image-time" }, "Time"), time), when), out);
    let pending = null, latest = 0;
    /* Only the answer to the latest request is shown (a slow earlier one must not replace it). */
    async function show() {
      const mine = ++latest;
      const request = { bag: bag.id, topic: topic.node.value, time: Number(time.value) };
      let shownNodes;
      try {
        const answer = await ns.api.callToolOk("get_image_at_time", request);
        const picture = (answer.content || []).find((b) => b.type === "image");
        const r = answer.structuredContent || {};
        shownNodes = [picture ? el("img", { class: "picture", src: "data:" + picture.mimeType + ";base64," + picture.data,
          alt: request.topic + " at " + fmt.seconds(r.time ? r.time.offset_s : request.time) }) : null,
          el("p", { class: "muted" }, ns.api.resultText(answer))];
      } catch (err) {
        shownNodes = [ns.shell.errorBox(err)];
      }
      if (mine === latest) ns.replace(out, shownNodes);
    }
    const later = () => { when.textContent = fmt.seconds(Number(time.value)); clearTimeout(pending); pending = setTimeout(show, 250); };
    time.addEventListener("input", later);
    topic.node.addEventListener("change", later);
    await show();
  }

  ns.bagViews = { plot, trajectory, scan, logs, tf, image };
})(window.BagViews = window.BagViews || {});
