"""The sections of the ``reproduce`` report: they put computed numbers and the paper's printed
values into tables, sentences and figures, and compute nothing themselves.

The numbers come from the package's API (:mod:`.data` for the cached ones,
:mod:`hyperlattice.compare.levels` for the graph-vs-continuum analysis), the printed values from
:mod:`hyperlattice.paper_values`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from .. import geometry
from ..cache import Cache
from ..compare.levels import RelativeErrorTrend
from ..graph.lattice import ring_lattice, ring_sizes
from ..paper_labels import cite
from ..paper_values import PaperValue, paper_value
from . import data
from .writers import Section, Table, column_label, fmt as _fmt, save_figure as _save_figure

__all__ = ["geometry_section", "counts_section", "fig1_section", "spectrum_section", "open_question_text",
           "fig2_section", "green_section", "formal_operator_figure", "scaling_section", "magnetic_section"]

#: The butterfly of the report: flake size and number of flux values computed in [0, 1/2] (every
#: 1/800; the figure mirrors them to [1/2, 1], since E(1 − f) = E(f) on a site flake)
BUTTERFLY_RINGS = 5
BUTTERFLY_FLUXES = 401

#: Flakes of the magnetic error map (the 1e-3 contour first appears at l = 6).
MAGNETIC_RINGS = (3, 4, 5, 6, 7)

#: The columns of ``SuppTab1``, in the paper's order.
_LEVEL_KEYS = ("E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph", "E1_continuum", "E1_asymptotic")


#: subscript digits for level names in prose (E0 -> E₀)
_SUB = {str(d): chr(0x2080 + d) for d in range(10)}


def _omega(omega) -> str:
    """ω as prose: -2.95 -> "−2.95", (-2.5+0.1j) -> "−2.5 + 0.1i"."""
    if isinstance(omega, complex):
        sign = "+" if omega.imag >= 0 else "−"
        return f"{omega.real:g} {sign} {abs(omega.imag):g}i".replace("-", "−")
    return f"{omega:g}".replace("-", "−")


def _printed(key: str, index) -> PaperValue | None:
    """The paper's printed value, or None where the paper prints none (e.g. l > 10)."""
    try:
        return paper_value(key, index)
    except ValueError:
        return None


def geometry_section() -> Section:
    """Constants of {p,3} beside the table of App. ``AppFS`` (Table III).

    For p = 7, 8, 9, 10 and ∞: r₀, d₀ and h = tanh d₀ (with the paper's printed d₀ and h and a flag
    where they differ), the area per site and the constant c of L = √(N/(N + c)); the text explains the
    p = ∞ column and every flagged value.

    Returns
    -------
    Section
        The section ``"Geometry of {p,3} tessellations"`` (anchor ``"geometry"``) with one table,
        ``"geometry"``.

    Examples
    --------
    >>> from hyperlattice.report.sections import geometry_section
    >>> s = geometry_section()
    >>> s.reference_line
    'Reproduces: Table III, Eq. (A1), Eq. (B6), Eq. (10)'
    >>> table = s.tables[0]
    >>> table.columns[:5]
    ['p', 'r0', 'd0', 'd0_paper', 'd0_flag']
    >>> table.rows[0][:5]
    [7, '0.300742619', '0.283128153', '0.283128', '']
    """
    rows = []
    flags = []
    for p in (7, 8, 9, 10, "inf"):
        pp = math.inf if p == "inf" else p
        c = geometry.tiling_constants(pp, 3)
        d0_p, h_p = paper_value("geometry_d0", p), paper_value("geometry_h", p)
        f1, n1 = d0_p.check(c.d0)
        f2, n2 = h_p.check(c.h)
        rows.append([p, _fmt(c.r0, 9), _fmt(c.d0, 9), d0_p.printed, f1, _fmt(c.h, 9), h_p.printed, f2,
                     _fmt(c.site_area, 9), _fmt(c.radius_constant, 6)])
        flags += [n for n in (n1, n2) if n]
    table = Table("geometry", ["p", "r0", "d0", "d0_paper", "d0_flag", "h", "h_paper", "h_flag", "site_area",
                               "radius_constant"], rows,
                  f"Constants of {{p,3}}: r₀ ({cite('Eqr0')}), d₀ = d(r₀, r₀ e^(2πi/p)), h = tanh d₀ "
                  f"({cite('adj6')}), area per site π(1 − 6/p)/4 ({cite('sum1c')}) and c = 4p/(p − 6) in "
                  f"L = √(N/(N + c)) ({cite('eq12')}).", paper="AppFS table")
    text = ["The p = ∞ column is computed as a limit: cosh d₀ = cos(π/p)/sin(π/q) → 1/sin(π/3), "
            "so d₀ → ½ ln 3 and h → cos(π/3) = 1/2."]
    text += [f"Flagged: {n}" for n in flags]
    return Section("Geometry of {p,3} tessellations", ("AppFS table", "Eqr0", "adj6", "eq12"), text, [table],
                   anchor="geometry")


def counts_section(max_rings: int) -> Section:
    """Sites per ring and in total, and L, beside ``Tab1`` and ``AppTab1``.

    One row per l = 1 .. max(max_rings, 10): sites on ring l and in total (with the paper's values and
    the closed form of the ``Tab1`` caption) and the effective disk radius L = √(N/(N + 28)); flagged
    values are explained in the text.

    Parameters
    ----------
    max_rings : int
        Largest number of rings of the report; the table covers at least l = 1..10 (the paper's).

    Returns
    -------
    Section
        The section ``"Lattice sizes and effective radius"`` (anchor ``"sizes"``) with the table
        ``"paper_table1_sizes"``.

    Raises
    ------
    ValueError
        If ``max_rings`` is not an integer.

    Examples
    --------
    >>> from hyperlattice.report.sections import counts_section
    >>> s = counts_section(3)
    >>> s.reference_line, len(s.tables[0].rows)
    ('Reproduces: Table I, Table II, Eq. (10)', 10)
    >>> s.tables[0].rows[7]
    [8, 9548, '9548', 15435, '15435', '', 15435, '0.9990942027', '0.9990', '≠']
    >>> print(s.text[1])
    Flagged: ℓ = 8: rounding slip: √(15435/15463) = 0.999094 rounds to 0.9991.
    """
    sizes = ring_sizes(7, 3, max(max_rings, 10))
    rows = []
    notes = []
    for ell in range(1, len(sizes) + 1):
        n = int(sizes[:ell].sum())
        L = geometry.effective_radius(n)
        pv_n, pv_ring, pv_l = _printed("N", ell), _printed("N_ring", ell), _printed("L", ell)
        fl, nl = pv_l.check(L) if pv_l else ("", "")
        closed = round(7 * (((3 + 5**0.5) / 2) ** ell + ((3 - 5**0.5) / 2) ** ell - 2))
        ok = pv_n.check(n)[0] if pv_n else ""
        rows.append([ell, int(sizes[ell - 1]), pv_ring.printed if pv_ring else "", n, pv_n.printed if pv_n else "",
                     ok, closed, _fmt(L, 10), pv_l.printed if pv_l else "", fl])
        if nl:
            notes.append(f"ℓ = {ell}: {nl}")
    table = Table("paper_table1_sizes", ["rings", "N_ring", "N_ring_paper", "N", "N_paper", "N_flag", "N_closed_form",
                                 "L", "L_paper", "L_flag"], rows,
                  f"Sites per ring and in total ({cite('Tab1', 'AppTab1')}), the closed form of the caption of "
                  f"{cite('Tab1')}, and the effective disk radius L = √(N/(N + 28)) ({cite('eq12')}).", paper="Tab1")
    text = ["Counts come from the combinatorial ring construction; the closed form "
            "N = 7[((3+√5)/2)^ℓ + ((3−√5)/2)^ℓ − 2] is printed as an independent check."]
    text += [f"Flagged: {n}" for n in notes]
    return Section("Lattice sizes and effective radius", ("Tab1", "AppTab1", "eq12"), text, [table], anchor="sizes")


def fig1_section(out: Path) -> Section:
    """``Fig1``: the tessellation and the l = 3 graph.

    Parameters
    ----------
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.

    Returns
    -------
    Section
        The section ``"The {7,3} lattice in the Poincaré disk"`` with one figure, ``"paper_fig1"``: the
        {7,3} tessellation (7 rings, grey) and the l = 3 graph with its sites coloured by ring.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from hyperlattice.report.sections import fig1_section
    >>> with tempfile.TemporaryDirectory() as d:
    ...     s = fig1_section(Path(d))
    ...     files = sorted(p.name for p in Path(d).iterdir())
    >>> s.reference_line, [f.name for f in s.figures], files
    ('Reproduces: Fig. 1, Appendix A', ['paper_fig1'], ['fig_paper_fig1.png', 'fig_paper_fig1.svg'])
    """
    import matplotlib.pyplot as plt

    from ..plots.paper import plot_tessellation

    fig, ax = plt.subplots(figsize=(6.2, 5.4), layout="constrained")
    plot_tessellation(rings=3, background_rings=7, ax=ax)
    f = _save_figure(fig, out, "paper_fig1", f"{cite('Fig1')}: the {{7,3}} tessellation in the Poincaré disk (grey, "
                     "7 rings) and the ℓ = 3 graph (black) with its sites coloured by ring; edges drawn as geodesics.",
                     paper="Fig1")
    return Section("The {7,3} lattice in the Poincaré disk", ("Fig1", "AppGraph"), [], [], [f], anchor="lattice")


def _signed(value: float, spec: str) -> str:
    """``value`` by ``spec`` with a true minus for its sign (the exponent's hyphen stays): −2.50e-01."""
    text = format(value, spec)
    return "−" + text[1:] if text.startswith("-") else text


def open_question_text(trends: list[RelativeErrorTrend], worst_residual: float | None = None) -> list[str]:
    """Sentences on the paper's open question (App. ``AppSpec``), one per level, from the trends.

    ``worst_residual``, when given, adds the introductory sentence with the largest residual of
    the graph levels (the report gives it once the computed range reaches l = 10).

    Parameters
    ----------
    trends : list of RelativeErrorTrend
        The relative error ``(E_graph − E_cont)/|E_graph|`` of each level against l, from
        :func:`~hyperlattice.compare.levels.relative_error_trend`.
    worst_residual : float, optional
        Largest residual ‖Hψ − Eψ‖ of the graph eigenpairs; no introductory sentence when None.

    Returns
    -------
    list of str
        One paragraph per trend (the errors, a sign change, and whether the error saturates or
        decreases), preceded by the introduction when ``worst_residual`` is given.

    Examples
    --------
    >>> from hyperlattice.compare.levels import relative_error_trend
    >>> from hyperlattice.report.sections import open_question_text
    >>> trend = relative_error_trend([1, 2, 3], [-2.0, -2.636405, -2.787], [-1.5, -2.570293, -2.77],
    ...                              level="E0")
    >>> print(open_question_text([trend])[0])
    E₀: (E_graph − E_cont)/|E_graph| = −2.50e-01, −2.51e-02, −6.10e-03 for ℓ = 1–3. Its magnitude decreases monotonically over the computed range.
    >>> len(open_question_text([trend], worst_residual=1e-13))
    2
    """
    out = []
    for t in trends:
        parts = [f"{t.level[0]}{_SUB.get(t.level[1:], t.level[1:])}: (E_graph − E_cont)/|E_graph| = "
                 + ", ".join(_signed(v, "+.2e") for v in t.relative_error) + f" for ℓ = {t.rings[0]}–{t.rings[-1]}."]
        if t.sign_change is not None:
            a, b = t.sign_change
            move = "from below to above" if t.rising else "from above to below"
            grows = "grows monotonically" if t.rising else "grows monotonically in magnitude"
            parts.append(f"It changes sign between ℓ = {a} and {b} (the graph level moves {move} the continuum "
                         "level),")
            if t.saturates:
                d1, d2 = t.increments
                parts.append(f"then {grows} with shrinking increments ({_signed(d1, '.1e')}, {_signed(d2, '.1e')} "
                             "over the last rings): it saturates (Aitken estimate of the limit "
                             f"{_signed(t.aitken_limit, '.2e')}) instead of decreasing "
                             "to zero.")
            elif t.monotone:
                d1, d2 = t.increments
                parts.append(f"then {grows} without shrinking increments ({_signed(d1, '.1e')}, {_signed(d2, '.1e')} "
                             "over the last "
                             "rings): no limit can be estimated within the computed range.")
            else:
                parts.append("and does not settle into a monotone trend within the computed range.")
        elif t.magnitude_decreasing:
            parts.append("Its magnitude decreases monotonically over the computed range.")
        out.append(" ".join(parts))
    if worst_residual is not None:
        out.insert(0, f"The paper's open question ({cite('AppSpec')}): does the relative error between graph and "
                      "continuum keep decreasing as ℓ → ∞? The computed levels (largest residual "
                      f"‖Hψ − Eψ‖ = {worst_residual:.1e}) say:")
    return out


def spectrum_section(cache: Cache, max_rings: int, timings: dict,
                     progress: Callable[[str], None]) -> tuple[Section, list[dict]]:
    """``SuppTab1``/``Tab1`` energies, beside the paper, and the open question; also returns the records.

    For l = 1..max_rings: E0 and E1 of the graph (cached), of the continuum disk and of the asymptotic
    formulas; the same beside the paper's printed values with flags; and the relative error with the
    graph solver's residuals.

    Parameters
    ----------
    cache : Cache
        The result cache (:class:`~hyperlattice.cache.Cache`) for the expensive numbers.
    max_rings : int
        Largest number of rings l.
    timings : dict
        Filled in place with the solver time of each flake (see :func:`~hyperlattice.report.data.graph_levels`).
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    section : Section
        The section (anchor ``"spectrum"``) with the tables ``"paper_table4"`` (the paper's Table IV),
        ``"paper_table4_E0_printed"`` and ``"paper_table4_E1_printed"`` (printed beside computed, one level each) and
        ``"graph_vs_continuum"`` and the sentences on the open question.
    records : list of dict
        One dict per l: ``rings``, ``sites``, ``radius``, the six energies of ``SuppTab1``,
        ``method``, ``residual_max`` and ``m_E1``.

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> from hyperlattice.report.sections import spectrum_section
    >>> with tempfile.TemporaryDirectory() as d:
    ...     s, records = spectrum_section(Cache(d), 2, {}, lambda msg: None)
    >>> [t.name for t in s.tables], len(records)
    (['paper_table4', 'paper_table4_E0_printed', 'paper_table4_E1_printed', 'graph_vs_continuum'], 2)
    >>> round(records[1]["E0_graph"], 6), round(records[1]["E0_continuum"], 6)
    (-2.636405, -2.570293)
    """
    from ..compare.levels import relative_error_trend

    rows_out, records, notes = [], [], []
    for ell in range(1, max_rings + 1):
        progress(f"graph and continuum levels, l = {ell}/{max_rings}")
        g = data.graph_levels(cache, ell, timings)
        c = data.continuum_levels(ell)
        n = int(ring_sizes(7, 3, ell).sum())
        rec = {"rings": ell, "sites": n, "radius": c["radius"], "E0_graph": g["E0"], "E0_continuum": c["E0"],
               "E0_asymptotic": c["E0_asym"], "E1_graph": g["E1"], "E1_continuum": c["E1"],
               "E1_asymptotic": c["E1_asym"], "method": g["method"],
               "residual_max": max(g["residuals"]), "m_E1": g["m"][1]}
        records.append(rec)
        row = [ell, n, _fmt(c["radius"], 10)]
        for key in _LEVEL_KEYS:
            row.append(_fmt(rec[key], 12))
        rows_out.append(row)
        for key in _LEVEL_KEYS:
            pv = _printed(key, ell)
            if pv is not None:
                flag, note = pv.check(rec[key])
                if flag:
                    notes.append((ell, key, pv.printed, rec[key], flag, note))
    table = Table("paper_table4", ["rings", "sites", "radius", *_LEVEL_KEYS], rows_out,
                  f"{cite('SuppTab1')} (and the energy rows of {cite('Tab1')}): lowest levels of H = −A on the "
                  "ℓ-ring {7,3} graph, of H_cont = −3 − (3/4)h²Δ_g on the disk of radius L "
                  f"({cite('spec1', 'spec2')}), and the asymptotic formulas {cite('spec11', 'spec17')} "
                  f"({cite('eq19')}).", paper="SuppTab1")
    # side by side with the paper
    # side by side with the paper: one table per level (10 columns each, readable at 1400 px), the
    # flag column first after the ring number so that a disagreement is seen before the digits
    sides = []
    for level in ("E0", "E1"):
        keys = [k for k in _LEVEL_KEYS if k.startswith(level + "_")]
        side_rows = []
        for rec in records:
            ell = rec["rings"]
            if _printed("E0_graph", ell) is None:
                continue
            row = [ell]
            checks = [(rec[key], paper_value(key, ell)) for key in keys]
            row += [",".join(k.split("_", 1)[1] for k, (v, pv) in zip(keys, checks) if pv.check(v)[0])]
            for v, pv in checks:
                row += [_fmt(v, 6), pv.printed, pv.check(v)[0]]
            side_rows.append(row)
        cols = ["rings", "flagged"]
        for key in keys:
            cols += [key, f"{key}_paper", f"{key}_flag"]
        sides.append(Table(f"paper_table4_{level}_printed", cols, side_rows,
                           f"{level} of {cite('SuppTab1')}: computed values (6 decimals) beside the paper's printed "
                           "ones; ≠ marks a difference larger than half a unit of the last printed digit, and "
                           "“flagged” lists the columns of the row that carry one."))
    rings = [r["rings"] for r in records]
    trends = [relative_error_trend(rings, [r[f"{k}_graph"] for r in records], [r[f"{k}_continuum"] for r in records],
                                   level=k) for k in ("E0", "E1")]
    rel_rows = []
    for i, rec in enumerate(records):
        rel_rows.append([rec["rings"], rec["sites"], f"{trends[0].relative_error[i]:.3e}",
                         f"{trends[1].relative_error[i]:.3e}", rec["method"], f"{rec['residual_max']:.1e}"])
    rel = Table("graph_vs_continuum", ["rings", "sites", "rel_err_E0", "rel_err_E1", "graph_method",
                                       "max_residual"], rel_rows,
                "Relative difference (E_graph − E_continuum)/|E_graph| and the residual ‖Hψ − Eψ‖ of the "
                "graph eigenpairs.")
    text = [f"E₁ of the graph lies in the angular-momentum sectors m = ±1 for every ℓ (computed: m = "
            f"{sorted({r['m_E1'] for r in records})}), the ground state in m = 0, as for the continuum "
            "levels (n, m) = (1, 0) and (1, ±1)."]
    for ell, key, printed, value, flag, note in notes:
        text.append(f"Flagged {column_label(key)} at ℓ = {ell}: printed {printed}, computed {value:.6f} ({note.rstrip('.')}).")
    worst = max(r["residual_max"] for r in records) if records[-1]["rings"] >= 10 else None
    text += open_question_text(trends, worst)
    return Section("Ground state and first excited state: graph vs continuum",
                   ("Tab1", "SuppTab1", "spec1", "spec2", "spec11", "spec17", "eq19"), text, [table, *sides, rel],
                   anchor="spectrum"), records


def fig2_section(records: list[dict], out: Path, progress: Callable[[str], None]) -> Section:
    """``Fig2``: levels against rings, and the partition functions of its inset (l = 4).

    Parameters
    ----------
    records : list of dict
        The level records of :func:`spectrum_section` (one per l).
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    Section
        The section (anchor ``"levels-vs-rings"``) with the figure ``"paper_fig3"`` (levels against l;
        the partition function over negative energies for l = 4, graph against disk) and the table
        ``"partition_function_l4"``.

    Raises
    ------
    ValueError
        If ``out`` is not a path.

    Examples
    --------
    The section takes several seconds (the l = 4 partition function); the argument check is
    immediate:

    >>> from hyperlattice.report.sections import fig2_section
    >>> fig2_section([], 42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt
    import numpy as np

    from ..compare.levels import continuum_levels_below, graph_levels_below, partition_functions
    from ..plots.paper import plot_levels

    progress("Fig2: partition functions for l = 4")
    beta = np.linspace(0.05, 6.0, 120)
    z = partition_functions(graph_levels_below(ring_lattice(7, 3, 4)), continuum_levels_below(7, 3, rings=4), beta)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12.0, 4.8), layout="constrained",
                                  gridspec_kw={"width_ratios": [1.6, 1.0]})
    plot_levels(records, ax=ax)
    ax.set_title(r"(a) lowest levels vs rings ($\ell = 1$ is off scale)", fontsize=11)
    z.plot(ax=ax2)
    ax2.set_title(r"(b) $\ell=4$: $Z=\sum_n\Theta(-E_n)\,e^{-\beta E_n}$", fontsize=11)
    ax2.xaxis.label.set_size(12)
    ax2.yaxis.label.set_size(12)
    ax2.tick_params(labelsize=10)
    ax2.legend(fontsize=10)
    fig_obj = _save_figure(fig, out, "paper_fig3", f"{cite('Fig2')}: (a) E₀ (blue) and E₁ (orange) of the graph "
                           "(filled) and the continuum disk (open) vs number of rings, with the asymptotes of "
                           f"{cite('eq19')}; (b, the paper's inset) partition function over negative energies for "
                           "ℓ = 4, graph vs disk.", paper="Fig2")
    # ten significant digits: Z carries the levels' error bound (about 5e-13) times beta as its
    # relative error (~3e-12 at beta = 6); eight decimals of Z ~ 4e7 printed sixteen digits, whose
    # last ones moved with the eigensolver's rounding (BLAS kernel, CPU)
    zt = Table("partition_function_l4", ["beta", "Z_graph", "Z_continuum"],
               [[_fmt(b, 4), f"{a:.10g}", f"{c:.10g}"]
                for b, a, c in zip(z.beta[::10], z.z_graph[::10], z.z_continuum[::10])],
               f"Z(β) for ℓ = 4 over {z.graph_states} negative graph levels and {z.continuum_states} negative "
               "continuum states (degenerate ±m counted twice); "
               + (f"the flake's {z.graph_zero_modes} zero modes (|E| within the eigensolver's error bound "
                  f"{z.graph_tolerance:.0e}, so their computed sign is rounding noise) are left out."
                  if z.graph_zero_modes else "the graph has no zero mode."))
    return Section("Spectrum vs number of rings; partition function", ("Fig2",), [], [zt], [fig_obj],
                   anchor="levels-vs-rings")


def formal_operator_figure(angles, hs: tuple = (None, 0.15, 0.05)):
    """``FigSh`` as the report draws it: one panel per h and one legend for all, below the panels.

    Each panel of :func:`hyperlattice.plots.scaling.plot_formal_operator` carries its own legend,
    which covers the data near the boundary; here the panels share one legend in a row of its own
    under the axes, so no marker is hidden.

    Parameters
    ----------
    angles : FrameAngles
        The flake's frame angles (:func:`hyperlattice.compare.scaling.frame_angles`).
    hs : tuple of float or None
        The values of h, one panel each; None is the lattice's own h (default: it, 0.15, 0.05).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not yet saved), one axes per h and one figure legend.

    Raises
    ------
    ValueError
        If ``angles`` is not a :class:`~hyperlattice.compare.scaling.FrameAngles`, ``hs`` is empty
        or longer than 6, or an h is not accepted by ``plot_formal_operator``.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.report.sections import formal_operator_figure
    >>> fig = formal_operator_figure(hl.frame_angles(hl.ring_lattice(7, 3, 3)))
    >>> len(fig.axes), [ax.get_legend() for ax in fig.axes], len(fig.legends)
    (3, [None, None, None], 1)
    >>> plt.close(fig)
    """
    import matplotlib.pyplot as plt

    from ..compare.scaling import FrameAngles
    from ..plots.scaling import plot_formal_operator

    if not isinstance(angles, FrameAngles):
        raise ValueError(f"angles must be the FrameAngles of a flake (hyperlattice.frame_angles), got "
                         f"{type(angles).__name__}.")
    if not hs or len(hs) > 6:
        raise ValueError(f"hs must name 1 to 6 values of h (None for the lattice's own), got {len(hs)}.")
    fig, axes = plt.subplots(1, len(hs), figsize=(13.5, 4.6), layout="constrained", squeeze=False)
    axes = axes[0]
    for h, ax in zip(hs, axes):
        plot_formal_operator(angles, h=angles.h if h is None else h, ax=ax)
        ax.get_legend().remove()
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=11, frameon=False)
    return fig


def scaling_section(out: Path, progress: Callable[[str], None]) -> Section:
    """``FigS1``, ``FigScos3delta``, ``FigSh`` and the fit of b (``sum4``).

    Parameters
    ----------
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    Section
        The section (anchor ``"scaling"``) with three figures (``"paper_fig7"``: the counting function of
        the l = 4 lattice with its fitted line; ``"paper_fig5"``: cos 3δ against radius for l = 5;
        ``"paper_fig6"``: the formal operator A_h at three h) and the table ``"counting_fit"`` (slope and b
        beside the paper's b).

    Raises
    ------
    ValueError
        If ``out`` is not a path.

    Examples
    --------
    The section takes several seconds; the argument check is immediate:

    >>> from hyperlattice.report.sections import scaling_section
    >>> scaling_section(42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt

    from ..compare.scaling import frame_angles
    from ..compare.sums import fit_counting
    from ..plots.scaling import plot_counting, plot_frame_angles

    progress("FigS1, FigScos3delta, FigSh")
    figs = []
    lat4 = ring_lattice(7, 3, 4)
    fit = fit_counting(lat4)
    fig, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
    plot_counting(lat4, ax=ax)
    figs.append(_save_figure(fig, out, "paper_fig7", f"{cite('FigS1')}: counting function N(r) of the ℓ = 4 lattice "
                             f"against ρ = (1 + r²)/(1 − r²) with the fitted line sρ + b ({cite('sum4')}).",
                             paper="FigS1"))
    angles = frame_angles(ring_lattice(7, 3, 5))
    fig, ax = plt.subplots(figsize=(8.0, 4.8), layout="constrained")
    plot_frame_angles(angles, ax=ax, distance=True)
    figs.append(_save_figure(fig, out, "paper_fig5", f"{cite('FigScos3delta')}: cos 3δᵢ, δᵢ = χᵢ − φᵢ, "
                             "averaged over the sites of equal radius for ℓ = 5 (847 sites), against the "
                             "hyperbolic distance from the centre (the paper plots against the radius rᵢ, shown "
                             "on the top axis: the outer rings, crowded below r = 1 there, are spread out here); "
                             "red bars span the values at radii where r ↦ δ is not unique.",
                             paper="FigScos3delta"))
    figs.append(_save_figure(formal_operator_figure(angles), out, "paper_fig6",
                             f"{cite('FigSh')}: A_h f − 3f for f = cos[π d(r, 0)] "
                             f"({cite('adj34')}) with the quadratic ({cite('adj35')}) and cubic ({cite('adj36')}) "
                             f"approximations, at the lattice h = {angles.h:.6f} and two smaller h; one legend for "
                             "the three panels, below them.", paper="FigSh"))
    pv = paper_value("b_counting", 4)
    flag, note = pv.check(fit.intercept)
    t = Table("counting_fit", ["rings", "slope", "slope_expected", "b", "b_paper", "b_flag"],
              [[4, _fmt(fit.slope, 4), _fmt(fit.expected_slope, 1), _fmt(fit.intercept, 4), pv.printed, flag]],
              "Fit of N(r) = sρ + b over the distinct site radii of the ℓ = 4 lattice.")
    text = [f"Flagged b: {note}"] if flag else []
    return Section("Sums as integrals and the formal operator A_h",
                   ("FigScos3delta", "FigSh", "FigS1", "sum4", "adj34", "adj35", "adj36"), text, [t], figs,
                   anchor="scaling")


def green_section(cache: Cache, max_rings: int, out: Path, progress: Callable[[str], None]) -> Section:
    """``Fig3`` (l = 6 and l = 3 rows at both omega) and the rel-L2 / collapse table for l = 3..8 (or more).

    The l = 6 and l = 3 comparisons are computed once and serve both the figure and the table.

    Parameters
    ----------
    cache : Cache
        The result cache (:class:`~hyperlattice.cache.Cache`) for the expensive numbers.
    max_rings : int
        Largest number of rings of the report; the table covers l = 3 .. max(8, min(max_rings, 10)).
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    Section
        The section (anchor ``"green"``) with the figures ``"paper_fig4_upper"`` (ω = −2.95) and ``"paper_fig4_lower"``
        (ω = −2.5 + 0.1i), source site 10 on ring 2, and the table ``"green_distance"`` (relative L²
        distance, collapse numbers, m terms and tail estimate per l and ω).

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    Examples
    --------
    The section takes several seconds; the argument check is immediate:

    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> from hyperlattice.report.sections import green_section
    >>> with tempfile.TemporaryDirectory() as d:
    ...     green_section(Cache(d), 8, 42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt

    from ..compare.green import compare_green
    from ..plots.green import plot_fig3_row

    source = 10  # a site on ring 2, as in the paper's ``Fig3``
    omegas = (-2.95, complex(-2.5, 0.1))
    figs = []
    shown = {}  # (rings, omega) -> GreenComparison drawn in the figure
    for tag, omega in zip(("a", "b"), omegas):
        progress(f"Fig3: Green functions at omega = {omega}")
        fig, axes = plt.subplots(2, 3, figsize=(13.0, 8.2), layout="constrained",
                                 gridspec_kw={"width_ratios": [1, 1, 1.4]})
        for row, ell in zip(axes, (6, 3)):
            lat = ring_lattice(7, 3, ell)
            shown[ell, omega] = compare_green(lat, omega, source)
            plot_fig3_row(lat, omega, source, axes=row, comparison=shown[ell, omega])
            row[0].set_ylabel(fr"$\ell = {ell}$", fontsize=13)
        part = "" if isinstance(omega, float) else " (real part)"
        figs.append(_save_figure(fig, out, f"paper_fig4_{'upper' if tag == 'a' else 'lower'}", f"{cite('Fig3')} ({'upper' if tag == 'a' else 'lower'} "
                                 f"panel): ω = {_omega(omega)}{part}, source site {source} on ring 2; top row ℓ = 6, "
                                 "bottom row ℓ = 3 (the paper's insets). Left: graph G_ij, middle: continuum "
                                 f"prediction of {cite('eq21')} (dot size ∝ |F|^(1/2), blue > 0, red < 0); right: "
                                 "mean ± standard deviation versus hyperbolic distance, graph and continuum.",
                                 paper="Fig3", panel=f"{'upper' if tag == 'a' else 'lower'} panels"))
    rows = []
    for ell in range(3, max(8, min(max_rings, 10)) + 1):
        progress(f"Fig3: graph vs continuum Green function, l = {ell}")
        for omega in omegas:
            v = data.green_row(cache, ell, omega, source, comparison=shown.get((ell, omega)))
            rows.append([ell, str(omega), f"{v['rel_l2']:.4f}", f"{v['collapse_graph']:.4f}",
                         f"{v['collapse_continuum']:.4f}", v["terms"], f"{v['tail']:.1e}"])
    table = Table("green_distance", ["rings", "omega", "rel_l2", "collapse_graph", "collapse_continuum",
                                 "m_terms", "tail_estimate"], rows,
                  f"Relative L² distance between the graph column G_ij(ω) and the right-hand side of {cite('eq21')} "
                  f"over all sites but the source (site {source}, ring 2); collapse = spread within distance bins "
                  "relative to the mean (0 for a function of hyperbolic distance alone); m terms and "
                  f"tail estimate describe the truncated sum of {cite('green36')}.")
    text = [f"The paper shows the agreement of {cite('Fig3')} graphically; the relative L² distances quantify it. "
            "The collapse number of the graph data measures how far G_ij is from a function of d(z_i, z_j) alone "
            "(emergent conformal symmetry for large ℓ)."]
    return Section("Green functions: graph vs continuum and emergent conformal symmetry",
                   ("Fig3", "eq20", "eq21", "eq23", "path8", "green33", "green36", "green38"), text, [table], figs,
                   anchor="green")


def magnetic_section(out: Path, progress: Callable[[str], None], cache: Cache | None = None) -> Section:
    """Beyond the paper: the hyperbolic Hofstadter butterfly and a graph-vs-continuum table with flux.

    The ℓ = 5 butterfly (401 flux values in [0, 1/2], mirrored to [1/2, 1]) drawn as a density of levels,
    with the continuum Dirichlet levels overlaid and magnified in an inset, the error map
    of the two lowest levels over (f, l) for l = 3..7, and a short table of the levels at
    f = 0, 0.1, 0.2, 0.3 (small and fast).

    Parameters
    ----------
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.
    cache : Cache, optional
        Result cache for the butterfly and the comparison; computed afresh when None.

    Returns
    -------
    Section
        The section (anchor ``"magnetic"``, part ``"beyond"``) with the figures ``"butterfly"`` and
        ``"magnetic_error"`` and the table ``"magnetic_levels"``.

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    Examples
    --------
    The section takes several seconds without a warm cache; the argument check is immediate:

    >>> from hyperlattice.report.sections import magnetic_section
    >>> magnetic_section(42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt
    import numpy as np

    from ..compare.magnetic import magnetic_comparison
    from ..graph.butterfly import butterfly
    from ..plots.magnetic import butterfly_figure

    progress("beyond the paper: magnetic flux")
    from ..graph.butterfly import Butterfly

    # 401 fluxes in [0, 1/2] (every 1/800, 801 columns once mirrored: about one per pixel of the
    # printed figure) on the 847-site l = 5 flake: 13 s on the loaded 2-core machine, cached. l = 6
    # (2,240 sites) costs 7x more per flux and l = 7 about 100x.
    key = {"p": 7, "q": 3, "rings": BUTTERFLY_RINGS, "fluxes": BUTTERFLY_FLUXES, "flux_max": 0.5}
    make = lambda: butterfly(ring_lattice(7, 3, BUTTERFLY_RINGS), np.linspace(0.0, 0.5, BUTTERFLY_FLUXES))  # noqa: E731
    bf = cache.get("butterfly", key, make, expect=Butterfly) if cache is not None else make()
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(9.5, 5.6), layout="constrained", width_ratios=(3, 1))
    # 240 energy rows: about 2 pixels each at the printed size, several levels per row in a band
    butterfly_figure(bf, continuum=True, max_flux=0.3, points=31, levels=4, ax=ax, density=True, energy_bins=240,
                     mirror=True, zoom_ax=zoom)
    figs = [_save_figure(fig, out, "butterfly", f"Hyperbolic Hofstadter butterfly of the ℓ = {bf.rings} {{7,3}} "
                         f"flake ({bf.sites} sites): all levels at {2 * bf.fluxes.size - 1} flux values f ∈ [0, 1] "
                         "(flux quanta per heptagon, sector by sector; computed for f ≤ 1/2 and mirrored, since "
                         "E(1 − f) = E(f) on a flake: f → −f is complex conjugation and f → f + 1 a gauge "
                         "transformation), drawn as a density of levels (240 energy rows; grey linear in the "
                         "number of levels per pixel, black from the 98th percentile). (a) The bands are dark; "
                         "the gaps between them are white or crossed only by thin lines, the edge states of the "
                         "flake (its outer ring holds more than half of its sites). Red: the continuum Dirichlet "
                         f"levels of the same disk (magnetic_levels, {cite('spec2')} with B = 2πf/A₇) that are among "
                         "the 4 lowest at some f ≤ 0.3, each drawn as one level (n, m) through the flux, so that "
                         "levels cross where they cross rather than turning a corner (the steep m = −1 level "
                         "is drawn until it leaves the 20 lowest levels of the disk). (b) The band bottom magnified: the lowest levels of the flake (dots) and the "
                         "same continuum levels.")]
    # l = 3..7: the 1e-3 contour first appears at l = 6 (docs/magnetic.md has l = 3..12)
    from ..compare.magnetic import MagneticComparison

    fluxes = [0.0, 0.1, 0.2, 0.3]
    make_cmp = lambda: magnetic_comparison(7, 3, rings=MAGNETIC_RINGS, fluxes=fluxes, levels=2)  # noqa: E731
    cmp = (cache.get("magnetic_comparison", {"p": 7, "q": 3, "rings": list(MAGNETIC_RINGS), "fluxes": fluxes,
                                             "levels": 2}, make_cmp, expect=MagneticComparison)
           if cache is not None else make_cmp())
    fig, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
    cmp.plot(ax=ax)
    lim = cmp.agreement_limit(1e-3)
    reached = [int(r) for r, f in zip(cmp.rings, lim) if not math.isnan(f)]
    where = (f"the white line is the 10⁻³ contour: the error stays below it for ℓ ≥ {reached[0]} at small f "
             f"and for no f at ℓ ≤ {reached[0] - 1}" if reached and reached[0] > int(cmp.rings[0]) else
             "the white line is the 10⁻³ contour" if reached else
             f"the error stays above 10⁻³ everywhere in ℓ = {int(cmp.rings[0])}–{int(cmp.rings[-1])}, so no "
             "10⁻³ contour appears")
    figs.append(_save_figure(fig, out, "magnetic_error", "log₁₀ of the worst relative error of the two lowest "
                             f"levels, graph vs continuum, over the (f, ℓ) plane (ℓ = {int(cmp.rings[0])}–"
                             f"{int(cmp.rings[-1])}, f = 0–0.3); {where}. The full ℓ = 3–12 grid is in "
                             "docs/magnetic.md (`hyperlattice fluxmap --rings 3-12 --fluxes 13`)."))
    cols = cmp.columns()
    rows = [[int(cols["rings"][i]), _fmt(float(cols["flux"][i]), 2), f"({cols['n'][i]},{cols['m'][i]})",
             _fmt(float(cols["E_graph"][i]), 8), _fmt(float(cols["E_continuum"][i]), 8),
             f"{cols['rel_error'][i]:.2e}", f"{cols['lB_over_d0'][i]:.3g}", f"{cols['lB_over_R'][i]:.3g}"]
            for i in range(len(cols["flux"]))]
    table = Table("magnetic_levels", ["rings", "flux", "(n,m)", "E_graph", "E_continuum", "rel_error",
                                      "lB_over_d0", "lB_over_R"], rows,
                  "Two lowest levels of the Peierls Hamiltonian (flux f per heptagon, symmetric gauge) and the "
                  f"continuum Dirichlet levels of the same (n, m) on the disk of {cite('eq12')}; l_B = 1/√B, d₀ the "
                  "edge length, R = artanh L the disk radius (paper's metric).")
    text = ["Not in the paper (its conclusion names artificial gauge fields as the next step): a uniform field "
            "of f flux quanta per p-gon, f > 0 counterclockwise. " + cmp.statement()]
    return Section("Magnetic flux: Hofstadter butterfly and Landau levels", ("eq12", "spec2"), text, [table], figs,
                   anchor="magnetic", part="beyond")


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
