/* The console's frame: pages register by name, the hash (#/bags, #/bag/<id>, ...) picks one, and a page
   may return a function that stops what it started (polling) when the user leaves it. */
(function (ns) {
  "use strict";
  const { el } = ns;
  const pages = {};
  let leave = null;
  let toastTimer = null;

  function page(name, render) { pages[name] = render; }

  function toast(message) {
    const box = document.getElementById("toast");
    box.textContent = message;
    clearTimeout(toastTimer);
    toastTimer = setTimeout(() => { box.textContent = ""; }, 4000);
  }

  function errorBox(err) {
    return el("p", { class: "error", role: "alert" }, err && err.message ? err.message : String(err));
  }

  function parseHash() {
    const parts = (location.hash || "#/bags").replace(/^#\/?/, "").split("/").map(decodeURIComponent);
    return { name: parts[0] || "bags", args: parts.slice(1) };
  }

  async function show() {
    if (leave) { try { leave(); } catch (_) { /* a page's cleanup never blocks the next page */ } leave = null; }
    const main = ns.clear(document.getElementById("main"));
    const signedIn = Boolean(ns.api.token()) || ns.api.open;
    document.getElementById("nav").hidden = !signedIn;
    document.getElementById("signout").hidden = !ns.api.token();
    const { name, args } = signedIn ? parseHash() : { name: "signin", args: [] };
    document.querySelectorAll("nav a").forEach((a) => {
      if (a.getAttribute("href") === "#/" + name) a.setAttribute("aria-current", "page"); else a.removeAttribute("aria-current");
    });
    const render = pages[name] || pages.bags;
    try {
      const cleanup = await render(main, args);
      if (typeof cleanup === "function") leave = cleanup;
    } catch (err) {
      if (err && err.status === 401) { ns.api.signOut(); toast("Your token is no longer valid; sign in again."); show(); return; }
      main.appendChild(errorBox(err));
    }
  }

  /* Poll fn every periodMs while the page is shown; returns the stop function. */
  function every(periodMs, fn) {
    let stopped = false, timer = null;
    const tick = async () => {
      if (stopped) return;
      try { await fn(); } catch (_) { /* the page shows its own errors */ }
      if (!stopped) timer = setTimeout(tick, periodMs);
    };
    timer = setTimeout(tick, periodMs);
    return () => { stopped = true; clearTimeout(timer); };
  }

  ns.shell = { page, show, toast, errorBox, every, go: (hash) => { location.hash = hash; } };
})(window.BagViews = window.BagViews || {});
