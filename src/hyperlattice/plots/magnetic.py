"""Figures for a uniform magnetic field: the butterfly with the continuum levels, the error map."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import _check_axes, new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..graph.butterfly import Butterfly

__all__ = ["continuum_curves", "continuum_level_curves", "butterfly_figure", "error_map"]


def continuum_curves(p: int, q: int, rings: int, fluxes, levels: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """The lowest continuum Dirichlet levels in a magnetic field at each flux.

    The ``levels`` lowest levels of ``magnetic_levels`` on the disk of the ``rings``-ring flake; returns
    ``(fluxes, energies)`` with energies of shape (F, levels).

    The energies are the graph energies of the dictionary (``spec2`` with the field B of
    :func:`~hyperlattice.dictionary.field_from_flux`), so they go on the same axis as the butterfly.

    Parameters
    ----------
    p, q : int
        The {p,q} lattice.
    rings : int
        Number of rings l of the flake whose disk is used.
    fluxes : array_like of float
        Flux values f (flux quanta per p-gon face), one-dimensional.
    levels : int, optional
        Number of levels per flux, lowest first (default 6).

    Returns
    -------
    fluxes : numpy.ndarray
        The flux values, shape (F,).
    energies : numpy.ndarray
        The continuum levels in units of t, shape (F, levels), ascending along each row.

    Raises
    ------
    ValueError
        If ``fluxes`` is not a one-dimensional array of real numbers.

    See Also
    --------
    hyperlattice.continuum.magnetic.magnetic_levels : the levels at one flux.

    Examples
    --------
    >>> from hyperlattice.plots.magnetic import continuum_curves
    >>> f, e = continuum_curves(7, 3, 2, [0.0, 0.1], levels=2)
    >>> e.shape
    (2, 2)
    >>> [[round(float(x), 4) for x in row] for row in e]
    [[-2.5703, -2.0845], [-2.5567, -2.1686]]
    """
    from ..continuum.magnetic import magnetic_levels

    from .. import _validate

    f = _validate.real_array("fluxes", fluxes, ndim=1)
    e = np.array([magnetic_levels(p, q, rings=rings, levels=levels, flux=float(fk)).energies[:levels]
                  for fk in f.tolist()])
    return f, e


def continuum_level_curves(p: int, q: int, rings: int, fluxes, levels: int = 6) -> dict:
    """The continuum Dirichlet levels in a magnetic field, each followed through the flux by its (n, m).

    :func:`continuum_curves` returns the k-th lowest level at each flux; where two levels cross, a
    line joining the k-th values turns a corner (it jumps from one level to the other). Here each
    level keeps its quantum numbers (radial n, angular m): the curves cross as the levels do. Every
    level that is among the ``levels`` lowest at some flux of ``fluxes`` is returned over the whole
    flux range.

    Parameters
    ----------
    p, q : int
        The {p,q} lattice.
    rings : int
        Number of rings l of the flake whose disk is used.
    fluxes : array_like of float
        Flux values f (flux quanta per p-gon face), one-dimensional.
    levels : int, optional
        How many of the lowest levels at each flux select the curves (default 6).

    Returns
    -------
    dict
        ``(n, m) -> energies`` (numpy array, one value per flux, in units of t; NaN where the level
        was not among the levels computed at that flux), ordered by the energy at the first flux.

    Raises
    ------
    ValueError
        If ``fluxes`` is not a one-dimensional array of real numbers or ``levels`` is not an
        integer in [1, 50].

    See Also
    --------
    continuum_curves : the k-th lowest level at each flux.

    Examples
    --------
    >>> from hyperlattice.plots.magnetic import continuum_level_curves
    >>> curves = continuum_level_curves(7, 3, 5, [0.0, 0.05, 0.1], levels=4)
    >>> [key for key in curves][:4]
    [(1, 0), (1, 1), (1, -1), (1, 2)]
    >>> [round(float(x), 4) for x in curves[(1, 3)]]   # lowest four at f = 0.1, not at f = 0
    [-2.7442, -2.7717, -2.7718]
    """
    from ..continuum.magnetic import magnetic_levels

    from .. import _validate

    f = _validate.real_array("fluxes", fluxes, ndim=1)
    levels = _validate.integer("levels", levels, minimum=1, maximum=50)
    # more levels than shown, so that a level chosen at one flux is found at every other
    spectra = [magnetic_levels(p, q, rings=rings, levels=4 * levels + 4, flux=float(fk)) for fk in f.tolist()]
    chosen: list = []
    for sp in spectra:
        for n, m in zip(sp.n[:levels].tolist(), sp.m[:levels].tolist()):
            if (n, m) not in chosen:
                chosen.append((n, m))
    curves = {key: np.full(f.size, np.nan) for key in chosen}
    for k, sp in enumerate(spectra):
        found = {(n, m): e for n, m, e in zip(sp.n.tolist(), sp.m.tolist(), sp.energies.tolist())}
        for key in chosen:
            if key in found:
                curves[key][k] = found[key]
    first = {key: (np.nanmin(v) if np.isnan(v[0]) else v[0]) for key, v in curves.items()}
    return {key: curves[key] for key in sorted(chosen, key=lambda k: first[k])}


def butterfly_figure(result: Butterfly, *, continuum: bool = True, max_flux: float = 0.3, points: int = 13,
                     levels: int = 6, ax=None, path=None, density: bool = False,
                     energy_bins: int = 480, mirror: bool = False, zoom_ax=None) -> Axes:
    """The butterfly with the continuum levels overlaid; returns the axes.

    Every level against f, with, for a site flake, the ``levels`` lowest continuum Dirichlet levels
    overlaid at 0 ≤ f ≤ ``max_flux`` (red lines, ``points`` flux values).

    ``density=True`` draws the levels as a 2-D histogram image (one column per flux value,
    ``energy_bins`` rows, grey scale linear in the number of levels per pixel, black from the 98th
    percentile of the non-empty pixels up) instead of dots: with a few hundred fluxes the gaps of the
    butterfly stay white or light where dots would merge into columns, and the bands stand out
    against the lone edge-state levels that cross the gaps of a flake.
    ``mirror=True`` draws the levels computed at 0 ≤ f ≤ 1/2 a second time at 1 − f: on a site flake
    the spectrum at 1 − f is the spectrum at f (f → −f is complex conjugation, f → f + 1 a gauge
    transformation since every face is a p-gon), so half the fluxes give the whole period.
    ``zoom_ax`` (with ``continuum``), a second axes, gets the band bottom at 0 ≤ f ≤ ``max_flux``
    magnified: the lowest levels as dots beside the same continuum lines.
    ``path``, if given, is where the figure is saved (format by suffix).

    Parameters
    ----------
    result : Butterfly
        The spectra against the flux, from :func:`~hyperlattice.graph.butterfly.butterfly`.
    continuum : bool, optional
        Overlay the continuum levels (site flakes only; default True).
    max_flux : float, optional
        Largest flux of the continuum curves (default 0.3).
    points : int, optional
        Number of flux values of the continuum curves (default 13).
    levels : int, optional
        Number of continuum levels (default 6).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 7 x 5 inch figure when None.
    path : str or path-like, optional
        Where to save the figure (150 dpi); the figure is then closed. Not saved when None.
    density : bool, optional
        Draw the levels as a 2-D histogram image instead of dots (default False).
    energy_bins : int, optional
        Number of energy rows of the histogram image (default 480).
    mirror : bool, optional
        Also draw every level at 1 − f (default False); needs a site flake and 0 ≤ f ≤ 1/2.
    zoom_ax : matplotlib.axes.Axes, optional
        Where to draw the band bottom magnified with the continuum levels (default: not drawn).

    Returns
    -------
    matplotlib.axes.Axes
        The axes: f horizontal, E / t vertical, the levels as dots or as an image, and the continuum
        levels as red lines with a legend.

    Raises
    ------
    ValueError
        If ``mirror`` is asked for a line graph or for fluxes outside [0, 1/2], or ``ax`` or
        ``zoom_ax`` is not a matplotlib Axes.

    See Also
    --------
    continuum_curves : the red lines.
    hyperlattice.plots.basic.plot_butterfly : the dots alone.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.magnetic import butterfly_figure
    >>> bf = hl.butterfly(hl.ring_lattice(7, 3, 2), [0.0, 0.1, 0.2])
    >>> ax = butterfly_figure(bf, points=3, levels=2)
    >>> ax.get_title(), len(ax.lines), ax.lines[0].get_label()
    ('{7,3} flake, 2 rings, 35 sites', 2, 'continuum (Dirichlet disk)')
    >>> ax = butterfly_figure(bf, continuum=False, density=True, energy_bins=40)
    >>> ax.get_title(), len(ax.images)
    ('{7,3} flake, 2 rings, 35 sites, 3 fluxes', 1)
    >>> ax = butterfly_figure(hl.butterfly(hl.ring_lattice(7, 3, 2), [0.0, 0.25, 0.5]), continuum=False,
    ...                       density=True, energy_bins=40, mirror=True)
    >>> ax.get_title(), [float(x) for x in ax.get_xlim()]
    ('{7,3} flake, 2 rings, 35 sites, 5 fluxes', [-0.125, 1.125])
    >>> plt.close("all")
    """
    _check_axes("zoom_ax", zoom_ax)
    f = np.asarray(result.fluxes, dtype=float)
    e = np.asarray(result.energies, dtype=float)
    if mirror:
        if result.kind != "sites":
            raise ValueError("mirror needs a site flake: on a line graph one more flux quantum per p-gon is "
                             "not a gauge transformation (its triangles carry flux too).")
        if float(f.min()) < 0.0 or float(f.max()) > 0.5:
            raise ValueError(f"mirror needs fluxes in [0, 1/2], got {float(f.min()):g} to {float(f.max()):g}.")
        keep = f < 0.5  # f = 1/2 is its own mirror image
        f, e = np.concatenate([f, 1.0 - f[keep]]), np.concatenate([e, e[keep]])
        order = np.argsort(f, kind="stable")
        f, e = f[order], e[order]
    ax = new_axes(ax, size=(7.0, 5.0))
    if density:
        step = (f[-1] - f[0]) / max(f.size - 1, 1) or 1.0
        f_edges = np.linspace(f[0] - step / 2, f[-1] + step / 2, f.size + 1)
        lo, hi = float(e.min()), float(e.max())
        pad = 0.01 * (hi - lo)
        e_edges = np.linspace(lo - pad, hi + pad, int(energy_bins) + 1)
        counts, _, _ = np.histogram2d(np.repeat(f, e.shape[1]), e.ravel(), bins=(f_edges, e_edges))
        # linear, saturated at the 98th percentile: a lone edge level in a gap stays light grey,
        # a band is black (a log scale made both mid-grey)
        vmax = max(float(np.percentile(counts[counts > 0], 98)), 1.0)
        ax.imshow(counts.T, origin="lower", aspect="auto", cmap="Greys", interpolation="nearest", vmin=0.0,
                  vmax=vmax, extent=(f_edges[0], f_edges[-1], e_edges[0], e_edges[-1]), rasterized=True)
        ax.set_xlabel("flux f per p-gon")
        ax.set_ylabel("energy E / t")
        ax.set_title(f"{{{result.p},{result.q}}} flake, {result.rings} rings, {result.sites:,} sites, "
                     f"{f.size} fluxes")
    else:
        result.plot(ax=ax)
        if mirror:
            ax.scatter(np.repeat(1.0 - result.fluxes[result.fluxes < 0.5], e.shape[1]),
                       result.energies[result.fluxes < 0.5].ravel(), s=0.3, c="k", linewidths=0, rasterized=True)
    if continuum and result.kind == "sites":
        f = np.linspace(0.0, max_flux, points)
        curves = continuum_level_curves(result.p, result.q, result.rings, f, levels)
        for k, ((n, m), e_nm) in enumerate(curves.items()):
            ax.plot(f, e_nm, color="tab:red", lw=0.9, gid=f"continuum n={n} m={m}",
                    label="continuum (Dirichlet disk)" if k == 0 else None)
        ax.legend(loc="upper right", fontsize=8)
        if zoom_ax is not None:
            _band_bottom(zoom_ax, result, f, curves, max_flux, levels)
    if path is not None:
        import matplotlib.pyplot as plt

        ax.figure.savefig(path, dpi=150)
        plt.close(ax.figure)
    return ax


def _band_bottom(inset: Axes, result: Butterfly, f: np.ndarray, curves: dict, max_flux: float,
                 levels: int) -> Axes:
    """The levels at 0 ≤ f ≤ max_flux near the band bottom as dots and the continuum levels ``curves``
    (one per (n, m)) at ``f`` as red lines, on ``inset`` (the whole butterfly squeezes both into a corner)."""
    # the window: up to the highest of the ``levels`` lowest continuum levels at any flux
    stacked = np.sort(np.array(list(curves.values())), axis=0)[:levels]
    e = stacked.T
    fl = np.asarray(result.fluxes, dtype=float)
    sel = (fl >= 0.0) & (fl <= max_flux)
    lo = float(np.min(result.energies[sel, 0])) if sel.any() else float(np.nanmin(e))
    hi = float(np.nanmax(e)) + 0.35 * (float(np.nanmax(e)) - lo)
    # a level that climbs out of the computed ones ends early: keep its end above the window
    ends = [float(v[np.isfinite(v)][-1]) for v in curves.values() if np.isnan(v[-1]) and np.isfinite(v).any()]
    hi = min([hi] + [x for x in ends if x > float(np.nanmax(e))])
    en = np.asarray(result.energies, dtype=float)[sel]
    rows, cols = np.nonzero(en <= hi)
    inset.scatter(fl[sel][rows], en[rows, cols], s=1.5, c="k", linewidths=0, rasterized=True)
    for (n, m), e_nm in curves.items():
        inset.plot(f, e_nm, color="tab:red", lw=0.9, gid=f"continuum n={n} m={m}")
    inset.set_xlim(0.0, max_flux)
    inset.set_ylim(lo - 0.05 * (hi - lo), hi)
    inset.set_xlabel("flux f per p-gon")
    inset.set_ylabel("energy E / t")
    inset.set_title("band bottom: flake levels (dots),\ncontinuum Dirichlet levels (red)", fontsize=9)
    return inset


def error_map(fluxes, ells, rel_error, *, ax: Axes | None = None, title: str = "") -> Axes:
    r"""log10 of the relative error over the (f, l) plane; returns the axes.

    A colour map of :math:`\log_{10}` of ``rel_error`` (floored at 1e-17) with a colour bar and the
    white contour where the error is 1e-3 (or a note on the figure when the error is below or above
    1e-3 everywhere).

    Parameters
    ----------
    fluxes : array_like of float
        Flux values f (flux quanta per p-gon face), shape (F,).
    ells : array_like of float
        Ring numbers l, shape (R,); integer rings up to 20 get one tick each.
    rel_error : array_like of float
        Relative error of graph against continuum, shape (R, F) (one row per l).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None.
    title : str, optional
        Axes title; ``"graph vs continuum: lowest level"`` when empty.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the colour mesh (f horizontal, l vertical); the colour bar is a second axes of
        the same figure.

    Raises
    ------
    ValueError
        If the arrays are not real or ``rel_error`` does not have shape (len(ells), len(fluxes)).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.plots.magnetic import error_map
    >>> ax = error_map([0.0, 0.1, 0.2], [2, 3], [[1e-4, 1e-3, 1e-2], [1e-5, 1e-4, 1e-2]], title="E0")
    >>> ax.get_title(), len(ax.figure.axes), [t.get_text() for t in ax.get_yticklabels()]
    ('E0', 2, ['2', '3'])
    >>> error_map([0.0, 0.1], [2], [[1e-4, 1e-3, 1e-2]])
    Traceback (most recent call last):
        ...
    ValueError: rel_error must have shape (1, 2), got (1, 3).
    >>> plt.close("all")
    """
    from .. import _validate

    f = _validate.real_array("fluxes", fluxes, ndim=1)
    ell = _validate.real_array("ells", ells, ndim=1)
    err = _validate.real_array("rel_error", rel_error, shape=(ell.size, f.size))
    ax = new_axes(ax)
    z = np.log10(np.maximum(err, 1e-17))
    mesh = ax.pcolormesh(f, ell, z, shading="nearest", cmap="viridis")
    ax.figure.colorbar(mesh, ax=ax, label=r"$\log_{10}$ relative error")
    if np.nanmin(z) < -3 < np.nanmax(z) and ell.size > 1 and f.size > 1:
        ax.contour(f, ell, z, levels=[-3.0], colors="w", linewidths=1.5, linestyles="solid")
    else:
        # say so on the figure: an absent contour must not read as a missing line
        where = "everywhere" if np.nanmax(z) < -3 else "nowhere"
        ax.text(0.5, 0.5, f"error < $10^{{-3}}$ {where}\nin this range", transform=ax.transAxes, ha="center",
                va="center", color="w", fontsize=10)
    if np.allclose(ell, np.round(ell)) and ell.size <= 20:
        ax.set_yticks(np.round(ell).astype(int))  # rings are integers: no ticks at l = 2.5
    ax.set_xlabel("flux f per p-gon")
    ax.set_ylabel(r"rings $\ell$")
    ax.set_title(title or "graph vs continuum: lowest level")
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
