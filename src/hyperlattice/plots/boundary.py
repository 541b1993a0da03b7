"""Figures below the band: boundary correlators, Δ(m²), the lattice BF bound, qubit exchange and sizes.

Each function draws on ``ax`` (a new figure when None) and returns the axes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.boundary import BoundaryCorrelator, DeltaCurve, LatticeBFBound
    from ..compare.qubits import BoundStateSizes, ExchangeComparison

__all__ = ["plot_boundary_correlator", "plot_delta_curve", "plot_bf_bound", "plot_exchange",
           "plot_bound_state_sizes"]


def _axes(ax, size=(5.2, 3.8)):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def plot_boundary_correlator(bc: BoundaryCorrelator, ax: Axes | None = None) -> Axes:
    r"""The boundary correlator on the outer ring against the angle, log-log; returns the axes.

    :math:`G_{ij}` on the outer ring against :math:`\sin(\theta/2)` (log-log): graph, continuum
    (``eq21`` on the disk named by ``bc.continuum_disk``) and the fitted conformal slope
    :math:`-2\Delta` over the window.

    Parameters
    ----------
    bc : BoundaryCorrelator
        The correlator of one source on the outer ring, from
        :func:`~hyperlattice.compare.boundary.boundary_correlator`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.2 x 3.8 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the graph points, the continuum points (when computed), the window edge
        :math:`\theta_{\min}` and the fitted power law, a legend and a title naming l, ω and m².

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.boundary import plot_boundary_correlator
    >>> ax = plot_boundary_correlator(hl.boundary_correlator(hl.ring_lattice(7, 3, 4), -3.5))
    >>> print(ax.get_title())
    $\ell = 4$, $\omega = -3.5$, $m^2 = 8.765$
    >>> ax.get_xscale(), len(ax.lines)
    ('log', 4)
    >>> plt.close("all")
    """
    from ..paper_labels import cite

    ax = _axes(ax)
    keep = np.asarray(bc.sites) != bc.source
    s = np.abs(np.sin(0.5 * np.asarray(bc.theta)[keep]))
    g = np.asarray(bc.graph)[keep]
    ax.loglog(s, g, ".", ms=2, color="tab:red", alpha=0.5, label=r"graph $G_{ij}$")
    c = np.asarray(bc.continuum)[keep]
    if np.any(np.isfinite(c)):
        disk = {"whole": "L = 1", "dirichlet": "Dirichlet disk of radius L",
                "mapped": "radius L, sites at the mean depth"}[bc.continuum_disk]
        ax.loglog(s, c, ".", ms=1.5, color="k", alpha=0.4, label=f"continuum ({cite('eq21')}, {disk})")
    s_min = np.sin(0.5 * bc.theta_min)
    ax.axvline(s_min, color="0.5", ls=":", lw=1, label=r"window edge $\theta_{\min}$")
    xs = np.geomspace(max(s_min, s.min()), 1.0, 20)
    sel = s >= s_min
    if np.any(sel):
        # the fitted slope drawn through the geometric mean of the windowed data
        a = np.exp(np.mean(np.log(g[sel]) + 2 * bc.delta_lattice * np.log(s[sel])))
        ax.loglog(xs, a * xs ** (-2 * bc.delta_lattice), "-", color="tab:blue", lw=1.2,
                  label=fr"fit $\Delta = {bc.delta_lattice:.3f} \pm {bc.delta_lattice_err:.3f}$")
    ax.set_xlabel(r"$\sin(\theta_{ij}/2)$")
    ax.set_ylabel(r"$G_{ij}(\omega)$")
    ax.set_title(fr"$\ell = {bc.rings}$, $\omega = {bc.omega:g}$, $m^2 = {bc.mass2:.3f}$", fontsize=10)
    ax.legend(fontsize=8)
    return ax


def plot_delta_curve(curves: Sequence[DeltaCurve], ax: Axes | None = None) -> Axes:
    r"""Δ against m² for one or more lattices (error bars) and the continuum Δ(m²), with the BF bound; returns the axes.

    Parameters
    ----------
    curves : sequence of DeltaCurve
        One curve per lattice, from :func:`~hyperlattice.compare.boundary.delta_curve`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.2 x 3.8 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the continuum :math:`\Delta = \frac12 + \frac12\sqrt{1 + m^2}` (from the BF
        bound m² = -1 on), the lattice Δ with its fit error bars for each curve and, as a wider
        light bar, the fit and systematic errors together, the BF bound as a dashed vertical line,
        and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.boundary import plot_delta_curve
    >>> dc = hl.delta_curve(hl.ring_lattice(7, 3, 4), [-3.5, -4.0])
    >>> ax = plot_delta_curve([dc])
    >>> print(ax.get_legend().get_texts()[-1].get_text())
    lattice $\ell = 4$
    >>> plt.close("all")
    """
    from ..continuum.massive import BF_MASS2, delta_from_mass2

    ax = _axes(ax)
    lo = min(float(np.min(c.mass2)) for c in curves)
    hi = max(float(np.max(c.mass2)) for c in curves)
    m2 = np.linspace(max(BF_MASS2, lo), hi, 200)
    ax.plot(m2, delta_from_mass2(m2), "k-", lw=1.2, label=r"continuum $\frac{1}{2} + \frac{1}{2}\sqrt{1+m^2}$")
    for c in curves:
        bars = ax.errorbar(c.mass2, c.delta_lattice, yerr=c.delta_lattice_err, fmt="o", ms=3, capsize=2,
                           label=fr"lattice $\ell = {c.rings}$")
        total = np.hypot(c.delta_lattice_err, np.nan_to_num(c.delta_lattice_sys))
        if np.any(np.isfinite(c.delta_lattice_sys)):
            # the systematic error (finite l, lattice spacing) beside the fit's, as a lighter bar
            ax.errorbar(c.mass2, c.delta_lattice, yerr=total, fmt="none", lw=4, alpha=0.25,
                        color=bars[0].get_color())
    ax.axvline(BF_MASS2, color="0.5", ls="--", lw=1, label="continuum BF bound $m^2 = -1$")
    ax.set_xlabel(r"$m^2 = -\lambda = -4(\omega+q)/(qh^2)$")
    ax.set_ylabel(r"$\Delta$")
    ax.legend(fontsize=8)
    return ax


def plot_bf_bound(bf: LatticeBFBound, ax: Axes | None = None) -> Axes:
    r"""Lattice BF bound :math:`E_0(\ell)` against ℓ with the continuum bound :math:`E_\infty`; returns the axes.

    Parameters
    ----------
    bf : LatticeBFBound
        The lowest flake levels against l, from :func:`~hyperlattice.compare.boundary.lattice_bf_bound`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.2 x 3.8 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with :math:`E_0(\ell)` (points and line) and the dashed continuum
        :math:`E_\infty = -q + \frac{q}{4}h^2`, and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.compare.boundary import lattice_bf_bound
    >>> from hyperlattice.plots.boundary import plot_bf_bound
    >>> ax = plot_bf_bound(lattice_bf_bound(7, 3, rings=(3, 4)))
    >>> len(ax.lines), ax.lines[0].get_xdata().tolist()
    (2, [3, 4])
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(bf.rings, bf.e0, "o-", color="tab:red", label=r"lattice $E_0(\ell)$")
    ax.axhline(bf.omega_continuum, color="k", ls="--", label=r"continuum $E_\infty = -q + \frac{q}{4}h^2$")
    ax.set_xlabel(r"rings $\ell$")
    ax.set_ylabel(r"BF bound $\omega$")
    ax.legend(fontsize=8)
    return ax


def plot_exchange(ex: ExchangeComparison, ax: Axes | None = None) -> Axes:
    r"""``|J|`` against hyperbolic distance (log axis): graph points, binned means, and the continuum; returns the axes.

    J can change sign (the continuum's does near the disk edge): ``|J|`` is drawn, negative values with
    open markers (graph) or a dashed line (continuum), so that nothing drops off the log axis unseen.

    Parameters
    ----------
    ex : ExchangeComparison
        The qubit exchange couplings of graph and continuum, from
        :func:`~hyperlattice.compare.qubits.exchange_comparison`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.2 x 3.8 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log y) with the graph couplings, their binned means, the continuum's binned means
        and a legend; the title names the kind of lattice, l and the qubit frequency.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.boundary import plot_exchange
    >>> ax = plot_exchange(hl.exchange_comparison(hl.ring_lattice(7, 3, 4), -3.2, 0.1))
    >>> print(ax.get_title())
    sites, $\ell = 4$, $\omega_q = -3.2$
    >>> ax.get_yscale()
    'log'
    >>> plt.close("all")
    """
    from ..paper_labels import cite

    ax = _axes(ax)
    keep = np.isfinite(np.asarray(ex.continuum))
    d, g = np.asarray(ex.distance)[keep], np.asarray(ex.graph)[keep]
    pos = g > 0
    ax.semilogy(d[pos], g[pos], ".", ms=2, color="tab:red", alpha=0.4, label="graph $g^2 G_{ij}$")
    if np.any(~pos):
        ax.semilogy(d[~pos], -g[~pos], "o", ms=3, mfc="none", color="tab:red", alpha=0.6, label="graph, $J < 0$")
    bins = np.asarray(ex.bins)
    gm, cm = np.asarray(ex.graph_mean), np.asarray(ex.continuum_mean)
    ax.semilogy(bins[gm > 0], gm[gm > 0], "o", ms=3, color="tab:red", label="graph (binned mean)")
    if np.any(gm < 0):
        ax.semilogy(bins[gm < 0], -gm[gm < 0], "o", ms=4, mfc="none", color="tab:red", label="graph mean, $J < 0$")
    pos_c = np.where(cm > 0, cm, np.nan)
    neg_c = np.where(cm < 0, -cm, np.nan)
    ax.semilogy(bins, pos_c, "k-", lw=1.2, label=f"continuum ({cite('eq21')}, binned mean)")
    if np.any(cm < 0):
        ax.semilogy(bins, neg_c, "k--", lw=1.2, label="continuum, $J < 0$ ($|J|$ shown)")
    ax.set_xlabel("hyperbolic distance")
    ax.set_ylabel(r"$|J|$")
    ax.set_title(fr"{ex.kind}, $\ell = {ex.rings}$, $\omega_q = {ex.omega_q:g}$", fontsize=10)
    ax.legend(fontsize=8)
    return ax


def plot_bound_state_sizes(bs: BoundStateSizes, ax: Axes | None = None) -> Axes:
    r"""Bound-state size and decay length against detuning from the band bottom; returns the axes.

    Parameters
    ----------
    bs : BoundStateSizes
        Sizes of the qubit-photon bound states, from
        :func:`~hyperlattice.compare.qubits.bound_state_sizes`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new 5.2 x 3.8 inch figure when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes (log x) with the mean distance :math:`\langle d\rangle` of graph and continuum, the
        graph decay length ξ, the continuum :math:`1/(2\Delta)` and the line 2R = 1, all hyperbolic
        distances against the detuning :math:`E_0(\ell) - \omega_q`.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.qubits import bound_state_sizes
    >>> from hyperlattice.plots.boundary import plot_bound_state_sizes
    >>> ax = plot_bound_state_sizes(bound_state_sizes(hl.ring_lattice(7, 3, 4), [-3.0, -3.5], 0.1))
    >>> ax.get_xscale(), ax.get_ylabel(), len(ax.lines)
    ('log', 'hyperbolic distance', 5)
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(bs.detuning, bs.size_graph, "o-", color="tab:red", label=r"$\langle d\rangle$ graph (exact)")
    if np.any(np.isfinite(bs.size_continuum)):
        ax.plot(bs.detuning, bs.size_continuum, "s--", color="k", ms=3, label=r"$\langle d\rangle$ continuum")
    ax.plot(bs.detuning, bs.decay_length_graph, "^-", color="tab:blue", ms=3, label=r"decay length $\xi$ graph")
    ax.plot(bs.detuning, bs.decay_length_asymptotic, "k:", label=r"$1/(2\Delta)$ continuum")
    ax.axhline(1.0, color="0.6", lw=0.8, ls="-.", label=r"$2R = 1$ (BF-bound limit of $1/(2\Delta)$)")
    ax.set_xscale("log")
    ax.set_xlabel(r"detuning $E_0(\ell) - \omega_q$")
    ax.set_ylabel("hyperbolic distance")
    ax.legend(fontsize=7)
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
