/* The view side of MCP Apps (extension io.modelcontextprotocol/ui): JSON-RPC 2.0 over postMessage with
   the host window. The view asks ui/initialize, says ui/notifications/initialized, then hears
   ui/notifications/tool-input ({arguments}) and ui/notifications/tool-result (a CallToolResult), and
   reports its height with ui/notifications/size-changed. Messages from any window but the parent are
   ignored. */
(function (ns) {
  "use strict";
  const PROTOCOL = "2026-01-26";
  const handlers = {};
  const pending = new Map();
  let nextId = 1;

  function post(message) { window.parent.postMessage(Object.assign({ jsonrpc: "2.0" }, message), "*"); }

  function request(method, params) {
    const id = nextId++;
    post({ id, method, params });
    return new Promise((resolve, reject) => pending.set(id, { resolve, reject }));
  }

  function notify(method, params) { post({ method, params: params || {} }); }

  window.addEventListener("message", (event) => {
    if (event.source !== window.parent) return;
    const message = event.data;
    if (!message || message.jsonrpc !== "2.0") return;
    if (message.id !== undefined && pending.has(message.id) && !message.method) {
      const waiter = pending.get(message.id); pending.delete(message.id);
      if (message.error) waiter.reject(new Error(message.error.message || "host error")); else waiter.resolve(message.result);
      return;
    }
    const handler = handlers[message.method];
    if (handler) {
      const answer = handler(message.params || {});
      if (message.id !== undefined) post({ id: message.id, result: answer || {} });
    } else if (message.id !== undefined) {
      post({ id: message.id, error: { code: -32601, message: "method not supported by this view: " + message.method } });
    }
  });

  function reportSize() {
    const height = Math.ceil(document.documentElement.scrollHeight);
    notify("ui/notifications/size-changed", { width: Math.ceil(document.documentElement.scrollWidth), height });
  }

  async function connect(appInfo) {
    const result = await request("ui/initialize", {
      protocolVersion: PROTOCOL, appInfo, appCapabilities: {},
    });
    notify("ui/notifications/initialized", {});
    if (window.ResizeObserver) new ResizeObserver(reportSize).observe(document.body);
    return result || {};
  }

  function on(method, handler) { handlers[method] = handler; }

  ns.apps = { connect, on, request, notify, reportSize, PROTOCOL };
})(window.BagViews = window.BagViews || {});
