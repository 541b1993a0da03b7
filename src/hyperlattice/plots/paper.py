"""Figures ``Fig1`` (tessellation and ring graph) and ``Fig2`` (lowest levels vs rings, Z(beta)), and the
plots of the graph-vs-continuum level results of :mod:`hyperlattice.compare.levels`."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from . import new_axes
from .. import geometry
from ..graph.lattice import Lattice, ring_lattice
from ..paper_labels import cite

if TYPE_CHECKING:
    from ..compare.levels import LevelComparison, LevelCount, RelativeErrorTrend

__all__ = ["plot_tessellation", "plot_levels", "plot_partition", "plot_relative_error", "plot_level_counting", "plot_level_comparison"]


def _axes(ax, size=(5.0, 5.0)):
    return new_axes(ax, size)


def _geodesic_segments(lattice: Lattice, samples: int = 12) -> np.ndarray:
    """Edges drawn as hyperbolic geodesics (circular arcs orthogonal to the unit circle)."""
    t = np.linspace(0.0, 1.0, samples)
    a = lattice.z[lattice.edges[:, 0]][:, None]
    b = lattice.z[lattice.edges[:, 1]][:, None]
    pts = geometry.geodesic_point(a, b, t[None, :])
    return np.stack([pts.real, pts.imag], axis=-1)


def plot_tessellation(rings: int = 3, background_rings: int = 7, p: int = 7, q: int = 3, ax: Axes | None = None) -> Axes:
    r"""``Fig1``: the {p,q} tessellation in the Poincaré disk (grey) with the ``rings``-ring graph
    highlighted, sites coloured by ring.

    Edges are drawn as hyperbolic geodesics (arcs orthogonal to the unit circle).

    Parameters
    ----------
    rings : int, optional
        Number of rings l of the highlighted graph (default 3).
    background_rings : int, optional
        Number of rings of the grey background tessellation (default 7).
    p, q : int, optional
        The {p,q} lattice (default {7,3}).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (equal aspect, Re z and Im z in the unit disk) with the background edges, the graph,
        its sites, the unit circle and a colour bar of the ring index (a second axes of the figure).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.plots.paper import plot_tessellation
    >>> ax = plot_tessellation(rings=2, background_rings=3)
    >>> print(ax.get_title())
    $\{7,3\}$ tessellation; graph with $\ell=2$ rings (35 sites)
    >>> len(ax.figure.axes)
    2
    >>> plt.close("all")
    """
    ax = _axes(ax)
    bg = ring_lattice(p, q, background_rings)
    ax.add_collection(LineCollection(_geodesic_segments(bg), colors="0.7", linewidths=0.4))
    lat = ring_lattice(p, q, rings)
    ax.add_collection(LineCollection(_geodesic_segments(lat), colors="k", linewidths=1.1))
    sc = ax.scatter(lat.z.real, lat.z.imag, c=lat.ring, cmap="viridis", s=14, zorder=3)
    ax.add_patch(plt.Circle((0, 0), 1.0, fill=False, color="k", lw=1.0))
    cb = ax.figure.colorbar(sc, ax=ax, shrink=0.7, ticks=range(1, rings + 1))
    cb.set_label("ring", fontsize=11)
    ax.set_aspect("equal")
    ax.set_xlim(-1.03, 1.03)
    ax.set_ylim(-1.03, 1.03)
    ax.set_xlabel("Re z", fontsize=11)
    ax.set_ylabel("Im z", fontsize=11)
    ax.set_title(fr"$\{{{p},{q}\}}$ tessellation; graph with $\ell={rings}$ rings ({lat.sites} sites)",
                 fontsize=11)
    return ax


def plot_levels(table: list[dict], ax: Axes | None = None, *, lnphi_form: bool = True) -> Axes:
    r"""``Fig2`` main panel: E0 and E1 against the number of rings, graph (filled) and continuum
    (open), with the asymptotic formulas of ``eq19`` as lines.

    ``table`` rows need keys rings, E0_graph, E1_graph, E0_continuum, E1_continuum and the
    asymptotes are recomputed for a continuous l from ``hyperlattice.continuum.spectrum``.

    Parameters
    ----------
    table : list of dict
        One dict per flake with the keys ``rings``, ``E0_graph``, ``E1_graph``, ``E0_continuum`` and
        ``E1_continuum`` (energies in units of t), e.g. the records of
        :func:`~hyperlattice.report.sections.spectrum_section`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    lnphi_form : bool, optional
        Draw the asymptotes of ``eq19`` (default True).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the graph levels (filled circles), the continuum levels (open circles), the two
        asymptotes and the band edge :math:`E_\infty = -3 + \frac34 h^2` (dotted), with a legend.

    Raises
    ------
    ValueError
        If ``table`` is not a list of dicts with the five keys.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.plots.paper import plot_levels
    >>> table = [{"rings": 2, "E0_graph": -2.6364, "E1_graph": -2.2833, "E0_continuum": -2.5703,
    ...            "E1_continuum": -2.0845},
    ...          {"rings": 3, "E0_graph": -2.787, "E1_graph": -2.627, "E0_continuum": -2.770,
    ...            "E1_continuum": -2.578}]
    >>> ax = plot_levels(table)
    >>> len(ax.lines)
    7
    >>> plot_levels([{"rings": 2}])
    Traceback (most recent call last):
        ...
    ValueError: table must be a list of dicts with keys rings, E0_graph, E1_graph, E0_continuum, E1_continuum.
    >>> plt.close("all")
    """
    from ..continuum.spectrum import asymptotic_energies

    keys = ("rings", "E0_graph", "E1_graph", "E0_continuum", "E1_continuum")
    if not isinstance(table, (list, tuple)) or not all(isinstance(r, dict) and all(k in r for k in keys)
                                                        for r in table):
        raise ValueError(f"table must be a list of dicts with keys {', '.join(keys)}.")
    ax = _axes(ax, (6.4, 4.6))
    rings = np.array([r["rings"] for r in table])
    for key, color, label in (("E0", "C0", "$E_0$"), ("E1", "C1", "$E_1$")):
        ax.plot(rings, [r[f"{key}_graph"] for r in table], "o", color=color, ms=6, label=f"{label} graph")
        ax.plot(rings, [r[f"{key}_continuum"] for r in table], "o", mfc="none", mec=color, ms=10,
                mew=1.4, label=f"{label} continuum")
    ell = np.linspace(max(1.5, rings.min()), rings.max() + 0.5, 200)
    asym = [asymptotic_energies(7, 3, rings=float(x)) if lnphi_form else None for x in ell]
    ax.plot(ell, [a["E0"] for a in asym], "-", color="C0", lw=1.2, label=cite("eq19") + r", $c_0=\ln 2$")
    ax.plot(ell, [a["E1"] for a in asym], "-", color="C1", lw=1.2, label=cite("eq19") + r", $c_1=\ln 2-1$")
    ax.axhline(asym[0]["E_inf"], color="0.4", ls=":", lw=1.0, label=r"$E_\infty=-3+\frac{3}{4}h^2$")
    lo = min(min(r["E0_graph"] for r in table), asym[0]["E_inf"]) - 0.02
    ax.set_ylim(lo, -2.45)
    ax.set_xlabel(r"number of rings $\ell$", fontsize=12)
    ax.set_ylabel("energy (units of t)", fontsize=12)
    ax.legend(fontsize=8.5, ncol=2, loc="upper right")
    return ax


def plot_partition(beta: np.ndarray, z_graph: np.ndarray, z_cont: np.ndarray, e0: float, ax: Axes | None = None) -> Axes:
    r"""``Fig2`` inset: ln Z(beta) over negative energies, graph vs disk, and the asymptote -beta E0.

    Parameters
    ----------
    beta : array_like of float
        Inverse temperatures β (in units of 1/t), shape (B,).
    z_graph, z_cont : array_like of float
        Partition functions over the negative graph and continuum levels, shape (B,) each.
    e0 : float
        The ground-state energy E0 (units of t) of the asymptote :math:`\ln Z \approx -\beta E_0`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with ln Z of graph (solid), disk (dashed) and the asymptote (dotted), and a legend.

    Raises
    ------
    ValueError
        If the arrays are not real or their shapes differ from that of ``beta``.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> from hyperlattice.plots.paper import plot_partition
    >>> beta = np.array([0.5, 1.0, 2.0])
    >>> ax = plot_partition(beta, np.exp(2.6 * beta), np.exp(2.5 * beta), -2.64)
    >>> [line.get_label() for line in ax.lines][:2]
    ['graph', 'disk']
    >>> plt.close("all")
    """
    from .. import _validate

    beta = _validate.real_array("beta", beta, ndim=1)
    z_graph = _validate.real_array("z_graph", z_graph, shape=beta.shape)
    z_cont = _validate.real_array("z_cont", z_cont, shape=beta.shape)
    e0 = _validate.real("e0", e0)
    ax = _axes(ax, (3.2, 2.4))
    ax.plot(beta, np.log(z_graph), "-", color="C0", lw=1.6, label="graph")
    ax.plot(beta, np.log(z_cont), "--", color="C3", lw=1.6, label="disk")
    ax.plot(beta, -beta * e0, ":", color="k", lw=1.0, label=r"$-\beta E_0$")
    ax.set_xlabel(r"$\beta$", fontsize=9)
    ax.set_ylabel(r"$\ln Z$", fontsize=9)
    ax.tick_params(labelsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_relative_error(trend: RelativeErrorTrend, ax: Axes | None = None) -> Axes:
    r"""Signed relative error :math:`(E_{\rm graph}-E_{\rm cont})/|E_{\rm graph}|` against l; returns the axes.

    From a :class:`~hyperlattice.compare.levels.RelativeErrorTrend`, with its last sign change and,
    when it saturates, the Aitken limit as a dotted line.

    Parameters
    ----------
    trend : RelativeErrorTrend
        From :func:`~hyperlattice.compare.levels.relative_error_trend`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (symmetric-log y, linear within 1e-4 of zero) with the error against l, the shaded
        last sign change and the Aitken limit when present, and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.compare.levels import relative_error_trend
    >>> from hyperlattice.plots.paper import plot_relative_error
    >>> trend = relative_error_trend([1, 2, 3], [-2.0, -2.6364, -2.787], [-1.5, -2.5703, -2.77])
    >>> ax = plot_relative_error(trend)
    >>> ax.get_yscale(), ax.lines[0].get_label()
    ('symlog', 'E0')
    >>> plt.close("all")
    """
    ax = _axes(ax, (6.0, 4.2))
    ax.plot(trend.rings, trend.relative_error, "o-", color="C0", ms=5, lw=1.0, label=trend.level)
    ax.axhline(0.0, color="0.7", lw=0.8)
    if trend.sign_change is not None:
        ax.axvspan(*trend.sign_change, color="0.9", lw=0, label="last sign change")
    if trend.saturates:
        ax.axhline(trend.aitken_limit, color="C3", ls=":", lw=1.0, label="Aitken limit")
    ax.set_yscale("symlog", linthresh=1e-4)
    ax.set_xlabel(r"number of rings $\ell$")
    ax.set_ylabel(r"$(E_{\rm graph}-E_{\rm cont})/|E_{\rm graph}|$")
    ax.legend(fontsize=8)
    return ax


def plot_level_counting(count: LevelCount, ax: Axes | None = None, *, label: str | None = None, **kwargs) -> Axes:
    r"""Counting function :math:`\mathcal N(E)` (states up to E) as a staircase; returns the axes.

    Parameters
    ----------
    count : LevelCount
        Levels below a cutoff with their degeneracies, from
        :func:`~hyperlattice.compare.levels.graph_levels_below` or
        :func:`~hyperlattice.compare.levels.continuum_levels_below`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    label : str, optional
        Legend label; ``count.side`` (``"graph"`` or ``"continuum"``) when None.
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.step`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the staircase from 0 to ``count.states`` at the cutoff, against E / t.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import graph_levels_below
    >>> from hyperlattice.plots.paper import plot_level_counting
    >>> below = graph_levels_below(hl.ring_lattice(7, 3, 2))
    >>> ax = plot_level_counting(below)
    >>> ax.lines[0].get_label(), int(ax.lines[0].get_ydata()[-1])
    ('graph', 16)
    >>> plt.close("all")
    """
    ax = _axes(ax, (5.2, 3.8))
    e = np.concatenate([[count.energies[0] if count.energies.size else count.cutoff], count.energies,
                        [count.cutoff]])
    n = np.concatenate([[0], np.cumsum(count.degeneracy), [count.states]])
    ax.step(e, n, where="post", label=label or count.side, **kwargs)
    ax.set_xlabel("energy E / t")
    ax.set_ylabel(r"states below E, $\mathcal{N}(E)$")
    ax.legend(fontsize=8)
    return ax


def plot_level_comparison(comparison: LevelComparison, ax: Axes | None = None) -> Axes:
    """Graph (filled) and continuum (open) levels against the level index; returns the axes.

    Parameters
    ----------
    comparison : LevelComparison
        Graph and continuum levels side by side, from
        :func:`~hyperlattice.compare.levels.levels_side_by_side`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the energies (units of t) against the index (a ±m pair counts twice), labelled
        with each side's method.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import levels_side_by_side
    >>> from hyperlattice.plots.paper import plot_level_comparison
    >>> cmp = levels_side_by_side(hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2),
    ...                           hl.continuum_levels(7, 3, rings=2, levels=2))
    >>> [line.get_label() for line in plot_level_comparison(cmp).lines]
    ['graph (sector-dense)', 'continuum (dirichlet-roots)']
    >>> plt.close("all")
    """
    ax = _axes(ax, (5.2, 3.8))
    k = np.arange(len(comparison))
    ax.plot(k, comparison.graph.energies[:k.size], "o", color="C0", ms=6, label=f"graph ({comparison.graph.method})")
    ax.plot(k, comparison.continuum.energies[:k.size], "o", mfc="none", mec="C3", ms=10, mew=1.4,
            label=f"continuum ({comparison.continuum.method})")
    ax.set_xlabel("level index (a ±m pair counts twice)")
    ax.set_ylabel("energy E / t")
    ax.legend(fontsize=8)
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
