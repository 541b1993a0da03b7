"""Figures of classical spin Monte Carlo (:mod:`hyperlattice.spins.classical`, :mod:`hyperlattice.spins.tempering`):
an observable by ring (bulk against boundary), against distance, or against temperature, with error bars."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..spins.classical import ClassicalResult
    from ..spins.tempering import TemperingResult

__all__ = ["plot_classical", "plot_temperature_scan", "plot_tempering"]

#: per-ring observables of a ClassicalResult and their axis labels
RING_OBSERVABLES = {"alignment": r"$\langle s_i\cdot\hat M\rangle$", "alignment_s": r"$\langle\epsilon_i s_i\cdot\hat M_s\rangle$",
                    "energy": r"energy per site $/J$", "m": r"$\langle s_i^z\rangle$"}
#: scalar observables of a ClassicalResult and their axis labels
SCALARS = {"e": r"$e/J$", "c": r"$c$", "m2": r"$\langle|m|^2\rangle$", "m_abs": r"$\langle|m|\rangle$", "U4": r"$U_4$",
           "chi": r"$\chi$", "m2_s": r"$\langle|m_s|^2\rangle$", "U4_s": r"$U_{4,s}$", "chi_s": r"$\chi_s$"}


def _is_classical(r) -> bool:
    return hasattr(r, "update_reason") and hasattr(r, "ring_alignment")


def plot_classical(result: ClassicalResult, ax: Axes | None = None, *, observable: str = "alignment") -> Axes:
    """One chain: a per-ring observable against the ring (flakes), or the correlation against distance.

    Parameters
    ----------
    result : ClassicalResult
        From :func:`~hyperlattice.spins.classical_mc`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    observable : {"alignment", "alignment_s", "energy", "m", "correlation"}, optional
        A per-ring observable (flakes only; default the alignment with the total moment) or the
        spin correlation by distance class.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if not _is_classical(result):
        raise ValueError(f"result must be a ClassicalResult, got {type(result).__name__}.")
    if observable not in (*RING_OBSERVABLES, "correlation"):
        raise ValueError(f"observable must be one of {', '.join((*RING_OBSERVABLES, 'correlation'))}, got {observable!r}.")
    ax = new_axes(ax)
    title = f"{result.model}, {result.system}, T = {result.T:.4g}"
    if observable == "correlation":
        if result.corr is None:
            raise ValueError("this result holds no spin correlation (measure_correlation was off or the graph too big).")
        d = np.asarray(result.corr_distance)
        fin = np.isfinite(d)
        ax.errorbar(d[fin], result.corr[fin], yerr=result.corr_err[fin], fmt="o", ms=3, capsize=2, color="k")
        ax.set_xlabel(f"distance ({result.distance_kind})")
        ax.set_ylabel(r"$\langle s_i\cdot s_j\rangle$")
    else:
        if result.ring_index is None:
            raise ValueError("per-ring observables exist on flakes only; use observable='correlation'.")
        y = getattr(result, "ring_" + observable)
        err = getattr(result, "ring_" + observable + "_err")
        ax.errorbar(result.ring_index, y, yerr=err, fmt="o-", ms=4, capsize=2, color="k")
        ax.set_xlabel("ring")
        ax.set_ylabel(RING_OBSERVABLES[observable])
    ax.set_title(title, fontsize=9)
    return ax


def plot_temperature_scan(results, ax: Axes | None = None, *, observable: str = "U4", by_ring: bool = False,
                          label: str | None = None) -> Axes:
    """An observable against temperature over a list of chains, with error bars.

    Parameters
    ----------
    results : sequence of ClassicalResult
        Chains of one system at several temperatures.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    observable : str, optional
        A scalar (``e, c, m2, m_abs, U4, chi`` and the staggered ones) or, with ``by_ring``, a
        per-ring observable (``alignment, alignment_s, energy, m``); one curve per ring then.
    by_ring : bool, optional
        One curve per ring (flakes).
    label : str, optional
        Legend label of the curve (scalars).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if not isinstance(results, (list, tuple)):
        raise ValueError("results must be a non-empty list of ClassicalResult.")
    res = list(results)
    if not res or not all(_is_classical(r) for r in res):
        raise ValueError("results must be a non-empty list of ClassicalResult.")
    table = RING_OBSERVABLES if by_ring else SCALARS
    if observable not in table:
        raise ValueError(f"observable must be one of {', '.join(table)}, got {observable!r}.")
    res.sort(key=lambda r: r.T)
    T = np.array([r.T for r in res])
    ax = new_axes(ax)
    if by_ring:
        if any(r.ring_index is None for r in res):
            raise ValueError("by_ring needs flakes (results with per-ring observables).")
        rings = res[0].ring_index
        y = np.array([getattr(r, "ring_" + observable) for r in res])
        err = np.array([getattr(r, "ring_" + observable + "_err") for r in res])
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        for k, ring in enumerate(rings):
            ax.errorbar(T, y[:, k], yerr=err[:, k], fmt="o-", ms=3, capsize=2,
                        color=cmap(k / max(len(rings) - 1, 1)), label=f"ring {int(ring)}")
        ax.legend(fontsize=7, ncol=2)
    else:
        y = np.array([getattr(r, observable) for r in res])
        err = np.array([getattr(r, observable + "_err") for r in res])
        ax.errorbar(T, y, yerr=err, fmt="o-", ms=3, capsize=2, label=label)
        if label is not None:
            ax.legend(fontsize=8)
    ax.set_xlabel("T / J")
    ax.set_ylabel(table[observable])
    return ax


def plot_tempering(result: TemperingResult, ax: Axes | None = None, *, observable: str = "e",
                   by_ring: bool = False) -> Axes:
    """A tempering run: an observable against temperature (its chains), with error bars.

    Parameters
    ----------
    result : TemperingResult
        From :func:`~hyperlattice.spins.tempering_mc`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    observable : str, optional
        As for :func:`plot_temperature_scan` (default the energy).
    by_ring : bool, optional
        One curve per ring (flakes).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if not hasattr(result, "chains") or not hasattr(result, "acceptance"):
        raise ValueError(f"result must be a TemperingResult, got {type(result).__name__}.")
    ax = plot_temperature_scan(result.chains, ax=ax, observable=observable, by_ring=by_ring)
    ax.set_title(f"parallel tempering, {result.model}, {result.system}; acceptance "
                 f"{np.nanmin(result.acceptance):.2f} to {np.nanmax(result.acceptance):.2f}", fontsize=9)
    return ax
