r"""Periodic {p,q} clusters: finite {p,q} maps on closed orientable surfaces of genus g >= 2.

A cluster is the quotient of the infinite {p,q} lattice by a torsion-free normal subgroup N of
the rotation group :math:`\Delta(2, q, p) = \langle x, y \mid x^2, y^q, (xy)^p\rangle` of the
lattice (N is a surface group; the cluster is the unit cell of hyperbolic band theory, see
:mod:`hyperlattice.graph.bands`). It is built from the finite group :math:`G = \Delta/N`: the
darts (directed edges) are the elements of G, the vertices the cosets of :math:`\langle y\rangle`
(q darts each, in counterclockwise order), the edges the cosets of :math:`\langle x \rangle`,
the faces the cosets of :math:`\langle xy\rangle` (p-gons). Hence
:math:`V = |G|/q,\ E = |G|/2,\ F = |G|/p` and :math:`2 - 2g = V - E + F`. N is torsion-free
exactly when the images of x, y and xy have orders 2, q and p, which is checked.

Two routes give G (:mod:`hyperlattice.graph.groups`):

* a small table of known quotients (:data:`KNOWN`), each a presentation with extra relators,
  enumerated by Todd–Coxeter; their duals {q,p} come from the same group;
* the family :math:`PSL(2, \mathbb F_r)`, r an odd prime with elements of orders p and q
  (for {7,3} these are Macbeath's Hurwitz groups, r = 7 or r ≡ ±1 mod 7; for {8,3},
  r ≡ ±1 mod 16), without bound in size: :math:`|G| = r(r^2-1)/2`.

Every cluster is a regular map (its rotation group G acts transitively on the darts), hence
vertex-transitive. The systole (the length of the shortest non-contractible cycle) is therefore
found from one vertex: breadth-first search from vertex 0 in the cluster and from a vertex of the
infinite lattice (a large :func:`~hyperlattice.graph.lattice.ring_lattice` flake, from a site far
from its boundary); the first radius R at which the ball of the cluster has fewer vertices than
the lattice ball gives systole 2R, the first radius at which it has more edges gives 2R + 1
(the covering map is injective on balls of radius below half the systole).
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from .. import _validate
from ..errors import HyperlatticeError
from ..results import Result
from . import groups
from .lattice import _available_memory

if TYPE_CHECKING:
    import scipy.sparse

__all__ = ["Cluster", "pbc_cluster", "list_clusters", "cluster_from_relators", "psl2_cluster",
           "psl2_primes", "lattice_ball_counts", "map_code", "same_map", "named_schlafli", "KNOWN"]

#: bytes per dart of the PSL construction (mark, vertex list, neighbour table, later edges)
_BYTES_PER_DART = 1 + 3 + 4 + 4
#: largest prime r searched for the PSL(2, r) family (|G| ~ r^3/2: 10^9 darts at r ~ 1260)
_R_MAX = 2000


# ----------------------------------------------------------------------------
# the table of known quotients
# ----------------------------------------------------------------------------

#: name -> (p, q, extra relators in x, y, group, source). The duals {q,p} are derived.
KNOWN: dict[str, tuple] = {
    "klein": (7, 3, ("(x Y x y)^4",), "PSL(2,7), order 168",
              "Klein quartic: F. Klein, Math. Ann. 14, 428 (1878); presentation (2,3,7;4) of "
              "PSL(2,7) (Coxeter & Moser, Generators and Relations for Discrete Groups, ch. 8); "
              "the regular map {7,3} of genus 3 in Conder's census of regular maps"),
    "hurwitz14a": (7, 3, ("(x Y x y)^7",), "PSL(2,13), order 1092",
                   "one of the first Hurwitz triplet, the three Hurwitz surfaces of genus 14 with group "
                   "PSL(2,13) (A. M. Macbeath, Proc. Glasgow Math. Assoc. 5, 90 (1961)); presentation "
                   "(2,3,7;7), verified here by coset enumeration (order 1092, torsion-free); the same map "
                   "as the family member PSL(2,13)"),
    "hurwitz14b": (7, 3, ("(x Y x y)^6",), "PSL(2,13), order 1092",
                   "another of the first Hurwitz triplet (genus 14, group PSL(2,13); Macbeath 1961); "
                   "presentation (2,3,7;6), verified here by coset enumeration; systole 12, not "
                   "isomorphic to hurwitz14a"),
    "macbeath": (7, 3, ("(x y x y x Y x y x y x Y x Y)^2",), "PSL(2,8), order 504",
                 "Macbeath surface: A. M. Macbeath, Proc. London Math. Soc. (3) 15, 527 (1965), the "
                 "Hurwitz surface of genus 7 with group PSL(2,8) (168 vertices, 252 edges, 72 heptagons). "
                 "Relator found and verified here: it holds for a (2,3,7) generating pair of PSL(2,8) "
                 "(Moebius maps of the projective line over GF(8)) and the coset enumeration closes at "
                 "order 504 = |PSL(2,8)|, so the quotient is PSL(2,8). The commutator relator "
                 "(x Y x y)^9 alone does not close (more than 10^6 cosets)"),
    "bolza": (8, 3, ("(x y x y x Y)^2",), "GL(2,3), order 48",
              "Bolza surface: O. Bolza, Am. J. Math. 20, 1 (1887); the regular map {8,3} of genus 2 "
              "with 16 vertices and rotation group GL(2,3) in Conder's census of regular maps "
              "(relator verified here by coset enumeration: order 48, torsion-free)"),
    "dyck": (8, 3, ("(x y x Y)^3",), "order 96",
             "Dyck's map: W. Dyck, Math. Ann. 17, 473 (1880); the regular map {8,3} of genus 3 "
             "with 32 vertices (the Dyck graph) in Conder's census of regular maps (relator "
             "verified here by coset enumeration: order 96, torsion-free)"),
}


def _dual_relator(word: tuple[int, ...]) -> tuple[int, ...]:
    """Rewrite a word in (x, y) for the dual map, whose generators are x and y' = xy (y = x y')."""
    out: list[int] = []
    for g in word:
        if g == 2:
            out += [0, 2]        # y = x y'
        elif g == 3:
            out += [3, 1]        # y^-1 = y'^-1 x^-1
        else:
            out.append(g)
    return tuple(out)


def _known_table() -> dict[str, tuple]:
    """Known quotients with their duals: name -> (p, q, relators (words), group, source)."""
    out = {}
    for name, (p, q, rels, group, source) in KNOWN.items():
        words = tuple(groups.parse_word(w) for w in rels)
        out[name] = (p, q, words, group, source)
        out[f"{name}-dual"] = (q, p, tuple(_dual_relator(w) for w in words), group,
                               f"dual of the {{{p},{q}}} map '{name}' ({source})")
    return out


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class Cluster(Result):
    r"""A periodic {p,q} cluster: a {p,q} map on a closed orientable surface of genus g.

    Attributes
    ----------
    name : str
        Name in :func:`list_clusters` (``"klein"``, ``"PSL(2,13)"``, ...).
    p, q : int
        Schläfli symbol: p-gon faces, q neighbours per site.
    neighbours : ndarray of int32, shape (sites, q)
        The neighbours of each site in counterclockwise order (the rotation system, which
        fixes the map); the fast path for matrix-free products :math:`(A\psi)_i = \sum_j
        \psi_{\mathrm{nb}[i, j]}`.
    genus : int
        Genus of the surface, from :math:`V - E + F = 2 - 2g`.
    systole : int
        Length of the shortest non-contractible cycle (see the module docstring); a lower
        bound when ``systole_exact`` is False (the lattice ball needed to decide did not fit).
    systole_exact : bool
        Whether ``systole`` is exact.
    group : str
        The rotation group :math:`G = \Delta(2,q,p)/N` (:math:`|G| = qV` darts).
    source : str
        Where the cluster comes from (citation, or the construction of the family).

    Notes
    -----
    Sites are indexed 0-based (rows of ``neighbours``); there are no rings and no positions.
    The faces (:attr:`faces`, counterclockwise p-gons) and the edges (:attr:`edges`) follow
    from the rotation system and are computed on first use.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.pbc_cluster(7, 3, "klein")
    >>> c
    Cluster('klein', {7,3}, sites=56, genus=3, systole=8)
    >>> c.n_edges, c.n_faces, c.faces.shape, c.group
    (84, 24, (24, 7), 'PSL(2,7), order 168')
    >>> c.sites - c.n_edges + c.n_faces == 2 - 2 * c.genus
    True
    """

    name: str
    p: int
    q: int
    neighbours: np.ndarray
    genus: int
    systole: int
    systole_exact: bool = True
    group: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "neighbours", np.asarray(self.neighbours, dtype=np.int32))
        super().__post_init__()
        _check_map(self)

    def __repr__(self) -> str:
        bound = "" if self.systole_exact else ">="
        return (f"Cluster({self.name!r}, {{{self.p},{self.q}}}, sites={self.sites}, genus={self.genus}, "
                f"systole{bound}={self.systole})")

    @property
    def sites(self) -> int:
        """Number of sites (vertices)."""
        return int(self.neighbours.shape[0])

    @property
    def n_edges(self) -> int:
        """Number of edges, q V / 2."""
        return self.sites * self.q // 2

    @property
    def n_faces(self) -> int:
        """Number of faces, q V / p."""
        return self.sites * self.q // self.p

    @cached_property
    def edges(self) -> np.ndarray:
        """The edges as an (E, 2) int32 array, each pair ``i < j``, sorted."""
        v = np.repeat(np.arange(self.sites, dtype=np.int32), self.q)
        u = self.neighbours.ravel()
        keep = v < u
        v, u = v[keep], u[keep]
        order = np.lexsort((u, v))  # rows of the neighbour table are in rotation order, not sorted
        out = np.stack([v[order], u[order]], axis=1)
        out.setflags(write=False)
        return out

    @cached_property
    def faces(self) -> np.ndarray:
        """The faces as an (F, p) int32 array, each counterclockwise.

        At ``faces[f, k]`` the neighbour following ``faces[f, k+1]`` counterclockwise is
        ``faces[f, k-1]``. Faces are numbered by their first dart ``q v + j``.
        """
        out = np.empty((self.n_faces, self.p), dtype=np.int32)
        nf = _kernels()["faces"](self.neighbours, self.p, out)
        if nf != self.n_faces:
            raise HyperlatticeError(f"the rotation system of {self.name!r} does not close into "
                                    f"{self.n_faces} {self.p}-gons.")
        out.setflags(write=False)
        return out

    def to_networkx(self):
        """The cluster as a :class:`networkx.Graph` with plain attributes (GraphML-safe).

        Nodes are the vertex indices 0..N-1; each edge carries ``slot_u`` and ``slot_v``, the
        positions of the edge in the counterclockwise neighbour lists of its smaller and larger
        end (the rotation system that defines the faces, so the surface is recoverable from the
        graph). Graph attributes: ``name``, ``p``, ``q``, ``genus``, ``systole``, ``group``.
        A cluster has no coordinates: it is a graph on a surface of genus g, not in the disk.
        """
        try:
            import networkx as nx
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError("to_networkx() needs networkx: pip install 'hyperlattice[networkx]'") from exc
        g = nx.Graph(name=str(self.name), p=int(self.p), q=int(self.q), genus=int(self.genus),
                     systole=int(self.systole), group=str(self.group))
        g.add_nodes_from(range(self.sites))
        nb = np.asarray(self.neighbours)
        for u in range(nb.shape[0]):
            for j, v in enumerate(nb[u].tolist()):
                if u < v:
                    k = int(np.flatnonzero(nb[v] == u)[0])
                    g.add_edge(u, int(v), slot_u=j, slot_v=k)
        return g

    def adjacency(self) -> scipy.sparse.csr_matrix:
        """The adjacency matrix A (symmetric, entries 0/1) as a CSR matrix; H = -tA."""
        import scipy.sparse as sp

        n, q = self.sites, self.q
        idx = np.int64 if n * q >= 2**31 else np.int32
        indptr = np.arange(0, n * q + 1, q, dtype=idx)
        nb = np.sort(self.neighbours, axis=1)
        return sp.csr_matrix((np.ones(n * q), nb.ravel().astype(idx), indptr), shape=(n, n))

    def info(self) -> dict:
        """The CLI view: ``name, p, q, sites, edges, faces, genus, systole`` (counts)."""
        return {"name": self.name, "p": self.p, "q": self.q, "sites": self.sites,
                "edges": self.n_edges, "faces": self.n_faces, "genus": self.genus,
                "systole": self.systole}

    def summary(self) -> dict:
        """The short JSON view: :meth:`info` plus ``type``, ``systole_exact``, ``group``, ``source``."""
        return {"type": self.TYPE, **self.info(), "systole_exact": self.systole_exact,
                "group": self.group, "source": self.source}


def _check_map(c: Cluster) -> None:
    """Sanity checks at birth: shapes, ranges, counts, Euler characteristic, simple graph."""
    nb = c.neighbours
    p, q = _validate.pq(c.p, c.q)
    if nb.ndim != 2 or nb.shape[1] != q or nb.shape[0] < 1:
        raise ValueError(f"a {{{p},{q}}} cluster needs a (sites, {q}) neighbour table, got shape {nb.shape}.")
    v = nb.shape[0]
    if nb.min() < 0 or nb.max() >= v:
        raise ValueError("the cluster's neighbour table names sites out of range.")
    if (v * q) % 2 or (v * q) % p:
        raise ValueError(f"{v} sites cannot form a {{{p},{q}}} map (q V must be divisible by 2 and p).")
    chi = v - v * q // 2 + v * q // p
    if chi % 2 or 1 - chi // 2 != c.genus:
        raise ValueError(f"V - E + F = {chi} does not match genus {c.genus}.")
    if v <= 200_000:  # the constructions guarantee these; verified in full on small clusters
        s = np.sort(nb, axis=1)
        if np.any(s[:, 1:] == s[:, :-1]) or np.any(nb == np.arange(v)[:, None]):
            raise ValueError("the cluster graph has multiple edges or loops (systole below 3).")
        a = np.repeat(np.arange(v, dtype=np.int64), q)
        fwd = np.sort(a * v + nb.ravel())
        bwd = np.sort(nb.ravel().astype(np.int64) * v + a)
        if not np.array_equal(fwd, bwd):
            raise ValueError("the cluster's neighbour table is not symmetric.")
        _ = c.faces  # every face walk must close after p steps (raises otherwise)


# ----------------------------------------------------------------------------
# from dart permutations to the map
# ----------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _kernels() -> dict:
    """numba kernels, compiled on first use (never at import) and cached on disk."""
    import numba

    @numba.njit(cache=True)
    def build(X, Y, p, q, nb):
        n = X.shape[0]
        vid = np.full(n, -1, np.int32)
        nv = 0
        # vertices: the <y>-orbits, numbered by their smallest dart; the rotation is ccw
        for d in range(n):
            if vid[d] < 0:
                e = d
                for _ in range(q):
                    if vid[e] >= 0:
                        return -1  # an orbit shorter than q: y does not have order q
                    vid[e] = nv
                    e = Y[e]
                if e != d:
                    return -1
                nv += 1
        for d in range(n):
            if X[X[d]] != d or X[d] == d:
                return -2
            e = d  # xy must have order p on every dart
            for k in range(p):
                e = Y[X[e]]
                if e == d and k < p - 1:
                    return -3
            if e != d:
                return -3
        # neighbours in rotation order: the head of dart y^j d0 is the vertex of (y^j d0) x
        for d in range(n):
            v = vid[d]
            if nb[v, 0] < 0:
                e = d
                for j in range(q):
                    nb[v, j] = vid[X[e]]
                    e = Y[e]
        return nv

    @numba.njit(cache=True)
    def faces_from_rotation(nb, p, faces):
        # the face walk d -> d x y on darts d = q v + j: the reversed dart of (v, j) is (u, i)
        # with nb[u, i] = v, then y turns it to (u, i + 1); this walk runs clockwise
        n, q = nb.shape
        seen = np.zeros(n * q, np.bool_)
        nf = 0
        for d0 in range(n * q):
            if seen[d0]:
                continue
            if nf >= faces.shape[0]:
                return -1
            d = d0
            for k in range(p):
                if seen[d]:
                    return -1
                seen[d] = True
                v = d // q
                faces[nf, p - 1 - k] = v
                u = nb[v, d - v * q]
                i = -1
                for t in range(q):
                    if nb[u, t] == v:
                        i = t
                        break
                if i < 0:
                    return -2
                d = u * q + (i + 1) % q
            if d != d0:
                return -1
            nf += 1
        return nf

    return {"build": build, "faces": faces_from_rotation}


def _map_from_darts(X: np.ndarray, Y: np.ndarray, p: int, q: int) -> np.ndarray:
    """Neighbour table (ccw rotation system) of the map with dart permutations x and y."""
    n = X.shape[0]
    if n % q or n % p or n % 2:
        raise HyperlatticeError(f"a group of order {n} cannot give a {{{p},{q}}} map.")
    nb = np.full((n // q, q), -1, dtype=np.int32)
    code = _kernels()["build"](np.ascontiguousarray(X, dtype=np.int32),
                               np.ascontiguousarray(Y, dtype=np.int32), p, q, nb)
    if code < 0:
        what = {-1: f"y does not have order {q} on every dart", -2: "x is not a fixed-point-free involution",
                -3: f"xy does not have order {p} on every dart"}[int(code)]
        raise HyperlatticeError(f"the group does not give a torsion-free {{{p},{q}}} quotient: {what}.")
    return nb


def _genus(p: int, q: int, darts: int) -> int:
    chi_times = darts * (2 * p + 2 * q - p * q)  # chi * 2pq
    chi = chi_times // (2 * p * q)
    return 1 - chi // 2


# ----------------------------------------------------------------------------
# systole: balls of the cluster against balls of the infinite lattice
# ----------------------------------------------------------------------------

def _bfs(nb: np.ndarray, start: int, max_radius: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Graph distances from ``start`` over a neighbour table (breadth-first, SciPy's csgraph).

    Returns ``dist`` (int32, -1 beyond ``max_radius`` or unreachable) and the reached vertices.
    Rows padded with the vertex itself (boundary sites of a flake) are self-loops, which a
    shortest-path search ignores.
    """
    from scipy.sparse import csgraph, csr_matrix

    n, q = nb.shape
    graph = csr_matrix((np.ones(n * q, dtype=np.int8), np.asarray(nb, dtype=np.int32).ravel(),
                        np.arange(0, n * q + 1, q)), shape=(n, n))
    d = csgraph.dijkstra(graph, directed=True, indices=start, unweighted=True,
                         limit=np.inf if max_radius is None else float(max_radius) + 0.5)
    reached = np.isfinite(d)
    dist = np.where(reached, d, -1).astype(np.int32)
    return dist, np.flatnonzero(reached).astype(np.int32)


def _ball_counts(nb: np.ndarray, start: int = 0, max_radius: int | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Vertex and edge counts of the balls B_R(start), R = 0 .. max_radius (cumulative).

    The breadth-first search stops at ``max_radius`` (default: the whole graph), so the cost is
    that of the ball, not of the cluster.
    """
    dist, seen = _bfs(nb, int(start), max_radius)
    d = dist[seen].astype(np.int64)
    rmax = int(d.max())
    nverts = np.cumsum(np.bincount(d, minlength=rmax + 1))
    du = dist[nb[seen]].astype(np.int64)  # -1: beyond the searched ball
    ends = np.maximum(d[:, None], du)[du >= 0]
    nedges = np.cumsum(np.bincount(ends, minlength=rmax + 1)) // 2
    return nverts, nedges


@functools.lru_cache(maxsize=None)
def _lattice_reference(p: int, q: int, rings: int) -> tuple[np.ndarray, np.ndarray]:
    from .lattice import ring_lattice

    lat = ring_lattice(p, q, rings)
    n = lat.sites
    e = np.asarray(lat.edges, dtype=np.int64)
    # pad the neighbour lists of boundary sites with the site itself (never inside a valid ball)
    nb = np.repeat(np.arange(n, dtype=np.int32)[:, None], q, axis=1)
    src = np.concatenate([e[:, 0], e[:, 1]])
    dst = np.concatenate([e[:, 1], e[:, 0]])
    order = np.argsort(src, kind="stable")
    src, dst = src[order], dst[order]
    slot = np.arange(len(src)) - np.searchsorted(src, np.arange(n))[src]
    nb[src, slot] = dst
    dist, _ = _bfs(nb, 0)
    outer = np.asarray(lat.ring) == int(np.max(lat.ring))
    valid = int(dist[outer].min()) - 2  # balls of radius <= valid never touch the boundary
    nverts, nedges = _ball_counts(nb, 0, valid)
    return nverts[: valid + 1], nedges[: valid + 1]


#: the reference flake is refused above this many sites (systole reported as a lower bound)
_REFERENCE_MAX_SITES = 2_500_000


def lattice_ball_counts(p: int, q: int, radius: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertex and edge counts of the balls of radius 0..radius about a vertex of the {p,q} lattice.

    Computed by breadth-first search from a site of the central face of a ring lattice with
    enough rings that the balls stay two steps away from its boundary.

    Parameters
    ----------
    p, q : int
        Schläfli symbol.
    radius : int
        Largest graph distance R >= 0.

    Returns
    -------
    vertices, edges : numpy.ndarray of int, shape (radius + 1,)
        Cumulative counts: sites and edges in the ball :math:`B_R` of each radius.

    Raises
    ------
    ValueError
        When the flake needed exceeds 2.5 million sites, or for invalid input.

    Examples
    --------
    >>> from hyperlattice.graph.clusters import lattice_ball_counts
    >>> v, e = lattice_ball_counts(7, 3, 3)
    >>> v.tolist(), e.tolist()
    ([1, 4, 10, 22], [0, 3, 9, 24])
    """
    from .lattice import site_count

    p, q = _validate.pq(p, q)
    radius = _validate.integer("radius", radius, minimum=0)
    # a flake of l rings reaches 2 l - 3 steps or more from site 0 (at least l - 2 for small p):
    # start near the size needed instead of building every smaller flake first
    rings = max(3, (radius + 3) // 2 if p >= 7 else 3)
    while True:
        if site_count(p, q, rings) > _REFERENCE_MAX_SITES:
            raise ValueError(f"the {{{p},{q}}} lattice ball of radius {radius} needs a flake above "
                             f"{_REFERENCE_MAX_SITES:,} sites.")
        nv, ne = _lattice_reference(p, q, rings)
        if len(nv) > radius:
            return nv[: radius + 1].copy(), ne[: radius + 1].copy()
        rings += 1


def _systole(nb: np.ndarray, p: int, q: int) -> tuple[int, bool]:
    """(systole, exact) of a vertex-transitive cluster, by BFS from vertex 0 (module docstring).

    The ball of the cluster is compared radius by radius with the lattice ball; when the
    lattice ball needed no longer fits (:data:`_REFERENCE_MAX_SITES`), the systole is at least
    2 R + 2 for the last radius R that matched, returned with ``exact = False``. Both balls are
    grown by about a third at a time, so the cost is that of the largest ball compared.
    """
    lv = le = cv = ce = np.zeros(0, dtype=np.int64)
    radius = 0
    while True:
        if radius >= len(lv):
            try:
                lv, le = lattice_ball_counts(p, q, max(radius, 4, (4 * len(lv)) // 3))
            except ValueError:
                try:  # the larger step did not fit; one more radius may
                    lv, le = lattice_ball_counts(p, q, radius)
                except ValueError:
                    return 2 * radius, False  # balls of radius - 1 matched
        if radius >= len(cv):
            cv, ce = _ball_counts(nb, 0, max(radius, 4, (4 * len(cv)) // 3))
            if radius >= len(cv):  # the search exhausted the cluster without a mismatch
                raise HyperlatticeError("the cluster has no non-contractible cycle; it is not a closed surface.")
        if cv[radius] < lv[radius]:
            return 2 * radius, True
        if ce[radius] > le[radius]:
            return 2 * radius + 1, True
        radius += 1


# ----------------------------------------------------------------------------
# the two routes
# ----------------------------------------------------------------------------

def _check_fits(darts: int, what: str) -> None:
    need = darts * _BYTES_PER_DART
    avail = _available_memory()
    if darts >= 2**31 - 1 or need > 0.7 * avail:
        raise ValueError(f"{what} needs about {need / 2**30:.1f} GiB ({darts:,} darts); "
                         f"only {avail / 2**30:.1f} GiB are available.")


def cluster_from_relators(p: int, q: int, relators, *, name: str = "custom", source: str = "",
                          group: str = "", max_cosets: int = 1_000_000) -> Cluster:
    r"""The {p,q} cluster of :math:`\Delta(2,q,p)` with extra relators, by Todd–Coxeter.

    The group :math:`\langle x, y \mid x^2, y^q, (xy)^p, \text{relators} \rangle` is enumerated
    on the cosets of :math:`\langle x \rangle` (:func:`hyperlattice.graph.groups.coset_table`);
    its darts form the map.

    Parameters
    ----------
    p, q : int
        Schläfli symbol.
    relators : sequence of str or words
        Extra relators in x, y (``"(x Y x y)^4"``; capitals are inverses).
    name, source, group : str, optional
        Labels stored in the result; defaults ``"custom"``, a description of the enumeration,
        and the group order.
    max_cosets : int, optional
        Limit of the enumeration (the group order must stay below it); default 1,000,000.

    Returns
    -------
    Cluster
        The quotient map.

    Raises
    ------
    ValueError
        Bad input, an enumeration above ``max_cosets``, or a quotient that is not torsion-free
        or not a closed hyperbolic surface.

    See Also
    --------
    pbc_cluster, hyperlattice.graph.groups.coset_table

    Examples
    --------
    >>> from hyperlattice.graph.clusters import cluster_from_relators
    >>> c = cluster_from_relators(8, 3, ["(x y x Y)^4"], name="example")
    >>> c.name, c.sites, c.genus
    ('example', 112, 8)
    """
    p, q = _validate.pq(p, q)
    relators = groups._sequence("relators", relators)
    words = [groups._checked_word("relator", w, 4) for w in relators]
    try:
        table = groups.coset_table(2, groups.triangle_relators(p, q) + words, max_cosets=max_cosets)
        nb = _map_from_darts(table[:, 0].astype(np.int32), table[:, 2].astype(np.int32), p, q)
    except HyperlatticeError as exc:
        raise ValueError(str(exc)) from None
    order = len(table)
    return _finish(name, p, q, nb, order, group or f"order {order}", source or
                   f"Todd-Coxeter enumeration of <x, y | x^2, y^{q}, (xy)^{p}, {', '.join(map(str, relators))}>")


def _finish(name, p, q, nb, order, group, source) -> Cluster:
    genus = _genus(p, q, order)
    if genus < 2:
        raise ValueError(f"the quotient has genus {genus}; a hyperbolic cluster has genus >= 2.")
    systole, exact = _systole(nb, p, q)
    if systole < 3:
        raise ValueError(f"the {{{p},{q}}} quotient {name!r} has systole {systole}: its graph has loops "
                         "or multiple edges, which a {p,q} cluster may not have.")
    return Cluster(name=name, p=p, q=q, neighbours=nb, genus=genus, systole=systole,
                   systole_exact=exact, group=group, source=source)


def psl2_primes(p: int, q: int, r_max: int = _R_MAX) -> list[int]:
    """Odd primes r <= r_max for which PSL(2, r) is a torsion-free quotient of Δ(2, q, p).

    Parameters
    ----------
    p, q : int
        Schläfli symbol.
    r_max : int, optional
        Largest prime tried, 5 to 2000; default 2000.

    Returns
    -------
    list of int
        The primes, ascending.

    Raises
    ------
    ValueError
        For an invalid {p,q} or ``r_max``.

    See Also
    --------
    psl2_cluster

    Examples
    --------
    >>> from hyperlattice.graph.clusters import psl2_primes
    >>> psl2_primes(7, 3, 50)
    [7, 13, 29, 41, 43]
    """
    p, q = _validate.pq(p, q)
    r_max = _validate.integer("r_max", r_max, minimum=5, maximum=_R_MAX)
    return [r for r in range(5, r_max + 1) if groups.is_prime(r) and _psl2_triple(p, q, r) is not None]


@functools.lru_cache(maxsize=None)
def _psl2_triple(p: int, q: int, r: int):
    # cheap necessary condition first: an element of order n needs n | r or n | (r +- 1)/2
    for n in (p, q):
        if not (n == r or ((r - 1) // 2) % n == 0 or ((r + 1) // 2) % n == 0):
            return None
    return groups.psl2_triple(p, q, r)


def psl2_cluster(p: int, q: int, r: int) -> Cluster:
    r"""The {p,q} cluster with rotation group :math:`PSL(2, \mathbb F_r)`, r an odd prime.

    Sites :math:`r(r^2-1)/(2q)`. The generating triple (traces 0, t_y, t_z) is chosen by
    :func:`hyperlattice.graph.groups.psl2_triple`; for {7,3} these are Macbeath's Hurwitz
    surfaces.

    Parameters
    ----------
    p, q : int
        Schläfli symbol.
    r : int
        An odd prime, 5 <= r <= 2000, for which PSL(2, r) is a torsion-free quotient of
        :math:`\Delta(2,q,p)` (see :func:`psl2_primes`).

    Returns
    -------
    Cluster
        Named ``"PSL(2,r)"``.

    Raises
    ------
    ValueError
        If r is not a prime for which PSL(2, r) is such a quotient, or the cluster would not fit
        in memory (checked before allocating).

    See Also
    --------
    psl2_primes, pbc_cluster

    References
    ----------
    .. [1] A. M. Macbeath, "On a theorem of Hurwitz", Proc. Glasgow Math. Assoc. 5, 90 (1961).

    Examples
    --------
    >>> from hyperlattice.graph.clusters import psl2_cluster
    >>> c = psl2_cluster(7, 3, 13)
    >>> c.sites, c.genus
    (364, 14)
    """
    p, q = _validate.pq(p, q)
    r = _validate.integer("r", r, minimum=5, maximum=_R_MAX)
    if not groups.is_prime(r):
        raise ValueError(f"r must be an odd prime, got {r}.")
    triple = _psl2_triple(p, q, r)
    if triple is None:
        raise ValueError(f"PSL(2,{r}) is not a torsion-free quotient of the {{{p},{q}}} triangle group "
                         f"(it lacks elements of order {p} or {q}, or they generate a smaller group).")
    darts = groups.psl2_order(r)
    _check_fits(darts, f"the {{{p},{q}}} cluster PSL(2,{r})")
    nb = groups.psl2_map(*triple, r, q)
    if max(p, q) <= 5:  # the triple might generate A4, S4 or A5 only: then the graph falls apart
        dist, _ = _bfs(nb, 0)
        if np.any(dist < 0):
            raise ValueError(f"the chosen generators do not generate PSL(2,{r}); no {{{p},{q}}} cluster.")
    x, y = triple
    return _finish(f"PSL(2,{r})", p, q, nb, darts, f"PSL(2,{r}), order {darts}",
                   f"PSL(2,F_{r}) generated by x = {list(x)}, y = {list(y)} mod {r} (traces 0, "
                   f"{(y[0] + y[3]) % r}, {(_trace_xy(x, y, r))}); Macbeath, Proc. Symp. Pure Math. 12 (1969)")


def _trace_xy(x, y, r) -> int:
    return (x[0] * y[0] + x[1] * y[2] + x[2] * y[1] + x[3] * y[3]) % r


# ----------------------------------------------------------------------------
# public front end
# ----------------------------------------------------------------------------

_PSL_NAME = re.compile(r"^PSL\(2,\s*(\d+)\)$", re.IGNORECASE)


@functools.lru_cache(maxsize=64)
def _canonical_name(name: str) -> str:
    """A table name spelt in any case (``Bolza``, ``KLEIN-dual``) as the table spells it; other
    names unchanged (``PSL(2,r)`` is matched case-insensitively by its pattern)."""
    folded = {k.lower(): k for k in _known_table()}
    return folded.get(name.strip().lower(), name.strip())


def named_schlafli(name: str) -> tuple[int, int] | None:
    """The {p,q} of a cluster of the table (``"bolza"`` -> (8, 3), any case), or None for a
    name that does not fix it (a ``PSL(2,r)`` exists for many {p,q}) or is unknown.

    Parameters
    ----------
    name : str
        A cluster name.

    Returns
    -------
    tuple of int, or None
        (p, q).

    Examples
    --------
    >>> from hyperlattice.graph.clusters import named_schlafli
    >>> named_schlafli("Bolza"), named_schlafli("klein-dual"), named_schlafli("PSL(2,13)")
    ((8, 3), (3, 7), None)
    """
    if not isinstance(name, str):
        raise ValueError(f"name must be a string such as 'klein' or 'PSL(2,13)', got {_validate._shown(name)}.")
    entry = _known_table().get(_canonical_name(name))
    return None if entry is None else (entry[0], entry[1])


@functools.lru_cache(maxsize=64)
def _cached(p: int, q: int, name: str) -> Cluster:
    table = _known_table()
    name = _canonical_name(name)
    if name in table:
        pp, qq, words, group, source = table[name]
        if (pp, qq) != (p, q):
            raise ValueError(f"the cluster {name!r} is a {{{pp},{qq}}} cluster, not {{{p},{q}}}.")
        return cluster_from_relators(p, q, words, name=name, source=source, group=group)
    m = _PSL_NAME.match(name)
    if m:
        return psl2_cluster(p, q, int(m.group(1)))
    raise ValueError(f"unknown cluster name {name!r}; see list_clusters({p}, {q}).")


#: clusters above this many sites are built afresh each time instead of being kept in memory
_CACHE_MAX_SITES = 1_000_000


def _lookup(p: int, q: int, name: str) -> Cluster:
    m = _PSL_NAME.match(name)
    if m:
        digits = m.group(1)
        if len(digits) > 7:
            raise ValueError(f"r must be at most {_R_MAX:,}, got {digits[:20]}{'...' if len(digits) > 20 else ''}.")
        r = int(digits)
        if r > _R_MAX or groups.psl2_order(r) // q > _CACHE_MAX_SITES:
            return psl2_cluster(p, q, r)  # refuses r above the limit with a ValueError
    return _cached(p, q, name)


def pbc_cluster(p: int, q: int, name: str | None = None, *, min_sites: int | None = None) -> Cluster:
    r"""A periodic {p,q} cluster (a {p,q} map on a closed surface).

    The cluster is the unit cell of the infinite {p,q} lattice under a torsion-free normal
    subgroup N of the triangle group :math:`\Delta(2,q,p)`: every site has q neighbours and
    every face is a p-gon, with no boundary.

    Parameters
    ----------
    p, q : int
        Schläfli symbol, :math:`(p-2)(q-2) > 4`.
    name : str, optional
        A name from :func:`list_clusters` (``"klein"``, ``"bolza"``, ``"PSL(2,13)"``, ...);
        any ``"PSL(2,r)"`` of the family is accepted, listed or not.
    min_sites : int, optional
        Instead of a name: the smallest member of the PSL(2, r) family with at least this many
        sites. Without name and min_sites: the smallest cluster available for {p,q}.

    Returns
    -------
    Cluster
        ``name``, ``p``, ``q``, ``neighbours`` (sites, q) in counterclockwise order (0-based),
        ``genus``, ``systole``, ``group`` and ``source``.

    Raises
    ------
    ValueError
        Unknown name, both name and min_sites given, no cluster of that size, or a cluster that
        would not fit in memory.

    See Also
    --------
    list_clusters, psl2_cluster, cluster_from_relators, hyperlattice.graph.bands.bloch_hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.pbc_cluster(7, 3, "klein")
    >>> c.sites, c.genus, c.systole
    (56, 3, 8)
    >>> hl.pbc_cluster(7, 3, min_sites=300).name
    'PSL(2,13)'
    """
    p, q = _validate.pq(p, q)
    if name is not None and min_sites is not None:
        raise ValueError("give either name or min_sites, not both.")
    if name is not None:
        if not isinstance(name, str):
            raise ValueError(f"name must be a string such as 'klein' or 'PSL(2,13)', got {name!r}.")
        return _lookup(p, q, name.strip())
    if min_sites is not None:
        r = _psl2_for(p, q, min_sites)
        _check_fits(groups.psl2_order(r), f"a {{{p},{q}}} cluster with at least {min_sites:,} sites")
        return _lookup(p, q, f"PSL(2,{r})")
    entries = list_clusters(p, q, max_sites=20_000)
    if not entries:
        raise ValueError(f"no {{{p},{q}}} cluster with at most 20,000 sites is known; give min_sites.")
    return _cached(p, q, entries[0]["name"])


def _psl2_for(p: int, q: int, min_sites) -> int:
    """The r of the smallest PSL(2,r) {p,q} cluster with at least ``min_sites`` sites (nothing is
    built: the CLI estimates the work from its ``psl2_order(r)`` darts before it starts)."""
    min_sites = _validate.positive_int("min_sites", min_sites)
    for r in range(5, _R_MAX + 1):
        if not groups.is_prime(r) or groups.psl2_order(r) // q < min_sites:
            continue
        if _psl2_triple(p, q, r) is not None:
            return r
    raise ValueError(f"no PSL(2,r) {{{p},{q}}} cluster with at least {min_sites:,} sites and r <= {_R_MAX}.")


#: seconds per dart to build a cluster and measure its systole (2.2-4.0 us measured for
#: PSL(2,113) and PSL(2,197) of {7,3} on the project's loaded 2-core machine, 2026-11-26)
SECONDS_PER_DART = 4e-6


def list_clusters(p: int, q: int, *, max_sites: int = 100_000) -> list[dict]:
    """The available {p,q} clusters with at most ``max_sites`` sites, smallest first.

    The known quotients of the table and their duals come first, then the PSL(2, r) family
    (every cluster listed is built once to measure its systole, and kept in memory).

    Parameters
    ----------
    p, q : int
        Schläfli symbol, :math:`(p-2)(q-2) > 4`.
    max_sites : int, optional
        Largest number of sites listed, at most 1e7; default 100,000.

    Returns
    -------
    list of dict
        One dict per cluster with the keys ``name, p, q, sites, edges, faces, genus, systole``;
        at equal size the cited table entries come before the family members.

    Raises
    ------
    ValueError
        For an invalid {p,q} or ``max_sites``.

    See Also
    --------
    pbc_cluster

    Examples
    --------
    >>> import hyperlattice as hl
    >>> [(c["name"], c["sites"], c["genus"]) for c in hl.list_clusters(7, 3, max_sites=100)]
    [('klein', 56, 3), ('PSL(2,7)', 56, 3)]
    """
    p, q = _validate.pq(p, q)
    # every listed cluster is built: beyond 10^7 sites use pbc_cluster(min_sites=...) directly
    max_sites = _validate.positive_int("max_sites", max_sites, maximum=10**7)
    out = []
    names = [n for n, e in _known_table().items() if (e[0], e[1]) == (p, q)]
    for r in range(5, _R_MAX + 1):
        if groups.psl2_order(r) // q > max_sites:
            break
        if groups.is_prime(r) and _psl2_triple(p, q, r) is not None:
            names.append(f"PSL(2,{r})")
    for name in names:
        try:
            c = _cached(p, q, name)
        except ValueError:
            continue  # a quotient with loops or multiple edges (systole < 3) is no cluster
        if c.sites <= max_sites:
            out.append(c.info())
    # smallest first; at equal size the cited table entries before the family members
    out.sort(key=lambda d: (d["sites"], d["name"].startswith("PSL("), d["name"]))
    return out


def map_code(cluster: Cluster, vertex: int = 0, slot: int = 0) -> np.ndarray:
    """A canonical code of the map seen from the dart (vertex, slot): isomorphic maps agree.

    Breadth-first search from ``vertex``, visiting the neighbours of each site counterclockwise
    starting from the one it was reached from (from ``slot`` at the start); sites are renamed in
    the order they are met and the renamed neighbour table, rows in that order and each row
    starting at the parent, is the code. Two maps are isomorphic (by an orientation-preserving
    map sending the first dart to the second) exactly when their codes are equal.

    Parameters
    ----------
    cluster : Cluster
        The map.
    vertex : int, optional
        Start site (0-based); default 0.
    slot : int, optional
        Start slot in ``cluster.neighbours[vertex]``, 0 to q - 1; default 0.

    Returns
    -------
    numpy.ndarray of int64, shape (sites, q)
        The code.

    Raises
    ------
    ValueError
        If ``cluster`` is not a Cluster, or ``vertex``/``slot`` is out of range.

    See Also
    --------
    same_map

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.clusters import map_code
    >>> code = map_code(hl.pbc_cluster(7, 3, "klein"))
    >>> code.shape, code[0].tolist()
    ((56, 3), [1, 2, 3])
    """
    if not isinstance(cluster, Cluster):
        raise ValueError(f"expected a Cluster, got {type(cluster).__name__}.")
    nb = cluster.neighbours
    n, q = nb.shape
    vertex = _validate.site_index("vertex", vertex, n)
    slot = _validate.integer("slot", slot, minimum=0, maximum=q - 1)
    label = np.full(n, -1, dtype=np.int64)
    start = np.zeros(n, dtype=np.int64)
    label[vertex], start[vertex] = 0, slot
    order = [vertex]
    k = 0
    while k < len(order):
        v = order[k]
        k += 1
        for t in range(q):
            u = int(nb[v, (start[v] + t) % q])
            if label[u] < 0:
                label[u] = len(order)
                start[u] = int(np.flatnonzero(nb[u] == v)[0])
                order.append(u)
    order = np.asarray(order)
    rows = (start[order][:, None] + np.arange(q)[None, :]) % q
    return label[nb[order[:, None], rows]]


def same_map(a: Cluster, b: Cluster, *, regular: bool = True) -> bool:
    """Whether two clusters are isomorphic maps (orientation-preserving isomorphism).

    With ``regular=True`` (every cluster built here is a regular map: all darts are alike)
    one code of each suffices; otherwise b is tried from every dart (cost V q times larger).

    Parameters
    ----------
    a, b : Cluster
        The two maps.
    regular : bool, optional
        Assume b is a regular map; default True.

    Returns
    -------
    bool
        True if a and b have the same {p,q}, size and :func:`map_code` from some dart of b.

    Raises
    ------
    ValueError
        If a or b is not a Cluster.

    See Also
    --------
    map_code

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.clusters import same_map
    >>> same_map(hl.pbc_cluster(7, 3, "klein"), hl.pbc_cluster(7, 3, "PSL(2,7)"))
    True
    """
    if not isinstance(a, Cluster) or not isinstance(b, Cluster):
        raise ValueError("same_map compares two Cluster results.")
    if (a.p, a.q, a.sites) != (b.p, b.q, b.sites):
        return False
    ca = map_code(a)
    darts = [(0, 0)] if regular else [(v, j) for v in range(b.sites) for j in range(b.q)]
    return any(np.array_equal(ca, map_code(b, v, j)) for v, j in darts)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
