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


def _axes(ax, size=(4.6, 4.4)):
    return new_axes(ax, size)


def plot_disk_map(lattice: Lattice, values, source: int | None = None, *, scale: float = 60.0,
                  radius: float | None = None, title: str | None = None, ax=None) -> Axes:
    r"""``Fig3`` (left): dot at each site, area :math:`\propto |F_j|^{1/2}`, blue for :math:`F_j>0`,
    red for :math:`F_j<0` (real part of complex values). The source (if given) is marked by a
    black cross and left out of the size normalisation (the continuum value there is infinite);
    ``radius`` draws the Dirichlet circle :math:`|z| = L`.
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
                 f"$\\omega$={comparison.omega:g}, rel. L2 = {comparison.rel_l2:.3f}", fontsize=9)
    ax.legend(frameon=False, fontsize=8)
    return ax


def plot_binned(binned: BinnedCorrelation, ax: Axes | None = None, **kwargs) -> Axes:
    """Mean ± standard deviation (real part of the mean) of a :class:`BinnedCorrelation` against the bin centre."""
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


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
