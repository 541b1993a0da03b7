"""Figures of densities of states: one KPM result (the ``dos`` command) and the comparison of
periodic clusters, flake interiors, the Abelian DOS, the exact moments and the continuum."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.dos import DosComparison
    from ..graph.kpm import KPMDos

__all__ = ["dos_figure", "comparison_axes", "convergence_axes", "bottom_axes", "comparison_figure"]


def dos_figure(result: KPMDos, *, path=None, ax: Axes | None = None, continuum: bool = True) -> Axes:
    """The density of states of one KPM result with the continuum density; returns the axes.

    The density of states of one :class:`~hyperlattice.graph.kpm.KPMDos` with its error band, and
    the continuum (Plancherel) density near the band bottom when {p,q} is known; saved to ``path``.

    Parameters
    ----------
    result : KPMDos
        A kernel-polynomial density of states, from :func:`~hyperlattice.graph.kpm.kpm_dos` or
        :func:`~hyperlattice.graph.kpm.bulk_dos`. A ``DosComparison`` is drawn by
        :func:`comparison_figure`.
    path : str or path-like, optional
        Where to save the figure (120 dpi); the figure is then closed. Not saved when None.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 6.4 x 4.4 inch figure when None.
    continuum : bool, optional
        Overlay the continuum density (paper's map) from E = -q to -q/2 (default True).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the density per site against E / t, its error band, the dashed continuum
        density, a legend and a title naming the moments and random vectors.

    See Also
    --------
    hyperlattice.plots.basic.plot_kpm_dos : the density alone.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.dos import dos_figure
    >>> ax = dos_figure(hl.kpm_dos(hl.ring_lattice(7, 3, 3), 32, vectors=2, seed=1))
    >>> ax.get_title()
    '{7,3} flake, 3 rings: 32 moments, 2 vector(s)'
    >>> [t.get_text() for t in ax.get_legend().get_texts()]
    ['{7,3} flake, 3 rings', "continuum (Plancherel, paper's map)"]
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    ax = new_axes(ax, size=(6.4, 4.4))
    result.plot(ax=ax)
    if continuum and result.p is not None and result.q is not None:
        from ..compare.dos import continuum_dos

        e = np.linspace(-result.q, -result.q + 0.5 * result.q, 600)
        ax.plot(e, continuum_dos(e, result.p, result.q), color="k", lw=1.0, ls="--",
                label="continuum (Plancherel, paper's map)")
    ax.set_title(f"{result.label}: {result.moments} moments, {result.vectors} vector(s)", fontsize=9)
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    if path is not None:
        ax.figure.savefig(path, dpi=120)
        plt.close(ax.figure)
    return ax


def comparison_axes(cmp: DosComparison, ax: Axes | None = None, *, window: tuple[float, float] | None = None) -> Axes:
    """The densities of the comparison at full resolution; returns the axes.

    The largest cluster, the largest flake interior and the Abelian DOS (those present), with the exact
    reference (closed walks), the continuum density and the proven band-bottom interval (grey).

    Parameters
    ----------
    cmp : DosComparison
        The comparison of densities, from :func:`~hyperlattice.compare.dos.dos_comparison`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    window : tuple of float, optional
        Energy range (E_min, E_max) in units of t; the whole grid when None.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the densities (states per site per unit energy) against E / t and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> from hyperlattice.plots.dos import comparison_axes
    >>> ax = comparison_axes(cmp)
    >>> ax.get_title(), len(ax.lines)
    ('{7,3}: densities of states, 32 moments', 3)
    >>> plt.close("all")
    """
    from ..compare.dos import continuum_dos

    ax = new_axes(ax, size=(7.0, 4.6))
    e = cmp.energies
    cl = [i for i, k in enumerate(cmp.kinds) if k == "cluster"]
    fl = [i for i, k in enumerate(cmp.kinds) if k == "flake"]
    if cl:
        ax.plot(e, cmp.density[cl[-1]], color="tab:blue", lw=0.8, label=cmp.labels[cl[-1]])
    if fl:
        ax.plot(e, cmp.density[fl[-1]], color="tab:orange", lw=0.8, ls="-.", label=cmp.labels[fl[-1]])
    for i, k in enumerate(cmp.kinds):
        if k == "abelian":
            ax.plot(e, cmp.density[i], color="tab:green", lw=0.8, label=cmp.labels[i])
    ax.plot(e, cmp.reference, color="k", lw=1.6, label=f"exact moments (closed walks), M = {cmp.resolution}")
    ec = np.linspace(cmp.continuum_bottom["paper"] - 0.01, -cmp.q + 0.35 * cmp.q, 400)
    ax.plot(ec, continuum_dos(ec, cmp.p, cmp.q), color="tab:red", lw=1.2, ls="--",
            label="continuum (Plancherel density via the dictionary)")
    ax.axvspan(-cmp.rho_upper, -cmp.rho_lower, color="0.85", zorder=0, label="proven band-bottom interval")
    if window is not None:
        ax.set_xlim(*window)
    ax.set_ylim(0, 1.15 * float(np.nanmax(cmp.reference)) * 2.5)
    ax.set_xlabel("E / t")
    ax.set_ylabel("states per site per unit energy")
    ax.set_title(f"{{{cmp.p},{cmp.q}}}: densities of states, {cmp.moments} moments", fontsize=9)
    ax.legend(fontsize=6.5, loc="upper left")
    return ax


def convergence_axes(cmp: DosComparison, ax: Axes | None = None) -> Axes:
    """Every curve at the resolution of the exact moments: the L1 distance to the exact DOS against size.

    Parameters
    ----------
    cmp : DosComparison
        The comparison of densities, from :func:`~hyperlattice.compare.dos.dos_comparison`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log-log) with the distance and its error bar against the number of sites: periodic
        clusters (N sites), flake interiors (traced sites) and Abelian DOS (unit-cell sites).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> from hyperlattice.plots.dos import convergence_axes
    >>> ax = convergence_axes(cmp)
    >>> ax.get_xscale(), ax.get_ylabel()
    ('log', 'L1 distance to the exact DOS (M = 8)')
    >>> plt.close("all")
    """
    ax = new_axes(ax, size=(5.0, 4.2))
    for kind, marker, color in (("cluster", "o", "tab:blue"), ("flake", "s", "tab:orange"),
                                ("abelian", "^", "tab:green")):
        idx = [i for i, k in enumerate(cmp.kinds) if k == kind]
        if not idx:
            continue
        n = cmp.sites[idx] if kind != "flake" else np.array([_traced(cmp.labels[i]) for i in idx])
        err = np.nan_to_num(cmp.distance_err[idx])
        label = {"cluster": "periodic clusters (N sites)", "flake": "flake interiors (traced sites)",
                 "abelian": "Abelian DOS (unit-cell sites)"}[kind]
        ax.errorbar(n, cmp.distance[idx], yerr=err, marker=marker, color=color, ls="-" if kind != "abelian" else "",
                    capsize=2, label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("sites")
    ax.set_ylabel(f"L1 distance to the exact DOS (M = {cmp.resolution})")
    ax.set_title("convergence to the infinite lattice", fontsize=9)
    ax.legend(fontsize=7)
    return ax


def _traced(label: str) -> int:
    # "flake interior, 8 rings (315 of 15,435 sites)" -> 315
    try:
        return int(label.split("(")[1].split(" of")[0].replace(",", ""))
    except (IndexError, ValueError):
        return 1


def bottom_axes(cmp: DosComparison, ax: Axes | None = None) -> Axes:
    """Integrated DOS N(E) near the band bottom: the largest cluster against the continuum (both maps).

    Parameters
    ----------
    cmp : DosComparison
        The comparison of densities, from :func:`~hyperlattice.compare.dos.dos_comparison`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log y) with N(E) of the largest cluster and its error band (when computed), the
        continuum N(E) with the paper's and the improved map, and the proven band-bottom interval.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> from hyperlattice.plots.dos import bottom_axes
    >>> ax = bottom_axes(cmp)
    >>> ax.get_title(), ax.get_yscale()
    ('band bottom: integrated DOS', 'log')
    >>> plt.close("all")
    """
    from ..compare.dos import continuum_integrated_dos

    ax = new_axes(ax, size=(5.0, 4.2))
    e = cmp.bottom_energies
    if np.any(np.isfinite(cmp.bottom_integrated)):
        n = cmp.bottom_integrated
        ax.plot(e, n, color="tab:blue", lw=1.2, label=cmp.bottom_label)
        ax.fill_between(e, n - cmp.bottom_integrated_err, n + cmp.bottom_integrated_err, color="tab:blue", alpha=0.3)
    ax.plot(e, continuum_integrated_dos(e, cmp.p, cmp.q), color="tab:red", ls="--", label="continuum, paper's map")
    ax.plot(e, continuum_integrated_dos(e, cmp.p, cmp.q, dictionary_name="improved"), color="tab:purple", ls=":",
            label="continuum, improved map")
    ax.axvspan(-cmp.rho_upper, -cmp.rho_lower, color="0.85", zorder=0, label="proven band-bottom interval")
    ax.set_yscale("log")
    ax.set_ylim(1e-5, 0.3)
    ax.set_xlim(e[0], -cmp.q + 0.4 * cmp.q)
    ax.set_xlabel("E / t")
    ax.set_ylabel("states per site below E")
    ax.set_title("band bottom: integrated DOS", fontsize=9)
    ax.legend(fontsize=6.5, loc="lower right")
    return ax


def comparison_figure(cmp: DosComparison, *, path=None):
    """The three panels of the density comparison in one figure; returns the figure.

    (a) the densities (full width, top), (b) the convergence with size and (c) the band bottom
    against the continuum (bottom row): a row of three was unreadable at page width.

    Parameters
    ----------
    cmp : DosComparison
        The comparison of densities, from :func:`~hyperlattice.compare.dos.dos_comparison`.
    path : str or path-like, optional
        Where to save the figure (110 dpi); not saved when None.

    Returns
    -------
    matplotlib.figure.Figure
        The 11 x 8.4 inch figure with three axes labelled (a) to (c).

    See Also
    --------
    comparison_axes, convergence_axes, bottom_axes : the single panels.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> from hyperlattice.plots.dos import comparison_figure
    >>> fig = comparison_figure(cmp)
    >>> [ax.texts[0].get_text() for ax in fig.axes]
    ['(a)', '(b)', '(c)']
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(11.0, 8.4), layout="constrained")
    grid = fig.add_gridspec(2, 2, height_ratios=[1.1, 1.0])
    axes = [fig.add_subplot(grid[0, :]), fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])]
    comparison_axes(cmp, ax=axes[0])
    convergence_axes(cmp, ax=axes[1])
    bottom_axes(cmp, ax=axes[2])
    for letter, ax in zip("abc", axes):
        ax.text(-0.06 if letter == "a" else -0.12, 1.02, f"({letter})", transform=ax.transAxes, fontsize=12,
                fontweight="bold")
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
