"""Open the HTML pages the project writes in headless Chromium and check what a reader sees.

    python scripts/browser.py [PAGE.html|FOLDER ...] [--shots DIR] [--width PX]

Every page given (or every ``*.html`` under a folder given; default ``build/campaign``) is
opened from the disk in the distribution's Chromium (``/usr/bin/chromium``, driven by
Playwright's Python package: no browser download, no server, no network) and checked:

- **layout**: no image or canvas sticks out of the box that holds it, and the page does not
  scroll sideways at the window's width;
- **figures whole**: every image decodes (``naturalWidth > 0``), and none has ink on its
  outermost rows or columns — a figure drawn outside its canvas (a title or legend cut at
  the edge) leaves it there, while a figure laid out inside its canvas keeps a margin;
- **links**: every local ``href`` reaches a file (and its ``#fragment`` an element of it);
  links to the web are not followed;
- **console and requests**: no console error, no uncaught exception, no file that fails to
  load, and nothing asked of the network (every request off the disk is refused and
  reported: the pages must work offline).

``--shots DIR`` keeps a full-page screenshot of each page (``DIR/<folder>_<name>.png``).
Exit status: 0 when every page passed (or no Chromium is installed: then nothing is
checked, and it says so), 1 when a check failed (each problem printed), 2 for bad use.

The test suite (``tests/test_browser.py``) uses the same :class:`Browser`; ``make
reproduce`` runs this script on the campaign it writes, keeping the screenshots in
``build/browser/``.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import sys
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from urllib.parse import unquote, urlsplit

#: Where the distribution's Chromium is (``PIPELINE_CHROMIUM`` overrides it).
CHROMIUM = "/usr/bin/chromium"

#: Chromium's switches: headless as root (no sandbox), and nothing that reaches the
#: network by itself (updates, sync, first-run pages); file pages may read each other's
#: images (for the edge check of the docs' figures).
FLAGS = (
    "--no-sandbox",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-gpu",
    "--allow-file-access-from-files",
)

#: Milliseconds any one step may take before it counts as hung (a guard against a page
#: that never finishes, not a speed requirement: pages take well under a second).
HANG_MS = 600_000

#: The layout, image and link facts of the page in the window, gathered in the page.
_FACTS_JS = r"""
() => {
  const problems = [];
  const root = document.documentElement;
  const vw = root.clientWidth;
  if (root.scrollWidth > vw + 1)
    problems.push(`the page is ${root.scrollWidth}px wide in a ${vw}px window: it scrolls ` +
                  `sideways`);
  const label = (el, k) => {
    const src = el.getAttribute && el.getAttribute('src');
    if (src && !src.startsWith('data:')) return `image ${src}`;
    const alt = el.getAttribute && el.getAttribute('alt');
    const kind = el.tagName.toLowerCase() === 'img' ? 'image' : el.tagName.toLowerCase();
    return `${kind} ${k + 1}` + (alt ? ` ("${alt.slice(0, 60)}")` : '') + ' of the page';
  };
  const parentOf = (el) => el.parentElement || (el.getRootNode() && el.getRootNode().host);
  // an element sticking out of any box that holds it, up to the page's body
  const outside = (el) => {
    const r = el.getBoundingClientRect();
    for (let p = parentOf(el); p && p !== document.body && p !== root; p = parentOf(p)) {
      const s = getComputedStyle(p);
      if (s.display === 'contents' || s.display.startsWith('inline')) continue;
      const b = p.getBoundingClientRect();
      if (r.right > b.right + 1 || r.left < b.left - 1) {
        const name = p.id ? `#${p.id}` : (p.className && typeof p.className === 'string'
          ? `.${p.className.trim().split(/\s+/)[0]}` : p.tagName.toLowerCase());
        return `${Math.round(r.width)}px wide, sticks out of its box ${name} ` +
               `(${Math.round(b.left)}–${Math.round(b.right)}px)`;
      }
    }
    if (r.right > vw + 1) return `reaches ${Math.round(r.right)}px, past the window (${vw}px)`;
    return null;
  };
  const all = (node, sel, out = []) => {
    node.querySelectorAll(sel).forEach((e) => out.push(e));
    node.querySelectorAll('*').forEach((e) => { if (e.shadowRoot) all(e.shadowRoot, sel, out); });
    return out;
  };
  const images = [...document.images];
  images.forEach((img, k) => {
    if (!img.complete || img.naturalWidth === 0) {
      problems.push(`${label(img, k)}: broken (it does not decode)`);
      return;
    }
    const r = img.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) return;  // not shown
    const o = outside(img);
    if (o) problems.push(`${label(img, k)}: ${o}`);
  });
  all(document, 'canvas').forEach((c, k) => {
    const r = c.getBoundingClientRect();
    if (r.width === 0) return;
    const o = outside(c);
    if (o) problems.push(`canvas ${k + 1} of the page: ${o}`);
  });
  const ids = all(document, '[id], a[name]').map((e) => e.id || e.getAttribute('name'));
  const links = [...document.querySelectorAll('a[href]')].map(
    (a) => ({href: a.href, raw: a.getAttribute('href')}));
  return {problems, ids, links, images: images.length};
}
"""

#: Images with ink on an edge (drawn outside their canvas), found in the page.
_EDGES_JS = r"""
() => {
  const out = [];
  [...document.images].forEach((img, k) => {
    if (!img.complete || img.naturalWidth < 16 || img.naturalHeight < 16) return;
    // a gallery's thumbnails are figures shrunk into a box: their margins shrink to
    // nothing (the figures themselves are checked on their examples' pages)
    if (img.closest('.sphx-glr-thumbcontainer')) return;
    const w = img.naturalWidth, h = img.naturalHeight;
    const c = document.createElement('canvas');
    c.width = w; c.height = h;
    const g = c.getContext('2d', {willReadFrequently: true});
    g.drawImage(img, 0, 0);
    let px;
    try { px = g.getImageData(0, 0, w, h).data; } catch (e) { return; }
    const at = (x, y) => { const i = 4 * (y * w + x); return [px[i], px[i+1], px[i+2], px[i+3]]; };
    // the background: the colour of most corners (transparent counts as one colour)
    const corners = [at(0, 0), at(w - 1, 0), at(0, h - 1), at(w - 1, h - 1)];
    const key = (p) => p[3] < 16 ? 'clear' : p.slice(0, 3).map((v) => v >> 4).join(',');
    const counts = {};
    corners.forEach((p) => { counts[key(p)] = (counts[key(p)] || 0) + 1; });
    const bgKey = Object.keys(counts).sort((a, b) => counts[b] - counts[a])[0];
    const bg = corners.find((p) => key(p) === bgKey);
    const ink = (p) => bg[3] < 16 ? p[3] > 96 :
      (p[3] > 96 && Math.max(Math.abs(p[0] - bg[0]), Math.abs(p[1] - bg[1]),
                             Math.abs(p[2] - bg[2])) > 64);
    const edges = {top: [], bottom: [], left: [], right: []};
    for (let x = 0; x < w; x++) { edges.top.push(at(x, 0)); edges.bottom.push(at(x, h - 1)); }
    for (let y = 0; y < h; y++) { edges.left.push(at(0, y)); edges.right.push(at(w - 1, y)); }
    const cut = Object.entries(edges).filter(([, ps]) => ps.filter(ink).length >= 2)
      .map(([side]) => side);
    const src = img.getAttribute('src') || '';
    if (cut.length)
      out.push({k, src: src.startsWith('data:') ? '' : src, alt: img.getAttribute('alt') || '',
                cut});
  });
  return out;
}
"""


def chromium() -> str | None:
    """The Chromium to drive: ``$PIPELINE_CHROMIUM``, else :data:`CHROMIUM` or ``chromium``
    on the PATH; None where there is none (the browser checks then skip)."""
    for candidate in (os.environ.get("PIPELINE_CHROMIUM"), CHROMIUM, shutil.which("chromium")):
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    return None


@dataclass(frozen=True)
class PageCheck:
    """What a page showed in the browser.

    Attributes
    ----------
    page : pathlib.Path — the HTML file
    problems : tuple of str — each failed check, in words (empty: the page passed)
    screenshot : pathlib.Path or None — the full-page screenshot, where one was asked for
    images : int — images on the page
    links : int — local links followed
    """

    page: Path
    problems: tuple = ()
    screenshot: Path | None = None
    images: int = 0
    links: int = 0

    @property
    def ok(self) -> bool:
        return not self.problems


@dataclass
class _Events:
    """Console errors, exceptions, failed and refused requests of one page load."""

    problems: list = field(default_factory=list)


class Browser:
    """Headless Chromium (Playwright) opening pages from the disk, one at a time.

    Use as a context manager: ``with Browser() as b: b.check(path, screenshot=png)``.

    Parameters
    ----------
    executable : str, optional — the Chromium binary (default :func:`chromium`)
    width, height : int — the window [px] (a laptop's: 1280 × 900)
    """

    def __init__(self, executable: str | None = None, *, width: int = 1280, height: int = 900):
        self.executable = executable or chromium()
        if self.executable is None:
            raise RuntimeError(
                f"no Chromium: install it (apt-get install chromium) or set "
                f"PIPELINE_CHROMIUM (looked at {CHROMIUM} and the PATH)"
            )
        self.viewport = {"width": width, "height": height}
        self._pw = self._browser = self._page = None

    def __enter__(self) -> Browser:
        from playwright.sync_api import sync_playwright

        self._pw = sync_playwright().start()
        try:
            self._browser = self._pw.chromium.launch(
                executable_path=self.executable, args=list(FLAGS), timeout=HANG_MS
            )
        except BaseException:
            self._pw.stop()
            raise
        return self

    def __exit__(self, *exc) -> None:
        try:
            self._browser.close()
        finally:
            self._pw.stop()

    @property
    def version(self) -> str:
        return self._browser.version

    def new_page(self):
        """A fresh page (its own context) that records console errors, exceptions and
        failed requests in ``page.events`` and refuses every request off the disk."""
        context = self._browser.new_context(viewport=self.viewport)
        context.set_default_timeout(HANG_MS)
        events = _Events()

        def refuse(route):
            # the page that asked (not another tab it opened) records it
            asker = getattr(route.request.frame.page, "events", None)
            if asker is not None:
                asker.problems.append(f"asks the network for {route.request.url[:120]}")
            route.abort()

        context.route(re.compile(r"^(?!file:|data:|blob:|about:).*"), refuse)
        page = context.new_page()
        page.on(
            "console",
            lambda m: m.type == "error" and events.problems.append(f"console error: {m.text}"),
        )
        page.on("pageerror", lambda e: events.problems.append(f"uncaught exception: {e}"))
        page.on(
            "requestfailed",
            lambda r: (
                r.url.startswith("file:")
                and events.problems.append(f"cannot load {_short(r.url)} ({r.failure})")
            ),
        )
        page.events = events
        return page

    def load(self, page, path) -> None:
        """Open ``path`` in ``page`` and wait until it has drawn (its images decoded, a
        Bokeh document idle)."""
        page.goto(Path(path).resolve().as_uri(), wait_until="load")
        if page.evaluate("() => Boolean(window.Bokeh)"):  # BokehJS draws after the load
            page.wait_for_function(
                "() => Bokeh.documents.length > 0 && Bokeh.documents.every((d) => d.is_idle)"
            )
        page.evaluate(
            "() => Promise.all([...document.images].map((i) => i.decode().catch(() => null)))"
        )

    def check(self, path, *, screenshot=None) -> PageCheck:
        """Open ``path`` and run every check (module notes); keep a screenshot if asked.

        The pages are opened one after the other in one tab (a fresh tab costs twice the
        time of a page), its record of errors emptied before each."""
        path = Path(path).resolve()
        if self._page is None:
            self._page = self.new_page()
        page = self._page
        page.events.problems.clear()
        self.load(page, path)
        problems, images, links = inspect_page(page, path)
        if screenshot is not None:
            screenshot = Path(screenshot)
            screenshot.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(screenshot), full_page=True)
        problems = page.events.problems + problems
        return PageCheck(path, tuple(problems), screenshot, images, links)


def inspect_page(page, path: Path) -> tuple[list, int, int]:
    """The layout, figure and link problems of a loaded page; its numbers of images and
    local links."""
    facts = page.evaluate(_FACTS_JS)
    problems = list(facts["problems"])
    for edge in page.evaluate(_EDGES_JS):
        name = f"image {edge['src']}" if edge["src"] else f"image {edge['k'] + 1} of the page"
        alt = f' ("{edge["alt"][:60]}")' if edge["alt"] else ""
        problems.append(
            f"{name}{alt}: drawn to its {' and '.join(edge['cut'])} edge — the figure "
            "does not fit its canvas (cut)"
        )
    n_links = 0
    for link in facts["links"]:
        problem = _link_problem(link["href"], link["raw"], path, set(facts["ids"]))
        if problem is not None:
            problems.append(problem)
        n_links += urlsplit(link["href"]).scheme == "file"
    return problems, facts["images"], n_links


def _link_problem(href: str, raw: str, page: Path, ids: set) -> str | None:
    """Why a link is broken, or None (links off the disk are not followed)."""
    url = urlsplit(href)
    if url.scheme != "file":
        return None
    target = Path(unquote(url.path))
    # a browser looks for the fragment as written, then percent-decoded (HTML standard,
    # "the indicated part of the document"); "#top" is the page's top
    fragments = {url.fragment, unquote(url.fragment)} - {"", "top"}
    if target == page:
        if fragments and not fragments & ids:
            return f"link {raw!r}: no element #{unquote(url.fragment)} on the page"
        return None
    if target.is_dir():
        target = target / "index.html"
    if not target.is_file():
        return f"link {raw!r}: no such file {_short(target.as_uri())}"
    if fragments and target.suffix in (".html", ".htm") and not fragments & _ids_of(target):
        return f"link {raw!r}: no element #{unquote(url.fragment)} in {target.name}"
    return None


@lru_cache(maxsize=512)
def _ids_of(page: Path) -> frozenset:
    text = page.read_text(encoding="utf-8", errors="replace")
    return frozenset(
        m.group(2) for m in re.finditer(r"""\b(id|name)\s*=\s*["']([^"']+)["']""", text)
    )


def _short(url: str) -> str:
    path = unquote(urlsplit(url).path)
    try:
        return os.path.relpath(path)
    except ValueError:
        return path


def pages_under(paths) -> list[Path]:
    """The HTML files named, or found under the folders named (sorted; staging and hidden
    folders left out)."""
    out = []
    for p in map(Path, paths):
        if p.is_dir():
            out += sorted(
                f
                for f in p.rglob("*.html")
                if not any(part.startswith(".") for part in f.relative_to(p).parts)
            )
        elif p.is_file():
            out.append(p)
    return out


def shot_name(page: Path, shots: Path) -> Path:
    """The screenshot of ``page``: ``<shots>/<parent folder>_<stem>.png``."""
    return shots / f"{page.parent.name}_{page.stem}.png"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawTextHelpFormatter
    )
    parser.add_argument("paths", nargs="*", default=["build/campaign"], type=Path)
    parser.add_argument("--shots", type=Path, help="keep a screenshot of each page here")
    parser.add_argument("--width", type=int, default=1280, help="window width [px, 1280]")
    args = parser.parse_args(argv)
    pages = pages_under(args.paths)
    if not pages:
        print(f"no HTML pages in {', '.join(map(str, args.paths))}", file=sys.stderr)
        return 2
    if chromium() is None:
        print(f"no Chromium at {CHROMIUM} or on the PATH: {len(pages)} pages not checked")
        return 0
    failed = 0
    with Browser(width=args.width) as browser:
        for page in pages:
            shot = None if args.shots is None else shot_name(page, args.shots)
            r = browser.check(page, screenshot=shot)
            failed += not r.ok
            status = "ok" if r.ok else f"{len(r.problems)} problem(s)"
            print(f"{page}: {status}" + (f" → {shot}" if shot else ""))
            for problem in r.problems:
                print(f"  {problem}")
    print(f"{len(pages) - failed} of {len(pages)} pages read well in Chromium {browser.version}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
