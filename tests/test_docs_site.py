"""The documentation site (``make docs``, Sphinx): its index lists every docs page.

The build itself runs in CI (``.ci/run``: ``make docs``, warnings as errors); a page missing
from the toctree would be a warning there, this test says which one without building.
"""

from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_index_toctree_lists_every_page_once():
    text = (DOCS / "index.md").read_text()
    block = text.split("```{toctree}", 1)[1].split("```", 1)[0]
    entries = [line.strip() for line in block.splitlines() if line.strip() and not line.strip().startswith(":")]
    pages = sorted(p.stem for p in DOCS.glob("*.md") if p.stem != "index")
    assert len(entries) == len(set(entries))
    assert sorted(e for e in entries if e != "api") == pages
    assert "api" in entries and (DOCS / "api.rst").exists() and (DOCS / "conf.py").exists()
