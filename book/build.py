#!/usr/bin/env python3
"""Builds the raystep book: `python3 book/build.py` (or `book/build.sh`) writes the site to
target/book/ and checks every link in it; `book/build.sh --with-app --raystep BIN` builds the
browser app too and puts the book and the app in that one folder, ready for any static host.

The book's pages are the repository's own Markdown, one copy each: the README (the first page),
the chapters in book/, the lessons in lessons/ and the references in docs/ (book/SUMMARY.md
lists them). They link to each other, and to scenes, images and source files, by paths relative
to where they sit in the repository, so that the links work when the files are read on GitHub.
To keep them working in the built site, the pages are copied into target/book-src/ laid out as
the repository is, with every file they link to beside them, and mdBook builds that copy. A
lesson's TOML front matter (between `+++` lines, read by the app and the tests) is left out of
its page.

Every lesson is live: with `--app DIST` (the browser build, `web/build.sh`), the site holds the
app in app/, and each lesson's page opens with its moment — its scene at its pixel, on the first
of its steps worth looking at (the lesson's front matter) — embedded: the app's compact window
(`#embed&scene=…&pixel=…&step=…`: the render, the stepper and the diagram, with a link to the
full app), loaded only when the reader comes within a screen of it, and a link per step that
moves it there (book/moments.js). With `--raystep BIN`, each moment also gets the figure
`raystep diagram` draws of it, generated now from the scene and shown where the browser has no
WebAssembly, with the command that made it.

Then every internal link of the built HTML is checked: the file it names exists and, where it
names an anchor (`page.html#heading`), the page has that id (the app's own `#…`, a moment's
address, is not an anchor). A broken link fails the build, listed with the page it is on.

mdBook: `cargo install mdbook --version 0.5.4 --locked` (the version CI installs); `--mdbook
PATH` names the binary, else `mdbook` on the PATH or in ~/.cargo/bin.
"""

import argparse
import html
import html.parser
import tomllib
import os
import re
import shutil
import subprocess
import sys
import urllib.parse
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
# A moment a chapter embeds where it stands: a built-in scene's name, a pixel and a step.
MOMENT = re.compile(r"^<!-- moment: scene=([a-z0-9-]+) pixel=(\d+),(\d+) step=(\d+) -->$",
                    re.MULTILINE)


def pages(summary: Path) -> list[str]:
    """The Markdown files book/SUMMARY.md lists, as paths relative to the repository."""
    return re.findall(r"\]\(([^)]+\.md)\)", summary.read_text(encoding="utf-8"))


def front_matter(text: str) -> tuple[dict, str]:
    """A lesson's TOML front matter (between `+++` lines) and the text after it."""
    if text.startswith("+++\n"):
        end = text.find("\n+++\n", 4)
        if end >= 0:
            return tomllib.loads(text[4:end]), text[end + 5:].lstrip("\n")
    return {}, text


class Moments:
    """What the lessons' live figures need: where the app is (None: no embeds) and the raystep
    binary that draws their figures (None: no figures)."""

    def __init__(self, app: bool, raystep: str | None, staging: Path):
        self.app, self.raystep, self.staging = app, raystep, staging
        self.count = 0

    def insert(self, rel: Path, meta: dict, text: str) -> str:
        """The page's text with its moments: a lesson's (its front matter's scene, pixel and
        steps) after its title, and each `<!-- moment: scene=NAME pixel=X,Y step=K -->` line a
        chapter holds where it stands (the marker is left alone without --app or --raystep)."""
        if not (self.app or self.raystep):
            return text
        n = 0

        def marker(m: re.Match) -> str:
            nonlocal n
            n += 1
            name, x, y, k = m.group(1), int(m.group(2)), int(m.group(3)), int(m.group(4))
            return self.figure(rel, f"scenes/{name}.toml", x, y, [k], f"{rel.stem}-{n}")

        text = MOMENT.sub(marker, text)
        scene, pixel, steps = meta.get("scene"), meta.get("pixel"), meta.get("steps") or [0]
        if not scene or not pixel:
            return text
        x, y = pixel
        block = self.figure(rel, scene, x, y, steps, rel.stem)
        lines = text.split("\n")
        at = next((i for i, l in enumerate(lines) if l.startswith("# ")), -1)
        lines.insert(at + 1, "\n" + block + "\n")
        return "\n".join(lines)

    def figure(self, rel: Path, scene: str, x: int, y: int, steps: list, stem: str) -> str:
        """The figure of a moment: the embedded app (with --app), the drawn diagram (with
        --raystep), the caption with a link per step."""
        name = Path(scene).stem
        first = steps[0]
        up = "../" * (len(rel.parts) - 1)
        moment = f"scene={name}&pixel={x},{y}"
        parts = [f'<figure class="raystep-moment" data-scene="{name}" data-pixel="{x},{y}">']
        if self.app:
            src = html.escape(f"{up}app/index.html#embed&{moment}&step={first}")
            # Loaded by book/moments.js when the reader comes near it (not before).
            parts.append(
                f'<iframe class="raystep-embed" hidden data-src="{src}" '
                f'title="raystep: {html.escape(scene)}, pixel ({x}, {y})"></iframe>')
        command = f"raystep diagram {scene} --pixel {x},{y} --step {first} -o figure.png"
        if self.raystep:
            figure = Path("figures") / f"{stem}.png"
            out = self.staging / figure
            out.parent.mkdir(parents=True, exist_ok=True)
            subprocess.run([self.raystep, "diagram", str(ROOT / scene), "--pixel",
                            f"{x},{y}", "--step", str(first), "-o", str(out)], check=True,
                           stdout=subprocess.DEVNULL)
            parts.append(f'<img class="raystep-fallback" src="{up}{figure.as_posix()}" '
                         f'alt="the diagram of step {first} of pixel ({x}, {y})">')
        caption = [f"Pixel ({x}, {y}) of <code>{html.escape(scene)}</code>"]
        if self.app:
            links = ", ".join(
                f'<a class="raystep-step" data-step="{k}" href="'
                + html.escape(f"{up}app/index.html#{moment}&step={k}") + f'">{k}</a>'
                for k in steps)
            caption.append(f"live: step through it here; go to step {links}; or "
                           + '<a target="_blank" href="'
                           + html.escape(f"{up}app/index.html#{moment}&step={first}")
                           + '">open it in the full app</a>')
        note = ""
        if self.raystep:
            note = (f'<span class="raystep-fallback-note"> · the figure: <code>'
                    f"{html.escape(command)}</code></span>")
        parts.append("<figcaption>" + " · ".join(caption) + note + "</figcaption>")
        parts.append("</figure>")
        self.count += 1
        return "\n".join(parts)


def linked_files(md: Path) -> list[Path]:
    """The repository files a page links to (not web addresses, not anchors in the page)."""
    out = []
    fenced = False
    for line in md.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        for target in LINK.findall(line):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                continue
            path = urllib.parse.unquote(target.split("#", 1)[0])
            if path:
                out.append((md.parent / path).resolve())
    return out


def assemble(staging: Path, moments: Moments) -> None:
    if staging.exists():
        shutil.rmtree(staging)
    staging.mkdir(parents=True)
    shutil.copy(ROOT / "book" / "book.toml", staging / "book.toml")
    shutil.copy(ROOT / "book" / "SUMMARY.md", staging / "SUMMARY.md")
    listed = pages(ROOT / "book" / "SUMMARY.md")
    todo = [ROOT / p for p in listed]
    seen = set()
    missing = []
    while todo:
        src = todo.pop()
        if src in seen:
            continue
        seen.add(src)
        try:
            rel = src.relative_to(ROOT)
        except ValueError:
            missing.append(f"{src}: outside the repository")
            continue
        if not src.exists():
            missing.append(str(rel))
            continue
        dst = staging / rel
        if src.is_dir():
            # A link to a folder: its README, where it has one, is what GitHub shows.
            readme = src / "README.md"
            if readme.exists():
                todo.append(readme)
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        if src.suffix == ".md":
            meta, text = front_matter(src.read_text(encoding="utf-8"))
            dst.write_text(moments.insert(rel, meta, text), encoding="utf-8")
            todo.extend(linked_files(src))
        else:
            shutil.copy(src, dst)
    if missing:
        sys.exit("book: pages link to files that do not exist:\n  " + "\n  ".join(sorted(missing)))


class Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.hrefs, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        for key in ("href", "src"):
            if a.get(key) and not (tag == "link" and key == "href" and a.get("rel") == "preload"):
                self.hrefs.append(a[key])


def check_links(out: Path) -> list[str]:
    """Every internal link and anchor of the built site, checked."""
    parsed = {}

    def parse(p: Path) -> Links:
        if p not in parsed:
            h = Links()
            h.feed(p.read_text(encoding="utf-8", errors="replace"))
            parsed[p] = h
        return parsed[p]

    broken = []
    for page in sorted(out.rglob("*.html")):
        if page.name in ("print.html", "404.html", "toc.html"):
            continue
        for href in parse(page).hrefs:
            if re.match(r"^[a-z][a-z0-9+.-]*:", href) or href.startswith("//"):
                continue
            path, _, frag = href.partition("#")
            path = urllib.parse.unquote(path.split("?", 1)[0])
            target = (page.parent / path).resolve() if path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(out)}: {href} (no such file)")
                continue
            app = target.parent.name == "app" and target.parent.parent == out
            if (frag and not app and target.suffix == ".html"
                    and urllib.parse.unquote(frag) not in parse(target).ids):
                broken.append(f"{page.relative_to(out)}: {href} (no such anchor)")
    return broken


def mdbook_binary(given: str | None) -> str:
    if given:
        return given
    found = shutil.which("mdbook")
    if found:
        return found
    home = Path.home() / ".cargo" / "bin" / "mdbook"
    if home.exists():
        return str(home)
    sys.exit("book: no mdbook (cargo install mdbook --version 0.5.4 --locked)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mdbook", help="the mdbook binary")
    ap.add_argument("--out", default=str(ROOT / "target" / "book"), help="where the site goes")
    ap.add_argument("--app", help="the browser build (dist/ of web/build.sh): the lessons' "
                    "moments are embedded live, the app beside the book in app/")
    ap.add_argument("--raystep", help="a raystep binary: draws each moment's figure")
    ap.add_argument("--with-app", action="store_true",
                    help="build the browser app first (web/build.sh, into dist/) and use it: "
                    "the book and the app in one folder, by one command")
    args = ap.parse_args()
    if args.with_app:
        subprocess.run([str(ROOT / "web" / "build.sh")], check=True)
        args.app = args.app or str(ROOT / "dist")
    staging = ROOT / "target" / "book-src"
    out = Path(args.out).resolve()
    if args.app and not (Path(args.app) / "index.html").exists():
        sys.exit(f"book: {args.app} holds no index.html (build it with web/build.sh)")
    moments = Moments(bool(args.app), args.raystep, staging)
    assemble(staging, moments)
    for extra in ("moments.js", "moments.css"):
        shutil.copy(ROOT / "book" / extra, staging / extra)
    if out.exists():
        shutil.rmtree(out)
    subprocess.run([mdbook_binary(args.mdbook), "build", str(staging), "-d", str(out)], check=True)
    if args.app:
        shutil.copytree(args.app, out / "app")
    broken = check_links(out)
    if broken:
        sys.exit(f"book: {len(broken)} broken links:\n  " + "\n  ".join(broken))
    n = sum(1 for _ in out.rglob("*.html"))
    live = f", {moments.count} live moments" if moments.count else ""
    print(f"book: {n} pages in {out}{live}, every internal link and anchor resolves")


if __name__ == "__main__":
    main()
