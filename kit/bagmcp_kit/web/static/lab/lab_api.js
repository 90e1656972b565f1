/* The Lab's calls: the model choice from the form (the API key read from this tab's sessionStorage and sent
   only in the body of requests to this server's /api/v1/lab), chat turns read as a stream of JSON lines. */
(function (ns) {
  "use strict";
  const KEY = "bagmcp.lab.key";
  const FIELDS = { provider: "lab-provider", model: "lab-model", base_url: "lab-base-url" };

  function remember() {
    for (const id of Object.values(FIELDS)) sessionStorage.setItem("bagmcp.lab." + id, document.getElementById(id).value);
    const key = document.getElementById("lab-key").value;
    if (key) sessionStorage.setItem(KEY, key); else sessionStorage.removeItem(KEY);
    const token = document.getElementById("lab-token").value.trim();
    if (token) ns.api.setToken(token); else ns.api.signOut();
  }

  function restore() {
    for (const id of Object.values(FIELDS)) {
      const value = sessionStorage.getItem("bagmcp.lab." + id);
      if (value !== null) document.getElementById(id).value = value;
    }
    document.getElementById("lab-key").value = sessionStorage.getItem(KEY) || "";
    document.getElementById("lab-token").value = ns.api.token() || "";
  }

  function choice() {
    remember();
    const body = {
      provider: document.getElementById(FIELDS.provider).value,
      model: document.getElementById(FIELDS.model).value.trim(),
    };
    const base = document.getElementById(FIELDS.base_url).value.trim();
    if (base) body.base_url = base;
    const key = sessionStorage.getItem(KEY);
    if (key) body.api_key = key;
    if (!body.model) throw new Error("Enter a model name first.");
    return body;
  }

  /* POST /api/v1/lab/chat; onEvent(event) for each line until the stream ends. */
  async function chat(body, onEvent) {
    const headers = { "Content-Type": "application/json" };
    const token = ns.api.token();
    if (token) headers.Authorization = "Bearer " + token;
    const response = await fetch("/api/v1/lab/chat", { method: "POST", headers, body: JSON.stringify(body) });
    if (!response.ok) {
      let message = response.statusText;
      try { message = (await response.json()).error.message; } catch (_) { /* keep the status text */ }
      throw new ns.api.ApiError(response.status, "lab", message);
    }
    await ns.api.eachPiece(response, "\n", (line) => {
      if (line.trim()) onEvent(JSON.parse(line));
      return false;
    });
  }

  /* A file from the Lab's API (figures, results.json) as an object URL; the token goes in a header. */
  async function blobUrl(path) {
    const blob = await ns.api.get(path);
    return URL.createObjectURL(blob instanceof Blob ? blob : new Blob([JSON.stringify(blob, null, 2)], { type: "application/json" }));
  }

  ns.lab = { remember, restore, choice, chat, blobUrl };
})(window.BagViews = window.BagViews || {});
