"""The report in a browser: tools/screenshot_report.py checks the in-page links and, where a Chromium
binary exists, screenshots a small report built by the same writers as ``hyperlattice reproduce``."""

import importlib.util
from pathlib import Path

import pytest

from hyperlattice.report.writers import Section, Table, write_html, write_md

TOOL = Path(__file__).resolve().parents[1] / "tools" / "screenshot_report.py"


def _tool():
    spec = importlib.util.spec_from_file_location("screenshot_report", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _small_report(out: Path) -> Path:
    wide = Table("wide", [f"column_{k}" for k in range(19)], [[f"{k * 1.234567:.6f}" for k in range(19)]] * 3,
                 "A table with 19 columns (like s1_vs_paper): it scrolls instead of being clipped.")
    sections = [Section("Levels", ("SuppTab1", "spec17"), ["E_inf and -rho for l = 3..5."], [wide],
                        anchor="spectrum"),
                Section("Band bottom", ("AppSpec",), ["Beyond the paper."], [], anchor="band-bottom", part="beyond",
                        provenance=["stored; regenerate with `python -c \"print(1)\"`"])]
    header = ["# A small report", "", "Intro.", ""]
    write_html(sections, header, out)
    write_md(sections, header, out)
    return out / "report.html"


def test_links_of_the_table_of_contents_resolve(tmp_path):
    tool = _tool()
    page = _small_report(tmp_path)
    html = page.read_text(encoding="utf-8")
    got = tool.check_links(html)
    assert got["missing"] == [] and got["duplicate_ids"] == []
    assert {"sec-spectrum", "sec-band-bottom", "table-wide", "part-paper", "part-beyond"} <= set(got["links"])
    assert "Reproduces: " not in html and "<b>Reproduces:</b> Table IV, Eq. (F16)" in html
    assert "E∞ and −ρ for ℓ = 3–5." in html
    assert tool.check_links('<a href="#nowhere">x</a><p id="a"></p><p id="a"></p>') == {
        "links": ["nowhere"], "missing": ["nowhere"], "duplicate_ids": ["a"]}


@pytest.mark.skipif(_tool().find_chromium() is None, reason="no chromium binary on this machine")
def test_screenshots(tmp_path):
    tool = _tool()
    page = _small_report(tmp_path)
    code = tool.main([str(page), "--out", str(tmp_path / "shots"), "--section", "sec-band-bottom",
                      "--width", "800", "--height", "600"])
    assert code == 0
    from matplotlib.image import imread

    for name in ("top", "toc", "sec-band-bottom"):
        path = tmp_path / "shots" / f"{name}.png"
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        img = imread(path)
        assert img.shape[:2] == (600, 800), name
        # text drawn (a blank page is what headless Chromium gives for a scrolled page: see the tool)
        assert (img[..., :3] < 0.3).mean() > 0.002, name


def test_contents_use_the_papers_numbers_not_file_stems(tmp_path):
    """Issue 28 item 3: "Table IV", "Fig. 3" for what the paper prints, "Table 2.1" for the report's own."""
    from hyperlattice.report.writers import Figure

    levels = Table("s1", ["rings", "E0"], [[1, -2.0]], "Table IV: levels.", paper="SuppTab1")
    own = Table("band_fit", ["rings", "E0"], [[1, -2.0]], "Fits.")
    fig = Figure("fig2", "Levels against rings.", paper="Fig2")
    sections = [Section("Levels", ("SuppTab1",), [], [levels], [fig], anchor="spectrum"),
                Section("Band bottom", ("AppSpec",), [], [own], [], anchor="band-bottom", part="beyond")]
    write_html(sections, ["# r"], tmp_path)
    write_md(sections, ["# r"], tmp_path)
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    nav = page[page.index('<nav class="toc"'):page.index("</nav>")]
    assert '>Table IV</a>' in nav and '>Fig. 3</a>' in nav and '>Table 2.1</a>' in nav
    assert "s1<" not in nav and "fig2<" not in nav and "band_fit<" not in nav
    assert "<figcaption>Fig. 3. Levels against rings.</figcaption>" in page
    assert '<p class="cap" id="table-s1">Table IV: levels. ' in page     # not "Table IV. Table IV: ..."
    assert '<p class="cap" id="table-band-fit">Table 2.1. Fits. ' in page
    md = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "[Table IV](#table-s1)" in md and "[Fig. 3](#fig-fig2)" in md and "*Table 2.1. Fits.*" in md
    with pytest.raises(ValueError, match="not a label of the paper"):
        Table("x", ["a"], [[1]], paper="Tab99")


#: sets data-overflow on <body> to the ids of the tables wider than their box, once the page is laid out
_MEASURE = """<script>
window.addEventListener("load", function () {
  var wide = [];
  document.querySelectorAll("div.scroll").forEach(function (d) {
    if (d.scrollWidth > d.clientWidth + 1) wide.push(d.previousElementSibling.id);
  });
  document.body.setAttribute("data-overflow", wide.join(",") || "none");
});
</script>"""


@pytest.mark.skipif(_tool().find_chromium() is None, reason="no chromium binary on this machine")
def test_the_papers_tables_fit_a_1400px_window_in_chromium(tmp_path):
    """Issue 28 item 3: the printed-vs-computed tables (11 columns each, as the report writes them)
    need no sideways scrolling in a 1400-px window; a 19-column table would."""
    import re
    import subprocess

    cols = ["rings", "flagged"]
    for kind in ("graph", "continuum", "asymptotic"):
        cols += [f"E0_{kind}", f"E0_{kind}_paper", f"E0_{kind}_flag"]
    rows = [[ell, "graph", "-2.846633", "-2.847", "≠", "-2.841760", "-2.842", "", "-2.860802", "-2.861", ""]
            for ell in range(1, 11)]
    wide = Table("wide19", [f"E0_continuum_paper_{k}" for k in range(19)], [["-2.841760"] * 19], "Too wide.")
    sections = [Section("Levels", ("SuppTab1",), [], [Table("s1_vs_paper_E0", cols, rows, "E0."), wide])]
    write_html(sections, ["# r"], tmp_path)
    page = tmp_path / "report.html"
    page.write_text(page.read_text(encoding="utf-8").replace("</body>", _MEASURE + "</body>"), encoding="utf-8")
    tool = _tool()
    with __import__("tempfile").TemporaryDirectory() as profile:
        dom = subprocess.run([tool.find_chromium(), *tool.FLAGS, f"--user-data-dir={profile}", "--window-size=1400,900",
                              "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120).stdout
    overflow = re.search(r'data-overflow="([^"]*)"', dom).group(1)
    assert overflow == "table-wide19"     # the 19-column table would scroll; the 11-column one fits
