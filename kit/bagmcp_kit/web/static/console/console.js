/* Start the console: sign-out, hash routing, the admin-only menu entry. */
(function (ns) {
  "use strict";
  document.getElementById("signout").addEventListener("click", () => {
    ns.api.signOut(); location.hash = "#/bags"; ns.shell.show();
  });
  window.addEventListener("hashchange", () => ns.shell.show());
  ns.shell.show();
})(window.BagViews = window.BagViews || {});
