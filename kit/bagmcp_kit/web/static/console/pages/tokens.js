/* Tokens, for admins: create one (scopes, tool profile, expiry; the secret is shown once), list them,
   revoke one. The server checks the admin scope on every call; this page only shows what it answers. */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;
  const SCOPES = ["read", "upload", "delete", "admin"];

  function form(onCreated) {
    const name = el("input", { id: "token-name", required: true, autocomplete: "off"});
    const profile = el("select", { id: "token-profile" }, el("option", { value: "" }, "every tool"), el("option", { value: "core" }, "core (small models)"), el("option", { value: "full" }, "full"));
    const expires = el("input", { id: "token-expires", placeholder: "e.g. 30d, 12h; empty: never", autocomplete: "off" });
    const scopes = SCOPES.map((s) => el("label", { for: "scope-" + s }, el("input", { type: "checkbox", id: "scope-" + s, value: s, checked: s === "read" }), " " + s));
    const message = el("div", { role: "alert" });
    const node = el("form", { class: "card", "aria-labelledby": "new-token-title" },
      el("h2", { id: "new-token-title" }, "New token"),
      el("div", { class: "field" }, el("label", { for: "token-name" }, "Name"), name),
      el("fieldset", { class: "row" }, el("legend", {}, "Scopes"), scopes),
      el("div", { class: "field" }, el("label", { for: "token-profile" }, "Tool profile"), profile),
      el("div", { class: "field" }, el("label", { for: "token-expires" }, "Expires after"), expires),
      el("button", { type: "submit", class: "primary" }, "Create token"), message);
    node.addEventListener("submit", async (event) => {
      event.preventDefault();
      const body = {
        name: name.value.trim(), scopes: SCOPES.filter((s) => node.querySelector("#scope-" + s).checked),
        profile: profile.value || null, expires: expires.value.trim() || null,
      };
      try {
        const made = await ns.api.post("/api/v1/tokens", body);
        const secret = el("input", { id: "new-secret", readonly: true, value: made.token, "aria-label": "the new token's secret" });
        ns.replace(message, el("div", { class: "ok" }, el("p", {}, "Created " + made.name + ". Copy the secret now: it is not shown again."), secret));
        secret.select();
        name.value = "";
        onCreated();
      } catch (err) {
        ns.replace(message, el("p", { class: "error" }, err.message));
      }
    });
    return node;
  }

  ns.shell.page("tokens", async (main) => {
    main.appendChild(el("h1", {}, "Tokens"));
    const listBox = el("div", { id: "token-list" });
    let table = null;
    async function refresh() {
      const tokens = await ns.api.get("/api/v1/tokens");
      const columns = [
        { key: "name", label: "Name" },
        { key: "scopes", label: "Scopes", format: (v) => v.join(", ") },
        { key: "profile", label: "Profile", format: (v) => v || "every tool" },
        { key: "created_at", label: "Created", format: (v) => fmt.date(v) },
        { key: "expires_at", label: "Expires", format: (v, row) => (row.expired ? "expired " : "") + (v ? fmt.date(v) : "never") },
        { key: "name", label: "", format: (v) => el("button", { type: "button", class: "danger", "aria-label": "revoke " + v, onclick: () => revoke(v) }, "Revoke") },
      ];
      if (!table) table = ns.table(listBox, columns, tokens, { caption: tokens.length + " tokens" }); else table.update(tokens);
    }
    async function revoke(name) {
      if (!window.confirm("Revoke the token “" + name + "”? Clients using it stop working at once.")) return;
      try { await ns.api.del("/api/v1/tokens/" + encodeURIComponent(name)); ns.shell.toast("Revoked " + name); await refresh(); } catch (err) { ns.shell.toast(err.message); }
    }
    try {
      await refresh();
    } catch (err) {
      main.appendChild(el("p", { class: "error", role: "alert" }, err.status === 403 ? "Managing tokens needs a token with the admin scope." : err.message));
      return;
    }
    main.append(form(refresh), el("h2", {}, "Tokens on this server"), listBox);
  });
})(window.BagViews = window.BagViews || {});
