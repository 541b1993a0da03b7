r"""Chern and quantum-spin-Hall models on embedded graphs, as data.

A model on a graph is a list of *hops*: for each directed step (dart) from site i to site j, a
d x d block :math:`B` with :math:`H_{ij} \mathrel{+}= B`, and, on a periodic graph, the
step's winding :math:`w \in \mathbb Z^{2g}` so that the Abelian Bloch Hamiltonian is
:math:`H(k)_{ij} \mathrel{+}= B\, e^{i k\cdot w}` (the convention of
:mod:`hyperlattice.graph.bands`). The reverse step carries :math:`B^\dagger` and :math:`-w`,
so H is Hermitian. One description (:class:`ModelTerms`) feeds the sparse flake Hamiltonian
(:func:`model_hamiltonian`) and the Bloch Hamiltonian on a closed surface
(:func:`bloch_model_hamiltonian`).

The three models (site index i, orbital or spin index inside the block):

* **QWZ** (two orbitals; Qi, Wu and Zhang, PRB 74, 085308 (2006)):
  :math:`H = \sum_i M c_i^\dagger\sigma_z c_i + \sum_{i\to j} c_i^\dagger T_{ij} c_j` with
  :math:`T_{ij} = \tfrac12[\sigma_z + i(\cos\theta_{ij}\sigma_x + \sin\theta_{ij}\sigma_y)]`,
  :math:`\theta_{ij} = \arg(z_j - z_i)` the chord angle of the bond in the chart (Poincaré
  disk for hyperbolic flakes, the plane for Euclidean graphs); :math:`\theta_{ji} = \theta_{ij}+\pi`
  gives :math:`T_{ji} = T_{ij}^\dagger`. On the square lattice
  :math:`H(k) = (M + \cos k_x + \cos k_y)\sigma_z - \sin k_x\sigma_x - \sin k_y\sigma_y`.
* **Haldane** (one orbital; Haldane, PRL 61, 2015 (1988)) on a bipartite graph of degree 3:
  :math:`H = -t_1\sum_{\langle ij\rangle} c_i^\dagger c_j + t_2 \sum_{i\to j\to k}
  e^{i\phi\nu_{ijk}} c_i^\dagger c_k + M\sum_i \epsilon_i n_i`, the second sum over the paths of
  two steps (k != i), :math:`\nu = +1` when the path turns left (counterclockwise) at the
  middle site j, -1 when it turns right; :math:`\epsilon = +1` on the sublattice of site 0.
  On a flake the turn is the orientation of the triangle :math:`(z_i, z_j, z_k)` (the chart
  preserves orientation); on a cluster it comes from the rotation system (the ccw order of
  the neighbours of j).
* **Kane–Mele** (spin 1/2; Kane and Mele, PRL 95, 226801 (2005)): two Haldane copies with
  :math:`\phi \to \phi s_z` (spin up :math:`\phi`, spin down :math:`-\phi`), and the optional
  Rashba term :math:`i\lambda_R \sum_{i\to j} c_i^\dagger (s_x \sin\theta_{ij} - s_y
  \cos\theta_{ij}) c_j`.

Euclidean reference graphs (:func:`square_flake`, :func:`honeycomb_flake`,
:func:`square_torus`, :func:`honeycomb_torus`) are :class:`PlaneGraph` results, so that the
same code runs where the answers are known.

On a cluster the QWZ bond angles come from lifting the cluster into the disk along a
breadth-first spanning tree (:func:`cluster_angles`): site 0 at the origin with its first
neighbour on the positive real axis, each further site placed by the rotation about its parent
and the half-turn about the edge midpoint (the generators x, y of the rotation group). An edge
off the tree gets the chord angle seen from its lower-numbered end, the reverse step that angle
plus pi. This is one choice of frame; it is not invariant under the surface group, and
:func:`~hyperlattice.topology.surfaces.cluster_chern` reports the Chern numbers it gives.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Result

__all__ = ["PlaneGraph", "ModelTerms", "square_flake", "honeycomb_flake", "square_torus", "honeycomb_torus",
           "model_terms", "model_hamiltonian", "bloch_model_hamiltonian", "cluster_angles", "MODELS",
           "orbitals", "spin_operator", "FRAMES", "transport_rotation"]

#: the model names every front end accepts
MODELS = ("qwz", "haldane", "kane-mele")
#: the bond frames of a {p,q} flake (:func:`model_terms`)
FRAMES = ("chord", "tangent", "transport")

_SX = np.array([[0, 1], [1, 0]], dtype=np.complex128)
_SY = np.array([[0, -1j], [1j, 0]], dtype=np.complex128)
_SZ = np.array([[1, 0], [0, -1]], dtype=np.complex128)
_ID = np.eye(2, dtype=np.complex128)

#: largest number of sites a model is built on (sparse: ~ 1 kB per site with the NNN hops)
MAX_SITES = 2_000_000


# ----------------------------------------------------------------------------
# Euclidean reference graphs
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class PlaneGraph(Result):
    """A graph embedded in the Euclidean plane: a flake, or the unit cell of a torus.

    Attributes
    ----------
    z : ndarray of complex128, shape (N,)
        Site positions (lattice constant 1).
    edges : ndarray of int64, shape (E, 2)
        Bonds (i, j); on a torus i may equal j (a bond to the same site of the next cell).
    windings : ndarray of int64, shape (E, 2)
        On a torus the cell the bond i -> j ends in (j sits at ``z[j] + windings @ vectors``);
        zeros on a flake.
    vectors : ndarray of complex128, shape (2,)
        Lattice vectors of the torus (zeros for a flake).
    ring : ndarray of int64, shape (N,)
        Shell of each site around the centre (1 = closest), for ring-resolved markers.
    periodic : bool
        True for a torus.
    name : str
        ``"square"`` or ``"honeycomb"``.
    p, q : int
        {4,4} or {6,3}: the Euclidean tilings (faces of p sides, degree q).

    Examples
    --------
    >>> from hyperlattice.topology.models import square_flake, honeycomb_torus
    >>> square_flake(4).z.shape, honeycomb_torus().edges.tolist()
    ((16,), [[0, 1], [0, 1], [0, 1]])
    """

    NOT_TABULAR = "a graph: its per-site arrays mean something only with its edge list"

    z: np.ndarray
    edges: np.ndarray
    windings: np.ndarray
    vectors: np.ndarray
    ring: np.ndarray
    periodic: bool
    name: str
    p: int
    q: int

    @property
    def sites(self) -> int:
        """Number of sites."""
        return int(self.z.shape[0])


def _shells(z: np.ndarray) -> np.ndarray:
    """Shell index by distance from the centre of mass (ties within 1e-9 of the spacing share a shell)."""
    r = np.abs(z - z.mean())
    levels = np.unique(np.round(r, 9))
    return (np.searchsorted(levels, np.round(r, 9)) + 1).astype(np.int64)


def square_flake(length: int) -> PlaneGraph:
    """An open ``length`` x ``length`` square-lattice flake (lattice constant 1).

    Parameters
    ----------
    length : int
        Sites per side, 2 to 400.

    Returns
    -------
    PlaneGraph

    Examples
    --------
    >>> from hyperlattice.topology.models import square_flake
    >>> g = square_flake(3)
    >>> g.sites, len(g.edges)
    (9, 12)
    """
    n = _validate.integer("length", length, minimum=2, maximum=400)
    x, y = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    idx = (y * n + x)
    right = np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], axis=1)
    up = np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], axis=1)
    z = (x.ravel() + 1j * y.ravel()).astype(np.complex128)
    edges = np.concatenate([right, up]).astype(np.int64)
    return PlaneGraph(z=z, edges=edges, windings=np.zeros((len(edges), 2), dtype=np.int64),
                      vectors=np.zeros(2, dtype=np.complex128), ring=_shells(z), periodic=False,
                      name="square", p=4, q=4)


_A1 = complex(np.sqrt(3) / 2, 1.5)     # honeycomb lattice vectors for bond length 1
_A2 = complex(-np.sqrt(3) / 2, 1.5)


def honeycomb_flake(length: int) -> PlaneGraph:
    r"""A rectangular honeycomb flake, about ``length`` hexagons wide and high (bond length 1).

    Cut from the lattice spanned by :math:`a_{1,2} = (\pm\sqrt3/2, 3/2)` (A sites at the
    lattice points, B one bond above): the sites with :math:`0 \le x < \sqrt3\,\ell`,
    :math:`0 \le y < 1.5\,\ell`, without sites left with fewer than two bonds. A rectangle
    (not a rhombus) so that the Bott index's coordinates :math:`e^{2\pi i x/L_x}`,
    :math:`e^{2\pi i y/L_y}` see a flake that fills their box.

    Parameters
    ----------
    length : int
        Hexagons per side, 2 to 200.

    Returns
    -------
    PlaneGraph

    Examples
    --------
    >>> from hyperlattice.topology.models import honeycomb_flake
    >>> g = honeycomb_flake(4)
    >>> g.sites, len(g.edges)
    (22, 27)
    """
    n = _validate.integer("length", length, minimum=2, maximum=200)
    m = 3 * n + 4
    a, b = np.meshgrid(np.arange(-m, m), np.arange(-m, m), indexing="ij")
    zA = (a * _A1 + b * _A2).ravel()
    z = np.concatenate([zA, zA + 1j])
    width, height = np.sqrt(3) * n, 1.5 * n
    eps = 1e-9
    keep = (z.real > -eps) & (z.real < width - eps) & (z.imag > -eps) & (z.imag < height - eps)
    idx = -np.ones(len(z), dtype=np.int64)
    while True:
        idx[:] = -1
        idx[keep] = np.arange(keep.sum())
        zk = z[keep]
        # bonds: B at zA + 1j joins A at zA, zA + a1 - ... found by distance 1 (vectorised on a grid)
        key = np.round(zk.real * 2 / np.sqrt(3)).astype(np.int64) * 100003 + np.round(zk.imag * 2).astype(np.int64)
        lookup = dict(zip(key.tolist(), range(len(zk))))
        isA = np.isin(np.flatnonzero(keep), np.arange(len(zA)))
        edges = []
        for i in np.flatnonzero(isA):
            for dz in (1j, complex(-np.sqrt(3) / 2, -0.5), complex(np.sqrt(3) / 2, -0.5)):
                t = zk[i] + dz
                j = lookup.get(int(round(t.real * 2 / np.sqrt(3))) * 100003 + int(round(t.imag * 2)))
                if j is not None:
                    edges.append((i, j))
        e = np.array(edges, dtype=np.int64).reshape(-1, 2)
        deg = np.bincount(e.ravel(), minlength=len(zk))
        if np.all(deg >= 2):
            break
        keep[np.flatnonzero(keep)[deg < 2]] = False
    e = np.sort(e, axis=1)
    e = e[np.lexsort((e[:, 1], e[:, 0]))]
    return PlaneGraph(z=zk.astype(np.complex128), edges=e, windings=np.zeros((len(e), 2), dtype=np.int64),
                      vectors=np.zeros(2, dtype=np.complex128), ring=_shells(zk), periodic=False,
                      name="honeycomb", p=6, q=3)


def square_torus() -> PlaneGraph:
    """The one-site unit cell of the square lattice (two bonds, to the next cell in x and in y).

    Returns
    -------
    PlaneGraph

    Examples
    --------
    >>> from hyperlattice.topology.models import square_torus
    >>> square_torus().windings.tolist()
    [[1, 0], [0, 1]]
    """
    return PlaneGraph(z=np.zeros(1, dtype=np.complex128), edges=np.zeros((2, 2), dtype=np.int64),
                      windings=np.array([[1, 0], [0, 1]], dtype=np.int64),
                      vectors=np.array([1.0, 1j], dtype=np.complex128), ring=np.ones(1, dtype=np.int64),
                      periodic=True, name="square", p=4, q=4)


def honeycomb_torus() -> PlaneGraph:
    """The two-site unit cell of the honeycomb lattice (A at 0, B one bond above).

    Returns
    -------
    PlaneGraph

    Examples
    --------
    >>> from hyperlattice.topology.models import honeycomb_torus
    >>> honeycomb_torus().windings.tolist()
    [[0, 0], [-1, 0], [0, -1]]
    """
    return PlaneGraph(z=np.array([0.0, 1j], dtype=np.complex128), edges=np.array([[0, 1]] * 3, dtype=np.int64),
                      windings=np.array([[0, 0], [-1, 0], [0, -1]], dtype=np.int64),
                      vectors=np.array([_A1, _A2], dtype=np.complex128), ring=np.ones(2, dtype=np.int64),
                      periodic=True, name="honeycomb", p=6, q=3)


# ----------------------------------------------------------------------------
# darts of any supported graph
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Darts:
    """Directed bonds of a graph: tail, head, chord angle at the tail, winding, reverse dart, turns."""

    n: int
    tail: np.ndarray
    head: np.ndarray
    angle: np.ndarray | None      # None where no chord angle is defined (cluster without a lift)
    wind: np.ndarray              # (D, 2g), zeros on an open flake
    rev: np.ndarray
    paths: tuple                  # (first dart, second dart, turn sign) of the two-step paths
    bipartite_sign: np.ndarray | None
    kind: str                     # "flake" | "cluster" | "torus"


def _kind(graph) -> str:
    from ..graph.clusters import Cluster

    if isinstance(graph, Cluster):
        return "cluster"
    if isinstance(graph, PlaneGraph):
        return "torus" if graph.periodic else "flake"
    if getattr(type(graph), "__hyperlattice_lattice__", False):
        _validate.lattice(graph)
        if graph.kind != "sites":
            return "flake"
        return "flake"
    raise ValueError(f"expected a Lattice (ring_lattice), a Cluster (pbc_cluster) or a PlaneGraph, "
                     f"got {type(graph).__name__}.")


def _sublattice(n: int, tail: np.ndarray, head: np.ndarray) -> np.ndarray | None:
    """+1/-1 two-colouring (site 0 is +1, per connected component its lowest site), None if odd cycles."""
    from scipy.sparse import csgraph

    a = sp.csr_matrix((np.ones(len(tail), dtype=np.int8), (tail, head)), shape=(n, n))
    colour = np.zeros(n, dtype=np.int64)
    ncomp, labels = csgraph.connected_components(a, directed=False)
    for c in range(ncomp):
        start = int(np.flatnonzero(labels == c)[0])
        order, pred = csgraph.breadth_first_order(a, start, directed=False, return_predecessors=True)
        colour[start] = 1
        for v in order[1:]:
            colour[v] = -colour[pred[v]]
    if np.any(colour[tail] == colour[head]):
        return None
    return colour


def _two_step_paths(n, tail, head, rev, turn_fn):
    """All paths d1 = (i -> j), d2 = (j -> k) with d2 != reverse(d1); turn sign from ``turn_fn``."""
    order = np.argsort(tail, kind="stable")
    starts = np.searchsorted(tail[order], np.arange(n + 1))
    deg = np.diff(starts)
    d1 = np.repeat(np.arange(len(tail)), deg[head])
    off = np.arange(len(d1)) - np.repeat(np.cumsum(deg[head]) - deg[head], deg[head])
    d2 = order[starts[head[d1]] + off]
    keep = d2 != rev[d1]
    d1, d2 = d1[keep], d2[keep]
    return d1, d2, turn_fn(d1, d2)


def _orientation_turns(vec: np.ndarray):
    """Turn sign of two chord vectors: +1 left (ccw), -1 right; a straight path is refused."""
    def turn(d1, d2):
        cross = (np.conj(vec[d1]) * vec[d2]).imag
        scale = np.abs(vec[d1]) * np.abs(vec[d2])
        # a {p,3} or square path turns by 2 pi/3 or pi/2: |cross| is of the order of scale, so a
        # value within 1e-9 of zero relative to it is a straight path (the square lattice has them)
        return np.where(cross > 1e-9 * scale, 1, np.where(cross < -1e-9 * scale, -1, 0)).astype(np.int64)
    return turn


def _reverse(d: int) -> np.ndarray:
    """Index of the reverse of every dart: the darts are the edges forwards, then backwards."""
    rev = np.empty(d, dtype=np.int64)
    rev[: d // 2] = np.arange(d // 2, d)
    rev[d // 2:] = np.arange(d // 2)
    return rev


def _darts(graph) -> _Darts:
    kind = _kind(graph)
    if kind == "cluster":
        return _cluster_darts(graph)
    z = np.asarray(graph.z, dtype=np.complex128)
    e = np.asarray(graph.edges, dtype=np.int64)
    n = len(z)
    if n > MAX_SITES:
        raise ValueError(f"a model on {n:,} sites is refused (the limit is {MAX_SITES:,}).")
    if isinstance(graph, PlaneGraph):
        w = np.asarray(graph.windings, dtype=np.int64)
        shift = w @ np.asarray(graph.vectors)
        periodic = graph.periodic
    else:
        w = np.zeros((len(e), 0), dtype=np.int64)
        shift = np.zeros(len(e), dtype=np.complex128)
        periodic = False
    tail = np.concatenate([e[:, 0], e[:, 1]])
    head = np.concatenate([e[:, 1], e[:, 0]])
    wind = np.concatenate([w, -w]) if periodic else np.zeros((2 * len(e), 0), dtype=np.int64)
    vec = np.concatenate([z[e[:, 1]] + shift - z[e[:, 0]], z[e[:, 0]] - shift - z[e[:, 1]]])
    rev = _reverse(len(tail))
    d1, d2, turns = _two_step_paths(n, tail, head, rev, _orientation_turns(vec))
    return _Darts(n=n, tail=tail, head=head, angle=np.angle(vec), wind=wind, rev=rev,
                  paths=(d1, d2, turns), bipartite_sign=_sublattice(n, tail, head) if not periodic
                  else _torus_sublattice(graph), kind="torus" if periodic else "flake")


def _torus_sublattice(graph: PlaneGraph) -> np.ndarray | None:
    if graph.name == "honeycomb":
        return np.array([1, -1], dtype=np.int64)
    return None


def _cluster_darts(c) -> _Darts:
    from ..graph.bands import edge_windings

    nb = np.asarray(c.neighbours, dtype=np.int64)
    n, q = nb.shape
    try:
        c.faces  # noqa: B018 - the rotation system must close into p-gon faces
    except Exception as exc:  # HyperlatticeError: not a map
        raise ValueError(f"the cluster {c.name!r} has no rotation system that closes into faces ({exc}).") from None
    dw = edge_windings(c).dart_windings(c)                    # (n, q, 2g)
    tail = np.repeat(np.arange(n), q)
    head = nb.ravel()
    # back slot: the slot of the reverse dart at the head (unique on a simple graph)
    back = np.full((n, q), -1, dtype=np.int64)
    for r in range(q):
        hit = nb[head.reshape(n, q), r] == np.arange(n)[:, None]
        back = np.where(hit & (back < 0), r, np.where(hit, -2, back))
    simple = bool(np.all(back >= 0))
    rev = (head * q + back.ravel()) if simple else None
    if rev is None:
        raise ValueError(f"the cluster {c.name!r} has two edges between one pair of sites; the models need a "
                         "simple graph.")
    wind = dw.reshape(n * q, -1)
    # turn at the middle site j of i -> j -> k from the ccw rotation at j: arriving through slot a
    # (the slot of i at j), leaving through b = a - 1 turns left, b = a + 1 turns right (q = 3)
    slot = np.tile(np.arange(q), n)
    a_in = back.ravel()

    def turn(d1, d2):
        diff = (slot[d2] - a_in[d1]) % q
        return np.where(diff == q - 1, 1, np.where(diff == 1, -1, 0)).astype(np.int64)

    d1, d2, turns = _two_step_paths(n, tail, head, rev, turn)
    if q != 3:
        turns = np.zeros_like(turns)   # only {p,3} has Haldane's left/right rule; Haldane refuses q != 3
    sign = _sublattice(n, tail, head)
    return _Darts(n=n, tail=tail, head=head, angle=None, wind=wind, rev=rev, paths=(d1, d2, turns),
                  bipartite_sign=sign, kind="cluster")


def _mobius_apply(m: np.ndarray, z):
    return (m[0, 0] * z + m[0, 1]) / (m[1, 0] * z + m[1, 1])


def cluster_angles(cluster) -> np.ndarray:
    """Chord angles of the steps of a cluster, from its lift into the Poincaré disk.

    See the module docstring: a breadth-first lift by the rotation about each site and the
    half-turn about each edge midpoint; the steps off the spanning tree take the chord angle
    seen from their lower-numbered end.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster (:func:`~hyperlattice.graph.clusters.pbc_cluster`), simple graph.

    Returns
    -------
    numpy.ndarray of float64, shape (sites, q)
        ``out[v, s]`` is the angle of the step from v to its s-th neighbour (ccw order).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import cluster_angles
    >>> a = cluster_angles(hl.pbc_cluster(8, 3, "bolza"))
    >>> a.shape, round(float(a[0, 0]), 12)
    ((16, 3), 0.0)
    """
    from .. import geometry
    from ..graph.clusters import Cluster

    if not isinstance(cluster, Cluster):
        raise ValueError(f"expected a Cluster (from pbc_cluster), got {type(cluster).__name__}.")
    darts = _cluster_darts(cluster)
    nb = np.asarray(cluster.neighbours, dtype=np.int64)
    n, q = nb.shape
    back = (darts.rev % q).reshape(n, q)
    d0 = geometry.d0(cluster.p, cluster.q)
    a = np.tanh(d0)                  # disk radius of a neighbour of the origin (metric |dz|/(1-|z|^2))
    m = np.tanh(d0 / 2)              # the edge midpoint
    tm = np.array([[1, m], [m, 1]], dtype=np.complex128) / np.sqrt(1 - m * m)
    tmi = np.array([[1, -m], [-m, 1]], dtype=np.complex128) / np.sqrt(1 - m * m)
    half = np.array([[1j, 0], [0, -1j]], dtype=np.complex128)
    x = tm @ half @ tmi

    def rot(k):
        phi = 2 * np.pi * k / q
        return np.array([[np.exp(0.5j * phi), 0], [0, np.exp(-0.5j * phi)]], dtype=np.complex128)

    frame = np.zeros((n, 2, 2), dtype=np.complex128)
    seen = np.zeros(n, dtype=bool)
    frame[0] = np.eye(2)
    seen[0] = True
    queue = [0]
    angles = np.zeros((n, q))
    for v in queue:
        zv = _mobius_apply(frame[v], 0.0)
        for s in range(q):
            u = nb[v, s]
            zu = _mobius_apply(frame[v], np.exp(2j * np.pi * s / q) * a)
            angles[v, s] = np.angle(zu - zv)
            if not seen[u]:
                seen[u] = True
                frame[u] = frame[v] @ rot(s) @ x @ rot(-back[v, s])
                frame[u] /= np.sqrt(np.linalg.det(frame[u]))
                queue.append(u)
    # one angle per edge: the lower-numbered end's, the reverse step plus pi
    v = np.repeat(np.arange(n), q)
    lower = v < nb.ravel()
    out = angles.ravel().copy()
    rev = darts.rev
    out[rev[lower]] = out[lower] + np.pi
    # steps i -> i do not exist on a simple graph; loops back to the same index are excluded above
    return np.angle(np.exp(1j * out)).reshape(n, q)


# ----------------------------------------------------------------------------
# the models as hop lists
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class ModelTerms(Result):
    r"""A model as data: on-site blocks and hops :math:`H_{ij} \mathrel{+}= B\,e^{ik\cdot w}`.

    Attributes
    ----------
    model : str
        ``"qwz"``, ``"haldane"`` or ``"kane-mele"``.
    orbitals : int
        Block size d (2, 1, 2).
    onsite : ndarray of complex128, shape (N, d, d)
        On-site blocks.
    tail, head : ndarray of int64, shape (H,)
        Hop from site ``head`` to site ``tail``: the block sits at rows of ``tail``, columns of
        ``head``.
    blocks : ndarray of complex128, shape (H, d, d)
        The hop blocks.
    windings : ndarray of int64, shape (H, 2g)
        The hop's winding on a closed surface (2g = 0 on a flake).
    parameters : dict
        The model's parameters (M, t1, t2, phi, rashba, flux, disorder, seed).

    Examples
    --------
    >>> from hyperlattice.topology.models import model_terms, square_torus
    >>> terms = model_terms(square_torus(), "qwz", M=1.0)
    >>> terms.orbitals, terms.blocks.shape
    (2, (4, 2, 2))
    """

    NOT_TABULAR = "a sparse operator as data: rows only mean something together"

    model: str
    orbitals: int
    onsite: np.ndarray
    tail: np.ndarray
    head: np.ndarray
    blocks: np.ndarray
    windings: np.ndarray
    parameters: dict

    @property
    def sites(self) -> int:
        """Number of sites."""
        return int(self.onsite.shape[0])


def orbitals(model: str) -> int:
    """Orbitals (or spin states) per site of a model: qwz 2, haldane 1, kane-mele 2.

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.

    Returns
    -------
    int

    Examples
    --------
    >>> from hyperlattice.topology.models import orbitals
    >>> orbitals("qwz"), orbitals("haldane")
    (2, 1)
    """
    return {"qwz": 2, "haldane": 1, "kane-mele": 2}[_validate.choice("model", model, MODELS)]


def spin_operator(model: str, sites: int) -> sp.csr_matrix:
    r"""The operator :math:`s_z` (Kane–Mele) or :math:`\sigma_z` (QWZ) on all sites (``1`` for Haldane).

    Parameters
    ----------
    model : str
        One of :data:`MODELS`.
    sites : int
        Number of sites.

    Returns
    -------
    scipy.sparse.csr_matrix

    Examples
    --------
    >>> from hyperlattice.topology.models import spin_operator
    >>> spin_operator("kane-mele", 2).diagonal().tolist()
    [1.0, -1.0, 1.0, -1.0]
    """
    d = orbitals(model)
    n = _validate.integer("sites", sites, minimum=1, maximum=MAX_SITES)
    diag = np.tile([1.0, -1.0], n) if d == 2 else np.ones(n)
    return sp.diags(diag).tocsr()


def model_terms(graph, model: str = "qwz", *, M: float = 1.0, t1: float = 1.0, t2: float = 0.2,
                phi: float = np.pi / 2, rashba: float = 0.0, flux: float = 0.0, disorder: float = 0.0,
                seed: int = 0, frame: str = "chord") -> ModelTerms:
    r"""The hop list of a model on a flake, a cluster or a Euclidean graph (see the module docstring).

    Parameters
    ----------
    graph : Lattice, Cluster or PlaneGraph
        A {p,q} flake (:func:`~hyperlattice.graph.lattice.ring_lattice`), a periodic cluster
        (:func:`~hyperlattice.graph.clusters.pbc_cluster`, with its rotation system), or a
        Euclidean flake or torus of this module.
    model : {"qwz", "haldane", "kane-mele"}
        The model.
    M : float, optional
        QWZ: the mass :math:`M\sigma_z`; Haldane and Kane–Mele: the sublattice mass
        :math:`\pm M` (default 1).
    t1 : float, optional
        Haldane / Kane–Mele nearest-neighbour hopping (:math:`-t_1`), default 1. QWZ has none
        (its bond is :math:`T_{ij}`).
    t2 : float, optional
        Haldane / Kane–Mele next-nearest-neighbour amplitude, default 0.2.
    phi : float, optional
        Haldane phase (radians), default pi/2 (Kane–Mele's intrinsic spin-orbit term).
    rashba : float, optional
        Kane–Mele Rashba coupling :math:`\lambda_R`, default 0.
    flux : float, optional
        Uniform field, flux quanta per p-gon (flakes of :func:`ring_lattice` only): the Peierls
        phases of :func:`hyperlattice.graph.flux.edge_phases` on the bonds, their sum along
        two-step paths.
    disorder : float, optional
        Anderson box disorder: on-site energies uniform in [-W/2, W/2] (times the identity on
        the orbitals), default 0.
    seed : int, optional
        Seed of the disorder (realization 0 of :func:`~hyperlattice.graph.disorder.realization_rng`).
    frame : {"chord", "tangent", "transport"}, optional
        The bond angles of QWZ and of the Rashba term on a {p,q} flake: ``"chord"`` (default),
        :math:`\arg(z_j - z_i)`; ``"tangent"``, the direction at :math:`z_i` of the geodesic
        towards :math:`z_j` (the chart recentred at :math:`z_i`), taken at the lower-numbered end
        of each bond, the reverse step that angle plus pi (the two ends' tangents are not
        antipodal in the chart: the difference is the chart's rotation along the geodesic).
        Clusters always use their lift (:func:`cluster_angles`).
        ``"transport"`` (QWZ on a {p,q} flake): every site keeps the chart's frame and the hop
        carries the Levi-Civita connection, :math:`T_{ij} = U(a_{ij})\,T_0\,U(a_{ij} +
        \delta_{ij})^\dagger` with :math:`a_{ij}` the geodesic tangent at :math:`z_i` towards
        :math:`z_j`, :math:`U(\theta) = e^{-i\theta\sigma_z/2}`, :math:`T_0 = T(0)` and
        :math:`\delta_{ij} = a_{ji} - \pi - a_{ij} \in (-\pi, \pi)` the rotation of the chart's
        frame against parallel transport along the bond (:func:`transport_rotation`); the
        orbitals then see :math:`\pm A/2` flux per face, A the face's Levi-Civita holonomy: the
        flake counterpart of the covariant frame of
        :func:`~hyperlattice.topology.frames.qwz_frame_terms`.

    Returns
    -------
    ModelTerms

    Raises
    ------
    ValueError
        For an unknown model, non-finite parameters, Haldane or Kane–Mele on a graph that is not
        bipartite or not of degree 3, flux on anything but a ring lattice.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import model_terms
    >>> t = model_terms(hl.ring_lattice(8, 3, 2), "haldane", M=0.1, t2=0.2)
    >>> t.sites, t.orbitals, len(t.tail)
    (48, 1, 272)
    """
    model = _validate.choice("model", model, MODELS)
    M = _validate.real("M", M, minimum=-1e6, maximum=1e6)
    t1 = _validate.real("t1", t1, minimum=-1e6, maximum=1e6)
    t2 = _validate.real("t2", t2, minimum=-1e6, maximum=1e6)
    phi = _validate.real("phi", phi, minimum=-1e6, maximum=1e6)
    rashba = _validate.real("rashba", rashba, minimum=-1e6, maximum=1e6)
    flux = _validate.real("flux", flux, minimum=-1e6, maximum=1e6)
    disorder = _validate.real("disorder", disorder, minimum=0.0, maximum=1e6)
    seed = _validate.integer("seed", seed, minimum=0, maximum=2**63 - 1)
    frame = _validate.choice("frame", frame, FRAMES)
    dd = _darts(graph)
    if frame == "transport" and (model != "qwz" or dd.kind != "flake" or isinstance(graph, PlaneGraph)):
        raise ValueError("frame='transport' is defined for the qwz model on {p,q} flakes (ring_lattice) only.")
    if frame == "tangent":
        if dd.kind != "flake" or isinstance(graph, PlaneGraph):
            raise ValueError("frame='tangent' is defined on {p,q} flakes (ring_lattice) only.")
        dd = _tangent_frame(graph, dd)
    n = dd.n
    hop_phase = np.ones(len(dd.tail), dtype=np.complex128)
    if flux != 0.0:
        if dd.kind != "flake" or isinstance(graph, PlaneGraph):
            raise ValueError("flux is supported on ring_lattice flakes only.")
        from ..graph.flux import edge_phases

        th = edge_phases(graph, flux)   # phase of the hop j -> i for edge (i, j): H[i, j] *= e^{i th}
        ne = len(th)
        # dart k < E is i -> j with the block at H[i, j]; dart E + k is the reverse
        hop_phase = np.exp(1j * np.concatenate([th, -th[:ne]]))
    params = dict(M=M, t1=t1, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder, seed=seed)
    d = orbitals(model)
    onsite = np.zeros((n, d, d), dtype=np.complex128)
    tails, heads, blocks, winds = [], [], [], []
    if model == "qwz":
        if rashba != 0.0:
            raise ValueError("rashba belongs to the kane-mele model, not to qwz.")
        if frame == "transport":
            T = _transport_blocks(graph, dd)
        else:
            ang = _angles(graph, dd)
            c, s = np.cos(ang), np.sin(ang)
            T = 0.5 * (_SZ[None] + 1j * (c[:, None, None] * _SX[None] + s[:, None, None] * _SY[None]))
        onsite[:] = M * _SZ
        tails.append(dd.tail), heads.append(dd.head), blocks.append(T * hop_phase[:, None, None])
        winds.append(dd.wind)
    else:
        _check_haldane_graph(graph, dd)
        sub = dd.bipartite_sign
        if model == "haldane":
            onsite[:, 0, 0] = M * sub
        else:
            onsite[:] = (M * sub)[:, None, None] * _ID[None]
            if rashba != 0.0:
                ang = _angles(graph, dd)
        # nearest neighbours
        nn = -t1 * hop_phase
        tails.append(dd.tail), heads.append(dd.head), winds.append(dd.wind)
        if model == "haldane":
            blocks.append(nn[:, None, None] * np.ones((1, 1, 1)))
        else:
            b = nn[:, None, None] * _ID[None]
            if rashba != 0.0:
                c, s = np.cos(ang), np.sin(ang)
                b = b + 1j * rashba * (s[:, None, None] * _SX[None] - c[:, None, None] * _SY[None]) \
                    * hop_phase[:, None, None]
            blocks.append(b)
        # next-nearest neighbours i -> j -> k: block at H[i, k]
        d1, d2, turns = dd.paths
        ph2 = hop_phase[d1] * hop_phase[d2]
        tails.append(dd.tail[d1]), heads.append(dd.head[d2]), winds.append(dd.wind[d1] + dd.wind[d2])
        if model == "haldane":
            blocks.append((t2 * np.exp(1j * phi * turns) * ph2)[:, None, None])
        else:
            up = t2 * np.exp(1j * phi * turns) * ph2
            dn = t2 * np.exp(-1j * phi * turns) * ph2
            b = np.zeros((len(d1), 2, 2), dtype=np.complex128)
            b[:, 0, 0], b[:, 1, 1] = up, dn
            blocks.append(b)
    if disorder > 0.0:
        from ..graph.disorder import realization_rng

        v = realization_rng(seed, 0).uniform(-0.5 * disorder, 0.5 * disorder, size=n)
        onsite = onsite + v[:, None, None] * np.eye(d)[None]
    return ModelTerms(model=model, orbitals=d, onsite=onsite, tail=np.concatenate(tails),
                      head=np.concatenate(heads), blocks=np.concatenate(blocks).astype(np.complex128),
                      windings=np.concatenate(winds), parameters=params)


def _tangent_frame(graph, dd: _Darts) -> _Darts:
    """The darts with geodesic-tangent angles at the lower-numbered end of each bond."""
    from dataclasses import replace

    z = np.asarray(graph.z, dtype=np.complex128)
    i, j = dd.tail, dd.head
    w = (z[j] - z[i]) / (1.0 - np.conj(z[i]) * z[j])       # z_j in the chart recentred at z_i
    ang = np.angle(w)
    lower = i < j
    out = ang.copy()
    out[dd.rev[lower]] = ang[lower] + np.pi
    return replace(dd, angle=out)


def transport_rotation(graph) -> np.ndarray:
    r"""Tangent angles and the frame's rotation along every bond of a {p,q} flake (parallel transport).

    For the bond i -> j, :math:`a_{ij} = \arg\frac{z_j - z_i}{1 - \bar z_i z_j}` is the direction at
    :math:`z_i` of the geodesic towards :math:`z_j` (the chart is conformal, so this is the angle
    in the metric against the chart's x axis at :math:`z_i`), and :math:`\delta_{ij} = a_{ji} - \pi -
    a_{ij}`, wrapped to :math:`(-\pi, \pi)`, is how far the chart's frame at :math:`z_j` is rotated
    against the frame at :math:`z_i` parallel-transported along the geodesic (zero in the plane).
    Around a face the :math:`\delta` add up to the Levi-Civita holonomy, :math:`\pm[(p-2)\pi - 2\pi p/q]`.

    Parameters
    ----------
    graph : Lattice
        A {p,q} flake (:func:`~hyperlattice.graph.lattice.ring_lattice`).

    Returns
    -------
    tail, head, a, delta : ndarray
        The darts (every edge forwards, then backwards) and their two angles (radians).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import transport_rotation
    >>> tail, head, a, delta = transport_rotation(hl.ring_lattice(8, 3, 2))
    >>> bool(abs(delta[0] + delta[len(delta) // 2]) < 1e-12)
    True
    """
    if _kind(graph) != "flake" or isinstance(graph, PlaneGraph):
        raise ValueError("transport_rotation needs a {p,q} flake (ring_lattice).")
    z = np.asarray(graph.z, dtype=np.complex128)
    e = np.asarray(graph.edges, dtype=np.int64)
    tail = np.concatenate([e[:, 0], e[:, 1]])
    head = np.concatenate([e[:, 1], e[:, 0]])
    a = np.angle((z[head] - z[tail]) / (1.0 - np.conj(z[tail]) * z[head]))
    back = np.concatenate([a[len(e):], a[: len(e)]])          # a_ji of every dart i -> j
    delta = np.angle(np.exp(1j * (back - np.pi - a)))
    return tail, head, a, delta


def _transport_blocks(graph, dd: _Darts) -> np.ndarray:
    """QWZ hops U(a) T_0 U(a + delta)^dagger in the chart's frame with the Levi-Civita connection."""
    tail, head, a, delta = transport_rotation(graph)
    if not (np.array_equal(tail, dd.tail) and np.array_equal(head, dd.head)):  # pragma: no cover - same edges
        raise ValueError("the flake's darts are not in the order of its edges.")

    def u(theta):
        out = np.zeros(theta.shape + (2, 2), dtype=np.complex128)
        out[..., 0, 0] = np.exp(-0.5j * theta)
        out[..., 1, 1] = np.exp(0.5j * theta)
        return out

    T0 = 0.5 * (_SZ + 1j * _SX)
    return u(a) @ T0[None] @ np.conj(np.swapaxes(u(a + delta), 1, 2))


def _angles(graph, dd: _Darts) -> np.ndarray:
    if dd.angle is not None:
        return dd.angle
    return cluster_angles(graph).ravel()


def _check_haldane_graph(graph, dd: _Darts) -> None:
    deg = np.bincount(dd.tail, minlength=dd.n)
    if dd.kind == "cluster" and graph.q != 3:
        raise ValueError(f"the Haldane and Kane-Mele models need a graph of degree 3 ({{p,3}}), got q = {graph.q}.")
    if getattr(graph, "q", 3) != 3 or deg.max() > 3:
        raise ValueError("the Haldane and Kane-Mele models need a graph of degree 3 ({p,3} or honeycomb).")
    if dd.bipartite_sign is None:
        raise ValueError("the Haldane and Kane-Mele sublattice mass needs a bipartite graph (p even).")


def model_hamiltonian(terms: ModelTerms) -> sp.csr_matrix:
    """The sparse Hamiltonian of a model on an open graph (windings ignored), site-major ordering.

    Row ``i * d + a`` is orbital a of site i.

    Parameters
    ----------
    terms : ModelTerms
        From :func:`model_terms`.

    Returns
    -------
    scipy.sparse.csr_matrix of complex128, shape (N d, N d)
        Hermitian.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import model_terms, model_hamiltonian
    >>> H = model_hamiltonian(model_terms(hl.ring_lattice(8, 3, 2), "qwz", M=1.0))
    >>> H.shape, bool(abs(H - H.getH()).max() < 1e-14)
    ((96, 96), True)
    """
    t = _terms(terms)
    d = t.orbitals
    n = t.sites
    a, b = np.meshgrid(np.arange(d), np.arange(d), indexing="ij")
    rows = [(np.arange(n)[:, None, None] * d + a[None]).ravel(), (t.tail[:, None, None] * d + a[None]).ravel()]
    cols = [(np.arange(n)[:, None, None] * d + b[None]).ravel(), (t.head[:, None, None] * d + b[None]).ravel()]
    vals = [t.onsite.ravel(), t.blocks.ravel()]
    H = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n * d, n * d))
    H = H.tocsr()
    H.eliminate_zeros()
    return H


def bloch_model_hamiltonian(terms: ModelTerms, k) -> np.ndarray:
    r"""The Abelian Bloch Hamiltonian :math:`H(k) = \sum B\, e^{ik\cdot w}` of a model on a closed surface.

    Parameters
    ----------
    terms : ModelTerms
        From :func:`model_terms` on a cluster or a torus.
    k : array_like, shape (2g,) or (K, 2g)
        Momenta on the 2g-torus (radians), in the basis of the windings.

    Returns
    -------
    numpy.ndarray of complex128, shape (N d, N d) or (K, N d, N d)

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.topology.models import model_terms, bloch_model_hamiltonian, square_torus
    >>> H = bloch_model_hamiltonian(model_terms(square_torus(), "qwz", M=1.0), [0.0, 0.0])
    >>> np.round(np.diag(H).real, 12).tolist()
    [3.0, -3.0]
    """
    t = _terms(terms)
    g2 = t.windings.shape[1]
    if g2 == 0:
        raise ValueError("these model terms are on an open graph: no Bloch Hamiltonian (use a cluster or a torus).")
    k = _validate.real_array("k", k)
    single = k.ndim == 1
    kk = np.atleast_2d(k)
    if kk.ndim != 2 or kk.shape[1] != g2:
        raise ValueError(f"k must have {g2} components, got shape {k.shape}.")
    d, n = t.orbitals, t.sites
    if n * d > 4000:
        raise ValueError(f"a dense Bloch Hamiltonian of {n * d:,} rows is refused (at most 4,000).")
    phase = np.exp(1j * (kk @ t.windings.T))                  # (K, H)
    out = np.zeros((len(kk), n, d, n, d), dtype=np.complex128)
    diag = np.arange(n)
    out[:, diag, :, diag, :] += t.onsite[None].transpose(1, 0, 2, 3)
    # accumulate hops: loop over the K momenta with np.add.at on the (tail, head) pairs
    for m in range(len(kk)):
        np.add.at(out[m], (t.tail, slice(None), t.head), (phase[m][:, None, None] * t.blocks))
    out = out.reshape(len(kk), n * d, n * d)
    return out[0] if single else out


def _terms(value) -> ModelTerms:
    if not isinstance(value, ModelTerms):
        raise ValueError(f"expected ModelTerms (from model_terms), got {type(value).__name__}.")
    return value


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
