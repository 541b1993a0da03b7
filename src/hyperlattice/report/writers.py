"""The report's building blocks and writers: tables (CSV/JSON), figures (PNG/SVG), Markdown, HTML.

Nothing here computes physics; :mod:`.sections` fills :class:`Section` objects and
:func:`write_md` / :func:`write_html` render them. Output is deterministic (no dates in the
figure files), so two runs give byte-identical files.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import math
import numbers
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _validate
from .manifest import writing

__all__ = ["Table", "Figure", "Section", "PARTS", "table_id", "figure_id", "item_labels", "fmt", "column_label", "save_figure", "write_md",
           "write_html"]


@dataclass
class Table:
    """A table of the report, written as ``table_<name>.csv`` and ``table_<name>.json``.

    Attributes
    ----------
    name : str
        File-name stem (``table_<name>.*``).
    columns : list of str
        Column names; units, where there are any, are part of the name (e.g. ``"E0 (t)"``).
    rows : list of list
        One list per row, in column order.
    caption : str
        Caption in the Markdown and HTML report.
    paper : str
        The paper's TeX label of the table it reproduces (``"SuppTab1"``), shown as the paper
        prints it (``"Table IV"``); empty for a table of the report's own (numbered ``Table 9.2``:
        section 9, second table).

    Examples
    --------
    >>> from hyperlattice.report.writers import Table
    >>> table = Table("counts", ["rings", "N"], [[1, 7], [2, 35]], caption="Sites per flake.")
    >>> table.columns, table.rows[1]
    (['rings', 'N'], [2, 35])
    """

    name: str
    columns: list[str]
    rows: list[list]
    caption: str = ""
    paper: str = ""

    def __post_init__(self) -> None:
        _check_paper_label(self.paper)
        # a value that rounds to zero is printed as 0, never "−0.0000" (the sign of rounding noise)
        self.rows = [[_unsigned_zero(v) for v in row] for row in self.rows]

    def write(self, out: Path) -> None:
        """Write the CSV and JSON files into ``out``.

        Parameters
        ----------
        out : pathlib.Path
            An existing directory.

        Returns
        -------
        None
            Writes ``table_<name>.csv`` (header row, then the rows) and ``table_<name>.json`` (a
            list of one dict per row).

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from hyperlattice.report.writers import Table
        >>> with tempfile.TemporaryDirectory() as d:
        ...     Table("counts", ["rings", "N"], [[1, 7], [2, 35]]).write(Path(d))
        ...     print(sorted(p.name for p in Path(d).iterdir()))
        ...     print((Path(d) / "table_counts.csv").read_text().splitlines())
        ['table_counts.csv', 'table_counts.json']
        ['rings,N', '1,7', '2,35']
        """
        with writing(out, f"table_{self.name}.csv") as path, open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.columns)
            w.writerows(self.rows)
        with writing(out, f"table_{self.name}.json") as path, open(path, "w") as fh:
            json.dump([dict(zip(self.columns, r)) for r in self.rows], fh, indent=1)


@dataclass
class Figure:
    """A figure already written as ``fig_<name>.png`` / ``.svg``; ``png`` is embedded in the HTML.

    Attributes
    ----------
    name : str
        File-name stem (``fig_<name>.*``).
    caption : str
        Caption in the Markdown and HTML report.
    png : bytes
        The PNG file's bytes (empty when not embedded).
    paper : str
        The paper's TeX label of the figure it reproduces (``"Fig2"``), shown as the paper prints it
        (``"Fig. 3"``); empty for a figure of the report's own (numbered ``Fig. 9.1``).
    panel : str
        Which part of the paper's figure, when it takes several (``"upper panels"``).

    Examples
    --------
    >>> from hyperlattice.report.writers import Figure
    >>> fig = Figure("spectrum", "Lowest levels.")
    >>> fig.name, fig.png
    ('spectrum', b'')
    """

    name: str
    caption: str
    png: bytes = b""
    paper: str = ""
    panel: str = ""

    def __post_init__(self) -> None:
        _check_paper_label(self.paper)


def _check_paper_label(label: str) -> None:
    from ..paper_labels import cite

    if not isinstance(label, str):
        raise ValueError(f"paper must be one TeX label of the paper as a string, got {type(label).__name__}.")
    if label:
        cite(label)


@dataclass
class Section:
    """One section of the report.

    ``labels`` are the paper's TeX labels the section reproduces (or, beyond the paper, builds on);
    the report prints them as the paper prints them (:func:`hyperlattice.paper_labels.cite`).
    ``anchor`` is the section's stable id (``sec-<anchor>`` in the HTML and Markdown), ``part`` is
    ``"paper"`` or ``"beyond"``, ``provenance`` says where numbers not computed by this run come from.

    Attributes
    ----------
    title : str
        Section heading.
    labels : tuple of str
        The paper's TeX labels (checked by :func:`hyperlattice.paper_labels.cite`).
    text : list of str
        Paragraphs.
    tables : list of Table
        The section's tables.
    figures : list of Figure
        The section's figures.
    anchor : str
        Stable id; default: a slug of the title.
    part : str
        ``"paper"`` or ``"beyond"``.
    provenance : list of str
        Where numbers not computed by this run come from.

    Raises
    ------
    ValueError
        For labels given as one string, an unknown label, or another ``part``.

    Examples
    --------
    >>> from hyperlattice.report.writers import Section
    >>> sec = Section("Band bottom and BF bound", labels=("eq21",))
    >>> sec.id, sec.reference_line
    ('sec-band-bottom-and-bf-bound', 'Reproduces: Eq. (19)')
    """

    title: str
    labels: tuple = ()
    text: list[str] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    anchor: str = ""
    part: str = "paper"
    provenance: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        from ..paper_labels import cite

        if isinstance(self.labels, str):
            raise ValueError("Section labels are a tuple of the paper's TeX labels, not a string.")
        cite(*self.labels)  # an unknown label is an error here, not a wrong number in the report
        if self.part not in ("paper", "beyond"):
            raise ValueError(f"part must be 'paper' or 'beyond', got {self.part!r}.")
        if not self.anchor:
            self.anchor = _slug(self.title)

    @property
    def id(self) -> str:
        """The HTML id of the section heading."""
        return f"sec-{self.anchor}"

    @property
    def reference_line(self) -> str:
        """``Reproduces: Table I, Eq. (10)`` (paper part) or ``Builds on: ...`` (beyond the paper)."""
        from ..paper_labels import cite

        if not self.labels:
            return ""
        return ("Reproduces: " if self.part == "paper" else "Builds on: ") + cite(*self.labels)


#: ASCII maths in sentences (many come from the ``statement()`` methods of :mod:`hyperlattice.compare`)
#: -> the symbols a reader expects; applied to prose, captions and titles, never to table cells,
#: column names, file names or commands (text in backticks is left alone).
_PROSE = [(re.compile(a), b) for a, b in (
    (r"\bl\s*->\s*infinity\b", "ℓ → ∞"), (r"\bl ?= ?(?=[\d{(])", "ℓ = "), (r"\bl ?<= ?", "ℓ ≤ "),
    (r"\bl ?>= ?", "ℓ ≥ "), (r"\bl ?≥ ?", "ℓ ≥ "), (r"\bl ?≤ ?", "ℓ ≤ "), (r"\(f, l\)", "(f, ℓ)"),
    (r"\bl ≳", "ℓ ≳"), (r"\bE\(l\)", "E(ℓ)"), (r"\(l\)", "(ℓ)"), (r"\bl_max\b", "ℓ_max"), (r"\bl-ring\b", "ℓ-ring"),
    (r"\bE_inf\^impr\b", "E∞^impr"), (r"\bE_inf\b", "E∞"), (r"-rho\b", "−ρ"), (r"\brho\b", "ρ"),
    (r"\bomega_q\b", "ω_q"), (r"\bomega\b", "ω"), (r"\bDelta_g\b", "Δ_g"), (r"\bDelta\b", "Δ"),
    (r"\bSigma\b", "Σ"), (r"\bsqrt\(", "√("), (r"\bsqrt ?(?=\w)", "√"), (r"\bpi\b", "π"), (r"\blambda\b", "λ"),
    (r"\btheta\b", "θ"), (r"\bpsi\b", "ψ"), (r"\bphi\b", "φ"), (r"\bchi\b", "χ"), (r"\bnu\b", "ν"),
    (r"\bbeta\b", "β"), (r"\bmu\b", "μ"), (r"\bxi\b", "ξ"), (r"\binfinity\b", "∞"),
    (r"\^2(?![\d.])", "²"), (r"\^3(?![\d.])", "³"), (r"\^4(?![\d.])", "⁴"), (r"\^6(?![\d.])", "⁶"),
    (r"\^-1(?![\d.])", "⁻¹"), (r"(?<![A-Za-z_])d0\b", "d₀"), (r"(?<![A-Za-z_])E0\b", "E₀"),
    (r"(?<![A-Za-z_])E1\b", "E₁"), (r"\bk0\b", "k₀"), (r"\blog10\b", "log₁₀"), (r"_nu\b", "_ν"),
    (r"\bdlambda\b", "dλ"), (r"\bL2\b", "L²"),
    (r"\b(in|as|all|large|finite|on|with|of|and|per|each|over) l\b(?![-'])", r"\1 ℓ"), (r"/l(?=²|\^)", "/ℓ"),
    (r" <= ", " ≤ "), (r" >= ", " ≥ "), (r" >> ", " ≫ "), (r" << ", " ≪ "), (r" -> ", " → "), (r" \+- ", " ± "),
    (r"(?<=\d)\.\.(?=\d)", "–"), (r"(?<=\d)\.\.(?=-)", " to "),
    # a true minus: before a number that follows a space, bracket, '=', ',', ':' or '/' (not 1e-3, not
    # a range 3-12, not a flag), and between two terms of a difference
    (r"(?:^|(?<=[\s(\[=,:;/]))-(?=\.?\d)", "−"), (r"(?<=[\w)\]}|]) - (?=[\w(\[{|])", " − "),
)]


def prose(text: str) -> str:
    """``text`` with ASCII maths replaced by symbols (ℓ, ρ, E∞, ω, ≤, ...), backtick spans kept as they are.

    Applied to the report's sentences, captions and titles (many come from the ``statement()``
    methods of :mod:`hyperlattice.compare`), never to table cells, column names, file names or
    commands.

    Parameters
    ----------
    text : str
        A sentence; spans between backticks (commands, file names) are not changed.

    Returns
    -------
    str
        The sentence with l -> ℓ where it means the ring number, rho -> ρ, E_inf -> E∞, E0 -> E₀,
        ``<=`` -> ≤, ``->`` -> →, ``+-`` -> ±, squares as superscripts, and the like.

    Examples
    --------
    >>> from hyperlattice.report.writers import prose
    >>> prose("E0(l) -> E_inf as l -> infinity, rho = 2.94 +- 0.01; run `hyperlattice spectrum -l 2`")
    'E₀(ℓ) → E∞ as ℓ → ∞, ρ = 2.94 ± 0.01; run `hyperlattice spectrum -l 2`'
    """
    pieces = text.split("`")
    for i in range(0, len(pieces), 2):
        t = pieces[i]
        for pattern, repl in _PROSE:
            t = pattern.sub(repl, t)
        pieces[i] = t
    return "`".join(pieces)


def _code(text: str) -> str:
    """HTML-escaped ``text`` with `backtick spans` as <code> (commands, file names)."""
    pieces = text.split("`")
    if len(pieces) % 2 == 0:  # an unpaired backtick: show it as it is
        return html.escape(text)
    return "".join(html.escape(p) if i % 2 == 0 else f"<code>{html.escape(p)}</code>" for i, p in enumerate(pieces))


def _slug(text: str) -> str:
    out = "".join(c.lower() if c.isalnum() else "-" for c in text)
    while "--" in out:
        out = out.replace("--", "-")
    return out.strip("-")


#: the two parts of the report, in order, with their headings and ids
PARTS = (("paper", "The paper", "part-paper"), ("beyond", "Beyond the paper", "part-beyond"))


def table_id(t: Table) -> str:
    """The HTML id of a table's caption.

    Parameters
    ----------
    t : Table
        A table of the report.

    Returns
    -------
    str
        ``"table-<slug of the name>"`` (lower case, runs of other characters replaced by one ``-``),
        the anchor the table of contents links to.

    See Also
    --------
    figure_id : the same for figures.

    Examples
    --------
    >>> from hyperlattice.report.writers import Table, table_id
    >>> table_id(Table("counts", ["rings", "N"], [[1, 7]]))
    'table-counts'
    """
    return f"table-{_slug(t.name)}"


def figure_id(f: Figure) -> str:
    """The HTML id of a figure.

    Parameters
    ----------
    f : Figure
        A figure of the report.

    Returns
    -------
    str
        ``"fig-<slug of the name>"`` (lower case, runs of other characters replaced by one ``-``).

    See Also
    --------
    table_id : the same for tables.

    Examples
    --------
    >>> from hyperlattice.report.writers import Figure, figure_id
    >>> figure_id(Figure("Fig 2 (a)", "caption"))
    'fig-fig-2-a'
    """
    return f"fig-{_slug(f.name)}"


def item_labels(sections: list[Section]) -> dict[int, str]:
    """The name of each table and figure in the report, as the paper prints it or numbered per section.

    The names are ``"Table IV"`` or ``"Fig. 3"`` (the paper's) and ``"Table 9.2"`` (the report's own).
    A table or figure that reproduces one of the paper's is named as the paper prints it
    (:func:`hyperlattice.paper_labels.cite`, plus the panel for a figure split in several); every
    other one is numbered within its section of the report: ``Table 9.2`` is the second of the
    report's own tables in section 9, ``Fig. 9.1`` its first own figure. Internal file names
    (``paper_table4``, ``paper_fig3``) never name an item; they appear only as the files' names.

    Parameters
    ----------
    sections : list of Section
        The sections in the report's order (:func:`write_md` and :func:`write_html` number them
        1, 2, ... in that order, the paper's first).

    Returns
    -------
    dict of int to str
        ``id()`` of each :class:`Table` and :class:`Figure` -> its name in the report.

    Examples
    --------
    >>> from hyperlattice.report.writers import Figure, Section, Table, item_labels
    >>> t1 = Table("s1", ["rings"], [[1]], paper="SuppTab1")
    >>> t2 = Table("s1_vs_paper", ["rings"], [[1]])
    >>> f = Figure("fig3a", "", paper="Fig3", panel="upper panels")
    >>> names = item_labels([Section("Levels", tables=[t1, t2], figures=[f])])
    >>> names[id(t1)], names[id(t2)], names[id(f)]
    ('Table IV', 'Table 1.1', 'Fig. 4, upper panels')
    """
    from ..paper_labels import cite

    names: dict[int, str] = {}
    for n, s in enumerate(_ordered(sections), start=1):
        own_t = own_f = 0
        for t in s.tables:
            if t.paper:
                names[id(t)] = cite(t.paper)
            else:
                own_t += 1
                names[id(t)] = f"Table {n}.{own_t}"
        for f in s.figures:
            if f.paper:
                names[id(f)] = cite(f.paper) + (f", {f.panel}" if f.panel else "")
            else:
                own_f += 1
                names[id(f)] = f"Fig. {n}.{own_f}"
    return names


def _captioned(label: str, caption: str) -> str:
    """``"Table 9.2. caption"``; a caption that already opens with the label keeps it once."""
    caption = caption.strip()
    base = label.split(",")[0]
    if caption.startswith(base):
        return caption
    return f"{label}. {caption}" if caption else f"{label}."


def _ordered(sections: list[Section]) -> list[Section]:
    """The paper's sections first, then those beyond it (each group in the given order)."""
    return [s for part, _, _ in PARTS for s in sections if s.part == part]


def _toc_md(sections: list[Section]) -> list[str]:
    lines = ["## Contents", ""]
    names = item_labels(sections)
    n = 0
    for part, heading, pid in PARTS:
        lines.append(f"- [{heading}](#{pid})")
        for s in sections:
            if s.part != part:
                continue
            n += 1
            lines.append(f"  - [{n}. {prose(s.title)}](#{s.id})")
            items = [f"[{names[id(t)]}](#{table_id(t)})" for t in s.tables]
            items += [f"[{names[id(f)]}](#{figure_id(f)})" for f in s.figures]
            if items:
                lines.append("    - " + " · ".join(items))
    return lines + [""]


#: column names (the CSV/JSON keys, stable identifiers) whose printed header is not a word-by-word reading
_COLUMN_LABELS = {
    "N_ring": "sites on ring", "N_closed_form": "N (closed form)", "E_inf_paper": "E∞, paper's map",
    "E_inf_improved": "E∞, improved map", "paper_E0": "E₀, paper's map", "improved_E0": "E₀, improved map",
    "paper_E1": "E₁, paper's map", "improved_E1": "E₁, improved map", "paper_mass": "q h²/4 (paper's map)",
    "band_minus_improved": "band bottom − improved E∞", "tip_t_c_over_U": "tip (t/U)_c",
    "tip_t_c_over_U_error": "tip (t/U)_c error", "mass2_at_E0": "m² at E₀", "radius_constant": "c = π/𝒜",
    "site_area": "area per site 𝒜", "share_of_total": "share of total", "flagged": "flagged (≠)",
    "rel_l2": "relative L² distance", "schur": "Schur test", "born_ratio": "Born ratio", "lambda_max": "λ_max",
    "lambda_max_error": "λ_max error",
    "gap_ed_error_bound": "ED gap error bound", "gap_ed": "ED gap", "decay_length_continuum_asymptotic":
    "decay length, continuum (asymptotic)", "exact_moments": "exact moments",
}
#: words of a column name as printed: symbols for the physics names, whole words for abbreviations
_COLUMN_WORDS = {
    "E0": "E₀", "E1": "E₁", "d0": "d₀", "r0": "r₀", "L1": "L¹", "l2": "L²", "lB": "ℓ_B", "omega": "ω",
    "omega1": "ω₁", "omega_q": "ω_q", "beta": "β", "lambda": "λ", "mu": "μ", "xi": "ξ", "sigma": "σ",
    "delta": "Δ", "mass2": "m²", "rel": "relative", "err": "error", "diff": "difference", "ed": "ED",
    "scba": "SCBA", "rho": "ρ", "Z": "Z", "inf": "∞",
}


def column_label(name: str) -> str:
    """The header a reader sees for the column ``name`` (the CSV/JSON key stays the identifier).

    ``"E0_graph_flag"`` is printed ``"E₀ graph: flag (≠)"``, ``"N_paper"`` ``"N (paper)"``,
    ``"lB_over_d0"`` ``"ℓ_B/d₀"``; names that are already text (``"μ/U QMC"``) are kept.

    Parameters
    ----------
    name : str
        A column name of a :class:`Table` (its CSV/JSON key).

    Returns
    -------
    str
        The header printed in ``report.md`` and ``report.html``.

    Examples
    --------
    >>> from hyperlattice.report.writers import column_label
    >>> [column_label(c) for c in ("E0_graph_flag", "N_closed_form", "rel_l2", "lB_over_d0", "rings", "μ/U QMC")]
    ['E₀ graph: flag (≠)', 'N (closed form)', 'relative L² distance', 'ℓ_B/d₀', 'rings', 'μ/U QMC']
    """
    if name in _COLUMN_LABELS:
        return _COLUMN_LABELS[name]
    for suffix, tail in (("_paper", " (paper)"), ("_flag", ": flag (≠)")):
        if name.endswith(suffix) and len(name) > len(suffix):
            return column_label(name[: -len(suffix)]) + tail
    if "_over_" in name:
        top, _, bottom = name.partition("_over_")
        return f"{column_label(top)}/{column_label(bottom)}"
    if name in _COLUMN_WORDS:
        return _COLUMN_WORDS[name]
    if name.startswith("E_") and name[2:] in ("inf",):
        return "E∞"
    if name.startswith("omega_q"):
        return " ".join(["ω_q", *[_COLUMN_WORDS.get(w, w) for w in name[8:].split("_") if w]])
    return " ".join(_COLUMN_WORDS.get(w, w) for w in name.split("_") if w)


_NEGATIVE_ZERO = re.compile(r"[-−]0(?:\.0*)?(?:e[-+]?0+)?")


def _unsigned_zero(x):
    """``x`` with the sign of a zero dropped: ``"-0.0000"`` -> ``"0.0000"``, ``-0.0`` -> ``0.0``."""
    if isinstance(x, str):
        return x.replace("-", "", 1).replace("−", "", 1) if _NEGATIVE_ZERO.fullmatch(x.strip()) else x
    if isinstance(x, (float, np.floating)) and x == 0:
        return 0.0
    return x


def fmt(x, digits: int = 12) -> str:
    """A table cell: strings as they are, integers exactly, floats with ``digits`` decimals, NaN/None empty.

    Parameters
    ----------
    x : str, int, float or None
        The cell value (numpy integers and reals included).
    digits : int, optional
        Decimals of a real number (default 12).

    Returns
    -------
    str
        The cell as written into the Markdown and HTML tables.

    Raises
    ------
    ValueError
        If ``x`` is neither a string, a real number nor None.

    Examples
    --------
    >>> from hyperlattice.report.writers import fmt
    >>> fmt(0.5, 3), fmt(7), fmt(None), fmt(float("nan")), fmt("≠"), fmt(-1e-17, 4)
    ('0.500', '7', '', '', '≠', '0.0000')
    >>> fmt([1])
    Traceback (most recent call last):
        ...
    ValueError: a table cell must be a number, a string or None, got list.
    """
    if isinstance(x, str):
        return x
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return ""
    if not isinstance(x, numbers.Real):
        raise ValueError(f"a table cell must be a number, a string or None, got {type(x).__name__}.")
    return _unsigned_zero(f"{x:.{digits}f}")


def save_figure(fig: matplotlib.figure.Figure, out: Path, name: str, caption: str, *, paper: str = "",
                panel: str = "") -> Figure:
    r"""Write ``fig`` as ``fig_<name>.png`` and ``.svg`` without timestamps, close it, return the Figure.

    Before writing, a figure with several panels and no panel letters gets (a), (b), ..., and text is
    enlarged to at least 8 pt at the width the report shows it. The PNG (110 dpi) and SVG carry no
    date, so two runs write byte-identical files.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to write; it is closed afterwards.
    out : str or path-like
        An existing directory to write into.
    name : str
        File stem: the files are ``fig_<name>.png`` and ``fig_<name>.svg``.
    caption : str
        The caption printed under the figure in the report.
    paper, panel : str, optional
        The paper's TeX label of the figure reproduced and which part of it (see :class:`Figure`).

    Returns
    -------
    Figure
        The report's record of the figure, with the PNG bytes to embed in the HTML.

    Raises
    ------
    ValueError
        If ``out`` is not an existing directory.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.report.writers import Section, Table, save_figure
    >>> fig, ax = plt.subplots()
    >>> _ = ax.plot([0, 1], [0, 1])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = save_figure(fig, Path(d), "line", "a straight line")
    ...     files = sorted(p.name for p in Path(d).iterdir())
    >>> f.name, f.png[:4], files
    ('line', b'\x89PNG', ['fig_line.png', 'fig_line.svg'])
    >>> plt.fignum_exists(fig.number)
    False
    """
    out = _validate.directory("out", out, create=False)
    import matplotlib.pyplot as plt

    _readable(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    png = buf.getvalue()
    with writing(out, f"fig_{name}.png") as path:
        path.write_bytes(png)
    with writing(out, f"fig_{name}.svg") as path:
        fig.savefig(path, format="svg", metadata={"Date": None})
    plt.close(fig)
    return Figure(name=name, caption=caption, png=png, paper=paper, panel=panel)


#: the width (inches) a report figure is shown at: 1050 px of the page at the PNG's 110 dpi
_SHOWN_WIDTH_IN = 1050 / 110


def _readable(fig) -> None:
    """Panel letters (a), (b), ... on figures with several panels that have none, and text at least
    8 pt once the figure is shrunk to the page width (wide figures are shown at 1050 px)."""
    from matplotlib.text import Text

    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.get_visible() and ax.axison]
    lettered = any(t.get_text().startswith("(a)") for ax in panels for t in [ax.title, *ax.texts])
    if len(panels) > 1 and not lettered:
        for k, ax in enumerate(panels):
            ax.text(-0.08, 1.04, f"({chr(ord('a') + k)})", transform=ax.transAxes, fontsize=12,
                    fontweight="bold", va="bottom", ha="right")
    scale = min(1.0, _SHOWN_WIDTH_IN / fig.get_figwidth())
    floor = 8.0 / scale
    if scale < 1.0:
        for t in fig.findobj(Text):
            if t.get_text() and t.get_fontsize() < floor:
                t.set_fontsize(floor)


def _md_table(t: Table, label: str) -> list[str]:
    lines = [f'<a id="{table_id(t)}"></a>', "", f"*{prose(_captioned(label, t.caption))}* (`table_{t.name}.csv`)", "", "| " + " | ".join(column_label(c) for c in t.columns) + " |",
             "|" + "---|" * len(t.columns)]
    for r in t.rows:
        lines.append("| " + " | ".join(fmt(v) for v in r) + " |")
    return lines + [""]


def write_md(sections: list[Section], header: list[str], out: Path) -> None:
    r"""Write ``report.md`` (figures linked as ``fig_*.png``).

    The file has the header, a table of contents, then the two parts ("The paper", "Beyond the
    paper") with their sections: reference line, provenance, text, tables and figures. Prose is
    rewritten with symbols (ℓ, ρ, ω, ...), except in backtick spans.

    Parameters
    ----------
    sections : list of Section
        The sections; the paper's come first, then those beyond it, each group in the given order,
        numbered 1, 2, ... through the report.
    header : list of str
        Lines above the table of contents (a line starting with ``"# "`` is the title).
    out : str or path-like
        An existing directory to write into.

    Returns
    -------
    None
        The report is written to ``out / "report.md"``.

    Raises
    ------
    ValueError
        If ``out`` is not an existing directory.

    See Also
    --------
    write_html : the same report as one self-contained HTML file.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from hyperlattice.report.writers import Section, Table, write_md
    >>> t = Table("counts", ["rings", "N"], [[1, 7], [2, 35]], caption="sites of the flakes")
    >>> s = Section("Counting sites", labels=("Tab1",), text=["l = 2 has 35 sites."], tables=[t])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_md([s], ["# demo"], Path(d))
    ...     md = (Path(d) / "report.md").read_text()
    >>> print("\n".join(x for x in md.splitlines() if x.startswith(("###", "Reproduces", "ℓ", "|"))))
    ### 1. Counting sites
    Reproduces: Table I
    ℓ = 2 has 35 sites.
    | rings | N |
    |---|---|
    | 1 | 7 |
    | 2 | 35 |
    """
    out = _validate.directory("out", out, create=False)
    sections = _ordered(sections)
    names = item_labels(sections)
    lines = list(header) + _toc_md(sections)
    n = 0
    for part, heading, pid in PARTS:
        lines += [f'<a id="{pid}"></a>', "", f"## {heading}", ""]
        for s in sections:
            if s.part != part:
                continue
            n += 1
            lines += [f'<a id="{s.id}"></a>', "", f"### {n}. {prose(s.title)}", ""]
            if s.reference_line:
                lines += [s.reference_line, ""]
            for p in s.provenance:
                lines += [f"Provenance: {prose(p)}", ""]
            for p in s.text:
                lines += [prose(p), ""]
            for t in s.tables:
                lines += _md_table(t, names[id(t)])
            for f in s.figures:
                lines += [f'<a id="{figure_id(f)}"></a>', "", f"![{names[id(f)]}](fig_{f.name}.png)", "",
                          f"*{prose(_captioned(names[id(f)], f.caption))}* (vector: `fig_{f.name}.svg`)", ""]
    with writing(out, "report.md") as path:
        path.write_text("\n".join(lines))


def write_html(sections: list[Section], header: list[str], out: Path) -> None:
    """Write ``report.html``, self-contained: figures embedded as base64 PNG, no external references.

    Same content and order as :func:`write_md`, with a linked table of contents, tables whose
    ``...flag`` columns are highlighted, and the figures' PNG bytes inlined.

    Parameters
    ----------
    sections : list of Section
        The sections; the paper's come first, then those beyond it, each group in the given order,
        numbered 1, 2, ... through the report.
    header : list of str
        Lines above the table of contents (a line starting with ``"# "`` is the title).
    out : str or path-like
        An existing directory to write into.

    Returns
    -------
    None
        The report is written to ``out / "report.html"``.

    Raises
    ------
    ValueError
        If ``out`` is not an existing directory.

    See Also
    --------
    write_md : the Markdown version.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.report.writers import Section, Table, save_figure
    >>> from hyperlattice.report.writers import write_html
    >>> fig, ax = plt.subplots()
    >>> _ = ax.plot([0, 1], [0, 1])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = save_figure(fig, Path(d), "line", "a straight line")
    ...     t = Table("counts", ["rings", "N"], [[1, 7], [2, 35]], caption="sites of the flakes")
    ...     write_html([Section("Counting sites", tables=[t], figures=[f])], ["# demo"], Path(d))
    ...     page = (Path(d) / "report.html").read_text()
    >>> page.splitlines()[0], page.count("<table>"), "data:image/png;base64," in page
    ('<!DOCTYPE html>', 1, True)
    """
    out = _validate.directory("out", out, create=False)
    e = html.escape
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             "<title>hyperlattice: reproduction of Boettcher et al., PRA 102, 032208</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.4}"
             ".scroll{overflow-x:auto;max-width:100%}"
             "table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0}"
             "nav.toc{background:#f6f6f6;border:1px solid #ddd;padding:0.5em 1em}nav.toc ul{margin:0.2em 0}"
             "nav.toc .items{font-size:0.85em;color:#555}"
             "h2,h3,p.cap,figure{scroll-margin-top:0.5em}"
             "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}"
             "th{background:#eee;vertical-align:bottom}td{white-space:nowrap}td.flag{color:#b00;font-weight:bold}"
             "img{max-width:100%}figcaption{font-size:0.9em;color:#333}.cap{font-style:italic}</style>",
             "</head>", "<body>"]
    for line in header:
        if line.startswith("# "):
            parts.append(f"<h1>{e(line[2:])}</h1>")
        elif line:
            parts.append(f"<p>{_code(prose(line))}</p>")
    sections = _ordered(sections)
    names = item_labels(sections)
    parts.append('<nav class="toc" id="contents"><h2>Contents</h2><ul>')
    n = 0
    for part, heading, pid in PARTS:
        parts.append(f'<li><a href="#{pid}">{e(heading)}</a><ul>')
        for s in sections:
            if s.part != part:
                continue
            n += 1
            items = [f'<a href="#{table_id(t)}">{e(names[id(t)])}</a>' for t in s.tables]
            items += [f'<a href="#{figure_id(f)}">{e(names[id(f)])}</a>' for f in s.figures]
            sub = f'<br><span class="items">{" · ".join(items)}</span>' if items else ""
            parts.append(f'<li><a href="#{s.id}">{n}. {e(prose(s.title))}</a>{sub}</li>')
        parts.append("</ul></li>")
    parts.append("</ul></nav>")
    n = 0
    for part, heading, pid in PARTS:
        parts.append(f'<h2 id="{pid}">{e(heading)}</h2>')
        for s in sections:
            if s.part != part:
                continue
            n += 1
            parts.append(f'<h3 id="{s.id}">{n}. {e(prose(s.title))}</h3>')
            if s.reference_line:
                head, _, rest = s.reference_line.partition(": ")
                parts.append(f"<p><b>{e(head)}:</b> {e(rest)}</p>")
            for p in s.provenance:
                parts.append(f'<p class="prov"><b>Provenance:</b> {_code(prose(p))}</p>')
            for p in s.text:
                parts.append(f"<p>{_code(prose(p))}</p>")
            for t in s.tables:
                parts.append(f'<p class="cap" id="{table_id(t)}">{_code(prose(_captioned(names[id(t)], t.caption)))} '
                             f'(<code>table_{e(t.name)}.csv</code>)</p>')
                # headers may break after an underscore (E0_continuum_paper): a wide table fits the page
                heads = "".join("<th>" + e(column_label(c)) + "</th>" for c in t.columns)
                parts.append(f'<div class="scroll"><table><thead><tr>{heads}</tr></thead><tbody>')
                for r in t.rows:
                    cells = []
                    for c, v in zip(t.columns, r):
                        cls = ' class="flag"' if c.endswith("flag") and v else ""
                        cells.append(f"<td{cls}>{e(fmt(v))}</td>")
                    parts.append("<tr>" + "".join(cells) + "</tr>")
                parts.append("</tbody></table></div>")
            for f in s.figures:
                b64 = base64.b64encode(f.png).decode("ascii")
                parts.append(f'<figure id="{figure_id(f)}"><img alt="{e(names[id(f)])}" '
                             f'src="data:image/png;base64,{b64}">'
                             f"<figcaption>{_code(prose(_captioned(names[id(f)], f.caption)))}</figcaption></figure>")
    parts += ["</body>", "</html>", ""]
    with writing(out, "report.html") as path:
        path.write_text("\n".join(parts))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
