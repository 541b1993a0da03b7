"""Figures of the QMC Mott lobe (:mod:`hyperlattice.compare.qmc_lobe`): QMC points over mean field and strong coupling."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.qmc_lobe import QMCLobe

__all__ = ["plot_qmc_lobe_system", "plot_qmc_lobe", "qmc_lobe_figure"]

_NAMES = {"flake": "{7,3} flake, ℓ = ", "cluster": "{7,3} cluster ", "square": "square lattice, L = "}


def _check(lobe) -> None:
    if not (hasattr(lobe, "systems") and hasattr(lobe, "rows") and hasattr(lobe, "square")):
        raise ValueError(f"lobe must be a QMCLobe (from compare.qmc_lobe.qmc_lobe), got {type(lobe).__name__}.")


def _title(spec: str, sites: int) -> str:
    kind, _, arg = spec.partition(":")
    return f"{_NAMES.get(kind, kind)}{arg} ({sites} sites)"


def plot_qmc_lobe_system(lobe: QMCLobe, system: str, ax: Axes | None = None) -> Axes:
    """One graph of ``lobe``: QMC μ±/U with error bars, mean field (dashed), strong coupling (solid).

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`~hyperlattice.compare.qmc_lobe.qmc_lobe`.
    system : str
        Its system spec (``"flake:3"``, ``"cluster:klein"``, ``"square:6"``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.

    Returns
    -------
    matplotlib.axes.Axes
        t/U horizontal, μ/U vertical; the legend names the three sources.

    Raises
    ------
    ValueError
        If ``system`` is not in ``lobe``.
    """
    _check(lobe)
    if not isinstance(system, str):
        raise ValueError(f"system must be a string such as 'flake:3', got {type(system).__name__}.")
    spec = next((s for s in lobe.systems if s["system"] == system), None)
    if spec is None:
        raise ValueError(f"system {system!r} is not in this lobe; it has {[s['system'] for s in lobe.systems]}.")
    ax = new_axes(ax, size=(4.0, 3.2))
    x = np.asarray(spec["t_line"])
    ax.plot(x, spec["mf_plus"], "--", color="tab:blue", lw=1.2, label="Gutzwiller mean field")
    ax.plot(x, spec["mf_minus"], "--", color="tab:blue", lw=1.2)
    ax.plot(x, spec["sc_plus"], "-", color="tab:orange", lw=1.2, label="strong coupling, 3rd order")
    ax.plot(x, spec["sc_minus"], "-", color="tab:orange", lw=1.2)
    rows = [r for r in lobe.rows if r["system"] == system and math.isfinite(r["mu"])]
    if rows:
        tx = [r["t_over_U"] for r in rows]
        mu = [r["mu"] for r in rows]
        err = [r["mu_err"] if math.isfinite(r["mu_err"]) else 0.0 for r in rows]
        beta = sorted({r["beta_t"] for r in rows})
        ax.errorbar(tx, mu, yerr=err, fmt="o", ms=4, color="k", capsize=2,
                    label=f"QMC, βt = {', '.join(f'{b:g}' for b in beta)}")
    ax.set_xlim(0.0, x[-1])
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("t/U")
    ax.set_ylabel("μ/U")
    ax.set_title(_title(system, spec["sites"]), fontsize=9)
    return ax


def plot_qmc_lobe(lobe: QMCLobe, ax: Axes | None = None) -> Axes:
    """The first graph of ``lobe`` (the drawing :meth:`QMCLobe.plot` uses); see :func:`qmc_lobe_figure` for all."""
    _check(lobe)
    return plot_qmc_lobe_system(lobe, lobe.systems[0]["system"], ax=ax)


def qmc_lobe_figure(lobe: QMCLobe, path=None):
    """All graphs of ``lobe``, one panel each, with one legend; saved to ``path`` when given.

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`~hyperlattice.compare.qmc_lobe.qmc_lobe`.
    path : str or path, optional
        A .png or .svg file to write.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from .. import _validate

    _check(lobe)
    k = len(lobe.systems)
    cols = min(3, k)
    rows = (k + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.0 * rows + 0.5), squeeze=False)
    for ax, spec in zip(axes.ravel(), lobe.systems):
        plot_qmc_lobe_system(lobe, spec["system"], ax=ax)
    for ax in axes.ravel()[k:]:
        ax.set_visible(False)
    handles, labels = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    if path is not None:
        fig.savefig(_validate.output_path("path", path, suffixes=(".png", ".svg")), dpi=130)
    return fig
