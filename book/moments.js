// The lessons' live moments (book/build.py): each step link moves its figure's embedded raystep
// to that step (only the address's #… changes, so the app goes there without loading again);
// where the browser has no WebAssembly, the figure drawn by `raystep diagram` replaces the app.
(function () {
  "use strict";
  var wasm = typeof WebAssembly === "object" && typeof WebAssembly.instantiate === "function";
  document.querySelectorAll("figure.raystep-moment").forEach(function (figure) {
    var frame = figure.querySelector("iframe.raystep-embed");
    var fallback = figure.querySelector("img.raystep-fallback");
    if (!wasm && frame) {
      frame.remove();
      frame = null;
      if (fallback) {
        fallback.hidden = false;
      }
    }
    figure.querySelectorAll("a.raystep-step").forEach(function (link) {
      link.addEventListener("click", function (event) {
        if (!frame) {
          return; // no live app here: the link opens the full app instead
        }
        event.preventDefault();
        var base = frame.getAttribute("src").replace(/&step=\d+$/, "");
        frame.setAttribute("src", base + "&step=" + link.dataset.step);
        frame.scrollIntoView({ block: "nearest" });
      });
    });
  });
})();
