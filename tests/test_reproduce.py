"""Reduced end-to-end reproduction: files exist, tables parse, numbers equal the API's."""

import csv
import json
import re
from html.parser import HTMLParser

import numpy as np
import pytest

from hyperlattice.cache import Cache
from hyperlattice.cli import main
from hyperlattice.compare.levels import relative_error_trend
from hyperlattice.paper_values import paper_value
from hyperlattice.report import reproduce
from hyperlattice.report.sections import open_question_text
from hyperlattice.report.writers import prose


class _Checker(HTMLParser):
    """Collects tags and every external reference; checks the tag nesting."""

    VOID = {"meta", "img", "br", "hr", "link", "input", "wbr"}

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.external, self.images = [], [], [], 0
        self.ids, self.links, self.headings = [], [], []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name == "id":
                self.ids.append(value)
                if tag in ("h2", "h3"):
                    self.headings.append(value)
            if name == "href" and value and value.startswith("#"):
                self.links.append(value[1:])
            elif name in ("src", "href") and value and not value.startswith("data:"):
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


#: compare_green calls of the first (cold-cache) run, by (rings, omega)
GREEN_CALLS: list = []

#: the texts (titles, labels, legends, notes) of every figure the first run saved
FIGURE_TEXTS: list = []


@pytest.fixture(scope="module")
def repro(tmp_path_factory):
    import hyperlattice.compare.green as green

    out = tmp_path_factory.mktemp("repro")
    cache = Cache(out / "cache")
    original = green.compare_green

    def counted(lattice, omega, source, **kwargs):
        GREEN_CALLS.append((lattice.rings, complex(omega)))
        return original(lattice, omega, source, **kwargs)

    from matplotlib.figure import Figure
    from matplotlib.text import Text

    savefig = Figure.savefig

    def saved(fig, *args, **kwargs):
        FIGURE_TEXTS.extend(t.get_text() for t in fig.findobj(Text) if t.get_text())
        return savefig(fig, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(green, "compare_green", counted)
        mp.setattr(Figure, "savefig", saved)
        summary = reproduce(out / "report", max_rings=4, cache=cache)
    return out, summary


def test_files_exist(repro):
    out, _ = repro
    rep = out / "report"
    for name in ("report.html", "report.md", "table_paper_table4.csv", "table_paper_table4.json", "table_geometry.csv",
                 "table_paper_table1_sizes.csv", "fig_paper_fig1.png", "fig_paper_fig1.svg", "fig_paper_fig3.png", "fig_paper_fig7.png",
                 "fig_paper_fig5.png", "fig_paper_fig6.png", "fig_paper_fig4_upper.png", "fig_paper_fig4_lower.png",
                 "table_green_distance.csv", "timings.json"):
        assert (rep / name).stat().st_size > 0, name


def test_table_s1_matches_api(repro):
    from hyperlattice import ring_lattice
    from hyperlattice.continuum.spectrum import asymptotic_energies, continuum_levels
    from hyperlattice.graph.spectrum import lowest_levels

    out, _ = repro
    with open(out / "report" / "table_paper_table4.csv") as fh:
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
    with open(out / "report" / "table_paper_table4.json") as fh:
        assert len(json.load(fh)) == 4


def test_fig3_table_matches_api(repro):
    from hyperlattice import ring_lattice
    from hyperlattice.compare.green import compare_green

    out, _ = repro
    with open(out / "report" / "table_green_distance.csv") as fh:
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
    assert "printed −1.274" in md  # E1 of the heptagon (with a true minus)
    assert "(1/2) ln 3" in md      # p = inf column
    # the paper's tables and figures by the numbers it prints (Tab1, SuppTab1, AppFS's table, Fig1..FigS1)
    for label in ("Table I", "Table II", "Table III", "Table IV", "Fig. 1", "Fig. 3", "Fig. 4", "Fig. 5", "Fig. 6",
                  "Fig. 7", "Eq. (19)", "Appendix F"):
        assert label in md, label


@pytest.mark.slow
def test_rerun_uses_cache_and_is_deterministic(repro, tmp_path):
    out, first = repro
    again = reproduce(tmp_path / "again", max_rings=4, cache=Cache(out / "cache"))
    assert again["cache_misses"] == 0 and again["cache_hits"] >= 4
    for name in ("report.md", "table_paper_table4.csv", "fig_paper_fig1.svg"):
        assert (tmp_path / "again" / name).read_bytes() == (out / "report" / name).read_bytes(), name


def test_compare_flags():
    assert paper_value("E0_graph", 2).check(-2.6364049) == ("", "")
    flag, note = paper_value("E1_graph", 1).check(-1.2469796)
    assert flag == "≠" and "heptagon" in note
    assert paper_value("E0_graph", 8).check(-2.9127)[0] == ""
    assert paper_value("E0_graph", 9).check(-2.9127)[0] == "≠"  # printed -2.92: the sparse estimate


def test_side_table_uses_the_paper_values(repro):
    out, summary = repro
    for level in ("E0", "E1"):
        with open(out / "report" / f"table_paper_table4_{level}_printed.csv") as fh:
            rows = list(csv.DictReader(fh))
        assert rows and list(rows[0])[:2] == ["rings", "flagged"] and len(rows[0]) == 11
        for row, rec in zip(rows, summary["records"]):
            flagged = []
            for kind in ("graph", "continuum", "asymptotic"):
                key = f"{level}_{kind}"
                pv = paper_value(key, rec["rings"])
                assert row[f"{key}_paper"] == pv.printed
                assert row[f"{key}_flag"] == pv.check(rec[key])[0]
                flagged += [kind] if row[f"{key}_flag"] else []
            assert row["flagged"] == ",".join(flagged)


def _trends(records):
    rings = [r["rings"] for r in records]
    return [relative_error_trend(rings, [r[f"{k}_graph"] for r in records], [r[f"{k}_continuum"] for r in records],
                                 level=k) for k in ("E0", "E1")]


def test_open_question_sentences_come_from_the_result(repro):
    out, summary = repro
    md = (out / "report" / "report.md").read_text()
    trends = _trends(summary["records"])
    sentences = open_question_text(trends)
    assert len(sentences) == 2
    for s in sentences:
        assert prose(s) == s  # written with symbols already
        assert s in md
    # l = 1..4: the graph levels stay below the continuum ones and approach them
    assert trends[0].sign_change is None and trends[0].magnitude_decreasing
    assert sentences[0].endswith("for ℓ = 1–4. Its magnitude decreases monotonically over the computed range.")
    with open(out / "report" / "table_graph_vs_continuum.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["rel_err_E0"] for r in rows] == [f"{v:.3e}" for v in trends[0].relative_error]


def test_open_question_sentences_pinned():
    """The sentences of the default run (l = 1..10) from a RelativeErrorTrend, word for word."""
    rel = [-2.50e-01, -2.51e-02, -5.86e-03, -1.71e-03, -3.85e-04, +1.45e-04, +3.89e-04, +5.11e-04, +5.77e-04,
           +6.13e-04]
    g = np.full(10, -2.9)
    t = relative_error_trend(range(1, 11), g, g - np.array(rel) * 2.9, level="E0")
    assert t.sign_change.tolist() == [5, 6] and t.rising and t.saturates
    d1, d2 = t.increments
    assert (f"{d1:.1e}", f"{d2:.1e}") == ("6.6e-05", "3.6e-05")
    assert t.aitken_limit == pytest.approx(6.13e-4 + 3.6e-5 ** 2 / 3.0e-5, rel=1e-6)
    text = open_question_text([t], worst_residual=1.8e-14)
    assert text == [
        "The paper's open question (Appendix F): does the relative error between graph and continuum keep "
        "decreasing as ℓ → ∞? The computed levels (largest residual ‖Hψ − Eψ‖ = 1.8e-14) say:",
        "E₀: (E_graph − E_cont)/|E_graph| = −2.50e-01, −2.51e-02, −5.86e-03, −1.71e-03, −3.85e-04, +1.45e-04, "
        "+3.89e-04, +5.11e-04, +5.77e-04, +6.13e-04 for ℓ = 1–10. It changes sign between ℓ = 5 and 6 (the graph "
        "level moves from below to above the continuum level), then grows monotonically with shrinking increments "
        f"(6.6e-05, 3.6e-05 over the last rings): it saturates (Aitken estimate of the limit {t.aitken_limit:.2e}) "
        "instead of decreasing to zero."]
    assert f"{t.aitken_limit:.2e}" == "6.56e-04"


def test_open_question_sentences_other_branches():
    g = np.full(5, -2.9)
    # graph level crossing from above to below, growing increments: no saturation claimed
    t = relative_error_trend(range(1, 6), g, g - np.array([1e-2, -1e-4, -2e-4, -4e-4, -8e-4]) * 2.9, level="E1")
    (s,) = open_question_text([t])
    assert "moves from above to below" in s and "grows monotonically in magnitude without shrinking" in s
    assert "Aitken" not in s
    t = relative_error_trend(range(1, 6), g, g - np.array([-1e-2, 1e-4, 3e-4, 2e-4, 4e-4]) * 2.9, level="E1")
    assert open_question_text([t])[0].endswith("does not settle into a monotone trend within the computed range.")


@pytest.mark.slow
def test_fig2_partition_table_matches_api(repro):
    """Z and Z' of the Fig2 inset are the compare.levels results; every +-m pair counts twice."""
    from hyperlattice.compare.levels import continuum_levels_below, graph_levels_below, partition_functions
    from hyperlattice.graph.lattice import ring_lattice

    out, _ = repro
    with open(out / "report" / "table_partition_function_l4.csv") as fh:
        rows = list(csv.DictReader(fh))
    z = partition_functions(graph_levels_below(ring_lattice(7, 3, 4)), continuum_levels_below(7, 3, rings=4),
                            np.linspace(0.05, 6.0, 120))
    assert [r["Z_graph"] for r in rows] == [f"{v:.10g}" for v in z.z_graph[::10]]
    assert [r["Z_continuum"] for r in rows] == [f"{v:.10g}" for v in z.z_continuum[::10]]
    md = (out / "report" / "report.md").read_text()
    assert "over 146 negative graph levels and 108 negative continuum states" in md


def test_fig3_green_columns_computed_once(repro):
    """The l = 3 and l = 6 columns drawn in Fig3 are reused by its table (no second computation)."""
    calls = sorted(GREEN_CALLS, key=lambda c: (c[0], c[1].real, c[1].imag))
    assert len(calls) == len(set(calls)) == 12  # l = 3..8 at two omega


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


def test_magnetic_section(repro):
    """Issue 11: the "beyond the paper: magnetic flux" section, its figure and a table equal to the API's."""
    from hyperlattice import ring_lattice
    from hyperlattice.continuum.magnetic import magnetic_levels
    from hyperlattice.graph.spectrum import lowest_levels

    out, summary = repro
    rep = out / "report"
    assert "Magnetic flux: Hofstadter butterfly and Landau levels" in summary["sections"]
    for name in ("fig_butterfly.png", "fig_butterfly.svg", "fig_magnetic_error.png"):
        assert (rep / name).stat().st_size > 0, name
    with open(rep / "table_magnetic_levels.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 5 * 4 * 2  # l = 3..7, four fluxes, two levels
    r = next(r for r in rows if r["rings"] == "4" and r["flux"] == "0.10")
    g = lowest_levels(ring_lattice(7, 3, 4), 2, flux=0.1)
    c = magnetic_levels(7, 3, rings=4, levels=2, flux=0.1)
    assert r["(n,m)"] == f"({g.n[0]},{g.m[0]})"
    assert float(r["E_graph"]) == pytest.approx(g.energies[0], abs=1e-8)
    assert float(r["E_continuum"]) == pytest.approx(c.energies[0], abs=1e-8)
    assert "Magnetic flux" in (rep / "report.md").read_text()


PAPER_ORDER = ["lattice", "sizes", "spectrum", "levels-vs-rings", "green", "scaling", "geometry"]
BEYOND_ORDER = ["magnetic", "band-bottom", "infinite", "holography", "qubits", "disorder", "bosons", "qmc-lobe",
                "magnetism", "topology"]


def _html(repro):
    out, _ = repro
    checker = _Checker()
    checker.feed((out / "report" / "report.html").read_text())
    return checker


def test_table_of_contents_and_anchors(repro):
    """A linked table of contents; every section, table and figure has a unique id; every link resolves."""
    out, summary = repro
    c = _html(repro)
    assert len(c.ids) == len(set(c.ids)), sorted(i for i in c.ids if c.ids.count(i) > 1)
    assert c.links and set(c.links) <= set(c.ids)
    assert {f"sec-{a}" for a in PAPER_ORDER + BEYOND_ORDER} <= set(c.links)
    tables = [p.name[len("table_"):-len(".csv")] for p in (out / "report").glob("table_*.csv")]
    for name in tables:
        assert f"table-{name.lower().replace('_', '-')}" in c.ids, name
    md = (out / "report" / "report.md").read_text()
    toc = md[md.index("## Contents"):md.index('<a id="part-paper">')]
    md_links = re.findall(r"\]\(#([\w-]+)\)", toc)
    md_ids = re.findall(r'<a id="([\w-]+)"></a>', md)
    assert len(md_ids) == len(set(md_ids)) and set(md_links) <= set(md_ids)
    assert set(md_links) == set(c.links)


def test_order_paper_then_beyond(repro):
    c = _html(repro)
    heads = c.headings
    assert heads[0] == "part-paper" and "part-beyond" in heads
    cut = heads.index("part-beyond")
    assert heads[1:cut] == [f"sec-{a}" for a in PAPER_ORDER]
    assert heads[cut + 1:] == [f"sec-{a}" for a in BEYOND_ORDER]


def _prose_of(md: str) -> str:
    """The report's sentences and captions: no table rows, no code spans, no file names."""
    lines = [ln for ln in md.splitlines() if not ln.startswith("|") and not ln.startswith("![")]
    return re.sub(r"`[^`]*`", "", "\n".join(lines))


def test_no_tex_labels_issue_numbers_or_ascii_maths(repro):
    from hyperlattice.paper_labels import PAPER_LABELS

    out, _ = repro
    for name in ("report.md", "report.html"):
        text = (out / "report" / name).read_text()
        if name.endswith(".html"):
            text = re.sub(r'src="data:[^"]*"', "", text)
        words = set(re.findall(r"[A-Za-z][A-Za-z0-9]*", _prose_of(text)))
        assert not {k for k in PAPER_LABELS if " " not in k} & words, name
        assert not re.search(r"\bissues? \d", text), name
    prose_md = _prose_of((out / "report" / "report.md").read_text())
    for ascii_maths in ("E_inf", "-rho", " rho ", " l = ", " l=", "omega", "sqrt(", " <= ", "->"):
        assert ascii_maths not in prose_md, ascii_maths
    for symbol in ("ℓ = ", "E∞", "−ρ", "ω", "Δ"):
        assert symbol in prose_md, symbol


def test_report_prose_has_no_ascii_maths(repro):
    """Every sentence, caption and title of the report, scanned with the list of test_reader_text."""
    from test_reader_text import ascii_maths

    out, _ = repro
    found = {}
    for line in _prose_of((out / "report" / "report.md").read_text()).splitlines():
        bad = ascii_maths(line)
        if bad:
            found[line[:120]] = bad
    assert not found, found


def test_report_figure_texts_have_no_ascii_maths(repro):
    """Titles, axis labels, legends and notes of every figure the report saved."""
    from test_reader_text import ascii_maths

    assert len(FIGURE_TEXTS) > 100
    found = {t: ascii_maths(t) for t in set(FIGURE_TEXTS) if ascii_maths(t)}
    assert not found, found


def test_every_label_of_the_report_is_in_the_map(repro):
    from hyperlattice.paper_labels import PAPER_LABELS
    from hyperlattice.report.writers import Section

    out, _ = repro
    md = (out / "report" / "report.md").read_text()
    printed = set(PAPER_LABELS.values())
    # "Fig. 8.1", "Table 9.2": the report's own items, numbered by section (writers.item_labels)
    for ref in re.findall(r"(?:Eq\. \([A-I]?\d+\)|Fig\. \d+(?!\d|\.\d)|Table [IVX]+|Appendix [A-I])", md):
        assert ref in printed, ref
    with pytest.raises(ValueError, match="not a label"):
        Section("x", ("green99",))


def test_provenance_names_stored_levels_and_a_command_that_runs(repro):
    """The band-bottom section says which levels are stored, where, since when, and prints the command of
    compare.limits.reference_command for exactly those rings (the command itself is run in test_limits)."""
    from hyperlattice.compare.limits import REFERENCE_DATE, REFERENCE_LEVELS, reference_command

    out, _ = repro
    md = (out / "report" / "report.md").read_text()
    stored = [x for x in sorted(REFERENCE_LEVELS[(7, 3)]) if x > 4]
    assert f"`{reference_command(7, 3, stored)}`" in md
    assert "lmax" not in md and REFERENCE_DATE in md
    assert "src/hyperlattice/compare/limits.py" in md
    assert f"for ℓ = {stored[0]}–{stored[-1]} (the band-bottom fit" in md
    assert "Every number below is computed by the package;" not in md


def test_cache_counts_on_an_empty_cache(repro):
    """The first run starts from an empty cache: nothing is read from an earlier run."""
    _, summary = repro
    assert summary["cache_hits"] == 0
    assert summary["cache_misses"] > 0 and summary["cache_reused"] > 0  # the limits section reads graph_levels


def test_tables_scroll_instead_of_clipping(repro):
    out, _ = repro
    text = (out / "report" / "report.html").read_text()
    assert ".scroll{overflow-x:auto" in text
    assert text.count('<div class="scroll"><table>') == text.count("<table>")


def test_two_band_bottom_intervals_explained(repro):
    out, _ = repro
    md = (out / "report" / "report.md").read_text()
    m = re.search(r"Two proven intervals for the band bottom −ρ of \{7,3\} appear in this report, "
                  r"\[(−[\d.]+), (−[\d.]+)\] in the band-bottom section and \[(−[\d.]+), (−[\d.]+)\] here",
                  md)
    assert m   # the numbers carry a true minus (prose)
    bound = [None] + [float(g.replace("−", "-")) for g in m.groups()]
    with open(out / "report" / "table_band_edges.csv") as fh:
        row = next(csv.DictReader(fh))
    assert bound[3] == pytest.approx(float(row["interval_lower"]), abs=1e-4)
    assert bound[4] == pytest.approx(float(row["interval_upper"]), abs=1e-4)
    with open(out / "report" / "table_band_bottom.csv") as fh:
        row = next(r for r in csv.DictReader(fh) if r["lattice"] == "{7,3}")
    assert bound[1] == pytest.approx(float(row["rigorous_lower"]), abs=1e-5)


def test_contents_name_tables_and_figures_as_the_paper_prints_them(repro):
    """The table of contents and the captions say "Table IV", "Fig. 3", "Table 9.2" (issue 28 item 3),
    never the internal file stems (``table s1``, ``figure fig2``)."""
    out, _ = repro
    md = (out / "report" / "report.md").read_text()
    toc = md[md.index("## Contents"):md.index('<a id="part-paper">')]
    for printed in ("Table I", "Table III", "Table IV", "Fig. 1", "Fig. 3", "Fig. 4, upper panels", "Fig. 5",
                    "Fig. 6", "Fig. 7"):
        assert f"[{printed}](#" in toc, printed
    assert not re.search(r"\[(table|figure) [\w]+\]", toc), re.findall(r"\[(?:table|figure) [\w]+\]", toc)
    assert re.search(r"\[Table \d+\.\d\]\(#table-band-fit\)", toc)
    html_text = (out / "report" / "report.html").read_text()
    nav = html_text[html_text.index('<nav class="toc"'):html_text.index("</nav>")]
    assert ">Table IV</a>" in nav and ">Fig. 3</a>" in nav and ">table s1<" not in nav and ">figure fig2<" not in nav
    assert "<p class=\"cap\" id=\"table-paper-table4\">Table IV (and the energy rows of Table I)" in html_text


def test_every_table_fits_a_1400px_page(repro):
    """No table of the report is wider than 12 columns (the 19-column side table is split, issue 28 item 3)."""
    out, _ = repro
    for path in (out / "report").glob("table_*.csv"):
        with open(path) as fh:
            header = next(csv.reader(fh))
        assert len(header) <= 12, (path.name, len(header))


def test_bosons_tables_carry_error_bars_and_solver_tolerances(repro):
    """Issue 28 item 3: the infinite lattice's lobe tip inherits ρ's error bar; the GP caption says
    mean filling; the gap and GP tables state their solvers' tolerances and the errors reached."""
    out, _ = repro
    with open(out / "report" / "table_bosons_lobes.csv") as fh:
        lobes = list(csv.DictReader(fh))
    inf = next(r for r in lobes if r["system"].startswith("infinite"))
    rho, err = float(inf["lambda_max"]), float(inf["lambda_max_error"])
    assert 0 < err < 1e-2
    assert float(inf["tip_t_c_over_U_error"]) == pytest.approx(float(inf["tip_t_c_over_U"]) * err / rho, rel=0.1)
    assert all(r["lambda_max_error"] and r["tip_t_c_over_U_error"] for r in lobes)
    md = (out / "report" / "report.md").read_text()
    assert "at mean filling N/sites = 1" in md and "one boson per site" not in md
    assert "relative residual ≤ 1e−10" in md or "relative residual ≤ 1e-10" in md
    with open(out / "report" / "table_bosons_gp.csv") as fh:
        gp = list(csv.DictReader(fh))
    for r in gp:
        assert float(r["residual_graph"]) <= 1e-8 and float(r["residual_continuum"]) <= 1e-8
        # the continuum μ is printed to 5 decimals: its discretisation error is stated beside it
        assert 0 < float(r["mu_continuum_error"]) < 1e-4
    with open(out / "report" / "table_bosons_gap.csv") as fh:
        gaps = list(csv.DictReader(fh))
    assert all(0 < float(r["gap_ed_error_bound"]) < 5e-6 for r in gaps)


def test_tables_and_files_are_named_for_a_reader(repro):
    """Table headers are labels (not ``E0_graph_flag``, ``N_closed_form``), cells name graphs (not
    ``flake:1``), no table prints a negative zero, blank bounds are explained, and the figure files of
    the paper's figures carry the printed numbers (``fig_paper_fig3.png`` is Fig. 3)."""
    out, _ = repro
    rep = out / "report"
    md = (rep / "report.md").read_text()
    rows = [ln for ln in md.splitlines() if ln.startswith("| ")]
    headers = [ln for k, ln in enumerate(md.splitlines()) if ln.startswith("| ")
               and md.splitlines()[k + 1].startswith("|---")]
    assert headers
    bad = [h for h in headers if re.search(r"[A-Za-z0-9]_[A-Za-z0-9]{2,}", h)]
    assert not bad, bad
    assert not [r for r in rows if re.search(r"\| (flake|cluster|square):", r)]
    assert not [r for r in rows if re.search(r"\| [-−]0\.0+ \|", r)]
    assert "are blank for {9,3}, {10,3} and {5,4}" in md
    names = {p.name for p in rep.iterdir()}
    assert not {n for n in names if n.startswith("fig_fig")}, names
    assert {"fig_paper_fig1.png", "fig_paper_fig3.png", "fig_paper_fig4_upper.png", "fig_paper_fig7.png"} <= names
    html_text = (rep / "report.html").read_text()
    assert "<th>E₀ graph: flag (≠)</th>" in html_text and "E0_graph_flag" not in html_text
