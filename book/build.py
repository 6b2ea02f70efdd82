#!/usr/bin/env python3
"""Builds the raystep book: `python3 book/build.py` (or `book/build.sh`) writes the site to
target/book/ and checks every link in it.

The book's pages are the repository's own Markdown, one copy each: the README (the first page),
the chapters in book/, the lessons in lessons/ and the references in docs/ (book/SUMMARY.md
lists them). They link to each other, and to scenes, images and source files, by paths relative
to where they sit in the repository, so that the links work when the files are read on GitHub.
To keep them working in the built site, the pages are copied into target/book-src/ laid out as
the repository is, with every file they link to beside them, and mdBook builds that copy. A
lesson's TOML front matter (between `+++` lines, read by the app and the tests) is left out of
its page.

Then every internal link of the built HTML is checked: the file it names exists and, where it
names an anchor (`page.html#heading`), the page has that id. A broken link fails the build,
listed with the page it is on.

mdBook: `cargo install mdbook --version 0.5.4 --locked` (the version CI installs); `--mdbook
PATH` names the binary, else `mdbook` on the PATH or in ~/.cargo/bin.
"""

import argparse
import html.parser
import os
import re
import shutil
import subprocess
import sys
import urllib.parse
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def pages(summary: Path) -> list[str]:
    """The Markdown files book/SUMMARY.md lists, as paths relative to the repository."""
    return re.findall(r"\]\(([^)]+\.md)\)", summary.read_text(encoding="utf-8"))


def strip_front_matter(text: str) -> str:
    if text.startswith("+++\n"):
        end = text.find("\n+++\n", 4)
        if end >= 0:
            return text[end + 5:].lstrip("\n")
    return text


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


def assemble(staging: Path) -> None:
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
            dst.write_text(strip_front_matter(src.read_text(encoding="utf-8")), encoding="utf-8")
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
            if frag and target.suffix == ".html" and urllib.parse.unquote(frag) not in parse(target).ids:
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
    args = ap.parse_args()
    staging = ROOT / "target" / "book-src"
    out = Path(args.out).resolve()
    assemble(staging)
    if out.exists():
        shutil.rmtree(out)
    subprocess.run([mdbook_binary(args.mdbook), "build", str(staging), "-d", str(out)], check=True)
    broken = check_links(out)
    if broken:
        sys.exit(f"book: {len(broken)} broken links:\n  " + "\n  ".join(broken))
    n = sum(1 for _ in out.rglob("*.html"))
    print(f"book: {n} pages in {out}, every internal link and anchor resolves")


if __name__ == "__main__":
    main()
