"""The map from the paper's TeX labels to its printed numbers (hyperlattice.paper_labels)."""

from pathlib import Path

import pytest

from hyperlattice.paper_labels import PAPER_LABELS, cite, number_labels

#: the paper's source, where the project keeps it (``shared/paper`` next to a parent of the checkout)
PAPER_TEX = next((d / "shared" / "paper" / "graphs-to-geometry.tex" for d in Path(__file__).resolve().parents
                  if (d / "shared" / "paper" / "graphs-to-geometry.tex").is_file()), Path("graphs-to-geometry.tex"))


def test_numbering_rules_on_a_small_source():
    tex = r"""
    \begin{document}
    \begin{align} \label{a} x \end{align}
    \begin{align} y \end{align}
    \begin{align} \label{b} u \\ \nonumber v \\ \label{c} w \end{align}
    \begin{equation*} z \end{equation*}
    \begin{figure} \label{F1} \end{figure}
    \begin{table*} \label{T1} \end{table*}
    % \begin{align} \label{commented} \end{align}
    \begin{appendix}
    \section{One}\label{SecA}
    \begin{align} \label{a1} s \end{align}
    \begin{figure} \label{F2} \end{figure}
    \section{Two}\label{SecB}
    \begin{table} no label \end{table}
    \begin{align} t \\ \label{b2} t2 \end{align}
    \end{appendix}
    """
    assert number_labels(tex) == {
        "a": "Eq. (1)", "b": "Eq. (3)", "c": "Eq. (4)", "F1": "Fig. 1", "T1": "Table I", "SecA": "Appendix A",
        "a1": "Eq. (A1)", "F2": "Fig. 2", "SecB": "Appendix B", "SecB table": "Table II", "b2": "Eq. (B2)"}


@pytest.mark.skipif(not PAPER_TEX.is_file(), reason="the paper's TeX source is not next to this checkout")
def test_map_equals_the_numbering_of_the_source():
    assert number_labels(PAPER_TEX.read_text(encoding="utf-8")) == PAPER_LABELS


def test_known_numbers():
    # checked by hand against the typeset source
    assert cite("Tab1", "SuppTab1", "AppFS table") == "Table I, Table IV, Table III"
    assert cite("Fig1", "Fig2", "Fig3", "FigS1") == "Fig. 1, Fig. 3, Fig. 4, Fig. 7"
    assert cite("eq12", "eq19", "eq21", "spec17", "green36") == "Eq. (10), Eq. (17), Eq. (19), Eq. (F16), Eq. (I4)"
    assert cite("AppFS", "AppSpec") == "Appendix C, Appendix F"


def test_unknown_label_is_an_error():
    with pytest.raises(ValueError, match="not a label"):
        cite("eq99")


def test_pages_that_name_a_label_print_its_number():
    """README.md and docs/*.md write "Eq. (N) (label eqX)" or "Eqs. (N)–(M), TeX labels eqX–eqY":
    the printed numbers must be the ones the map gives for those labels (one numbering everywhere)."""
    import re

    root = Path(__file__).resolve().parents[1]
    pages = [root / "README.md", *sorted((root / "docs").glob("*.md"))]
    single = re.compile(r"Eq\. \((\d+)\),? \((?:TeX )?label (eq\w+)\)|Eq\. \((\d+)\), (?:TeX )?label (eq\w+)\)")
    pair = re.compile(r"Eqs\. \((\d+)\)–\((\d+)\), (?:TeX )?labels (eq\w+)–(eq\w+)")
    seen = 0
    for page in pages:
        text = page.read_text(encoding="utf-8")
        for m in single.finditer(text):
            number, label = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
            assert cite(label) == f"Eq. ({number})", f"{page.name}: {m.group(0)!r}"
            seen += 1
        for m in pair.finditer(text):
            assert cite(m.group(3), m.group(4)) == f"Eq. ({m.group(1)}), Eq. ({m.group(2)})", f"{page.name}: {m.group(0)!r}"
            seen += 1
    assert seen >= 5


def test_a_wrong_page_number_would_be_caught():
    assert cite("eq4") != "Eq. (4)"      # the label's digits are not the printed number


def test_docstrings_that_name_a_label_print_its_number():
    """Docstrings write "Eq. (N) (source label ``eqX``)": N must be the map's number for eqX."""
    import re

    src = Path(__file__).resolve().parents[1] / "src" / "hyperlattice"
    pat = re.compile(r"Eq\. \((\d+)\)\s+\((?:source )?label\s+``(eq\w+)``\)")
    seen = 0
    for path in sorted(src.rglob("*.py")):
        for m in pat.finditer(path.read_text(encoding="utf-8")):
            assert cite(m.group(2)) == f"Eq. ({m.group(1)})", f"{path.name}: {m.group(0)!r}"
            seen += 1
    assert seen >= 5
