r"""Abelian hyperbolic band theory on periodic {p,q} clusters.

A periodic cluster (:mod:`hyperlattice.graph.clusters`) is the unit cell of the {p,q} lattice
under its translation group N, a surface group of genus g. Abelian Bloch states
(Maciejko & Rayan, Sci. Adv. 7, eabe9170 (2021)) are those on which N acts through a character
of its Abelianization :math:`N^{ab} = H_1(\Sigma_g; \mathbb Z) = \mathbb Z^{2g}`: a crystal
momentum :math:`k \in [-\pi, \pi)^{2g}` (the 2g-torus). On the cell the Bloch Hamiltonian is

.. math:: H(k)_{ij} = -t \sum_{e: i \to j} e^{\,i\, k \cdot w_e},

the sum over the directed edges e from i to j, where :math:`w_e \in \mathbb Z^{2g}` is the
*winding* of e: an integer 1-cochain whose sum along any closed walk of the cluster is the
homology class of that walk. H(k) is Hermitian because :math:`w_{-e} = -w_e`.

Windings (:func:`edge_windings`) come from a tree–cotree decomposition (Eppstein, SODA 2003):
a spanning tree T of the graph (windings 0), a spanning tree C of the dual graph among the
remaining edges, and the 2g leftover edges L, whose fundamental cycles are the homology basis
(unit windings). The winding of each cotree edge is then fixed, leaf faces first, by the
condition that every face boundary sums to zero, so :math:`c \mapsto \sum_{e \in c} w_e` is
the isomorphism :math:`Z_1/B_1 \to \mathbb Z^{2g}` (cycles modulo face boundaries). The basis is
that of the L-cycles (not a symplectic one); k is expressed in it.

Exact check (:func:`abelian_cover`): the :math:`\mathbb Z_n^{2g}` cover of the cell is again a
{p,q} cluster (the quotient by the kernel of :math:`N \to H_1(\Sigma; \mathbb Z_n)`, a
characteristic subgroup of N and hence normal in the triangle group, so the cover is a regular
map); its spectrum is the union of the spectra of H(k) over :math:`k \in (2\pi/n)\mathbb
Z^{2g}`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..errors import HyperlatticeError
from ..results import Column, Grid, INDEX, Result
from .clusters import Cluster, _finish
from .solvers import _single_threaded_blas


__all__ = ["edge_windings", "bloch_hamiltonian", "abelian_cover", "band_structure", "k_path",
           "abelian_dos", "Windings", "Bands", "AbelianDOS"]

#: dense Bloch Hamiltonians are limited to cells of this many sites (band theory needs small cells)
MAX_CELL_SITES = 20_000


def _cluster(value) -> Cluster:
    if not isinstance(value, Cluster):
        raise ValueError(f"expected a Cluster (from pbc_cluster), got {type(value).__name__}.")
    return value


# ----------------------------------------------------------------------------
# windings
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class Windings(Result):
    r"""The windings :math:`w_e \in \mathbb Z^{2g}` of the edges of a cluster.

    Attributes
    ----------
    edges : ndarray of int32, shape (E, 2)
        The edges (i, j) of the cluster, i < j (as :attr:`Cluster.edges`).
    windings : ndarray of int64, shape (E, 2g)
        The winding of the directed edge i -> j (j -> i has the opposite one).
    basis_edges : ndarray of int64, shape (2g,)
        The leftover edges L (indices into ``edges``) whose fundamental cycles in the spanning
        tree are the homology basis: ``windings[basis_edges]`` is the identity matrix.
    genus : int
        Genus g of the cell.
    name : str
        Name of the cluster.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.bands import edge_windings
    >>> cell = hl.pbc_cluster(8, 3, "bolza")
    >>> w = edge_windings(cell)
    >>> w.name, w.genus, w.windings.shape
    ('bolza', 2, (24, 4))
    >>> w.dart_windings(cell).shape
    (16, 3, 4)
    """

    edges: np.ndarray
    windings: np.ndarray
    basis_edges: np.ndarray
    genus: int
    name: str

    def dart_windings(self, cluster: Cluster) -> np.ndarray:
        """Windings per dart: ``out[v, j]`` for the edge from v to ``cluster.neighbours[v, j]``.

        Parameters
        ----------
        cluster : Cluster
            The cluster these windings were computed for (its neighbour table orders the darts).

        Returns
        -------
        numpy.ndarray of int64, shape (sites, q, 2g)
            The winding of each directed edge; the two darts of an edge carry opposite windings.
        """
        nb = cluster.neighbours
        v = np.repeat(np.arange(nb.shape[0], dtype=np.int64), nb.shape[1])
        u = nb.ravel().astype(np.int64)
        lo, hi = np.minimum(v, u), np.maximum(v, u)
        keys = self.edges[:, 0].astype(np.int64) * nb.shape[0] + self.edges[:, 1]
        idx = np.searchsorted(keys, lo * nb.shape[0] + hi)
        sign = np.where(v < u, 1, -1)[:, None]
        return (self.windings[idx] * sign).reshape(nb.shape[0], nb.shape[1], -1)


def edge_windings(cluster: Cluster) -> Windings:
    """Homology windings of the edges by a tree–cotree decomposition (see the module docstring).

    A spanning tree of the cluster gets windings 0, a spanning tree of the dual graph among the
    remaining edges is fixed by requiring every face boundary to sum to zero, and the 2g
    leftover edges carry the unit windings of the homology basis.

    Parameters
    ----------
    cluster : Cluster
        The unit cell, e.g. from :func:`~hyperlattice.graph.clusters.pbc_cluster`.

    Returns
    -------
    Windings
        ``edges`` (E, 2), ``windings`` (E, 2g) of the directed edges i -> j, ``basis_edges``
        (2g,) whose windings are the identity matrix, ``genus`` and ``name``.

    Raises
    ------
    ValueError
        If the cluster is not a Cluster.

    See Also
    --------
    bloch_hamiltonian

    References
    ----------
    .. [1] D. Eppstein, "Dynamic generators of topologically embedded graphs", Proc. SODA
       (2003) (tree–cotree decomposition).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.bands import edge_windings
    >>> w = edge_windings(hl.pbc_cluster(8, 3, "bolza"))
    >>> w.genus, w.windings.shape, w.windings[w.basis_edges].tolist()
    (2, (24, 4), [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    """
    c = _cluster(cluster)
    n, q, p = c.sites, c.q, c.p
    edges = np.asarray(c.edges, dtype=np.int64)
    ne = len(edges)
    keys = edges[:, 0] * n + edges[:, 1]

    def edge_of(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.searchsorted(keys, np.minimum(a, b) * n + np.maximum(a, b))

    # spanning tree T of the graph: breadth-first from site 0 (SciPy's csgraph)
    from scipy.sparse import csgraph, csr_matrix

    nb = np.asarray(c.neighbours, dtype=np.int64)
    graph = csr_matrix((np.ones(n * q, dtype=np.int8), nb.ravel(), np.arange(0, n * q + 1, q)), shape=(n, n))
    _, pred = csgraph.breadth_first_order(graph, 0, directed=True, return_predecessors=True)
    child = np.flatnonzero(pred >= 0)
    in_tree = np.zeros(ne, dtype=bool)
    in_tree[edge_of(pred[child], child)] = True
    # faces and their directed edges
    faces = np.asarray(c.faces, dtype=np.int64)
    nf = len(faces)
    a, b = faces, np.roll(faces, -1, axis=1)
    face_edge = edge_of(a, b)                       # (F, p)
    face_sign = np.where(a < b, 1, -1)              # +1 when the face runs along i -> j, i < j
    # the two faces of each edge
    owners = np.full((ne, 2), -1, dtype=np.int64)
    flat_e, flat_f = face_edge.ravel(), np.repeat(np.arange(nf), p)
    side = (face_sign.ravel() < 0).astype(np.int64)  # a face runs i -> j on one side, j -> i on the other
    owners[flat_e, side] = flat_f
    if np.any(owners < 0):  # pragma: no cover - guaranteed by the map checks
        raise HyperlatticeError("an edge does not border two faces.")
    # spanning tree C of the dual among non-tree edges: breadth-first from face 0. Written out
    # rather than csgraph's: the dual of a small cluster is a multigraph (two faces can share
    # several edges) and the tree must name *which* edge joins a face to its parent, which a
    # sparse adjacency matrix (duplicates summed) cannot keep.
    in_cotree = np.zeros(ne, dtype=bool)
    parent_edge = np.full(nf, -1, dtype=np.int64)
    fseen = np.zeros(nf, dtype=bool)
    fseen[0] = True
    order = [0]
    k = 0
    while k < len(order):
        f = order[k]
        k += 1
        for e in face_edge[f]:
            if in_tree[e] or in_cotree[e]:
                continue
            g = owners[e, 0] if owners[e, 1] == f else owners[e, 1]
            if not fseen[g]:
                fseen[g] = True
                in_cotree[e] = True
                parent_edge[g] = e
                order.append(g)
    leftover = np.flatnonzero(~in_tree & ~in_cotree)
    two_g = 2 * c.genus
    if len(leftover) != two_g or len(order) != nf:
        raise HyperlatticeError(f"tree-cotree decomposition left {len(leftover)} edges, expected 2g = {two_g}.")
    w = np.zeros((ne, two_g), dtype=np.int64)
    w[leftover, np.arange(two_g)] = 1
    # leaf faces first: the boundary of face f sums to zero fixes its parent edge
    for f in reversed(order[1:]):
        e = parent_edge[f]
        es, sg = face_edge[f], face_sign[f]
        # e separates f from its parent face, so it is on the boundary of f exactly once
        s = sg[np.flatnonzero(es == e)[0]]
        total = (w[es] * sg[:, None]).sum(axis=0)  # w[e] is still zero here
        w[e] = -s * total
    # every face boundary sums to zero, including the root's (the relation of the surface group)
    sums = (w[face_edge] * face_sign[:, :, None]).sum(axis=1)
    if np.any(sums != 0):  # pragma: no cover - an internal inconsistency
        raise HyperlatticeError("the windings do not vanish on every face.")
    return Windings(edges=edges.astype(np.int32), windings=w, basis_edges=leftover, genus=c.genus, name=c.name)


# ----------------------------------------------------------------------------
# Bloch Hamiltonian and covers
# ----------------------------------------------------------------------------

def _momentum(k, two_g: int) -> np.ndarray:
    k = _validate.real_array("k", k)
    if k.shape[-1:] != (two_g,):
        raise ValueError(f"k must have {two_g} components (2g for genus {two_g // 2}), got shape {k.shape}.")
    return k


def bloch_hamiltonian(cluster: Cluster, k, *, windings: Windings | None = None, t: float = 1.0) -> np.ndarray:
    r"""The Abelian Bloch Hamiltonian :math:`H(k) = -t \sum_e e^{i k\cdot w_e}|i\rangle\langle j| + h.c.`

    The sum runs over the edges e = (i, j) of the cell with their homology windings
    :math:`w_e \in \mathbb Z^{2g}` (:func:`edge_windings`); at k = 0 it is :math:`H = -tA`
    of the periodic cluster.

    Parameters
    ----------
    cluster : Cluster
        The unit cell (at most :data:`MAX_CELL_SITES` = 20,000 sites: the matrix is dense).
    k : array_like, shape (2g,)
        Crystal momentum on the 2g-torus :math:`[-\pi, \pi)^{2g}` (radians), in the basis of
        :attr:`Windings.basis_edges`.
    windings : Windings, optional
        From :func:`edge_windings` of this cluster (computed when omitted).
    t : float, optional
        Hopping amplitude, the energy unit (H = -tA at k = 0); default 1.

    Returns
    -------
    numpy.ndarray of complex128, shape (sites, sites)
        The Hermitian matrix H(k).

    Raises
    ------
    ValueError
        If the cell has more than 20,000 sites, ``windings`` do not belong to this cluster, or
        ``k`` is not one vector of 2g real numbers.

    See Also
    --------
    edge_windings, band_structure, abelian_dos

    References
    ----------
    .. [1] J. Maciejko and S. Rayan, "Hyperbolic band theory", Sci. Adv. 7, eabe9170 (2021).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> cell = hl.pbc_cluster(8, 3, "bolza")
    >>> H = hl.bloch_hamiltonian(cell, [np.pi / 2, 0.0, 0.0, 0.0])
    >>> H.shape, round(float(np.linalg.eigvalsh(H)[0]), 6)
    ((16, 16), -2.90027)
    """
    c = _cluster(cluster)
    if c.sites > MAX_CELL_SITES:
        raise ValueError(f"a dense Bloch Hamiltonian needs a cell of at most {MAX_CELL_SITES:,} sites, "
                         f"got {c.sites:,}.")
    w = edge_windings(c) if windings is None else windings
    if not isinstance(w, Windings) or w.windings.shape[0] != c.n_edges:
        raise ValueError("windings must come from edge_windings of this cluster.")
    k = _momentum(k, 2 * c.genus)
    if k.ndim != 1:
        raise ValueError(f"k must be one momentum (a vector of {2 * c.genus} numbers), got shape {k.shape}.")
    t = _validate.real("t", t)
    phase = np.exp(1j * (w.windings @ k))
    H = np.zeros((c.sites, c.sites), dtype=np.complex128)
    i, j = w.edges[:, 0], w.edges[:, 1]
    np.add.at(H, (i, j), -t * phase)
    np.add.at(H, (j, i), -t * np.conj(phase))
    return H


def abelian_cover(cluster: Cluster, n: int) -> Cluster:
    r"""The :math:`\mathbb Z_n^{2g}` Abelian cover of a cell: a {p,q} cluster of :math:`V n^{2g}` sites.

    Site (v, m), :math:`m \in \mathbb Z_n^{2g}`, is numbered :math:`v + V \sum_i m_i n^i`; the
    edge from v to u with winding w joins (v, m) to (u, m + w mod n). Its genus is
    :math:`1 + (g-1) n^{2g}`; its systole is measured as for any cluster (the cover is a regular
    map, see the module docstring). Its spectrum is the union of the spectra of H(k) over
    :math:`k \in (2\pi/n)\mathbb Z^{2g}`, an exact check of :func:`bloch_hamiltonian`.

    Parameters
    ----------
    cluster : Cluster
        The unit cell, with V sites and genus g.
    n : int
        Order of the cyclic factors, 2 <= n <= 1000.

    Returns
    -------
    Cluster
        The cover, named ``"<cell>-Z<n>^<2g>"``.

    Raises
    ------
    ValueError
        For n < 2 (or above 1000) or a cover above 2 million sites (refused before building).

    See Also
    --------
    bloch_hamiltonian, hyperlattice.graph.clusters.pbc_cluster

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cover = hl.abelian_cover(hl.pbc_cluster(8, 3, "bolza"), 2)
    >>> cover.sites, cover.genus
    (256, 17)
    """
    c = _cluster(cluster)
    n = _validate.integer("n", n, minimum=2, maximum=1000)
    two_g = 2 * c.genus
    size = c.sites * n ** two_g
    if size > 2_000_000:
        raise ValueError(f"the Z_{n}^{two_g} cover of {c.name!r} would have {size:,} sites; the limit is 2,000,000.")
    dw = edge_windings(c).dart_windings(c) % n            # (V, q, 2g)
    weights = n ** np.arange(two_g, dtype=np.int64)
    cells = np.arange(n ** two_g, dtype=np.int64)
    m = (cells[:, None] // weights[None, :]) % n          # (cells, 2g)
    # neighbour of (v, m) along slot j: (nb[v, j], m + w[v, j])
    shifted = (m[:, None, None, :] + dw[None, :, :, :]) % n   # (cells, V, q, 2g)
    cell_to = shifted @ weights                           # (cells, V, q)
    nb = c.neighbours[None, :, :].astype(np.int64) + c.sites * cell_to
    nb = nb.reshape(size, c.q).astype(np.int32)
    return _finish(f"{c.name}-Z{n}^{two_g}", c.p, c.q, nb, size * c.q,
                   f"extension of {c.group} by Z_{n}^{two_g}",
                   f"Z_{n}^{two_g} homology cover of {c.name!r} (hyperlattice.graph.bands.abelian_cover)")


# ----------------------------------------------------------------------------
# band structures and the Abelian DOS
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class Bands(Result):
    """Abelian band structure of a cell along a path in k-space.

    Attributes
    ----------
    k : ndarray, shape (K, 2g)
        The momenta.
    distance : ndarray, shape (K,)
        Cumulative Euclidean length along the path (the x axis of the plot).
    energies : ndarray, shape (K, sites)
        Eigenvalues of the Bloch Hamiltonian :math:`H(k) = -tA(k)` with t = 1 (units of t),
        ascending at each k (the bands).
    ticks : ndarray, shape (T,)
        Distances of the labelled corners of the path.
    tick_labels : list of str
        Their labels.
    name, p, q, genus : str, int, int, int
        The cell: its name, Schläfli symbol and genus g.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> bands = hl.band_structure(hl.pbc_cluster(8, 3, "bolza"), points=5)
    >>> bands.k.shape, bands.energies.shape, bands.tick_labels[:3]
    ((21, 4), (21, 16), ['Γ', 'X', 'M'])
    >>> round(float(bands.energies[0, 0]), 6)     # -q t at k = 0
    -3.0
    """

    #: the bands on the (point, band) grid of the k-path, with the momenta and the path length
    GRID = Grid(coords=(Column("point", INDEX, "1"), Column("band", INDEX, "1"), Column("component", INDEX, "1")),
                variables=(Column("distance", "distance", "1 (length along the k-path)", ("point",)),
                           Column("energy", "energies", "t", ("point", "band")),
                           Column("k", "k", "1 (phase per cycle)", ("point", "component"))))

    k: np.ndarray
    distance: np.ndarray
    energies: np.ndarray
    ticks: np.ndarray
    tick_labels: list
    name: str
    p: int
    q: int
    genus: int


def k_path(genus: int, corners=None, *, points: int = 50) -> tuple[np.ndarray, np.ndarray, list]:
    r"""A piecewise straight path through corners of the 2g-torus.

    Parameters
    ----------
    genus : int
        g >= 1; momenta have 2g components.
    corners : sequence of (label, k) pairs, optional
        Default: :math:`\Gamma = 0 \to X = \pi e_1 \to M = \pi(e_1 + e_2) \to \Gamma \to
        R = \pi(1, \dots, 1) \to \Gamma`.
    points : int, optional
        Points per straight segment (endpoints shared), 2 to 100,000; default 50.

    Returns
    -------
    k : numpy.ndarray of float64, shape (K, 2g)
        The momenta (radians).
    ticks : numpy.ndarray of int
        The indices of the corners in k.
    labels : list of str
        Their labels.

    Raises
    ------
    ValueError
        For an invalid genus or ``points``, or corners that are not (label, k) pairs with k of
        2g numbers (at least two of them).

    See Also
    --------
    band_structure

    Examples
    --------
    >>> from hyperlattice.graph.bands import k_path
    >>> k, ticks, labels = k_path(2, points=5)
    >>> k.shape, ticks.tolist(), labels
    ((21, 4), [0, 4, 8, 12, 16, 20], ['Γ', 'X', 'M', 'Γ', 'R', 'Γ'])
    """
    g = _validate.positive_int("genus", genus, maximum=10_000)
    points = _validate.integer("points", points, minimum=2, maximum=100_000)
    d = 2 * g
    if corners is None:
        e = np.eye(d)
        corners = [("Γ", np.zeros(d)), ("X", np.pi * e[0]), ("M", np.pi * (e[0] + e[1])),
                   ("Γ", np.zeros(d)), ("R", np.pi * np.ones(d)), ("Γ", np.zeros(d))]
    try:
        labels = [str(lab) for lab, _ in corners]
        pts = [_momentum(kk, d) for _, kk in corners]
    except (TypeError, ValueError) as exc:
        raise ValueError(f"corners must be (label, k) pairs with k of {d} numbers ({exc})") from None
    if len(pts) < 2 or any(np.ndim(p_) != 1 for p_ in pts):
        raise ValueError("a k-path needs at least two corners, each one momentum.")
    segs = [np.linspace(a, b, points)[:-1] for a, b in zip(pts[:-1], pts[1:])]
    k = np.vstack(segs + [pts[-1][None, :]])
    ticks = np.arange(len(pts)) * (points - 1)
    return k, ticks, labels


def band_structure(cluster: Cluster, k=None, *, labels=None, ticks=None, points: int = 50) -> Bands:
    """Eigenvalues of H(k) along a path (default :func:`k_path` of the cell's genus).

    Parameters
    ----------
    cluster : Cluster
        The unit cell.
    k : array_like, shape (K, 2g), optional
        The momenta (radians); default the path of :func:`k_path` with ``points`` per segment.
    labels, ticks : optional
        Corner labels (sequence of str) and their indices in k (sequence of int), given with
        k; default ``["start", "end"]`` at the two ends.
    points : int, optional
        Points per straight segment of the default path; default 50.

    Returns
    -------
    Bands
        ``k`` (K, 2g), ``distance`` along the path, ``energies`` (K, sites) ascending at each
        k in units of t, ``ticks`` and ``tick_labels`` of the corners; ``.plot(ax)`` draws it.

    Raises
    ------
    ValueError
        For an invalid cluster (or one above 20,000 sites) or momenta of the wrong shape.

    See Also
    --------
    bloch_hamiltonian, k_path, abelian_dos

    Examples
    --------
    >>> import hyperlattice as hl
    >>> bands = hl.band_structure(hl.pbc_cluster(8, 3, "bolza"), points=5)
    >>> bands.energies.shape, round(float(bands.energies[0, 0]), 6), bands.tick_labels
    ((21, 16), -3.0, ['Γ', 'X', 'M', 'Γ', 'R', 'Γ'])
    """
    c = _cluster(cluster)
    if k is None:
        k, ticks, labels = k_path(c.genus, points=points)
    else:
        k = _momentum(k, 2 * c.genus)
        if k.ndim != 2 or len(k) < 1:
            raise ValueError(f"k must be an array of shape (K, {2 * c.genus}).")
        ticks = np.array([0, len(k) - 1]) if ticks is None else np.asarray(ticks, dtype=int)
        labels = ["start", "end"] if labels is None else [str(s) for s in labels]
    w = edge_windings(c)
    # many small dense problems: a multi-threaded BLAS only waits for its threads here
    with _single_threaded_blas():
        energies = np.array([np.linalg.eigvalsh(bloch_hamiltonian(c, kk, windings=w)) for kk in k])
    step = np.linalg.norm(np.diff(k, axis=0), axis=1)
    distance = np.concatenate([[0.0], np.cumsum(step)])
    return Bands(k=k, distance=distance, energies=energies, ticks=distance[np.asarray(ticks)],
                 tick_labels=list(labels), name=c.name, p=c.p, q=c.q, genus=c.genus)


@dataclass(frozen=True, eq=False, kw_only=True)
class AbelianDOS(Result):
    """Density of states of the Abelian Bloch states, by sampling k on the 2g-torus.

    Attributes
    ----------
    energies : ndarray, shape (B,)
        Bin centres (units of t).
    density : ndarray, shape (B,)
        States per site per unit energy (integrates to 1).
    errors : ndarray, shape (B,)
        One standard error of ``density`` from the spread between independent batches of k.
    bin_edges : ndarray, shape (B+1,)
        Histogram bin edges on :math:`[-q, q]` (units of t).
    samples : int
        Number of k points.
    method : str
        ``"uniform-random-k"``.
    name, p, q, genus : str, int, int, int
        The cell: its name, Schläfli symbol and genus g.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> dos = hl.abelian_dos(hl.pbc_cluster(8, 3, "bolza"), samples=40, bins=20, batches=4)
    >>> dos.method, dos.samples, dos.bin_edges[[0, -1]].tolist()
    ('uniform-random-k', 40, [-3.0, 3.0])
    >>> round(float(np.sum(dos.density * np.diff(dos.bin_edges))), 6)
    1.0
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("density", "density", "1/t per site"),
               Column("error", "errors", "1/t per site"))

    energies: np.ndarray
    density: np.ndarray
    errors: np.ndarray
    bin_edges: np.ndarray
    samples: int
    method: str
    name: str
    p: int
    q: int
    genus: int


def abelian_dos(cluster: Cluster, *, samples: int = 400, bins: int = 200, seed: int = 0,
                batches: int = 8) -> AbelianDOS:
    r"""Abelian density of states: histogram of the eigenvalues of H(k), k uniform on the torus.

    Parameters
    ----------
    cluster : Cluster
        The unit cell.
    samples : int, optional
        Number of random momenta (uniform on :math:`[-\pi, \pi)^{2g}`), at most 1e7; default 400.
    bins : int, optional
        Histogram bins on :math:`[-q, q]` (units of t); default 200.
    seed : int, optional
        Seed of the random momenta (numpy default_rng), >= 0; default 0.
    batches : int, optional
        The momenta are split into this many batches (2 to ``samples``); the standard error of
        each bin is their spread divided by sqrt(batches). Default 8.

    Returns
    -------
    AbelianDOS
        ``energies`` (bin centres, units of t), ``density`` (states per site per unit energy,
        integrating to 1), ``errors``, ``bin_edges``, ``samples``, ``method ==
        "uniform-random-k"``.

    Raises
    ------
    ValueError
        For invalid arguments, including ``samples`` below ``batches``.

    See Also
    --------
    band_structure, hyperlattice.graph.kpm.kpm_dos

    References
    ----------
    .. [1] J. Maciejko and S. Rayan, "Hyperbolic band theory", Sci. Adv. 7, eabe9170 (2021).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> dos = hl.abelian_dos(hl.pbc_cluster(8, 3, "bolza"), samples=40, bins=20, batches=4)
    >>> dos.density.shape, round(float(np.sum(dos.density * np.diff(dos.bin_edges))), 6)
    ((20,), 1.0)
    """
    c = _cluster(cluster)
    samples = _validate.positive_int("samples", samples, maximum=10**7)
    bins = _validate.positive_int("bins", bins, maximum=10**6)
    seed = _validate.integer("seed", seed, minimum=0)
    batches = _validate.integer("batches", batches, minimum=2, maximum=samples)
    if samples < batches:
        raise ValueError(f"samples ({samples}) must be at least batches ({batches}).")
    w = edge_windings(c)
    rng = np.random.default_rng(seed)
    ks = rng.uniform(-np.pi, np.pi, size=(samples, 2 * c.genus))
    edges = np.linspace(-c.q, c.q, bins + 1)
    width = edges[1] - edges[0]
    counts = np.zeros((batches, bins))
    sizes = np.zeros(batches)
    with _single_threaded_blas():  # many small dense problems (see band_structure)
        for s, kk in enumerate(ks):
            e = np.linalg.eigvalsh(bloch_hamiltonian(c, kk, windings=w))
            # rounding can put the uniform state a hair below -q: clip into the first/last bin
            h, _ = np.histogram(np.clip(e, -c.q, c.q), bins=edges)
            counts[s % batches] += h
            sizes[s % batches] += 1
    per_batch = counts / (sizes[:, None] * c.sites * width)
    density = counts.sum(axis=0) / (samples * c.sites * width)
    errors = per_batch.std(axis=0, ddof=1) / np.sqrt(batches)
    return AbelianDOS(energies=0.5 * (edges[1:] + edges[:-1]), density=density, errors=errors,
                      bin_edges=edges, samples=samples, method="uniform-random-k", name=c.name,
                      p=c.p, q=c.q, genus=c.genus)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
