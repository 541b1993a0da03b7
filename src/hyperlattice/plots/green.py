r"""``Fig3``-style panels: correlation maps on the disk and mean/std versus hyperbolic distance.

Each function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .. import _validate
from . import new_axes
from ..compare.correlation import BinnedCorrelation, bin_by_distance, sorted_pairs
from ..compare.green import GreenComparison
from ..graph.lattice import Lattice
from ..paper_labels import cite

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_disk_map", "plot_distance_profile", "plot_binned", "plot_fig3_row"]


def _axes(ax, size=(4.6, 4.4)):
    return new_axes(ax, size)


def plot_disk_map(lattice: Lattice, values, source: int | None = None, *, scale: float = 60.0,
                  radius: float | None = None, title: str | None = None, ax=None) -> Axes:
    r"""``Fig3`` (left): a correlation map on the disk, one dot per site; returns the axes.

    Dot area :math:`\propto |F_j|^{1/2}`, blue for :math:`F_j>0`, red for :math:`F_j<0` (real part of
    complex values). The source (if given) is marked by a black cross and left out of the size
    normalisation (the continuum value there is infinite); ``radius`` draws the Dirichlet circle
    :math:`|z| = L`.

    Parameters
    ----------
    lattice : Lattice
        The flake whose sites carry the values.
    values : array_like
        One value :math:`F_j` per site (real or complex; non-finite values are not drawn).
    source : int, optional
        Index of the source site, marked and left out; none when None.
    scale : float, optional
        Marker area (points²) of the largest value (default 60).
    radius : float, optional
        Euclidean radius L of a dashed Dirichlet circle; none when None.
    title : str, optional
        Axes title.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (equal aspect, no ticks) with the dots, the source cross, the unit circle and the
        optional Dirichlet circle.

    Raises
    ------
    ValueError
        If ``values`` does not have one entry per site or ``source`` is not a site index.

    See Also
    --------
    plot_fig3_row : graph and continuum maps with the distance profile.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.green import compare_green
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> cmp = compare_green(lat, -2.95, 10)
    >>> from hyperlattice.plots.green import plot_disk_map
    >>> ax = plot_disk_map(lat, cmp.graph, 10, title="graph")
    >>> ax.get_title(), len(ax.collections)
    ('graph', 1)
    >>> plot_disk_map(lat, [1.0, 2.0])
    Traceback (most recent call last):
        ...
    ValueError: values must have one entry per site (112).
    >>> plt.close("all")
    """
    ax = _axes(ax)
    v = np.real(np.asarray(values))
    if v.shape != (lattice.sites,):
        raise ValueError(f"values must have one entry per site ({lattice.sites}).")
    keep = np.isfinite(v)
    if source is not None:
        source = _validate.site_index("source", source, lattice.sites)
        keep[source] = False
    amp = np.sqrt(np.abs(v[keep]))
    size = scale * amp / max(amp.max(), 1e-300)
    colour = np.where(v[keep] >= 0, "tab:blue", "tab:red")
    z = lattice.z[keep]
    ax.scatter(z.real, z.imag, s=size, c=colour, linewidths=0)
    if source is not None:
        ax.plot(lattice.z[source].real, lattice.z[source].imag, "kx", ms=6)
    t = np.linspace(0, 2 * np.pi, 400)
    ax.plot(np.cos(t), np.sin(t), color="0.7", lw=0.8)
    if radius is not None:
        ax.plot(radius * np.cos(t), radius * np.sin(t), color="0.4", lw=0.6, ls="--")
    ax.set_aspect("equal")
    ax.set_xlim(-1.05, 1.05)
    ax.set_ylim(-1.05, 1.05)
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=10)
    return ax


def plot_distance_profile(comparison: GreenComparison, lattice: Lattice | None = None, *,
                          width: float | None = None, ax=None) -> Axes:
    r"""``Fig3`` (right): binned mean :math:`\pm` standard deviation of :math:`\mathrm{Re}\,F_j` against
    :math:`d_{ij}`, graph (red) and continuum (black), source excluded.

    The distances come from ``comparison.distance``; ``lattice`` is not needed (accepted so that
    older calls ``plot_distance_profile(comparison, lattice)`` keep working) and, when given,
    must have one site per entry of the comparison.

    Parameters
    ----------
    comparison : GreenComparison
        Graph and continuum Green-function columns, from
        :func:`~hyperlattice.compare.green.compare_green`.
    lattice : Lattice, optional
        Ignored apart from the size check.
    width : float, optional
        Width of the distance bins; the default of
        :func:`~hyperlattice.compare.correlation.bin_by_distance` when None.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with both binned profiles (error bars), a legend and a title naming {p,q}, l, ω and
        the relative L2 distance.

    Raises
    ------
    ValueError
        If ``lattice`` does not have one site per entry of the comparison.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.green import compare_green
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> cmp = compare_green(lat, -2.95, 10)
    >>> from hyperlattice.plots.green import plot_distance_profile
    >>> print(plot_distance_profile(cmp).get_title())
    {7,3}, $\ell$=3, $\omega$=−2.95+0j, rel. L² = 0.143
    >>> plt.close("all")
    """
    if lattice is not None and _validate.lattice(lattice).sites != comparison.distance.shape[0]:
        raise ValueError(f"the lattice has {lattice.sites} sites, the comparison {comparison.distance.shape[0]}.")
    ax = _axes(ax, size=(5.2, 3.8))
    for vals, colour, label, shift in ((comparison.graph, "tab:red", "graph $G_{ij}$", -0.01),
                                       (comparison.continuum, "black", f"continuum ({cite('eq21')})", 0.01)):
        d, f = sorted_pairs(comparison.distance, np.real(vals), comparison.source)
        b = bin_by_distance(d, f, width=width)
        ax.errorbar(b.centre + shift, b.mean, yerr=b.std, fmt="o", ms=3.5, color=colour, capsize=2,
                    lw=0.9, label=label)
    ax.axhline(0.0, color="0.8", lw=0.6)
    ax.set_xlabel(r"hyperbolic distance $d_{ij}$")
    ax.set_ylabel(r"Re $G_{ij}(\omega)$")
    ax.set_title(f"{{{comparison.p},{comparison.q}}}, $\\ell$={comparison.rings}, "
                 f"$\\omega$={comparison.omega:g}, rel. L² = {comparison.rel_l2:.3f}".replace("-", "−"), fontsize=9)
    ax.legend(frameon=False, fontsize=8)
    return ax


def plot_binned(binned: BinnedCorrelation, ax: Axes | None = None, **kwargs) -> Axes:
    """Mean ± standard deviation (real part of the mean) of a :class:`BinnedCorrelation` against the bin centre.

    Parameters
    ----------
    binned : BinnedCorrelation
        Values binned by distance, from :func:`~hyperlattice.compare.correlation.bin_by_distance`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.errorbar` (defaults: circles, size 3.5, caps 2).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the error bars against the hyperbolic distance.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.compare.correlation import bin_by_distance
    >>> from hyperlattice.plots.green import plot_binned
    >>> ax = plot_binned(bin_by_distance([0.4, 0.6, 1.5], [1.0, 3.0, 5.0], width=1.0))
    >>> ax.get_ylabel()
    'binned mean'
    >>> plt.close("all")
    """
    ax = _axes(ax, size=(5.2, 3.8))
    opts = {"fmt": "o", "ms": 3.5, "capsize": 2, "lw": 0.9} | kwargs
    ax.errorbar(binned.centre, np.real(binned.mean), yerr=binned.std, **opts)
    ax.set_xlabel(r"hyperbolic distance $d$")
    ax.set_ylabel("binned mean")
    return ax


def plot_fig3_row(lattice: Lattice, omega, source: int = 10, *, axes: Sequence[Axes] | None = None,
                  comparison: GreenComparison | None = None) -> Sequence[Axes]:
    """One row of ``Fig3``: graph map, continuum map, distance profile. Returns the three axes.

    ``comparison`` is the :func:`~hyperlattice.compare.green.compare_green` result for these
    inputs if already computed (it is computed here otherwise).

    Parameters
    ----------
    lattice : Lattice
        A {p,q} flake.
    omega : float or complex
        Frequency ω (units of t).
    source : int, optional
        Index of the source site (default 10, a site on ring 2 as in the paper).
    axes : sequence of three matplotlib.axes.Axes, optional
        Where to draw; a new 12.5 x 4 inch row when None.
    comparison : GreenComparison, optional
        The comparison for these inputs, if already computed.

    Returns
    -------
    sequence of matplotlib.axes.Axes
        The three axes: :func:`plot_disk_map` of the graph column, of the continuum column (with the
        Dirichlet circle), and :func:`plot_distance_profile`.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.green import plot_fig3_row
    >>> axes = plot_fig3_row(hl.ring_lattice(7, 3, 3), -2.95, 10)
    >>> len(axes), axes[0].get_title()
    (3, 'graph $G_{ij}$')
    >>> plt.close("all")
    """
    from ..compare.green import compare_green

    if axes is None:
        import matplotlib.pyplot as plt

        _, axes = plt.subplots(1, 3, figsize=(12.5, 4.0), layout="constrained",
                               gridspec_kw={"width_ratios": [1, 1, 1.4]})
    cmp = comparison if comparison is not None else compare_green(lattice, omega, source)
    plot_disk_map(lattice, cmp.graph, source, ax=axes[0], title=r"graph $G_{ij}$")
    plot_disk_map(lattice, cmp.continuum, source, radius=lattice.radius, ax=axes[1],
                  title=r"continuum $\frac{4\mathcal{A}}{qh^2}G(z_i,z_j)$")
    plot_distance_profile(cmp, ax=axes[2])
    return axes


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
