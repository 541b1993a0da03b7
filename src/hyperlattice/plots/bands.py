"""Figures for Abelian hyperbolic band theory: bands along a k-path beside the Abelian DOS."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..graph.bands import AbelianDOS, Bands

__all__ = ["bands_and_dos"]


def bands_and_dos(bands: Bands, dos: AbelianDOS | None = None, *, path=None) -> Figure:
    """Bands along the path (left) and, if given, the Abelian DOS turned sideways (right).

    The uniform state E = -q (k = Γ only) is marked: it is not in the spectrum of the infinite
    lattice, whose band bottom lies above it.

    Parameters
    ----------
    bands : Bands
        From :func:`hyperlattice.graph.bands.band_structure`.
    dos : AbelianDOS, optional
        From :func:`hyperlattice.graph.bands.abelian_dos` (same cell).
    path : str or Path, optional
        Write the figure there (the suffix chooses the format).

    Returns
    -------
    matplotlib.figure.Figure
        One axes (the bands, E / t against the path, with E = -q dotted) or, with ``dos``, two axes
        sharing the energy axis (the DOS per site with its error band on the right).

    Raises
    ------
    ValueError
        If ``bands`` is not a ``Bands`` result or ``dos`` not an ``AbelianDOS``.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.bands import bands_and_dos
    >>> cell = hl.pbc_cluster(8, 3, "bolza")
    >>> fig = bands_and_dos(hl.band_structure(cell, points=5),
    ...                     hl.abelian_dos(cell, samples=40, bins=20, batches=4))
    >>> len(fig.axes), fig.axes[1].get_title()
    (2, '40 random k')
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    from ..graph.bands import AbelianDOS, Bands

    if not isinstance(bands, Bands):
        raise ValueError(f"bands must be a Bands result, got {type(bands).__name__}.")
    if dos is not None and not isinstance(dos, AbelianDOS):
        raise ValueError(f"dos must be an AbelianDOS result, got {type(dos).__name__}.")
    if dos is None:
        fig, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
        axes = [ax]
    else:
        fig, axes = plt.subplots(1, 2, figsize=(8.0, 4.2), layout="constrained", sharey=True,
                                 gridspec_kw={"width_ratios": [3, 1]})
    bands.plot(axes[0])
    axes[0].axhline(-bands.q, color="C3", linewidth=0.6, linestyle=":")
    if dos is not None:
        ax = axes[1]
        ax.plot(dos.density, dos.energies, color="C0")
        ax.fill_betweenx(dos.energies, np.maximum(dos.density - dos.errors, 0), dos.density + dos.errors,
                         color="C0", alpha=0.3, linewidth=0)
        ax.set_xlabel("Abelian DOS per site")
        ax.set_title(f"{dos.samples} random k")
    if path is not None:
        fig.savefig(path)
    return fig


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
