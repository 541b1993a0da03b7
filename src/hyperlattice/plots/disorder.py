"""Figures of the disorder ensembles: averaged DOS, <r> against W, Green function against distance,
and the SCBA comparison. Each takes an optional ``ax`` and returns it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..paper_labels import cite

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.disorder import DisorderEnsemble, DisorderGreen, RScan, SCBAComparison

__all__ = ["plot_dos", "plot_r_scan", "plot_green_distance", "plot_scba_comparison"]


def _axes(ax, size=(5.5, 4.0)):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def plot_dos(ens: DisorderEnsemble, ax: Axes | None = None, **kwargs) -> Axes:
    """Disorder-averaged density of states per site (stairs); returns the axes.

    Parameters
    ----------
    ens : DisorderEnsemble
        The ensemble, from :func:`~hyperlattice.compare.disorder.disorder_ensemble`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.5 x 4 inch figure when None (the default).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.stairs`; ``label`` defaults to ``"W = <strength>"``.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the averaged histogram (DOS per site against E / t), a legend and a title naming
        the lattice, the disorder model and the number of realizations.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.disorder import plot_dos
    >>> ens = hl.disorder_ensemble(hl.ring_lattice(7, 3, 3), 2.0, realizations=3, seed=1)
    >>> ax = plot_dos(ens)
    >>> ax.get_title(), ax.get_legend().get_texts()[0].get_text()
    ('{7,3} ℓ = 3, box, 3 realizations', 'W = 2')
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.stairs(ens.dos, ens.dos_edges, label=kwargs.pop("label", f"W = {ens.W:g}"), **kwargs)
    ax.set_xlabel("E / t")
    ax.set_ylabel("DOS per site")
    ax.set_title(f"{{{ens.p},{ens.q}}} ℓ = {ens.rings}, {ens.model}, {ens.realizations} realizations", fontsize=9)
    ax.legend(fontsize=8)
    return ax


def plot_r_scan(scan: RScan, ax: Axes | None = None, **kwargs) -> Axes:
    r"""<r> against W (log axis) with the GOE and Poisson values; returns the axes.

    Parameters
    ----------
    scan : RScan
        The mean spacing ratio against the disorder strength, from
        :func:`~hyperlattice.compare.disorder.r_scan`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.5 x 4 inch figure when None (the default).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.errorbar`; ``label`` defaults to
        ``"ℓ = <rings> (<sites> sites)"``.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with :math:`\langle r\rangle` and its error bars against W / t (log scale when all
        W > 0) and the GOE and Poisson reference lines.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.disorder import plot_r_scan
    >>> scan = hl.r_scan(hl.ring_lattice(7, 3, 3), [0.5, 4.0], realizations=2, window=None)
    >>> ax = plot_r_scan(scan)
    >>> ax.get_xscale(), [t.get_text() for t in ax.get_legend().get_texts()]
    ('log', ['GOE 0.5307', 'Poisson 0.3863', 'ℓ = 3 (112 sites)'])
    >>> plt.close("all")
    """
    from ..compare.disorder import GOE_R, POISSON_R

    ax = _axes(ax)
    w = np.asarray(scan.W, float)
    ax.errorbar(w, scan.r_mean, yerr=scan.r_err, marker="o", ms=4, capsize=2,
                label=kwargs.pop("label", f"ℓ = {scan.rings} ({scan.sites} sites)"), **kwargs)
    ax.axhline(GOE_R, color="C3", ls="--", lw=1, label=f"GOE {GOE_R}")
    ax.axhline(POISSON_R, color="C2", ls=":", lw=1, label=f"Poisson {POISSON_R:.4f}")
    if np.all(w > 0):
        ax.set_xscale("log")
    # room above GOE and below Poisson: the reference lines must not sit on the frame
    lo = min(POISSON_R, float(np.min(np.asarray(scan.r_mean) - np.asarray(scan.r_err))))
    hi = max(GOE_R, float(np.max(np.asarray(scan.r_mean) + np.asarray(scan.r_err))))
    ax.set_ylim(lo - 0.08 * (hi - lo), hi + 0.08 * (hi - lo))
    ax.set_xlabel("W / t")
    ax.set_ylabel(r"$\langle r\rangle$")
    ax.legend(fontsize=8)
    return ax


def plot_green_distance(ens: DisorderGreen, ax: Axes | None = None, *, bins: int = 12, clean: bool = True) -> Axes:
    """The averaged Green function against hyperbolic distance; returns the axes.

    ``|<G_ij>|`` (and ``|G_ij(W=0)|`` if ``clean``) against the hyperbolic distance (binned means),
    source excluded.

    Parameters
    ----------
    ens : DisorderGreen
        The ensemble of Green-function columns, from
        :func:`~hyperlattice.compare.disorder.green_ensemble`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.5 x 4 inch figure when None (the default).
    bins : int, optional
        Number of equal distance bins from 0 to the largest distance (default 12).
    clean : bool, optional
        Also draw the clean (W = 0) column, dashed (default True).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log y) with the bin means of the absolute values against the distance, and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.disorder import green_ensemble
    >>> from hyperlattice.plots.disorder import plot_green_distance
    >>> ge = green_ensemble(hl.ring_lattice(7, 3, 3), -2.9 + 0.2j, 1.0, realizations=4)
    >>> ax = plot_green_distance(ge, bins=6)
    >>> ax.get_yscale(), [line.get_label() for line in ax.lines]
    ('log', ['W = 0', 'W = 1'])
    >>> plt.close("all")
    """
    ax = _axes(ax)
    keep = np.arange(ens.distance.size) != ens.source
    d = ens.distance[keep]
    edges = np.linspace(0.0, d.max() * (1 + 1e-12), bins + 1)
    idx = np.digitize(d, edges) - 1
    centres = 0.5 * (edges[1:] + edges[:-1])
    curves = [(ens.clean[keep], "W = 0", "--")] if clean else []
    for vals, label, style in curves + [(ens.mean[keep], f"W = {ens.W:g}", "-")]:
        a = np.abs(vals)
        m = np.array([a[idx == k].mean() if np.any(idx == k) else np.nan for k in range(bins)])
        ax.semilogy(centres, m, style, marker="o", ms=3, label=label)
    ax.set_xlabel("hyperbolic distance d(z_i, z_j)")
    ax.set_ylabel(r"$|\langle G_{ij}(\omega)\rangle|$")
    ax.legend(fontsize=8)
    return ax


def plot_scba_comparison(cmp: SCBAComparison, ax: Axes | None = None) -> Axes:
    """Distance of the ensemble average from the clean column and the two SCBA predictions; returns the axes.

    Relative L2 distances against W on log-log axes: the clean Green function, the graph SCBA, the
    continuum SCBA (the continuum Green function at the shifted frequency), the statistical error of
    the average, and, as a dashed line, the floor set by the clean graph against the continuum.

    Parameters
    ----------
    cmp : SCBAComparison
        The comparison, from :func:`~hyperlattice.compare.disorder.compare_scba`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.5 x 4 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the four curves, the floor and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.disorder import plot_scba_comparison
    >>> cmp = hl.compare_scba(hl.ring_lattice(7, 3, 3), -2.9 + 0.2j, [1.0, 2.0], realizations=4)
    >>> ax = plot_scba_comparison(cmp)
    >>> [line.get_label() for line in ax.lines][:2]
    ['clean G₀(ω)', 'graph SCBA']
    >>> plt.close("all")
    """
    ax = _axes(ax)
    w = np.asarray(cmp.W, float)
    ax.loglog(w, cmp.rel_clean, "o-", label="clean G₀(ω)")
    ax.loglog(w, cmp.rel_graph_scba, "s-", label="graph SCBA")
    ax.loglog(w, cmp.rel_continuum_scba, "^-", label=f"continuum SCBA ({cite('eq21')} at shifted $\\omega$)")
    ax.loglog(w, cmp.rel_noise, ":", color="0.5", label="statistical error")
    ax.axhline(cmp.continuum_floor, color="0.6", lw=0.8, ls="--", label=f"clean graph vs {cite('eq21')}")
    ax.set_xlabel("W / t")
    ax.set_ylabel("relative L² distance from the ensemble average")
    ax.legend(fontsize=7)
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
