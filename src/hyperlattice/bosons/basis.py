r"""Number-conserving Fock basis of N bosons on M sites with at most ``nmax`` bosons per site.

A basis state is an occupation vector :math:`(n_0, \dots, n_{M-1})` with :math:`\sum_i n_i = N`
and :math:`0 \le n_i \le n_{\max}`; ``nmax = 1`` is the hard-core limit, ``nmax >= N`` no
truncation at all. Its dimension is the number of such compositions, by inclusion-exclusion
over the sites that exceed the cutoff (Riordan, *Introduction to Combinatorial Analysis*,
ch. 5; the coefficient of :math:`x^N` in :math:`(1 + x + \dots + x^{n_{\max}})^M`):

.. math::

    D(N, M, n_{\max}) = \sum_{k \ge 0} (-1)^k \binom{M}{k}
        \binom{N - k(n_{\max}+1) + M - 1}{M - 1}.

States are numbered 0..D-1 in lexicographic order of :math:`(n_0, n_1, \dots)`. With
:math:`C_m(r)` the number of ways to put r bosons on m sites (the formula above), the rank of a
state is

.. math::

    \mathrm{rank}(n) = \sum_{i=0}^{M-1} W_i(r_i, n_i), \qquad
    W_i(r, v) = \sum_{k < v} C_{M-1-i}(r - k), \qquad r_i = N - \sum_{l<i} n_l,

a sum of table look-ups (the combinatorial number system of Knuth, TAOCP vol. 4A, 7.2.1.3,
extended to a cutoff). Moving one boson between sites i and j changes only the terms
between them, which is what makes the Hamiltonian kernels of :mod:`hyperlattice.bosons.ed`
cheap: no hash table and no search.

Numba kernels are compiled on first use (and cached on disk), not at import.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate

__all__ = ["BosonBasis", "basis_dimension", "boson_basis", "rank_states", "unrank_states", "basis_memory"]

#: largest number of sites (the occupation table stores one uint8 per site and state)
MAX_SITES = 4096
#: largest cutoff (occupations are stored as uint8)
MAX_NMAX = 255
#: largest dimension: ranks are int64 and the table below is summed in int64
MAX_DIM = 2**62


def basis_dimension(sites: int, particles: int, nmax: int) -> int:
    r"""Exact dimension :math:`D(N, M, n_{\max})` of the Fock basis (a Python int, no allocation).

    Parameters
    ----------
    sites : int
        Number of sites M >= 1.
    particles : int
        Number of bosons N >= 0.
    nmax : int
        Occupation cutoff per site, >= 1 (1 = hard-core bosons).

    Returns
    -------
    int
        The number of occupation vectors; 0 when ``particles > sites * nmax``.

    Raises
    ------
    ValueError
        If an argument is not an integer in its range (at most 4096 sites, cutoff at most 255).

    See Also
    --------
    basis_memory, boson_basis

    Examples
    --------
    >>> from hyperlattice.bosons.basis import basis_dimension
    >>> basis_dimension(7, 3, 3), basis_dimension(4, 2, 1), basis_dimension(2, 5, 2)
    (84, 6, 0)
    """
    m = _validate.integer("sites", sites, minimum=1, maximum=MAX_SITES)
    n = _validate.integer("particles", particles, minimum=0, maximum=MAX_SITES * MAX_NMAX)
    c = _validate.integer("nmax", nmax, minimum=1, maximum=MAX_NMAX)
    return _dimension(m, n, c)


def _dimension(m: int, n: int, c: int) -> int:
    total = 0
    for k in range(0, min(m, n // (c + 1)) + 1):
        total += (-1) ** k * math.comb(m, k) * math.comb(n - k * (c + 1) + m - 1, m - 1)
    return total


def basis_memory(sites: int, particles: int, nmax: int) -> int:
    """Bytes of a :class:`BosonBasis` (its occupation table and rank tables), before building it.

    Parameters
    ----------
    sites : int
        Number of sites M, 1 to 4096.
    particles : int
        Number of bosons N >= 0.
    nmax : int
        Occupation cutoff per site, 1 to 255.

    Returns
    -------
    int
        The bytes :func:`boson_basis` would allocate for these arguments.

    Raises
    ------
    ValueError
        If an argument is not an integer in its range.

    Examples
    --------
    >>> from hyperlattice.bosons.basis import basis_memory
    >>> basis_memory(7, 3, 3)
    1964
    """
    m = _validate.integer("sites", sites, minimum=1, maximum=MAX_SITES)
    n = _validate.integer("particles", particles, minimum=0, maximum=MAX_SITES * MAX_NMAX)
    c = _validate.integer("nmax", nmax, minimum=1, maximum=MAX_NMAX)
    return _dimension(m, n, c) * m + 8 * m * (n + 1) * (c + 2) + 8 * (m + 1) * (n + 1)


@dataclass(frozen=True, eq=False)
class BosonBasis:
    r"""The Fock basis of ``particles`` bosons on ``sites`` sites with cutoff ``nmax``.

    Attributes
    ----------
    sites, particles, nmax : int
        M, N and the cutoff (1 = hard-core).
    dim : int
        Number of states D (see the module docstring).
    states : ndarray of uint8, shape (D, M)
        Occupations of every state, in rank order (lexicographic, site 0 most significant).
    weights : ndarray of int64, shape (M, N + 1, nmax + 2)
        The rank table :math:`W_i(r, v)`; ``weights[i, r, v]`` for :math:`v \le \min(r, n_{\max})`.
    counts : ndarray of int64, shape (M + 1, N + 1)
        :math:`C_m(r)`: states of r bosons on m sites.

    Notes
    -----
    Sites are 0-based, in the lattice's order (ring by ring) when the basis is built for a lattice.

    Examples
    --------
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> basis = boson_basis(3, 2, 1)
    >>> basis
    BosonBasis(sites=3, particles=2, nmax=1, dim=3)
    >>> basis.hard_core, basis.states.tolist()
    (True, [[0, 1, 1], [1, 0, 1], [1, 1, 0]])
    """

    sites: int
    particles: int
    nmax: int
    dim: int
    states: np.ndarray
    weights: np.ndarray
    counts: np.ndarray

    def __repr__(self) -> str:
        return f"BosonBasis(sites={self.sites}, particles={self.particles}, nmax={self.nmax}, dim={self.dim})"

    @property
    def hard_core(self) -> bool:
        """Whether the cutoff is 1 (hard-core bosons)."""
        return self.nmax == 1


def _tables(m: int, n: int, c: int) -> tuple[np.ndarray, np.ndarray]:
    counts = np.zeros((m + 1, n + 1), dtype=np.int64)
    counts[0, 0] = 1
    for k in range(1, m + 1):
        prev = counts[k - 1]
        # C_k(r) = sum_{v=0}^{min(r,c)} C_{k-1}(r - v), as a running window sum
        csum = np.concatenate([[0], np.cumsum(prev)])
        r = np.arange(n + 1)
        counts[k] = csum[r + 1] - csum[np.maximum(r - c, 0)]
    weights = np.zeros((m, n + 1, c + 2), dtype=np.int64)
    for i in range(m):
        rest = counts[m - 1 - i]
        for v in range(1, c + 2):
            # W_i(r, v) = W_i(r, v-1) + C_{M-1-i}(r - v + 1)
            r = np.arange(n + 1)
            add = np.where(r - v + 1 >= 0, rest[np.maximum(r - v + 1, 0)], 0)
            weights[i, :, v] = weights[i, :, v - 1] + add
    return counts, weights


_KERNELS: dict = {}


def _kernels() -> dict:
    """numba kernels (compiled on first use, cached on disk)."""
    if not _KERNELS:
        import numba

        @numba.njit(cache=True)
        def enumerate_states(m, n, c, counts, out):  # pragma: no cover - jitted
            # lexicographic enumeration by an odometer: the next state of (n_0..n_{M-1}) is found
            # by raising the rightmost site i < M-1 that can take one more boson from the sites
            # after it, and packing the rest of the bosons as far right as possible
            dim = out.shape[0]
            occ = np.zeros(m, dtype=np.int64)
            rem = n
            for i in range(m - 1, -1, -1):
                v = min(rem, c)
                occ[i] = v
                rem -= v
            for s in range(dim):
                for i in range(m):
                    out[s, i] = occ[i]
                if s == dim - 1:
                    break
                # bosons to the right of i (inclusive of i+1..M-1)
                tail = 0
                i = m - 1
                tail += occ[i]
                i -= 1
                while i >= 0:
                    # can site i go up by one with the tail (minus one) fitting into sites i+1..M-1?
                    if occ[i] < c and tail >= 1:
                        break
                    tail += occ[i]
                    i -= 1
                occ[i] += 1
                tail -= 1
                for k in range(i + 1, m):
                    occ[k] = 0
                # pack the tail to the right
                k = m - 1
                while tail > 0:
                    v = min(tail, c)
                    occ[k] = v
                    tail -= v
                    k -= 1
            return 0

        @numba.njit(cache=True)
        def rank_many(occs, n, weights, out):  # pragma: no cover - jitted
            m = occs.shape[1]
            for s in range(occs.shape[0]):
                rem = n
                r = 0
                for i in range(m):
                    v = occs[s, i]
                    r += weights[i, rem, v]
                    rem -= v
                out[s] = r
            return 0

        @numba.njit(cache=True)
        def unrank_many(idx, m, n, c, counts, out):  # pragma: no cover - jitted
            for s in range(idx.shape[0]):
                r = idx[s]
                rem = n
                for i in range(m):
                    v = 0
                    while True:
                        w = counts[m - 1 - i, rem - v]
                        if r < w:
                            break
                        r -= w
                        v += 1
                    out[s, i] = v
                    rem -= v
            return 0

        _KERNELS.update(enumerate_states=enumerate_states, rank_many=rank_many, unrank_many=unrank_many)
    return _KERNELS


def boson_basis(sites: int, particles: int, nmax: int, *, max_states: int | None = None) -> BosonBasis:
    r"""Build the Fock basis of ``particles`` bosons on ``sites`` sites, at most ``nmax`` per site.

    Parameters
    ----------
    sites : int
        Number of sites M (1..4096).
    particles : int
        Number of bosons N >= 0, at most ``sites * nmax``.
    nmax : int
        Occupation cutoff (1..255); 1 gives hard-core bosons, ``nmax >= particles`` is exact.
    max_states : int, optional
        Refuse bases larger than this (default: only the memory limit).

    Returns
    -------
    BosonBasis
        ``dim`` states, their occupations ``states`` (uint8, shape (D, M), rank order:
        lexicographic with site 0 most significant) and the rank tables.

    Raises
    ------
    ValueError
        Bad arguments, no state at all (N > M nmax), or more than ``max_states`` states.
    MemoryError
        When the occupation table would not fit in the memory this process may use (checked
        from the exact dimension before anything is allocated).

    See Also
    --------
    basis_dimension, rank_states, unrank_states

    Examples
    --------
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> basis = boson_basis(3, 2, 2)
    >>> basis.dim
    6
    >>> basis.states.tolist()
    [[0, 0, 2], [0, 1, 1], [0, 2, 0], [1, 0, 1], [1, 1, 0], [2, 0, 0]]
    """
    m = _validate.integer("sites", sites, minimum=1, maximum=MAX_SITES)
    n = _validate.integer("particles", particles, minimum=0, maximum=MAX_SITES * MAX_NMAX)
    c = _validate.integer("nmax", nmax, minimum=1, maximum=MAX_NMAX)
    if max_states is not None:
        max_states = _validate.positive_int("max_states", max_states)
    if n > m * c:
        raise ValueError(f"{n} bosons do not fit on {m} sites with at most {c} per site.")
    dim = _dimension(m, n, c)
    if dim > MAX_DIM:
        raise ValueError(f"the basis of {n} bosons on {m} sites (cutoff {c}) has about 10^{len(str(dim)) - 1} states, "
                         f"beyond the {MAX_DIM:.1e} that int64 ranks can number.")
    if max_states is not None and dim > max_states:
        raise ValueError(f"the basis has {dim:,} states, more than max_states = {max_states:,}.")
    _validate.require_memory(f"the Fock basis of {n} bosons on {m} sites (cutoff {c}, {dim:,} states)",
                             basis_memory(m, n, c))
    counts, weights = _tables(m, n, c)
    states = np.empty((dim, m), dtype=np.uint8)
    _kernels()["enumerate_states"](m, n, c, counts, states)
    for a in (states, weights, counts):
        a.setflags(write=False)
    return BosonBasis(sites=m, particles=n, nmax=c, dim=dim, states=states, weights=weights, counts=counts)


def _check_basis(basis) -> BosonBasis:
    if not isinstance(basis, BosonBasis):
        raise ValueError(f"basis must come from boson_basis(...), got {type(basis).__name__}.")
    return basis


def rank_states(basis: BosonBasis, occupations) -> np.ndarray:
    """Indices of occupation vectors in the basis (rank order).

    Parameters
    ----------
    basis : BosonBasis
        From :func:`boson_basis`.
    occupations : array of int, shape (M,) or (K, M)
        Occupation vectors; each must have N bosons in total and none above the cutoff.

    Returns
    -------
    ndarray of int64, shape () or (K,)
        The 0-based rank of each vector in ``basis``.

    Raises
    ------
    ValueError
        If ``basis`` is not a BosonBasis, or a vector has the wrong length, an occupation
        outside ``0..nmax`` or not N bosons.

    See Also
    --------
    unrank_states : the inverse.

    Examples
    --------
    >>> from hyperlattice.bosons.basis import boson_basis, rank_states
    >>> basis = boson_basis(3, 2, 2)
    >>> rank_states(basis, [0, 1, 1]).tolist(), rank_states(basis, [[2, 0, 0], [0, 0, 2]]).tolist()
    (1, [5, 0])
    """
    b = _check_basis(basis)
    occ = _validate.real_array("occupations", occupations)
    single = occ.ndim == 1
    occ2 = occ.reshape(1, -1) if single else occ
    if occ2.ndim != 2 or occ2.shape[1] != b.sites:
        raise ValueError(f"occupations must have {b.sites} entries per state, got shape {occ.shape}.")
    if np.any(occ2 != np.round(occ2)) or np.any(occ2 < 0) or np.any(occ2 > b.nmax):
        raise ValueError(f"occupations must be integers between 0 and nmax = {b.nmax}.")
    if np.any(occ2.sum(axis=1) != b.particles):
        raise ValueError(f"every occupation vector must hold {b.particles} bosons.")
    occ_u = occ2.astype(np.int64)
    out = np.empty(occ_u.shape[0], dtype=np.int64)
    _kernels()["rank_many"](occ_u, b.particles, b.weights, out)
    return out[0] if single else out


def unrank_states(basis: BosonBasis, indices) -> np.ndarray:
    """Occupation vectors of basis indices (the inverse of :func:`rank_states`), without the table.

    Parameters
    ----------
    basis : BosonBasis
        From :func:`boson_basis`.
    indices : int or array of int
        Ranks in ``range(basis.dim)``.

    Returns
    -------
    ndarray of int64, shape (M,) or (K, M)
        The occupation vector of each index.

    Raises
    ------
    ValueError
        If ``basis`` is not a BosonBasis or an index is not an integer in ``range(basis.dim)``.

    See Also
    --------
    rank_states : the inverse.

    Examples
    --------
    >>> from hyperlattice.bosons.basis import boson_basis, unrank_states
    >>> basis = boson_basis(3, 2, 2)
    >>> unrank_states(basis, 3).tolist(), unrank_states(basis, [0, 5]).tolist()
    ([1, 0, 1], [[0, 0, 2], [2, 0, 0]])
    """
    b = _check_basis(basis)
    idx = _validate.real_array("indices", indices)
    single = idx.ndim == 0
    idx1 = idx.reshape(-1)
    if np.any(idx1 != np.round(idx1)) or np.any(idx1 < 0) or np.any(idx1 >= b.dim):
        raise ValueError(f"indices must be integers in range({b.dim}).")
    out = np.empty((idx1.shape[0], b.sites), dtype=np.int64)
    _kernels()["unrank_many"](idx1.astype(np.int64), b.sites, b.particles, b.nmax, b.counts, out)
    return out[0] if single else out


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
