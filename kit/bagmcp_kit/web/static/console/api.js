/* The one client every page (console and Lab) uses: the REST API under /api/v1 and MCP at /mcp, with the
   token the user signed in with. The token lives in this tab's sessionStorage only: never in a URL, a
   cookie or localStorage, and sign-out removes it. */
(function (ns) {
  "use strict";
  const KEY = "bagmcp.token";
  const MCP_VERSION = "2026-07-28";
  const APPS = { "io.modelcontextprotocol/ui": { mimeTypes: ["text/html;profile=mcp-app"] } };
  let nextId = 1;

  class ApiError extends Error {
    constructor(status, code, message) { super(message); this.status = status; this.code = code; }
  }

  const token = () => sessionStorage.getItem(KEY);
  const setToken = (value) => sessionStorage.setItem(KEY, value);
  const signOut = () => sessionStorage.removeItem(KEY);

  function headers(extra) {
    const out = Object.assign({}, extra || {});
    const t = token();
    if (t) out.Authorization = "Bearer " + t;
    return out;
  }

  async function errorOf(response) {
    let code = "http_" + response.status, message = response.statusText || "request failed";
    try {
      const body = await response.json();
      if (body && body.error) { code = body.error.code || code; message = body.error.message || message; }
      else if (body && body.detail) message = typeof body.detail === "string" ? body.detail : JSON.stringify(body.detail);
    } catch (_) { /* not JSON: keep the status text */ }
    if (response.status === 413 && message === response.statusText) message = "the file is larger than this server accepts";
    return new ApiError(response.status, code, message);
  }

  async function request(method, path, body) {
    const init = { method, headers: headers(body === undefined ? {} : { "Content-Type": "application/json" }) };
    if (body !== undefined) init.body = JSON.stringify(body);
    const response = await fetch(path, init);
    if (!response.ok) throw await errorOf(response);
    if (response.status === 204) return null;
    const type = response.headers.get("content-type") || "";
    return type.includes("json") ? response.json() : response.blob();
  }

  /* An upload with progress: {promise, cancel}. onProgress(sentBytes, totalBytes); the promise gives the
     server's answer or rejects with an ApiError (status 0 and code "cancelled" when cancelled). */
  function upload(file, options) {
    const xhr = new XMLHttpRequest();
    const query = new URLSearchParams({ filename: file.name });
    if (options && options.name) query.set("name", options.name);
    const promise = new Promise((resolve, reject) => {
      xhr.open("POST", "/api/v1/bags?" + query.toString());
      const auth = headers();
      if (auth.Authorization) xhr.setRequestHeader("Authorization", auth.Authorization);
      xhr.setRequestHeader("Content-Type", "application/octet-stream");
      xhr.upload.onprogress = (e) => options && options.onProgress && options.onProgress(e.loaded, e.lengthComputable ? e.total : file.size);
      xhr.onload = () => {
        let body = null;
        try { body = JSON.parse(xhr.responseText); } catch (_) { body = null; }
        if (xhr.status >= 200 && xhr.status < 300) resolve(body);
        else {
          const err = body && body.error ? body.error : { code: "http_" + xhr.status, message: xhr.statusText || "upload refused" };
          reject(new ApiError(xhr.status, err.code, err.message));
        }
      };
      xhr.onerror = () => reject(new ApiError(0, "network", "the upload was interrupted (network error)"));
      xhr.onabort = () => reject(new ApiError(0, "cancelled", "upload cancelled"));
      xhr.send(file);
    });
    return { promise, cancel: () => xhr.abort() };
  }

  /* The pieces of a streamed body cut at `separator` ("\n" for JSON lines, "\n\n" for SSE events), each
     given to onPiece as it arrives; onPiece returns true to stop reading. True when it stopped, false at the end. */
  async function eachPiece(response, separator, onPiece) {
    const reader = response.body.getReader();
    const decoder = new TextDecoder();
    let buffer = "";
    for (;;) {
      const { done, value } = await reader.read();
      if (value) buffer += decoder.decode(value, { stream: true });
      let cut;
      while ((cut = buffer.indexOf(separator)) >= 0) {
        const piece = buffer.slice(0, cut); buffer = buffer.slice(cut + separator.length);
        if (onPiece(piece)) { reader.cancel(); return true; }
      }
      if (done) return false;
    }
  }

  /* Read one JSON-RPC answer from a JSON or SSE response; progress notifications go to onProgress. */
  async function rpcAnswer(response, id, onProgress) {
    const type = response.headers.get("content-type") || "";
    if (!type.includes("text/event-stream")) return response.json();
    let answer = null;
    await eachPiece(response, "\n\n", (event) => {
      const data = event.split("\n").filter((l) => l.startsWith("data:")).map((l) => l.slice(5).trim()).join("\n");
      if (!data) return false;
      const message = JSON.parse(data);
      if (message.id === id) { answer = message; return true; }
      if (message.method === "notifications/progress" && onProgress) onProgress(message.params);
      return false;
    });
    if (answer === null) throw new ApiError(502, "no_answer", "the server closed the stream without an answer");
    return answer;
  }

  /* tools/call on the 2026-07-28 protocol (one POST, no session); the CallToolResult in its wire form. */
  async function callTool(name, args, options) {
    const id = nextId++;
    const meta = {
      "io.modelcontextprotocol/protocolVersion": MCP_VERSION,
      "io.modelcontextprotocol/clientInfo": { name: "bagmcp-console", version: "1" },
      "io.modelcontextprotocol/clientCapabilities": { extensions: APPS },
    };
    if (options && options.onProgress) meta.progressToken = "console-" + id;
    const body = { jsonrpc: "2.0", id, method: "tools/call", params: { name, arguments: args || {}, _meta: meta } };
    const response = await fetch("/mcp", {
      method: "POST",
      headers: headers({
        "Content-Type": "application/json", Accept: "application/json, text/event-stream",
        "MCP-Protocol-Version": MCP_VERSION, "Mcp-Method": "tools/call", "Mcp-Name": name,
      }),
      body: JSON.stringify(body),
    });
    if (!response.ok) throw await errorOf(response);
    const message = await rpcAnswer(response, id, options && options.onProgress);
    if (message.error) throw new ApiError(400, "mcp_" + message.error.code, message.error.message);
    return message.result;
  }

  /* A tool result's text, and the error it carries when isError is set. */
  function resultText(result) {
    return (result.content || []).filter((b) => b.type === "text").map((b) => b.text).join("\n");
  }
  async function callToolOk(name, args, options) {
    const result = await callTool(name, args, options);
    if (result.isError) throw new ApiError(400, "tool_error", resultText(result).replace(/^Error executing tool \S+: /, ""));
    return result;
  }

  ns.api = {
    open: false, ApiError, token, setToken, signOut, request, upload, callTool, callToolOk, resultText, eachPiece,
    get: (path) => request("GET", path), del: (path) => request("DELETE", path), post: (path, body) => request("POST", path, body),
  };
})(window.BagViews = window.BagViews || {});
