r"""Exact grand-canonical thermal averages of the Bose–Hubbard model by full diagonalisation.

The reference of the quantum Monte Carlo (:func:`hyperlattice.bosons.qmc`): every particle-number
block :math:`N = 0 \dots M\,n_{\max}` of

.. math::

    H = -\sum_{i<j} t_{ij} (a_i^\dagger a_j + \mathrm{h.c.})
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i ,
    \qquad t_{ij} = t A_{ij},

with the occupation cutoff :math:`n_i \le n_{\max}` is diagonalised densely, and

.. math::

    \langle O \rangle = \frac{\sum_N \operatorname{Tr}_N O\, e^{-\beta H}}{\sum_N \operatorname{Tr}_N e^{-\beta H}} .

Only small graphs: the whole Fock space :math:`(n_{\max}+1)^M` is limited to
:data:`MAX_STATES` states.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from .. import _validate

__all__ = ["exact_thermal", "MAX_STATES"]

#: largest Fock space (all particle numbers) that :func:`exact_thermal` diagonalises
MAX_STATES = 20_000


def _bond_list(system, t: float):
    """(sites, bi, bj, t_ij) of a flake, a cluster or an adjacency matrix (each bond once, i < j)."""
    from .meanfield import _adjacency

    a = sp.csr_matrix(_adjacency(system))
    up = sp.triu(a, k=1).tocoo()
    keep = up.data != 0
    return (a.shape[0], up.row[keep].astype(np.int64), up.col[keep].astype(np.int64),
            t * up.data[keep].astype(float))


def exact_thermal(system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0) -> dict:
    r"""Exact thermal averages of the Bose–Hubbard model over all particle numbers.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake (:func:`~hyperlattice.ring_lattice`), a periodic cluster, or a symmetric adjacency
        matrix with non-negative weights (bond hopping :math:`t_{ij} = t A_{ij}`).
    U, mu : float
        On-site interaction and chemical potential (units of t... of the same energy unit as t).
    beta : float
        Inverse temperature, > 0.
    nmax : int
        Occupation cutoff per site, >= 1.
    t : float, optional
        Hopping scale (default 1); any sign, the spectrum is exact.

    Returns
    -------
    dict
        ``energy`` (total :math:`\langle H\rangle`, the :math:`-\mu N` term included), ``density``
        (:math:`\langle N\rangle/M`), ``compressibility`` (:math:`\beta(\langle N^2\rangle -
        \langle N\rangle^2)/M`), ``site_density`` (shape (M,)), ``green`` (:math:`G_{ij} =
        \langle a_i^\dagger a_j\rangle`, shape (M, M), with :math:`G_{ii} = \langle n_i\rangle`),
        ``condensate_fraction`` (largest eigenvalue of G over :math:`\langle N\rangle`),
        ``bond_kinetic`` (:math:`\langle a_i^\dagger a_j + a_j^\dagger a_i\rangle` per bond, with
        ``bonds`` the (i, j) pairs), ``free_energy``, ``states`` and ``sites``.

    Raises
    ------
    ValueError
        On bad input, or when the Fock space has more than :data:`MAX_STATES` states.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import exact_thermal
    >>> ex = exact_thermal(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2)
    >>> round(ex["density"], 6), ex["states"]
    (0.723826, 2187)
    """
    U = _validate.real("U", U)
    mu = _validate.real("mu", mu)
    t = _validate.real("t", t)
    beta = _validate.real("beta", beta)
    if not beta > 0:
        raise ValueError(f"beta must be positive, got {beta!r}.")
    nmax = _validate.integer("nmax", nmax, minimum=1)
    sites, bi, bj, tij = _bond_list(system, t)
    if (nmax + 1) ** min(sites, 64) > MAX_STATES or sites > 64:
        raise ValueError(f"exact_thermal diagonalises at most {MAX_STATES:,} Fock states, and {sites} sites with "
                         f"nmax = {nmax} have {(nmax + 1) ** sites:,}.")
    c = nmax + 1
    dim = c ** sites
    codes = np.arange(dim, dtype=np.int64)
    occ = (codes[:, None] // c ** np.arange(sites, dtype=np.int64)[None, :]) % c      # (dim, sites)
    ntot = occ.sum(axis=1)
    radix = c ** np.arange(sites, dtype=np.int64)
    diag = 0.5 * U * (occ * (occ - 1)).sum(axis=1) - mu * ntot
    sq = np.sqrt(np.arange(c + 1, dtype=float))
    blocks = []
    emin = np.inf
    for n in range(sites * nmax + 1):
        idx = np.flatnonzero(ntot == n)
        pos = np.full(dim, -1, dtype=np.int64)
        pos[idx] = np.arange(idx.size)
        h = np.diag(diag[idx]).astype(float)
        o = occ[idx]
        for b in range(bi.size):
            i, j = bi[b], bj[b]
            for src, dst in ((j, i), (i, j)):            # a_dst^dagger a_src
                ok = (o[:, src] > 0) & (o[:, dst] < nmax)
                rows = np.flatnonzero(ok)
                amp = tij[b] * sq[o[rows, src]] * sq[o[rows, dst] + 1]
                tgt = pos[idx[rows] - radix[src] + radix[dst]]
                np.add.at(h, (tgt, rows), -amp)
        w, v = np.linalg.eigh(h)
        blocks.append((n, idx, w, v))
        emin = min(emin, float(w[0]))
    z = 0.0
    e1 = n1 = n2 = 0.0
    dens = np.zeros(sites)
    green = np.zeros((sites, sites))
    for n, idx, w, v in blocks:
        bw = np.exp(-beta * (w - emin))
        z += bw.sum()
        e1 += (bw * w).sum()
        n1 += n * bw.sum()
        n2 += n * n * bw.sum()
        rho = (v * bw) @ v.T                              # unnormalised block density matrix
        o = occ[idx]
        dens += np.diag(rho) @ o
        pos = np.full(dim, -1, dtype=np.int64)
        pos[idx] = np.arange(idx.size)
        for i in range(sites):
            for j in range(sites):
                if i == j:
                    continue
                ok = (o[:, j] > 0) & (o[:, i] < nmax)
                rows = np.flatnonzero(ok)                 # |beta> -> a_i^dag a_j |beta> = amp |alpha>
                amp = sq[o[rows, j]] * sq[o[rows, i] + 1]
                tgt = pos[idx[rows] - radix[j] + radix[i]]
                green[i, j] += float(np.sum(rho[rows, tgt] * amp))
    e = e1 / z
    nm = n1 / z
    dens /= z
    green /= z
    green[np.diag_indices(sites)] = dens
    kin = np.array([green[i, j] + green[j, i] for i, j in zip(bi, bj)])
    lam = float(np.linalg.eigvalsh(green)[-1])
    return {
        "sites": int(sites), "states": int(dim), "U": U, "mu": mu, "t": t, "beta": beta, "nmax": nmax,
        "energy": float(e), "density": float(nm / sites),
        "compressibility": float(beta * (n2 / z - nm * nm) / sites),
        "site_density": dens, "green": green,
        "condensate_fraction": float(lam / nm) if nm > 0 else math.nan,
        "bonds": np.stack([bi, bj], axis=1), "bond_kinetic": kin,
        "free_energy": float(emin - math.log(z) / beta),
    }
