#!/usr/bin/env python3
"""web/check.py: checks raystep's browser build (dist/, from web/build.sh) from outside, in
headless Chromium driven by Playwright, at 1024x768 and at 1920x1080:

  - the app draws: the page's first frame, then the first finished render (times printed,
    counted from the navigation's start); the screenshot has many distinct colours;
  - a click on the render selects that pixel (the step list and math panel follow it);
  - the next-step key (ArrowRight, with the canvas focused) advances the step;
  - a lesson opens (Lessons -> the lesson list -> a lesson);
  - an exercise answer is checked (Exercises -> a sheet -> a student id -> an answer -> Check);
  - the answers are exported (Export answers -> a download of the class CSV); with --raystep,
    the teacher's `raystep grade` marks that file as the page marked the answer;
  - a link `#scene=cornell&pixel=160,120&step=7` opens that scene, pixel and step;
  - the render threads: the page is cross-origin isolated through its service worker (coi.js)
    and renders the Cornell box (area light, 16 spp) on Web Workers, one per core but the page's
    own; with `?workers=0`, and in a browser that blocks service workers (no isolation: the same
    wasm on one thread), on the page's one thread, saying why; the image is the same each way; the render's time
    and the page's longest frame while it renders are printed;
  - the GPU tab: without WebGPU it says so; in a second browser with WebGPU (Chromium's
    SwiftShader, `--enable-unsafe-webgpu`) it traces the scene, its debug pixel is the CPU's hit,
    and its image is the CPU's within one 8-bit step on both paths (the CPU − GPU tab);
  - no uncaught exception or console error (other than those in ALLOWED, with the reason).

The app's state is read from the hidden `<div id="raystep-status">` it keeps up to date (its
data- attributes: scene, pixel, step, steps, view, lesson, feedback, ready). Clicks go to
coordinates: the menu bar and the tabs at the top of the left panel sit at the same place in any
window; the render image and the exercise's answer field are found in screenshots. A build
without the status element (older than it) is checked by screenshot differences instead.

Usage: web/check.py [--dist DIST] [--url URL] [--chromium PATH] [--raystep BIN] SCREENSHOT_DIR
Serves DIST (default dist/) on a free loopback port unless --url names a running server.
Exits 1 with a message naming the failed check. Needs Python 3.11+ (tomllib) and `playwright` (pip); the
browser is Debian's /usr/bin/chromium where installed, else Playwright's own.
"""

import argparse
import csv
import functools
import glob
import io
import http.server
import os
import re
import struct
import subprocess
import sys
import tempfile
import threading
import time
import tomllib
import zlib

# Console errors that are not failures, each with the reason.
ALLOWED = [
    # wgpu asks for WebGPU first; a browser without it (headless Chromium on SwiftShader) has no
    # adapter and eframe falls back to WebGL2. Logged as a warning today; listed in case a
    # browser logs it as an error.
    (re.compile(r"No available adapters"), "no WebGPU here: eframe falls back to WebGL2"),
]

# SwiftShader renders WebGL on the CPU; the flags let headless Chromium use it.
CHROMIUM_ARGS = ["--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                 "--ignore-gpu-blocklist"]
PANEL = (248, 248, 248)  # egui's light panel fill
TEXT_EDIT = (255, 255, 255)  # egui's light text-edit fill
BUTTON = (230, 230, 230)  # egui's light button fill
# The built-in scene's image (Three spheres), to turn a click's place into its pixel.
SCENE_SIZE = (320, 240)
# Places that do not move with the window's size: the menu bar, the left panel's tabs and the
# first rows of the exercise tab, and the first rows of a combo box's list below them.
LESSONS_MENU = (154, 12)
LESSON_TAB, EXERCISES_TAB = (38, 37), (115, 37)
LESSON_COMBO = (100, 69)
SHEET_COMBO = (120, 69)
STUDENT_ID = (110, 91)
LIST_ROW = lambda i: (100, 96 + 23 * i)  # noqa: E731 (row i of a combo box's list, from 0)


class Failed(Exception):
    """A check that failed: its message says which and what was seen."""


def decode_png(data):
    """(width, height, channels, bytes) of an 8-bit RGB(A) PNG such as Chromium writes."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError(f"PNG kind not read here (depth {depth}, colour type {ctype})")
        elif kind == b"IDAT":
            idat += body
    bpp = 3 if ctype == 2 else 4
    raw, stride = zlib.decompress(idat), w * bpp
    out, prev, i = bytearray(h * stride), bytearray(stride), 0
    for y in range(h):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        if f == 1:
            for x in range(bpp, stride):
                line[x] = (line[x] + line[x - bpp]) & 255
        elif f == 2:
            for x in range(stride):
                line[x] = (line[x] + prev[x]) & 255
        elif f == 3:
            for x in range(stride):
                left = line[x - bpp] if x >= bpp else 0
                line[x] = (line[x] + (left + prev[x]) // 2) & 255
        elif f == 4:
            for x in range(stride):
                a = line[x - bpp] if x >= bpp else 0
                b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out[y * stride:(y + 1) * stride] = line
        prev = line
    return w, h, bpp, bytes(out)


class Shot:
    """A screenshot (or a clip of one), its pixels readable."""

    def __init__(self, png, x0=0, y0=0):
        self.png, self.x0, self.y0 = png, x0, y0
        self.w, self.h, self.bpp, self.px = decode_png(png)

    def at(self, x, y):
        """The colour at page coordinates (x, y)."""
        i = ((y - self.y0) * self.w + (x - self.x0)) * self.bpp
        return tuple(self.px[i:i + 3])

    def colours(self):
        """How many distinct colours it has."""
        return len({self.px[i:i + 3] for i in range(0, len(self.px), self.bpp)})


def shot(page, x=0, y=0, w=None, h=None):
    """A screenshot of the page, or of the rectangle x, y, w, h."""
    vp = page.viewport_size
    w, h = w or vp["width"] - x, h or vp["height"] - y
    return Shot(page.screenshot(clip={"x": x, "y": y, "width": w, "height": h}), x, y)


def longest_run(values, inside):
    """(start, end) of the longest run of values for which inside(value) holds (end exclusive)."""
    best, start = (0, 0), None
    for i, v in enumerate(list(values) + [None]):
        if v is not None and inside(v):
            start = i if start is None else start
        elif start is not None:
            best = max(best, (start, i), key=lambda r: r[1] - r[0])
            start = None
    return best


def render_rect(page):
    """(left, top, width, height) of the render image on the page: the longest run of
    non-panel pixels across the window's middle row, then down the column through its middle."""
    vp = page.viewport_size
    row = shot(page, 0, vp["height"] // 2, vp["width"], 1)
    x0, x1 = longest_run((row.at(x, row.y0) for x in range(vp["width"])), lambda c: c != PANEL)
    cx = (x0 + x1) // 2
    col = shot(page, cx, 0, 1, vp["height"])
    y0, y1 = longest_run((col.at(cx, y) for y in range(vp["height"])), lambda c: c != PANEL)
    if x1 - x0 < 100 or y1 - y0 < 75:
        raise Failed(f"no render image found (widest drawn run {x0}..{x1}, {y0}..{y1})")
    return x0, y0, x1 - x0, y1 - y0


def find_answer_field(page):
    """(left, right, top) of the exercise's answer field: the first row below the student id
    with a run of text-edit white at least 100 pixels wide; None if there is none."""
    vp = page.viewport_size
    panel = shot(page, 0, 110, min(vp["width"] // 2, 600), vp["height"] - 220)
    for y in range(panel.y0, panel.y0 + panel.h):
        x0, x1 = longest_run((panel.at(x, y) for x in range(panel.w)), lambda c: c == TEXT_EDIT)
        if x1 - x0 >= 100:
            return x0, x1, y
    return None


def serve(dist):
    """Serves dist on a free loopback port in a thread; returns (server, url)."""
    handler = functools.partial(Quiet, directory=dist)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_address[1]}/"


class Quiet(http.server.SimpleHTTPRequestHandler):
    """A static file server that serves .wasm as application/wasm and logs nothing."""

    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".wasm": "application/wasm", ".js": "text/javascript"}

    def log_message(self, *args):
        pass


class App:
    """One page of the app in one window size, and what it logged."""

    def __init__(self, browser, url, size, has_status, outdir):
        self.size, self.has_status, self.errors, self.outdir = size, has_status, [], outdir
        viewport = {"width": size[0], "height": size[1]}
        # A browser (a page in a context of its own), or a context already made.
        if hasattr(browser, "new_context"):
            self.page = browser.new_page(viewport=viewport)
        else:
            self.page = browser.new_page()
            self.page.set_viewport_size(viewport)
        self.page.on("pageerror", lambda e: self.errors.append(f"uncaught exception: {e}"))
        self.page.on("console", self._console)
        self.url = url

    def _console(self, msg):
        if msg.type == "error":
            text = f"console error: {msg.text}"
            if msg.location and msg.location.get("url"):
                text += f" ({msg.location['url']})"
            self.errors.append(text)

    def status(self):
        """The app's status attributes, or None where the build has no status element (or the
        page is between two documents: the first visit reloads through the service worker)."""
        try:
            return self.page.evaluate(
                "() => { const e = document.getElementById('raystep-status');"
                " return e ? Object.assign({}, e.dataset) : null; }")
        except Exception as e:  # noqa: BLE001 (Playwright's error while the page navigates)
            if "context was destroyed" in str(e) or "navigat" in str(e):
                return None
            raise

    def wait(self, condition, what, timeout=30):
        """Waits until condition(status) holds; fails naming what was awaited and the status."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            s = self.status()
            if s is not None and condition(s):
                return s
            time.sleep(0.1)
        self.fail(f"{what}: not within {timeout} s (status: {self.status()})")

    def fail(self, message):
        """Fails with message, leaving a screenshot of the moment beside the others."""
        name = "failed-{}x{}.png".format(*self.size)
        self.page.screenshot(path=os.path.join(self.outdir, name))
        logged = "".join(f"\n  the page logged: {e}" for e in self.errors)
        raise Failed(f"{message} (screenshot: {name}){logged}")

    def click(self, xy, settle=0.6):
        """A click as a hand makes it: move, a frame's pause, press, release."""
        self.page.mouse.move(*xy)
        time.sleep(0.2)
        self.page.mouse.down()
        time.sleep(0.05)
        self.page.mouse.up()
        time.sleep(settle)

    def open_list(self, combo, row):
        """Opens the combo box at combo, waits for its list to show, and picks its row."""
        region = {"x": 0, "y": combo[1] + 14, "width": 400, "height": 23 * (row + 2)}
        before = self.page.screenshot(clip=region)
        self.click(combo, settle=0.2)
        end = time.monotonic() + 10
        while self.page.screenshot(clip=region) == before:
            if time.monotonic() > end:
                self.fail(f"the combo box at {combo} showed no list")
            time.sleep(0.2)
        time.sleep(0.3)
        self.click(LIST_ROW(row))

    def download_from_dialog(self, open_dialog, what, tries=3):
        """A download from a save dialog that has its name ready: open_dialog() (a click that
        opens the dialog), then, once the middle of the page shows the dialog, Enter. Each step
        waits for the screen rather than for a fixed time (a fixed pause let Enter reach a loaded
        page before the dialog did: CI, stop 68); tried `tries` times, Escape closing what the
        last try left open. Returns the download and the try (0-based) that gave it."""
        w, h = self.size
        middle = {"x": w // 2 - 200, "y": h // 2 - 120, "width": 400, "height": 240}
        for attempt in range(tries):
            if attempt:
                self.page.keyboard.press("Escape")
                time.sleep(0.5)
            if not self.shows_change(open_dialog, middle, 10):
                continue
            time.sleep(0.3)
            try:
                with self.page.expect_download(timeout=15000) as waiting:
                    self.page.keyboard.press("Enter")
                return waiting.value, attempt
            except Exception:  # noqa: BLE001 (Playwright's timeout: tried again, then named)
                continue
        self.fail(f"{what} and Enter gave no download ({tries} tries)")

    def shows_change(self, action, region, timeout):
        """Whether region's pixels change within timeout seconds of action."""
        before = self.page.screenshot(clip=region)
        action()
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.page.screenshot(clip=region) != before:
                return True
            time.sleep(0.2)
        return False

    def changed_after(self, action, region, what):
        """Screenshot check (builds without the status element): region differs after action."""
        before = self.page.screenshot(clip=region)
        action()
        time.sleep(1.5)
        if self.page.screenshot(clip=region) == before:
            self.fail(f"{what}: the screen did not change")


def check_size(browser, url, size, outdir, has_status, raystep=None):
    """All the checks in one window size; returns the timings. raystep: the native binary that
    grades the exported answers (None: the download is checked, not graded)."""
    w, h = size
    app = App(browser, url, size, has_status, outdir)
    page, tag = app.page, f"{w}x{h}"
    t0 = time.monotonic()
    page.goto(url)
    if has_status:
        app.wait(lambda s: True, "the app's first frame", 60)
        first = time.monotonic() - t0
        s = app.wait(lambda s: s.get("ready") == "1", "the first render", 120)
        ready = time.monotonic() - t0
    else:
        page.wait_for_function("() => !document.getElementById('loading')", timeout=60000)
        first = time.monotonic() - t0
        while shot(page, w // 4, 0, w // 2, h).colours() < 200:
            if time.monotonic() - t0 > 120:
                raise Failed("the first render: not within 120 s")
            time.sleep(0.5)
        ready, s = time.monotonic() - t0, None
    print(f"{tag}: first frame {first:.1f} s, first render finished {ready:.1f} s after navigation"
          + (f" ({s['scene']}, {s['steps']} steps at pixel {s['pixel']})" if s else ""))
    full = shot(page)
    n = full.colours()
    if n < 200:
        app.fail(f"{tag}: the app does not draw: its screenshot has {n} distinct colours")
    page.screenshot(path=os.path.join(outdir, f"{tag}-app.png"))

    # A click on the render selects the pixel under it.
    left, top, iw, ih = render_rect(page)
    target = (left + iw // 4, top + (ih * 3) // 4)
    want = (int((target[0] - left + 0.5) * SCENE_SIZE[0] / iw),
            int((target[1] - top + 0.5) * SCENE_SIZE[1] / ih))
    side = (0, 30, left, h - 130)  # the step list and the math panel beside the render
    if has_status:
        region = {"x": side[0], "y": side[1], "width": side[2], "height": side[3]}
        math = {"x": left + iw, "y": 30, "width": w - left - iw, "height": h - 130}
        before, before_math = page.screenshot(clip=region), page.screenshot(clip=math)
        app.click(target)
        s = app.wait(lambda s: s["pixel"] not in ("", "160,120") and s["steps"] != "0",
                     f"{tag}: a click at {target} on the render (at {left},{top}, {iw}x{ih})"
                     f" selecting a pixel near {want[0]},{want[1]}", 30)
        got = tuple(int(v) for v in s["pixel"].split(","))
        if abs(got[0] - want[0]) > 3 or abs(got[1] - want[1]) > 3:
            app.fail(f"{tag}: a click at {target} selected pixel {s['pixel']}, not one near"
                         f" {want[0]},{want[1]} (render found at {left},{top}, {iw}x{ih})")
        time.sleep(0.5)
        if page.screenshot(clip=region) == before:
            app.fail(f"{tag}: pixel {s['pixel']} selected but the step list beside the render"
                     " did not change")
        if page.screenshot(clip=math) == before_math:
            app.fail(f"{tag}: pixel {s['pixel']} selected but the math panel right of the render"
                     " did not change")
        print(f"{tag}: a click on the render selected pixel {s['pixel']} ({s['steps']} steps)")
    else:
        app.changed_after(lambda: app.click(target),
                          {"x": side[0], "y": side[1], "width": side[2], "height": side[3]},
                          f"{tag}: a click on the render")
        print(f"{tag}: a click on the render changed the step list")

    # ArrowRight, with the canvas focused (the click above focused it), advances the step.
    if has_status:
        before = int(s["step"] or 0)
        page.keyboard.press("ArrowRight")
        s = app.wait(lambda s: s["step"] == str(before + 1),
                     f"{tag}: ArrowRight advancing the step from {before}", 10)
        print(f"{tag}: ArrowRight went from step {before} to step {s['step']}")
    else:
        app.changed_after(lambda: page.keyboard.press("ArrowRight"),
                          {"x": 0, "y": h - 90, "width": w, "height": 60},
                          f"{tag}: ArrowRight on the step bar")
        print(f"{tag}: ArrowRight changed the step bar")

    # Lessons -> the lesson list -> its third lesson.
    region = {"x": 0, "y": 25, "width": 220, "height": h - 130}
    if has_status:
        app.click(LESSONS_MENU)
        s = app.wait(lambda s: s["view"] == "lesson" and s["lesson"],
                     f"{tag}: the Lessons menu at {LESSONS_MENU} opening the lesson panel", 10)
        first_lesson = s["lesson"]
        app.open_list(LESSON_COMBO, 2)
        s = app.wait(lambda s: s["lesson"] not in ("", first_lesson),
                     f"{tag}: the third lesson in the list at {LESSON_COMBO} opening", 10)
        print(f"{tag}: opened the lesson \"{s['lesson']}\" (from \"{first_lesson}\")")
    else:
        app.changed_after(lambda: app.click(LESSONS_MENU), region, f"{tag}: the Lessons menu")
        app.changed_after(lambda: app.open_list(LESSON_COMBO, 2), region,
                          f"{tag}: choosing a lesson")
        print(f"{tag}: a lesson opened")
    page.screenshot(path=os.path.join(outdir, f"{tag}-lesson.png"))

    # Exercises -> the first sheet -> a student id -> an answer -> Check.
    app.click(EXERCISES_TAB)
    if has_status:
        app.wait(lambda s: s["view"] == "exercise", f"{tag}: the Exercises tab at {EXERCISES_TAB}")
    app.open_list(SHEET_COMBO, 0)
    # The answer field: the first text-edit-white row of the left panel below the student id
    # (it sits under the question or beside "Answer:", as the panel's width allows). It shows
    # once a student id is in; a keystroke that came before the field had the focus is lost,
    # so the id is typed again while no question shows.
    answer = None
    for attempt in range(3):
        app.click(STUDENT_ID)
        page.keyboard.type("alice")
        page.keyboard.press("Enter")
        end = time.monotonic() + 4
        while answer is None and time.monotonic() < end:
            time.sleep(0.5)
            answer = find_answer_field(page)
        if answer:
            break
    if answer is None:
        app.fail(f"{tag}: no answer field in the exercise panel (after choosing the sheet"
                 f" at {SHEET_COMBO} and typing a student id at {STUDENT_ID})")
    x0, x1, ay = answer
    panel = shot(page, 0, 110, min(w // 2, 600), h - 220)
    app.click((x0 + 20, ay + 8))
    page.keyboard.type("ball")
    # The Check button: the first button-grey run after the field, beside it or below it.
    check = None
    for y in range(ay, min(ay + 60, panel.y0 + panel.h)):
        xs = range(x1, panel.w) if y < ay + 18 else range(0, panel.w)
        b0, b1 = longest_run((panel.at(x, y) for x in xs), lambda c: c == BUTTON)
        if b1 - b0 >= 20:
            check = (xs[0] + (b0 + b1) // 2, y + 6)
            break
    if check is None:
        app.fail(f"{tag}: no Check button beside or below the answer field at {x0},{ay}")
    if has_status:
        app.click(check)
        s = app.wait(lambda s: s["feedback"] != "",
                     f"{tag}: Check at {check} marking the answer typed at {x0 + 20},{ay + 8}", 10)
        print(f"{tag}: the answer \"ball\" was checked: {s['feedback']}")
    else:
        app.changed_after(lambda: app.click(check), region, f"{tag}: Check")
        print(f"{tag}: Check changed the exercise panel")
    page.screenshot(path=os.path.join(outdir, f"{tag}-exercise.png"))
    if has_status:
        export_answers(app, tag, ay, s["feedback"], raystep)
    page.close()
    return app.errors, first, ready


EXERCISES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lessons", "exercises")


def export_answers(app, tag, answer_top, feedback, raystep):
    """Export answers (the button in the row of question numbers, above the answer field at
    answer_top; its dialog has the name ready, so Enter saves) gives a download: one row, the
    student "alice" and the answer "ball" to the sheet's first question. With raystep (the
    native binary), `raystep grade` marks it as the page's feedback did."""
    page = app.page
    top = STUDENT_ID[1] + 12
    panel = shot(page, 0, top, min(page.viewport_size["width"] // 2, 600), answer_top - top)
    button = None
    for y in range(panel.y0, panel.y0 + panel.h):
        x0, x1 = longest_run((panel.at(x, y) for x in range(panel.w)), lambda c: c == BUTTON)
        if x1 - x0 >= 60:
            button = ((x0 + x1) // 2, y + 6)
            break
    if button is None:
        app.fail(f"{tag}: no Export answers button between the student id and the answer field")
    d, _ = app.download_from_dialog(lambda: app.click(button, settle=0),
                                    f"{tag}: Export answers at {button}")
    text = open(d.path(), encoding="utf-8").read()
    rows = list(csv.reader(io.StringIO(text)))
    if (not d.suggested_filename.endswith(".csv") or len(rows) != 2 or rows[0][0] != "student"
            or rows[1][:2] != ["alice", "ball"]):
        app.fail(f"{tag}: the download {d.suggested_filename} is not alice's answers: {text!r}")
    print(f"{tag}: the answers were exported as the download {d.suggested_filename}: {rows}")
    if not raystep:
        return
    # The sheet: the built-in one whose question ids the file's header names.
    sheet = None
    for path in sorted(glob.glob(os.path.join(EXERCISES, "*.toml"))):
        with open(path, "rb") as f:
            ids = [q["id"] for q in tomllib.load(f).get("question", [])]
        if ids == rows[0][1:]:
            sheet = path
    if sheet is None:
        app.fail(f"{tag}: no sheet in {EXERCISES} has the questions {rows[0][1:]}")
    with tempfile.TemporaryDirectory() as tmp:
        answers, grades = os.path.join(tmp, "answers.csv"), os.path.join(tmp, "grades.csv")
        with open(answers, "w", encoding="utf-8") as f:
            f.write(text)
        run = subprocess.run([raystep, "grade", sheet, answers, "-o", grades],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 0:
            app.fail(f"{tag}: raystep grade {sheet} on the exported answers failed:"
                     f" {run.stderr.strip()}")
        with open(grades, encoding="utf-8") as f:
            marks = list(csv.DictReader(f))
    want = "1" if feedback == "right" else "0"
    qid = rows[0][1]
    if len(marks) != 1 or marks[0]["student"] != "alice" or marks[0][qid] != want:
        app.fail(f"{tag}: raystep grade marked {marks}, the page's feedback was {feedback!r}"
                 f" ({qid} should be {want})")
    print(f"{tag}: raystep grade {os.path.basename(sheet)} marked it as the page did:"
          f" {qid} = {want} ({feedback})")


def check_link(browser, url, outdir):
    """A teacher's link opens its scene, pixel and step."""
    app = App(browser, url + "#scene=cornell&pixel=160,120&step=7", (1024, 768), True, outdir)
    app.page.goto(app.url)
    s = app.wait(lambda s: s.get("ready") == "1" and s["step"] == "7",
                 "the link #scene=cornell&pixel=160,120&step=7", 120)
    if s["pixel"] != "160,120" or "ornell" not in s["scene"]:
        app.fail(f"the link #scene=cornell&pixel=160,120&step=7 opened {s}")
    print(f"a link opened {s['scene']}, pixel {s['pixel']}, step {s['step']}")
    app.page.screenshot(path=os.path.join(outdir, "1024x768-link.png"))
    app.page.close()
    return app.errors


# Counts the page's animation frames from its first script on: the gaps between them are the
# page's frames as a user sees them (a long one is a page that does not answer).
FRAME_CLOCK = """
window.__frames = [];
const tick = (t) => { window.__frames.push(t); requestAnimationFrame(tick); };
requestAnimationFrame(tick);
window.__tasks = [];
new PerformanceObserver((list) => {
  for (const e of list.getEntries()) window.__tasks.push([e.startTime, e.duration]);
}).observe({ type: "longtask", buffered: true });
"""


def render_threads(browser, url, query, what, outdir):
    """Opens the Cornell box with its area light (path traced, 16 samples per pixel, 256 x 256)
    with `query`; waits for its render; returns (status, isolation, (the page's longest frame and
    its own longest task in ms while it rendered, after its first second), the render's pixels
    as screenshotted, errors)."""
    app = App(browser, url + query + "#scene=cornell-area", (1024, 768), True, outdir)
    app.page.add_init_script(FRAME_CLOCK)
    app.page.goto(app.url)
    s = app.wait(lambda s: s.get("ready") == "1" and "ornell" in s.get("scene", ""),
                 f"the Cornell box's render ({what})", 300)
    iso = app.page.evaluate("() => ({ isolated: self.crossOriginIsolated,"
                            " cores: navigator.hardwareConcurrency,"
                            " threads: window.raystepThreads })")
    ms = float(s["renderMs"])
    # The frames while it rendered, from a second after it started (it starts with the app, and
    # the app's own start-up fills its first frames); the few after its end, until now, are
    # the idle page's.
    frames = app.page.evaluate("() => window.__frames")
    end = frames[-1]
    during = [t for t in frames if t >= end - ms + 1000]
    longest = max((b - a for a, b in zip(during, during[1:])), default=0.0)
    # The page's own longest task in that time (Chromium's long tasks: 50 ms or more), apart
    # from the frame's drawing, which Chromium's GPU process does.
    tasks = app.page.evaluate("() => window.__tasks")
    task = max((d for t, d in tasks if t >= end - ms + 1000), default=0.0)
    time.sleep(0.5)
    image = shot(app.page, *render_rect(app.page))
    app.page.screenshot(path=os.path.join(outdir, f"1024x768-threads-{what.split()[0]}.png"))
    app.page.close()
    return s, iso, (longest, task), image, app.errors


def check_threads(browser, url, outdir, blocked_browser):
    """The render on every core where the page is cross-origin isolated (raystep's service
    worker, coi.js), on one thread where asked (?workers=0) or where it cannot be isolated (a
    browser that blocks service workers: the same wasm on a plain memory). The Cornell box at 16
    samples per pixel each way: its time, its threads and the page's longest frame printed; the
    images the same; the one-thread page says why in its status bar."""
    errors = []
    s1, iso1, long1, img1, e = render_threads(browser, url, "?workers=0", "1 thread", outdir)
    errors += e
    sn, ison, longn, imgn, e = render_threads(browser, url, "", "all cores", outdir)
    errors += e
    sb, isob, longb, imgb, e = render_threads(blocked_browser, url, "", "not isolated", outdir)
    errors += e
    if not ison["isolated"]:
        raise Failed(f"the page is not cross-origin isolated through coi.js: {ison}")
    cores = ison["cores"]
    want = max(1, cores - 1)
    if (s1["threads"] != "1" or iso1["threads"]["workers"] != 0
            or (cores > 1 and ison["threads"]["workers"] != want)
            or sn["threads"] != str(ison["threads"]["workers"] or 1)):
        raise Failed(f"threads: ?workers=0 rendered on {s1['threads']} ({iso1}), the default on"
                     f" {sn['threads']} ({ison}; the machine has {cores} cores)")
    if isob["isolated"] or sb["threads"] != "1" or not isob["threads"]["oneThread"]:
        raise Failed(f"a page that cannot be isolated: {isob}, rendered on {sb['threads']} threads")
    if img1.px != imgn.px or img1.px != imgb.px:
        raise Failed("the Cornell box on one thread and on every core are not the same image")
    for what, s, longest in [("the page's thread (?workers=0)", s1, long1),
                             (f"{sn['threads']} Web Worker(s) beside it", sn, longn),
                             ("the page's thread, not isolated", sb, longb)]:
        print(f"threads: the Cornell box (area light, 16 spp, 256x256) on {what}: "
              f"{float(s['renderMs']) / 1e3:.1f} s, the page's longest frame {longest[0]:.0f} ms"
              f" (its own longest task {longest[1]:.0f} ms)")
    print(f"threads: one thread where isolation fails says why: {isob['threads']['oneThread']}")
    return errors


FILE_MENU = (20, 12)
OPEN_ITEM = (40, 39)  # File → Open…, the menu's first item
SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")


def check_files(browser, url, outdir):
    """Files the web way: File → Open's file picker opens a scene; a trace is saved as a
    download; a scene dropped on the page opens."""
    app = App(browser, url, (1024, 768), True, outdir)
    page = app.page
    page.goto(url)
    app.wait(lambda s: s.get("ready") == "1", "the first render", 120)
    # The menu is awaited on screen before its item is clicked; tried three times (as the
    # save dialog below).
    menu = {"x": 0, "y": 24, "width": 300, "height": 160}
    chosen = None
    for attempt in range(3):
        if attempt:
            page.keyboard.press("Escape")
            time.sleep(0.5)
        if not app.shows_change(lambda: app.click(FILE_MENU, settle=0), menu, 10):
            continue
        time.sleep(0.3)
        try:
            with page.expect_file_chooser(timeout=10000) as chooser:
                app.click(OPEN_ITEM)
            chosen = chooser.value
            break
        except Exception:  # noqa: BLE001 (Playwright's timeout: tried again, then named)
            continue
    if chosen is None:
        app.fail(f"File at {FILE_MENU} → Open… at {OPEN_ITEM} opened no file picker (3 tries)")
    chosen.set_files([os.path.join(SCENES, "cornell.toml")])
    s = app.wait(lambda s: s["scene"] == "Cornell box" and s["ready"] == "1",
                 "scenes/cornell.toml picked in the file picker opening", 120)
    print(f"the file picker opened {s['scene']}")

    # Save trace: the File menu's item under Open…, Built-in scene, Recent, Reload and a
    # separator; its dialog has the name ready, so Enter saves. The menu is awaited on screen
    # before its item is clicked.
    def open_save_trace():
        if app.shows_change(lambda: app.click(FILE_MENU, settle=0), menu, 10):
            time.sleep(0.3)
            app.click((80, 140), settle=0)
    d, attempt = app.download_from_dialog(open_save_trace, "File → Save trace (JSON)…")
    data = open(d.path(), "rb").read()
    if not (d.suggested_filename.endswith(".json") and b'"version"' in data[:200]
            and b"Cornell box" in data[:400]):
        app.fail(f"the download {d.suggested_filename} ({len(data)} bytes) is not the trace:"
                 f" {data[:120]!r}")
    tries = f", on try {attempt + 1}" if attempt else ""
    print(f"the trace was saved as the download {d.suggested_filename} ({len(data)} bytes{tries})")

    # A scene dropped on the page (as a file from the desktop is: a DataTransfer with a File).
    text = open(os.path.join(SCENES, "three-spheres.toml"), encoding="utf-8").read()
    page.evaluate("""(text) => {
        const dt = new DataTransfer();
        dt.items.add(new File([text], "three-spheres.toml", { type: "text/plain" }));
        const c = document.getElementById("raystep");
        for (const type of ["dragenter", "dragover", "drop"]) {
            c.dispatchEvent(new DragEvent(type, { dataTransfer: dt, bubbles: true, cancelable: true }));
        }
    }""", text)
    s = app.wait(lambda s: s["scene"] == "Three spheres" and s["ready"] == "1",
                 "three-spheres.toml dropped on the page opening", 120)
    print(f"a dropped file opened {s['scene']}")
    page.screenshot(path=os.path.join(outdir, "1024x768-files.png"))
    page.close()
    return app.errors


# The central panel's tabs and the path radio at 1024x768 (the side panels at their default
# widths): GPU render, CPU − GPU, and "compute" below them.
GPU_TAB, DIFF_TAB, COMPUTE = (504, 43), (600, 43), (455, 66)
# Pixel (160, 120) of three-spheres.toml on the CPU (`raystep trace scenes/three-spheres.toml
# --pixel 160,120`): it hits the sphere "middle" at t = 4.6522236.
PICK_OBJECT, PICK_T = "middle", 4.6522236


def check_gpu(p, chromium, browser, url, outdir):
    """The GPU tab: says what it needs without WebGPU; with it, traces the scene as the CPU."""
    app = App(browser, url, (1024, 768), True, outdir)
    app.page.goto(url)
    app.wait(lambda s: s.get("ready") == "1", "the first render", 120)
    app.click(GPU_TAB)
    app.wait(lambda s: s.get("gpu") == "no-webgpu", "the GPU tab saying it needs WebGPU", 30)
    app.page.screenshot(path=os.path.join(outdir, "1024x768-gpu-no-webgpu.png"))
    print("without WebGPU the GPU tab says so")
    app.page.close()
    errors = app.errors

    webgpu = p.chromium.launch(executable_path=chromium,
                               args=CHROMIUM_ARGS + ["--enable-unsafe-webgpu"])
    try:
        app = App(webgpu, url, (1024, 768), True, outdir)
        app.page.goto(url)
        app.wait(lambda s: s.get("ready") == "1", "the first render (WebGPU browser)", 120)
        start = time.monotonic()
        app.click(GPU_TAB)
        s = app.wait(lambda s: s.get("gpu") == "ready" and s.get("gpuPick"),
                     "the GPU tab's first frame and debug pixel (WebGPU)", 180)
        print(f"WebGPU: the GPU tab traced its first frame in {time.monotonic() - start:.1f} s:"
              f" {s['gpuAdapter'][:90]}…")
        if s.get("gpu", "").startswith("error") or "BrowserWebGpu" not in s["gpuAdapter"]:
            app.fail(f"the GPU tab is not on WebGPU: {s}")
        m = re.fullmatch(r"160,120 object=(\S+) t=(\S+)", s["gpuPick"])
        if not m or m[1] != PICK_OBJECT or abs(float(m[2]) - PICK_T) > 1e-5 * PICK_T:
            app.fail(f"the GPU's debug pixel {s['gpuPick']!r} is not the CPU's hit"
                     f" ({PICK_OBJECT} at t = {PICK_T})")
        app.page.screenshot(path=os.path.join(outdir, "1024x768-gpu.png"))
        app.click(DIFF_TAB)
        for path, click in [("fragment", None), ("compute", COMPUTE)]:
            if click:
                app.click(click)
            s = app.wait(lambda s: s.get("gpuDiff", "").startswith(path + " path"),
                         f"the CPU − GPU comparison on the {path} path (WebGPU)", 180)
            m = re.search(r"max error (\d+)/255, (\d+) of (\d+) pixels differ", s["gpuDiff"])
            if not m or int(m[1]) > 1 or int(m[2]) > int(m[3]) // 100:
                app.fail(f"the GPU image is not the CPU's within one 8-bit step: {s['gpuDiff']}")
            print(f"WebGPU: {s['gpuDiff']}")
        app.page.screenshot(path=os.path.join(outdir, "1024x768-gpu-difference.png"))
        app.page.close()
        errors += app.errors
    finally:
        webgpu.close()
    return errors


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("screenshots", help="folder for the screenshots (made if missing)")
    ap.add_argument("--dist", default=os.path.join(os.path.dirname(__file__), "..", "dist"))
    ap.add_argument("--url", help="a server already serving dist/ (else one is started)")
    ap.add_argument("--chromium", default="/usr/bin/chromium" if os.path.exists(
        "/usr/bin/chromium") else None, help="the browser (default: Debian's, else Playwright's)")
    ap.add_argument("--size", action="append", metavar="WxH",
                    help="check only this window size (repeatable; default 1024x768, 1920x1080)")
    ap.add_argument("--no-link", action="store_true", help="skip the link check")
    ap.add_argument("--no-gpu", action="store_true", help="skip the GPU tab's checks")
    ap.add_argument("--no-threads", action="store_true",
                    help="skip the render threads' check (Web Workers, isolation)")
    ap.add_argument("--raystep", help="the native raystep binary: `raystep grade` marks the"
                    " answers the page exported (else the download is checked, not graded)")
    args = ap.parse_args()
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.size or ["1024x768", "1920x1080"]]
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sys.exit("web/check.py: Playwright is missing (python3 -m pip install playwright)")
    wasm = os.path.join(args.dist, "raystep_web_bg.wasm")
    if not os.path.exists(wasm):
        sys.exit(f"web/check.py: {wasm} is missing: build it with web/build.sh")
    # A build older than the status element is checked by screenshots only.
    with open(wasm, "rb") as f:
        has_status = b"raystep-status" in f.read()
    if not has_status:
        print("(this build keeps no #raystep-status: checking by screenshot differences)")
    os.makedirs(args.screenshots, exist_ok=True)
    server, url = (None, args.url) if args.url else serve(args.dist)
    errors = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=args.chromium, args=CHROMIUM_ARGS)
            for size in sizes:
                e, _, _ = check_size(browser, url, size, args.screenshots, has_status,
                                     args.raystep)
                errors += e
            if has_status and not args.no_link:
                errors += check_link(browser, url, args.screenshots)
            if has_status:
                errors += check_files(browser, url, args.screenshots)
            if has_status and not args.no_threads:
                blocked = p.chromium.launch(executable_path=args.chromium, args=CHROMIUM_ARGS)
                try:
                    context = blocked.new_context(service_workers="block")
                    errors += check_threads(browser, url, args.screenshots, context)
                finally:
                    blocked.close()
            if has_status and not args.no_gpu:
                errors += check_gpu(p, args.chromium, browser, url, args.screenshots)
            browser.close()
    except Failed as e:
        sys.exit(f"web/check.py FAILED: {e}")
    finally:
        if server:
            server.shutdown()
    bad = []
    for e in errors:
        reason = next((r for pat, r in ALLOWED if pat.search(e)), None)
        if reason:
            print(f"(allowed: {e}: {reason})")
        else:
            bad.append(e)
    if bad:
        sys.exit("web/check.py FAILED: the page logged errors:\n  " + "\n  ".join(bad))
    print(f"web/check.py: all checks passed; screenshots in {args.screenshots}")


if __name__ == "__main__":
    main()
