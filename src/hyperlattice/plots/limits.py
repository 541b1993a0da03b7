"""Figures of the infinite-lattice analysis (:mod:`hyperlattice.compare.limits`): the band-bottom
fit with its residuals, the band bottom against l, the plateau of the paper map's error and the
two dictionaries' errors."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.limits import BandBottom, BandBottomFit, DictionaryComparison, PlateauAnalysis

__all__ = ["plot_band_fit", "plot_band_residuals", "plot_band_bottom", "plot_plateau", "plot_dictionaries",
           "limits_figure"]


def _minus(value, spec: str) -> str:
    """``value`` by ``spec`` with a true minus sign (−2.941155, not -2.941155) for a label."""
    return format(float(value), spec).replace("-", "−")


def _sub(level) -> str:
    """A level index as a subscript digit: 0 -> '₀' (E₀ on the figure, not E0)."""
    return "".join(chr(0x2080 + int(d)) for d in str(int(level)))


def plot_band_fit(fit: BandBottomFit, ax: Axes | None = None) -> Axes:
    """One band-bottom fit: the flake levels, the fit and its residuals; returns the axes.

    ``E(l) - E_b`` of the fitted flakes (points) and of the fit (line, continued four rings beyond the
    last flake) on a log scale, with the residuals (fit - data) on a twin axis.

    Parameters
    ----------
    fit : BandBottomFit
        One fit of E0 or E1 against the ring number, from
        :func:`~hyperlattice.compare.limits.fit_band_bottom`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The main axes (log y, ``E - E_b`` in units of t against l); the residuals are on a twin axes
        of the same figure.

    See Also
    --------
    plot_band_residuals : the residuals of all fit models together.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.compare.limits import fit_band_bottom, reference_levels
    >>> from hyperlattice.plots.limits import plot_band_fit
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> ax = plot_band_fit(fit_band_bottom(rings[-6:], E0[-6:], p=7, q=3))
    >>> [line.get_label() for line in ax.lines], len(ax.figure.axes)
    (['E₀ of the flakes', 'disk fit'], 2)
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    ell = np.asarray(fit.rings, dtype=float)
    grid = np.linspace(ell[0], ell[-1] + 4.0, 200)
    ax.semilogy(ell, fit.energies - fit.band_bottom, "o", label=f"E{_sub(fit.level)} of the flakes")
    ax.semilogy(grid, fit.predict(grid) - fit.band_bottom, "-", label=f"{fit.model} fit")
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel(f"E{_sub(fit.level)} − E_b  (E_b = {fit.band_bottom:.7f})".replace("= -", "= −"))
    twin = ax.twinx()
    twin.plot(ell, fit.residuals, "x", color="C3", label="residual")
    twin.axhline(0.0, color="C3", linewidth=0.5)
    twin.set_ylabel("fit − data", color="C3")
    ax.legend(fontsize="small", loc="upper right")
    return ax


def plot_band_residuals(band: BandBottom, ax: Axes | None = None) -> Axes:
    """Residuals of the band-bottom fits on the central window of flakes; returns the axes.

    Residuals (fit - data) of the disk-model fits of E0 and E1 over the last six flakes (the central
    variant and its E1 partner) and of the rational fits over the same flakes.

    Parameters
    ----------
    band : BandBottom
        The band-bottom estimate with its fit variants, from
        :func:`~hyperlattice.compare.limits.band_bottom`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with four residual curves (E0/E1 times disk/rational model) against l, in units
        of t, and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.limits import plot_band_residuals
    >>> ax = plot_band_residuals(hl.band_bottom(7, 3, schur_window=None))
    >>> [t.get_text() for t in ax.get_legend().get_texts()]
    ['E₀, disk model', 'E₀, rational model', 'E₁, disk model', 'E₁, rational model']
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    central = next(v for v in band.variants if v["central"])
    styles = {("disk", 0): ("o-", "C0"), ("disk", 1): ("s-", "C1"), ("rational", 0): ("o:", "C0"),
              ("rational", 1): ("s:", "C1")}
    for v in band.variants:
        if v["rings"] == central["rings"]:
            marker, color = styles[(v["model"], v["level"])]
            ax.plot(v["fit_rings"], v["residuals"], marker, color=color, mfc="none" if v["model"] == "rational" else None,
                    label=f"E{_sub(v['level'])}, {v['model']} model")
    ax.axhline(0.0, color="0.5", linewidth=0.6)
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel("fit − flake level")
    ax.legend(fontsize="x-small")
    return ax


def plot_band_bottom(band: BandBottom, ax: Axes | None = None) -> Axes:
    r"""The band bottom against l with its bounds and the maps' band edges; returns the axes.

    The extrapolated value with its error bar, the rigorous interval, both maps' edges, and the
    central fit of E0 continued in l (to three times the largest flake).

    Parameters
    ----------
    band : BandBottom
        The band-bottom estimate, from :func:`~hyperlattice.compare.limits.band_bottom`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (E / t against l) with the continued fit and its error band, the estimate
        :math:`-\rho` as a shaded band, the paper's and the improved :math:`E_\infty`, and the
        rigorous upper (and, when known, lower) bound, with a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.limits import plot_band_bottom
    >>> ax = plot_band_bottom(hl.band_bottom(7, 3, schur_window=None))
    >>> ax.get_ylabel(), len(ax.get_legend().get_texts())
    ('energy E / t', 5)
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    ell = np.asarray(band.rings, dtype=float)
    grid = np.arange(ell[0], 3.0 * ell[-1] + 1.0)      # the disk model lives on integer l (site counts)
    value, err = band.predict(grid)
    ax.plot(grid, value, "-", color="C0", label="E₀ fit (disk model) continued")
    ax.fill_between(grid, value - err, value + err, color="C0", alpha=0.2)
    ax.plot(ell, band.predict(ell)[0], "o", color="C0", markersize=3)
    ax.axhspan(band.estimate - band.error, band.estimate + band.error, color="C2", alpha=0.3,
               label=rf"$-\rho$ = {_minus(band.estimate, '.6f')} ± {band.error:.1e}")
    ax.axhline(band.paper_edge, color="C1", linestyle="--",
               label=rf"paper $E_\infty$ = {_minus(band.paper_edge, '.6f')}")
    ax.axhline(band.improved_edge, color="C4", linestyle=":",
               label=rf"improved $E_\infty$ = {_minus(band.improved_edge, '.6f')}")
    ax.axhline(band.upper, color="0.4", linewidth=0.8, label=rf"rigorous: $-\rho \leq$ {_minus(band.upper, '.5f')}")
    if np.isfinite(band.lower):
        ax.axhline(band.lower, color="0.4", linewidth=0.8, linestyle="-.",
                   label=rf"rigorous: $-\rho \geq$ {_minus(band.lower, '.5f')}")
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel("energy E / t")
    low = band.lower if np.isfinite(band.lower) else band.estimate
    ax.set_ylim(min(low, band.paper_edge) - 0.002, band.upper + 0.006)
    ax.legend(fontsize="x-small")
    return ax


def plot_plateau(plateau: PlateauAnalysis, ax: Axes | None = None) -> Axes:
    r"""The paper map's relative error of E0 and E1 against l with its predicted limit; returns the axes.

    The limit is :math:`(-\rho - E_\infty)/\rho`, drawn with its error band, together with the E0 fit
    continued in l.

    Parameters
    ----------
    plateau : PlateauAnalysis
        The plateau of the paper map's error, from :func:`~hyperlattice.compare.limits.plateau_analysis`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the relative errors ``(E_graph - E_cont)/|E_graph|`` of E0 and E1, the
        predicted limit band and the continued E0 curve, with a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.limits import plot_plateau
    >>> ax = plot_plateau(hl.plateau_analysis(hl.band_bottom(7, 3, schur_window=None)))
    >>> ax.get_ylabel()
    '(E_graph − E_cont)/|E_graph|, paper map'
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    ell = np.asarray(plateau.rings, dtype=float)
    ax.plot(ell, plateau.relative_E0, "o-", label="E₀")
    ax.plot(ell, plateau.relative_E1, "s-", label="E₁")
    ax.axhspan(plateau.limit - plateau.limit_error, plateau.limit + plateau.limit_error, color="C2", alpha=0.3,
               label=rf"$(-\rho - E_\infty)/\rho$ = {plateau.limit:.2e}")
    ax.plot(plateau.curve_rings, plateau.curve, "-", color="C0", linewidth=0.8,
            label=rf"E₀ fit continued (peak {plateau.peak_value:.2e} at $\ell$ = {plateau.peak_rings:.0f})")
    ax.set_ylim(-2e-4, 1e-3)
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel("(E_graph − E_cont)/|E_graph|, paper map")
    ax.legend(fontsize="small")
    return ax


def plot_dictionaries(comparison: DictionaryComparison, ax: Axes | None = None) -> Axes:
    """Relative errors of E0 and E1 with both dictionaries against l; returns the axes.

    ``|relative error|`` of E0 and E1 with the paper's and the improved map against l (log scale),
    and the improved map's l -> infinity limit.

    Parameters
    ----------
    comparison : DictionaryComparison
        The errors of both maps, from :func:`~hyperlattice.compare.limits.compare_dictionaries`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log y) with four curves and, when finite, the improved map's limit as a dotted line.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.limits import reference_levels
    >>> from hyperlattice.plots.limits import plot_dictionaries
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> ax = plot_dictionaries(hl.compare_dictionaries(rings[-2:], E0[-2:], E1[-2:], p=7, q=3))
    >>> ax.get_yscale(), [line.get_label() for line in ax.lines][:2]
    ('log', ['E₀, paper map', 'E₁, paper map'])
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    ell = np.asarray(comparison.rings, dtype=float)
    ax.semilogy(ell, np.abs(comparison.paper_E0), "o-", color="C0", label="E₀, paper map")
    ax.semilogy(ell, np.abs(comparison.paper_E1), "s-", color="C1", label="E₁, paper map")
    ax.semilogy(ell, np.abs(comparison.improved_E0), "o--", color="C0", mfc="none", label="E₀, improved map")
    ax.semilogy(ell, np.abs(comparison.improved_E1), "s--", color="C1", mfc="none", label="E₁, improved map")
    if np.isfinite(comparison.improved_limit):
        ax.axhline(abs(comparison.improved_limit), color="C2", linestyle=":",
                   label=rf"improved, $\ell \to \infty$: |{comparison.improved_limit:.1e}|")
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel("|E_graph − E_cont| / |E_graph|")
    ax.legend(fontsize="x-small")
    return ax


def limits_figure(band: BandBottom, plateau: PlateauAnalysis, comparison: DictionaryComparison, path=None):
    """The four infinite-lattice panels in one figure; returns the figure.

    A 2 x 2 grid, (a) band bottom, (b) the fits' residuals, (c) plateau, (d) dictionaries (a row of
    four was unreadable once shrunk to a page width); saved to ``path`` if given.

    Parameters
    ----------
    band : BandBottom
        From :func:`~hyperlattice.compare.limits.band_bottom`; panels (a) and (b).
    plateau : PlateauAnalysis
        From :func:`~hyperlattice.compare.limits.plateau_analysis`; panel (c).
    comparison : DictionaryComparison
        From :func:`~hyperlattice.compare.limits.compare_dictionaries`; panel (d).
    path : str or path-like, optional
        Where to save the figure (format from the suffix); not saved when None (the default).

    Returns
    -------
    matplotlib.figure.Figure
        The 12 x 8.6 inch figure with the four panels, labelled (a) to (d).

    See Also
    --------
    plot_band_bottom, plot_band_residuals, plot_plateau, plot_dictionaries : the single panels.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.limits import reference_levels
    >>> from hyperlattice.plots.limits import limits_figure
    >>> band = hl.band_bottom(7, 3, schur_window=None)
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> dc = hl.compare_dictionaries(rings[-2:], E0[-2:], E1[-2:], p=7, q=3)
    >>> fig = limits_figure(band, hl.plateau_analysis(band), dc)
    >>> [ax.texts[0].get_text() for ax in fig.axes]
    ['(a)', '(b)', '(c)', '(d)']
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12.0, 8.6), layout="constrained")
    axes = axes.ravel()
    plot_band_bottom(band, ax=axes[0])
    plot_band_residuals(band, ax=axes[1])
    plot_plateau(plateau, ax=axes[2])
    plot_dictionaries(comparison, ax=axes[3])
    for letter, ax in zip("abcd", axes):
        ax.text(-0.1, 1.02, f"({letter})", transform=ax.transAxes, fontsize=12, fontweight="bold")
    if path is not None:
        fig.savefig(path)
    return fig


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
