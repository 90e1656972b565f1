/* The chat tab: each turn is the agent loop on the server; every step is shown as it happens: the model's
   text, each tool call with its arguments, time, result text, plots and images, and progress of long work. */
(function (ns) {
  "use strict";
  const { el } = ns;
  const history = [];

  function item(kind, ...children) {
    const node = el("li", { class: "lab-" + kind }, children);
    document.getElementById("chat-log").appendChild(node);
    node.scrollIntoView({ block: "nearest" });
    return node;
  }

  function step(event) {
    const args = JSON.stringify(event.arguments === null ? "(arguments were not JSON)" : event.arguments, null, 1);
    const node = item("step", el("div", { class: "lab-step-head" },
      el("strong", {}, event.name), " ", el("code", { class: "lab-args" }, args),
      el("span", { class: "lab-step-state muted" }, "running…")));
    node.dataset.call = event.id;
    return node;
  }

  function answer(node, event) {
    const state = node.querySelector(".lab-step-state");
    state.textContent = (event.is_error ? "error · " : "") + Math.round(event.ms) + " ms";
    node.classList.toggle("lab-step-error", event.is_error);
    const text = event.text.split("\n")[0];
    node.appendChild(el("p", { class: "lab-result" }, text));
    for (const image of event.images) {
      if (!/^image\/(png|jpeg|gif|webp)$/.test(image.mime_type)) continue;
      node.appendChild(el("img", { class: "lab-image", alt: event.name + " image", src: "data:" + image.mime_type + ";base64," + image.data }));
    }
    if (event.text.includes("\n")) {
      node.appendChild(el("details", {}, el("summary", {}, "Full answer"), el("pre", {}, event.text)));
    }
  }

  async function send(prompt) {
    const body = Object.assign(ns.lab.choice(), { prompt, history: history.slice(-20) });
    item("user", prompt);
    const steps = {};
    let final = null;
    await ns.lab.chat(body, (event) => {
      if (event.kind === "call") steps[event.id] = step(event);
      else if (event.kind === "answer" && steps[event.id]) answer(steps[event.id], event);
      else if (event.kind === "progress" && steps[event.id]) {
        const total = event.total ? " / " + event.total : "";
        steps[event.id].querySelector(".lab-step-state").textContent = "running… " + event.done + total + (event.message ? " " + event.message : "");
      } else if (event.kind === "text") item("reply", event.text);
      else if (event.kind === "done") {
        final = event;
        item("meta", event.tool_calls.length + " tool calls · " + event.latency_s.toFixed(1) + " s · " +
          event.input_tokens + " in / " + event.output_tokens + " out tokens" + (event.stopped ? " · " + event.stopped : ""));
      } else if (event.kind === "error") item("error", event.message);
    });
    history.push({ role: "user", text: prompt });
    if (final && final.final_answer) history.push({ role: "assistant", text: final.final_answer });
  }

  ns.labChat = function setUpChat() {
    const form = document.getElementById("chat-form");
    const input = document.getElementById("chat-input");
    const button = document.getElementById("chat-send");
    form.addEventListener("submit", async (event) => {
      event.preventDefault();
      const prompt = input.value.trim();
      if (!prompt) return;
      button.disabled = true;
      try {
        await send(prompt);
        input.value = "";
      } catch (err) {
        item("error", err.message);
      } finally {
        button.disabled = false;
      }
    });
  };
})(window.BagViews = window.BagViews || {});
