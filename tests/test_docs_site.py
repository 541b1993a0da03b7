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


def _topic_index() -> dict:
    """The topic index of ``hyperlattice.__doc__``: topic -> names (the block after ``::``)."""
    import hyperlattice

    block = hyperlattice.__doc__.split("::", 1)[1].split("\nConventions", 1)[0]
    topics: dict = {}
    head = None
    for line in block.splitlines():
        if not line.strip():
            continue
        if line[4:24].strip():
            head = line[4:24].strip()
        topics.setdefault(head, []).extend(line[24:].split())
    return topics


def test_help_is_short_and_indexes_the_whole_top_level_api_by_topic():
    """Issue 28 item 4: ``help(hyperlattice)`` is the topic index, not ~6,000 lines of every class."""
    import pydoc

    import hyperlattice

    for name in hyperlattice.__all__:   # every lazy export loaded, as after other tests or a session's work
        getattr(hyperlattice, name)
    text = pydoc.render_doc(hyperlattice, renderer=pydoc.plaintext)
    assert len(text.splitlines()) < 120, len(text.splitlines())
    assert "Index by topic" in text and "class Butterfly" not in text
    names = [n for names in _topic_index().values() for n in names]
    assert len(names) == len(set(names))
    assert sorted(names) == sorted(n for n in hyperlattice.__all__ if n != "__version__")
    assert "ring_lattice" in dir(hyperlattice) and "mott_lobes" in dir(hyperlattice)   # completion keeps the API


def test_bosons_api_is_exported_at_top_level():
    import hyperlattice
    import hyperlattice.bosons as bosons

    for name in bosons.__all__:
        assert name in hyperlattice.__all__ and getattr(hyperlattice, name) is getattr(bosons, name), name
    from hyperlattice.compare.bosons import gp_comparison, mott_gap_comparison

    assert hyperlattice.gp_comparison is gp_comparison and hyperlattice.mott_gap_comparison is mott_gap_comparison


def test_landing_page_indexes_the_api_by_topic_with_links():
    """docs/index.md has the same topic index as the package docstring, each name linked to its page."""
    import re

    import hyperlattice

    text = (DOCS / "index.md").read_text()
    rows = {m.group(1): m.group(2) for m in re.finditer(r"^\| ([^|]+?) \| (\{py:.*) \|$", text, re.M)}
    expected = _topic_index()
    assert list(rows) == list(expected)
    for topic, names in expected.items():
        links = re.findall(r"\{py:(func|class)\}`(\w+) <([\w.]+)>`", rows[topic])
        assert [n for _, n, _ in links] == names, topic
        for _, name, target in links:
            obj = getattr(hyperlattice, name)
            assert target == f"{obj.__module__}.{name}", name


def test_maths_rendered_offline_and_code_blocks_wrap():
    """No MathJax (it comes from a CDN): the maths is MathML written at build time (docs/_ext/mathml.py)."""
    import importlib.util

    conf = (DOCS / "conf.py").read_text()
    assert "sphinx.ext.mathjax" not in conf and 'html_math_renderer = "mathml"' in conf
    spec = importlib.util.spec_from_file_location("mathml", DOCS / "_ext" / "mathml.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    import hyperlattice.bosons as bosons

    formula = bosons.__doc__.split(".. math::", 1)[1].split("\n\n")[1]   # the Bose-Hubbard Hamiltonian
    markup = mod.to_mathml(formula, display=True)
    assert markup.startswith("<math") and 'display="block"' in markup and "\\sum" not in markup
    assert "&#x02211;" in markup or "∑" in markup
    css = (DOCS / "_static" / "hyperlattice.css").read_text()
    assert "white-space: pre-wrap" in css and '"hyperlattice.css"' in conf


def test_readme_opens_with_the_two_commands_one_example_and_links_to_docs():
    """A newcomer meets what the package does, the two commands and one example on the first screen
    and finds the rest in docs/ (the README stays short); the report's time is a range measured on
    a loaded 2-core machine (docs/quickstart.md), not one idle-machine number."""
    import re

    readme = (DOCS.parent / "README.md").read_text()
    lines = readme.splitlines()
    assert len(lines) <= 250
    heads = re.findall(r"^## (.+)$", readme, re.M)
    assert heads[0] == "Start here" and "What else it does" in heads
    first = readme.split("## Start here", 1)[1].split("\n## ", 1)[0]
    assert "make run " in first and "make test " in first and "```python" in first
    assert "report.html" in first and "help(hyperlattice)" in first
    screen = "\n".join(lines[:60])
    assert "make run" in screen and "make test" in screen and "```python" in screen
    # the README's list links the docs pages (a page added later gets its line there), and every link works
    linked = set(re.findall(r"\(docs/([\w-]+\.md)\)", readme))
    assert len(linked) >= 15 and all((DOCS / name).is_file() for name in linked), linked
    quick = (DOCS / "quickstart.md").read_text()
    run = quick.split("`make run` runs `hyperlattice reproduce --out reproduction`", 1)[1].split("\n\n", 1)[0]
    assert re.search(r"\d+–\d+ minutes", run) and "about 50 s" not in run
