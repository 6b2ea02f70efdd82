// The lessons' live moments (book/build.py). Each figure holds the figure `raystep diagram` drew
// of its moment and an app frame that is not loaded yet (its address in data-src). Where the
// browser runs WebAssembly, a figure coming within a screen of the window loads its app (one
// wasm instance per moment, only for the moments the reader reaches) and the app takes the
// drawing's place; each step link then moves that app to its step (only the address's #…
// changes, so the app goes there without loading again). Without WebAssembly or scripts, the
// drawing stays.
(function () {
  "use strict";
  var wasm = typeof WebAssembly === "object" && typeof WebAssembly.instantiate === "function";
  if (!wasm) {
    return;
  }
  function start(figure) {
    var frame = figure.querySelector("iframe.raystep-embed");
    if (!frame || frame.getAttribute("src")) {
      return frame;
    }
    frame.setAttribute("src", frame.dataset.src);
    frame.hidden = false;
    var drawing = figure.querySelector("img.raystep-fallback");
    if (drawing) {
      drawing.hidden = true;
    }
    return frame;
  }
  var figures = document.querySelectorAll("figure.raystep-moment");
  var near = "IntersectionObserver" in window ? new IntersectionObserver(function (entries) {
    entries.forEach(function (e) {
      if (e.isIntersecting) {
        start(e.target);
        near.unobserve(e.target);
      }
    });
  }, { rootMargin: "100% 0px" }) : null;
  figures.forEach(function (figure) {
    if (near) {
      near.observe(figure);
    } else {
      start(figure);
    }
    figure.querySelectorAll("a.raystep-step").forEach(function (link) {
      link.addEventListener("click", function (event) {
        event.preventDefault();
        var frame = start(figure);
        var base = frame.dataset.src.replace(/&step=\d+$/, "");
        frame.dataset.src = base + "&step=" + link.dataset.step;
        frame.setAttribute("src", frame.dataset.src);
        frame.scrollIntoView({ block: "nearest" });
      });
    });
  });
})();
