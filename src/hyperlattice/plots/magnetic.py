"""Figures for a uniform magnetic field: the butterfly with the continuum levels, the error map."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..graph.flux import Butterfly

__all__ = ["continuum_curves", "butterfly_figure", "error_map"]


def continuum_curves(p: int, q: int, rings: int, fluxes, levels: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """The ``levels`` lowest continuum Dirichlet levels (``magnetic_levels`` on the disk of the
    ``rings``-ring flake) at each flux; returns ``(fluxes, energies)`` with energies of shape (F, levels).

    The energies are the graph energies of the dictionary (``spec2`` with the field B of
    :func:`~hyperlattice.dictionary.field_from_flux`), so they go on the same axis as the butterfly.
    """
    from ..continuum.magnetic import magnetic_levels

    from .. import _validate

    f = _validate.real_array("fluxes", fluxes, ndim=1)
    e = np.array([magnetic_levels(p, q, rings=rings, levels=levels, flux=float(fk)).energies[:levels]
                  for fk in f.tolist()])
    return f, e


def butterfly_figure(result: Butterfly, *, continuum: bool = True, max_flux: float = 0.3, points: int = 13,
                     levels: int = 6, ax=None, path=None) -> Axes:
    """The butterfly (every level against f) with, for a site flake, the ``levels`` lowest continuum
    Dirichlet levels overlaid at ``0 <= f <= max_flux`` (red lines, ``points`` flux values).

    ``path``, if given, is where the figure is saved (format by suffix). Returns the axes.
    """
    ax = new_axes(ax, size=(7.0, 5.0))
    result.plot(ax=ax)
    if continuum and result.kind == "sites":
        f, e = continuum_curves(result.p, result.q, result.rings, np.linspace(0.0, max_flux, points), levels)
        for k in range(e.shape[1]):
            ax.plot(f, e[:, k], color="tab:red", lw=0.9, label="continuum (Dirichlet disk)" if k == 0 else None)
        ax.legend(loc="upper right", fontsize=8)
    if path is not None:
        import matplotlib.pyplot as plt

        ax.figure.savefig(path, dpi=150)
        plt.close(ax.figure)
    return ax


def error_map(fluxes, ells, rel_error, *, ax: Axes | None = None, title: str = "") -> Axes:
    """log10 of the relative error over the (f, l) plane (``rel_error`` of shape (len(ells), len(fluxes)))."""
    from .. import _validate

    f = _validate.real_array("fluxes", fluxes, ndim=1)
    ell = _validate.real_array("ells", ells, ndim=1)
    err = _validate.real_array("rel_error", rel_error, shape=(ell.size, f.size))
    ax = new_axes(ax)
    z = np.log10(np.maximum(err, 1e-17))
    mesh = ax.pcolormesh(f, ell, z, shading="nearest", cmap="viridis")
    ax.figure.colorbar(mesh, ax=ax, label="log10 relative error")
    if np.nanmin(z) < -3 < np.nanmax(z):
        ax.contour(f, ell, z, levels=[-3.0], colors="w", linewidths=1.0)
    ax.set_xlabel("flux f per p-gon")
    ax.set_ylabel("rings l")
    ax.set_title(title or "graph vs continuum: lowest level")
    return ax


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
