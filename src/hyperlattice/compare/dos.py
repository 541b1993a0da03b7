r"""Densities of states of the infinite {p,q} lattice: periodic clusters, flake interiors, the
Abelian Bloch DOS and exact moments, against each other and against the continuum.

What converges to what
----------------------
The reference is exact: the closed-walk counts :math:`W_n` of the infinite lattice
(:func:`hyperlattice.graph.walks.closed_walks`, integers, n < ``resolution``) give its Chebyshev
moments without error (:func:`~hyperlattice.graph.walks.chebyshev_from_walks`), hence its DOS
smoothed by the Jackson kernel of ``resolution`` moments. Every other route is compared with it at
that same resolution, by the :math:`L^1` distance :math:`\int|\rho_A - \rho_{\rm exact}|\,dE`
(0 = identical, 2 = disjoint):

* periodic clusters (KPM stochastic trace over all sites, the :math:`E = -q` uniform state left
  out): exact for the first moments below the systole, and converging as the clusters grow;
* flake interiors (:func:`~hyperlattice.graph.kpm.bulk_dos`): exact up to ``exact_moments``
  (proven), which grows by about 4 per 2 rings; beyond it the boundary leaks in;
* the Abelian DOS of the smallest clusters (:func:`hyperlattice.graph.bands.abelian_dos`, if that
  module is there), whose moments are exact only below the unit cell's systole (the Abelian
  states miss the non-Abelian part of the translation group).

The uniform state and the band bottom
-------------------------------------
Every periodic cluster is q-regular, so :math:`E = -q` is an eigenvalue (the constant vector),
with weight 1/N; a bipartite cluster also has :math:`E = +q`. The infinite lattice is
non-amenable: its spectrum starts at :math:`-\rho` with :math:`\rho < q` (Kesten), proven here to
lie in :math:`[\rho_{\rm low}, \rho_{\rm up}]` from the exact walks and the isoperimetric bound
(:func:`~hyperlattice.graph.walks.spectral_radius`). So a cluster's ground state says nothing about
the band bottom; neither do its lowest non-uniform levels individually (Greenberg's theorem only
says that for covers of growing size :math:`\liminf \lambda_2 \ge \rho`, i.e. levels *below*
:math:`-\rho` may persist, with vanishing weight). The band bottom is a property of the limiting
density: we read the edges as quantiles of the DOS (the energy below which a fraction
``quantile`` of the states lie), with error bars from the kernel width and the random vectors.

The continuum side
------------------
The density of states of :math:`-\Delta_g` on the hyperbolic plane of curvature -4 (the paper's
metric) per unit area is the Plancherel density :math:`\frac{1}{4\pi}\tanh(\pi k/2)` per unit
:math:`\lambda = 1 + k^2` (for curvature -1 it is :math:`\frac1{4\pi}\tanh(\pi k')` with
:math:`\lambda' = \frac14 + k'^2`; scaling lengths by 1/2 gives :math:`k = 2k'`; its large-k limit
is Weyl's :math:`1/4\pi`). Per lattice site (area :math:`\mathcal A`) and through the dictionary
(:func:`hyperlattice.dictionary.lambda_from_energy`, or the improved map),

.. math:: N_{\rm cont}(E) = \frac{\mathcal A}{4\pi}\int_1^{\lambda(E)}\tanh\Big(\frac\pi2\sqrt{\lambda'-1}\Big)
          d\lambda' \approx \frac{\mathcal A}{12}k^3 \quad (k \to 0).

It starts at :math:`E = -q + \frac q4 h^2` (paper's map), and is valid only near the band bottom,
where the lattice eigenfunctions vary slowly on the scale of a bond. :class:`DosComparison`
measures where it holds by comparing the quantile energies :math:`E(\nu)` of both sides.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .. import _validate, dictionary, geometry
from .._ties import monotone_tolerance
from ..results import Column, Grid, Result


__all__ = ["continuum_dos", "continuum_integrated_dos", "jackson_density", "DosComparison", "dos_comparison",
           "quantile_energy", "DEFAULT_CLUSTERS"]

#: clusters used by default, smallest first (names of :func:`hyperlattice.graph.clusters.pbc_cluster`)
DEFAULT_CLUSTERS = {
    (7, 3): ("klein", "PSL(2,13)", "PSL(2,29)", "PSL(2,71)"),
    (8, 3): ("bolza", "dyck", "PSL(2,17)", "PSL(2,31)", "PSL(2,79)"),
}
#: quantiles at which the continuum and lattice integrated DOS are compared
QUANTILES = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.2, 0.3)


# ----------------------------------------------------------------------------
# continuum
# ----------------------------------------------------------------------------

@functools.lru_cache(maxsize=1)
def _num(value, spec: str) -> str:
    """``value`` formatted by ``spec`` with a true minus sign, for a sentence (−2.9412, not -2.9412)."""
    return format(float(value), spec).replace("-", "−")


def _plancherel_table() -> tuple[np.ndarray, np.ndarray]:
    """k on [0, 200] (step 1e-3) and F(k) by the cumulative trapezoid rule, whose error the
    Euler-Maclaurin end correction -dk^2/12 [f'(k) - f'(0)] removes to O(dk^4) (relative < 1e-9)."""
    k = np.linspace(0.0, 200.0, 200_001)
    x = 0.5 * math.pi * k
    f = 2.0 * k * np.tanh(x)
    fp = 2.0 * np.tanh(x) + math.pi * k / np.cosh(np.minimum(x, 300.0)) ** 2  # f'(k); f'(0) = 0
    dk = k[1] - k[0]
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dk)]) - dk * dk / 12.0 * fp
    return k, cum


def _plancherel_integral(k: np.ndarray) -> np.ndarray:
    r""":math:`F(k) = \int_0^k 2u\tanh(\pi u/2)\,du` (= :math:`\int_1^{1+k^2}\tanh(\frac\pi2\sqrt{\lambda'-1})d\lambda'`).

    :math:`F/k^2` (smooth: :math:`\pi k/3` at 0, 1 at infinity) is interpolated linearly in a table on
    [0, 200] (relative error below 1e-6); beyond, :math:`F(200) + k^2 - 200^2` (tanh = 1 there)."""
    kt, ft = _plancherel_table()
    g = np.concatenate([[0.0], ft[1:] / kt[1:] ** 2])
    k = np.asarray(k, dtype=float)
    return np.where(k <= kt[-1], k * k * np.interp(k, kt, g), ft[-1] + k * k - kt[-1] ** 2)


def _improved_table(p: int, q: int) -> tuple[np.ndarray, np.ndarray]:
    """(lambda, E) of the improved map on [1, lambda_*], where E rises monotonically."""
    d0 = geometry.d0(p, q)
    lam = 1.0 + np.linspace(0.0, 2.0 * (3.9 / (2.0 * d0)), 3001) ** 2
    e = np.asarray(dictionary.improved_energy_from_lambda(lam, p, q), dtype=float)
    # the monotone branch ends where E stops rising; steps within rounding of zero (at the
    # maximum) count as not rising, so the end does not move with the last bits of E
    flat = np.diff(e) <= monotone_tolerance(e)
    stop = int(np.argmax(flat)) if np.any(flat) else e.size - 1
    return lam[: stop + 1], e[: stop + 1]


def _lambda_of(energies: np.ndarray, p: int, q: int, which: str) -> np.ndarray:
    """lambda(E) by the chosen map; below the continuum band bottom lambda <= 1 (no states). The
    improved map is inverted by interpolation in a table of E(lambda) (3001 points, monotone
    branch), beyond which lambda is held at the branch's end."""
    if which == "paper":
        return np.asarray(dictionary.lambda_from_energy(energies, p, q), dtype=float)
    lam, e = _improved_table(p, q)
    return np.where(energies < e[0], 0.0, np.interp(energies, e, lam))


def _lambda_at_quantile(nu: float, p: int, q: int) -> float:
    """The lambda below which a fraction nu of the continuum states per site lie (any map)."""
    k, f = _plancherel_table()
    n = geometry.site_area(p, q) / (4.0 * math.pi) * f
    kn = float(np.interp(nu, n, k))
    # one Newton step on the exact integrand removes the interpolation error
    dn = geometry.site_area(p, q) / (4.0 * math.pi) * 2.0 * kn * math.tanh(0.5 * math.pi * kn)
    if dn > 0:
        kn -= (geometry.site_area(p, q) / (4.0 * math.pi) * float(_plancherel_integral(np.array([kn]))[0]) - nu) / dn
    return 1.0 + kn * kn


def continuum_integrated_dos(energies, p: int = 7, q: int = 3, *, dictionary_name: str = "paper") -> np.ndarray:
    r"""Continuum states per site below E: :math:`\frac{\mathcal A}{4\pi}F(k(E))` (module docstring),
    zero below the continuum's band bottom.

    Parameters
    ----------
    energies : array_like of float, shape (K,)
        Lattice energies E (units of t).
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    dictionary_name : {"paper", "improved"}, optional
        The map between lattice energy and :math:`\lambda`: the paper's
        :math:`E = -q + \frac q4 h^2\lambda` or the improved one
        (:mod:`hyperlattice.dictionary`). Default ``"paper"``.

    Returns
    -------
    ndarray of float, shape (K,)
        The integrated density of states per site of :math:`-\Delta_g` (Plancherel measure,
        :math:`\lambda = 1 + k^2`) below each E, :math:`\mathcal A` the area per site.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic, ``energies`` is not a finite 1-d array or the dictionary is
        unknown.

    See Also
    --------
    continuum_dos : its derivative in E.

    Examples
    --------
    >>> from hyperlattice.compare.dos import continuum_integrated_dos
    >>> [round(float(n), 6) for n in continuum_integrated_dos([-3.0, -2.5, -2.0], 7, 3)]
    [0.0, 0.066355, 0.144604]
    """
    p, q = _validate.pq(p, q)
    which = _validate.choice("dictionary_name", dictionary_name, dictionary.DICTIONARIES)
    e = _validate.real_array("energies", energies, ndim=1)
    lam = _lambda_of(e, p, q, which)
    k = np.sqrt(np.maximum(lam - 1.0, 0.0))
    return geometry.site_area(p, q) / (4.0 * math.pi) * _plancherel_integral(k)


def continuum_dos(energies, p: int = 7, q: int = 3, *, dictionary_name: str = "paper") -> np.ndarray:
    r"""Continuum density of states per site :math:`\frac{\mathcal A}{4\pi}\tanh(\pi k/2)\,d\lambda/dE`
    at the lattice energies ``energies`` (paper's map: :math:`d\lambda/dE = 4/(qh^2)`; improved map:
    numerical derivative); zero below the continuum band bottom.

    Parameters
    ----------
    energies : array_like of float, shape (K,)
        Lattice energies E (units of t).
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    dictionary_name : {"paper", "improved"}, optional
        The map between lattice energy and :math:`\lambda`: the paper's
        :math:`E = -q + \frac q4 h^2\lambda` or the improved one
        (:mod:`hyperlattice.dictionary`). Default ``"paper"``.

    Returns
    -------
    ndarray of float, shape (K,)
        Density of states per site and unit energy (units of 1/t), :math:`\mathcal A` the area
        per site, :math:`\lambda = 1 + k^2`.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic, ``energies`` is not a finite 1-d array or the dictionary is
        unknown.

    See Also
    --------
    continuum_integrated_dos : the states below E.

    Examples
    --------
    >>> from hyperlattice.compare.dos import continuum_dos
    >>> [round(float(r), 6) for r in continuum_dos([-3.0, -2.5, -2.0], 7, 3)]
    [0.0, 0.15646, 0.156508]
    >>> round(float(continuum_dos([-2.5], dictionary_name="improved")[0]), 6)
    0.164462
    """
    p, q = _validate.pq(p, q)
    which = _validate.choice("dictionary_name", dictionary_name, dictionary.DICTIONARIES)
    e = _validate.real_array("energies", energies, ndim=1)
    lam = _lambda_of(e, p, q, which)
    k = np.sqrt(np.maximum(lam - 1.0, 0.0))
    if which == "paper":
        dlam = np.full_like(e, 1.0 / dictionary.hopping_scale(p, q))
    else:
        step = 1e-6
        dlam = (_lambda_of(e + step, p, q, which) - _lambda_of(e - step, p, q, which)) / (2 * step)
    return np.where(lam > 1.0, geometry.site_area(p, q) / (4.0 * math.pi) * np.tanh(0.5 * math.pi * k) * dlam, 0.0)


# ----------------------------------------------------------------------------
# helpers on moments
# ----------------------------------------------------------------------------

def jackson_density(mu, scale: float, energies) -> np.ndarray:
    r"""The Jackson-smoothed density of states :math:`\rho(E)` of the Chebyshev moments ``mu`` of
    :math:`H/a` (``scale`` a), at ``energies`` (zero outside :math:`|E| < a`).

    .. math:: \rho(E) = \frac{1}{\pi\sqrt{a^2 - E^2}}\Bigl[g_0\mu_0
              + 2\sum_{n\ge1} g_n\mu_n T_n(E/a)\Bigr],

    :math:`g_n` the Jackson kernel of ``len(mu)`` moments.

    Parameters
    ----------
    mu : array_like of float, shape (M,)
        Chebyshev moments :math:`\mu_n = \mathrm{tr}\,T_n(H/a)/N`.
    scale : float
        The scale a > 0 (units of t), larger than the spectral radius of H.
    energies : array_like of float, shape (K,)
        Where to evaluate (units of t).

    Returns
    -------
    ndarray of float, shape (K,)
        Density of states per site and unit energy (units of 1/t).

    Raises
    ------
    ValueError
        If ``mu`` or ``energies`` is not a finite 1-d array or ``scale`` is not positive.

    See Also
    --------
    hyperlattice.graph.kpm.jackson_kernel

    Examples
    --------
    >>> from hyperlattice.compare.dos import jackson_density
    >>> rho = jackson_density([1.0, 0.0, 0.0, 0.0], 1.0, [0.0])
    >>> round(float(rho[0]), 6)   # 1/pi: the arcsine density at its centre
    0.31831
    """
    from ..graph.kpm import jackson_kernel

    mu = _validate.real_array("mu", mu, ndim=1)
    a = _validate.positive_real("scale", scale)
    e = _validate.real_array("energies", energies, ndim=1)
    x = e / a
    inside = np.abs(x) < 1
    theta = np.arccos(np.clip(x, -1, 1))
    m = mu.shape[0]
    w = np.where(np.arange(m) == 0, 1.0, 2.0) * jackson_kernel(m) * mu
    pref = np.where(inside, 1.0 / (math.pi * a * np.sqrt(np.maximum(1 - x * x, 1e-300))), 0.0)
    return pref * (np.cos(np.outer(theta, np.arange(m))) @ w)


def quantile_energy(energies, integrated, quantile: float) -> float:
    r"""The lowest energy at which the (non-decreasing in the mean) integrated DOS reaches ``quantile``,
    linearly interpolated between grid points; NaN if it never does.

    Parameters
    ----------
    energies : array_like of float, shape (K,)
        Increasing energy grid (units of t), not empty.
    integrated : array_like of float, shape (K,)
        Integrated density of states per site on that grid (its running maximum is used, so
        rounding wiggles do not matter).
    quantile : float
        The fraction of states :math:`\nu`.

    Returns
    -------
    float
        :math:`E(\nu)` (units of t): the first grid energy if ``integrated`` already reaches
        ``quantile`` there, NaN if it never does.

    Raises
    ------
    ValueError
        If the arrays are not finite, of different shapes or empty.

    Examples
    --------
    >>> from hyperlattice.compare.dos import quantile_energy
    >>> quantile_energy([0.0, 1.0, 2.0], [0.0, 0.5, 1.0], 0.25)
    0.5
    >>> quantile_energy([0.0, 1.0, 2.0], [0.0, 0.5, 1.0], 2.0)
    nan
    """
    e = _validate.real_array("energies", energies, ndim=1)
    n = _validate.real_array("integrated", integrated, shape=e.shape)
    quantile = _validate.real("quantile", quantile)
    if e.shape[0] == 0:
        raise ValueError("energies must not be empty.")
    n = np.maximum.accumulate(n)  # the smoothed N may wiggle by rounding
    i = int(np.searchsorted(n, quantile))
    if i >= e.shape[0]:
        return math.nan
    if i == 0:
        return float(e[0])
    f = (quantile - n[i - 1]) / (n[i] - n[i - 1]) if n[i] > n[i - 1] else 0.0
    return float(e[i - 1] + f * (e[i] - e[i - 1]))


def _integrated_tables(res, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """(grid, N of the mean moments, [N of each leave-one-out mean]) on 2001 energies in [lo, hi]."""
    from ..graph.kpm import jackson_kernel

    grid = np.linspace(lo, hi, 2001)
    m = res.moments
    theta = np.arccos(np.clip(grid / res.scale, -1, 1))
    base = np.empty((grid.shape[0], m))
    base[:, 0] = (math.pi - theta) / math.pi
    nn = np.arange(1, m)
    base[:, 1:] = -np.sin(np.outer(theta, nn)) / (nn[None, :] * math.pi)
    w = np.where(np.arange(m) == 0, 1.0, 2.0) * jackson_kernel(m)
    n_mean = base @ (w * res.mu)
    jack = []
    r = res.vectors
    if r > 2 and res.method != "local":
        total = res.mu_vectors.sum(axis=0)
        mus = (total[None, :] - res.mu_vectors) / (r - 1)  # leave-one-out means
        jack = list((mus * w[None, :]) @ base.T)
        jack = [(j, float(mu[0])) for j, mu in zip(jack, mus)]
    return grid, n_mean, jack


def _quantile_with_error(res, quantile: float, lo: float, hi: float, top: bool = False,
                         tables=None) -> tuple[float, float]:
    """Quantile energy of a KPM result (bottom, or top with ``top``) and its error bar: the
    jackknife standard error over the random vectors combined with the kernel width there."""
    grid, n_mean, jack = tables if tables is not None else _integrated_tables(res, lo, hi)
    total = float(res.mu[0])  # (N - deflated)/N for a deflated trace, 1 otherwise
    if top:
        ebest = _top_quantile(grid, n_mean, total - quantile)
    else:
        ebest = quantile_energy(grid, n_mean, quantile)
    if not math.isfinite(ebest):
        return math.nan, math.nan
    stat = 0.0
    if jack:
        vals = np.asarray([_top_quantile(grid, nj, tot - quantile) if top else quantile_energy(grid, nj, quantile)
                           for nj, tot in jack])
        r = len(jack)
        stat = float(math.sqrt((r - 1) / r * np.nansum((vals - np.nanmean(vals)) ** 2)))
    width = res.kernel_width(min(max(ebest, -0.999 * res.scale), 0.999 * res.scale))
    return ebest, float(math.hypot(stat, width))


def _top_quantile(grid, n, target) -> float:
    """The highest energy at which N(E) is still below ``target`` (for the top edge)."""
    n = np.minimum.accumulate(np.asarray(n)[::-1])[::-1]  # non-decreasing from the top down
    i = int(np.searchsorted(n, target, side="right")) - 1
    if i < 0 or i >= grid.shape[0] - 1:
        return math.nan
    f = (target - n[i]) / (n[i + 1] - n[i]) if n[i + 1] > n[i] else 0.0
    return float(grid[i] + f * (grid[i + 1] - grid[i]))


# ----------------------------------------------------------------------------
# the comparison
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class DosComparison(Result):
    r"""Densities of states of one {p,q} lattice by several routes, and the measured comparison.

    Energies are those of :math:`H = -tA` in units of t; densities are per site and per unit
    energy (1/t).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    moments : int
        Chebyshev moments of the full-resolution curves.
    resolution : int
        Moments of the comparison with the exact DOS (``distance``, ``density_resolved``).
    quantile : float
        :math:`\nu` of the quantile band edges ``bottom`` and ``top``.
    energies : ndarray (K,)
        Energy grid of the densities.
    labels, kinds : list of str
        One per curve; kind "cluster", "flake" or "abelian".
    sites : ndarray (C,)
        Sites of each cluster/flake (unit-cell sites for "abelian").
    density, density_err : ndarray (C, K)
        Density per site at the full resolution (``moments``; the Abelian histogram interpolated).
    reference : ndarray (K,)
        Exact infinite-lattice DOS at ``resolution`` moments (from closed walks).
    distance, distance_err : ndarray (C,)
        :math:`\int|\rho - \rho_{\rm exact}|dE` at ``resolution`` moments, with its error bar.
    exact_moments : ndarray (C,)
        Moments proven (or, for clusters, known: below the systole) equal to the lattice's.
    bottom, bottom_err, top, top_err : ndarray (C,)
        Quantile band edges :math:`E(\nu)` and :math:`E(1-\nu)`, ``nu = quantile``, with error bars
        (kernel width and random vectors); NaN for the Abelian curve.
    rho_lower, rho_upper : float
        Proven bounds on :math:`\rho`: the band bottom of the infinite lattice is in
        :math:`[-\rho_{\rm up}, -\rho_{\rm low}]`.
    continuum_bottom : dict
        Continuum band bottom by dictionary ("paper", "improved").
    quantiles, quantile_lattice, quantile_lattice_err, quantile_continuum : ndarray
        Energies :math:`E(\nu)` of the largest cluster and of the continuum (paper's map) at each
        :math:`\nu` of ``quantiles``.
    quantile_improved : ndarray
        The continuum's :math:`E(\nu)` with the improved map.
    density_resolved : ndarray (C, K)
        Each curve at the ``resolution`` of the exact comparison (what ``distance`` measures).
    ratio_band : ndarray (3, Q)
        :math:`N_{\rm cont}(E)/\nu` at :math:`E = E_{\rm latt}(\nu)` and at :math:`E \mp 2` error bars
        (:meth:`continuum_ratio`).
    bottom_energies, bottom_integrated, bottom_integrated_err : ndarray
        Integrated DOS of the largest cluster near the band bottom (``bottom_label`` says which run).
    bottom_label : str
        The run behind ``bottom_integrated`` (cluster and moments), or "".
    timings : dict
        Wall-clock seconds of the stages.
    notes : list of str
        What was left out and why (e.g. the Abelian DOS when graph/bands.py is absent).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> cmp.labels, cmp.kinds, cmp.moments, cmp.resolution
    (['flake interior, 3 rings (35 of 112 sites)'], ['flake'], 32, 8)
    >>> print(f"{cmp.distance[0]:.4f} {cmp.rho_lower:.4f} {cmp.rho_upper:.4f}")
    0.3291 2.8284 2.9665
    >>> cmp.continuum_window(0.1), cmp.continuum_exceptions(0.1)   # no cluster: nothing agrees
    (0.0, [])
    """

    #: one row per curve (cluster, flake or Abelian): its size and its measured distance and band edges
    COLUMNS = (Column("label", "curve", "text"), Column("kind", "curve_kind", "text"), Column("sites", "sites", "1"),
               Column("distance", "distance", "1"), Column("distance_err", "distance_err", "1"),
               Column("exact_moments", "exact_moments", "1"), Column("bottom", "bottom", "t"),
               Column("bottom_err", "bottom_err", "t"), Column("top", "top", "t"), Column("top_err", "top_err", "t"))
    #: the densities on the (curve, energy) grid, with the exact infinite-lattice reference
    GRID = Grid(coords=(Column("curve", "curve", "text"), Column("energy", "energies", "t")),
                variables=(Column("density", "density", "1/t per site", ("curve", "energy")),
                           Column("density_err", "density_err", "1/t per site", ("curve", "energy")),
                           Column("reference", "reference", "1/t per site", ("energy",))))

    @property
    def curve(self) -> np.ndarray:
        """The curves' labels as an array (the rows of the table)."""
        return np.array(self.labels, dtype=str)

    @property
    def curve_kind(self) -> np.ndarray:
        """Each curve's kind: "cluster", "flake" or "abelian"."""
        return np.array(self.kinds, dtype=str)

    p: int
    q: int
    moments: int
    resolution: int
    quantile: float
    energies: np.ndarray
    labels: list
    kinds: list
    sites: np.ndarray
    density: np.ndarray
    density_err: np.ndarray
    reference: np.ndarray
    distance: np.ndarray
    distance_err: np.ndarray
    exact_moments: np.ndarray
    bottom: np.ndarray
    bottom_err: np.ndarray
    top: np.ndarray
    top_err: np.ndarray
    rho_lower: float
    rho_upper: float
    continuum_bottom: dict
    quantiles: np.ndarray
    quantile_lattice: np.ndarray
    quantile_lattice_err: np.ndarray
    quantile_continuum: np.ndarray
    quantile_improved: np.ndarray
    density_resolved: np.ndarray
    ratio_band: np.ndarray
    bottom_energies: np.ndarray
    bottom_integrated: np.ndarray
    bottom_integrated_err: np.ndarray
    bottom_label: str = ""
    notes: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)

    def table(self) -> list[dict]:
        """One row per curve: label, kind, sites, exact moments, distance, band edges."""
        return [{"label": self.labels[i], "kind": self.kinds[i], "sites": int(self.sites[i]),
                 "exact_moments": int(self.exact_moments[i]), "distance": float(self.distance[i]),
                 "distance_err": float(self.distance_err[i]), "bottom": float(self.bottom[i]),
                 "bottom_err": float(self.bottom_err[i]), "top": float(self.top[i]), "top_err": float(self.top_err[i])}
                for i in range(len(self.labels))]

    def continuum_ratio(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r"""Per quantile :math:`\nu`: :math:`N_{\rm cont}(E_{\rm latt}(\nu))/\nu` (paper's map), the fraction
        of states the continuum puts below the lattice's :math:`E(\nu)` relative to the lattice's, and the
        same at :math:`E(\nu) \mp 2` error bars (low, high): 1 = agreement (stored ``ratio_band``)."""
        band = np.asarray(self.ratio_band, dtype=float).reshape(3, -1)
        return band[0], band[1], band[2]

    def continuum_agreement(self, tolerance: float = 0.1) -> np.ndarray:
        r"""Per quantile :math:`\nu`: does the continuum count the same states below the lattice's
        :math:`E(\nu)` within ``tolerance`` (relative), allowing two error bars of :math:`E(\nu)`?

        Parameters
        ----------
        tolerance : float, optional
            Relative tolerance on the state count, > 0; default 0.1.

        Returns
        -------
        numpy.ndarray of bool
            One entry per ``quantiles``.
        """
        tol = _validate.positive_real("tolerance", tolerance)
        _, lo, hi = self.continuum_ratio()
        return np.where(np.isfinite(lo) & np.isfinite(hi), (hi >= 1 - tol) & (lo <= 1 + tol), False)

    def continuum_window(self, tolerance: float = 0.1) -> float:
        r"""The largest :math:`\nu` up to which the continuum agrees (:meth:`continuum_agreement`), walking up
        from the band bottom and stopping at the first two consecutive disagreements (an isolated one
        below is an exception, listed by :meth:`continuum_exceptions`: the cluster's integrated DOS is
        a staircase of its lowest multiplets, wider than the kernel's error bar); 0 if none agrees.

        Parameters
        ----------
        tolerance : float, optional
            As in :meth:`continuum_agreement`; default 0.1.

        Returns
        -------
        float
            The quantile :math:`\nu` (a fraction of the states).
        """
        ok = list(self.continuum_agreement(tolerance))
        good = 0.0
        for i, (nu, o) in enumerate(zip(self.quantiles, ok)):
            if not o and (i + 1 == len(ok) or not ok[i + 1]):
                break
            if o:
                good = float(nu)
        return good

    def continuum_exceptions(self, tolerance: float = 0.1) -> list[float]:
        """Quantiles below :meth:`continuum_window` where the continuum disagrees (isolated).

        Parameters
        ----------
        tolerance : float, optional
            As in :meth:`continuum_agreement`; default 0.1.

        Returns
        -------
        list of float
            The quantiles :math:`\\nu`.
        """
        w = self.continuum_window(tolerance)
        return [float(nu) for nu, o in zip(self.quantiles, self.continuum_agreement(tolerance)) if not o and nu < w]

    def statement(self) -> str:
        """Plain sentences from the data: convergence, band edges, where the continuum holds."""
        i_cl = [i for i, k in enumerate(self.kinds) if k == "cluster"]
        i_fl = [i for i, k in enumerate(self.kinds) if k == "flake"]
        parts = []
        if i_cl:
            a, b = i_cl[0], i_cl[-1]
            parts.append(f"At the resolution of {self.resolution} moments the cluster DOS approaches the exact "
                         f"infinite-lattice DOS as the clusters grow (L1 distance {self.distance[a]:.2g} at "
                         f"{int(self.sites[a])} sites, {self.distance[b]:.2g} at {int(self.sites[b])} sites).")
        if i_fl:
            a, b = i_fl[0], i_fl[-1]
            parts.append(f"Flake interiors are exact up to their proven moment ({int(self.exact_moments[a])} to "
                         f"{int(self.exact_moments[b])}) and then feel the boundary (distance {self.distance[a]:.2g}"
                         f" to {self.distance[b]:.2g}).")
        if "abelian" in self.kinds:
            i = self.kinds.index("abelian")
            same = [j for j in i_cl if self.sites[j] == self.sites[i]]
            own = f" (the {int(self.sites[i])}-site cell itself: {self.distance[same[0]]:.2g})" if same else ""
            parts.append(f"The Abelian DOS ({self.labels[i]}) is at distance {self.distance[i]:.2g}{own}: "
                         "sampling the Bloch phases on the 2g-torus removes most of the finite-size error of its "
                         "unit cell, but its moments are exact only below the cell's systole.")
        parts.append(f"Every periodic cluster has the uniform state at E = −{self.q} (weight 1/N), which is not in "
                     f"the spectrum of the infinite lattice: its band bottom −ρ is proven to lie in "
                     f"[{_num(-self.rho_upper, '.4f')}, {_num(-self.rho_lower, '.4f')}], so the band bottom must be "
                     "read from the "
                     f"limiting density (the uniform state is left out here), not from a cluster's ground state.")
        if i_cl:
            b = i_cl[-1]
            parts.append(f"The {self.quantile:g} quantile of the largest cluster's DOS is "
                         f"E = {_num(self.bottom[b], '.4f')} ± {self.bottom_err[b]:.4f} (bottom) and "
                         f"{_num(self.top[b], '.4f')} ± {self.top_err[b]:.4f} (top); the continuum band bottom is "
                         f"{_num(self.continuum_bottom['paper'], '.4f')} (paper's map) and "
                         f"{_num(self.continuum_bottom['improved'], '.4f')} (improved map).")
        nu = self.continuum_window()
        ratio = self.continuum_ratio()[0]
        if nu > 0:
            i = int(np.searchsorted(self.quantiles, nu))
            nxt = (f"; at ν = {self.quantiles[i + 1]:g} the continuum counts {ratio[i + 1]:.2f} times the "
                   "lattice's states (the band is bounded and structured, the continuum law is not)"
                   if i + 1 < len(self.quantiles) else " (the largest fraction measured)")
            parts.append(f"The continuum (Plancherel density of −Δ_g through the paper's dictionary) counts "
                         f"the states below the lattice's E(ν) within 10% (allowing two error bars of E) for "
                         f"the measured fractions ν up to {nu:g}, i.e. from the band bottom to "
                         f"E = {_num(self.quantile_lattice[i], '.3f')}{nxt}."
                         + (f" Isolated exception: ν = {', '.join(f'{x:g}' for x in self.continuum_exceptions())} "
                            "(ratio " + ", ".join(f"{ratio[list(self.quantiles).index(x)]:.2f}"
                                                  for x in self.continuum_exceptions())
                            + "), where the cluster's integrated DOS is a staircase of its lowest multiplets."
                            if self.continuum_exceptions() else ""))
        else:
            parts.append("The continuum (Plancherel) count of states differs from the lattice's by more than 10% "
                         "already at the lowest quantile measured.")
        return " ".join(parts)

    def summary(self) -> dict:
        return {"p": self.p, "q": self.q, "moments": self.moments, "resolution": self.resolution,
                "curves": self.table(), "rho_bounds": [self.rho_lower, self.rho_upper],
                "continuum_bottom": dict(self.continuum_bottom), "continuum_window": self.continuum_window(),
                "quantiles": self.quantiles.tolist(), "quantile_lattice": self.quantile_lattice.tolist(),
                "quantile_lattice_err": self.quantile_lattice_err.tolist(),
                "quantile_continuum": self.quantile_continuum.tolist(),
                "notes": list(self.notes)}


def _default_rings(p: int, q: int, max_sites: int = 300_000) -> tuple[int, ...]:
    from ..graph.lattice import site_count

    out = []
    r = 4
    while r <= 30 and site_count(p, q, r) <= max_sites:
        out.append(r)
        r += 2
    return tuple(out[-3:]) or (3,)


def _abelian(cluster, energies, samples, seed):
    from ..graph.bands import abelian_dos

    ab = abelian_dos(cluster, samples=samples, bins=240, seed=seed)
    dens = np.interp(energies, ab.energies, ab.density, left=0.0, right=0.0)
    err = np.interp(energies, ab.energies, ab.errors, left=0.0, right=0.0)
    return ab, dens, err


def _hist_moments(ab, scale: float, m: int) -> np.ndarray:
    """Chebyshev moments of a histogram density (uniform within each bin, 9-point average of T_n)."""
    edges = np.asarray(ab.bin_edges) / scale
    weights = np.asarray(ab.density) * np.diff(ab.bin_edges)
    n = np.arange(m)
    # average of cos(n theta) over x in the bin, weighted by dx: int T_n dx over the bin / dx
    out = np.zeros(m)
    for b in range(weights.shape[0]):
        if weights[b] == 0:
            continue
        xs = np.linspace(edges[b], edges[b + 1], 9)
        out += weights[b] * np.cos(np.outer(n, np.arccos(np.clip(xs, -1, 1)))).mean(axis=1)
    return out


def dos_comparison(p: int = 7, q: int = 3, *, clusters=None, rings=None, moments: int = 256,
                   resolution: int = 40, vectors: int = 8, seed: int = 0, quantile: float = 1e-3,
                   abelian: bool = True, abelian_samples: int = 200, quantile_moments: int | None = None,
                   walk_length: int = 45,
                   progress: Callable[[str], None] | None = None) -> DosComparison:
    r"""Densities of states of the infinite {p,q} lattice by every route, compared (module docstring).

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    clusters : sequence of str, optional
        Cluster names for :func:`hyperlattice.graph.clusters.pbc_cluster`, smallest first (default
        :data:`DEFAULT_CLUSTERS`, or none for other {p,q}).
    rings : sequence of int, optional
        Flake sizes for the interior DOS (default: the three largest even ring counts with at most
        300,000 sites).
    moments : int, optional
        KPM moments of the densities shown (resolution about :math:`\pi q/M`, units of t),
        8 to 100 000. Default 256.
    resolution : int, optional
        Moments of the exact comparison (closed walks up to length ``resolution - 1``), 4 to
        ``min(moments, 200)``. Default 40.
    vectors : int, optional
        Random vectors of the stochastic traces (at least 3, for the jackknife). Default 8.
    seed : int, optional
        Seed of the random vectors (>= 0). Default 0.
    quantile : float, optional
        The band edges are the energies below which (above which) this fraction of states lies,
        1e-8 to 0.25. Default 1e-3.
    abelian : bool, optional
        Include the Abelian DOS of the smallest cluster (needs graph/bands.py; else a note).
        Default True.
    abelian_samples : int, optional
        k-points of the Abelian DOS. Default 200.
    quantile_moments : int, optional
        Moments of a separate, sharper KPM run on the largest cluster for the continuum comparison
        of the quantile energies (default: reuse the ``moments`` run).
    walk_length : int, optional
        Longest exact closed walk for the proven bounds on :math:`\rho` (at least ``resolution - 1``;
        45 for {7,3} needs a 12-ring flake, 0.7 s), 6 to 200. Default 45.
    progress : callable, optional
        Receives one-line messages as the routes run.

    Returns
    -------
    DosComparison
        One curve per cluster, flake and Abelian DOS (``labels``, ``kinds``, ``sites``,
        ``density`` per site and unit energy on ``energies``), the exact ``reference``, the
        :math:`L^1` ``distance`` of each curve from it, the quantile band edges ``bottom`` and
        ``top``, the proven bounds ``rho_lower``, ``rho_upper``, the continuum band bottoms and
        quantile energies, and ``notes`` on what was left out.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic or an argument is out of its range, ``clusters`` is not a list
        of names or ``rings`` not a list of ring counts.

    See Also
    --------
    hyperlattice.graph.kpm.kpm_dos, hyperlattice.graph.kpm.bulk_dos
    continuum_dos : the continuum side.

    Examples
    --------
    A small, fast comparison: the interior of a 3-ring flake against the exact moments.

    >>> import hyperlattice as hl
    >>> cmp = hl.dos_comparison(7, 3, clusters=[], rings=[3], moments=32, resolution=8,
    ...                         vectors=3, walk_length=7, abelian=False)
    >>> cmp.labels
    ['flake interior, 3 rings (35 of 112 sites)']
    >>> print(f"{cmp.distance[0]:.4f}")
    0.3291
    >>> print(f"{cmp.rho_lower:.4f} {cmp.rho_upper:.4f}")
    2.8284 2.9665
    """
    import time

    from ..graph.kpm import bulk_dos, kpm_dos
    from ..graph.lattice import ring_lattice
    from ..graph.walks import chebyshev_from_walks, closed_walks, spectral_radius

    t_start = time.perf_counter()
    p, q = _validate.pq(p, q)
    moments = _validate.integer("moments", moments, minimum=8, maximum=100_000)
    resolution = _validate.integer("resolution", resolution, minimum=4, maximum=min(moments, 200))
    walk_length = _validate.integer("walk_length", walk_length, minimum=6, maximum=200)
    vectors = _validate.integer("vectors", vectors, minimum=3, maximum=10_000)
    seed = _validate.integer("seed", seed, minimum=0)
    quantile = _validate.real("quantile", quantile, minimum=1e-8, maximum=0.25)
    abelian = _validate.flag("abelian", abelian)
    abelian_samples = _validate.integer("abelian_samples", abelian_samples, minimum=8, maximum=100_000)
    if quantile_moments is not None:
        quantile_moments = _validate.integer("quantile_moments", quantile_moments, minimum=8, maximum=100_000)
    if clusters is None:
        clusters = DEFAULT_CLUSTERS.get((p, q), ())
    elif (isinstance(clusters, str) or not isinstance(clusters, (list, tuple))
          or not all(isinstance(c, str) for c in clusters)):
        raise ValueError("clusters must be a list of cluster names such as ['klein', 'PSL(2,13)'].")
    clusters = list(clusters)
    if rings is None:
        rings = _default_rings(p, q)
    elif not isinstance(rings, (list, tuple, np.ndarray)):
        raise ValueError("rings must be a list of ring counts such as [6, 8].")
    else:
        rings = [_validate.integer("rings", r, minimum=2, maximum=40) for r in rings]
    progress = progress or (lambda msg: None)
    notes: list[str] = []

    scale = q / (1.0 - 0.01)  # the KPM scale for max degree q (graph/kpm.py: EPS = 0.01)
    energies = np.linspace(-q, q, 1201)
    progress("exact closed walks")
    walks = closed_walks(p, q, max(resolution - 1, walk_length))
    mu_exact = chebyshev_from_walks(walks[:resolution], scale)
    reference = jackson_density(mu_exact, scale, energies)
    sr = spectral_radius(p, q, max(resolution - 1, walk_length))

    labels, kinds, sizes, dens, derr, dist, dist_err, exact, edges = [], [], [], [], [], [], [], [], []
    resolved = []

    def add(res, label, kind, ex):
        e, rho, err = res.density(energies)
        mu_r = res.mu[:resolution] / res.mu[0]  # normalised: the deflated states are left out
        rho_r = jackson_density(mu_r, res.scale, energies)
        resolved.append(rho_r)
        d = np.trapezoid(np.abs(rho_r - reference), energies)
        # error of the distance: its spread over leave-one-out means
        r = res.vectors
        vals = []
        for j in range(r):
            mu = (res.mu_vectors[:, :resolution].sum(axis=0) - res.mu_vectors[j, :resolution]) / (r - 1)
            vals.append(np.trapezoid(np.abs(jackson_density(mu / mu[0], res.scale, energies) - reference), energies))
        vals = np.asarray(vals)
        de = float(math.sqrt((r - 1) / r * np.sum((vals - vals.mean()) ** 2))) if r > 2 else math.nan
        lo, hi = -res.scale * 0.999, res.scale * 0.999
        b = _quantile_with_error(res, quantile, lo, 0.0)
        t = _quantile_with_error(res, quantile, 0.0, hi, top=True)
        labels.append(label)
        kinds.append(kind)
        sizes.append(res.sites)
        dens.append(rho)
        derr.append(err)
        dist.append(float(d))
        dist_err.append(de)
        exact.append(int(ex))
        edges.append((*b, *t))
        return res

    largest = largest_cluster = None
    if clusters:
        try:
            from ..graph.clusters import pbc_cluster
        except ImportError:  # pragma: no cover - an install without the cluster module
            notes.append("periodic clusters left out: hyperlattice.graph.clusters is not available.")
            clusters = []
    for name in clusters:
        progress(f"cluster {name}")
        c = pbc_cluster(p, q, name)
        res = kpm_dos(c, moments, vectors=vectors, seed=seed, deflate=True)
        largest = add(res, f"cluster {name} (N = {c.sites:,})", "cluster", c.systole)
        largest_cluster = c
    for r in rings:
        progress(f"flake interior, {r} rings")
        lat = ring_lattice(p, q, r)
        res = bulk_dos(lat, moments, vectors=vectors, seed=seed)
        add(res, f"flake interior, {r} rings ({res.traced_sites:,} of {lat.sites:,} sites)", "flake", res.exact_moments)
    if abelian and clusters:
        try:
            from ..graph.bands import abelian_dos  # noqa: F401
        except ImportError:
            notes.append("Abelian DOS left out: hyperlattice.graph.bands is not available.")
        else:
            progress("Abelian DOS")
            cell = pbc_cluster(p, q, clusters[0])
            ab, rho, err = _abelian(cell, energies, abelian_samples, seed)
            mu_ab = _hist_moments(ab, scale, resolution)
            rho_r = jackson_density(mu_ab / mu_ab[0], scale, energies)
            resolved.append(rho_r)
            d = np.trapezoid(np.abs(rho_r - reference), energies)
            labels.append(f"Abelian DOS of {clusters[0]} ({abelian_samples} k-points, genus {cell.genus})")
            kinds.append("abelian")
            sizes.append(cell.sites)
            dens.append(rho)
            derr.append(err)
            dist.append(float(d))
            dist_err.append(math.nan)
            exact.append(int(cell.systole))
            edges.append((math.nan,) * 4)
    elif abelian:
        notes.append("Abelian DOS left out: no periodic cluster for this {p,q}.")

    # continuum against the largest cluster's quantile energies
    bottoms = {"paper": float(dictionary.energy_from_lambda(1.0, p, q)),
               "improved": float(dictionary.improved_band_bottom(p, q))}
    qs = np.asarray(QUANTILES)
    q_lat = np.full(qs.shape, np.nan)
    q_lat_err = np.full(qs.shape, np.nan)
    if largest is not None and quantile_moments is not None and quantile_moments != moments:
        progress(f"largest cluster, {quantile_moments} moments")
        largest = kpm_dos(largest_cluster, quantile_moments, vectors=vectors, seed=seed, deflate=True)
    e_bot = np.linspace(-q, -q + 0.5 * q, 501)
    n_bot = np.full(e_bot.shape, np.nan)
    n_bot_err = np.full(e_bot.shape, np.nan)
    if largest is not None:
        _, n_bot, n_bot_err = largest.integrated(e_bot)
        tables = _integrated_tables(largest, -largest.scale * 0.999, largest.scale * 0.5)
        for i, nu in enumerate(qs):
            q_lat[i], q_lat_err[i] = _quantile_with_error(largest, float(nu), 0, 0, tables=tables)
    lam_nu = np.array([_lambda_at_quantile(float(nu), p, q) for nu in qs])
    q_cont = np.asarray(dictionary.energy_from_lambda(lam_nu, p, q), dtype=float)
    tab_lam, tab_e = _improved_table(p, q)
    q_imp = np.where(lam_nu <= tab_lam[-1], np.interp(lam_nu, tab_lam, tab_e), np.nan)
    edges = np.asarray(edges, dtype=float).reshape(-1, 4)

    def ratio_at(x):
        out = np.full(x.shape, np.nan)
        ok = np.isfinite(x)
        out[ok] = continuum_integrated_dos(x[ok], p, q) / qs[ok]
        return out

    err2 = 2.0 * np.nan_to_num(q_lat_err)
    ratio_band = np.vstack([ratio_at(q_lat), ratio_at(q_lat - err2), ratio_at(q_lat + err2)])
    return DosComparison(
        p=p, q=q, moments=moments, resolution=resolution, quantile=quantile, energies=energies, labels=labels,
        kinds=kinds, sites=np.asarray(sizes, dtype=np.int64), density=np.asarray(dens).reshape(len(labels), -1),
        density_err=np.asarray(derr).reshape(len(labels), -1), reference=reference,
        distance=np.asarray(dist), distance_err=np.asarray(dist_err), exact_moments=np.asarray(exact, dtype=np.int64),
        bottom=edges[:, 0], bottom_err=edges[:, 1], top=edges[:, 2], top_err=edges[:, 3],
        rho_lower=sr.lower, rho_upper=sr.upper, continuum_bottom=bottoms, quantiles=qs, quantile_lattice=q_lat,
        quantile_lattice_err=q_lat_err, quantile_continuum=q_cont, quantile_improved=q_imp, notes=notes,
        density_resolved=np.asarray(resolved).reshape(len(labels), -1), ratio_band=ratio_band, bottom_energies=e_bot,
        bottom_integrated=n_bot, bottom_integrated_err=n_bot_err,
        bottom_label=(f"{labels[[i for i, k in enumerate(kinds) if k == 'cluster'][-1]]}, {largest.moments} moments"
                      if largest is not None else ""),
        timings={"total": time.perf_counter() - t_start})


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
