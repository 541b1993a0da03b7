"""Drawings of the graph- and continuum-side results: lattices, levels, butterflies, densities,
bands, Dirichlet tables, Mott lobes and qubit bound states.

They were methods of their result types; here they sit in the plotting layer, and
:mod:`hyperlattice.plots.registry` registers each one for :meth:`hyperlattice.results.Result.plot`.
Each takes the result and an optional ``ax`` (a new figure when None) and returns the axes.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .. import _validate, geometry
from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..bosons.meanfield import MottLobe
    from ..continuum.spectrum import DirichletTable
    from ..graph.bands import AbelianDOS, Bands
    from ..graph.butterfly import Butterfly
    from ..graph.kpm import KPMDos
    from ..graph.lattice import Lattice
    from ..graph.qubits import BoundState
    from ..results import Levels

__all__ = ["plot_levels", "plot_lattice", "plot_butterfly", "plot_kpm_dos", "plot_bands", "plot_abelian_dos",
           "plot_bound_state", "plot_dirichlet_table", "plot_mott_lobe"]


def plot_levels(levels: Levels, ax: Axes | None = None, *, label: str | None = None, marker: str = "_",
                **kwargs) -> Axes:
    """Levels against m (the angular momentum), one marker per state; returns the axes.

    Parameters
    ----------
    levels : Levels
        Energies with their labels, e.g. the :class:`~hyperlattice.graph.spectrum.Spectrum` of
        :func:`~hyperlattice.graph.spectrum.lowest_levels`. Levels without angular-momentum labels
        (``levels.m`` is None) are drawn at m = 0.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    label : str, optional
        Legend label of the markers; ``levels.method`` when None.
    marker : str, optional
        Matplotlib marker, a horizontal bar ``"_"`` by default (a level scheme).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes, with one marker per level at (m, E / t).

    See Also
    --------
    plot_dirichlet_table : the continuum levels against m.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_levels
    >>> ax = plot_levels(hl.lowest_levels(hl.ring_lattice(7, 3, 2), 4))
    >>> ax.get_xlabel(), ax.get_ylabel(), ax.lines[0].get_label()
    ('angular momentum m', 'energy E / t', 'sector-dense')
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    x = np.zeros(len(levels)) if levels.m is None else levels.m
    ax.plot(x, levels.energies, linestyle="none", marker=marker, markersize=14,
            label=label or levels.method, **kwargs)
    ax.set_xlabel("angular momentum m")
    ax.set_ylabel("energy E / t")
    return ax


def plot_lattice(lattice: Lattice, ax: Axes | None = None, *, geodesic: bool = True, samples: int = 9,
                 color: str = "0.25", linewidth: float | None = None, sites: bool = True, circle: bool = True) -> Axes:
    """Draw the graph in the Poincaré disk and return the axes.

    Parameters
    ----------
    lattice : Lattice
        A flake, a line graph or a cluster drawn in the disk.
    ax : matplotlib.axes.Axes, optional
        Where to draw (a new 5 x 5 inch figure if None).
    geodesic : bool, optional
        Draw edges as hyperbolic geodesics (arcs sampled at ``samples`` points) instead of
        straight chords; both coincide for edges through the centre. Default True.
    samples : int, optional
        Points per geodesic arc, 2 to 1000 (default 9).
    color : str, optional
        Matplotlib colour of the edges (default ``"0.25"``, dark grey).
    linewidth : float, optional
        Line width of the edges; when None it shrinks with the number of sites (0.1 to 1.5).
    sites : bool, optional
        Mark the sites, coloured by ring (small lattices only: at most 20,000 sites). Default True.
    circle : bool, optional
        Draw the unit circle, the boundary of the disk. Default True.

    Returns
    -------
    matplotlib.axes.Axes
        The axes (equal aspect, axis off) with the edges as one line collection, the sites, the
        unit circle and a title naming {p,q}, the rings and the sites.

    Raises
    ------
    ValueError
        If ``samples`` is not an integer in [2, 1000] or a flag is not a bool.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_lattice
    >>> ax = plot_lattice(hl.ring_lattice(7, 3, 2))
    >>> ax.get_title()
    '{7,3}, 2 rings, 35 sites'
    >>> plt.close("all")
    """
    from matplotlib.collections import LineCollection

    samples = _validate.integer("samples", samples, minimum=2, maximum=1000)
    ax = new_axes(ax, size=(5.0, 5.0))
    t = np.linspace(0.0, 1.0, samples if _validate.flag("geodesic", geodesic) else 2)
    a = lattice.z[lattice.edges[:, 0]][:, None]
    b = lattice.z[lattice.edges[:, 1]][:, None]
    pts = geometry._geodesic_point(a, b, t[None, :])
    if linewidth is None:  # thinner lines for bigger graphs, so that they stay legible
        linewidth = float(np.clip(3.0 / math.sqrt(max(lattice.sites, 1) / 7.0), 0.1, 1.5))
    ax.add_collection(LineCollection(np.stack([pts.real, pts.imag], axis=-1), colors=color,
                                     linewidths=linewidth))
    if _validate.flag("sites", sites) and lattice.sites <= 20_000:
        ax.scatter(lattice.z.real, lattice.z.imag, c=lattice.ring, s=max(4.0, 8 * linewidth), cmap="viridis",
                   zorder=3, linewidths=0)
    if _validate.flag("circle", circle):
        w = np.exp(2j * math.pi * np.linspace(0.0, 1.0, 361))
        ax.plot(w.real, w.imag, color="0.6", lw=0.8)
    ax.set_xlim(-1.02, 1.02)
    ax.set_ylim(-1.02, 1.02)
    ax.set_aspect("equal")
    ax.set_axis_off()
    what = "line graph of " if lattice.kind == "line_graph" else ""
    ax.set_title(f"{what}{{{lattice.p},{lattice.q}}}, {lattice.rings} rings, {lattice.sites} sites")
    return ax


def plot_butterfly(bf: Butterfly, ax: Axes | None = None, *, color: str = "k", size: float = 0.3,
                   **kwargs) -> Axes:
    """Every level as a dot against the flux; returns the axes.

    Parameters
    ----------
    bf : Butterfly
        The spectra of a flake against the flux f (flux quanta per p-gon face), from
        :func:`~hyperlattice.graph.butterfly.butterfly`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    color : str, optional
        Colour of the dots (default black).
    size : float, optional
        Marker area of the dots in points² (default 0.3).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.scatter`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with one (rasterized) dot per level and flux: f horizontal, E / t vertical.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_butterfly
    >>> ax = plot_butterfly(hl.butterfly(hl.ring_lattice(7, 3, 2), [0.0, 0.25]))
    >>> ax.get_xlabel(), ax.get_title()
    ('flux f per p-gon', '{7,3} flake, 2 rings, 35 sites')
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    n = bf.energies.shape[1]
    ax.scatter(np.repeat(bf.fluxes, n), bf.energies.ravel(), s=size, c=color, linewidths=0,
               rasterized=True, **kwargs)
    ax.set_xlabel("flux f per p-gon")
    ax.set_ylabel("energy E / t")
    ax.set_title(f"{{{bf.p},{bf.q}}} flake, {bf.rings} rings, {bf.sites:,} sites")
    return ax


def plot_kpm_dos(dos: KPMDos, ax: Axes | None = None, *, label: str | None = None, errors: bool = True,
                 **kwargs) -> Axes:
    """Draw the density (with a band of +-1 standard error) and return the axes.

    Parameters
    ----------
    dos : KPMDos
        A kernel-polynomial density of states, from :func:`~hyperlattice.graph.kpm.kpm_dos` or
        :func:`~hyperlattice.graph.kpm.bulk_dos`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    label : str, optional
        Legend label of the line; ``dos.label`` when None.
    errors : bool, optional
        Shade the band of +-1 standard error of the stochastic trace (when it is nonzero). Default
        True.
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the density per site against E / t (and the error band).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_kpm_dos
    >>> dos = hl.kpm_dos(hl.ring_lattice(7, 3, 3), 32, vectors=2, seed=1)
    >>> ax = plot_kpm_dos(dos)
    >>> ax.get_ylabel(), ax.lines[0].get_label()
    ('density of states per site', '{7,3} flake, 3 rings')
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    e, rho, err = dos.density()
    (line,) = ax.plot(e, rho, label=label if label is not None else dos.label, **kwargs)
    if errors and np.any(err > 0):
        ax.fill_between(e, rho - err, rho + err, color=line.get_color(), alpha=0.25, lw=0)
    ax.set_xlabel("E / t")
    ax.set_ylabel("density of states per site")
    return ax


def plot_bands(bands: Bands, ax: Axes | None = None, *, color: str = "C0", **kwargs) -> Axes:
    """The bands against the distance along the path; returns the axes.

    Parameters
    ----------
    bands : Bands
        Abelian (Bloch) bands of a periodic cluster along a path in the Brillouin zone, from
        :func:`~hyperlattice.graph.bands.band_structure`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    color : str, optional
        Colour of the bands (default ``"C0"``).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with one line per band, E / t against the path, the high-symmetry points as ticks
        and thin vertical lines.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_bands
    >>> ax = plot_bands(hl.band_structure(hl.pbc_cluster(8, 3, "bolza"), points=5))
    >>> ax.get_title()
    'Abelian bands of bolza ({8,3}, genus 2)'
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    ax.plot(bands.distance, bands.energies, color=color, linewidth=0.8, **kwargs)
    ax.set_xticks(bands.ticks, bands.tick_labels)
    for x in bands.ticks:
        ax.axvline(x, color="0.8", linewidth=0.5)
    ax.set_xlim(bands.distance[0], bands.distance[-1])
    ax.set_ylabel("energy E / t")
    ax.set_title(f"Abelian bands of {bands.name} ({{{bands.p},{bands.q}}}, genus {bands.genus})")
    return ax


def plot_abelian_dos(dos: AbelianDOS, ax: Axes | None = None, *, label: str | None = None, **kwargs) -> Axes:
    """The DOS with its error band; returns the axes.

    Parameters
    ----------
    dos : AbelianDOS
        The Abelian density of states of a periodic cluster, from
        :func:`~hyperlattice.graph.bands.abelian_dos`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    label : str, optional
        Legend label; ``"Abelian DOS, <cluster name>"`` when None.
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the density per site against E / t and a shaded band of +-1 error.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_abelian_dos
    >>> dos = hl.abelian_dos(hl.pbc_cluster(8, 3, "bolza"), samples=40, bins=20, batches=4)
    >>> plot_abelian_dos(dos).lines[0].get_label()
    'Abelian DOS, bolza'
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    line, = ax.plot(dos.energies, dos.density, label=label or f"Abelian DOS, {dos.name}", **kwargs)
    ax.fill_between(dos.energies, dos.density - dos.errors, dos.density + dos.errors,
                    color=line.get_color(), alpha=0.3, linewidth=0)
    ax.set_xlabel("energy E / t")
    ax.set_ylabel("density of states per site")
    return ax


def plot_bound_state(state: BoundState, ax: Axes | None = None) -> Axes:
    """``|photon|`` (exact) and the leading-order profile against hyperbolic distance, log scale.

    Parameters
    ----------
    state : BoundState
        A qubit-photon bound state below the band, from :func:`~hyperlattice.graph.qubits.bound_state`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (logarithmic y) with the exact photon amplitude of every site and the leading-order
        profile, proportional to the lattice Green function at the qubit frequency, against the
        hyperbolic distance from the qubit, and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_bound_state
    >>> ax = plot_bound_state(hl.bound_state(hl.ring_lattice(7, 3, 3), 0, -3.5, 0.2))
    >>> ax.get_yscale(), ax.get_legend().get_texts()[0].get_text()
    ('log', 'exact bound state')
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    ax.semilogy(state.distance, state.photon, ".", ms=3, label="exact bound state")
    ax.semilogy(state.distance, state.leading, ".", ms=1.5, label=r"$\propto G_{ij_0}(\omega_q)$")
    ax.set_xlabel("hyperbolic distance from the qubit")
    ax.set_ylabel("photon amplitude")
    ax.legend()
    return ax


def plot_dirichlet_table(table: DirichletTable, ax: Axes | None = None, **kwargs) -> Axes:
    """Energies against m, one line per radial index n; returns the axes.

    Parameters
    ----------
    table : DirichletTable
        The continuum Dirichlet levels E(n, m) of a disk, from
        :func:`~hyperlattice.continuum.spectrum.dirichlet_levels`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).
    **kwargs
        Passed on to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with one line (with markers) per n = 1, 2, ..., E / t against ``|m|``, and a legend.

    See Also
    --------
    plot_levels : the graph levels against m.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.basic import plot_dirichlet_table
    >>> ax = plot_dirichlet_table(hl.dirichlet_levels(7, 3, rings=3, n_max=2, m_max=3))
    >>> len(ax.lines), ax.get_xlabel()
    (2, 'angular momentum |m|')
    >>> plt.close("all")
    """
    ax = new_axes(ax)
    m = np.arange(table.energies.shape[1])
    for n, row in enumerate(table.energies, start=1):
        ax.plot(m, row, marker="o", label=f"n = {n}", **kwargs)
    ax.set_xlabel("angular momentum |m|")
    ax.set_ylabel("energy E / t")
    ax.legend(fontsize="small")
    return ax


def plot_mott_lobe(lobe: MottLobe, ax: Axes | None = None) -> Axes:
    """The lobe boundary (t/U horizontal, μ/U vertical, the usual orientation).

    Parameters
    ----------
    lobe : MottLobe
        The mean-field boundary of a Mott lobe, from :func:`~hyperlattice.bosons.meanfield.mott_lobe`.
    ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the boundary t_c / U against μ / U, labelled with ``lobe.label``.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.bosons.meanfield import mott_lobe
    >>> from hyperlattice.plots.basic import plot_mott_lobe
    >>> ax = plot_mott_lobe(mott_lobe(3.0, points=21))
    >>> ax.get_xlabel(), ax.get_ylabel(), ax.lines[0].get_label()
    ('t / U', 'μ / U', 'lambda_max = 3')
    >>> plt.close("all")
    """
    ax = new_axes(ax, size=(4.5, 3.5))
    ax.plot(lobe.t_c_over_U, lobe.mu_over_U, label=lobe.label)
    ax.set_xlabel("t / U")
    ax.set_ylabel("μ / U")
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
