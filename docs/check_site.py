"""Check the built documentation as a browser sees it (``make docs-check``).

1. Every HTML page of ``docs/_build/html`` is parsed (``html.parser``): each internal
   ``href`` and ``src`` (links, images, scripts, style sheets) must name a file that
   exists in the site, and each ``#fragment`` of a link to a page must be an ``id`` on
   that page. External links are not followed (the check runs offline).
2. The site is served on localhost and opened in Debian's headless ``chromium``: the
   landing page and one demo page are saved as screenshots in
   ``docs/_build/screenshots/``, and their DOM after scripts ran (``--dump-dom``) is
   checked again for images, so that a page whose picture fails to load in the browser
   fails the check (every ``<img>`` is fetched from the server; a missing one is a 404).

Exit status 0 when everything holds, 1 with one line per problem otherwise.

    python docs/check_site.py [--site docs/_build/html] [--no-browser]
"""
from __future__ import annotations

import argparse
import functools
import http.server
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import threading
import urllib.parse
from html.parser import HTMLParser

DOCS = pathlib.Path(__file__).resolve().parent
SCREENSHOT_PAGES = {"landing.png": "index.html",
                    "demo.png": "_generated/gallery/hopper_membrane.html"}


class Refs(HTMLParser):
    """The internal references and the ids of one page."""

    def __init__(self):
        super().__init__()
        self.refs: list[tuple[str, str]] = []      # (tag.attr, value)
        self.ids: set[str] = set()
        self.images: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        for attr in ("href", "src"):
            v = a.get(attr)
            if v and tag in ("a", "img", "link", "script", "source", "iframe"):
                if tag == "link" and attr == "href" and a.get("rel") in ("preconnect",):
                    continue
                self.refs.append((f"{tag}.{attr}", v))
                if tag == "img":
                    self.images.append(v)


def _parse(path: pathlib.Path) -> Refs:
    p = Refs()
    p.feed(path.read_text(errors="replace"))
    return p


def _internal(value: str) -> bool:
    u = urllib.parse.urlsplit(value)
    return not u.scheme and not u.netloc and not value.startswith(("mailto:", "javascript:", "data:"))


def check_links(site: pathlib.Path) -> list[str]:
    problems, pages = [], {}
    html = sorted(site.rglob("*.html"))
    for page in html:
        pages[page] = _parse(page)
    for page, refs in pages.items():
        rel = page.relative_to(site)
        for where, value in refs.refs:
            if not _internal(value):
                continue
            u = urllib.parse.urlsplit(value)
            target = (page.parent / urllib.parse.unquote(u.path)).resolve() if u.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                problems.append(f"{rel}: {where} = {value!r}: no such file in the site")
                continue
            if u.fragment and target.suffix == ".html" and where == "a.href":
                ids = pages[target].ids if target in pages else _parse(target).ids
                if u.fragment not in ids:
                    problems.append(f"{rel}: {where} = {value!r}: no id {u.fragment!r} "
                                    f"in {target.relative_to(site)}")
    if not html:
        problems.append(f"{site}: no HTML pages (run make docs first)")
    return problems


class _Quiet(http.server.SimpleHTTPRequestHandler):
    failed: list[str] = []

    def log_message(self, fmt, *args):
        pass

    def send_error(self, code, message=None, explain=None):
        if code >= 400 and not self.path.endswith("favicon.ico"):
            _Quiet.failed.append(f"{code} {self.path}")
        super().send_error(code, message, explain)


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        p = shutil.which(name)
        if p:
            return p
    return None


def check_in_browser(site: pathlib.Path, shots: pathlib.Path) -> list[str]:
    exe = _chromium()
    if exe is None:
        return ["chromium not found (apt-get install chromium; .ci/setup.sh installs it)"]
    handler = functools.partial(_Quiet, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    port = server.server_address[1]
    threading.Thread(target=server.serve_forever, daemon=True).start()
    problems = []
    shots.mkdir(parents=True, exist_ok=True)
    try:
        for shot, page in SCREENSHOT_PAGES.items():
            if not (site / page).exists():
                problems.append(f"{page}: not in the site")
                continue
            url = f"http://127.0.0.1:{port}/{page}"
            with tempfile.TemporaryDirectory() as profile:
                base = [exe, "--headless", "--no-sandbox", "--disable-gpu",
                        "--disable-background-networking", "--disable-component-update",
                        "--disable-sync", "--no-first-run", "--hide-scrollbars",
                        f"--user-data-dir={profile}", "--window-size=1280,900",
                        "--virtual-time-budget=5000"]
                r = subprocess.run(base + [f"--screenshot={shots / shot}", url],
                                   capture_output=True, text=True, timeout=120)
                if r.returncode != 0 or not (shots / shot).exists():
                    problems.append(f"{page}: chromium screenshot failed (exit {r.returncode}): "
                                    f"{r.stderr.strip()[-300:]}")
                dom = subprocess.run(base + ["--dump-dom", url], capture_output=True,
                                     text=True, timeout=120)
                if dom.returncode != 0 or "<html" not in dom.stdout:
                    problems.append(f"{page}: chromium --dump-dom failed (exit {dom.returncode})")
                    continue
                refs = Refs()
                refs.feed(dom.stdout)
                for src in refs.images:
                    if _internal(src):
                        target = (site / page).parent / urllib.parse.unquote(
                            urllib.parse.urlsplit(src).path)
                        if not target.resolve().exists():
                            problems.append(f"{page}: image {src!r} does not load")
    finally:
        server.shutdown()
    problems += [f"the browser's request failed: {f}" for f in _Quiet.failed]
    return problems


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--site", default=str(DOCS / "_build" / "html"))
    ap.add_argument("--screenshots", default=str(DOCS / "_build" / "screenshots"))
    ap.add_argument("--no-browser", action="store_true", help="only the link check")
    args = ap.parse_args(argv)
    site = pathlib.Path(args.site)
    problems = check_links(site)
    n_pages = len(list(site.rglob("*.html")))
    if not args.no_browser:
        problems += check_in_browser(site, pathlib.Path(args.screenshots))
    for p in problems:
        print(f"docs-check: {p}", file=sys.stderr)
    shots = "" if args.no_browser else f"; screenshots in {args.screenshots}"
    print(f"docs-check: {n_pages} pages, {len(problems)} problem(s){shots}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
