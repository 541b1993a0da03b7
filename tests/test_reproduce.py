"""Reduced end-to-end reproduction: files exist, tables parse, numbers equal the API's."""

import csv
import json
from html.parser import HTMLParser

import pytest

from hyperlattice.cache import Cache
from hyperlattice.cli import main
from hyperlattice.report import compare, reproduce


class _Checker(HTMLParser):
    """Collects tags and every external reference; checks the tag nesting."""

    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.external, self.images = [], [], [], 0

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("src", "href") and value and not value.startswith("data:"):
                self.external.append(value)
        if tag == "img":
            self.images += 1
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"unexpected </{tag}> (open: {self.stack[-3:]})")
        else:
            self.stack.pop()


@pytest.fixture(scope="module")
def repro(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    cache = Cache(out / "cache")
    summary = reproduce(out / "report", max_rings=4, cache=cache)
    return out, summary


def test_files_exist(repro):
    out, _ = repro
    rep = out / "report"
    for name in ("report.html", "report.md", "table_s1.csv", "table_s1.json", "table_geometry.csv",
                 "table_tab1_sizes.csv", "fig_fig1.png", "fig_fig1.svg", "fig_fig2.png", "fig_figS1.png",
                 "fig_figScos3delta.png", "fig_figSh.png", "fig_fig3a.png", "fig_fig3b.png",
                 "table_fig3_green.csv", "timings.json"):
        assert (rep / name).stat().st_size > 0, name


def test_table_s1_matches_api(repro):
    from hyperlattice import ring_lattice
    from hyperlattice.continuum.spectrum import asymptotic_energies, continuum_levels
    from hyperlattice.graph.spectrum import lowest_levels

    out, _ = repro
    with open(out / "report" / "table_s1.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["rings", "sites", "radius", "E0_graph", "E0_continuum", "E0_asymptotic",
                             "E1_graph", "E1_continuum", "E1_asymptotic"]
    assert [int(r["rings"]) for r in rows] == [1, 2, 3, 4]
    for r in rows:
        ell = int(r["rings"])
        g = lowest_levels(ring_lattice(7, 3, ell), levels=2)
        c = continuum_levels(7, 3, rings=ell, levels=2)
        a = asymptotic_energies(7, 3, rings=ell)
        assert float(r["E0_graph"]) == pytest.approx(g.energies[0], abs=1e-11)
        assert float(r["E1_graph"]) == pytest.approx(g.energies[1], abs=1e-11)
        assert float(r["E0_continuum"]) == pytest.approx(c.energies[0], abs=1e-11)
        assert float(r["E1_continuum"]) == pytest.approx(c.energies[1], abs=1e-11)
        assert float(r["E0_asymptotic"]) == pytest.approx(a["E0"], abs=1e-11)
        assert float(r["radius"]) == pytest.approx(c.radius, abs=1e-9)
    # E_graph printed with at least 10 digits
    assert len(rows[3]["E0_graph"].split(".")[1]) >= 10
    with open(out / "report" / "table_s1.json") as fh:
        assert len(json.load(fh)) == 4


def test_fig3_table_matches_api(repro):
    from hyperlattice import ring_lattice
    from hyperlattice.compare.green import compare_green

    out, _ = repro
    with open(out / "report" / "table_fig3_green.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["rings"]) for r in rows[::2]] == [3, 4, 5, 6, 7, 8]
    row = rows[0]
    assert row["omega"] == "-2.95"
    cmp = compare_green(ring_lattice(7, 3, 3), -2.95, 10)
    assert float(row["rel_l2"]) == pytest.approx(cmp.rel_l2, abs=1e-4)


def test_html_is_valid_and_self_contained(repro):
    out, _ = repro
    text = (out / "report" / "report.html").read_text()
    assert text.startswith("<!DOCTYPE html>")
    checker = _Checker()
    checker.feed(text)
    assert checker.errors == []
    assert checker.stack == []
    assert checker.external == []  # no network fetches: every figure is a data: URI
    assert checker.images >= 5
    assert "http://" not in text and "https://" not in text


def test_report_flags_the_known_misprints(repro):
    out, _ = repro
    md = (out / "report" / "report.md").read_text()
    assert "printed -1.274" in md  # E1 of the heptagon
    assert "(1/2) ln 3" in md      # p = inf column
    for label in ("Tab1", "SuppTab1", "Fig1", "Fig2", "Fig3", "FigS1", "FigScos3delta", "FigSh"):
        assert label in md


def test_rerun_uses_cache_and_is_deterministic(repro, tmp_path):
    out, first = repro
    again = reproduce(tmp_path / "again", max_rings=4, cache=Cache(out / "cache"))
    assert again["cache_misses"] == 0 and again["cache_hits"] >= 4
    for name in ("report.md", "table_s1.csv", "fig_fig1.svg"):
        assert (tmp_path / "again" / name).read_bytes() == (out / "report" / name).read_bytes(), name


def test_compare_flags():
    assert compare("-2.636", -2.6364049, "E0_graph", 2) == ("", "")
    flag, note = compare("-1.274", -1.2469796, "E1_graph", 1)
    assert flag == "≠" and "heptagon" in note
    assert compare("-2.91", -2.9127, "E0_graph", 8)[0] == ""
    assert compare("-2.92", -2.9127, "E0_graph", 8)[0] == "≠"


@pytest.mark.parametrize("argv", [["reproduce", "--max-rings", "1"], ["reproduce", "--max-rings", "15"],
                                  ["reproduce", "--max-rings", "x"]])
def test_cli_bad_max_rings(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_bad_max_rings_api(tmp_path):
    with pytest.raises(ValueError):
        reproduce(tmp_path, max_rings=20)
