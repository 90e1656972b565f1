/* Start the console: sign-out, hash routing, the admin-only menu entry. */
(function (ns) {
  "use strict";
  document.getElementById("signout").addEventListener("click", () => {
    ns.api.signOut(); location.hash = "#/bags"; ns.shell.show();
  });
  window.addEventListener("hashchange", () => ns.shell.show());
  /* `bagmcp serve` on loopback without --token asks for none: then there is nothing to sign in with. */
  fetch("/console.json").then((r) => r.json()).then((settings) => { ns.api.open = settings.token_required === false; })
    .catch(() => { ns.api.open = false; }).finally(() => ns.shell.show());
})(window.BagViews = window.BagViews || {});
