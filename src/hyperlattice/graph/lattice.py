r"""Finite {p,q} ring lattices embedded in the Poincaré disk.

Construction (paper, Fig. 1 and App. ``AppGraph``): ring 1 is the central regular p-gon,
with vertices at :math:`r_0 e^{2\pi i k/p}`; ring :math:`k+1` adds every p-gon that shares a
vertex with the cluster of rings :math:`\le k`. Sites are polygon vertices and edges are
polygon edges, every edge having hyperbolic length :math:`d_0`.

The graph is built combinatorially, one ring at a time, from the cyclic boundary of the
cluster (never by searching for points at distance :math:`d_0`, which degrades as
:math:`|z| \to 1`):

* a boundary vertex with :math:`c` cluster polygons has :math:`q-c-1` new edges
  ("spokes") pointing out of the cluster;
* between two consecutive spokes (in the counterclockwise order around the cluster)
  lies exactly one new polygon; it contains the :math:`n_{\rm old}` boundary vertices
  from the owner of the first spoke to the owner of the second, the two spoke ends,
  and :math:`p - n_{\rm old} - 2` further new vertices ("middles");
* all vertices of the old boundary become interior, so the new boundary is exactly the
  new ring, whose counterclockwise order is read off from the polygons.

Coordinates follow from hyperbolic rotations: a spoke at vertex v is the boundary
predecessor of v rotated about v by multiples of :math:`2\pi/q`; the remaining vertices of
a new polygon are rotations of a spoke end about the polygon's centre by multiples of
:math:`2\pi/p`. Every step is a vectorized numpy operation over a whole ring. The p-fold
rotation maps ring k onto itself as a cyclic shift by :math:`N_{\rm ring}(k)/p`.
"""

from __future__ import annotations

import json
import math
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from .. import _validate
from .. import geometry
from ..results import Result, _digest, _verify_digest

if TYPE_CHECKING:  # only for annotations: matplotlib and networkx are imported where used
    import networkx

__all__ = [
    "Lattice",
    "lattice_from_networkx",
    "ring_lattice",
    "line_graph",
    "ring_sizes",
    "site_count",
    "edge_count",
    "site_count_float",
    "load_lattice",
]

#: Bytes of peak memory per site while building a lattice and its adjacency (measured,
#: with margin): used to refuse sizes that cannot fit before allocating anything.
_BYTES_PER_SITE = 400
#: Peak bytes of :func:`line_graph` per line-graph site (= parent edge) and per line-graph
#: edge, with an interior site's q - 1 edges per site assumed. Measured: about 270 + 43 per
#: edge with tracemalloc ({7,3}, {3,7}, {3,12}, {4,5}), 362 B per site of peak RSS for the
#: {7,3} line graph of 13 rings (2.4 M sites); ~30 % margin on top.
_BYTES_PER_LINE_SITE = 350
_BYTES_PER_LINE_EDGE = 60
#: Site ids, edges and per-ring counters are 32-bit: no lattice beyond this many sites.
_MAX_SITES = 2**31 - 1
_INT64_MAX = 2**63 - 1
#: The explicit layer construction cross-checks the counting recursion only while a boundary
#: has at most this many spokes (well under a megabyte of temporaries).
_CALIBRATION_SPOKES = 2**16


def _available_memory() -> int:
    # the package's one probe: machine, RLIMIT_AS and cgroup limits (so that `lattice --rings 15
    # --line-graph` under `ulimit -v` is sized by the limit, not by the machine's RAM)
    return _validate.available_memory()


# ----------------------------------------------------------------------------
# the immutable result
# ----------------------------------------------------------------------------

#: dtype of each array field: kept whatever the source (a JSON list, an old .npz file)
_DTYPES = {"z": np.complex128, "ring": np.int16, "edges": np.int32, "rotation": np.int32,
           "parent_edges": np.int32}
_KINDS = ("sites", "line_graph")


@dataclass(frozen=True, eq=False, kw_only=True)
class Lattice(Result):
    r"""A finite hyperbolic lattice: an immutable bundle of numpy arrays (a :class:`Result`).

    Attributes
    ----------
    p, q : int
        Schläfli symbol of the tessellation the lattice is cut from.
    rings : int
        Number of rings :math:`\ell`.
    z : ndarray of complex128, shape (N,)
        Site coordinates in the Poincaré disk (metric :math:`|dz|^2/(1-|z|^2)^2`).
    ring : ndarray of int16, shape (N,)
        Ring index (1-based) of each site; sites are sorted by ring.
    edges : ndarray of int32, shape (E, 2)
        Undirected edges ``i < j``, grouped by the ring in which they were created (ring
        1's cycle, then for each further ring its edges to the previous ring and its own
        cycle). Use :meth:`neighbours` or :func:`hyperlattice.adjacency` for sorted access.
    rotation : ndarray of int32, shape (N,)
        The p-fold rotation :math:`z \mapsto e^{2\pi i/p} z` as a site permutation:
        site ``i`` is mapped onto site ``rotation[i]``.
    kind : str
        ``"sites"`` for the {p,q} lattice itself, ``"line_graph"`` for its line graph
        (then ``z`` are edge midpoints, and ``parent_edges`` holds the original edges).
    parent_edges : ndarray of int32, shape (N, 2), or None
        For ``kind == "line_graph"``: the edge ``(i, j)`` of the parent lattice that each
        line-graph site stands for (site indices of the parent); ``None`` for ``"sites"``.

    Notes
    -----
    Sites are indexed 0-based, ring by ring (ring 1 first), which is the row order of every
    operator built from the lattice (:func:`hyperlattice.adjacency`, :func:`hyperlattice.hamiltonian`
    with :math:`H = -tA`). As a :class:`~hyperlattice.results.Result` it round-trips through
    :meth:`as_dict` / :meth:`from_dict` and :meth:`save` / :meth:`load`; :meth:`save` keeps the
    ``.npz`` layout of earlier versions (``z, ring, edges, rotation, p, q, rings, kind[,
    parent_edges]``), so :func:`load_lattice` reads old and new files alike.

    Examples
    --------
    >>> from hyperlattice import ring_lattice
    >>> lat = ring_lattice(7, 3, 2)
    >>> lat
    <Lattice {7,3} rings=2 sites=35 edges=42>
    >>> lat.sites_per_ring.tolist(), lat.ring[:3].tolist()
    ([7, 28], [1, 1, 1])
    >>> lat.rotation[:7].tolist()          # ring 1 is shifted by one site
    [1, 2, 3, 4, 5, 6, 0]
    >>> bool(abs(lat.edge_lengths().max() - lat.d0) < 1e-12), round(lat.d0, 6)
    (True, 0.283128)
    """

    NOT_TABULAR = ("a graph: its per-site arrays (z, ring, rotation) mean something only with its edge list, "
                   "and both are stored as they are")

    #: the marker :func:`hyperlattice._validate.lattice` recognises (the input door sits below
    #: ``graph/`` and does not import this module)
    __hyperlattice_lattice__: ClassVar[bool] = True

    p: int
    q: int
    rings: int
    z: np.ndarray
    ring: np.ndarray
    edges: np.ndarray
    rotation: np.ndarray
    kind: str = "sites"
    parent_edges: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        # scalars may arrive as 0-d arrays (an .npz file) and arrays as lists (JSON): normalise
        # them, so that every lattice has the same dtypes however it was made
        for name in ("p", "q", "rings"):
            object.__setattr__(self, name, int(getattr(self, name)))
        object.__setattr__(self, "kind", str(self.kind))
        for name, dtype in _DTYPES.items():
            a = getattr(self, name)
            if a is not None:
                a = np.ascontiguousarray(a, dtype=dtype)
                if name in ("edges", "parent_edges") and a.size == 0:
                    a = a.reshape(0, 2)
                object.__setattr__(self, name, a)
        super().__post_init__()  # read-only arrays

    def __repr__(self) -> str:
        what = "line graph of " if self.kind == "line_graph" else ""
        return (f"<Lattice {what}{{{self.p},{self.q}}} rings={self.rings} "
                f"sites={self.sites} edges={len(self.edges)}>")

    # -- sizes ---------------------------------------------------------------
    @property
    def sites(self) -> int:
        """Number of sites N."""
        return int(self.z.shape[0])

    @property
    def sites_per_ring(self) -> np.ndarray:
        """Number of sites on each ring 1..rings."""
        return np.bincount(self.ring, minlength=self.rings + 1)[1:]

    @property
    def ring_offsets(self) -> np.ndarray:
        """``ring_offsets[k-1]:ring_offsets[k]`` are the sites of ring k (length rings+1)."""
        return np.concatenate([[0], np.cumsum(self.sites_per_ring)])

    @property
    def coordination(self) -> int:
        """Coordination number of interior sites (q, or 2(q-1) for the line graph)."""
        return self.q if self.kind == "sites" else 2 * (self.q - 1)

    # -- derived geometry ----------------------------------------------------
    @property
    def d0(self) -> float:
        """Hyperbolic edge length of the parent tessellation."""
        return geometry.d0(self.p, self.q)

    @property
    def h(self) -> float:
        """:math:`h = \\tanh d_0`."""
        return geometry.lattice_h(self.p, self.q)

    @property
    def radius(self) -> float:
        """Effective disk radius :math:`L = \\sqrt{N/(N+c_{pq})}` (``eq12``, generalised)."""
        return geometry.effective_radius(self.sites, self.p, self.q)

    @property
    def degree(self) -> np.ndarray:
        """Number of neighbours of each site."""
        return np.bincount(self.edges.ravel(), minlength=self.sites)

    def edge_lengths(self) -> np.ndarray:
        """Hyperbolic length of every edge (all equal to d0 for ``kind == 'sites'``)."""
        return geometry.distance(self.z[self.edges[:, 0]], self.z[self.edges[:, 1]])

    def neighbours(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR-style neighbour lists ``(indptr, indices)``, neighbours in increasing order."""
        e = self.edges
        src = np.concatenate([e[:, 0], e[:, 1]])
        dst = np.concatenate([e[:, 1], e[:, 0]])
        return _csr_sorted(src, dst, self.sites)

    # -- result protocol -------------------------------------------------------
    def summary(self) -> dict:
        """The CLI's JSON view: p, q, rings, kind, sites, edges, sites_per_ring, d0, h, radius."""
        return {
            "p": self.p,
            "q": self.q,
            "rings": self.rings,
            "kind": self.kind,
            "sites": self.sites,
            "edges": int(self.edges.shape[0]),
            "sites_per_ring": self.sites_per_ring.tolist(),
            "d0": self.d0,
            "h": self.h,
            "radius": self.radius,
        }

    def _check_loaded(self) -> str | None:
        # a lattice read back must be the lattice its p, q, rings and kind describe
        return _lattice_error(self)

    @classmethod
    def from_dict(cls, data: dict) -> "Lattice":
        """Rebuild a lattice from :meth:`as_dict` output, checking that its arrays fit together.

        Parameters
        ----------
        data : dict
            The output of :meth:`as_dict` (or its JSON round trip).

        Returns
        -------
        Lattice
            The lattice, checked (shapes, index ranges, rotation, ring structure).

        Raises
        ------
        ValueError
            If the arrays do not describe the {p,q} lattice of the stored ``rings`` and ``kind``.

        Examples
        --------
        >>> from hyperlattice import Lattice, ring_lattice
        >>> Lattice.from_dict(ring_lattice(7, 3, 2).as_dict()).sites
        35
        """
        return _checked(super().from_dict(data), "the stored lattice")

    # -- export --------------------------------------------------------------
    def to_networkx(self, *, pos: bool = True) -> networkx.Graph:
        """The lattice as a :class:`networkx.Graph` with plain attributes.

        Nodes are the site indices (0-based, the paper's order) with ``x``, ``y`` (float,
        Poincaré-disk coordinates, ``z = x + iy``), ``ring`` (int) and, unless ``pos=False``,
        ``pos = (x, y)``, the attribute networkx's drawing functions read
        (``nx.draw(g, pos=nx.get_node_attributes(g, "pos"))``). Edges carry nothing; the graph
        attributes are ``p``, ``q``, ``rings`` and ``kind``. GraphML has no tuples: write
        ``to_networkx(pos=False)`` with :func:`networkx.write_graphml`; :func:`from_networkx`
        reads the graph, or its GraphML round trip, back into a checked :class:`Lattice`.

        Parameters
        ----------
        pos : bool, optional
            Add the ``pos = (x, y)`` node attribute (default True).

        Returns
        -------
        networkx.Graph
            One node per site, one edge per lattice edge.

        Examples
        --------
        >>> from hyperlattice import ring_lattice
        >>> g = ring_lattice(7, 3, 2).to_networkx()
        >>> g.number_of_nodes(), g.number_of_edges(), g.nodes[0]["ring"]
        (35, 42, 1)
        """
        try:
            import networkx as nx
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError("to_networkx() needs networkx: pip install 'hyperlattice[networkx]'") from exc
        pos = _validate.flag("pos", pos)
        g = nx.Graph(p=int(self.p), q=int(self.q), rings=int(self.rings), kind=str(self.kind))
        xs, ys, rs = self.z.real.tolist(), self.z.imag.tolist(), self.ring.tolist()
        g.add_nodes_from((i, {"x": x, "y": y, "ring": int(r), **({"pos": (x, y)} if pos else {})})
                         for i, (x, y, r) in enumerate(zip(xs, ys, rs)))
        g.add_edges_from(map(tuple, self.edges.tolist()))
        return g

    def save(self, path) -> Path:
        """Write the lattice to ``path``, the format chosen by the file extension.

        ``.dat``: the paper's coordinates.dat (Re z and Im z, one site per line, ``%.17g`` so
        that the numbers round-trip exactly); ``.npz``: the arrays and p, q, rings, kind (the
        layout :func:`load_lattice` and :func:`hyperlattice.results.load_result` read);
        ``.json``: :meth:`as_dict`.

        Parameters
        ----------
        path : str or pathlib.Path
            Output file ending in ``.dat``, ``.npz`` or ``.json``.

        Returns
        -------
        pathlib.Path
            The path written.

        Raises
        ------
        ValueError
            If the extension is none of these or the file cannot be written.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> from hyperlattice import Lattice, ring_lattice
        >>> with tempfile.TemporaryDirectory() as d:
        ...     path = ring_lattice(7, 3, 2).save(pathlib.Path(d) / "flake.npz")
        ...     Lattice.load(path).sites
        35
        """
        suffixes = (".dat", ".npz", ".json")
        path = _validate.output_path("path", path)
        suffix = path.suffix.lower()
        if suffix not in suffixes:
            raise ValueError(f"unknown output format {path.suffix!r}: use .dat, .npz or .json.")
        try:
            if suffix == ".dat":
                np.savetxt(path, np.column_stack([self.z.real, self.z.imag]), fmt="%.17g")
            elif suffix == ".npz":
                arrays = {"z": self.z, "ring": self.ring, "edges": self.edges, "p": self.p, "q": self.q,
                          "rings": self.rings, "kind": self.kind, "rotation": self.rotation}
                if self.parent_edges is not None:
                    arrays["parent_edges"] = self.parent_edges
                arrays = {k: np.asarray(v) for k, v in arrays.items()}
                # the layout of earlier versions, plus the protocol's type tag and the arrays' sha256
                meta = {"type": self.TYPE}
                meta["sha256"] = _digest(meta, arrays)
                np.savez_compressed(path, __meta__=np.array(json.dumps(meta)), **arrays)
            else:
                data = self.as_dict()
                data["sha256"] = _digest(data)
                path.write_text(json.dumps(data, allow_nan=False))
        except OSError as exc:
            raise ValueError(f"cannot write {str(path)!r}: {exc.strerror or exc}.") from None
        return path

    @classmethod
    def load(cls, path) -> "Lattice":
        """Read a lattice written by :meth:`save` (``.npz`` or ``.json``); see :func:`load_lattice`.

        Parameters
        ----------
        path : str or pathlib.Path
            A ``.npz`` or ``.json`` file written by :meth:`save`.

        Returns
        -------
        Lattice
            The lattice, checked as in :meth:`from_dict`.
        """
        return load_lattice(path)


def _checked(lat: Lattice, source: str) -> Lattice:
    """``lat`` if its arrays describe a lattice (shapes, index ranges, permutation, structure), else ValueError.

    Used for lattices read from files, never on the builder's hot path.
    """
    why = _lattice_error(lat)
    if why is not None:
        raise ValueError(f"{source} is not a valid lattice: {why}.")
    return lat


def _lattice_error(lat: Lattice) -> str | None:
    """Why ``lat`` is not a consistent lattice (one clause), or None."""
    try:
        _validate.pq(lat.p, lat.q)
    except ValueError as exc:
        return str(exc).rstrip(".")
    if lat.kind not in _KINDS:
        return f"kind must be 'sites' or 'line_graph', got {lat.kind!r}"
    n = lat.sites
    if lat.z.ndim != 1 or n == 0:
        return "z must be a non-empty 1-d array"
    if not (np.all(np.isfinite(lat.z)) and np.all(np.abs(lat.z) < 1.0)):
        return "some sites lie outside the open unit disk"
    if lat.ring.shape != (n,) or lat.rotation.shape != (n,):
        return "ring and rotation must have one entry per site"
    if lat.rings < 1 or np.any(lat.ring < 1) or np.any(lat.ring > lat.rings) or np.any(np.diff(lat.ring) < 0):
        return "ring indices must be sorted and lie in 1..rings"
    if lat.edges.ndim != 2 or lat.edges.shape[1] != 2 or (lat.edges.size and (lat.edges.min() < 0
                                                                            or lat.edges.max() >= n)):
        return "edges must be pairs of site indices"
    if np.any(lat.rotation < 0) or np.any(lat.rotation >= n) or np.any(np.bincount(lat.rotation, minlength=n) != 1):
        return "rotation must be a permutation of the sites"
    if lat.kind == "line_graph" and (lat.parent_edges is None or lat.parent_edges.shape != (n, 2)):
        return "a line graph needs parent_edges, one pair per site"
    return _structure_error(lat)


#: Rounding of stored coordinates grows with the ring through the construction (each ring is
#: placed from the previous one): measured |d - d0| <= 37 eps (w_a + w_b) over {7,3} to 9 rings,
#: {8,3} 8, {12,3} 6, {3,7} 5, {4,5} 6, {6,4} 5 (w = 1/(1 - |z|^2), the metric factor that turns
#: an error in z into a hyperbolic length). The tolerance takes 256 eps (w_a + w_b) per ring:
#: still 1e-10 of a hyperbolic length for a site moved by 1e-6 near the boundary.
_LENGTH_EPS_PER_RING = 256.0


def _structure_error(lat: Lattice) -> str | None:
    """Why ``lat`` is not the lattice its p, q, rings and kind describe, or None.

    Checks what the solvers trust: no self-loop or repeated edge; for a site lattice the ring
    sizes and edge count of {p,q} with that many rings, edges only within a ring or between
    neighbouring rings, degree q inside and at most q on the last ring, every edge of length
    d0 and each ring counterclockwise once around; for both kinds the rotation table maps each
    ring onto itself, every edge onto an edge and (site lattices) z onto exp(2 pi i/p) z. Float
    comparisons use a tolerance from the coordinates' own rounding (``_LENGTH_EPS_PER_RING``).
    """
    n = lat.sites
    e = lat.edges.astype(np.int64)
    if e.shape[0] and np.any(e[:, 0] == e[:, 1]):
        return f"site {int(e[np.argmax(e[:, 0] == e[:, 1]), 0])} has an edge to itself"
    lo, hi = np.minimum(e[:, 0], e[:, 1]), np.maximum(e[:, 0], e[:, 1])
    keys = np.sort(lo * n + hi)
    if keys.size and np.any(np.diff(keys) == 0):
        k = int(keys[np.argmax(np.diff(keys) == 0)])
        return f"the edge ({k // n}, {k % n}) appears twice"
    # the rotation: each ring onto itself, edges onto edges (the sector solver builds on this)
    rot = lat.rotation.astype(np.int64)
    if np.any(lat.ring[rot] != lat.ring):
        return "the rotation table moves sites between rings"
    a, b = rot[e[:, 0]], rot[e[:, 1]]
    img = np.minimum(a, b) * n + np.maximum(a, b)
    pos = np.minimum(np.searchsorted(keys, img), max(keys.size - 1, 0))
    if keys.size and not np.array_equal(keys[pos], img):
        return "the rotation table does not map the edges onto edges"
    if lat.kind != "sites":
        return None
    p, q, rings = lat.p, lat.q, lat.rings
    if not np.array_equal(lat.sites_per_ring, ring_sizes(p, q, rings)):
        return f"its ring sizes are not those of {{{p},{q}}} with {rings} rings"
    if e.shape[0] != edge_count(p, q, rings):
        return f"it has {e.shape[0]} edges, {{{p},{q}}} with {rings} rings has {edge_count(p, q, rings)}"
    ring = lat.ring.astype(np.int64)
    if e.shape[0] and np.any(np.abs(ring[e[:, 0]] - ring[e[:, 1]]) > 1):
        return "an edge skips a ring"
    deg = lat.degree
    inner = ring < rings
    if np.any(deg[inner] != q) or np.any(deg > q):
        i = int(np.argmax(((deg != q) & inner) | (deg > q)))
        return f"site {i} has {int(deg[i])} neighbours (q = {q} inside, at most q on the last ring)"
    eps = np.finfo(float).eps
    w = 1.0 / geometry.one_minus_abs2(lat.z)
    tol_scale = _LENGTH_EPS_PER_RING * eps * rings
    d0 = lat.d0
    lengths = geometry.distance(lat.z[e[:, 0]], lat.z[e[:, 1]], check=False)
    err = np.abs(lengths - d0) - tol_scale * (w[e[:, 0]] + w[e[:, 1]] + d0)
    if err.size and np.any(err > 0):
        k = int(np.argmax(err))
        return (f"the edge ({int(e[k, 0])}, {int(e[k, 1])}) has length {float(lengths[k]):.17g}, "
                f"not d0 = {d0:.17g}")
    moved = geometry.distance(lat.z[rot], np.exp(2j * math.pi / p) * lat.z, check=False) - tol_scale * 2 * w
    if np.any(moved > 0):
        return f"the rotation table maps site {int(np.argmax(moved))} elsewhere than its rotated position"
    # each ring counterclockwise, once around: the angular steps to the next site sum to 2 pi
    offsets = lat.ring_offsets.astype(np.int64)
    nxt = np.arange(1, n + 1, dtype=np.int64)
    nxt[offsets[1:] - 1] = offsets[:-1]
    ang = np.angle(lat.z)
    steps = np.mod(ang[nxt] - ang, 2 * math.pi)
    turns = np.bincount(ring - 1, weights=steps, minlength=rings) / (2 * math.pi)
    if np.any(np.abs(turns - 1.0) > 1e-6):
        k = int(np.argmax(np.abs(turns - 1.0))) + 1
        return f"the sites of ring {k} are not in counterclockwise order"
    return None


def _csr_sorted(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Group ``cols`` by ``rows`` (a counting sort, O(N + E)) with sorted columns per row, repeats dropped."""
    return _csr_kernel()(np.ascontiguousarray(rows), np.ascontiguousarray(cols), n)


_KERNELS: dict = {}


def _csr_kernel():
    """Numba counting sort of (row, column) pairs into CSR, each row sorted (insertion sort: a few
    entries per row) and without repeated columns."""
    if "csr" in _KERNELS:
        return _KERNELS["csr"]
    import numba

    @numba.njit(cache=True)
    def csr(rows, cols, n):                    # pragma: no cover - compiled
        # two arrays of the output's size and nothing else: every fresh page costs time
        m = rows.shape[0]
        indptr = np.zeros(n + 1, np.int64)
        for e in range(m):
            indptr[rows[e] + 1] += 1
        for r in range(n):
            indptr[r + 1] += indptr[r]
        idx = np.empty(m, np.int32)
        for e in range(m):                     # indptr[r] runs to the end of row r
            r = rows[e]
            idx[indptr[r]] = cols[e]
            indptr[r] += 1
        for r in range(n, 0, -1):              # back to the starts
            indptr[r] = indptr[r - 1]
        indptr[0] = 0
        out = 0
        b = 0
        for r in range(n):
            a, b = b, indptr[r + 1]             # the row as filled (indptr[r] may be compacted)
            for i in range(a + 1, b):          # insertion sort of the row
                v = idx[i]
                j = i - 1
                while j >= a and idx[j] > v:
                    idx[j + 1] = idx[j]
                    j -= 1
                idx[j + 1] = v
            for i in range(a, b):              # drop repeats, compacting in place
                if i == a or idx[i] != idx[i - 1]:
                    idx[out] = idx[i]
                    out += 1
            indptr[r + 1] = out
        if out < m:
            return indptr, idx[:out].copy()
        return indptr, idx

    _KERNELS["csr"] = csr
    return csr


def lattice_from_networkx(graph) -> Lattice:
    """Rebuild a :class:`Lattice` from a :meth:`Lattice.to_networkx` graph.

    The graph may also come back from a GraphML round trip. It must carry the attributes
    ``to_networkx`` writes (graph: ``p``, ``q``, ``rings``, ``kind``; nodes ``0..N-1``, as ints
    or their strings, with ``x`` and ``y``). The lattice is rebuilt from (p, q, rings, kind) and
    the graph is checked against it: the same sites at the same positions (to 1e-12) and the
    same edges; anything else is refused, since a solver would otherwise trust a rotation table
    the graph does not have.

    Parameters
    ----------
    graph : networkx.Graph
        A graph written by :meth:`Lattice.to_networkx` (or read back from GraphML). Node
        positions ``x``, ``y`` are Poincaré-disk coordinates; node labels are the 0-based
        site indices.

    Returns
    -------
    Lattice
        The lattice (``kind`` ``"sites"`` or ``"line_graph"``) the graph names, with the same
        site order as the graph's node labels.

    Raises
    ------
    ValueError
        If the graph is not such a lattice graph or differs from the lattice it names.

    See Also
    --------
    ring_lattice, load_lattice

    Examples
    --------
    >>> import hyperlattice as hl
    >>> g = hl.ring_lattice(7, 3, 2).to_networkx()
    >>> lat = hl.lattice_from_networkx(g)
    >>> lat.p, lat.q, lat.rings, lat.sites
    (7, 3, 2, 35)
    """
    if not (hasattr(graph, "graph") and hasattr(graph, "nodes") and hasattr(graph, "edges")):
        raise ValueError(f"lattice_from_networkx takes a networkx graph, got {type(graph).__name__}.")
    attrs = graph.graph
    missing = [k for k in ("p", "q", "rings", "kind") if k not in attrs]
    if missing:
        raise ValueError(f"the graph lacks the lattice attributes {', '.join(missing)} (written by to_networkx).")
    p, q = _validate.pq(attrs["p"], attrs["q"])
    rings = _validate.positive_int("rings", attrs["rings"])
    kind = attrs["kind"]
    if kind not in ("sites", "line_graph"):
        raise ValueError(f"the graph's kind must be 'sites' or 'line_graph', got {kind!r}.")
    lat = ring_lattice(p, q, rings)
    if kind == "line_graph":
        lat = line_graph(lat)
    n = graph.number_of_nodes()
    if n != lat.sites:
        raise ValueError(f"the graph has {n:,} nodes, the {kind} lattice {{{p},{q}}} with {rings} rings {lat.sites:,}.")
    try:
        index = {node: int(node) for node in graph.nodes}
    except (TypeError, ValueError):
        raise ValueError("the graph's nodes must be the site indices 0..N-1.") from None
    if sorted(index.values()) != list(range(n)):
        raise ValueError("the graph's nodes must be the site indices 0..N-1.")
    z = np.empty(n, dtype=complex)
    for node, data in graph.nodes(data=True):
        try:
            z[index[node]] = complex(float(data["x"]), float(data["y"]))
        except (KeyError, TypeError, ValueError):
            raise ValueError(f"node {node!r} lacks float x and y coordinates.") from None
    if not np.allclose(z, lat.z, rtol=0.0, atol=1e-12):
        raise ValueError("the graph's site positions differ from those of the lattice it names.")
    edges = np.array(sorted((min(index[a], index[b]), max(index[a], index[b])) for a, b in graph.edges),
                     dtype=np.int64).reshape(-1, 2)
    ref = np.asarray(lat.edges, dtype=np.int64)
    ref = ref[np.lexsort((ref[:, 1], ref[:, 0]))]
    if edges.shape != ref.shape or not np.array_equal(edges, ref):
        raise ValueError("the graph's edges differ from those of the lattice it names.")
    return lat


def load_lattice(path) -> Lattice:
    """Read a lattice written by :meth:`Lattice.save`.

    Reads ``.npz`` (also from earlier versions) or ``.json``. What is read back is checked,
    never trusted: a file written by this version carries the sha256 of its contents, and a
    mismatch (an edited or damaged file) is refused; every file, also one without a checksum,
    must hold the lattice its p, q, rings and kind describe (ring sizes, edge count, no
    self-loop or repeated edge, degrees, every edge of length d0 within the coordinates'
    rounding, counterclockwise rings, and a rotation table that maps sites to their rotated
    positions and edges onto edges -- the sector solver relies on it).

    Parameters
    ----------
    path : str or os.PathLike
        The file; its suffix (``.json`` or else ``.npz``) selects the format.

    Returns
    -------
    Lattice
        The lattice as saved.

    Raises
    ------
    ValueError
        If the file does not exist, cannot be read, fails its checksum or does not hold a
        consistent lattice; the message names the file.

    See Also
    --------
    Lattice.save, lattice_from_networkx

    Examples
    --------
    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> path = os.path.join(tempfile.mkdtemp(), "lat.npz")
    >>> _ = hl.ring_lattice(7, 3, 2).save(path)
    >>> hl.load_lattice(path).sites
    35
    """
    path = _validate.input_path("path", path)
    where = repr(str(path))
    try:
        if path.suffix.lower() == ".json":
            try:
                data = json.loads(path.read_text())
            except RecursionError:
                raise ValueError(f"{where} is not a saved lattice (nested too deeply).") from None
            if not isinstance(data, dict):
                raise ValueError(f"{where} is not a saved lattice (not a JSON object).")
            _verify_digest(where, data)
            return _checked(Lattice.from_dict(data), where)
        if not zipfile.is_zipfile(path):
            raise ValueError(f"{where} is not a saved lattice (not an .npz archive).")
        with np.load(path, allow_pickle=False) as f:
            missing = [k for k in ("z", "ring", "edges", "rotation", "p", "q", "rings", "kind") if k not in f.files]
            if missing:
                raise ValueError(f"{where} is not a saved lattice (it lacks {', '.join(missing)}).")
            arrays = {k: f[k] for k in f.files if k != "__meta__"}
            if "__meta__" in f.files:
                # files of this version carry the sha256 of their arrays; earlier ones have none
                try:
                    meta = json.loads(str(f["__meta__"]))
                except (ValueError, RecursionError):
                    meta = None
                if not isinstance(meta, dict):
                    raise ValueError(f"{where} is not a saved lattice (unreadable __meta__).")
                _verify_digest(where, meta, arrays)
        unknown = set(arrays) - {"z", "ring", "edges", "rotation", "p", "q", "rings", "kind", "parent_edges"}
        if unknown:
            raise ValueError(f"{where} is not a saved lattice (unknown arrays {', '.join(sorted(unknown))}).")
        scalars = {}
        for name in ("p", "q", "rings"):
            v = arrays[name]
            if v.ndim != 0 or v.dtype.kind not in "iu":
                raise ValueError(f"{where} is not a valid lattice: {name} must be an integer.")
            scalars[name] = _validate.integer(name, v.item())
        kind = arrays["kind"]
        if kind.ndim != 0 or kind.dtype.kind != "U":
            raise ValueError(f"{where} is not a valid lattice: kind must be a string.")
        for name, kinds in (("z", "c"), ("ring", "iu"), ("edges", "iu"), ("rotation", "iu"), ("parent_edges", "iu")):
            if name in arrays and arrays[name].dtype.kind not in kinds:
                raise ValueError(f"{where} is not a valid lattice: {name} has the wrong dtype "
                                 f"{arrays[name].dtype}.")
            if name in arrays and kinds == "iu" and arrays[name].size:
                # the lattice stores these narrower (int16 rings, int32 ids): refuse what would wrap
                info = np.iinfo(_DTYPES[name])
                if arrays[name].min() < info.min or arrays[name].max() > info.max:
                    raise ValueError(f"{where} is not a valid lattice: {name} has entries beyond {info.dtype}.")
        lat = Lattice(**scalars, z=arrays["z"], ring=arrays["ring"], edges=arrays["edges"],
                      rotation=arrays["rotation"], kind=str(kind), parent_edges=arrays.get("parent_edges"))
    except (OSError, EOFError, zipfile.BadZipFile, json.JSONDecodeError, UnicodeDecodeError, TypeError,
            OverflowError) as exc:
        raise ValueError(f"cannot read a lattice from {where}: {_validate.file_problem(exc)}.") from None
    except ValueError as exc:
        if str(exc).startswith(where):
            raise
        raise ValueError(f"cannot read a lattice from {where}: {_validate.file_problem(exc)}.") from None
    return _checked(lat, where)


# ----------------------------------------------------------------------------
# combinatorial layer step
# ----------------------------------------------------------------------------

@dataclass
class _Layer:
    """Counterclockwise boundary of the cluster: vertex ids and number of outward spokes."""

    ids: np.ndarray      # global ids of the boundary vertices, ccw
    spokes: np.ndarray   # outward spokes per boundary vertex (q - c - 1)


def _layer_topology(spokes: np.ndarray, p: int, q: int):
    """Combinatorics of the next ring from the spoke counts of the current boundary.

    Returns (owner, k, n_new, spoke_slot, mid_poly, mid_t, mid_slot, poly_count).
    ``owner[j]``: boundary position owning spoke j (spokes in ccw order), ``k[j]``: its
    index 1..s at that vertex. ``spoke_slot[j]``: position in the new ring of spoke j's end.
    Middles: polygon ``mid_poly``, step ``mid_t`` (1 = next to the second spoke end),
    ring position ``mid_slot``. ``poly_count``: number of new polygons containing each
    new-ring vertex.
    """
    # int32 throughout: a ring of 2**31 sites could not be held in memory anyway
    nb = spokes.shape[0]
    owner = np.repeat(np.arange(nb, dtype=np.int32), spokes)
    n_spokes = owner.shape[0]
    if n_spokes == 0:
        raise RuntimeError("boundary without outward spokes: not a hyperbolic tessellation")
    # k = 1..s within each vertex
    first = np.zeros(nb, dtype=np.int32)
    np.cumsum(spokes[:-1], out=first[1:])
    k = np.arange(n_spokes, dtype=np.int32) - first[owner] + 1
    nxt_owner = np.roll(owner, -1)
    n_old = np.mod(nxt_owner - owner, nb) + 1  # boundary vertices of each new polygon
    contrib = p - n_old - 1  # new-ring entries per polygon: its first spoke end + middles
    if np.any(contrib < 0):
        raise RuntimeError("inconsistent layer combinatorics (polygon with too many old vertices)")
    offsets = np.zeros(n_spokes, dtype=np.int32)
    np.cumsum(contrib[:-1], out=offsets[1:])
    n_new = int(offsets[-1] + contrib[-1])
    spoke_slot = offsets % n_new
    # middles of polygon j: t = 1..r_j, r_j = contrib_j - 1, at slot offsets_j + contrib_j - t
    r = contrib - 1
    rpos = np.maximum(r, 0)
    mid_poly = np.repeat(np.arange(n_spokes, dtype=np.int32), rpos)
    mstart = np.zeros(n_spokes, dtype=np.int32)
    np.cumsum(rpos[:-1], out=mstart[1:])
    mid_t = np.arange(mid_poly.shape[0], dtype=np.int32) - mstart[mid_poly] + 1
    mid_slot = offsets[mid_poly] + contrib[mid_poly] - mid_t
    # polygons per new vertex (spoke ends shared by neighbouring polygons; p = 3 merges them)
    nxt_slot = np.roll(spoke_slot, -1)
    distinct = nxt_slot != spoke_slot
    # int32, not int8: q - poly_count - 1 must not overflow for large q (q > 127 did)
    poly_count = np.bincount(spoke_slot, minlength=n_new).astype(np.int32)
    poly_count += np.bincount(nxt_slot[distinct], minlength=n_new).astype(np.int32)
    poly_count += np.bincount(mid_slot, minlength=n_new).astype(np.int32)
    return owner, k, n_new, spoke_slot, mid_poly, mid_t, mid_slot, poly_count


# ----------------------------------------------------------------------------
# counting (exact, cheap, bounded): used to refuse sizes before allocating
# ----------------------------------------------------------------------------

def _ring_counts(p: int, q: int, rings: int, max_spokes: int) -> list[int]:
    """Exact sites per ring from the explicit layer combinatorics (arrays, no coordinates).

    Used only to cross-check :func:`_type_counts`; stops (returning fewer rings) before a
    boundary with more than ``max_spokes`` outward spokes, so it never allocates much.
    """
    if p > max_spokes:
        return []
    counts = [p]
    spokes = np.full(p, q - 2, dtype=np.int64)
    for _ in range(rings - 1):
        if int(spokes.sum()) > max_spokes:
            break
        topology = _layer_topology(spokes, p, q)
        n_new, poly_count = topology[2], topology[7]
        counts.append(n_new)
        spokes = q - 1 - poly_count.astype(np.int64)
    return counts


def _type_counts(p: int, q: int, rings: int, stop_above: int | None = None) -> tuple[list[int], list[int]]:
    """Sites per ring and outward spokes of each ring, exact, via a recursion on vertex types.

    Returns ``(counts, spokes)``: ``counts[k]`` sites on ring k+1, ``spokes[k]`` outward
    spokes of ring k+1 (= spoke edges and new polygons of ring k+2). Python integers, so
    nothing overflows; O(rings) additions. With ``stop_above`` the count stops as soon as
    the running total exceeds it (the lists are then shorter than ``rings``): ring sizes
    grow exponentially, so a refusal costs a few dozen steps whatever ``rings`` is.

    Every new-ring vertex is one of two types (below); the explicit layer construction of
    the first rings (as far as it is cheap) guards the derivation.
    """
    if p == 3:
        # triangles, q >= 7: a vertex with s spokes gets s - 1 new polygons between its own
        # spokes and one shared with the next vertex; the last spoke end of a vertex is the
        # first of the next (merged). New vertices: s - 2 inner spoke ends (in 2 new
        # triangles, q - 3 spokes: type a) and one merged end (in 3, q - 4 spokes: type b).
        # Ring 1 has s = q - 2; all later vertices have s >= q - 4 >= 3.
        def spokes_of(a, b):
            return a * (q - 3) + b * (q - 4)

        def step(a, b):
            return a * (q - 5) + b * (q - 6), a + b

        first_spokes = p * (q - 2)
        a, b = p * (q - 4), p  # ring 2
    elif q >= 4:
        # every boundary vertex has >= 1 spoke; polygons have n_old in {1, 2}.
        # type a: vertex in 1 polygon (s = q-2 spokes), type b: in 2 polygons (s = q-3).
        # Each vertex with s spokes yields (s-1) polygons touching it alone (p-1 new-ring
        # entries each: 1 spoke end + p-2 middles) and one polygon spanning it and the next
        # vertex (p-3 entries: 1 spoke end + p-4 middles; for p = 4 just the spoke end).
        def spokes_of(a, b):
            return a * (q - 2) + b * (q - 3)

        def step(a, b):
            # spoke ends (type b): one per spoke; middles (type a): per polygon
            new_a = a * ((q - 3) * (p - 3) + (p - 4)) + b * ((q - 4) * (p - 3) + (p - 4))
            return new_a, spokes_of(a, b)

        first_spokes = p * (q - 2)
        a, b = step(p, 0)
    else:
        # q = 3, p >= 7: type a (1 polygon, 1 spoke), type b (2 polygons, no spoke);
        # b vertices are isolated, so a polygon spans 2 (a,a) or 3 (a,b,a) old vertices.
        # Polygons = number of a vertices; those spanning a b vertex: one per b vertex.
        def spokes_of(a, b):
            return a

        def step(a, b):
            return (a - b) * (p - 4) + b * (p - 5), a  # middles, one spoke end per polygon

        first_spokes = p
        a, b = step(p, 0)
    counts, spokes = [p], [first_spokes]
    total = p
    while len(counts) < rings and (stop_above is None or total <= stop_above):
        if len(counts) > 1:
            a, b = step(a, b)
        counts.append(a + b)
        spokes.append(spokes_of(a, b))
        total += a + b
    explicit = _ring_counts(p, q, min(len(counts), 6), _CALIBRATION_SPOKES)
    if counts[: len(explicit)] != explicit:  # pragma: no cover - guards the derivation
        raise AssertionError(f"ring-size recursion disagrees with the construction for {{{p},{q}}}")
    return counts, spokes


def _check_pq(p, q) -> tuple[int, int]:
    """A hyperbolic {p,q} small enough for the builder's 32-bit counters."""
    p, q = _validate.pq(p, q)
    for name, v in (("p", p), ("q", q)):
        if v > _MAX_SITES:
            raise ValueError(f"{name} must be at most {_MAX_SITES:,} (the lattice builder counts in "
                             f"32-bit integers), got {v:,}.")
    return p, q


def ring_sizes(p: int, q: int, rings: int) -> np.ndarray:
    r"""Number of sites on each ring 1..rings of the {p,q} lattice.

    Exact and O(rings): the vertices of a new ring are of two types whose counts obey a
    linear recursion (derived for each family p = 3, q = 3 and p, q >= 4, and cross-checked
    against the explicit layer construction of the first rings). For {7,3} the sizes are
    7, 28, 77, 203, ...

    Parameters
    ----------
    p, q : int
        Schläfli symbol, hyperbolic: :math:`(p-2)(q-2) > 4`, each at most 2**31 - 1.
    rings : int
        Number of rings :math:`\ell \ge 1` (ring 1 is the central p-gon).

    Returns
    -------
    numpy.ndarray of int64, shape (rings,)
        Entry k is the number of sites on ring k + 1.

    Raises
    ------
    ValueError
        For a non-hyperbolic or non-integer {p,q}, ``rings < 1``, or if the total exceeds
        2**63 - 1 sites (about 43 rings of {7,3}), which no int64 holds.

    See Also
    --------
    site_count, edge_count, site_count_float

    Examples
    --------
    >>> import hyperlattice as hl
    >>> hl.ring_sizes(7, 3, 4).tolist()
    [7, 28, 77, 203]
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    counts, _ = _type_counts(p, q, rings, stop_above=_INT64_MAX)
    if len(counts) < rings or sum(counts) > _INT64_MAX:
        raise ValueError(f"the {{{p},{q}}} lattice with {rings:,} rings has more than 2**63 sites, "
                         f"too many to count in 64-bit integers (at most {len(counts) - 1} rings fit).")
    return np.array(counts, dtype=np.int64)


def site_count(p: int, q: int, rings: int) -> int:
    r"""Total number of sites N of the ``rings``-ring {p,q} lattice, exact.

    Parameters
    ----------
    p, q : int
        Schläfli symbol, hyperbolic: :math:`(p-2)(q-2) > 4`.
    rings : int
        Number of rings :math:`\ell \ge 1`.

    Returns
    -------
    int
        The sum of :func:`ring_sizes`.

    Raises
    ------
    ValueError
        For invalid p, q or rings, or more than 2**63 - 1 sites (see :func:`ring_sizes`).

    See Also
    --------
    ring_sizes, edge_count, site_count_float

    Examples
    --------
    >>> import hyperlattice as hl
    >>> hl.site_count(7, 3, 3)
    112
    """
    return int(ring_sizes(p, q, rings).sum())


def site_count_float(p: int, q: int, rings: int) -> float:
    r"""N of the ``rings``-ring {p,q} lattice as a float, for rings beyond what int64 holds.

    The count is exact in Python integers and rounded once; what uses it is the disk radius of
    ``eq12`` for huge disks (:func:`hyperlattice.dictionary.disk_radius_for_rings`).

    Parameters
    ----------
    p, q : int
        Schläfli symbol, hyperbolic: :math:`(p-2)(q-2) > 4`.
    rings : int
        Number of rings :math:`\ell \ge 1`.

    Returns
    -------
    float
        The number of sites, correctly rounded.

    Raises
    ------
    ValueError
        For invalid p, q or rings, or beyond 1e308 sites (about 737 rings of {7,3}), where a
        float overflows.

    See Also
    --------
    site_count

    Examples
    --------
    >>> from hyperlattice.graph.lattice import site_count_float
    >>> site_count_float(7, 3, 3)
    112.0
    >>> f"{site_count_float(7, 3, 100):.4e}"
    '4.3916e+42'
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    limit = int(1e308)
    counts, _ = _type_counts(p, q, rings, stop_above=limit)
    total = sum(counts)
    if len(counts) < rings or total > limit:
        raise ValueError(f"the {{{p},{q}}} lattice with {rings:,} rings has more than 1e308 sites; "
                         "its disk radius is 1 to double precision.")
    return float(total)


def edge_count(p: int, q: int, rings: int) -> int:
    r"""Number of edges of the ``rings``-ring {p,q} lattice (= sites of its line graph), exact.

    Each ring adds its own cycle and one spoke edge per outward spoke of the previous ring.

    Parameters
    ----------
    p, q : int
        Schläfli symbol, hyperbolic: :math:`(p-2)(q-2) > 4`.
    rings : int
        Number of rings :math:`\ell \ge 1`.

    Returns
    -------
    int
        The number of edges (nearest-neighbour bonds).

    Raises
    ------
    ValueError
        For invalid p, q or rings, or more than 2**63 - 1 edges.

    See Also
    --------
    site_count, line_graph

    Examples
    --------
    >>> import hyperlattice as hl
    >>> hl.edge_count(7, 3, 3)
    140
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    counts, spokes = _type_counts(p, q, rings, stop_above=_INT64_MAX)
    n = sum(counts) + sum(spokes[: rings - 1])
    if len(counts) < rings or n > _INT64_MAX:
        raise ValueError(f"the {{{p},{q}}} lattice with {rings:,} rings has more than 2**63 edges, "
                         f"too many to count in 64-bit integers.")
    return n


def _refusal(what: str, n: int, exact: bool, limit: int, by_memory: bool, bytes_per_site: float) -> str:
    """The one-sentence message for a lattice that will not fit."""
    need = n * bytes_per_site / 1024**3
    if exact:
        size = f"has {n:,} sites and needs about {need:.1f} GB"
    else:  # the count stopped at the limit
        size = f"has more than {n:,} sites and needs more than {need:.1f} GB"
    if limit >= _MAX_SITES:
        why = "the 32-bit site ids allow"
    elif by_memory:
        why = "this process may allocate (machine, ulimit -v and cgroup limits)"
    else:
        why = "max_sites allows"
    return f"the {what} {size}, more than {why} (limit {max(limit, 0):,} sites)."


def _check_size(p: int, q: int, rings: int, max_sites) -> int:
    """Exact site count, or ValueError as soon as the count passes the limit (before any allocation)."""
    if max_sites is None:
        limit = min(_available_memory() // _BYTES_PER_SITE, _MAX_SITES)
    else:
        limit = min(_validate.positive_int("max_sites", max_sites), _MAX_SITES)
    counts, _ = _type_counts(p, q, rings, stop_above=limit)
    n = sum(counts)
    if len(counts) < rings or n > limit:
        raise ValueError(_refusal(f"{{{p},{q}}} lattice with {rings:,} rings", n, len(counts) == rings,
                                  limit, max_sites is None, _BYTES_PER_SITE))
    return n


def _line_graph_bytes_per_site(q: int) -> float:
    """Peak bytes per line-graph site: its own arrays plus its q - 1 edges per site (interior)."""
    return _BYTES_PER_LINE_SITE + _BYTES_PER_LINE_EDGE * (q - 1)


def _check_line_graph_size(p: int, q: int, rings: int, n_edges: int, max_sites, resident: int = 0) -> None:
    """Refuse a line graph with ``n_edges`` sites that will not fit (``resident``: bytes still to be held)."""
    per_site = _line_graph_bytes_per_site(q)
    if max_sites is None:
        limit = min(int((_available_memory() - resident) // per_site), _MAX_SITES)
    else:
        limit = min(_validate.positive_int("max_sites", max_sites), _MAX_SITES)
    if n_edges > limit:
        raise ValueError(_refusal(f"line graph of the {{{p},{q}}} lattice with {rings:,} rings", n_edges, True,
                                  limit, max_sites is None, per_site))


def _check_line_graph_fits(p, q, rings, *, max_sites=None) -> int:
    """Refuse (``ValueError``) a line graph that will not fit, before even its parent is built.

    Counts the parent's sites and edges exactly (and cheaply) and compares the memory of the
    parent lattice plus its line graph with what is available. Returns the line-graph size.
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    n_sites = _check_size(p, q, rings, None)
    n_edges = edge_count(p, q, rings)
    # the parent stays resident while its line graph is built: z, ring, rotation and edges
    resident = n_sites * (16 + 2 + 4) + n_edges * 8
    _check_line_graph_size(p, q, rings, n_edges, max_sites, resident=resident)
    return n_edges


# ----------------------------------------------------------------------------
# the builder
# ----------------------------------------------------------------------------

def _grow_ring(z: np.ndarray, ring: np.ndarray, layer: _Layer, base: int, level: int, p: int, q: int,
               centre_fraction: float):
    """Add ring ``level`` around the cluster whose boundary is ``layer``: fills ``z`` and
    ``ring`` from position ``base`` and returns (n_new, spoke_edges, cycle_edges, next layer).

    A function of its own so that the large per-ring temporaries are freed on return."""
    theta = 2.0 * math.pi / q
    ids, spokes = layer.ids, layer.spokes
    owner, k, n_new, spoke_slot, mid_poly, mid_t, mid_slot, poly_count = _layer_topology(spokes, p, q)
    zb = z[ids]
    # The construction order of every ring is exactly p-periodic (ring 1 starts at angle
    # 0 and the layer rule is rotation equivariant), so coordinates are computed for the
    # first 1/p of the new ring only and the rest are rotated copies: p times less
    # Moebius arithmetic, and the p-fold symmetry holds to rounding.
    n_spokes = owner.shape[0]
    n_sub = n_spokes // p             # spokes (= polygons) of one angular sector
    m_sub = n_new // p                # new-ring slots of one angular sector
    js = np.arange(n_sub + 1)         # one extra spoke: the second end of the last polygon
    own = owner[js]
    # spoke ends: boundary predecessor rotated ccw about the owner by k * 2pi/q
    ends = geometry._rotate_about(zb[own - 1], zb[own], k[js] * theta)
    sub_z = np.empty(m_sub, dtype=np.complex128)
    first = spoke_slot[:n_sub] < m_sub  # p = 3 may merge the sector's last end into the next sector
    sub_z[spoke_slot[:n_sub][first]] = ends[:n_sub][first]
    # middles: polygon j is traversed clockwise  w_j, a, ..., b, w_{j+1}, m_1, ..., m_r.
    # Its centre lies at the circumradius from w_{j+1}, bisecting the interior angle
    # between the directions to b and to m_1; the middles are w_{j+1} rotated about the
    # centre by -2*pi*t/p. One rotation per vertex keeps the error from compounding
    # along the polygon (a vertex-to-vertex walk amplifies it Fibonacci-like in p).
    sel = mid_poly < n_sub
    if np.any(sel):
        mp, mt = mid_poly[sel], mid_t[sel]
        second_end = ends[mp + 1]
        b_pt = zb[owner[mp + 1]]              # boundary vertex b, owner of the next spoke
        toward_b = geometry._geodesic_point(second_end, b_pt, centre_fraction)
        centre = geometry._rotate_about(toward_b, second_end, 0.5 * theta)
        sub_z[mid_slot[sel]] = geometry._rotate_about(second_end, centre, -2.0 * math.pi * mt / p)
    phases = np.exp(2j * math.pi * np.arange(p) / p)
    z[base:base + n_new].reshape(p, m_sub)[:] = phases[:, None] * sub_z[None, :]
    ring[base:base + n_new] = level
    new_ids = np.arange(base, base + n_new, dtype=np.int32)
    spoke_edges = np.column_stack([ids[owner], new_ids[spoke_slot]])
    cycle_edges = np.column_stack([new_ids, np.roll(new_ids, -1)])
    return n_new, spoke_edges, cycle_edges, _Layer(ids=new_ids, spokes=q - poly_count - 1)


def ring_lattice(p: int = 7, q: int = 3, rings: int = 3, *, max_sites: int | None = None) -> Lattice:
    r"""Build the finite {p,q} lattice of ``rings`` quasi-concentric rings.

    Parameters
    ----------
    p, q : int
        Schläfli symbol, hyperbolic: :math:`(p-2)(q-2) > 4`.
    rings : int
        Number of rings :math:`\ell \ge 1` (ring 1 is the central p-gon).
    max_sites : int, optional
        Refuse (``ValueError``) lattices with more sites; default: what fits in memory. The
        size is counted exactly but stops at the limit, so a huge request is refused at once.

    Returns
    -------
    Lattice
        Sites ordered ring by ring, each ring counterclockwise starting from the site with
        the smallest polar angle :math:`\ge 0`; site 0 is :math:`z = r_0` on the positive
        real axis. Every edge has hyperbolic length :math:`d_0`.

    Raises
    ------
    ValueError
        For a non-hyperbolic or non-integer {p,q}, p or q above 2**31 - 1, ``rings < 1``, or
        a lattice that will not fit (more than ``max_sites`` or 2**31 - 1 sites, or more
        memory than is available at about 400 bytes per site).

    Examples
    --------
    >>> from hyperlattice import ring_lattice
    >>> lat = ring_lattice(7, 3, 3)
    >>> lat.sites, lat.sites_per_ring.tolist()
    (112, [7, 28, 77])
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    n_total = _check_size(p, q, rings, max_sites)

    d0 = geometry.d0(p, q)
    circumradius = math.atanh(geometry.r0(p, q))  # hyperbolic distance centre-vertex
    z = np.empty(n_total, dtype=np.complex128)
    ring = np.empty(n_total, dtype=np.int16)
    r0 = geometry.r0(p, q)
    z[:p] = r0 * np.exp(2j * math.pi * np.arange(p) / p)
    ring[:p] = 1
    edge_blocks = [np.column_stack([np.arange(p, dtype=np.int32), np.roll(np.arange(p, dtype=np.int32), -1)])]
    # int32 ids/edges: N < 2**31 is guaranteed by the memory check, and it halves the peak
    layer = _Layer(ids=np.arange(p, dtype=np.int32), spokes=np.full(p, q - 2, dtype=np.int64))
    ring_starts = [0, p]
    base = p

    for level in range(2, rings + 1):
        n_new, spoke_edges, cycle_edges, layer = _grow_ring(z, ring, layer, base, level, p, q, circumradius / d0)
        edge_blocks.extend([spoke_edges, cycle_edges])
        base += n_new
        ring_starts.append(base)

    edges = np.concatenate(edge_blocks)
    del edge_blocks
    # renumber: roll each ring to start at the smallest polar angle >= 0
    perm = np.empty(n_total, dtype=np.int32)  # perm[old] = new
    for a, b in zip(ring_starts[:-1], ring_starts[1:]):
        ang = np.angle(z[a:b])
        # sites exactly on the positive real axis may come out as -1e-17: count them as 0
        ang = np.where(ang < -1e-12, ang + 2 * math.pi, np.maximum(ang, 0.0))
        start = int(np.argmin(ang))
        perm[a:b] = a + np.mod(np.arange(b - a) - start, b - a)
        z[a:b] = np.roll(z[a:b], -start)  # in place, one ring at a time
    np.take(perm, edges, out=edges)  # renumber in place
    first = edges[:, 0].copy()  # i < j via min/max (a row-wise sort of pairs is ~10x slower)
    np.minimum(first, edges[:, 1], out=edges[:, 0])
    np.maximum(first, edges[:, 1], out=edges[:, 1])
    rotation = _ring_rotation(ring_starts, p)
    return Lattice(p=p, q=q, rings=rings, z=z, ring=ring, edges=edges, rotation=rotation)


def _ring_rotation(ring_starts, p: int) -> np.ndarray:
    """Site permutation of the rotation by 2*pi/p: a cyclic shift by n_ring/p in each ring."""
    n = ring_starts[-1]
    rot = np.empty(n, dtype=np.int32)
    for a, b in zip(ring_starts[:-1], ring_starts[1:]):
        m = b - a
        rot[a:b] = a + np.mod(np.arange(m, dtype=np.int32) + m // p, m)
    return rot


# ----------------------------------------------------------------------------
# line graph
# ----------------------------------------------------------------------------

def line_graph(lattice: Lattice, *, max_sites: int | None = None) -> Lattice:
    """The line graph of a lattice: the layout of circuit-QED resonator arrays.

    Each edge of ``lattice`` becomes a site placed at the hyperbolic midpoint of the edge;
    two such sites are neighbours when their edges share a site. For q = 3 the adjacency
    is :math:`B^T B - 2I` with :math:`B` the site-edge incidence matrix.

    Line-graph sites are ordered by ring (the larger ring index of the two endpoints),
    then counterclockwise: by the position of the outer endpoint within its ring, spokes
    (edges from the previous ring) before ring edges, and ring edges keyed by their first
    endpoint in counterclockwise order. ``rotation`` is the induced permutation.

    Parameters
    ----------
    lattice : Lattice
        A site lattice (``kind == "sites"``), e.g. from :func:`ring_lattice`.
    max_sites : int, optional
        Refuse (``ValueError``) line graphs with more sites (= parent edges); default: what
        fits in the memory still available. Checked before anything is allocated.

    Returns
    -------
    Lattice
        ``kind == "line_graph"``, with ``parent_edges[k]`` the parent edge (a pair of 0-based
        site indices of ``lattice``) of site k.

    Raises
    ------
    ValueError
        If ``lattice`` is not a site lattice (e.g. already a line graph), or the line graph
        has more sites than ``max_sites`` or than fit in the available memory.

    See Also
    --------
    ring_lattice, edge_count, incidence

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> lg = hl.line_graph(lat)
    >>> lg.kind, lg.sites, len(lat.edges)
    ('line_graph', 42, 42)
    >>> lg.parent_edges[0].tolist()
    [0, 1]
    """
    _validate.lattice(lattice)
    if lattice.kind != "sites":
        raise ValueError("line_graph() takes a site lattice, not a line graph.")
    _check_line_graph_size(lattice.p, lattice.q, lattice.rings, int(lattice.edges.shape[0]), max_sites)
    e = lattice.edges.astype(np.int64)
    i, j = e[:, 0], e[:, 1]
    ri, rj = lattice.ring[i], lattice.ring[j]
    offsets = lattice.ring_offsets
    grp = np.maximum(ri, rj).astype(np.int64)
    # position of each endpoint inside its own ring
    pos = np.arange(lattice.sites) - offsets[lattice.ring.astype(np.int64) - 1]
    nring = lattice.sites_per_ring.astype(np.int64)[lattice.ring.astype(np.int64) - 1]
    is_spoke = ri != rj
    # within-ring edge (a, b): the ccw-earlier endpoint is the one whose successor is the other
    same_first = np.where((pos[j] - pos[i]) % nring[i] == 1, i, j)
    key_site = np.where(is_spoke, np.where(ri > rj, i, j), same_first)
    other = np.where(is_spoke, np.where(ri > rj, j, i), 0)
    order = np.lexsort((other, (~is_spoke).astype(np.int64), pos[key_site], grp))
    e_sorted = e[order]
    z_mid = geometry._midpoint(lattice.z[e_sorted[:, 0]], lattice.z[e_sorted[:, 1]])
    ring_lg = grp[order].astype(np.int16)
    n_e = e_sorted.shape[0]
    # incidence: line-graph sites sharing an endpoint
    src = np.concatenate([e_sorted[:, 0], e_sorted[:, 1]])
    eid = np.concatenate([np.arange(n_e), np.arange(n_e)])
    by_site = np.argsort(src, kind="stable")
    src_s, eid_s = src[by_site], eid[by_site]
    starts = np.searchsorted(src_s, np.arange(lattice.sites))
    ends = np.searchsorted(src_s, np.arange(lattice.sites), side="right")
    deg = ends - starts
    pairs = []
    for d in np.unique(deg):
        if d < 2:
            continue
        sel = np.nonzero(deg == d)[0]
        block = eid_s[starts[sel][:, None] + np.arange(d)[None, :]]
        for a in range(d):
            for b in range(a + 1, d):
                pairs.append(np.column_stack([block[:, a], block[:, b]]))
    lg_edges = np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)
    lg_edges = np.sort(lg_edges, axis=1)
    lg_edges = lg_edges[np.lexsort((lg_edges[:, 1], lg_edges[:, 0]))].astype(np.int32)
    # rotation: map both endpoints, find the edge id of the image
    # edge keys i*N + j reach N**2: int64 throughout (the int32 rotation made them wrap
    # around from 46,341 sites on, i.e. {7,3} with 10 rings, giving a wrong permutation)
    n_sites = np.int64(lattice.sites)
    key = e_sorted[:, 0] * n_sites + e_sorted[:, 1]
    rot = lattice.rotation.astype(np.int64)
    a, b = rot[e_sorted[:, 0]], rot[e_sorted[:, 1]]
    img = np.minimum(a, b) * n_sites + np.maximum(a, b)
    srt = np.argsort(key)
    found = np.minimum(np.searchsorted(key[srt], img), n_e - 1)
    if not np.array_equal(key[srt][found], img):  # pragma: no cover - the rotation maps edges to edges
        raise AssertionError("the rotation of the parent lattice does not map its edges onto edges")
    rotation = srt[found]
    return Lattice(p=lattice.p, q=lattice.q, rings=lattice.rings, z=z_mid, ring=ring_lg,
                   edges=lg_edges, rotation=rotation, kind="line_graph", parent_edges=e_sorted.astype(np.int32))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
