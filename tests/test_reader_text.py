"""Text a reader sees uses symbols, not ASCII maths.

The ``statement()`` sentences of real (small) results, the texts of real figures (titles, axis
labels, legends, annotations) and every literal string the figure code of ``plots/`` and
``report/`` hands to matplotlib are scanned for ASCII maths such as ``l = 5``, ``rho``, ``E_inf``,
``omega``, ``m^2``, ``<=`` or ``+-``. Mathtext (``$...$``) and code spans (backticks) are left out:
matplotlib typesets the first, the second are commands and file names.
"""

from __future__ import annotations

import ast
import dataclasses
import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import hyperlattice
from hyperlattice.graph.lattice import ring_lattice

matplotlib.use("Agg")

#: ASCII maths -> what the reader should see instead (the reason printed on failure)
ASCII_MATHS = [
    (r"\bl ?(?:=|<=|>=|<|>) ?[-\d{(]", "ℓ for the ring number"),
    (r"\bl=", "ℓ = for the ring number"),
    (r"\brho\b", "ρ"), (r"\bE_inf\b", "E∞"), (r"\bomega(?:_q)?\b", "ω"), (r"\bDelta(?:_g)?\b", "Δ"),
    (r"\bxi\b", "ξ"), (r"\bmu\b", "μ"), (r"\bnu\b", "ν"), (r"\blambda\b", "λ"), (r"\btheta\b", "θ"),
    (r"\bsqrt\b", "√"), (r"\bpi\b", "π"), (r"\binfinity\b", "∞"),
    # a power that is a number (m^2, f^1.5, x^-1); an expression in brackets, ^(1/2), stays readable
    (r"\^-?[\d.]", "a superscript (², ⁻¹)"), (r"<=", "≤"), (r">=", "≥"), (r"\+-", "±"), (r"~=", "≈"),
    (r"->", "→"), (r"(?<![\w{])[dEG][01](?![\w.])", "a subscript (d₀, E₀, E₁, G₀)"), (r"\bL2\b", "L²"),
    (r"(?<=[\w)}]) - (?=[\w({|])", "− for a difference"),
    (r"(?:^|[\s(\[=,])-(?=\.?\d)", "− (a true minus) before a number"),
]
_PATTERNS = [(re.compile(a), b) for a, b in ASCII_MATHS]


def _readable(text: str) -> str:
    """``text`` without mathtext ($...$, typeset by matplotlib) and code spans (`...`)."""
    text = re.sub(r"(?<!\\)\$[^$]*(?<!\\)\$", " ", text)
    return re.sub(r"`[^`]*`", " ", text)


def ascii_maths(text: str) -> list[str]:
    """The ASCII-maths findings in ``text``, as ``'match' (use ...)`` strings."""
    plain = _readable(text)
    return [f"{m.group(0)!r} (use {why})" for pat, why in _PATTERNS for m in pat.finditer(plain)]


@pytest.mark.parametrize("text, bad", [
    ("E0(l) -> E_inf as l -> infinity", True), ("rho = 2.94 +- 0.01", True), ("l = 5", True), ("l=3: never", True),
    ("m^2 = -1", True), ("f <= 0.3", True), ("omega_q", True), ("Delta_g", True), ("E = -2.5", True),
    ("E₀(ℓ) → E∞ as ℓ → ∞", False), ("ρ = 2.94 ± 0.01", False), ("$m^2 = -1$, $\\omega$", False),
    ("run `hyperlattice spectrum -l 2 --rho`", False), ("Mott lobe n = 1", False), ("E = −2.5, 1.9e-02", False),
    ("fit - data", True), ("relative L2 distance", True), ("flux f per p-gon", False), ("E − E_b", False),
    ("{7,3} flake, 5 rings", False), ("the lattice's E(ν)", False),
])
def test_the_scan_finds_ascii_maths(text, bad):
    assert bool(ascii_maths(text)) is bad, (text, ascii_maths(text))


# ----------------------------------------------------------------------------
# statement() of real results
# ----------------------------------------------------------------------------

def _statements():
    from hyperlattice.compare.boundary import lattice_bf_bound
    from hyperlattice.compare.dos import dos_comparison
    from hyperlattice.compare.magnetic import magnetic_comparison

    bf = lattice_bf_bound(7, 3, rings=(3, 4))
    yield "LatticeBFBound", bf.statement()
    # the other branch: a lattice bound below the continuum one
    yield "LatticeBFBound (below)", dataclasses.replace(bf, e0=np.array([-2.95, -2.96])).statement()
    cmp = magnetic_comparison(7, 3, rings=[3, 4], fluxes=[0.0, 0.1, 0.2], levels=2)
    yield "MagneticComparison", cmp.statement()
    yield "MagneticComparison (loose)", cmp.statement(threshold=0.05)
    dos = dos_comparison(7, 3, clusters=("klein",), rings=(4,), moments=32, vectors=3, abelian=False,
                         walk_length=11, resolution=20)
    yield "DosComparison", dos.statement()


def test_every_statement_of_the_package_is_exercised():
    """Each class with a statement() is in _statements(): a new one must be added there."""
    import ast as _ast

    owners = set()
    for path in Path(hyperlattice.__file__).parent.rglob("*.py"):
        for node in _ast.walk(_ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, _ast.ClassDef) and any(isinstance(b, _ast.FunctionDef) and b.name == "statement"
                                                       for b in node.body):
                owners.add(node.name)
    covered = {name.split(" ")[0] for name, _ in _statements()}
    assert owners == covered


def test_statements_use_symbols():
    found = {name: ascii_maths(text) for name, text in _statements()}
    assert not {k: v for k, v in found.items() if v}, found


# ----------------------------------------------------------------------------
# figures
# ----------------------------------------------------------------------------

#: matplotlib calls whose string arguments are read on the figure
_TEXT_CALLS = {"set_xlabel", "set_ylabel", "set_title", "suptitle", "text", "annotate", "colorbar", "set_label",
               "figtext", "legend"}


def _pieces(node) -> list[str]:
    """The literal text of a string or f-string node (formatted values as '{}')."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.JoinedStr):
        return ["".join(v.value if isinstance(v, ast.Constant) else "{}" for v in node.values)]
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        return _pieces(node.left) + _pieces(node.right)
    if isinstance(node, ast.IfExp):
        return _pieces(node.body) + _pieces(node.orelse)
    return []


def _figure_literals():
    """(file:line, text) of every literal handed to matplotlib as reader text in plots/ and report/."""
    root = Path(hyperlattice.__file__).parent
    for path in sorted([*root.joinpath("plots").glob("*.py"), *root.joinpath("report").glob("*.py")]):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call):
                continue
            name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            args = list(node.args) if name in _TEXT_CALLS else []
            args += [k.value for k in node.keywords if k.arg in ("label", "title")]
            for a in args:
                for text in _pieces(a):
                    yield f"{path.name}:{node.lineno}", text


def test_figure_text_literals_use_symbols():
    found = {where: ascii_maths(text) for where, text in _figure_literals()}
    assert not {k: v for k, v in found.items() if v}, {k: v for k, v in found.items() if v}


def _texts(fig) -> list[str]:
    from matplotlib.text import Text

    return [t.get_text() for t in fig.findobj(Text) if t.get_text()]


def _figures():
    import matplotlib.pyplot as plt

    from hyperlattice.compare.boundary import lattice_bf_bound
    from hyperlattice.compare.magnetic import magnetic_comparison
    from hyperlattice.graph.butterfly import butterfly
    from hyperlattice.plots.magnetic import butterfly_figure, error_map

    fig, (ax, zoom) = plt.subplots(1, 2)
    butterfly_figure(butterfly(ring_lattice(7, 3, 3), np.linspace(0.0, 0.5, 6)), points=3, levels=2, ax=ax,
                     density=True, mirror=True, zoom_ax=zoom)
    yield "butterfly_figure", fig
    yield "error_map", error_map([0.0, 0.1], [3, 4], [[1e-2, 1e-4], [1e-5, 1e-2]]).figure
    yield "MagneticComparison.plot", magnetic_comparison(7, 3, rings=[3], fluxes=[0.0, 0.1], levels=2).plot().figure
    yield "LatticeBFBound.plot", lattice_bf_bound(7, 3, rings=(3, 4)).plot().figure
    lat = ring_lattice(7, 3, 2)
    yield "Lattice.plot", lat.plot().figure
    yield "Spectrum.plot", hyperlattice.lowest_levels(lat, 3).plot().figure


def test_figure_texts_use_symbols():
    import matplotlib.pyplot as plt

    found = {}
    for name, fig in _figures():
        bad = [f for t in _texts(fig) for f in ascii_maths(t)]
        if bad:
            found[name] = bad
        plt.close(fig)
    assert not found, found


# ----------------------------------------------------------------------------
# no tracker references: a reader has no issue tracker
# ----------------------------------------------------------------------------

_ISSUE = re.compile(r"\bissues?\s*#?\d+", re.I)


def _reader_files():
    root = Path(__file__).resolve().parents[1]
    yield root / "README.md"
    for sub, pattern in (("src", "*.py"), ("docs", "*.md"), ("docs", "*.rst"), ("docs", "*.py")):
        yield from sorted(root.joinpath(sub).rglob(pattern))


def test_no_issue_numbers_in_code_docs_or_readme():
    """Code, docstrings, docs and the README say what the code does, never "issue N" (CHANGELOG may)."""
    found = []
    for path in _reader_files():
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if _ISSUE.search(line):
                found.append(f"{path.name}:{n}: {line.strip()[:100]}")
    assert not found, "\n".join(found)


# ----------------------------------------------------------------------------
# the CLI cites the paper as it is printed; report tables print labels, not identifiers
# ----------------------------------------------------------------------------

def _help_texts():
    """(command path, --help text) of the CLI and every (sub)command."""
    import argparse

    from hyperlattice.cli import build_parser

    stack = [("hyperlattice", build_parser())]
    while stack:
        name, parser = stack.pop()
        yield name, parser.format_help()
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack += [(f"{name} {sub}", p) for sub, p in action.choices.items()]


def test_cli_help_cites_printed_equation_numbers_never_tex_labels():
    """``(eq12)``, ``(spec2)``, ``Fig. FigS1``: a reader of ``--help`` sees Eq. (10), Eq. (F2), Fig. 7."""
    from hyperlattice.paper_labels import PAPER_LABELS

    labels = {k for k in PAPER_LABELS if " " not in k}
    found = {}
    for name, text in _help_texts():
        words = set(re.findall(r"[A-Za-z][A-Za-z0-9]*", text)) & labels
        if words:
            found[name] = sorted(words)
    assert not found, found


_IDENTIFIER = re.compile(r"[A-Za-z0-9]_[A-Za-z0-9]{2,}")


def test_report_column_labels_are_words_not_identifiers():
    from hyperlattice.report.writers import column_label

    names = ["E0_graph_flag", "E0_continuum_paper", "N_closed_form", "N_ring_paper", "rel_err_E0", "lB_over_d0",
             "tip_t_c_over_U_error", "E_inf_paper", "mass2_at_E0", "decay_length_continuum_asymptotic", "rel_l2",
             "omega_q", "omega1_graph", "gap_ed_error_bound", "xi_over_d0", "band_minus_improved", "sigma_graph"]
    labels = {n: column_label(n) for n in names}
    assert not {n: s for n, s in labels.items() if _IDENTIFIER.search(s)}, labels
    assert labels["E0_graph_flag"] == "E₀ graph: flag (≠)" and labels["N_closed_form"] == "N (closed form)"


def test_report_tables_never_print_a_negative_zero():
    """Table 11.1 printed m² = "−0.0000" at ω = −3 (the sign of rounding noise)."""
    from hyperlattice.report.writers import Table, fmt

    t = Table("boundary_delta", ["omega", "mass2", "rel_diff"], [["-3", "-0.0000", "-0.023"], ["-3", -0.0, "+0.000"]])
    assert t.rows == [["-3", "0.0000", "-0.023"], ["-3", 0.0, "+0.000"]]
    assert fmt(-1e-17, 4) == "0.0000" and fmt(-0.0) == "0.000000000000"


def test_qmc_lobe_tables_name_graphs_as_a_reader_does():
    from hyperlattice.report.qmc_lobe import system_label

    assert [system_label(s) for s in ("flake:1", "cluster:klein", "square:6")] == [
        "flake ℓ = 1", "cluster klein", "square L = 6"]
