"""Open a ``hyperlattice reproduce`` report in headless Chromium, screenshot it, check its links.

    python tools/screenshot_report.py reproduction/report.html --out /tmp/shots

writes ``top.png`` (the title and the table of contents), ``toc.png`` (``#contents``) and one PNG
per section anchor given with ``--section`` (default: the spectrum and the band-bottom sections),
and fails (exit 1) when a link of the table of contents points to an id the page does not have.
Look at the PNGs: this is the check that the report reads well in a browser, which no unit test
replaces. Needs a Chromium binary (Debian: ``apt-get install chromium``); ``--chromium`` names it.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path

#: Chromium's headless flags on this kind of machine (no GPU, no network side traffic, fresh profile)
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--virtual-time-budget=15000")


class _Ids(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.ids: list[str] = []
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name == "id" and value:
                self.ids.append(value)
            if name == "href" and value and value.startswith("#"):
                self.links.append(value[1:])


def check_links(html: str) -> dict:
    """``{"links": [...], "missing": [...], "duplicate_ids": [...]}`` of the in-page links of ``html``."""
    p = _Ids()
    p.feed(html)
    ids = set(p.ids)
    return {"links": p.links, "missing": sorted({x for x in p.links if x not in ids}),
            "duplicate_ids": sorted({x for x in p.ids if p.ids.count(x) > 1})}


def find_chromium(name: str | None = None) -> str | None:
    """The Chromium binary: ``name`` if given, else the first of chromium, chromium-browser, google-chrome."""
    for candidate in ([name] if name else ["chromium", "chromium-browser", "google-chrome"]):
        path = shutil.which(candidate)
        if path:
            return path
    return None


#: Headless Chromium's ``--screenshot`` draws a blank page once the document is scrolled (seen with
#: Chromium 156 and a page scrolled to its URL fragment), so the copy that is screenshot removes
#: everything before the fragment's target: the target is then at the top without scrolling. The
#: target is still found through the URL fragment, as a reader's browser finds it.
_TRIM = """<script>
(function () {
  var id = decodeURIComponent(location.hash.slice(1));
  var n = id ? document.getElementById(id) : null;
  if (!n) { if (id) document.title = "MISSING " + id; return; }
  while (n.parentNode && n.parentNode !== document.body) n = n.parentNode;
  while (n.previousSibling) n.parentNode.removeChild(n.previousSibling);
})();
</script>"""


def screenshot(chromium: str, page: Path, out: Path, fragment: str = "", size: tuple[int, int] = (1280, 900),
               timeout: float = 120.0) -> Path:
    """Screenshot ``page`` at ``#fragment`` (or its top) into ``out`` at ``size`` pixels."""
    html = Path(page).read_text(encoding="utf-8")
    if fragment:
        html = html.replace("</body>", _TRIM + "\n</body>", 1)
    with tempfile.TemporaryDirectory() as profile:
        # the copy sits next to the original so that relative references would still resolve
        copy = Path(page).resolve().parent / f".screenshot-{Path(out).stem}.html"
        copy.write_text(html, encoding="utf-8")
        try:
            url = copy.as_uri() + (f"#{fragment}" if fragment else "")
            cmd = [chromium, *FLAGS, f"--user-data-dir={profile}", f"--window-size={size[0]},{size[1]}",
                   f"--screenshot={out}", url]
            subprocess.run(cmd, check=True, capture_output=True, timeout=timeout)
        finally:
            copy.unlink(missing_ok=True)
    if not out.is_file() or out.stat().st_size == 0:
        raise RuntimeError(f"chromium wrote no screenshot for {url}")
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("report", type=Path, help="report.html")
    ap.add_argument("--out", type=Path, default=Path("report-shots"), help="directory for the PNGs")
    ap.add_argument("--section", action="append", help="anchor to screenshot (repeatable)")
    ap.add_argument("--chromium", help="Chromium binary (default: found on PATH)")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=900)
    args = ap.parse_args(argv)
    html = args.report.read_text(encoding="utf-8")
    links = check_links(html)
    print(f"{len(links['links'])} in-page links; missing targets: {links['missing'] or 'none'}; "
          f"duplicate ids: {links['duplicate_ids'] or 'none'}")
    chromium = find_chromium(args.chromium)
    if chromium is None:
        print("no chromium binary found: links checked, no screenshots taken", file=sys.stderr)
        return 1 if links["missing"] or links["duplicate_ids"] else 0
    args.out.mkdir(parents=True, exist_ok=True)
    size = (args.width, args.height)
    shots = [("top", ""), ("toc", "contents")]
    shots += [(s, s) for s in (args.section or ["sec-spectrum", "sec-band-bottom"])]
    for name, fragment in shots:
        path = screenshot(chromium, args.report, args.out / f"{name}.png", fragment, size)
        print(f"wrote {path}")
    return 1 if links["missing"] or links["duplicate_ids"] else 0


if __name__ == "__main__":
    sys.exit(main())
