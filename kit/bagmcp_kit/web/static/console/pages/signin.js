/* Sign in with a token: it is checked against the server (GET /api/v1/bags) before it is kept in this
   tab's sessionStorage; a wrong token is refused with the server's message and never stored. */
(function (ns) {
  "use strict";
  const { el } = ns;

  /* What this token may do (GET /api/v1/session); the Tokens page shows only to admins of a server that
     manages tokens. */
  ns.consoleAdmin = async function refreshAdmin() {
    const session = await ns.api.get("/api/v1/session");
    const admin = session.tokens_managed && session.scopes.includes("admin");
    document.getElementById("nav-tokens").hidden = !admin;
    return admin;
  };

  ns.shell.page("signin", (main) => {
    const input = el("input", { id: "token", name: "token", type: "password", autocomplete: "off", required: true, spellcheck: "false" });
    const message = el("p", { id: "signin-message", role: "alert", class: "error" });
    const form = el("form", { class: "card signin", "aria-labelledby": "signin-title" },
      el("h1", { id: "signin-title" }, "Sign in to bagmcp"),
      el("p", { class: "muted" }, "Paste an API token (bagmcp token create, or the one `bagmcp serve --token` was given). It stays in this browser tab only."),
      el("div", { class: "field" }, el("label", { for: "token" }, "Token"), input),
      message,
      el("button", { type: "submit", class: "primary" }, "Sign in"));
    form.addEventListener("submit", async (event) => {
      event.preventDefault();
      message.textContent = "";
      const value = input.value.trim();
      if (!value) { message.textContent = "Enter a token."; return; }
      ns.api.setToken(value);
      try {
        await ns.api.get("/api/v1/session");
      } catch (err) {
        ns.api.signOut();
        message.textContent = err.status === 401 ? "This token is not valid here: check it, or ask an admin for a new one." : err.message;
        return;
      }
      await ns.consoleAdmin();
      location.hash = "#/bags";
      ns.shell.show();
    });
    main.appendChild(form);
    input.focus();
  });
})(window.BagViews = window.BagViews || {});
