// web/static/coi.js: raystep's service worker. It makes the page cross-origin isolated on any
// static host, so that the page may share its memory with Web Workers (SharedArrayBuffer) and
// render on every core.
//
// A page is cross-origin isolated when its response carries two headers:
//   Cross-Origin-Opener-Policy: same-origin      (no other site's window shares its process)
//   Cross-Origin-Embedder-Policy: require-corp   (it loads nothing another site did not allow)
// A static host (GitHub Pages, a university folder) cannot be told to send them; a service
// worker can add them, because it answers the page's requests itself: this one fetches each
// request as the browser would have and returns the response with the two headers added. The
// page registers it (index.html) and reloads once, the first time, so that its own document
// comes through the worker. Everything raystep's page loads is its own (same origin), so
// require-corp refuses nothing.
//
// The technique is the one of the coi-serviceworker project (MIT; github.com/gzuidhof/
// coi-serviceworker); this is a smaller worker of raystep's own, written for its one page.

self.addEventListener("install", () => self.skipWaiting());
self.addEventListener("activate", (event) => event.waitUntil(self.clients.claim()));

self.addEventListener("fetch", (event) => {
  const request = event.request;
  // A request the worker cannot repeat as it came (Chromium's "only-if-cached" of another
  // origin): left to the browser.
  if (request.cache === "only-if-cached" && request.mode !== "same-origin") return;
  event.respondWith(
    fetch(request).then((response) => {
      // An opaque response (another origin's, no CORS) has no headers to add to.
      if (response.status === 0) return response;
      const headers = new Headers(response.headers);
      headers.set("Cross-Origin-Embedder-Policy", "require-corp");
      headers.set("Cross-Origin-Opener-Policy", "same-origin");
      return new Response(response.body, {
        status: response.status,
        statusText: response.statusText,
        headers,
      });
    })
  );
});
