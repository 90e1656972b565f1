/* Uploading bags: drop files on the box or pick them; each shows a progress bar while it is sent, can be
   cancelled, and ends with the server's answer: stored (ingest goes on in the list), a duplicate, or the
   server's reason for refusing it (too big, not a bag, an archive that unpacks too far). */
(function (ns) {
  "use strict";
  const { el, fmt } = ns;

  function send(file, list, done) {
    const bar = el("progress", { max: 1, value: 0, "aria-label": "upload of " + file.name });
    const status = el("span", { class: "muted" }, "starting…");
    const cancel = el("button", { type: "button" }, "Cancel");
    const item = el("li", { class: "upload-item" }, el("strong", {}, file.name), " (" + fmt.bytes(file.size) + ") ", cancel, bar, status);
    list.appendChild(item);
    const job = ns.api.upload(file, {
      onProgress: (sent, total) => {
        bar.value = total ? sent / total : 0;
        status.textContent = fmt.bytes(sent) + " of " + fmt.bytes(total) + " sent";
      },
    });
    cancel.addEventListener("click", () => job.cancel());
    job.promise.then((answer) => {
      bar.value = 1;
      status.className = "ok";
      status.textContent = answer.duplicate ? "already stored as " + answer.bag.name : "stored as " + answer.bag.name + "; ingest follows in the list";
      done();
    }).catch((err) => {
      status.className = "error";
      status.setAttribute("role", "alert");
      status.textContent = err.code === "cancelled" ? "cancelled" : "refused: " + err.message;
    }).finally(() => cancel.remove());
  }

  ns.uploadBox = function uploadBox(box, done) {
    const picker = el("input", { type: "file", id: "upload-file", multiple: true});
    const list = el("ul", { class: "uploads", "aria-label": "uploads" });
    const zone = el("div", { class: "dropzone", id: "dropzone" },
      el("p", {}, "Drop bag files here (.bag, .mcap, .db3, .ulg, .bin, or a ROS 2 bag directory as .zip/.tar)"),
      el("label", { for: "upload-file" }, "or choose files: "), picker);
    box.append(el("h2", { id: "upload-title" }, "Upload"), zone, list);
    const take = (files) => Array.from(files).forEach((f) => send(f, list, done));
    picker.addEventListener("change", () => { take(picker.files); picker.value = ""; });
    zone.addEventListener("dragover", (e) => { e.preventDefault(); zone.classList.add("over"); });
    zone.addEventListener("dragleave", () => zone.classList.remove("over"));
    zone.addEventListener("drop", (e) => { e.preventDefault(); zone.classList.remove("over"); take(e.dataTransfer.files); });
  };
})(window.BagViews = window.BagViews || {});
