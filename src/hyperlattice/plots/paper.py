"""Figures ``Fig1`` (tessellation and ring graph) and ``Fig2`` (lowest levels vs rings, Z(beta)), and the
plots of the graph-vs-continuum level results of :mod:`hyperlattice.compare.levels`."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

from . import new_axes
from .. import geometry
from ..graph.lattice import Lattice, ring_lattice
from ..paper_labels import cite

if TYPE_CHECKING:
    from ..compare.levels import LevelComparison, LevelCount, RelativeErrorTrend


def _axes(ax, size=(5.0, 5.0)):
    return new_axes(ax, size)


def _geodesic_segments(lattice: Lattice, samples: int = 12) -> np.ndarray:
    """Edges drawn as hyperbolic geodesics (circular arcs orthogonal to the unit circle)."""
    t = np.linspace(0.0, 1.0, samples)
    a = lattice.z[lattice.edges[:, 0]][:, None]
    b = lattice.z[lattice.edges[:, 1]][:, None]
    pts = geometry.geodesic_point(a, b, t[None, :])
    return np.stack([pts.real, pts.imag], axis=-1)


def plot_tessellation(rings: int = 3, background_rings: int = 7, p: int = 7, q: int = 3, ax: Axes | None = None) -> Axes:
    """``Fig1``: the {p,q} tessellation in the Poincaré disk (grey) with the ``rings``-ring graph
    highlighted, sites coloured by ring."""
    ax = _axes(ax)
    bg = ring_lattice(p, q, background_rings)
    ax.add_collection(LineCollection(_geodesic_segments(bg), colors="0.7", linewidths=0.4))
    lat = ring_lattice(p, q, rings)
    ax.add_collection(LineCollection(_geodesic_segments(lat), colors="k", linewidths=1.1))
    sc = ax.scatter(lat.z.real, lat.z.imag, c=lat.ring, cmap="viridis", s=14, zorder=3)
    ax.add_patch(plt.Circle((0, 0), 1.0, fill=False, color="k", lw=1.0))
    cb = ax.figure.colorbar(sc, ax=ax, shrink=0.7, ticks=range(1, rings + 1))
    cb.set_label("ring", fontsize=11)
    ax.set_aspect("equal")
    ax.set_xlim(-1.03, 1.03)
    ax.set_ylim(-1.03, 1.03)
    ax.set_xlabel("Re z", fontsize=11)
    ax.set_ylabel("Im z", fontsize=11)
    ax.set_title(fr"$\{{{p},{q}\}}$ tessellation; graph with $\ell={rings}$ rings ({lat.sites} sites)",
                 fontsize=11)
    return ax


def plot_levels(table: list[dict], ax: Axes | None = None, *, lnphi_form: bool = True) -> Axes:
    """``Fig2`` main panel: E0 and E1 against the number of rings, graph (filled) and continuum
    (open), with the asymptotic formulas of ``eq19`` as lines.

    ``table`` rows need keys rings, E0_graph, E1_graph, E0_continuum, E1_continuum and the
    asymptotes are recomputed for a continuous l from ``hyperlattice.continuum.spectrum``.
    """
    from ..continuum.spectrum import asymptotic_energies

    keys = ("rings", "E0_graph", "E1_graph", "E0_continuum", "E1_continuum")
    if not isinstance(table, (list, tuple)) or not all(isinstance(r, dict) and all(k in r for k in keys)
                                                        for r in table):
        raise ValueError(f"table must be a list of dicts with keys {', '.join(keys)}.")
    ax = _axes(ax, (6.4, 4.6))
    rings = np.array([r["rings"] for r in table])
    for key, color, label in (("E0", "C0", "$E_0$"), ("E1", "C1", "$E_1$")):
        ax.plot(rings, [r[f"{key}_graph"] for r in table], "o", color=color, ms=6, label=f"{label} graph")
        ax.plot(rings, [r[f"{key}_continuum"] for r in table], "o", mfc="none", mec=color, ms=10,
                mew=1.4, label=f"{label} continuum")
    ell = np.linspace(max(1.5, rings.min()), rings.max() + 0.5, 200)
    asym = [asymptotic_energies(7, 3, rings=float(x)) if lnphi_form else None for x in ell]
    ax.plot(ell, [a["E0"] for a in asym], "-", color="C0", lw=1.2, label=cite("eq19") + r", $c_0=\ln 2$")
    ax.plot(ell, [a["E1"] for a in asym], "-", color="C1", lw=1.2, label=cite("eq19") + r", $c_1=\ln 2-1$")
    ax.axhline(asym[0]["E_inf"], color="0.4", ls=":", lw=1.0, label=r"$E_\infty=-3+\frac{3}{4}h^2$")
    lo = min(min(r["E0_graph"] for r in table), asym[0]["E_inf"]) - 0.02
    ax.set_ylim(lo, -2.45)
    ax.set_xlabel(r"number of rings $\ell$", fontsize=12)
    ax.set_ylabel("energy (units of t)", fontsize=12)
    ax.legend(fontsize=8.5, ncol=2, loc="upper right")
    return ax


def plot_partition(beta: np.ndarray, z_graph: np.ndarray, z_cont: np.ndarray, e0: float, ax: Axes | None = None) -> Axes:
    """``Fig2`` inset: ln Z(beta) over negative energies, graph vs disk, and the asymptote -beta E0."""
    from .. import _validate

    beta = _validate.real_array("beta", beta, ndim=1)
    z_graph = _validate.real_array("z_graph", z_graph, shape=beta.shape)
    z_cont = _validate.real_array("z_cont", z_cont, shape=beta.shape)
    e0 = _validate.real("e0", e0)
    ax = _axes(ax, (3.2, 2.4))
    ax.plot(beta, np.log(z_graph), "-", color="C0", lw=1.6, label="graph")
    ax.plot(beta, np.log(z_cont), "--", color="C3", lw=1.6, label="disk")
    ax.plot(beta, -beta * e0, ":", color="k", lw=1.0, label=r"$-\beta E_0$")
    ax.set_xlabel(r"$\beta$", fontsize=9)
    ax.set_ylabel(r"$\ln Z$", fontsize=9)
    ax.tick_params(labelsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_relative_error(trend: RelativeErrorTrend, ax: Axes | None = None) -> Axes:
    r"""Signed relative error :math:`(E_{\rm graph}-E_{\rm cont})/|E_{\rm graph}|` against l
    (a :class:`~hyperlattice.compare.levels.RelativeErrorTrend`), with its last sign change and,
    when it saturates, the Aitken limit as a dotted line."""
    ax = _axes(ax, (6.0, 4.2))
    ax.plot(trend.rings, trend.relative_error, "o-", color="C0", ms=5, lw=1.0, label=trend.level)
    ax.axhline(0.0, color="0.7", lw=0.8)
    if trend.sign_change is not None:
        ax.axvspan(*trend.sign_change, color="0.9", lw=0, label="last sign change")
    if trend.saturates:
        ax.axhline(trend.aitken_limit, color="C3", ls=":", lw=1.0, label="Aitken limit")
    ax.set_yscale("symlog", linthresh=1e-4)
    ax.set_xlabel(r"number of rings $\ell$")
    ax.set_ylabel(r"$(E_{\rm graph}-E_{\rm cont})/|E_{\rm graph}|$")
    ax.legend(fontsize=8)
    return ax


def plot_level_counting(count: LevelCount, ax: Axes | None = None, *, label: str | None = None, **kwargs) -> Axes:
    r"""Counting function :math:`\mathcal N(E)` (states up to E) of a
    :class:`~hyperlattice.compare.levels.LevelCount` as a staircase."""
    ax = _axes(ax, (5.2, 3.8))
    e = np.concatenate([[count.energies[0] if count.energies.size else count.cutoff], count.energies,
                        [count.cutoff]])
    n = np.concatenate([[0], np.cumsum(count.degeneracy), [count.states]])
    ax.step(e, n, where="post", label=label or count.side, **kwargs)
    ax.set_xlabel("energy E / t")
    ax.set_ylabel(r"states below E, $\mathcal{N}(E)$")
    ax.legend(fontsize=8)
    return ax


def plot_level_comparison(comparison: LevelComparison, ax: Axes | None = None) -> Axes:
    """Graph (filled) and continuum (open) levels of a
    :class:`~hyperlattice.compare.levels.LevelComparison` against the level index."""
    ax = _axes(ax, (5.2, 3.8))
    k = np.arange(len(comparison))
    ax.plot(k, comparison.graph.energies[:k.size], "o", color="C0", ms=6, label=f"graph ({comparison.graph.method})")
    ax.plot(k, comparison.continuum.energies[:k.size], "o", mfc="none", mec="C3", ms=10, mew=1.4,
            label=f"continuum ({comparison.continuum.method})")
    ax.set_xlabel("level index (a ±m pair counts twice)")
    ax.set_ylabel("energy E / t")
    ax.legend(fontsize=8)
    return ax


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
