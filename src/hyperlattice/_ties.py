r"""Decisions on floating-point values that can be exactly degenerate or exactly at a threshold.

A computed eigenvalue carries a rounding error of order :math:`n\,\varepsilon\,\|H\|` (a backward
stable dense solver, Golub & Van Loan, *Matrix Computations*, 4th ed., Sec. 8.1.2 and Thm. 8.1.5;
for an iterative solver the residual :math:`\|Hv - Ev\|` bounds it instead). Its last bits depend
on the BLAS kernel and on the number of threads (different reduction orders), so a decision such
as "is this level negative?" or "which of two degenerate levels is lower?" taken on the raw value
gives different answers on different machines. Every such decision in the package goes through
this module: a value within the tolerance of a threshold is *at* the threshold and is reported as
such, and values within the tolerance of each other are one degenerate group whose internal
order is fixed by a rule that does not look at the rounding noise (e.g. by labels).

This is the bottom layer: numpy only, no imports from the rest of the package.
"""

from __future__ import annotations

import numpy as np

__all__ = ["EPS", "eigenvalue_tolerance", "monotone_tolerance", "classify", "degenerate_groups", "stable_order"]

#: machine epsilon of float64
EPS = float(np.finfo(float).eps)

#: safety factor on n * eps * ||H||: LAPACK's dense symmetric solvers guarantee a backward error
#: p(n) * eps * ||H|| with a modest p(n); the factor covers the p(n) we do not know exactly
#: while staying far below any physical level spacing (the smallest nonzero |E| of the {7,3}
#: flakes up to l = 6 is 9.5e-4, against tolerances of at most 3.4e-12 there).
SAFETY = 16.0


def eigenvalue_tolerance(norm: float, n: int, residual: float = 0.0) -> float:
    r"""Absolute error bound of a computed eigenvalue of a symmetric matrix.

    .. math:: \delta = \max\big(c\,n\,\varepsilon\,\|H\|,\ r\big)

    with :math:`c` = :data:`SAFETY`, :math:`n` the matrix dimension, :math:`\|H\|` any upper bound
    of the 2-norm (the largest absolute row sum is one) and :math:`r` the largest residual norm
    :math:`\|Hv - Ev\|` of normalised eigenvectors when an iterative solver computed them (by the
    Bauer–Fike / Kato bound an exact eigenvalue lies within :math:`r` of E).

    Parameters
    ----------
    norm : float
        Upper bound of :math:`\|H\|_2` (finite, non-negative).
    n : int
        Dimension of the matrix that was diagonalised (of each block, for a block-diagonal one).
    residual : float
        Largest residual norm, or 0 for a dense solver.

    Returns
    -------
    float
        The tolerance :math:`\delta \ge 0`.
    """
    norm = float(norm)
    residual = float(residual)
    if not (np.isfinite(norm) and norm >= 0.0 and np.isfinite(residual) and residual >= 0.0):
        raise ValueError("the norm and the residual must be finite and non-negative.")
    return max(SAFETY * max(int(n), 1) * EPS * norm, residual)


def classify(values, threshold: float, tol) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Split values into those below, at, and above a threshold, robustly.

    ``below`` means :math:`v < t - \delta`, ``at`` means :math:`|v - t| \le \delta`, ``above``
    means :math:`v > t + \delta`. A value in ``at`` cannot be sorted by its computed sign: the
    caller reports it (for ``threshold = 0`` of a graph spectrum: a zero mode).

    Parameters
    ----------
    values : array of float
    threshold : float
    tol : float or array broadcastable to ``values``
        The error bound of each value (see :func:`eigenvalue_tolerance`).

    Returns
    -------
    below, at, above : ndarray of bool
        Masks of the same shape as ``values``; exactly one is true for each value.
    """
    v = np.asarray(values, dtype=float)
    d = np.broadcast_to(np.asarray(tol, dtype=float), v.shape)
    below = v < threshold - d
    above = v > threshold + d
    return below, ~(below | above), above


def degenerate_groups(sorted_values, tol) -> np.ndarray:
    r"""Group labels of ascending values: neighbours closer than the tolerance share a group.

    Groups are formed by single linkage (a chain of near-equal values is one group), which is
    what an unknown rounding error allows: two values within :math:`\delta_i + \delta_{i+1}` of
    each other may be exactly equal.

    Parameters
    ----------
    sorted_values : array of float, ascending
    tol : float or array of the same length
        Error bound of each value.

    Returns
    -------
    ndarray of int
        ``group[i]``: 0 for the first group, increasing by one at each gap larger than the
        tolerance.
    """
    v = np.asarray(sorted_values, dtype=float).ravel()
    if v.size == 0:
        return np.zeros(0, dtype=np.int64)
    d = np.broadcast_to(np.asarray(tol, dtype=float), v.shape)
    gaps = np.diff(v) > (d[:-1] + d[1:])
    return np.concatenate([[0], np.cumsum(gaps)]).astype(np.int64)


def stable_order(values, tol, *keys) -> np.ndarray:
    r"""An ascending order of values that does not depend on the rounding of degenerate ones.

    Values are sorted, grouped by :func:`degenerate_groups`, and inside each group ordered by the
    integer ``keys`` (lexicographically, the first key most significant) instead of by their
    computed values. With keys that identify each level (e.g. a sector label and an index
    within the sector), the result is the same on every machine.

    Parameters
    ----------
    values : array of float
    tol : float or array
        Error bound of each value.
    *keys : arrays of int
        Tie-breaking labels, most significant first.

    Returns
    -------
    ndarray of int
        Indices that order ``values``.
    """
    v = np.asarray(values, dtype=float).ravel()
    d = np.broadcast_to(np.asarray(tol, dtype=float), v.shape)
    first = np.argsort(v, kind="stable")
    groups = np.empty(v.size, dtype=np.int64)
    groups[first] = degenerate_groups(v[first], d[first])
    # np.lexsort sorts by the last key first
    cols = [np.asarray(k).ravel()[::1] for k in reversed(keys)]
    return np.lexsort(tuple(cols) + (groups,)) if cols else first


def monotone_tolerance(values) -> float:
    r"""Smallest step of a tabulated function that counts as a rise: :math:`64\,\varepsilon\max|f|`.

    Finding where a function stops rising by ``np.diff(f) <= 0`` decides at exactly zero, where
    the computed step near a maximum is rounding noise of a few ulps of :math:`|f|`; comparing
    with this bound instead puts the decision where the noise cannot reach.
    """
    v = np.asarray(values, dtype=float)
    return 64.0 * EPS * float(np.max(np.abs(v), initial=0.0))
