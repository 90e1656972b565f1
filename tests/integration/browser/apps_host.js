/* A minimal MCP Apps host for the viewer tests: it answers ui/initialize, waits for
   ui/notifications/initialized, then sends ui/notifications/tool-input and ui/notifications/tool-result
   with the real tool call in window.CALL ({arguments, result}), and resizes the frame as the view asks.
   Every message from the view is kept in window.hostLog for the test to read. As a real host does, it
   listens before it creates the frame, so the view's first message cannot be missed. */
(function () {
  "use strict";
  const frame = document.createElement("iframe");
  const log = [];
  window.hostLog = log;
  const send = (message) => frame.contentWindow.postMessage(Object.assign({ jsonrpc: "2.0" }, message), "*");
  window.addEventListener("message", (event) => {
    if (event.source !== frame.contentWindow) return;
    const message = event.data;
    log.push(message);
    if (message.method === "ui/initialize") {
      send({ id: message.id, result: {
        protocolVersion: message.params.protocolVersion, hostInfo: { name: "bagmcp-test-host", version: "1" },
        hostCapabilities: {}, hostContext: { theme: "light", displayMode: "inline" },
      } });
    } else if (message.method === "ui/notifications/initialized") {
      send({ method: "ui/notifications/tool-input", params: { arguments: window.CALL.arguments } });
      send({ method: "ui/notifications/tool-result", params: window.CALL.result });
    } else if (message.method === "ui/notifications/size-changed") {
      frame.style.height = Math.min(2000, message.params.height + 4) + "px";
    }
  });
  Object.assign(frame, { id: "viewer", title: "bagmcp viewer", src: "/viewer.html" });
  frame.setAttribute("sandbox", "allow-scripts");
  document.querySelector("main").appendChild(frame);
})();
