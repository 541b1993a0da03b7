r"""Exact diagonalisation of the Bose–Hubbard model on flakes and periodic clusters.

.. math::

    H = -t \sum_{\langle ij\rangle} (a_i^\dagger a_j + a_j^\dagger a_i)
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i

in the number-conserving Fock basis of :mod:`hyperlattice.bosons.basis` (N bosons, at most
``nmax`` per site: a truncation of the boson Hilbert space unless ``nmax >= N``; ``nmax = 1`` is
exactly the hard-core model). Energies are in the units of t and U, with t = 1 unless given.
At fixed N the chemical potential only shifts every level by :math:`-\mu N`.

Three routes, one kernel (:mod:`hyperlattice.bosons._kernels`):

* ``"sectors"`` -- block-diagonal in angular momentum. A site permutation R of order p that
  preserves the graph (the p-fold rotation :math:`z \mapsto e^{2\pi i/p}z` of a flake, or the
  rotation of a periodic cluster about the centre of face 0, found as a map automorphism) moves
  the bosons of site i to site R(i). With :math:`L_r` the length of the orbit of the Fock state
  :math:`|r\rangle` (its smallest-rank member, L divides p), the states

  .. math:: |r, m\rangle = L_r^{-1/2} \sum_{s=0}^{L_r - 1} \omega^{m s} R^s |r\rangle,
            \qquad \omega = e^{2\pi i/p},

  exist for :math:`mL_r \equiv 0 \pmod p` and span sector m, so that the amplitude on
  :math:`R^s|r\rangle` is :math:`\omega^{ms}` times that on :math:`|r\rangle`: the convention
  :math:`\psi(R^s i) = \omega^{ms}\psi(i)` of the single-particle sectors
  (:mod:`hyperlattice.graph.symmetry`), to which the one-boson levels reduce. If
  :math:`H|r\rangle = \sum_c h_c |c\rangle` with :math:`c = R^{t_c} |r_c\rangle`, then
  :math:`(H_m)_{r_c, r} \mathrel{+}= h_c\,\omega^{-m t_c} \sqrt{L_r / L_{r_c}}`. Labels are
  signed, :math:`m \in (-p/2, p/2]`; H is real, so :math:`H_{-m} = \overline{H_m}` and only
  :math:`0 \le m \le p/2` are diagonalised (the -m levels are copies, listed after +m).
* ``"csr"`` -- the full sparse matrix (numba, two passes: row counts, then entries).
* ``"matrix-free"`` -- a :class:`scipy.sparse.linalg.LinearOperator` whose product gathers every
  row on the fly (memory: the occupation table and the Lanczos vectors only), for bases whose
  matrix would not fit.

Lowest levels come from dense ``eigh`` on small blocks and from Lanczos (ARPACK ``eigsh``,
``which="SA"``) otherwise; every level's residual :math:`\|H\psi - E\psi\|` is computed and a
:class:`~hyperlattice.errors.ConvergenceWarning` is raised when it exceeds the requested
tolerance times the norm bound of H.

Observables of the ground state (averaged over its degenerate multiplet, an equal-weight
mixture, so that they are well defined and rotation invariant): the density profile
:math:`\langle n_i\rangle`, the one-body density matrix :math:`\rho_{ij} = \langle a_i^\dagger a_j\rangle`,
the condensate fraction :math:`\lambda_{\max}(\rho)/N` (Penrose & Onsager, Phys. Rev. 104, 576
(1956)), and the binned average of :math:`\rho_{ij}` against the hyperbolic distance
:math:`d(z_i, z_j)` (flakes) or against the graph distance times :math:`d_0` (clusters, which
have no coordinates in the disk). The charge gap :math:`E_0(N+1) + E_0(N-1) - 2E_0(N)` at
:math:`\mu = 0` is :func:`charge_gap`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .. import _validate
from .._ties import eigenvalue_tolerance, stable_order
from ..errors import ConvergenceWarning, HyperlatticeError
from ..results import Column, Result
from .basis import BosonBasis, _check_basis, boson_basis, basis_dimension, basis_memory

__all__ = [
    "BoseHubbardGraph", "bose_hubbard_graph", "hamiltonian", "hamiltonian_operator", "FockSectors",
    "fock_sectors", "sector_block", "lift_sector_vector", "BoseHubbardLevels", "bose_hubbard",
    "density_profile", "one_body_density_matrix", "condensate_fraction", "correlation_vs_distance",
    "ChargeGap", "charge_gap", "METHODS",
]

#: the routes of :func:`bose_hubbard`
METHODS = ("auto", "sectors", "csr", "matrix-free", "dense")

#: blocks up to this size are diagonalised densely (LAPACK eigh): exact and faster than Lanczos
DENSE_MAX = 800
#: "auto" uses sectors for bases up to this size (the orbit tables cost 24 bytes per state)
SECTORS_MAX = 20_000_000


# ----------------------------------------------------------------------------
# the graph: sites, neighbour lists, symmetry
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class BoseHubbardGraph:
    r"""What the many-body code needs of a flake or a cluster.

    Attributes
    ----------
    sites : int
        Number of sites M (0-based, in the lattice's order: ring by ring for a flake).
    ptr, nbr : ndarray of int64
        Neighbour lists in CSR form: the neighbours of site j are ``nbr[ptr[j]:ptr[j+1]]``.
    rotation : ndarray of int64, shape (sites,), or None
        A graph automorphism R of order p (site i -> rotation[i]), None if none is known.
    p, q : int
        Schläfli symbol.
    rings : int or None
        Number of rings of a flake (None for a cluster).
    cluster : str or None
        Name of a periodic cluster (None for a flake).
    z : ndarray of complex128, shape (sites,), or None
        Site coordinates in the Poincaré disk (flakes; None for a cluster).
    distance_kind : str
        ``"hyperbolic"`` (flake: :math:`d(z_i, z_j)`, curvature -4) or ``"graph x d0"``
        (cluster: graph distance times :math:`d_0`); see :meth:`pair_distances`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import bose_hubbard_graph
    >>> g = bose_hubbard_graph(hl.ring_lattice(7, 3, 1))
    >>> g.sites, g.rings, g.distance_kind, g.nbr[g.ptr[0]:g.ptr[1]].tolist()
    (7, 1, 'hyperbolic', [1, 6])
    >>> round(float(g.pair_distances()[0, 1]), 6)          # d0 of {7,3}
    0.283128
    """

    sites: int
    ptr: np.ndarray
    nbr: np.ndarray
    rotation: np.ndarray | None
    p: int
    q: int
    rings: int | None
    cluster: str | None
    z: np.ndarray | None
    distance_kind: str

    def pair_distances(self) -> np.ndarray:
        """The (sites, sites) matrix of pair distances (:attr:`distance_kind`), refused if too big."""
        from .. import geometry

        n = self.sites
        _validate.require_memory(f"the {n:,} x {n:,} matrix of pair distances", 24.0 * n * n)
        if self.z is not None:
            return np.asarray(geometry.distance(self.z[:, None], self.z[None, :], check=False), dtype=float)
        from scipy.sparse.csgraph import shortest_path

        adj = sp.csr_matrix((np.ones(self.nbr.shape[0]), self.nbr, self.ptr), shape=(n, n))
        return shortest_path(adj, unweighted=True) * geometry.d0(self.p, self.q)

    @property
    def max_degree(self) -> int:
        return int(np.max(np.diff(self.ptr))) if self.sites else 0

    @property
    def label(self) -> str:
        return (f"{{{self.p},{self.q}}} cluster {self.cluster}" if self.cluster is not None
                else f"{{{self.p},{self.q}}} flake with {self.rings} ring(s)")


def _is_cluster(obj) -> bool:
    from ..graph.clusters import Cluster

    return isinstance(obj, Cluster)


def _face_rotation(nb: np.ndarray, faces: np.ndarray, p: int) -> np.ndarray | None:
    """The rotation of a regular map about the centre of face 0 as a vertex permutation.

    An orientation-preserving map automorphism is fixed by the image of one dart; the dart
    (v0 -> v1) of face 0 goes to (v1 -> v2) and the rest follows by breadth-first search along
    the rotation system (slot k of u goes to slot k + offset of its image). Returns None when
    the result is not an automorphism of order p acting without fixed points.
    """
    n, q = nb.shape
    f = faces[0]
    v0, v1, v2 = int(f[0]), int(f[1]), int(f[2])

    def slot(u, w):
        k = np.flatnonzero(nb[u] == w)
        return int(k[0]) if k.size == 1 else -1

    image = np.full(n, -1, dtype=np.int64)
    offset = np.zeros(n, dtype=np.int64)
    a, b = slot(v0, v1), slot(v1, v2)
    if a < 0 or b < 0:
        return None
    image[v0] = v1
    offset[v0] = (b - a) % q
    queue = [v0]
    while queue:
        u = queue.pop()
        uu = image[u]
        for k in range(q):
            w = int(nb[u, k])
            ww = int(nb[uu, (k + offset[u]) % q])
            bw, bww = slot(w, u), slot(ww, int(uu))
            if bw < 0 or bww < 0:
                return None
            off = (bww - bw) % q
            if image[w] < 0:
                image[w] = ww
                offset[w] = off
                queue.append(w)
            elif image[w] != ww or offset[w] != off:
                return None
    if np.any(image < 0) or np.unique(image).size != n:
        return None
    cur = np.arange(n)
    for s in range(1, p + 1):
        cur = image[cur]
        if s < p and np.any(cur == np.arange(n)):
            return None
    if not np.array_equal(cur, np.arange(n)):
        return None
    return image


def bose_hubbard_graph(lattice) -> BoseHubbardGraph:
    """The graph data of a flake (:func:`~hyperlattice.ring_lattice`) or a periodic cluster.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake of kind "sites" or a cluster from :func:`~hyperlattice.graph.clusters.pbc_cluster`.

    Returns
    -------
    BoseHubbardGraph
        ``sites``, the neighbour lists ``ptr``, ``nbr`` (CSR form), the rotation R of order p
        (None if none is known), p, q, ``rings`` or ``cluster``, the coordinates ``z`` (flakes)
        and ``distance_kind``.

    Raises
    ------
    ValueError
        If ``lattice`` is neither a site flake nor a periodic cluster.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import bose_hubbard_graph
    >>> g = bose_hubbard_graph(hl.ring_lattice(7, 3, 1))
    >>> g.sites, g.max_degree, g.rotation is not None
    (7, 2, True)
    """
    if _is_cluster(lattice):
        c = lattice
        n = c.sites
        nb = np.asarray(c.neighbours, dtype=np.int64)
        ptr = np.arange(0, n * c.q + 1, c.q, dtype=np.int64)
        nbr = nb.ravel().copy()
        rot = _face_rotation(nb, np.asarray(c.faces), c.p)
        return BoseHubbardGraph(sites=n, ptr=ptr, nbr=nbr, rotation=rot, p=c.p, q=c.q, rings=None,
                                cluster=str(c.name), z=None, distance_kind="graph x d0")
    lat = _validate.lattice(lattice, kind="sites")
    from ..graph.operators import adjacency

    a = adjacency(lat).tocsr()
    a.sort_indices()
    return BoseHubbardGraph(sites=lat.sites, ptr=a.indptr.astype(np.int64), nbr=a.indices.astype(np.int64),
                            rotation=np.asarray(lat.rotation, dtype=np.int64), p=int(lat.p), q=int(lat.q),
                            rings=int(lat.rings), cluster=None, z=np.asarray(lat.z, dtype=complex),
                            distance_kind="hyperbolic")


def _graph(lattice) -> BoseHubbardGraph:
    if isinstance(lattice, BoseHubbardGraph):
        return lattice
    if _is_cluster(lattice) or hasattr(lattice, "rotation"):
        return bose_hubbard_graph(lattice)
    raise ValueError(f"lattice must be a flake (ring_lattice) or a periodic cluster (pbc_cluster), "
                     f"got {type(lattice).__name__}.")


def _check_match(basis: BosonBasis, g: BoseHubbardGraph) -> None:
    if basis.sites != g.sites:
        raise ValueError(f"the basis has {basis.sites} sites but the lattice has {g.sites}.")


# ----------------------------------------------------------------------------
# the Hamiltonian: diagonal, CSR, matrix-free
# ----------------------------------------------------------------------------

def _params(U, t, mu) -> tuple[float, float, float]:
    return (_validate.real("U", U), _validate.real("t", t), _validate.real("mu", mu))


def _sq(c: int) -> np.ndarray:
    return np.sqrt(np.arange(c + 2, dtype=float))


def _nchunks(dim: int) -> int:
    import numba

    return max(1, min(dim, 64 * numba.get_num_threads()))


def _diag(basis: BosonBasis, U: float, mu: float) -> np.ndarray:
    from . import _kernels as K

    out = np.empty(basis.dim, dtype=float)
    if basis.dim:
        K.diagonal(basis.states, U, mu, out)
    return out


def _norm_bound(basis: BosonBasis, g: BoseHubbardGraph, U: float, t: float, mu: float) -> float:
    r"""Upper bound of :math:`\|H\|_2` (largest absolute row sum): interaction at most
    :math:`|U| N (n_{\max} - 1)/2`, chemical potential :math:`|\mu| N`, hopping at most
    :math:`|t| q_{\max} N \sqrt{n_{\max}+1}` (each boson hops along at most q_max edges with
    amplitude at most :math:`\sqrt{n_j (n_i+1)} \le n_j\sqrt{n_{\max}+1}`)."""
    n, c = basis.particles, basis.nmax
    return (abs(U) * n * max(c - 1, 0) / 2 + abs(mu) * n + abs(t) * g.max_degree * n * math.sqrt(c + 1))


def _csr_bytes(nnz: int, dim: int) -> int:
    return 20 * nnz + 16 * (dim + 1)   # int64 indices and float64 data, then the int32 copies


def hamiltonian(basis: BosonBasis, lattice, U: float, t: float = 1.0, mu: float = 0.0) -> sp.csr_matrix:
    r"""The Bose–Hubbard Hamiltonian on the full Fock basis as a real symmetric CSR matrix.

    Parameters
    ----------
    basis : BosonBasis
        From :func:`~hyperlattice.bosons.basis.boson_basis` with ``sites == lattice.sites``.
    lattice : Lattice, Cluster or BoseHubbardGraph
        A site flake (``ring_lattice``), a periodic cluster, or their graph data.
    U : float
        On-site interaction (units of t).
    t : float, optional
        Hopping amplitude. Default 1.
    mu : float, optional
        Chemical potential (units of t). Default 0.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (D, D)
        Real symmetric float64 matrix of
        :math:`H = -t\sum_{\langle ij\rangle}(a_i^\dagger a_j + {\rm h.c.})
        + \frac U2\sum_i n_i(n_i-1) - \mu\sum_i n_i` in the order of ``basis``, D its dimension.

    Raises
    ------
    ValueError
        For bad input, or a basis whose number of sites differs from the lattice's.
    MemoryError
        When the matrix would not fit (checked after counting its entries, before allocating them).

    See Also
    --------
    hamiltonian_operator : the same H without storing it.
    sector_block : one angular-momentum block.
    bose_hubbard : lowest levels and observables.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020): the Bose–Hubbard model on
       the hyperbolic graph (source label ``eq13``).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import hamiltonian
    >>> H = hamiltonian(basis, lat, U=4.0)
    >>> H.shape, H.nnz
    ((84, 84), 476)
    >>> print(f"{np.linalg.eigvalsh(H.toarray())[0]:.6f}")
    -5.169517
    """
    from . import _kernels as K

    b = _check_basis(basis)
    g = _graph(lattice)
    _check_match(b, g)
    U, t, mu = _params(U, t, mu)
    counts = np.empty(b.dim, dtype=np.int64)
    nch = _nchunks(b.dim)
    if b.dim:
        K.row_counts(b.states, b.nmax, g.ptr, g.nbr, counts, nch)
    nnz = int(counts.sum())
    _validate.require_memory(f"the Bose-Hubbard matrix ({b.dim:,} states, {nnz:,} entries)",
                             _csr_bytes(nnz, b.dim) + 8 * b.dim)
    indptr = np.zeros(b.dim + 1, dtype=np.int64)
    np.cumsum(counts, out=indptr[1:])
    del counts
    idx = np.int32 if b.dim < 2**31 else np.int64
    indices = np.empty(nnz, dtype=np.int64)
    data = np.empty(nnz, dtype=float)
    diag = _diag(b, U, mu)
    if b.dim:
        K.csr_fill(b.states, b.weights, b.particles, b.nmax, g.ptr, g.nbr, diag, t, _sq(b.nmax),
                   indptr, indices, data, nch)
    mat = sp.csr_matrix((data, indices.astype(idx), indptr.astype(idx)), shape=(b.dim, b.dim))
    return mat


def hamiltonian_operator(basis: BosonBasis, lattice, U: float, t: float = 1.0,
                         mu: float = 0.0) -> spla.LinearOperator:
    r"""The Bose–Hubbard Hamiltonian as a matrix-free :class:`~scipy.sparse.linalg.LinearOperator`.

    Each product recomputes the hops of every state (numba, parallel over states): memory is
    the occupation table plus two vectors, for bases whose matrix would not fit.

    Parameters
    ----------
    basis : BosonBasis
        From :func:`~hyperlattice.bosons.basis.boson_basis` with ``sites == lattice.sites``.
    lattice : Lattice, Cluster or BoseHubbardGraph
        As in :func:`hamiltonian`.
    U : float
        On-site interaction (units of t).
    t : float, optional
        Hopping amplitude. Default 1.
    mu : float, optional
        Chemical potential (units of t). Default 0.

    Returns
    -------
    scipy.sparse.linalg.LinearOperator
        Real symmetric, float64, shape (D, D).

    Raises
    ------
    ValueError
        For bad input, or a basis whose number of sites differs from the lattice's.

    See Also
    --------
    hamiltonian : the stored CSR matrix.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import hamiltonian, hamiltonian_operator
    >>> op = hamiltonian_operator(basis, lat, U=4.0)
    >>> v = np.ones(basis.dim)
    >>> op.shape, bool(np.allclose(op @ v, hamiltonian(basis, lat, U=4.0) @ v))
    ((84, 84), True)
    """
    from . import _kernels as K

    b = _check_basis(basis)
    g = _graph(lattice)
    _check_match(b, g)
    U, t, mu = _params(U, t, mu)
    diag = _diag(b, U, mu)
    sq = _sq(b.nmax)
    nch = _nchunks(b.dim)

    def mv(x):
        x = np.ascontiguousarray(np.asarray(x).reshape(-1))
        if np.iscomplexobj(x):
            return mv(x.real) + 1j * mv(x.imag)
        x = x.astype(float, copy=False)
        y = np.empty(b.dim, dtype=float)
        K.matvec(b.states, b.weights, b.particles, b.nmax, g.ptr, g.nbr, diag, t, sq, x, y, nch)
        return y

    return spla.LinearOperator((b.dim, b.dim), matvec=mv, rmatvec=mv, dtype=float)


# ----------------------------------------------------------------------------
# angular-momentum sectors
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class FockSectors:
    r"""Orbits of the Fock states under a site permutation R of order p.

    Attributes
    ----------
    p : int
        Order of R.
    rotation : ndarray of int64
        The site permutation (site i -> rotation[i]).
    rep : ndarray of int64, shape (D,)
        Smallest rank in the orbit of each state.
    shift : ndarray of int64, shape (D,)
        t in [0, L) with state = R^t rep.
    period : ndarray of int64, shape (D,)
        Orbit length L (a divisor of p).
    dims : ndarray of int64, shape (p,)
        ``dims[m % p]``: number of orbits with :math:`mL \equiv 0 \pmod p`, the dimension of
        sector m; they add up to D.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> from hyperlattice.bosons.ed import fock_sectors
    >>> sectors = fock_sectors(boson_basis(7, 3, 3), hl.ring_lattice(7, 3, 1))
    >>> sectors.p, sectors.dims.tolist(), sectors.dim(-1)
    (7, [12, 12, 12, 12, 12, 12, 12], 12)
    """

    p: int
    rotation: np.ndarray
    rep: np.ndarray
    shift: np.ndarray
    period: np.ndarray
    dims: np.ndarray

    def dim(self, m: int) -> int:
        """Dimension of sector m (any integer, taken mod p).

        Parameters
        ----------
        m : int
            Angular momentum (signed or not; taken mod p).

        Returns
        -------
        int
            The number of states of sector m.
        """
        return int(self.dims[int(m) % self.p])


def fock_sectors(basis: BosonBasis, lattice) -> FockSectors:
    """The rotation orbits of every Fock state (the bookkeeping of the sector blocks).

    Parameters
    ----------
    basis : BosonBasis
        From :func:`~hyperlattice.bosons.basis.boson_basis` with ``sites == lattice.sites``.
    lattice : Lattice, Cluster or BoseHubbardGraph
        Must have a rotation (every flake has; a cluster when its face rotation was found).

    Returns
    -------
    FockSectors
        For every Fock state its orbit representative ``rep``, ``shift`` and orbit length
        ``period``; ``dims[m % p]`` the dimension of sector m (``dim(m)`` gives it too).

    Raises
    ------
    ValueError
        For bad input, a basis of another size, or a lattice without a rotation symmetry.

    See Also
    --------
    sector_block, lift_sector_vector

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import fock_sectors
    >>> sectors = fock_sectors(basis, lat)
    >>> [sectors.dim(m) for m in range(7)]
    [12, 12, 12, 12, 12, 12, 12]
    """
    from . import _kernels as K

    b = _check_basis(basis)
    g = _graph(lattice)
    _check_match(b, g)
    if g.rotation is None:
        raise ValueError(f"the {g.label} has no rotation symmetry to label sectors with.")
    _validate.require_memory(f"the rotation orbits of {b.dim:,} Fock states", 24 * b.dim)
    p = g.p
    rep = np.empty(b.dim, dtype=np.int64)
    shift = np.empty(b.dim, dtype=np.int64)
    period = np.empty(b.dim, dtype=np.int64)
    if b.dim:
        K.orbits(b.states, b.weights, b.particles, g.rotation, p, rep, shift, period, _nchunks(b.dim))
    is_rep = rep == np.arange(b.dim)
    lengths = period[is_rep]
    dims = np.array([int(np.count_nonzero((m * lengths) % p == 0)) for m in range(p)], dtype=np.int64)
    return FockSectors(p=p, rotation=g.rotation, rep=rep, shift=shift, period=period, dims=dims)


def _sector_index(sec: FockSectors, m: int) -> tuple[np.ndarray, np.ndarray]:
    dim = sec.rep.shape[0]
    is_rep = sec.rep == np.arange(dim)
    keep = is_rep & ((m * sec.period) % sec.p == 0)
    reps = np.flatnonzero(keep)
    index = np.full(dim, -1, dtype=np.int64)
    index[reps] = np.arange(reps.shape[0])
    return reps, index


def _check_sectors(sec, basis: BosonBasis) -> FockSectors:
    if not isinstance(sec, FockSectors):
        raise ValueError(f"sectors must come from fock_sectors(basis, lattice), got {type(sec).__name__}.")
    if sec.rep.shape[0] != basis.dim:
        raise ValueError("the sectors belong to a different basis.")
    return sec


def sector_block(basis: BosonBasis, lattice, sectors: FockSectors, m: int, U: float, t: float = 1.0,
                 mu: float = 0.0) -> sp.csr_matrix:
    r"""The block :math:`H_m` of angular momentum m (complex Hermitian CSR; see the module docstring).

    Parameters
    ----------
    basis : BosonBasis
        From :func:`~hyperlattice.bosons.basis.boson_basis` with ``sites == lattice.sites``.
    lattice : Lattice, Cluster or BoseHubbardGraph
        As in :func:`hamiltonian`.
    sectors : FockSectors
        From :func:`fock_sectors` of the same basis and lattice.
    m : int
        Sector, in ``range(p)`` or signed in :math:`(-p/2, p/2]`.
    U : float
        On-site interaction (units of t).
    t : float, optional
        Hopping amplitude. Default 1.
    mu : float, optional
        Chemical potential (units of t). Default 0.

    Returns
    -------
    scipy.sparse.csr_matrix of complex128, shape (sectors.dim(m),) * 2
        The Hermitian block :math:`H_m` in the basis :math:`|r, m\rangle` of the module
        docstring.

    Raises
    ------
    ValueError
        For bad input, sectors of another basis, or m out of range.

    See Also
    --------
    fock_sectors, lift_sector_vector, hamiltonian

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import fock_sectors, sector_block
    >>> block = sector_block(basis, lat, fock_sectors(basis, lat), 0, U=4.0)
    >>> block.shape
    (12, 12)
    >>> print(f"{np.linalg.eigvalsh(block.toarray())[0]:.6f}")
    -5.169517
    """
    from . import _kernels as K

    b = _check_basis(basis)
    g = _graph(lattice)
    _check_match(b, g)
    sec = _check_sectors(sectors, b)
    p = sec.p
    m = _validate.integer("m", m)
    if not (-p / 2 < m < p):
        raise ValueError(f"sector m must be in range(p) = 0..{p - 1} or signed in ({-p / 2:g}, {p / 2:g}], got {m}.")
    U, t, mu = _params(U, t, mu)
    reps, index = _sector_index(sec, m)
    nr = reps.shape[0]
    counts = np.empty(nr, dtype=np.int64)
    nch = _nchunks(max(nr, 1))
    if nr:
        K.sector_counts(b.states, b.nmax, g.ptr, g.nbr, reps, counts, nch)
    nnz = int(counts.sum())
    _validate.require_memory(f"the sector block m = {m} ({nr:,} states, {nnz:,} entries)", 40 * nnz)
    offsets = np.zeros(nr + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    rows = np.empty(nnz, dtype=np.int64)
    cols = np.empty(nnz, dtype=np.int64)
    re = np.empty(nnz)
    im = np.empty(nnz)
    # omega^(-m t) from the integer j = m t mod p: exactly +-1 where 2j = 0 mod p, so that the
    # blocks m = 0 and m = p/2 come out exactly real
    j = (m * np.arange(p)) % p
    ang = -2.0 * np.pi * j / p
    ph_re, ph_im = np.cos(ang), np.sin(ang)
    ph_re[j == 0], ph_im[j == 0] = 1.0, 0.0
    ph_re[2 * j == p], ph_im[2 * j == p] = -1.0, 0.0
    if nr:
        K.sector_fill(b.states, b.weights, b.particles, b.nmax, g.ptr, g.nbr, _diag(b, U, mu), t, _sq(b.nmax),
                      reps, sec.rep, sec.shift, sec.period, index, ph_re, ph_im, offsets,
                      rows, cols, re, im, nch)
    mat = sp.coo_matrix((re + 1j * im, (rows, cols)), shape=(nr, nr)).tocsr()
    mat.sum_duplicates()
    return mat


def lift_sector_vector(sectors: FockSectors, m: int, phi) -> np.ndarray:
    r"""A sector-m vector (coefficients of :math:`|r, m\rangle`) as a vector of the full Fock basis.

    :math:`\psi(R^s r) = \omega^{ms}\,\phi_r / \sqrt{L_r}`.

    Parameters
    ----------
    sectors : FockSectors
        From :func:`fock_sectors`.
    m : int
        The sector of ``phi``.
    phi : array_like of complex, shape (sectors.dim(m),)
        Coefficients of :math:`|r, m\rangle`, one per orbit of the sector (as from an
        eigenvector of :func:`sector_block`).

    Returns
    -------
    ndarray of complex128, shape (D,)
        The same state in the full Fock basis (normalised when ``phi`` is).

    Raises
    ------
    ValueError
        If ``sectors`` is not a FockSectors or ``phi`` has the wrong length.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import fock_sectors, hamiltonian, lift_sector_vector, sector_block
    >>> sectors = fock_sectors(basis, lat)
    >>> w, v = np.linalg.eigh(sector_block(basis, lat, sectors, 0, U=4.0).toarray())
    >>> psi = lift_sector_vector(sectors, 0, v[:, 0])
    >>> H = hamiltonian(basis, lat, U=4.0)
    >>> psi.shape, bool(np.allclose(H @ psi, w[0] * psi))
    ((84,), True)
    """
    sec = sectors
    if not isinstance(sec, FockSectors):
        raise ValueError(f"sectors must come from fock_sectors(basis, lattice), got {type(sec).__name__}.")
    m = _validate.integer("m", m)
    reps, index = _sector_index(sec, m)
    phi = _validate.complex_array("phi", phi, ndim=1)
    if phi.shape[0] != reps.shape[0]:
        raise ValueError(f"phi must have the {reps.shape[0]} entries of sector {m}, got {phi.shape[0]}.")
    idx = index[sec.rep]
    ok = idx >= 0
    out = np.zeros(sec.rep.shape[0], dtype=complex)
    phase = np.exp(2j * np.pi * m * sec.shift[ok] / sec.p)
    out[ok] = phi[idx[ok]] * phase / np.sqrt(sec.period[sec.rep[ok]])
    return out


# ----------------------------------------------------------------------------
# eigensolvers
# ----------------------------------------------------------------------------

#: above this dimension the Krylov space is kept small (memory: ncv vectors of 8 or 16 bytes per state)
_WIDE_MAX = 1_000_000


def _krylov(n: int, k: int, extra: int = 3) -> tuple[int, int]:
    """(levels asked of ARPACK, Krylov dimension ncv) for k wanted levels of an n x n matrix.

    A few levels more than asked and a wide Krylov space: Lanczos from one start vector can miss
    copies of an exactly degenerate level (measured: a 4-fold level of the Bolza cluster, N = 5,
    found once with k = 3, ncv = 20); the sector route resolves +-m pairs exactly. Above
    :data:`_WIDE_MAX` states memory wins: no extra levels and ncv = 2k + 8. Sector blocks ask
    for ``extra = 1`` (the +-m pairs are resolved by the symmetry; the ARPACK work per step grows
    with ncv, measured 2x on the Bolza blocks).
    """
    if n <= _WIDE_MAX:
        kk = min(k + extra, n - 2)
        return kk, min(n - 1, max(2 * kk + 1, 30 if extra >= 3 else 20))
    kk = min(k, n - 2)
    return kk, min(n - 1, 2 * kk + 8)


def _lowest(op, k: int, tol: float, hermitian_complex: bool = False, extra: int = 3):
    """Lowest k eigenpairs of a Hermitian matrix/operator; dense below DENSE_MAX."""
    from ..graph.solvers import single_threaded_blas

    # BLAS on one thread for the dense eigh of small blocks and for ARPACK's many small calls:
    # on a loaded 2-core machine waking OpenBLAS threads costs more than the arithmetic
    # (measured 5.5 s -> 1.2 s on a 65,018-state Klein-quartic block)
    with single_threaded_blas():
        return _lowest_inner(op, k, tol, hermitian_complex, extra)


def _lowest_inner(op, k: int, tol: float, hermitian_complex: bool, extra: int):
    n = op.shape[0]
    k = min(k, n)
    if n <= DENSE_MAX:
        a = op.toarray() if sp.issparse(op) else op @ np.eye(n)
        w, v = sla.eigh(a, subset_by_index=(0, k - 1))
        return w, v
    if k >= n - 1:
        a = op.toarray() if sp.issparse(op) else op @ np.eye(n)
        w, v = sla.eigh(a)
        return w[:k], v[:, :k]
    k_ask = k
    k, ncv = _krylov(n, k, extra)
    rng = np.random.default_rng(12345)
    v0 = rng.standard_normal(n)
    if hermitian_complex:
        v0 = v0 + 1j * rng.standard_normal(n)
    w, v = spla.eigsh(op, k=k, which="SA", tol=tol, ncv=ncv, v0=v0)
    order = np.argsort(w, kind="stable")[:k_ask]
    return w[order], v[:, order]


def _residuals(op, w, v) -> np.ndarray:
    hv = op @ v
    return np.linalg.norm(hv - v * w[None, :], axis=0)


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class BoseHubbardLevels(Result):
    r"""Lowest levels of the Bose–Hubbard model and the ground-state observables.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : int or None
        Rings of the flake (None for a cluster).
    cluster : str or None
        Name of the periodic cluster (None for a flake).
    sites, particles, nmax : int
        M, N and the occupation cutoff (1 = hard-core; a truncation unless nmax >= N).
    U, t, mu : float
        Parameters of H (module docstring), in one energy unit (that of t).
    dim : int
        Dimension of the full Fock basis.
    energies : ndarray, shape (K,)
        The K lowest eigenvalues, ascending (a degenerate +-m pair twice, +m first), in the
        unit of t.
    m : ndarray of int64, shape (K,), or None
        Signed angular momentum in (-p/2, p/2] under the rotation (None without sectors).
    residuals : ndarray, shape (K,)
        :math:`\|H\psi - E\psi\|` of each level's normalised vector.
    tolerance : ndarray, shape (K,)
        Error bound of each energy (:func:`hyperlattice._ties.eigenvalue_tolerance`), used to
        group degenerate levels.
    method : str
        ``"sectors"``, ``"csr"``, ``"matrix-free"`` or ``"dense"``.
    sector_dims : ndarray of int64, shape (p,), or None
        Dimension of sector m at index ``m % p``.
    seconds : float
        Wall time of the diagonalisation.
    density : ndarray, shape (M,), or None
        :math:`\langle n_i\rangle` in the ground-state multiplet (None if not computed).
    density_matrix : ndarray, shape (M, M), or None
        :math:`\langle a_i^\dagger a_j\rangle` (real symmetric).
    condensate_fraction : float
        :math:`\lambda_{\max}(\rho)/N` (NaN if not computed or N = 0).
    distance_bins : ndarray or None
        Centres of the distance bins (width :math:`d_0`) of ``correlation``.
    correlation : ndarray or None
        Mean of :math:`\rho_{ij}` over pairs i != j whose distance falls in each bin.
    distance_kind : str
        ``"hyperbolic"`` (flake) or ``"graph x d0"`` (cluster).
    note : str
        Empty, or what the caller should know about the request (more levels asked than the
        basis has states: all of them are listed).

    Notes
    -----
    Site-indexed arrays (``density``, ``density_matrix``) follow the lattice's order (0-based,
    ring by ring); distances are in the paper's metric. Its table
    (:meth:`~hyperlattice.results.Result.to_dataframe`) has one row per level: ``energy``, ``m``,
    ``residual`` and ``tolerance`` (the per-site ``density`` and the correlations are not part of it).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import bose_hubbard
    >>> res = bose_hubbard(hl.ring_lattice(7, 3, 1), 3, 3, 4.0, levels=3)
    >>> res.method, res.dim, res.sector_dims.tolist()
    ('sectors', 84, [12, 12, 12, 12, 12, 12, 12])
    >>> [round(float(e), 6) for e in res.energies], res.m.tolist()
    ([-5.169517, -3.817032, -3.817032], [0, 1, -1])
    >>> [round(float(n), 6) for n in res.density[:2]]       # N/M = 3/7 per site
    [0.428571, 0.428571]
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("m", "m", "1"), Column("residual", "residuals", "t"),
               Column("tolerance", "tolerance", "t"))

    p: int
    q: int
    rings: int | None
    cluster: str | None
    sites: int
    particles: int
    nmax: int
    U: float
    t: float
    mu: float
    dim: int
    energies: np.ndarray
    m: np.ndarray | None
    residuals: np.ndarray
    tolerance: np.ndarray
    method: str
    sector_dims: np.ndarray | None = None
    seconds: float = math.nan
    density: np.ndarray | None = None
    density_matrix: np.ndarray | None = None
    condensate_fraction: float = math.nan
    distance_bins: np.ndarray | None = None
    correlation: np.ndarray | None = None
    distance_kind: str = ""
    note: str = ""

    def summary(self) -> dict:
        """The CLI view: ``sites, particles, nmax, U, t, dim, energies`` (the contract) and
        ``m, residuals, method, system`` (plus ``condensate_fraction`` when computed, and ``note``
        when there is one)."""
        out = {"sites": self.sites, "particles": self.particles, "nmax": self.nmax, "U": self.U,
               "t": self.t, "dim": self.dim, "energies": [float(e) for e in self.energies],
               "m": None if self.m is None else [int(v) for v in self.m],
               "residuals": [float(r) for r in self.residuals], "method": self.method,
               "p": self.p, "q": self.q, "rings": self.rings, "cluster": self.cluster}
        if self.density is not None:
            out["condensate_fraction"] = float(self.condensate_fraction)
        if self.note:
            out["note"] = self.note
        return out


# ----------------------------------------------------------------------------
# observables
# ----------------------------------------------------------------------------

#: chunks of basis states of the one-body kernel (threads take whole chunks; at most this many run)
_ONE_BODY_CHUNKS = 32


def _one_body(b: BosonBasis, psi: np.ndarray) -> np.ndarray:
    from . import _kernels as K

    # one (M, M) accumulator per chunk: few chunks, so the sum over them stays cheap. Their number
    # is fixed, not set by the thread count: the chunks' partial sums are added in order, so the
    # matrix is the same bit for bit on any number of threads (any machine's core count)
    nch = max(1, min(b.dim, _ONE_BODY_CHUNKS))
    out_re = np.zeros((nch, b.sites, b.sites))
    out_im = np.zeros((nch, b.sites, b.sites))
    K.one_body(b.states, b.weights, b.particles, b.nmax, _sq(b.nmax), np.ascontiguousarray(psi.real),
               np.ascontiguousarray(psi.imag), out_re, out_im, nch)
    return out_re.sum(axis=0) + 1j * out_im.sum(axis=0)


def one_body_density_matrix(basis: BosonBasis, psi) -> np.ndarray:
    r"""The one-body density matrix :math:`\rho_{ij} = \langle\psi| a_i^\dagger a_j |\psi\rangle`.

    Parameters
    ----------
    basis : BosonBasis
        The Fock basis of ``psi`` (M sites, N bosons).
    psi : array, shape (D,) or (D, k)
        A normalised state, or k orthonormal states (then the equal-weight mixture
        :math:`\frac1k\sum_l \langle\psi_l|\cdot|\psi_l\rangle`).

    Returns
    -------
    ndarray, shape (M, M)
        Hermitian; real (float64) when its imaginary part vanishes to rounding. Its diagonal is
        the density :math:`\langle n_i\rangle` and its trace N.

    Raises
    ------
    ValueError
        If ``psi`` does not have one entry per basis state or is not normalised.

    See Also
    --------
    condensate_fraction, correlation_vs_distance

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import hamiltonian, one_body_density_matrix
    >>> psi0 = np.linalg.eigh(hamiltonian(basis, lat, U=4.0).toarray())[1][:, 0]
    >>> rho = one_body_density_matrix(basis, psi0)
    >>> rho.shape, round(float(np.trace(rho)), 6)
    ((7, 7), 3.0)
    >>> print(f"{rho[0, 1]:.6f}")
    0.397753
    """
    b = _check_basis(basis)
    v = _validate.complex_array("psi", psi)
    if v.ndim == 1:
        v = v[:, None]
    if v.ndim != 2 or v.shape[0] != b.dim or v.shape[1] < 1:
        raise ValueError(f"psi must have {b.dim} entries (one per basis state), got shape {np.shape(psi)}.")
    norms = np.linalg.norm(v, axis=0)
    if np.any(np.abs(norms - 1.0) > 1e-8):
        raise ValueError("psi must be normalised (each column of unit norm).")
    rho = sum(_one_body(b, v[:, k]) for k in range(v.shape[1])) / v.shape[1]
    rho = 0.5 * (rho + rho.conj().T)
    # rounding of the sums: a few eps times N per entry
    if np.max(np.abs(rho.imag), initial=0.0) <= 1e3 * np.finfo(float).eps * max(1, b.particles):
        return np.ascontiguousarray(rho.real)
    return rho


def density_profile(basis: BosonBasis, psi) -> np.ndarray:
    r"""The density :math:`\langle n_i\rangle` of a state (or the mean over orthonormal states).

    Parameters
    ----------
    basis : BosonBasis
        The Fock basis of ``psi`` (M sites).
    psi : array, shape (D,) or (D, k)
        A normalised state, or k orthonormal states (then their mean).

    Returns
    -------
    ndarray of float, shape (M,)
        :math:`\langle n_i\rangle` per site (0-based site order of the lattice); sums to N.

    Raises
    ------
    ValueError
        If ``psi`` does not have one entry per basis state.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.basis import boson_basis
    >>> lat = hl.ring_lattice(7, 3, 1)            # one heptagon, 7 sites
    >>> basis = boson_basis(7, 3, 3)              # 3 bosons, at most 3 per site
    >>> from hyperlattice.bosons.ed import density_profile, hamiltonian
    >>> psi0 = np.linalg.eigh(hamiltonian(basis, lat, U=4.0).toarray())[1][:, 0]
    >>> [round(float(n), 6) for n in density_profile(basis, psi0)][:3]
    [0.428571, 0.428571, 0.428571]
    """
    b = _check_basis(basis)
    v = _validate.complex_array("psi", psi)
    if v.ndim == 1:
        v = v[:, None]
    if v.ndim != 2 or v.shape[0] != b.dim or v.shape[1] < 1:
        raise ValueError(f"psi must have {b.dim} entries (one per basis state), got shape {np.shape(psi)}.")
    w = np.sum(np.abs(v) ** 2, axis=1) / v.shape[1]
    return np.asarray(w @ b.states.astype(float))


def condensate_fraction(rho, particles: int) -> float:
    r"""Largest eigenvalue of the one-body density matrix over N (Penrose–Onsager).

    Parameters
    ----------
    rho : array, shape (M, M)
        Hermitian one-body density matrix (:func:`one_body_density_matrix`).
    particles : int
        N >= 1.

    Returns
    -------
    float
        In [1/M, 1] for a physical state (1 for a single orbital, N/M... for a Mott state).

    Raises
    ------
    ValueError
        If ``rho`` is not square and Hermitian, or N < 1.

    References
    ----------
    .. [1] O. Penrose and L. Onsager, Phys. Rev. 104, 576 (1956).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.bosons.ed import condensate_fraction
    >>> round(condensate_fraction(np.full((4, 4), 0.5), 2), 6)   # all bosons in one orbital
    1.0
    >>> round(condensate_fraction(0.5 * np.eye(4), 2), 6)        # no coherence between sites
    0.25
    """
    r = _validate.complex_array("rho", rho, ndim=2)
    n = _validate.positive_int("particles", particles)
    if r.shape[0] != r.shape[1]:
        raise ValueError(f"rho must be square, got shape {r.shape}.")
    if np.max(np.abs(r - r.conj().T), initial=0.0) > 1e-8 * max(1.0, np.max(np.abs(r), initial=0.0)):
        raise ValueError("rho must be Hermitian.")
    return float(sla.eigvalsh(0.5 * (r + r.conj().T))[-1] / n)


def correlation_vs_distance(rho, distance, width: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Mean of :math:`\mathrm{Re}\,\rho_{ij}` over site pairs i != j in distance bins.

    Parameters
    ----------
    rho : array, shape (M, M)
    distance : array, shape (M, M)
        Pair distances (hyperbolic, or graph distance times d0).
    width : float
        Bin width (> 0); bin k is :math:`[(k - 1/2)w, (k + 1/2)w)`, centred on k w, k >= 1.

    Returns
    -------
    centres, mean, count : ndarray
        Bin centres k w (units of the distance), the mean of :math:`\mathrm{Re}\,\rho_{ij}` in
        each bin and the number of ordered pairs (int64); only the bins that hold at least one
        pair.

    Raises
    ------
    ValueError
        If the arrays are not square of one shape or ``width`` is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.bosons.ed import correlation_vs_distance
    >>> rho = np.array([[1.0, 0.5, 0.1], [0.5, 1.0, 0.5], [0.1, 0.5, 1.0]])
    >>> d = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 1.0], [2.0, 1.0, 0.0]])
    >>> centres, mean, count = correlation_vs_distance(rho, d, 1.0)
    >>> centres.tolist(), mean.tolist(), count.tolist()
    ([1.0, 2.0], [0.5, 0.1], [4, 2])
    """
    r = _validate.complex_array("rho", rho, ndim=2)
    d = _validate.real_array("distance", distance, ndim=2)
    w = _validate.positive_real("width", width)
    if r.shape != d.shape or r.shape[0] != r.shape[1]:
        raise ValueError(f"rho and distance must be square of one shape, got {r.shape} and {d.shape}.")
    off = ~np.eye(r.shape[0], dtype=bool)
    k = np.floor(d[off] / w + 0.5).astype(np.int64)
    vals = r.real[off]
    if k.size == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=np.int64)
    cnt = np.bincount(k)
    tot = np.bincount(k, weights=vals)
    keep = cnt > 0
    idx = np.flatnonzero(keep)
    return idx * w, tot[keep] / cnt[keep], cnt[keep].astype(np.int64)


# ----------------------------------------------------------------------------
# the driver
# ----------------------------------------------------------------------------

def _choose(method: str, g: BoseHubbardGraph, dim: int, nnz_bound: int) -> str:
    if method != "auto":
        return method
    if g.rotation is not None and dim <= SECTORS_MAX:
        return "sectors"
    if dim <= DENSE_MAX:
        return "dense"
    if _csr_bytes(nnz_bound, dim) + 40 * 8 * dim < 0.5 * _validate.available_memory():
        return "csr"
    return "matrix-free"


def bose_hubbard(lattice, particles: int, nmax: int, U: float, *, t: float = 1.0, mu: float = 0.0,
                 levels: int = 4, method: str = "auto", tol: float = 1e-10,
                 observables: bool = True) -> BoseHubbardLevels:
    r"""Lowest levels (with sector labels) and ground-state observables of the Bose–Hubbard model.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake (:func:`~hyperlattice.ring_lattice`) or a periodic cluster
        (:func:`~hyperlattice.graph.clusters.pbc_cluster`).
    particles : int
        N >= 0.
    nmax : int
        Occupation cutoff (1 = hard-core; the truncation is exact only for nmax >= N).
    U : float
        On-site interaction (units of energy, as t).
    t : float
        Hopping (default 1).
    mu : float
        Chemical potential; shifts every level by :math:`-\mu N`.
    levels : int
        Number K of lowest levels (fewer if the basis is smaller).
    method : str
        ``"auto"`` (sectors when the lattice has a rotation, else dense / CSR / matrix-free by
        size), ``"sectors"``, ``"csr"``, ``"matrix-free"`` or ``"dense"``.
    tol : float
        Lanczos tolerance; levels whose residual exceeds ``max(tol, 1e-9)`` times the norm bound
        of H warn (:class:`~hyperlattice.errors.ConvergenceWarning`).
    observables : bool
        Compute density, one-body density matrix, condensate fraction and the distance
        dependence of :math:`\rho_{ij}` for the ground-state multiplet.

    Returns
    -------
    BoseHubbardLevels
        The K lowest ``energies`` (units of t) with their sector labels ``m``, ``residuals``,
        ``tolerance`` and the ``method`` used; with ``observables`` the ground-state ``density``,
        ``density_matrix``, ``condensate_fraction`` and ``correlation`` on ``distance_bins``.

    Raises
    ------
    ValueError
        For bad input, ``"sectors"`` on a lattice without a rotation, or more bosons than
        ``sites * nmax``.
    MemoryError
        When the chosen route (dense matrix, CSR matrix or Lanczos vectors) or the observables
        would not fit in the memory available (checked before allocating).
    hyperlattice.errors.HyperlatticeError
        If the ground-state one-body density matrix comes out complex (a multiplet that is not
        closed under the rotation).

    Warns
    -----
    ConvergenceWarning
        If a level's residual exceeds ``max(tol, 1e-9)`` times the norm bound of H.

    See Also
    --------
    hamiltonian, charge_gap
    hyperlattice.bosons.meanfield.mott_lobe : the mean-field phase boundary.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020): the Bose–Hubbard model on
       the hyperbolic graph (source label ``eq13``).

    Examples
    --------
    Three bosons on one heptagon, at most three per site:

    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import bose_hubbard
    >>> res = bose_hubbard(hl.ring_lattice(7, 3, 1), 3, 3, 4.0, levels=3)
    >>> res.method, res.m.tolist()
    ('sectors', [0, 1, -1])
    >>> [round(float(e), 6) for e in res.energies]
    [-5.169517, -3.817032, -3.817032]
    >>> print(f"{res.condensate_fraction:.6f}")
    0.879296
    """
    from .. import geometry

    g = _graph(lattice)
    n = _validate.integer("particles", particles, minimum=0, maximum=g.sites * 255)
    c = _validate.integer("nmax", nmax, minimum=1, maximum=255)
    U, t, mu = _params(U, t, mu)
    k = _validate.positive_int("levels", levels, maximum=10_000)
    method = _validate.choice("method", method, METHODS)
    tol = _validate.real("tol", tol, minimum=0.0, maximum=0.1)
    observables = _validate.flag("observables", observables)
    if method == "sectors" and g.rotation is None:
        raise ValueError(f"the {g.label} has no rotation symmetry: use method 'csr' or 'matrix-free'.")
    if n > g.sites * c:
        raise ValueError(f"{n} bosons do not fit on {g.sites} sites with at most {c} per site.")
    dim = basis_dimension(g.sites, n, c)
    if observables:
        # the density matrix, its per-thread accumulators and the pair distances are M x M each
        _validate.require_memory(f"the ground-state observables of {g.sites:,} sites", 8.0 * g.sites**2 * 12)
    hops = min(n, g.sites) * g.max_degree
    route = _choose(method, g, dim, dim * (1 + hops))
    if route == "dense":
        _validate.require_memory(f"a dense {dim:,} x {dim:,} Bose-Hubbard matrix", 3 * 8.0 * dim * dim)
    if route in ("matrix-free", "csr"):
        ncv = _krylov(dim, k)[1] if dim > 2 else 2
        _validate.require_memory(f"Lanczos on {dim:,} states ({ncv} vectors)",
                                 basis_memory(g.sites, n, c) + 8.0 * dim * (ncv + 4))
    b = boson_basis(g.sites, n, c)
    # more levels than states: all of them, and said so (8 asked on a 7-state basis came back as 7)
    note = f"{k} levels asked, but the basis has only {dim} states: all {dim} are listed." if k > dim else ""
    k = min(k, dim)
    # one level more than asked when observables are wanted: it shows where the ground multiplet ends
    k_out = k
    k = min(k + 1, dim) if observables else k
    norm = _norm_bound(b, g, U, t, mu)
    t0 = time.perf_counter()
    sector_dims = None
    if route == "sectors":
        sec = fock_sectors(b, g)
        sector_dims = sec.dims
        es, ms, rs, ns, vecs, tols = [], [], [], [], [], []
        p = g.p
        for m in range(0, p // 2 + 1):
            d = sec.dim(m)
            if d == 0:
                continue
            blk = sector_block(b, g, sec, m, U, t, mu)
            real = m == 0 or 2 * m == p
            if real:  # exactly real (integer phases): half the work in real arithmetic
                blk = blk.real.tocsr()
            kk = min(k, d)
            w, v = _lowest(blk, kk, tol, hermitian_complex=not real, extra=1)
            res = _residuals(blk, w, v)
            for a in range(kk):
                pair = [m] if (m == 0 or 2 * m == p) else [m, -m]
                for mm in pair:
                    es.append(w[a])
                    ms.append(mm)
                    rs.append(res[a])
                    ns.append(d)
                    vecs.append((m, mm, v[:, a]))
        es, ms, rs = np.array(es), np.array(ms, dtype=np.int64), np.array(rs)
        tols = np.array([eigenvalue_tolerance(norm, nd, r) for nd, r in zip(ns, rs)])
        # degenerate levels ordered by |m|, +m before -m (labels, not rounding noise)
        order = stable_order(es, tols, np.abs(ms), -np.sign(ms))[:k]
        energies, mlab, resid, tol_e = es[order], ms[order], rs[order], tols[order]
        chosen = [vecs[i] for i in order]
    else:
        op = (hamiltonian_operator(b, g, U, t, mu) if route == "matrix-free" else hamiltonian(b, g, U, t, mu))
        if route == "dense":
            a = op.toarray()
            w, v = sla.eigh(a, subset_by_index=(0, k - 1))
        else:
            w, v = _lowest(op, k, tol)
        resid = _residuals(op, w, v)
        energies = w
        mlab = None
        tol_e = np.array([eigenvalue_tolerance(norm, dim, r) for r in resid])
        order = stable_order(energies, tol_e)
        energies, resid, tol_e, v = energies[order], resid[order], tol_e[order], v[:, order]
        chosen = [(None, None, v[:, i]) for i in range(k)]
    seconds = time.perf_counter() - t0
    bound = max(tol, 1e-9) * max(norm, 1.0)
    if np.any(resid > bound):
        warnings.warn(f"Bose-Hubbard levels on the {g.label}: largest residual {np.max(resid):.2e} "
                      f"exceeds {bound:.1e} ({route}).", ConvergenceWarning, stacklevel=2)
    extra = {}
    if observables and n > 0 and dim > 0:
        from .._ties import degenerate_groups

        groups = degenerate_groups(energies, tol_e)
        ground = np.flatnonzero(groups == 0)
        if ground[-1] == len(energies) - 1 and len(energies) < dim and route != "dense":
            warnings.warn("the ground-state multiplet may extend beyond the levels computed; "
                          "observables average only the levels found (ask for more levels).",
                          ConvergenceWarning, stacklevel=2)
        psis = []
        for i in ground:
            m, mm, vec = chosen[i]
            if m is None:
                psis.append(np.asarray(vec, dtype=complex))
            else:
                phi = vec if mm == m else np.conj(vec)
                psis.append(lift_sector_vector(sec, mm, phi))
        psi = np.stack(psis, axis=1)
        psi /= np.linalg.norm(psi, axis=0)[None, :]
        rho = one_body_density_matrix(b, psi)
        if np.iscomplexobj(rho):
            raise HyperlatticeError("the ground-state one-body density matrix is not real: the multiplet "
                                    "was cut (ask for more levels).")
        width = geometry.d0(g.p, g.q)
        centres, corr, _ = correlation_vs_distance(rho, g.pair_distances(), width)
        extra = dict(density=np.diag(rho).copy(), density_matrix=rho,
                     condensate_fraction=condensate_fraction(rho, n), distance_bins=centres,
                     correlation=corr, distance_kind=g.distance_kind)
    energies, resid, tol_e = energies[:k_out], resid[:k_out], tol_e[:k_out]
    mlab = None if mlab is None else mlab[:k_out]
    return BoseHubbardLevels(p=g.p, q=g.q, rings=g.rings, cluster=g.cluster, sites=g.sites, particles=n,
                             nmax=c, U=U, t=t, mu=mu, dim=dim, energies=np.asarray(energies, dtype=float),
                             m=mlab, residuals=np.asarray(resid, dtype=float),
                             tolerance=np.asarray(tol_e, dtype=float), method=route, sector_dims=sector_dims,
                             seconds=seconds, note=note, **extra)


@dataclass(frozen=True, eq=False)
class ChargeGap(Result):
    r"""The charge gap :math:`\Delta_c = E_0(N+1) + E_0(N-1) - 2E_0(N)` at :math:`\mu = 0`.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : int or None
        Rings of the flake (None for a cluster).
    cluster : str or None
        Name of the periodic cluster (None for a flake).
    sites, particles, nmax : int
        M, N and the occupation cutoff.
    U, t : float
        Interaction and hopping (one energy unit, that of t).
    energies : ndarray, shape (3,)
        :math:`E_0(N-1), E_0(N), E_0(N+1)` in units of t.
    gap : float
        :math:`\Delta_c` (:math:`\mu_+ - \mu_-`, the width of the N-particle plateau in μ), units of t.
    tolerance : float
        Sum of the error bounds of the four energies entering the gap.

    Notes
    -----
    Its table (:meth:`~hyperlattice.results.Result.to_dataframe`) has three rows, N - 1, N and
    N + 1: ``particles`` and ``ground_energy``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import charge_gap
    >>> gap = charge_gap(hl.ring_lattice(7, 3, 1), 3, 3, 4.0)
    >>> [round(float(e), 6) for e in gap.energies], round(gap.gap, 6)
    ([-3.752579, -5.169517, -6.200382], 0.386073)
    """

    COLUMNS = (Column("particles", "particle_numbers", "1"), Column("ground_energy", "energies", "t"))

    p: int
    q: int
    rings: int | None
    cluster: str | None
    sites: int
    particles: int
    nmax: int
    U: float
    t: float
    energies: np.ndarray
    gap: float
    tolerance: float

    @property
    def particle_numbers(self) -> np.ndarray:
        """N - 1, N, N + 1: the particle numbers of ``energies``."""
        return self.particles + np.arange(-1, 2)


def charge_gap(lattice, particles: int, nmax: int, U: float, *, t: float = 1.0,
               method: str = "auto", tol: float = 1e-10) -> ChargeGap:
    r"""The charge gap :math:`E_0(N+1) + E_0(N-1) - 2E_0(N)` (three ground states at μ = 0).

    Parameters
    ----------
    lattice : Lattice or Cluster
        A site flake (``ring_lattice``) or a periodic cluster.
    particles : int
        N >= 1, with N + 1 <= sites * nmax.
    nmax : int
        Occupation cutoff (1 = hard-core).
    U : float
        On-site interaction (units of t).
    t : float, optional
        Hopping amplitude. Default 1.
    method : str, optional
        Route of :func:`bose_hubbard`. Default ``"auto"``.
    tol : float, optional
        Lanczos tolerance, as in :func:`bose_hubbard`. Default 1e-10.

    Returns
    -------
    ChargeGap
        ``energies`` :math:`E_0(N-1), E_0(N), E_0(N+1)` (units of t), the ``gap``
        :math:`\Delta_c` and its error bound ``tolerance``.

    Raises
    ------
    ValueError
        For bad input, N < 1 or N + 1 > ``sites * nmax``.
    MemoryError
        When one of the three diagonalisations would not fit.

    See Also
    --------
    bose_hubbard
    hyperlattice.compare.bosons.mott_gap_comparison : against mean field and the continuum.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.ed import charge_gap
    >>> cg = charge_gap(hl.ring_lattice(7, 3, 1), 3, 3, 4.0)
    >>> [round(float(e), 6) for e in cg.energies]
    [-3.752579, -5.169517, -6.200382]
    >>> print(f"{cg.gap:.6f}")
    0.386073
    """
    g = _graph(lattice)
    c = _validate.integer("nmax", nmax, minimum=1, maximum=255)
    n = _validate.integer("particles", particles, minimum=1, maximum=g.sites * c - 1)
    e, tl = [], 0.0
    for nn in (n - 1, n, n + 1):
        r = bose_hubbard(g, nn, c, U, t=t, levels=1, method=method, tol=tol, observables=False)
        e.append(float(r.energies[0]))
        tl += (2.0 if nn == n else 1.0) * float(r.tolerance[0])
    gap = e[2] + e[0] - 2 * e[1]
    return ChargeGap(p=g.p, q=g.q, rings=g.rings, cluster=g.cluster, sites=g.sites, particles=n, nmax=c,
                     U=float(U), t=float(t), energies=np.array(e), gap=gap, tolerance=tl)


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
