#!/usr/bin/env python3
"""Checks the built book's live moments in headless Chromium (Playwright), as a reader meets them.

For each of three pages — two lessons and the app's chapter (or those named with --page): the
page opens; scrolled to its first moment, the embedded raystep
reaches the moment's scene, pixel and step (as the figure names them) (read from the app's hidden `#raystep-status`,
as web/check.py reads it) with its render done; the figure's link to another step moves it
there; and nothing on the page or in the app logs an error. The first page is checked twice:
as a plain static host serves it (the embedded app is not cross-origin isolated and renders on
one thread), and from a host that sends the isolation headers (the embedded app is isolated and
renders on Web Workers, one per core but the page's own). Then the embeds are lazy
(book/moments.js loads a moment's app when the reader comes within a screen of it): on lesson
20, whose last moment is far below the window, that one has started no app before the reader
scrolls there.

Usage: book/check_embeds.py [--book target/book] [--chromium PATH] [--page PATH ...] SHOTS_DIR
Build the book with the app first: book/build.py --app dist --raystep BIN.
"""

import argparse
import functools
import http.server
import os
import sys
import threading
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGES = ["lessons/02-ray-sphere", "lessons/20-instances", "book/app"]
# SwiftShader renders WebGL on the CPU (as in web/check.py).
CHROMIUM_ARGS = ["--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                 "--ignore-gpu-blocklist"]
# Console messages that are not failures, with the reason (as in web/check.py).
ALLOWED = ["No available adapters"]  # no WebGPU here: eframe falls back to WebGL2


class Quiet(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".wasm": "application/wasm", ".js": "text/javascript"}

    def log_message(self, *args):
        pass


class Isolating(Quiet):
    """The book served as a host that sends the cross-origin isolation headers does: its pages
    and their embedded apps are isolated, and the apps render on Web Workers."""

    def end_headers(self):
        self.send_header("Cross-Origin-Opener-Policy", "same-origin")
        self.send_header("Cross-Origin-Embedder-Policy", "require-corp")
        super().end_headers()


def serve(book, handler):
    """Serves book on a free loopback port in a thread; returns (server, url)."""
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(handler, directory=str(book)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_address[1]}/"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--book", default=str(ROOT / "target" / "book"))
    ap.add_argument("--chromium", help="the Chromium binary (default: Playwright's own)")
    ap.add_argument("--page", action="append",
                    help="a page of the book, its path without .html (lessons/18-textures)")
    ap.add_argument("shots")
    args = ap.parse_args()
    book = Path(args.book)
    if not (book / "app" / "index.html").exists():
        sys.exit(f"{book} has no app/: build the book with --app")
    os.makedirs(args.shots, exist_ok=True)
    server, plain_url = serve(book, Quiet)
    isolating, isolated_url = serve(book, Isolating)
    from playwright.sync_api import sync_playwright

    failures = []
    with sync_playwright() as p:
        launch = {"args": CHROMIUM_ARGS}
        if args.chromium:
            launch["executable_path"] = args.chromium
        browser = p.chromium.launch(**launch)
        # Every page as a plain static host serves it (the embedded apps on one thread: a frame
        # is isolated only inside an isolated page), and the first again from a host that
        # isolates the book (the embedded app then renders on Web Workers).
        first = (args.page or PAGES)[0]
        for lesson, url, isolated in ([(p, plain_url, False) for p in args.page or PAGES]
                                      + [(first, isolated_url, True)]):
            page = browser.new_page(viewport={"width": 1100, "height": 800})
            errors = []
            page.on("pageerror", lambda e: errors.append(f"uncaught exception: {e}"))
            page.on("console", lambda m: m.type == "error" and not any(
                a in m.text for a in ALLOWED) and errors.append(f"console error: {m.text}"))
            start = time.monotonic()
            page.goto(f"{url}{lesson}.html", wait_until="load")
            frame_el = page.locator("iframe.raystep-embed").first
            # What the figure says it shows: its scene and pixel, the step its app opens on and
            # the steps it links to.
            fig = page.locator("figure.raystep-moment").first
            name, pixel = fig.get_attribute("data-scene"), fig.get_attribute("data-pixel")
            x, y = (int(v) for v in pixel.split(","))
            src = frame_el.get_attribute("data-src")
            steps = [int(src.rsplit("&step=", 1)[1])] + [
                int(a.get_attribute("data-step"))
                for a in fig.locator("a.raystep-step").all()][1:]
            title = tomllib.loads((ROOT / "scenes" / f"{name}.toml").read_text(
                encoding="utf-8")).get("title")
            def status():
                f = frame_el.element_handle().content_frame()
                if f is None:
                    return None
                return f.evaluate("() => { const e = document.getElementById('raystep-status');"
                                  " return e ? Object.assign({}, e.dataset) : null; }")

            def wait(cond, what, timeout=90):
                end = time.monotonic() + timeout
                while time.monotonic() < end:
                    try:
                        s = status()
                    except Exception:  # the frame navigating
                        s = None
                    if s and cond(s):
                        return s
                    time.sleep(0.2)
                page.screenshot(path=os.path.join(args.shots, f"failed-{lesson}.png"))
                raise TimeoutError(f"{lesson}: {what}: not within {timeout} s (status: {s})")

            try:
                fig.scroll_into_view_if_needed()
                s = wait(lambda s: s.get("ready") == "1" and s.get("pixel") == f"{x},{y}"
                         and s.get("step") == str(steps[0]),
                         f"the moment (pixel {x},{y}, step {steps[0]})")
                if title and s.get("scene") != title:
                    raise AssertionError(f"{lesson}: the moment shows {s.get('scene')!r}, "
                                         f"not {title!r}")
                took = time.monotonic() - start
                inner = frame_el.element_handle().content_frame()
                frame_isolated = inner.evaluate("() => self.crossOriginIsolated")
                if frame_isolated != isolated:
                    raise AssertionError(f"{lesson}: the embedded app is "
                                         f"{'' if frame_isolated else 'not '}cross-origin "
                                         f"isolated, served {'with' if isolated else 'without'}"
                                         " the headers")
                workers = inner.evaluate("() => window.raystepThreads.workers")
                cores = inner.evaluate("() => navigator.hardwareConcurrency")
                want = max(1, cores - 1) if isolated and cores > 1 else 0
                if workers != want or s.get("threads") != str(max(1, workers)):
                    raise AssertionError(f"{lesson}: the embedded app rendered on "
                                         f"{s.get('threads')} threads with {workers} Web "
                                         f"Workers, not {want} ({cores} cores)")
                if len(steps) > 1:
                    page.locator(f"figure.raystep-moment a.raystep-step[data-step='{steps[-1]}']"
                                 ).first.click()
                    wait(lambda s: s.get("step") == str(steps[-1]), f"step {steps[-1]}", 30)
                page.screenshot(path=os.path.join(args.shots, f"{lesson}{'-isolated' if isolated else ''}.png"))
                if errors:
                    raise AssertionError(f"{lesson}: " + "; ".join(errors))
                moved = f", then step {steps[-1]} by its link" if len(steps) > 1 else ""
                how = (f"isolated, {workers} Web Worker(s)" if isolated
                       else "not isolated, the page's thread")
                print(f"{lesson} ({how}): the moment reached {title!r}, pixel ({x}, {y}), step "
                      f"{steps[0]} in {took:.1f} s{moved}")
            except Exception as e:  # noqa: BLE001 (every failure is reported, then exit 1)
                failures.append(str(e))
            page.close()
        # Lazy: on a page with several moments, one far below the window has started no app
        # before the reader scrolls to it.
        page = browser.new_page(viewport={"width": 1100, "height": 800})
        page.goto(f"{plain_url}lessons/20-instances.html", wait_until="load")
        time.sleep(3)
        if page.locator("iframe.raystep-embed").last.get_attribute("src"):
            failures.append("lessons/20-instances: the moment at the bottom loaded before the "
                            "reader scrolled to it")
        page.close()
        browser.close()
    server.shutdown()
    isolating.shutdown()
    if failures:
        sys.exit("book embeds: " + "\n  ".join(failures))
    print("book embeds: every moment checked reached its scene, pixel and step")


if __name__ == "__main__":
    main()
