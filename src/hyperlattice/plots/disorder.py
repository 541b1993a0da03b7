"""Figures of the disorder ensembles: averaged DOS, <r> against W, Green function against distance,
and the SCBA comparison. Each takes an optional ``ax`` and returns it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..paper_labels import cite

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.disorder import DisorderEnsemble, DisorderGreen, RScan, SCBAComparison

__all__ = ["plot_dos", "plot_r_scan", "plot_green_distance", "plot_scba_comparison"]


def _axes(ax, size=(5.5, 4.0)):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def plot_dos(ens: DisorderEnsemble, ax: Axes | None = None, **kwargs) -> Axes:
    """Disorder-averaged density of states per site (stairs)."""
    ax = _axes(ax)
    ax.stairs(ens.dos, ens.dos_edges, label=kwargs.pop("label", f"W = {ens.W:g}"), **kwargs)
    ax.set_xlabel("E / t")
    ax.set_ylabel("DOS per site")
    ax.set_title(f"{{{ens.p},{ens.q}}} l = {ens.rings}, {ens.model}, {ens.realizations} realizations", fontsize=9)
    ax.legend(fontsize=8)
    return ax


def plot_r_scan(scan: RScan, ax: Axes | None = None, **kwargs) -> Axes:
    """<r> against W (log axis) with the GOE and Poisson values."""
    from ..compare.disorder import GOE_R, POISSON_R

    ax = _axes(ax)
    w = np.asarray(scan.W, float)
    ax.errorbar(w, scan.r_mean, yerr=scan.r_err, marker="o", ms=4, capsize=2,
                label=kwargs.pop("label", f"l = {scan.rings} ({scan.sites} sites)"), **kwargs)
    ax.axhline(GOE_R, color="C3", ls="--", lw=1, label=f"GOE {GOE_R}")
    ax.axhline(POISSON_R, color="C2", ls=":", lw=1, label=f"Poisson {POISSON_R:.4f}")
    if np.all(w > 0):
        ax.set_xscale("log")
    # room above GOE and below Poisson: the reference lines must not sit on the frame
    lo = min(POISSON_R, float(np.min(np.asarray(scan.r_mean) - np.asarray(scan.r_err))))
    hi = max(GOE_R, float(np.max(np.asarray(scan.r_mean) + np.asarray(scan.r_err))))
    ax.set_ylim(lo - 0.08 * (hi - lo), hi + 0.08 * (hi - lo))
    ax.set_xlabel("W / t")
    ax.set_ylabel(r"$\langle r\rangle$")
    ax.legend(fontsize=8)
    return ax


def plot_green_distance(ens: DisorderGreen, ax: Axes | None = None, *, bins: int = 12, clean: bool = True) -> Axes:
    """``|<G_ij>|`` (and ``|G_ij(W=0)|`` if ``clean``) against the hyperbolic distance (binned means), source excluded."""
    ax = _axes(ax)
    keep = np.arange(ens.distance.size) != ens.source
    d = ens.distance[keep]
    edges = np.linspace(0.0, d.max() * (1 + 1e-12), bins + 1)
    idx = np.digitize(d, edges) - 1
    centres = 0.5 * (edges[1:] + edges[:-1])
    curves = [(ens.clean[keep], "W = 0", "--")] if clean else []
    for vals, label, style in curves + [(ens.mean[keep], f"W = {ens.W:g}", "-")]:
        a = np.abs(vals)
        m = np.array([a[idx == k].mean() if np.any(idx == k) else np.nan for k in range(bins)])
        ax.semilogy(centres, m, style, marker="o", ms=3, label=label)
    ax.set_xlabel("hyperbolic distance d(z_i, z_j)")
    ax.set_ylabel(r"$|\langle G_{ij}(\omega)\rangle|$")
    ax.legend(fontsize=8)
    return ax


def plot_scba_comparison(cmp: SCBAComparison, ax: Axes | None = None) -> Axes:
    """Relative distance of the ensemble average from the clean column and the two SCBA predictions."""
    ax = _axes(ax)
    w = np.asarray(cmp.W, float)
    ax.loglog(w, cmp.rel_clean, "o-", label="clean G0(omega)")
    ax.loglog(w, cmp.rel_graph_scba, "s-", label="graph SCBA")
    ax.loglog(w, cmp.rel_continuum_scba, "^-", label=f"continuum SCBA ({cite('eq21')} at shifted $\\omega$)")
    ax.loglog(w, cmp.rel_noise, ":", color="0.5", label="statistical error")
    ax.axhline(cmp.continuum_floor, color="0.6", lw=0.8, ls="--", label=f"clean graph vs {cite('eq21')}")
    ax.set_xlabel("W / t")
    ax.set_ylabel("relative L2 distance from the ensemble average")
    ax.legend(fontsize=7)
    return ax


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
