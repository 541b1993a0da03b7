"""Figures of topological bands: the two-terminal conductance of a flake against energy, and the
{8,3} QWZ phase diagram in M (flake markers beside the Abelian Chern numbers of a cluster).
Each takes an optional ``ax`` and returns it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..topology.transport import Conductance

__all__ = ["plot_conductance", "plot_phase_diagram"]


def _axes(ax, size=(6.5, 3.6)):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def plot_conductance(res: Conductance, ax: Axes | None = None, **kwargs) -> Axes:
    """G (e²/h) against E (t), with the integers marked.

    Parameters
    ----------
    res : Conductance
        From :func:`hyperlattice.topology.transport.conductance`.
    ax : matplotlib Axes, optional
        Where to draw (default: a new figure).
    **kwargs
        Passed to ``ax.plot``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ax.plot(res.energies, res.conductance, "o-", ms=3, **kwargs)
    top = int(np.ceil(max(1.0, float(np.max(res.conductance)))))
    for k in range(top + 1):
        ax.axhline(k, color="grey", lw=0.5, ls=":")
    ax.set_xlabel("E (t)")
    ax.set_ylabel("G (e²/h)")
    ax.set_title(f"{res.model}, {res.sites} sites: two-terminal conductance")
    return ax


def plot_phase_diagram(rows, ax: Axes | None = None) -> Axes:
    """The QWZ phase diagram in M: flake marker, Kitaev sum, conductance, cluster gcd and gaps.

    Parameters
    ----------
    rows : list of dict
        One per M, keys ``M``, ``marker``, ``kitaev``, ``conductance``, ``gap`` (flake) and
        ``gcd``, ``cluster_gap`` (cluster; None where its gap closes).
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    matplotlib.axes.Axes
    """
    keys = ("M", "marker", "kitaev", "conductance", "gap", "gcd", "cluster_gap")
    if (not isinstance(rows, (list, tuple)) or not rows
            or not all(isinstance(r, dict) and all(k in r for k in keys) for r in rows)):
        raise ValueError(f"rows must be a non-empty list of dicts with the keys {', '.join(keys)}.")
    ax = _axes(ax, (7.0, 4.0))
    M = [r["M"] for r in rows]
    nan = float("nan")
    ax.plot(M, [r["marker"] for r in rows], "o-", label="local marker, flake centre")
    ax.plot(M, [r["kitaev"] for r in rows], "s--", ms=4, label="Kitaev sum, flake centre")
    ax.plot(M, [r["conductance"] for r in rows], "x", label="G (e²/h), flake, E = 0")
    ax.plot(M, [(r["gcd"] if r["gcd"] is not None else nan) for r in rows], "v", label="gcd C_ij, cluster")
    ax.plot(M, [r["gap"] for r in rows], ":", color="grey", label="ring-1 LDOS gap, flake (t)")
    ax.plot(M, [(r["cluster_gap"] if r["cluster_gap"] is not None else nan) for r in rows], "-.", color="C5",
            label="smallest Abelian gap, cluster (t)")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("M")
    ax.set_ylabel("invariant, G (e²/h), gap (t)")
    ax.legend(fontsize=7)
    return ax


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
