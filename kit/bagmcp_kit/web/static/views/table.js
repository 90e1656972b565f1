/* A table of rows (objects): columns {key, label, format?(value, row) -> string|Node, numeric?}; click a
   header to sort. Cell text goes through el(), so names from bags show as text. */
(function (ns) {
  "use strict";
  const { el } = ns;

  function table(container, columns, rows, options) {
    let sortKey = (options && options.sortKey) || null, ascending = true;
    const body = el("tbody");
    const caption = options && options.caption ? el("caption", {}, options.caption) : null;
    const headers = columns.map((c) => el("th", { scope: "col", class: c.numeric ? "bv-num" : null },
      c.label ? el("button", { type: "button", class: "bv-sort", onclick: () => sortBy(c.key) }, c.label)
        : el("span", { class: "bv-sr" }, "actions")));
    const node = el("table", { class: "bv-table" }, caption, el("thead", {}, el("tr", {}, headers)), body);
    container.appendChild(el("div", { class: "bv-table-wrap" }, node));
    function sortBy(key) {
      ascending = key === sortKey ? !ascending : true; sortKey = key; render();
    }
    function render() {
      const sorted = rows.slice();
      if (sortKey) {
        sorted.sort((a, b) => {
          const x = a[sortKey], y = b[sortKey];
          const order = typeof x === "number" && typeof y === "number" ? x - y : String(x).localeCompare(String(y));
          return ascending ? order : -order;
        });
      }
      ns.clear(body);
      sorted.forEach((row) => body.appendChild(el("tr", {}, columns.map((c) => {
        const shown = c.format ? c.format(row[c.key], row) : row[c.key];
        return el("td", { class: c.numeric ? "bv-num" : null }, shown === undefined || shown === null ? "–" : shown);
      }))));
    }
    render();
    return { node, update: (next) => { rows = next; render(); } };
  }

  ns.table = table;
})(window.BagViews = window.BagViews || {});
