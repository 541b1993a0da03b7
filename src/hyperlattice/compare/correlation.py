r"""Correlation analysis of a two-point function on a lattice (``Fig3``, right panels).

Correlation analysis (``Fig3``, right panels)
----------------------------------------------
For a source site :math:`i`: pairs :math:`(d_{ij}, F_j)`, binned means and standard deviations
versus distance, and a collapse number

.. math:: S = \Bigl[\frac{\sum_b n_b\sigma_b^2}{\sum_b n_b|\mu_b|^2}\Bigr]^{1/2},

the rms spread within distance bins relative to the rms bin mean (0 for a function of
distance alone). Conformal (automorphism) invariance emerges as :math:`S\to 0` for large
:math:`\ell`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..geometry import d0, distance
from ..graph.lattice import Lattice
from ..results import Column, Result


__all__ = ["correlation_pairs", "sorted_pairs", "bin_by_distance", "BinnedCorrelation", "collapse_measure"]


# ----------------------------------------------------------------------------
# correlation analysis
# ----------------------------------------------------------------------------

def correlation_pairs(lattice: Lattice, source: int, values) -> tuple[np.ndarray, np.ndarray]:
    r"""The list of pairs :math:`(d_{ij}, F_j)` for source i, all j except i, sorted by distance.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} lattice embedded in the Poincaré disk.
    source : int
        Source site i (0-based).
    values : array_like, shape (N,)
        One value :math:`F_j` per site (real or complex).

    Returns
    -------
    dist : ndarray of float, shape (N - 1,)
        Hyperbolic distances :math:`d(z_i, z_j)` (``eq4``, curvature -4), ascending (stable).
    values : ndarray, shape (N - 1,)
        The values in the same order.

    Raises
    ------
    ValueError
        If ``source`` is out of range or ``values`` does not have one entry per site.

    See Also
    --------
    sorted_pairs, bin_by_distance

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.correlation import correlation_pairs
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> dist, vals = correlation_pairs(lat, 0, np.arange(35.0))
    >>> dist.shape, round(float(dist[0]), 6), vals[:3].tolist()
    ((34,), 0.283128, [1.0, 6.0, 7.0])
    """
    _validate.lattice(lattice)
    source = _validate.site_index("source", source, lattice.sites)
    v = np.asarray(values)
    if v.shape != (lattice.sites,):
        raise ValueError(f"values must have one entry per site ({lattice.sites}), got shape {v.shape}.")
    return sorted_pairs(distance(lattice.z, lattice.z[source]), v, source)


def sorted_pairs(dist, values, exclude: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    r"""Pairs :math:`(d_j, F_j)` sorted by distance (stable), leaving out the site ``exclude``.

    The distances to a source are given (e.g. :attr:`GreenComparison.distance
    <hyperlattice.compare.green.GreenComparison>`), so no lattice is needed.

    Parameters
    ----------
    dist : array_like of float, shape (K,)
        Distances to the source.
    values : array_like, shape (K,)
        One value per site.
    exclude : int, optional
        Index left out (the source itself). Default None.

    Returns
    -------
    dist, values : ndarray
        Both sorted by distance (stable), without ``exclude``.

    Raises
    ------
    ValueError
        If the arrays differ in shape or ``exclude`` is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.correlation import sorted_pairs
    >>> dist, vals = sorted_pairs([0.0, 2.0, 1.0, 1.0], [10, 20, 30, 40], exclude=0)
    >>> dist.tolist(), vals.tolist()
    ([1.0, 1.0, 2.0], [30, 40, 20])
    """
    d = _validate.real_array("distances", dist, ndim=1)
    v = np.asarray(values)
    if v.shape != d.shape:
        raise ValueError(f"distances and values must have the same length, got {d.shape} and {v.shape}.")
    keep = np.ones(d.size, bool)
    if exclude is not None:
        keep[_validate.site_index("exclude", exclude, d.size)] = False
    order = np.argsort(d[keep], kind="stable")
    return d[keep][order], v[keep][order]


@dataclass(frozen=True, eq=False, kw_only=True)
class BinnedCorrelation(Result):
    r"""Means and standard deviations of F in distance bins (empty bins dropped).

    Attributes
    ----------
    edges : ndarray, shape (B+1,)
        All bin edges (including those of empty bins).
    centre : ndarray
        Centres of the non-empty bins.
    mean : ndarray (real or complex)
        Mean of F in each non-empty bin.
    std : ndarray
        Population standard deviation :math:`\sqrt{\langle|F-\mu|^2\rangle}` in each bin.
    count : ndarray of int
        Number of values in each bin.
    edge_ties : int
        Distances within rounding (:math:`64\varepsilon \max d`) of an interior bin edge: their
        bin is decided by the last bits of the distance, so they are counted here. The default
        bins are centred on the multiples of :math:`d_0/2`, where the lattice's exact distances
        (0, :math:`d_0`, ...) lie, so that this is 0 for the default bins on a lattice.

    Notes
    -----
    Distances are hyperbolic, in the paper's metric :math:`|dz|^2/(1-|z|^2)^2`; F keeps its own unit.

    Examples
    --------
    >>> from hyperlattice.compare.correlation import bin_by_distance
    >>> b = bin_by_distance([0.4, 0.6, 1.5], [1.0, 3.0, 5.0], width=1.0)
    >>> b.edges.tolist(), b.centre.tolist(), b.mean.tolist(), b.count.tolist()
    ([0.0, 1.0, 2.0], [0.5, 1.5], [2.0, 5.0], [2, 1])
    """

    COLUMNS = (Column("centre", "centre", "hyperbolic distance"), Column("mean", "mean", "of F"), Column("std", "std", "of F"),
               Column("count", "count", "1"))

    edges: np.ndarray
    centre: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    count: np.ndarray
    edge_ties: int = 0


def _values(name: str, values, shape) -> np.ndarray:
    if np.iscomplexobj(values):
        return _validate.complex_array(name, values, shape=shape)
    return _validate.real_array(name, values, shape=shape)


def bin_by_distance(dist, values, width: float | None = None, edges=None) -> BinnedCorrelation:
    r"""Bin :math:`F` by hyperbolic distance: mean and (population) standard deviation per bin.

    Default bins have width :math:`d_0/2` of {7,3} (0.141), fine enough to resolve the
    distance dependence and coarse enough to hold several sites each, and are *centred* on the
    multiples of :math:`d_0/2` (edges at :math:`(k - \tfrac12)\,d_0/2`): nearest neighbours lie
    at exactly :math:`d_0`, and a bin edge there would sort them by the sign of their rounding
    error. Complex values: the std is :math:`\sqrt{\langle|F-\mu|^2\rangle}`.

    Parameters
    ----------
    dist : array, shape (K,)
        Distances (finite, non-negative).
    values : array, shape (K,)
        Real or complex values F, finite.
    width : float, optional
        Bin width, edges at its multiples (default: :math:`d_0/2` of {7,3} with edges at the
        half-integer multiples); ignored when ``edges`` is given.
    edges : array, optional
        Strictly increasing bin edges; distances outside fall into the first or last bin.

    Returns
    -------
    BinnedCorrelation
        ``edges``, and for the non-empty bins their ``centre``, ``mean``, ``std`` and ``count``;
        ``edge_ties`` counts distances that lie on an interior edge to rounding.

    Raises
    ------
    ValueError
        If the arrays are empty, not finite or of different shapes, a distance is negative, or
        ``edges`` are not at least two strictly increasing numbers.

    See Also
    --------
    collapse_measure

    Examples
    --------
    >>> from hyperlattice.compare.correlation import bin_by_distance
    >>> b = bin_by_distance([0.4, 0.6, 1.5], [1.0, 3.0, 5.0], width=1.0)
    >>> b.centre.tolist(), b.mean.tolist(), b.std.tolist(), b.count.tolist()
    ([0.5, 1.5], [2.0, 5.0], [1.0, 0.0], [2, 1])
    """
    d = _validate.real_array("distances", dist, ndim=1)
    if d.size == 0:
        raise ValueError("distances and values must not be empty.")
    v = _values("values", values, d.shape)
    if np.any(d < 0):
        raise ValueError("distances must be non-negative.")
    if edges is None:
        if width is None:
            width = 0.5 * d0(7, 3)
            start = -0.5 * width   # centres on the multiples of d0/2 (docstring)
        else:
            width = _validate.positive_real("the bin width", width)
            start = 0.0
        edges = np.arange(start, d.max() + width, width)
        if edges[-1] <= d.max():
            edges = np.append(edges, edges[-1] + width)
    else:
        edges = _validate.real_array("edges", edges, ndim=1)
        if edges.size < 2 or np.any(np.diff(edges) <= 0):
            raise ValueError("edges must be at least two strictly increasing numbers.")
    idx = np.clip(np.searchsorted(edges, d, side="right") - 1, 0, len(edges) - 2)
    nb = len(edges) - 1
    count = np.bincount(idx, minlength=nb)
    s1 = np.bincount(idx, weights=v.real, minlength=nb) + 1j * np.bincount(idx, weights=v.imag, minlength=nb) \
        if np.iscomplexobj(v) else np.bincount(idx, weights=v, minlength=nb)
    nz = count > 0
    mean = np.zeros(nb, s1.dtype)
    mean[nz] = s1[nz] / count[nz]
    dev2 = np.abs(v - mean[idx]) ** 2
    var = np.bincount(idx, weights=dev2, minlength=nb)
    std = np.zeros(nb)
    std[nz] = np.sqrt(var[nz] / count[nz])
    centre = 0.5 * (edges[:-1] + edges[1:])
    tol = 64.0 * np.finfo(float).eps * max(float(d.max()), float(np.max(np.abs(edges))))
    ties = _edge_ties(d, edges[1:-1], tol)
    return BinnedCorrelation(edges=edges, centre=centre[nz], mean=mean[nz], std=std[nz], count=count[nz],
                             edge_ties=ties)


def _edge_ties(d: np.ndarray, inner: np.ndarray, tol: float) -> int:
    """How many of ``d`` lie within ``tol`` of one of the ascending ``inner`` edges."""
    if inner.size == 0:
        return 0
    j = np.searchsorted(inner, d)
    near = np.minimum(np.abs(d - inner[np.minimum(j, inner.size - 1)]), np.abs(d - inner[np.maximum(j - 1, 0)]))
    return int(np.count_nonzero(near <= tol))


def collapse_measure(dist, values, width: float | None = None) -> float:
    r"""Collapse number :math:`S = [\sum_b n_b\sigma_b^2 / \sum_b n_b|\mu_b|^2]^{1/2}` (module docstring).

    0 when F is a function of distance alone (up to the bin width), larger when sites at
    equal distance disagree.

    Parameters
    ----------
    dist : array_like of float, shape (K,)
        Distances (finite, non-negative).
    values : array_like, shape (K,)
        Real or complex values F, finite, not all zero.
    width : float, optional
        Bin width (default: the bins of :func:`bin_by_distance`).

    Returns
    -------
    float
        S >= 0 (dimensionless).

    Raises
    ------
    ValueError
        For bad arrays (as in :func:`bin_by_distance`) or values that vanish identically.

    Examples
    --------
    >>> from hyperlattice.compare.correlation import collapse_measure
    >>> round(collapse_measure([0.4, 0.6, 1.5], [1.0, 3.0, 5.0], width=1.0), 6)
    0.246183
    >>> collapse_measure([0.4, 0.6, 1.5], [2.0, 2.0, 5.0], width=1.0)
    0.0
    """
    b = bin_by_distance(dist, values, width=width)
    den = float(np.sum(b.count * np.abs(b.mean) ** 2))
    if den == 0:
        raise ValueError("the values vanish identically; the collapse number is undefined.")
    return float(np.sqrt(np.sum(b.count * b.std ** 2) / den))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
