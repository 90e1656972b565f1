/* The Lab page: the model form (remembered in this tab), the Chat and Benchmark tabs. */
(function (ns) {
  "use strict";

  function select(tab) {
    for (const name of ["chat", "bench"]) {
      const on = name === tab;
      const button = document.getElementById("tab-" + name);
      button.setAttribute("aria-selected", String(on));
      button.tabIndex = on ? 0 : -1;
      document.getElementById("panel-" + name).hidden = !on;
    }
  }

  document.addEventListener("DOMContentLoaded", () => {
    ns.lab.restore();
    document.getElementById("model-form").addEventListener("change", ns.lab.remember);
    document.getElementById("model-form").addEventListener("submit", (event) => event.preventDefault());
    document.getElementById("tab-chat").addEventListener("click", () => select("chat"));
    document.getElementById("tab-bench").addEventListener("click", () => select("bench"));
    ns.labChat();
    ns.labBench();
  });
})(window.BagViews = window.BagViews || {});
