r"""Densities of states by the kernel polynomial method (KPM), matrix-free, in numba.

For :math:`H = -tA` (``t = 1``) on a graph, the density of states per site is expanded in
Chebyshev polynomials of the rescaled operator :math:`\tilde H = H/a`,

.. math:: \rho(E) = \frac{1}{\pi a\sqrt{1-x^2}}\Big[g_0\mu_0 + 2\sum_{n=1}^{M-1} g_n\mu_n T_n(x)\Big],
          \qquad x = E/a, \qquad \mu_n = \frac1{|S|}\sum_{i\in S}\langle i|T_n(\tilde H)|i\rangle,

with the Jackson kernel :math:`g_n` (Weiße, Wellein, Alvermann, Fehske, Rev. Mod. Phys. 78, 275
(2006), Eq. 71), which keeps the estimate positive and broadens a delta peak at :math:`x_0` into
a near-Gaussian of width about :math:`\pi\sqrt{1-x_0^2}/M` (:meth:`KPMDos.kernel_width` measures it).

Spectral bounds without Lanczos
-------------------------------
The rescaling needs :math:`\|H\| \le a`. For an adjacency matrix every row sums to the degree, so by
Gershgorin :math:`|E| \le d_{\max}` *exactly*: :math:`|E| \le q` on a q-regular periodic cluster (where
:math:`E = -q` is attained by the uniform state) and on a flake (boundary sites have degree < q). For
a general symmetric matrix the bound is the largest absolute row sum, also exact. We take
:math:`a = d_{\max}/(1 - \epsilon)` with :math:`\epsilon = 0.01`, so the spectrum sits inside
:math:`[-0.99, 0.99]`, away from the end points where the Chebyshev weight is singular. No Lanczos
estimate (and no safety factor on an estimate) is needed.

Traces
------
* :func:`kpm_dos`: the stochastic trace :math:`\mathrm{Tr}\,X \approx \frac1R\sum_r \langle r|X|r\rangle`
  with R random vectors, Rademacher (:math:`\pm1`, real) or random-phase (:math:`e^{i\phi}`, complex:
  half the variance of Rademacher for a real H, twice the memory traffic). Vector r is drawn from
  ``numpy.random.default_rng([seed, r])``: a run with more vectors extends a run with fewer. The
  error bar of every moment (and of the density) is the standard error of the mean over the
  vectors, ``std / sqrt(R)``; it shrinks like :math:`1/\sqrt{R}` (tested).
* :func:`local_dos`: exact moments at one site (start vector :math:`|i\rangle`), no noise.
* :func:`bulk_dos`: the stochastic trace over the *interior* sites of a flake only (see its
  docstring for which rings are dropped and why).

Moments use the doubling identities :math:`\mu_{2n} = 2\langle t_n|t_n\rangle - \mu_0`,
:math:`\mu_{2n+1} = 2\langle t_{n+1}|t_n\rangle - \mu_1` (:math:`t_n = T_n(\tilde H)|r\rangle`), so M
moments cost M/2 products; the recurrence step and both dot products are one fused pass over the
vectors. The R random vectors of a stochastic trace run together, 8 at a time, as the columns of a
row-major (N, 8) array: one pass over the graph then serves all 8, and each random gather
``Y[nb[i, k], :]`` fetches one 64-byte cache line of 8 useful numbers instead of one. On the large
periodic clusters (expanders: no numbering puts neighbours close in memory) the product is bound by
these gathers, not by bandwidth; see docs/dos.md, "Performance". The partial dot products are summed
per fixed chunk of rows, so serial and parallel runs give identical moments. Graphs come as a neighbour table (q-regular clusters: a dense ``(N, q)`` int32 table, no
index pointer to stream) or as CSR (flakes, whose boundary sites have fewer neighbours).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np

from .. import _validate
from ..results import Column, Result

if TYPE_CHECKING:
    from pathlib import Path

    from ..cache import Cache

__all__ = ["KPMDos", "kpm_dos", "local_dos", "bulk_dos", "block_width", "jackson_kernel", "spectral_bound",
           "graph_operator", "GraphOperator", "VECTOR_KINDS"]

#: random vectors for the stochastic trace
VECTOR_KINDS = ("rademacher", "phase")
#: the spectrum is mapped into [-1 + EPS, 1 - EPS]
EPS = 0.01
#: most moments accepted (the density reconstruction holds points x moments numbers)
MAX_MOMENTS = 1_000_000
#: most random vectors accepted
MAX_VECTORS = 100_000


# ----------------------------------------------------------------------------
# the operator
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class GraphOperator:
    r"""The adjacency A of a graph in the layout the kernels stream; :math:`H = -A`.

    ``table`` (N, w) int32 for a regular graph, else CSR ``indptr`` (int64), ``indices`` (int32)
    and ``data`` (float64, None for a 0/1 adjacency). ``bound`` is the exact Gershgorin bound
    :math:`\max_i\sum_j|A_{ij}| \ge \|H\|`; ``ring`` the ring index per site for a flake (else None).
    Build it with :func:`graph_operator`.

    Attributes
    ----------
    sites : int
        Number of rows streamed: the sites N, or 2N for a complex Hermitian matrix (``copies``).
    bound : float
        The Gershgorin bound on :math:`\|H\|`, in units of t (the maximal degree for a 0/1 adjacency).
    table : ndarray of int32, shape (N, w), or None
        Neighbour table of a regular graph (rows in the order of ``perm``).
    indptr, indices, data : ndarray or None
        CSR arrays of an irregular graph (a flake); ``data`` None for a 0/1 adjacency.
    ring : ndarray or None
        Ring index (1-based) of each site of a flake.
    rings, p, q : int or None
        Rings and Schläfli symbol when known.
    label : str
        What the graph is, for plots and reports.
    copies : int
        1, or 2 for a complex Hermitian matrix :math:`A = B + iC`, streamed as its real symmetric
        embedding :math:`\begin{pmatrix} B & -C \\ C & B\end{pmatrix}` of 2N rows, which has every
        eigenvalue of A twice (so traces per row, i.e. densities per site, are those of A, and row
        i < N has the local moments of site i).
    perm : ndarray or None
        ``perm[original site] = row`` when a table was renumbered breadth-first for memory
        locality; None when rows are the original (0-based) site indices.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.kpm import graph_operator
    >>> op = graph_operator(hl.ring_lattice(7, 3, 2))
    >>> op.sites, op.bound, op.rings, op.table is None, op.label
    (35, 3.0, 2, True, '{7,3} flake, 2 rings')
    """

    sites: int
    bound: float
    table: np.ndarray | None = None
    indptr: np.ndarray | None = None
    indices: np.ndarray | None = None
    data: np.ndarray | None = None
    ring: np.ndarray | None = None
    rings: int | None = None
    p: int | None = None
    q: int | None = None
    label: str = ""
    perm: np.ndarray | None = None  # perm[original site] = row here (None: same numbering)
    copies: int = 1                 # 2: the real embedding of a complex Hermitian matrix (see above)

    @property
    def nbytes(self) -> int:
        """Bytes the kernel streams for the operator per product."""
        return int(sum(a.nbytes for a in (self.table, self.indptr, self.indices, self.data) if a is not None))


_BFS = None


def _bfs_order(table: np.ndarray) -> np.ndarray:
    """Breadth-first visiting order of a neighbour table (every component, neighbours in table
    order): consecutive sites then have their neighbours close together in memory."""
    global _BFS
    if _BFS is None:
        import numba

        @numba.njit(cache=True)
        def bfs(nb):  # pragma: no cover - jitted
            n, w = nb.shape
            order = np.empty(n, dtype=np.int64)
            seen = np.zeros(n, dtype=np.bool_)
            head = 0
            tail = 0
            for s in range(n):
                if seen[s]:
                    continue
                seen[s] = True
                order[tail] = s
                tail += 1
                while head < tail:
                    i = order[head]
                    head += 1
                    for k in range(w):
                        j = nb[i, k]
                        if not seen[j]:
                            seen[j] = True
                            order[tail] = j
                            tail += 1
            return order

        _BFS = bfs
    return _BFS(table)


def _table_operator(table: np.ndarray, label: str, p=None, q=None) -> GraphOperator:
    t = np.asarray(table)
    if t.ndim != 2 or t.shape[0] == 0 or t.shape[1] == 0 or t.dtype.kind not in "iu":
        raise ValueError("a neighbour table must be a non-empty 2-D integer array (sites x q).")
    n = t.shape[0]
    if t.min() < 0 or t.max() >= n:
        raise ValueError(f"the neighbour table has entries outside 0..{n - 1}.")
    t = np.ascontiguousarray(t, dtype=np.int32)
    # Relabel the sites in breadth-first order. Traces and spectra do not depend on the labels, but
    # the gathers y[nb[i, k]] do: a group-theoretic numbering (a PSL(2, r) cluster) scatters the
    # neighbours over the whole vector and each product waits on cache misses (measured: 61 ms vs
    # 17 ms per product at 1.27 million sites). ``perm[old] = new``.
    order = _bfs_order(t)
    perm = np.empty(n, dtype=np.int64)
    perm[order] = np.arange(n)
    t = np.ascontiguousarray(perm[t[order]], dtype=np.int32)
    return GraphOperator(sites=n, bound=float(t.shape[1]), table=t, p=p, q=q, label=label, perm=perm)


def graph_operator(graph) -> GraphOperator:
    """The adjacency of ``graph`` for the KPM kernels.

    Parameters
    ----------
    graph : Lattice, Cluster, scipy.sparse matrix or ndarray
        A flake from :func:`~hyperlattice.graph.lattice.ring_lattice` (CSR, degree < q on the
        boundary), a periodic cluster (anything with a ``neighbours`` array of shape (N, q), such as
        :class:`hyperlattice.graph.clusters.Cluster`: a neighbour table), a real symmetric or complex
        Hermitian sparse matrix taken as A (CSR with its weights; a complex one, such as the Peierls
        hopping of a flux, as its real embedding of twice the size, see :class:`GraphOperator`), or a
        (N, q) integer neighbour table.

    Returns
    -------
    GraphOperator
        The adjacency in the layout the kernels stream: a neighbour ``table`` for a regular
        graph, else CSR arrays; ``bound`` is the exact Gershgorin bound, ``ring`` and ``rings``
        are set for a flake.

    Raises
    ------
    ValueError
        For a matrix that is not square, finite and Hermitian, or an object of another kind.

    See Also
    --------
    spectral_bound, kpm_dos

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.kpm import graph_operator
    >>> op = graph_operator(hl.ring_lattice(7, 3, 4))
    >>> op.sites, op.bound, op.rings
    (315, 3.0, 4)
    """
    from .lattice import Lattice

    if isinstance(graph, GraphOperator):
        return graph
    if isinstance(graph, Lattice):
        indptr, indices = graph.neighbours()
        deg = np.diff(indptr)
        return GraphOperator(sites=graph.sites, bound=float(deg.max()), indptr=np.asarray(indptr, np.int64),
                             indices=np.ascontiguousarray(indices, dtype=np.int32),
                             ring=np.asarray(graph.ring), rings=graph.rings, p=graph.p, q=graph.q,
                             label=f"{{{graph.p},{graph.q}}} flake, {graph.rings} rings"
                             + (" (line graph)" if graph.kind != "sites" else ""))
    nb = getattr(graph, "neighbours", None)
    if isinstance(nb, np.ndarray):  # a periodic cluster
        name = getattr(graph, "name", None)
        p, q = getattr(graph, "p", None), getattr(graph, "q", None)
        label = f"{{{p},{q}}} cluster" + (f" {name}" if name else "") + f", {nb.shape[0]} sites"
        return _table_operator(nb, label, p, q)
    try:
        import scipy.sparse as sp
    except ImportError:  # pragma: no cover - scipy is a dependency
        sp = None
    if sp is not None and sp.issparse(graph):
        # the one door for matrices: square, finite, symmetric up to rounding (then symmetrised)
        a = _validate.hermitian_matrix("the matrix", graph)
        n, copies, label = a.shape[0], 1, f"matrix, {a.shape[0]} rows"
        # Gershgorin of A itself (also for a complex A: its embedding has the same norm)
        bound = float(np.asarray(abs(a).sum(axis=1)).max()) if a.nnz else 0.0
        if a.dtype.kind == "c":
            # the kernels stream real weights: B + iC (B symmetric, C antisymmetric) becomes the real
            # symmetric [[B, -C], [C, B]], whose spectrum is that of A with every level twice
            b, c = a.real, a.imag
            a = sp.bmat([[b, -c], [c, b]], format="csr")
            a.eliminate_zeros()
            copies, label = 2, f"complex Hermitian matrix, {n} rows"
        a.sort_indices()
        data = np.asarray(a.data, dtype=np.float64)
        return GraphOperator(sites=a.shape[0], bound=bound if bound > 0 else 1.0,
                             indptr=np.asarray(a.indptr, np.int64),
                             indices=np.ascontiguousarray(a.indices, dtype=np.int32), data=data,
                             label=label, copies=copies)
    if isinstance(graph, np.ndarray):
        return _table_operator(graph, f"neighbour table, {graph.shape[0] if graph.ndim else 0} sites")
    raise ValueError(f"expected a Lattice, a periodic cluster, a sparse matrix or a neighbour table, "
                     f"got {type(graph).__name__}.")


def spectral_bound(graph) -> float:
    r"""The exact bound :math:`\|H\| \le \max_i\sum_j |A_{ij}|` (Gershgorin) of a graph.

    q for a q-regular cluster, the largest degree for a flake. No Lanczos estimate is
    involved.

    Parameters
    ----------
    graph : Lattice, Cluster, sparse matrix or neighbour table
        See :func:`graph_operator`.

    Returns
    -------
    float
        The bound, in units of t.

    Raises
    ------
    ValueError
        If ``graph`` is not one of the accepted kinds (see :func:`graph_operator`).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.kpm import spectral_bound
    >>> spectral_bound(hl.ring_lattice(7, 3, 3))
    3.0
    """
    return graph_operator(graph).bound


# ----------------------------------------------------------------------------
# kernels (numba, compiled on first use and cached on disk, never at import)
# ----------------------------------------------------------------------------

_KERNELS: dict = {}


def _kernels(parallel: bool) -> tuple[Callable, Callable]:
    """Fused Chebyshev steps ``out = c * (A y) - yprev`` writing the per-chunk partial dots.

    ``c = -2/a`` turns A into :math:`2\\tilde H`. Real parts of the dots (H is real symmetric).
    ``soo[b]`` and ``soy[b]`` receive :math:`\\langle out|out\\rangle` and
    :math:`\\langle out|y\\rangle` over rows ``b * chunk`` to ``(b + 1) * chunk``; the caller sums
    the chunks in order. A ``prange`` reduction would add the threads' partial sums in an order
    set by the number of threads (the machine's core count), and so change the last bits of the
    moments from one machine to the next; fixed chunks give serial and parallel runs, on any
    number of threads, the same moments bit for bit (as the block kernels below).
    """
    if parallel in _KERNELS:
        return _KERNELS[parallel]
    import numba

    rng = numba.prange if parallel else range

    @numba.njit(cache=True, parallel=parallel, fastmath=False)
    def step_table(nb, c, y, yprev, out, soo, soy, chunk):  # pragma: no cover - jitted
        n, w = nb.shape
        for b in rng(soo.shape[0]):
            s_oo = 0.0
            s_oy = 0.0
            for i in range(b * chunk, min(n, (b + 1) * chunk)):
                acc = y[nb[i, 0]]
                for k in range(1, w):
                    acc += y[nb[i, k]]
                v = c * acc - yprev[i]
                out[i] = v
                s_oo += v.real * v.real + v.imag * v.imag
                s_oy += v.real * y[i].real + v.imag * y[i].imag
            soo[b] = s_oo
            soy[b] = s_oy

    @numba.njit(cache=True, parallel=parallel, fastmath=False)
    def step_csr(indptr, indices, data, weighted, c, y, yprev, out, soo, soy, chunk):  # pragma: no cover - jitted
        n = indptr.shape[0] - 1
        for b in rng(soo.shape[0]):
            s_oo = 0.0
            s_oy = 0.0
            for i in range(b * chunk, min(n, (b + 1) * chunk)):
                acc = 0.0 * y[0]
                if weighted:
                    for k in range(indptr[i], indptr[i + 1]):
                        acc += data[k] * y[indices[k]]
                else:
                    for k in range(indptr[i], indptr[i + 1]):
                        acc += y[indices[k]]
                v = c * acc - yprev[i]
                out[i] = v
                s_oo += v.real * v.real + v.imag * v.imag
                s_oy += v.real * y[i].real + v.imag * y[i].imag
            soo[b] = s_oo
            soy[b] = s_oy

    _KERNELS[parallel] = (step_table, step_csr)
    return _KERNELS[parallel]


def _step_fn(op: GraphOperator, parallel: bool):
    """``step(c, y, yprev, out) -> (<out,out>, <out,y>)`` for ``op``, summed over fixed chunks of rows."""
    step_table, step_csr = _kernels(_validate.flag("parallel", parallel))
    nch = -(-op.sites // CHUNK)
    soo = np.empty(nch)
    soy = np.empty(nch)
    if op.table is not None:
        nb = op.table

        def step(c, y, yprev, out):
            step_table(nb, c, y, yprev, out, soo, soy, CHUNK)
            return float(soo.sum()), float(soy.sum())
        return step
    weighted = op.data is not None
    data = op.data if weighted else np.zeros(1)
    indptr, indices = op.indptr, op.indices

    def step(c, y, yprev, out):
        step_csr(indptr, indices, data, weighted, c, y, yprev, out, soo, soy, CHUNK)
        return float(soo.sum()), float(soy.sum())
    return step


def _chebyshev_moments(op: GraphOperator, r: np.ndarray, moments: int, scale: float,
                       parallel: bool = False) -> np.ndarray:
    """Raw moments :math:`\\langle r|T_n(H/a)|r\\rangle`, n < ``moments``, by the doubling identities."""
    step = _step_fn(op, parallel)
    c = -2.0 / scale  # 2 H~ = -(2/a) A
    mu = np.empty(moments)
    t0 = r
    t1 = np.empty_like(r)
    # t1 = H~ r = (c/2) A r: one step with yprev = 0 gives c A r; halve it
    zero = np.zeros_like(r)
    step(c, t0, zero, t1)
    t1 *= 0.5
    del zero
    mu0 = float(np.vdot(t0, t0).real)
    mu1 = float(np.vdot(t0, t1).real)
    mu[0] = mu0
    if moments > 1:
        mu[1] = mu1
    if moments > 2:
        mu[2] = 2.0 * float(np.vdot(t1, t1).real) - mu0
    prev, cur = t0.copy(), t1
    nxt = np.empty_like(r)
    n = 1
    while 2 * n + 1 < moments:
        s_oo, s_oy = step(c, cur, prev, nxt)  # nxt = t_{n+1}
        mu[2 * n + 1] = 2.0 * s_oy - mu1
        if 2 * n + 2 < moments:
            mu[2 * n + 2] = 2.0 * s_oo - mu0
        prev, cur, nxt = cur, nxt, prev
        n += 1
    return mu


_BLOCK_KERNELS: dict = {}
#: rows per reduction chunk of the block kernels: the partial dot products of a chunk are summed in a
#: fixed order, so serial and parallel runs give the same moments bit for bit
CHUNK = 2048
#: vectors per block: 8 float64 = one 64-byte cache line per site, so a gather brings 8 useful numbers
BLOCK = 8


def _block_kernels(parallel: bool) -> tuple[Callable, Callable]:
    """Fused Chebyshev steps on a block of vectors, ``out = c * (A Y) - Yprev`` (Y of shape (N, R),
    row-major), writing the per-chunk partial dots ``<out,out>`` and ``<out,Y>`` of every column.

    ``out`` may be ``Yprev`` (row i of Yprev is read before row i of out is written): two work blocks
    instead of three, and one stream fewer.
    """
    if parallel in _BLOCK_KERNELS:
        return _BLOCK_KERNELS[parallel]
    import numba

    rng = numba.prange if parallel else range

    @numba.njit(cache=True, parallel=parallel, fastmath=False)
    def block_table(nb, c, y, yprev, out, soo, soy, chunk):  # pragma: no cover - jitted
        n, w = nb.shape
        nv = y.shape[1]
        for b in rng(soo.shape[0]):
            acc = np.zeros_like(y[0])
            for r in range(nv):
                soo[b, r] = 0.0
                soy[b, r] = 0.0
            for i in range(b * chunk, min(n, (b + 1) * chunk)):
                j = nb[i, 0]
                for r in range(nv):
                    acc[r] = y[j, r]
                for k in range(1, w):
                    j = nb[i, k]
                    for r in range(nv):
                        acc[r] += y[j, r]
                for r in range(nv):
                    v = c * acc[r] - yprev[i, r]
                    out[i, r] = v
                    soo[b, r] += v.real * v.real + v.imag * v.imag
                    soy[b, r] += v.real * y[i, r].real + v.imag * y[i, r].imag

    @numba.njit(cache=True, parallel=parallel, fastmath=False)
    def block_csr(indptr, indices, data, weighted, c, y, yprev, out, soo, soy, chunk):  # pragma: no cover
        n = indptr.shape[0] - 1
        nv = y.shape[1]
        for b in rng(soo.shape[0]):
            acc = np.zeros_like(y[0])
            for r in range(nv):
                soo[b, r] = 0.0
                soy[b, r] = 0.0
            for i in range(b * chunk, min(n, (b + 1) * chunk)):
                for r in range(nv):
                    acc[r] = 0.0
                for k in range(indptr[i], indptr[i + 1]):
                    j = indices[k]
                    if weighted:
                        d = data[k]
                        for r in range(nv):
                            acc[r] += d * y[j, r]
                    else:
                        for r in range(nv):
                            acc[r] += y[j, r]
                for r in range(nv):
                    v = c * acc[r] - yprev[i, r]
                    out[i, r] = v
                    soo[b, r] += v.real * v.real + v.imag * v.imag
                    soy[b, r] += v.real * y[i, r].real + v.imag * y[i, r].imag

    _BLOCK_KERNELS[parallel] = (block_table, block_csr)
    return _BLOCK_KERNELS[parallel]


def _block_step_fn(op: GraphOperator, parallel: bool, nv: int):
    """``step(c, Y, Yprev, out) -> (<out,out>, <out,Y>)`` per column, for a block of ``nv`` vectors."""
    block_table, block_csr = _block_kernels(_validate.flag("parallel", parallel))
    nch = -(-op.sites // CHUNK)
    soo = np.empty((nch, nv))
    soy = np.empty((nch, nv))
    if op.table is not None:
        nb = op.table

        def step(c, y, yprev, out):
            block_table(nb, c, y, yprev, out, soo, soy, CHUNK)
            return soo.sum(axis=0), soy.sum(axis=0)
        return step
    weighted = op.data is not None
    data = op.data if weighted else np.zeros(1)
    indptr, indices = op.indptr, op.indices

    def step(c, y, yprev, out):
        block_csr(indptr, indices, data, weighted, c, y, yprev, out, soo, soy, CHUNK)
        return soo.sum(axis=0), soy.sum(axis=0)
    return step


def _chebyshev_moments_block(op: GraphOperator, x: np.ndarray, moments: int, scale: float,
                             parallel: bool = False) -> np.ndarray:
    """Raw moments of every column of ``x`` (N, R), shape (R, moments); ``x`` is overwritten.

    The same doubling recurrence as :func:`_chebyshev_moments`, R vectors per pass over the graph:
    each gather ``x[nb[i, k], :]`` reads one cache line holding all R numbers of that site.
    """
    nv = x.shape[1]
    step = _block_step_fn(op, parallel, nv)
    c = -2.0 / scale
    mu = np.empty((nv, moments))
    t1 = np.zeros_like(x)
    step(c, x, t1, t1)  # t1 = c A x
    t1 *= 0.5
    mu0 = np.einsum("ij,ij->j", x.conj(), x).real
    mu1 = np.einsum("ij,ij->j", x.conj(), t1).real
    mu[:, 0] = mu0
    if moments > 1:
        mu[:, 1] = mu1
    if moments > 2:
        mu[:, 2] = 2.0 * np.einsum("ij,ij->j", t1.conj(), t1).real - mu0
    prev, cur = x, t1
    n = 1
    while 2 * n + 1 < moments:
        s_oo, s_oy = step(c, cur, prev, prev)  # prev <- t_{n+1}, in place
        mu[:, 2 * n + 1] = 2.0 * s_oy - mu1
        if 2 * n + 2 < moments:
            mu[:, 2 * n + 2] = 2.0 * s_oo - mu0
        prev, cur = cur, prev
        n += 1
    return mu


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

def jackson_kernel(moments: int) -> np.ndarray:
    r"""Jackson damping factors :math:`g_n`, n = 0..M-1.

    .. math:: g_n = \frac{(M - n + 1)\cos\frac{\pi n}{M+1}
              + \sin\frac{\pi n}{M+1}\cot\frac{\pi}{M+1}}{M+1}

    Parameters
    ----------
    moments : int
        Number of moments M (1 to 1,000,000).

    Returns
    -------
    numpy.ndarray of float64, shape (M,)
        The factors, :math:`g_0 = 1`, decreasing towards 0.

    Raises
    ------
    ValueError
        If ``moments`` is not a positive integer up to 1,000,000.

    References
    ----------
    .. [1] A. Weiße et al., Rev. Mod. Phys. 78, 275 (2006), Eq. (71).

    Examples
    --------
    >>> from hyperlattice.graph.kpm import jackson_kernel
    >>> [round(g, 6) for g in jackson_kernel(4).tolist()]
    [1.0, 0.809017, 0.447214, 0.138197]
    """
    m = _validate.positive_int("moments", moments, maximum=MAX_MOMENTS)
    n = np.arange(m)
    x = math.pi / (m + 1)
    return ((m - n + 1) * np.cos(n * x) + np.sin(n * x) / math.tan(x)) / (m + 1)


@dataclass(frozen=True, eq=False, kw_only=True)
class KPMDos(Result):
    r"""Chebyshev moments of a density of states and what is needed to read them.

    Attributes
    ----------
    method : str
        ``"stochastic"`` (trace over all sites), ``"bulk"`` (trace over interior sites of a flake),
        ``"local"`` (exact moments at ``site``).
    mu : ndarray (M,)
        Moments per traced site, :math:`\mu_n = \frac1{|S|}\mathrm{Tr}_S\,T_n(H/a)` (mean over vectors).
    mu_err : ndarray (M,)
        Standard error of each moment (``std / sqrt(R)`` over the R vectors; 0 for exact moments,
        NaN for one vector).
    mu_vectors : ndarray (R, M)
        Moments of each random vector (for error bars of derived quantities).
    scale : float
        :math:`a`, with :math:`\|H\| \le (1-\epsilon) a` exactly (Gershgorin).
    sites, traced_sites : int
        Sites of the graph, and sites in the trace S.
    exact_moments : int or None
        For a flake: moments :math:`\mu_n` with n below this equal those of the infinite lattice
        (proven depth limit, :func:`hyperlattice.graph.walks.exact_depth`); None otherwise.
    excluded_rings : int
        Outer rings left out of the trace (``bulk``).
    deflated : int
        States at :math:`E = \mp q` left out of the trace (``kpm_dos(..., deflate=True)``).
    label : str
        What the graph is (e.g. ``"{7,3} flake, 4 rings"``).
    p, q : int or None
        Schläfli symbol when known.
    bound : float
        The spectral bound b of H (Gershgorin), units of t; ``scale`` is slightly above it.
    vectors : int
        Number R of random vectors (1 for ``local``).
    vector_kind : str
        Distribution of the random vectors (``"rademacher"``, ...), or ``"site"`` for a local DOS.
    seed, site : int or None
        Seed of the random vectors; the site of a ``local`` DOS (0-based).
    timings : dict
        Wall-clock seconds (``"total"``).

    Notes
    -----
    Energies are those of :math:`H = -tA` with t = 1 (units of t); densities are per traced site
    and per unit energy. Its table (:meth:`~hyperlattice.results.Result.to_dataframe`) has one row
    per moment: ``order`` n, ``mu`` and ``mu_err``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> dos = hl.kpm_dos(hl.ring_lattice(7, 3, 4), 64, vectors=4, seed=1)
    >>> dos.method, dos.moments, dos.bound, dos.label
    ('stochastic', 64, 3.0, '{7,3} flake, 4 rings')
    >>> e, rho, err = dos.density([-1.0, 0.5])
    >>> [round(float(x), 3) for x in rho]
    [0.141, 0.231]
    >>> e, n, err = dos.integrated([3.0])
    >>> round(float(n[0]), 4)                      # all states lie below E = 3
    1.0
    """

    COLUMNS = (Column("order", "orders", "1"), Column("mu", "mu", "1"), Column("mu_err", "mu_err", "1"))

    method: str
    label: str
    p: int | None = None
    q: int | None = None
    sites: int
    traced_sites: int
    scale: float
    bound: float
    mu: np.ndarray
    mu_err: np.ndarray
    mu_vectors: np.ndarray
    vectors: int
    vector_kind: str
    seed: int | None = None
    site: int | None = None
    exact_moments: int | None = None
    excluded_rings: int = 0
    deflated: int = 0
    timings: dict = field(default_factory=dict)

    @property
    def moments(self) -> int:
        """Number of moments M."""
        return int(self.mu.shape[0])

    @property
    def orders(self) -> np.ndarray:
        """The order n = 0, 1, ..., M - 1 of each moment."""
        return np.arange(self.moments)

    def energy_grid(self, points: int | None = None) -> np.ndarray:
        """Uniform energies in :math:`[-b, b]` (b the spectral bound), ``points`` of them (default 2M+1).

        Parameters
        ----------
        points : int, optional
            Number of energies, 2 to 10,000,000; default 2M + 1.

        Returns
        -------
        numpy.ndarray
            The energies (units of t), ascending.
        """
        points = 2 * self.moments + 1 if points is None else _validate.integer("points", points, minimum=2,
                                                                              maximum=10_000_000)
        return np.linspace(-self.bound, self.bound, points)

    def _energies(self, energies) -> np.ndarray:
        if energies is None:
            return self.energy_grid()
        return np.atleast_1d(_validate.real_array("energies", energies, ndim=(0, 1)))

    def _basis(self, e: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x = e / self.scale
        inside = np.abs(x) < 1.0
        theta = np.arccos(np.clip(x, -1.0, 1.0))
        g = jackson_kernel(self.moments)
        w = np.where(np.arange(self.moments) == 0, 1.0, 2.0) * g
        return x, inside, theta, w

    def density(self, energies=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r"""``(E, rho, err)``: the Jackson-smoothed density of states per traced site and its error bar.

        ``err`` is the standard error over the random vectors of the density itself (each vector's
        density, then ``std / sqrt(R)``); 0 for exact moments. Outside :math:`|E| < a`: 0.

        Parameters
        ----------
        energies : float or array_like, optional
            Energies (units of t); default :meth:`energy_grid`.

        Returns
        -------
        E, rho, err : numpy.ndarray
            The energies, the density (per traced site per unit energy) and its standard error.
        """
        e = self._energies(energies)
        x, inside, theta, w = self._basis(e)
        cos = np.cos(np.outer(theta, np.arange(self.moments)))  # T_n(x), (points, M)
        pref = np.where(inside, 1.0 / (math.pi * self.scale * np.sqrt(np.maximum(1.0 - x * x, 1e-300))), 0.0)
        rho = pref * (cos @ (w * self.mu))
        if self.vectors > 1 and self.method != "local":
            per = pref[None, :] * ((self.mu_vectors * w[None, :]) @ cos.T)
            err = per.std(axis=0, ddof=1) / math.sqrt(self.vectors)
        elif self.method == "local" or self.vectors == 0:
            err = np.zeros_like(rho)
        else:
            err = np.full_like(rho, np.nan)
        return e, rho, err

    def integrated(self, energies=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r"""``(E, N, err)``: the integrated density of states :math:`\int_{-\infty}^E\rho`, per traced site.

        Closed form from the moments: :math:`\int_{-1}^x T_n/(\pi\sqrt{1-t^2})\,dt = (\pi-\theta)/\pi`
        for n = 0 and :math:`-\sin(n\theta)/(n\pi)` for n >= 1, :math:`x = \cos\theta`.

        Parameters
        ----------
        energies : float or array_like, optional
            Energies (units of t); default :meth:`energy_grid`.

        Returns
        -------
        E, N, err : numpy.ndarray
            The energies, the fraction of states below each, and its standard error.
        """
        e = self._energies(energies)
        x, inside, theta, w = self._basis(e)
        n = np.arange(1, self.moments)
        base = np.empty((e.shape[0], self.moments))
        base[:, 0] = (math.pi - theta) / math.pi
        base[:, 1:] = -np.sin(np.outer(theta, n)) / (n[None, :] * math.pi)
        val = base @ (w * self.mu)
        if self.vectors > 1 and self.method != "local":
            err = ((self.mu_vectors * w[None, :]) @ base.T).std(axis=0, ddof=1) / math.sqrt(self.vectors)
        elif self.method == "local":
            err = np.zeros_like(val)
        else:
            err = np.full_like(val, np.nan)
        return e, val, err

    def kernel_width(self, energy: float) -> float:
        r"""Standard deviation (in energy) of the Jackson-broadened delta peak at ``energy``: the
        resolution of this DOS there. Measured from the kernel itself on a fine grid.

        Parameters
        ----------
        energy : float
            Inside :math:`(-a, a)`, units of t.

        Returns
        -------
        float
            The width, units of t.

        Raises
        ------
        ValueError
            If ``energy`` lies outside :math:`(-a, a)`.
        """
        e0 = _validate.real("energy", energy)
        x0 = e0 / self.scale
        if not abs(x0) < 1:
            raise ValueError(f"energy must lie inside (-{self.scale:g}, {self.scale:g}), got {e0!r}.")
        m = self.moments
        g = jackson_kernel(m)
        w = np.where(np.arange(m) == 0, 1.0, 2.0) * g * np.cos(np.arange(m) * math.acos(x0))
        # the broadened peak as a density in theta (x = cos theta), then moments in x
        th = np.linspace(0.0, math.pi, 8 * m + 1)
        dens = np.cos(np.outer(th, np.arange(m))) @ w / math.pi  # density in theta, integrates to 1
        xs = np.cos(th) * self.scale
        wt = dens * np.gradient(th)
        mean = float(np.sum(wt * xs) / np.sum(wt))
        return float(math.sqrt(max(np.sum(wt * (xs - mean) ** 2) / np.sum(wt), 0.0)))

    def summary(self) -> dict:
        """The CLI's JSON view (moments and vectors, sizes, the first moments with error bars)."""
        return {"method": self.method, "label": self.label, "p": self.p, "q": self.q, "sites": self.sites,
                "traced_sites": self.traced_sites, "moments": self.moments, "vectors": self.vectors,
                "vector_kind": self.vector_kind, "seed": self.seed, "site": self.site, "scale": self.scale,
                "bound": self.bound, "exact_moments": self.exact_moments, "excluded_rings": self.excluded_rings,
                "deflated": self.deflated,
                "mu": self.mu[:8].tolist(), "mu_err": [None if math.isnan(v) else v for v in self.mu_err[:8].tolist()],
                "time": float(self.timings.get("total", 0.0))}


# ----------------------------------------------------------------------------
# front ends
# ----------------------------------------------------------------------------

def _available_memory() -> int:
    from .lattice import _available_memory as avail

    return avail()


def _check_memory(n: int, itemsize: int, block: int = 1) -> int:
    """The block width (<= ``block``) whose work arrays fit in memory; refuse if not even one vector fits."""
    have = _available_memory()
    for nv in range(block, 0, -1):
        if 3 * n * itemsize * nv <= have:  # two work blocks and the vectors being drawn
            return nv
    need = 5 * n * itemsize  # the single-vector path: four work vectors and one random vector
    raise ValueError(f"the KPM work vectors need about {need / 1024**3:.1f} GB for {n:,} sites, "
                     f"more than the {have / 1024**3:.1f} GB available.")


def _random_vector(kind: str, n: int, seed: int, r: int, support: np.ndarray | None) -> np.ndarray:
    rng = np.random.default_rng([seed, r])
    m = n if support is None else support.shape[0]
    if kind == "rademacher":
        v = rng.integers(0, 2, size=m).astype(np.float64) * 2.0 - 1.0
    else:
        v = np.exp(2j * math.pi * rng.random(m))
    if support is None:
        return v
    out = np.zeros(n, dtype=v.dtype)
    out[support] = v
    return out


def _common_args(moments, vectors, seed, kind):
    moments = _validate.integer("moments", moments, minimum=2, maximum=MAX_MOMENTS)
    vectors = _validate.positive_int("vectors", vectors, maximum=MAX_VECTORS)
    seed = _validate.integer("seed", seed, minimum=0, maximum=2**63 - 1)
    kind = _validate.choice("kind", kind, VECTOR_KINDS)
    return moments, vectors, seed, kind


def _row_lists(op: GraphOperator) -> tuple[np.ndarray, np.ndarray]:
    if op.table is not None:
        n, w = op.table.shape
        return np.arange(0, n * w + 1, w, dtype=np.int64), op.table.ravel()
    return op.indptr, op.indices


def _extreme_states(op: GraphOperator) -> list[np.ndarray]:
    """Unit vectors of the states at E = -d and E = +d of a d-regular connected graph: the uniform
    state (always) and the staggered one (if the graph is bipartite). Empty for irregular graphs
    (flakes), whose spectrum stays inside (-d, d)."""
    indptr, indices = _row_lists(op)
    deg = np.diff(indptr)
    if op.data is not None or deg.min() != deg.max():
        return []
    n = op.sites
    out = [np.full(n, 1.0 / math.sqrt(n))]
    # two-colouring by breadth-first search from site 0 (one component: regular clusters are connected)
    colour = np.zeros(n, dtype=np.int8)
    colour[0] = 1
    frontier = np.array([0])
    while frontier.shape[0]:
        starts = indptr[frontier]
        lens = indptr[frontier + 1] - starts
        idx = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens) + np.arange(lens.sum())
        nb = indices[idx]
        want = -np.repeat(colour[frontier], lens)
        clash = (colour[nb] != 0) & (colour[nb] != want)
        if np.any(clash):
            return out
        new = colour[nb] == 0
        colour[nb[new]] = want[new]
        frontier = np.unique(nb[new])
    if np.any(colour == 0):  # not connected: the uniform vector is not the only state at -d
        raise ValueError("deflate=True needs a connected graph.")
    out.append(colour.astype(np.float64) / math.sqrt(n))
    return out


def block_width(sites: int, vectors: int, kind: str = "rademacher") -> int:
    """Random vectors per block of the stochastic trace.

    At most :data:`BLOCK` (8), fewer when memory is short; a checkpoint keeps whole blocks.

    Parameters
    ----------
    sites : int
        Number of sites N of the graph.
    vectors : int
        Number R of random vectors asked for (at most 100,000).
    kind : {"rademacher", "phase"}, optional
        Kind of random vector (real: 8 bytes per entry, complex: 16); default ``"rademacher"``.

    Returns
    -------
    int
        Vectors per block, between 1 and ``min(BLOCK, vectors)``.

    Raises
    ------
    ValueError
        For invalid arguments, or if not even one vector's work arrays fit in memory.

    See Also
    --------
    kpm_dos

    Examples
    --------
    >>> from hyperlattice.graph.kpm import block_width
    >>> block_width(1000, 16)
    8
    >>> block_width(1000, 3)
    3
    """
    sites = _validate.positive_int("sites", sites)
    vectors = _validate.positive_int("vectors", vectors, maximum=MAX_VECTORS)
    kind = _validate.choice("kind", kind, VECTOR_KINDS)
    return _check_memory(sites, 8 if kind == "rademacher" else 16, min(BLOCK, vectors))


def _digest(op: GraphOperator, support, deflate) -> str:
    """What identifies the traced operator on disk (a checkpoint entry never serves another graph)."""
    import hashlib

    h = hashlib.sha256(f"{op.sites} {op.bound!r}".encode())
    for a in (op.table, op.indptr, op.indices, op.data, op.perm, support, *(deflate or ())):
        h.update(b"-" if a is None else np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def _stochastic(op: GraphOperator, moments: int, vectors: int, seed: int, kind: str,
                support: np.ndarray | None, parallel, progress,
                deflate: list[np.ndarray] | None = None, checkpoint=None) -> tuple[np.ndarray, float]:
    import time

    from .._progress import progress_bar
    from ..cache import checkpoint_cache

    cache = checkpoint_cache(checkpoint)
    width = block_width(op.sites, vectors, kind)
    scale = op.bound / (1.0 - EPS)
    ns = op.sites if support is None else support.shape[0]
    per = np.empty((vectors, moments))
    t0 = time.perf_counter()
    # R vectors in blocks of ``width`` columns of one row-major (N, width) array: a pass over the graph
    # then serves all of them, and each random gather fetches a whole cache line of useful numbers

    def block(start: int, nv: int) -> np.ndarray:
        x = np.empty((op.sites, nv), dtype=np.float64 if kind == "rademacher" else np.complex128)
        for j in range(nv):
            r = start + j
            bar.note(f"random vector {r + 1}/{vectors}")
            v = _random_vector(kind, op.sites, seed, r, support)
            if op.perm is not None:  # the same vector in the operator's numbering: results do not depend on it
                w = np.empty_like(v)
                w[op.perm] = v
                v = w
            for u in deflate or ():
                v -= np.dot(u, v) * u  # trace of (1 - P) T_n(H) (1 - P): the state u is left out
            x[:, j] = v
            del v
        return _chebyshev_moments_block(op, x, moments, scale, parallel) / ns

    # a block (not a vector) is what a checkpoint keeps: its columns are computed together, and
    # the same block gives the same bits
    key = None if cache is None else {"operator": _digest(op, support, deflate), "moments": moments,
                                      "kind": kind, "seed": seed}  # parallel: the same moments
    with progress_bar(vectors, "KPM moments", unit="vector", progress=progress) as bar:
        for start in range(0, vectors, width):
            nv = min(width, vectors - start)
            if cache is None:
                per[start:start + nv] = block(start, nv)
            else:
                entry = cache.get("kpm-block", dict(key, start=start, width=nv),
                                  lambda start=start, nv=nv: {"mu": block(start, nv).tolist()}, expect=dict)
                rows = np.asarray(entry["mu"], dtype=np.float64)
                if rows.shape != (nv, moments):
                    raise ValueError(f"the checkpoint entry of random vectors {start}..{start + nv - 1} has shape "
                                     f"{rows.shape}, not {(nv, moments)}; delete it or use another directory.")
                per[start:start + nv] = rows
            bar.update(nv)
    return per, time.perf_counter() - t0


def _finish(op, method, per, elapsed, *, kind, seed, vectors, traced, site=None, exact=None, excluded=0,
            label=None, deflated=0) -> KPMDos:
    mu = per.mean(axis=0)
    if method == "local":
        err = np.zeros_like(mu)
    elif vectors > 1:
        err = per.std(axis=0, ddof=1) / math.sqrt(vectors)
    else:
        err = np.full_like(mu, np.nan)
    return KPMDos(method=method, label=label or op.label, p=op.p, q=op.q, sites=op.sites // op.copies,
                  traced_sites=traced,
                  scale=op.bound / (1.0 - EPS), bound=op.bound, mu=mu, mu_err=err, mu_vectors=per,
                  vectors=vectors, vector_kind=kind, seed=seed, site=site, exact_moments=exact,
                  excluded_rings=excluded, deflated=deflated, timings={"total": elapsed})


def kpm_dos(graph, moments: int = 512, *, vectors: int = 16, seed: int = 0, kind: str = "rademacher",
            deflate: bool = False, parallel: bool = False,
            progress=None, checkpoint: Cache | Path | None = None) -> KPMDos:
    r"""Density of states per site of :math:`H = -A` by KPM with a stochastic trace over all sites.

    The kernel polynomial method expands the density of states in Chebyshev polynomials of
    :math:`H/a` (a just above the exact Gershgorin bound of :math:`\|H\|`); the moments
    :math:`\mu_n = \frac1N \mathrm{Tr}\, T_n(H/a)` are estimated with R random vectors and
    damped by the Jackson kernel (:func:`jackson_kernel`) when the density is evaluated
    (:meth:`KPMDos.density`). Energies are in units of t (t = 1).

    Parameters
    ----------
    graph : Lattice, Cluster, sparse matrix or neighbour table
        See :func:`graph_operator`.
    moments : int, optional
        Number of Chebyshev moments M (>= 2, at most 1,000,000); resolution about
        :math:`\pi a/M`. Default 512.
    vectors : int, optional
        Number R of random vectors (at most 100,000); error bars need R >= 2 (R = 1 gives NaN
        errors). Default 16.
    seed : int, optional
        Seed; vector r comes from ``default_rng([seed, r])``. Default 0.
    kind : {"rademacher", "phase"}, optional
        Real :math:`\pm 1` entries (default), or complex unit-modulus random phases.
    deflate : bool, optional
        Leave out the states at :math:`E = \mp q` of a q-regular graph (a periodic cluster): the
        uniform state and, if the graph is bipartite, the staggered one. They are not in the
        spectrum of the infinite lattice (whose band is :math:`[-\rho, \dots]` with
        :math:`\rho < q`) and carry weight 1/N each. The density then integrates to
        (N - deflated)/N; ``deflated`` records how many. No effect on flakes (none exist).
        Default False.
    parallel : bool, optional
        Use the numba-parallel kernel (threads over chunks of rows; same moments as serial). Off by
        default: on a shared 2-core machine a parallel loop waits for descheduled threads (measured
        28 ms against 17 ms serial per product at 1.27 million sites, load average 5); see
        benchmarks/bench_kpm.py.
    progress : bool, None or callable, optional
        A bar over the random vectors on stderr (:mod:`hyperlattice._progress`; None, the
        default: when stderr is a terminal), or a function receiving one-line messages.
    checkpoint : path or Cache, optional
        Keep the moments of every finished block of random vectors (:func:`block_width` of them) in
        this directory (a :class:`~hyperlattice.cache.Cache`, keyed on a digest of the operator, the
        moments, kind, seed and the block); blocks already there are read, not recomputed, so a run
        stopped by Ctrl-C resumes with the same moments, bit for bit. Default None.

    Returns
    -------
    KPMDos
        ``method == "stochastic"``; the moments ``mu`` (mean over vectors), their standard
        errors ``mu_err``, the moments of each vector ``mu_vectors``, the scale ``scale`` =
        a, ``sites`` = ``traced_sites`` = N, ``deflated``, and ``timings``. Evaluate with
        :meth:`KPMDos.density` or :meth:`KPMDos.integrated`.

    Raises
    ------
    ValueError
        For an invalid graph or argument, ``deflate=True`` on a disconnected graph, work vectors
        that do not fit in the available memory, or a checkpoint entry of the wrong shape.

    See Also
    --------
    bulk_dos, local_dos, hyperlattice.graph.bands.abelian_dos, hyperlattice.compare.dos.dos_comparison

    References
    ----------
    .. [1] A. Weiße, G. Wellein, A. Alvermann and H. Fehske, "The kernel polynomial method",
       Rev. Mod. Phys. 78, 275 (2006).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> dos = hl.kpm_dos(hl.ring_lattice(7, 3, 4), 64, vectors=4, seed=1)
    >>> dos.method, dos.moments, dos.sites, float(dos.mu[0])
    ('stochastic', 64, 315, 1.0)
    >>> E, rho, err = dos.density([-2.0, 0.0])
    >>> [round(float(r), 3) for r in rho]
    [0.177, 0.185]
    """
    op = graph_operator(graph)
    moments, vectors, seed, kind = _common_args(moments, vectors, seed, kind)
    states = _extreme_states(op) if _validate.flag("deflate", deflate) else []
    progress = _validate.progress("progress", progress)
    per, elapsed = _stochastic(op, moments, vectors, seed, kind, None, parallel, progress, states, checkpoint)
    return _finish(op, "stochastic", per, elapsed, kind=kind, seed=seed, vectors=vectors,
                   traced=op.sites // op.copies, deflated=len(states))


def local_dos(graph, site: int = 0, moments: int = 512, *, parallel: bool = False) -> KPMDos:
    r"""Exact KPM moments of the local density of states at ``site`` (start vector :math:`|i\rangle`).

    The moments are :math:`\mu_n = \langle i|T_n(H/a)|i\rangle` with :math:`H = -A`; no random
    vectors are involved. On a flake, :math:`\mu_n` equals the infinite lattice's for
    :math:`n \le 2d_b + 1`, :math:`d_b` the graph distance from the site to the nearest boundary
    site of degree < q (at least :math:`2(R - r) + 1` for a site on ring r of R;
    :mod:`hyperlattice.graph.walks`); recorded as ``exact_moments`` = :math:`2d_b + 2`. On a
    periodic cluster the moments are the lattice's below its systole.

    Parameters
    ----------
    graph : Lattice, Cluster, sparse matrix or neighbour table
        See :func:`graph_operator`.
    site : int, optional
        The site i (0-based, ring 1 first); default 0, a site of the central p-gon.
    moments : int, optional
        Number of Chebyshev moments M (2 to 1,000,000); default 512.
    parallel : bool, optional
        Use the numba-parallel kernel; default False (see :func:`kpm_dos`).

    Returns
    -------
    KPMDos
        ``method == "local"``, ``site``, the exact moments ``mu`` (``mu_err`` = 0) and, for a
        flake, ``exact_moments``.

    Raises
    ------
    ValueError
        For an invalid graph, site index or number of moments, or work vectors that do not fit
        in the available memory.

    See Also
    --------
    kpm_dos, bulk_dos, hyperlattice.graph.walks.boundary_distance

    Examples
    --------
    >>> import hyperlattice as hl
    >>> ldos = hl.local_dos(hl.ring_lattice(7, 3, 4), site=0, moments=16)
    >>> ldos.method, ldos.exact_moments, round(float(ldos.mu[2]), 6)
    ('local', 14, -0.3466)
    """
    import time

    op = graph_operator(graph)
    site = _validate.site_index("site", site, op.sites // op.copies)
    moments = _validate.integer("moments", moments, minimum=2, maximum=MAX_MOMENTS)
    _check_memory(op.sites, 8)
    v = np.zeros(op.sites)
    v[site if op.perm is None else op.perm[site]] = 1.0
    t0 = time.perf_counter()
    mu = _chebyshev_moments(op, v, moments, op.bound / (1.0 - EPS), parallel)
    exact = None
    from .lattice import Lattice

    if isinstance(graph, Lattice) and graph.kind == "sites":
        from .walks import boundary_distance

        exact = 2 * boundary_distance(graph, site=site) + 2
    return _finish(op, "local", mu[None, :], time.perf_counter() - t0, kind="site", seed=None, vectors=1,
                   traced=1, site=site, exact=exact, label=op.label + f", site {site}")


def default_exclusion(rings: int) -> int:
    """Outer rings dropped by :func:`bulk_dos` by default: half of them, ``rings // 2``."""
    return rings // 2


def bulk_dos(lattice, moments: int | None = None, *, exclude: int | None = None, vectors: int = 16,
             seed: int = 0, kind: str = "rademacher", parallel: bool = False,
             progress=None, checkpoint: Cache | Path | None = None) -> KPMDos:
    r"""Bulk density of states of a flake: the stochastic trace over its *interior* sites only.

    Which sites, and why: a flake of R rings is the induced subgraph of the infinite lattice on its
    rings 1..R, and every edge changes the ring index by at most one. A site on ring r therefore
    has the infinite lattice's moments :math:`\langle i|A^n|i\rangle` for all
    :math:`n \le 2(R-r)+1` (a closed walk of length n goes at most :math:`\lfloor n/2\rfloor` rings
    out; :func:`hyperlattice.graph.walks.exact_depth`), while a boundary site (62 % of a {7,3} flake
    sit on the outer ring) has the wrong degree already at n = 2. The trace is taken over rings
    :math:`1..R-K` only (``exclude`` = K outer rings dropped; default ``R // 2``); every traced site
    then has exact moments up to :math:`n = 2K+1`, in fact up to :math:`2d_b+1` with :math:`d_b` the
    smallest graph distance from a traced site to a boundary site of degree < q (about 2K for
    {7,3}; :func:`hyperlattice.graph.walks.boundary_distance`), and ``exact_moments`` =
    :math:`2d_b + 2` records it. Higher moments feel
    the boundary, so use ``moments <= exact_moments`` (the default) for the infinite lattice at
    kernel resolution; more moments resolve the flake's own (boundary-dominated) spectrum.

    Parameters
    ----------
    lattice : Lattice
        A flake from :func:`~hyperlattice.graph.lattice.ring_lattice` (kind ``"sites"``), with
        at least 2 rings.
    moments : int, optional
        Number of moments (default: ``exact_moments``).
    exclude : int, optional
        Outer rings to drop, 1 <= K < R (default ``R // 2``, at least 1).
    vectors, seed, kind, parallel, progress, checkpoint
        As in :func:`kpm_dos` (defaults 16, 0, ``"rademacher"``, False, None, None).

    Returns
    -------
    KPMDos
        ``method == "bulk"``, with ``traced_sites`` the interior sites traced,
        ``excluded_rings`` = K and ``exact_moments``.

    Raises
    ------
    ValueError
        If ``lattice`` is not a site flake or has fewer than 2 rings, ``exclude`` is out of
        range, or as :func:`kpm_dos`.

    See Also
    --------
    kpm_dos, local_dos

    Examples
    --------
    >>> import hyperlattice as hl
    >>> dos = hl.bulk_dos(hl.ring_lattice(7, 3, 4), vectors=4)
    >>> dos.method, dos.excluded_rings, dos.traced_sites, dos.exact_moments, dos.moments
    ('bulk', 2, 35, 10, 10)
    """
    from .lattice import Lattice

    if not isinstance(lattice, Lattice):
        raise ValueError(f"bulk_dos() takes a flake (a Lattice from ring_lattice), got {type(lattice).__name__}.")
    _validate.lattice(lattice, kind="sites")
    if lattice.rings < 2:
        raise ValueError("bulk_dos() needs a flake of at least 2 rings (one to keep, one to drop).")
    k = max(1, default_exclusion(lattice.rings)) if exclude is None else _validate.integer(
        "exclude", exclude, minimum=1, maximum=lattice.rings - 1)
    from .walks import boundary_distance

    support = np.nonzero(np.asarray(lattice.ring) <= lattice.rings - k)[0]
    # proven: every traced site has the lattice's moments up to n = 2 d_b + 1 (>= 2K + 1)
    exact = 2 * int(boundary_distance(lattice)[support].min()) + 2
    moments = exact if moments is None else moments
    moments, vectors, seed, kind = _common_args(moments, vectors, seed, kind)
    op = graph_operator(lattice)
    progress = _validate.progress("progress", progress)
    per, elapsed = _stochastic(op, moments, vectors, seed, kind, support, parallel, progress,
                               checkpoint=checkpoint)
    return _finish(op, "bulk", per, elapsed, kind=kind, seed=seed, vectors=vectors, traced=int(support.shape[0]),
                   exact=exact, excluded=k,
                   label=f"{{{lattice.p},{lattice.q}}} flake interior (rings 1..{lattice.rings - k} of {lattice.rings})")


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
