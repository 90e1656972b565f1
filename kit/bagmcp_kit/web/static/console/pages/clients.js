/* Client configuration, filled in with this server's URL: the same snippets `bagmcp config --client ...`
   prints (cli/bagmcp_cli/surface_commands.py; a browser test checks they are equal). */
(function (ns) {
  "use strict";
  const { el } = ns;
  const MCP_REMOTE = "mcp-remote@0.15.1";
  const PLACEHOLDER = "YOUR_TOKEN";

  function shellQuote(word) { return /^[A-Za-z0-9@%+=:,./_-]+$/.test(word) ? word : "'" + word.replace(/'/g, "'\"'\"'") + "'"; }

  function snippets(url, token) {
    const local = /^http:\/\/(127\.0\.0\.1|localhost)/.test(url);
    const remote = ["-y", MCP_REMOTE, url, "--header", "Authorization: Bearer ${BAGMCP_TOKEN}"].concat(url.startsWith("http://") && !local ? ["--allow-http"] : []);
    return {
      "claude-code": ["claude", "mcp", "add", "--transport", "http", "bagmcp", url, "--header", "Authorization: Bearer " + token].map(shellQuote).join(" "),
      cursor: JSON.stringify({ mcpServers: { bagmcp: { url, headers: { Authorization: "Bearer " + token } } } }, null, 2),
      desktop: JSON.stringify({ mcpServers: { bagmcp: { command: "npx", args: remote, env: { BAGMCP_TOKEN: token } } } }, null, 2),
    };
  }

  ns.clientSnippets = snippets;

  ns.shell.page("clients", (main) => {
    const url = location.origin + "/mcp";
    const texts = snippets(url, PLACEHOLDER);
    main.appendChild(el("h1", {}, "Connect a client"));
    main.appendChild(el("p", {}, "This server's MCP URL is ", el("code", { id: "mcp-url" }, url), ". Replace " + PLACEHOLDER + " with your token (an admin makes one on the Tokens page or with `bagmcp token create`)."));
    [["claude-code", "Claude Code", "Run in a shell:"], ["desktop", "Claude Desktop", "Add to claude_desktop_config.json (it bridges with mcp-remote, which needs Node.js):"],
      ["cursor", "Cursor", "Add to ~/.cursor/mcp.json:"]].forEach(([key, title, how]) => {
      main.appendChild(el("section", { class: "card", "aria-labelledby": "client-" + key },
        el("h2", { id: "client-" + key }, title), el("p", {}, how), el("pre", { class: "snippet", id: "snippet-" + key, tabindex: "0" }, texts[key])));
    });
  });
})(window.BagViews = window.BagViews || {});
