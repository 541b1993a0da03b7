"""Figures of the interacting bosons (:mod:`hyperlattice.bosons`): Mott lobes and order-parameter profiles."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..bosons.meanfield import GutzwillerState, MottLobeTable
    from ..compare.bosons import GPComparison

__all__ = ["plot_mott_lobes", "plot_lobe_tips", "plot_order_parameter", "meanfield_figure", "gp_comparison_figure"]

_STYLE = {"flake": "-", "continuum": "--", "cluster": ":", "infinite": "-"}


def plot_mott_lobes(table: MottLobeTable, ax: Axes | None = None) -> Axes:
    """The Mott lobes of every system of ``table`` (t/U horizontal, μ/U vertical); returns the axes.

    Flakes are solid lines shaded light to dark with l, their continuum disks dashed in the same
    shade, periodic clusters dotted, the infinite lattice black.

    Parameters
    ----------
    table : MottLobeTable
        Mean-field Mott lobes of several systems, from :func:`~hyperlattice.bosons.meanfield.mott_lobes`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with one lobe boundary per system, a legend outside the axes on the right (the
        continuum disks are labelled once, at the largest l) and a title naming {p,q} and the filling.

    See Also
    --------
    hyperlattice.plots.basic.plot_mott_lobe : one lobe.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.bosons.meanfield import mott_lobes
    >>> table = mott_lobes(7, 3, rings=(2, 3), points=21, infinite=False)
    >>> from hyperlattice.plots.bosons import plot_mott_lobes
    >>> ax = plot_mott_lobes(table)
    >>> ax.get_title(), len(ax.lines)
    ('{7,3} Mott lobe n = 1 (mean field)', 4)
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    ax = new_axes(ax, size=(5.0, 4.0))
    flakes = sorted({ell for ell, kind in zip(table.rings, table.kinds) if kind == "flake"})
    cmap = plt.get_cmap("viridis")
    shade = {ell: cmap(0.15 + 0.7 * i / max(1, len(flakes) - 1)) for i, ell in enumerate(flakes)}
    for lobe, kind, ell in zip(table.lobes, table.kinds, table.rings):
        color = "k" if kind == "infinite" else ("0.45" if kind == "cluster" else shade.get(ell, "C0"))
        label = lobe.label if kind != "continuum" or ell == flakes[-1] else None
        ax.plot(lobe.t_c_over_U, lobe.mu_over_U, _STYLE[kind], color=color, lw=1.6 if kind == "infinite" else 1.1,
                label=label)
    ax.set_xlabel("t / U")
    ax.set_ylabel("μ / U")
    ax.set_xlim(left=0.0)
    ax.set_title(f"{{{table.p},{table.q}}} Mott lobe n = {table.filling} (mean field)", fontsize=10)
    ax.legend(fontsize=8, frameon=False, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


def plot_lobe_tips(table: MottLobeTable, ax: Axes | None = None) -> Axes:
    """The lobe tips t_c/U against l; returns the axes.

    The flakes as points and their continuum disks as a dashed line, with the infinite lattice and the
    clusters as horizontal lines.

    Parameters
    ----------
    table : MottLobeTable
        Mean-field Mott lobes of several systems, from :func:`~hyperlattice.bosons.meanfield.mott_lobes`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the tips t_c / U against the ring number l (integer ticks) and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.bosons.meanfield import mott_lobes
    >>> table = mott_lobes(7, 3, rings=(2, 3), points=21, infinite=False)
    >>> from hyperlattice.plots.bosons import plot_lobe_tips
    >>> ax = plot_lobe_tips(table)
    >>> [line.get_label() for line in ax.lines]
    ['flakes', 'continuum (paper dictionary)']
    >>> plt.close("all")
    """
    ax = new_axes(ax, size=(5.0, 4.0))
    rows = table.rows()
    for kind, style, name in (("flake", "o", "flakes"), ("continuum", "s--", "continuum (paper dictionary)")):
        pts = [(r["rings"], r["tip_t_over_U"]) for r in rows if r["kind"] == kind]
        if pts:
            x, y = np.array(pts, dtype=float).T
            ax.plot(x, y, style, ms=4, label=name, mfc="none" if kind == "continuum" else None)
    for r in rows:
        if r["kind"] in ("infinite", "cluster"):
            ax.axhline(r["tip_t_over_U"], color="k" if r["kind"] == "infinite" else "0.5",
                       ls="-" if r["kind"] == "infinite" else ":", lw=1.0, label=r["label"])
    ax.set_xlabel("rings ℓ")
    ax.set_ylabel("lobe tip t_c / U")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.legend(fontsize=8, frameon=False)
    return ax


def plot_order_parameter(state: GutzwillerState, lattice, ax: Axes | None = None) -> Axes:
    r""":math:`|\psi_i|` of a Gutzwiller state against the ring of each site of a flake (one point per site); returns the axes.

    The points are spread by a small fixed horizontal jitter (seeded, so the figure is reproducible)
    to keep the sites of a ring apart.

    Parameters
    ----------
    state : GutzwillerState
        A mean-field state, from :func:`~hyperlattice.bosons.meanfield.gutzwiller`.
    lattice : Lattice
        The flake the state was computed on (its ``ring`` labels give the horizontal axis).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with :math:`\psi_i = \langle a_i\rangle` against the ring and a title naming t/U and μ/U.

    Raises
    ------
    ValueError
        If the lattice and the state have different numbers of sites.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.meanfield import gutzwiller
    >>> from hyperlattice.plots.bosons import plot_order_parameter
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> ax = plot_order_parameter(gutzwiller(lat, 0.1, 0.5), lat)
    >>> ax.get_title(), len(ax.lines[0].get_xdata())
    ('t/U = 0.1, μ/U = 0.5', 35)
    >>> plt.close("all")
    """
    ax = new_axes(ax, size=(5.0, 3.6))
    ring = np.asarray(lattice.ring)
    if ring.shape[0] != state.psi.shape[0]:
        raise ValueError("the lattice and the state have different numbers of sites.")
    ax.plot(ring + 0.15 * (np.random.default_rng(0).random(ring.shape[0]) - 0.5), state.psi, ".", ms=3)
    ax.set_xlabel("ring")
    ax.set_ylabel("ψ_i = ⟨a_i⟩")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.set_title(f"t/U = {state.t / state.U:.4g}, μ/U = {state.mu / state.U:.4g}", fontsize=9)
    return ax


def meanfield_figure(table: MottLobeTable, path=None):
    """Two panels, (a) the lobes and (b) the tips against l; saved to ``path`` when given. Returns the figure.

    Parameters
    ----------
    table : MottLobeTable
        Mean-field Mott lobes of several systems, from :func:`~hyperlattice.bosons.meanfield.mott_lobes`.
    path : str or path-like, optional
        Where to save the figure (130 dpi, format by suffix); not saved when None.

    Returns
    -------
    matplotlib.figure.Figure
        The 12 x 4.2 inch figure with the panels of :func:`plot_mott_lobes` and :func:`plot_lobe_tips`.

    Raises
    ------
    ValueError
        If ``path`` is not a writable file path.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.bosons.meanfield import mott_lobes
    >>> table = mott_lobes(7, 3, rings=(2, 3), points=21, infinite=False)
    >>> from hyperlattice.plots.bosons import meanfield_figure
    >>> fig = meanfield_figure(table)
    >>> [ax.texts[0].get_text() for ax in fig.axes]
    ['(a)', '(b)']
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12.0, 4.2), layout="constrained", width_ratios=(1.35, 1.0))
    plot_mott_lobes(table, ax=axes[0])
    plot_lobe_tips(table, ax=axes[1])
    for ax, letter in zip(axes, "ab"):
        ax.text(-0.12, 1.02, f"({letter})", transform=ax.transAxes, fontsize=11, fontweight="bold")
    if path is not None:
        from .. import _validate

        fig.savefig(_validate.output_path("path", path), dpi=130)
    return fig


def gp_comparison_figure(cmp: GPComparison, axes=None, path=None):
    """The Gross-Pitaevskii comparison of flakes and disks in three panels; returns the figure.

    (a) μ against ℓ, graph and continuum; (b) the density per site against the geodesic radius for
    the largest ℓ; (c) the lowest Bogoliubov frequencies against ℓ (the Goldstone mode omitted).

    Parameters
    ----------
    cmp : GPComparison
        The comparison, from :func:`~hyperlattice.compare.bosons.gp_comparison`.
    axes : sequence of three matplotlib.axes.Axes, optional
        Where to draw the three panels; a new 13 x 3.9 inch figure when None.
    path : str or path-like, optional
        Where to save the figure (130 dpi, format by suffix); not saved when None.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of the panels, labelled (a) to (c); energies in units of t.

    Raises
    ------
    ValueError
        If ``axes`` is not three axes, or ``path`` is not a writable file path.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.compare.bosons import gp_comparison
    >>> from hyperlattice.plots.bosons import gp_comparison_figure
    >>> fig = gp_comparison_figure(gp_comparison(7, 3, rings=(2,), U=0.5, modes=3, cells=200))
    >>> [ax.texts[0].get_text() for ax in fig.axes], fig.axes[0].get_title()
    (['(a)', '(b)', '(c)'], 'mean filling N/sites = 1, U = 0.5 t')
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt

    if axes is None:
        fig, axes = plt.subplots(1, 3, figsize=(13.0, 3.9), layout="constrained")
    else:
        axes = list(axes)
        if len(axes) != 3:
            raise ValueError("axes must be three matplotlib Axes.")
        fig = axes[0].figure
    ell = np.array([r["rings"] for r in cmp.rows])
    ax = axes[0]
    ax.plot(ell, [r["mu_graph"] for r in cmp.rows], "o", label="flake (discrete GP)")
    ax.plot(ell, [r["mu_continuum"] for r in cmp.rows], "s--", mfc="none", label="disk (continuum GP)")
    ax.set_xlabel("rings ℓ")
    ax.set_ylabel("μ / t")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.legend(fontsize=8, frameon=False)
    ax.set_title(f"mean filling N/sites = {cmp.filling:g}, U = {cmp.U:g} t", fontsize=9)
    ax = axes[1]
    prof = cmp.profiles[-1]
    ax.plot(prof["rho"], prof["graph"], "o", label=f"flake ℓ = {prof['rings']}, mean per ring")
    ax.plot(prof["rho"], prof["continuum"], "s--", mfc="none", label="disk, A|φ|² (A = area per site)")
    ax.axvline(prof["rho_max"], color="0.6", lw=0.8, ls=":", label="Dirichlet edge")
    ax.set_xlabel("geodesic radius ρ")
    ax.set_ylabel("bosons per site")
    ax.legend(fontsize=8, frameon=False)
    ax = axes[2]
    for r in cmp.rows:
        g, c = r["bogoliubov_graph"][1:], r["bogoliubov_continuum"][1:]
        ax.plot([r["rings"]] * len(g), g, "o", color="C0", ms=4, label="flake" if r is cmp.rows[0] else None)
        ax.plot([r["rings"] + 0.15] * len(c), c, "s", mfc="none", color="C1", ms=4,
                label="disk" if r is cmp.rows[0] else None)
    ax.set_yscale("log")
    ax.set_xlabel("rings ℓ")
    ax.set_ylabel("Bogoliubov ω / t (Goldstone mode omitted)")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.legend(fontsize=8, frameon=False)
    for ax, letter in zip(axes, "abc"):
        ax.text(-0.14, 1.02, f"({letter})", transform=ax.transAxes, fontsize=11, fontweight="bold")
    if path is not None:
        from .. import _validate

        fig.savefig(_validate.output_path("path", path), dpi=130)
    return fig


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
