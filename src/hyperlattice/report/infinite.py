"""Report section "Beyond the paper: the infinite lattice": densities of states of periodic
clusters, flake interiors, the Abelian DOS and the exact moments, band edges with error bars, and
the continuum (Plancherel) density at the band bottom. Small and fast (about 4 s)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from .writers import Section, Table, save_figure

__all__ = ["infinite_section", "REPORT_SETTINGS", "band_interval_sentence"]

#: what the report computes (the docs page runs larger settings: docs/dos.md)
REPORT_SETTINGS = dict(clusters=("klein", "PSL(2,29)", "PSL(2,71)"), rings=(6, 8), moments=256, resolution=40,
                       vectors=6, seed=0, quantile=1e-3, abelian_samples=100, quantile_moments=512)


def _f(x: float, digits: int = 4) -> str:
    return "" if x is None or not math.isfinite(x) else f"{x:.{digits}f}"


def infinite_section(out: Path, progress: Callable[[str], None]) -> Section:
    """Beyond the paper: the DOS figure, the convergence table and the band edges.

    The densities of states of periodic clusters, flake interiors, the Abelian DOS, the exact
    closed-walk moments and the continuum (:func:`~hyperlattice.compare.dos.dos_comparison` with the
    report's settings), with the proven band-bottom interval and quantile energies.

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
        The section ``"The infinite lattice: densities of states and band edges"`` (anchor
        ``"infinite"``, part ``"beyond"``) with the figure ``"dos_infinite"`` and two tables, the
        convergence table and ``"band_edges"``.

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    See Also
    --------
    band_interval_sentence : compares its interval with the band-bottom section's.

    Examples
    --------
    The section takes tens of seconds; the argument check is immediate:

    >>> from hyperlattice.report.infinite import infinite_section
    >>> infinite_section(42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt

    from ..compare.dos import dos_comparison
    from ..plots.dos import comparison_figure

    progress("beyond the paper: the infinite lattice")
    cmp = dos_comparison(7, 3, **REPORT_SETTINGS, progress=lambda m: progress(f"  infinite lattice: {m}"))
    fig = comparison_figure(cmp)
    figs = [save_figure(fig, out, "dos_infinite",
                        "{7,3}: densities of states per site of H = -A by KPM (Jackson kernel, "
                        f"{cmp.moments} moments, {REPORT_SETTINGS['vectors']} random vectors). (a) The largest "
                        "periodic cluster (uniform state at E = -3 left out), the largest flake interior, the "
                        "Abelian DOS of the Klein quartic, the exact infinite-lattice DOS from closed-walk counts "
                        f"(M = {cmp.resolution}), the continuum Plancherel density and the proven band-bottom "
                        "interval (grey). (b) L1 distance to the exact DOS at the same resolution against size. "
                        "(c) Integrated DOS at the band bottom, largest cluster against the continuum.")]
    plt.close("all")
    rows = [[r["label"], r["kind"], r["sites"], r["exact_moments"], f"{r['distance']:.2g}",
             "" if not math.isfinite(r["distance_err"]) else f"{r['distance_err']:.1g}",
             _f(r["bottom"]), _f(r["bottom_err"]), _f(r["top"]), _f(r["top_err"])] for r in cmp.table()]
    conv = Table("dos_routes", ["route", "kind", "sites", "exact_moments", "L1_distance", "L1_err",
                                "E_bottom", "E_bottom_err", "E_top", "E_top_err"], rows,
                 f"Each route against the exact infinite-lattice DOS at {cmp.resolution} moments (L1 distance, "
                 "jackknife error over the random vectors); exact moments: moments proven equal to the lattice's "
                 "(clusters: the systole; flakes: 2 d_b + 2). E bottom / E top: the energies below / above which "
                 f"a fraction {cmp.quantile:g} of the states lie, error = kernel width and random vectors.")
    ratio = cmp.continuum_ratio()[0]
    edge_rows = [["band bottom -rho, proven interval", "", "", _f(-cmp.rho_upper), _f(-cmp.rho_lower),
                  "rigorous: lower end from the isoperimetric bound, upper end from the exact closed walks"],
                 ["continuum band bottom, paper's map (E = -q + q h^2/4)", _f(cmp.continuum_bottom["paper"]), "", "",
                  "", "leading order in h"],
                 ["continuum band bottom, improved map (E = -q P_{-1/2}(cosh 2 d0))",
                  _f(cmp.continuum_bottom["improved"]), "", "", "", "isotropic star summed"]]
    for nu, e, err, ec, r in zip(cmp.quantiles, cmp.quantile_lattice, cmp.quantile_lattice_err,
                                 cmp.quantile_continuum, ratio):
        edge_rows.append([f"E(nu = {nu:g}): largest cluster vs continuum (paper's map)", _f(e), _f(err), "", "",
                          f"continuum {_f(ec)}, N_cont/nu = {r:.2f}"])
    edges = Table("band_edges", ["quantity", "E", "E_error", "interval_lower", "interval_upper", "note"], edge_rows,
                  "Band edges of the infinite {7,3} lattice: the proven interval for the band bottom (its two ends "
                  "in the interval columns), the continuum band bottoms, and the quantile energies E(nu) of the "
                  f"largest cluster ({cmp.bottom_label}) with their error bars, against the continuum's "
                  "(N_cont/nu = 1: the continuum counts the same states below E(nu)).")
    text = ["Not in the paper: the DOS of the infinite lattice, from periodic {7,3} clusters (compact surfaces of "
            "genus 3 to 2131, built from triangle-group quotients), the interiors of flakes (the outer half of the "
            "rings left out of the trace, since boundary sites have the wrong moments from n = 2 on), the Abelian "
            "Bloch DOS and the exact closed-walk moments. " + cmp.statement()]
    if cmp.notes:
        text.append("Left out: " + " ".join(cmp.notes))
    return Section("The infinite lattice: densities of states and band edges", (), text, [conv, edges], figs,
                   anchor="infinite", part="beyond")


def band_interval_sentence(band_bottom: Section, infinite: Section) -> str:
    """One sentence on why two sections prove different intervals for −ρ of {7,3}.

    The band-bottom section (:func:`~hyperlattice.report.limits.limits_section`) and the infinite-lattice
    section (:func:`infinite_section`) bound −ρ by different methods; the sentence gives both intervals,
    from the numbers in their tables (``band_bottom`` and ``band_edges``), and their intersection.

    Parameters
    ----------
    band_bottom : Section
        A section with a table ``"band_bottom"`` whose row starting with ``"{7,3}"`` has the columns
        ``rigorous_lower``, ``rigorous_upper``, ``rings_fitted`` (``"a..b"``) and ``schur``.
    infinite : Section
        A section with a table ``"band_edges"`` whose first row has the columns ``interval_lower``
        and ``interval_upper``.

    Returns
    -------
    str
        The sentence, appended to the infinite-lattice section by
        :func:`~hyperlattice.report.reproduce`.

    Examples
    --------
    Two hand-made sections with the tables it reads:

    >>> from hyperlattice.report.infinite import band_interval_sentence
    >>> from hyperlattice.report.writers import Section, Table
    >>> band = Section("Band bottom", tables=[Table("band_bottom",
    ...     ["lattice", "rigorous_lower", "rigorous_upper", "rings_fitted", "schur"],
    ...     [["{7,3}", -2.9655, -2.9413, "3..14", "W = 8"]])])
    >>> edges = Section("Infinite lattice", tables=[Table("band_edges",
    ...     ["quantity", "interval_lower", "interval_upper"], [["band bottom", -2.9665, -2.9400]])])
    >>> print(band_interval_sentence(band, edges))
    Two proven intervals for the band bottom −ρ of {7,3} appear in this report, [-2.96550, -2.94130] in the band-bottom section and [-2.9665, -2.9400] here; ... Both hold, so −ρ lies in their intersection [-2.96550, -2.94130].
    """
    band = next(t for t in band_bottom.tables if t.name == "band_bottom")
    row = dict(zip(band.columns, next(r for r in band.rows if r[0] == "{7,3}")))
    edges = next(t for t in infinite.tables if t.name == "band_edges")
    walks = dict(zip(edges.columns, edges.rows[0]))
    a_lo, a_hi = float(row["rigorous_lower"]), float(row["rigorous_upper"])
    b_lo, b_hi = float(walks["interval_lower"]), float(walks["interval_upper"])
    top = row["rings_fitted"].split("..")[-1]
    schur = row["schur"] or "no window"
    lo, hi = max(a_lo, b_lo), min(a_hi, b_hi)
    return (f"Two proven intervals for the band bottom −ρ of {{7,3}} appear in this report, [{a_lo:.5f}, {a_hi:.5f}] "
            f"in the band-bottom section and [{b_lo:.4f}, {b_hi:.4f}] here; they differ because they come from "
            f"different methods: there a Schur test ({schur}) gives the lower end and the ℓ = {top} flake, a "
            "subgraph of the lattice, the upper end; here the isoperimetric bound gives the lower end and exact "
            "closed-walk counts the upper end. Both hold, so −ρ lies in their intersection "
            f"[{lo:.5f}, {hi:.5f}].")


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
