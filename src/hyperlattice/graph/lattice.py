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

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _validate
from .. import geometry
__all__ = [
    "Lattice",
    "ring_lattice",
    "line_graph",
    "ring_sizes",
    "site_count",
    "load_lattice",
]

#: Bytes of peak memory per site while building a lattice and its adjacency (measured,
#: with margin): used to refuse sizes that cannot fit before allocating anything.
_BYTES_PER_SITE = 400


def _available_memory() -> int:
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8 * 1024**3


# ----------------------------------------------------------------------------
# the immutable result
# ----------------------------------------------------------------------------

def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Lattice:
    r"""A finite hyperbolic lattice: an immutable bundle of numpy arrays.

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
    """

    p: int
    q: int
    rings: int
    z: np.ndarray
    ring: np.ndarray
    edges: np.ndarray
    rotation: np.ndarray
    kind: str = "sites"
    parent_edges: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        for name in ("z", "ring", "edges", "rotation", "parent_edges"):
            a = getattr(self, name)
            if a is not None:
                object.__setattr__(self, name, _frozen(a))

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
        """Effective disk radius :math:`L = \\sqrt{N/(N+c_{pq})}` (Eq. eq12, generalised)."""
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

    # -- export --------------------------------------------------------------
    def to_networkx(self):
        """The lattice as a :class:`networkx.Graph` with node attributes ``z`` and ``ring``."""
        try:
            import networkx as nx
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError("to_networkx() needs networkx: pip install 'hyperlattice[networkx]'") from exc
        g = nx.Graph(p=self.p, q=self.q, rings=self.rings, kind=self.kind)
        g.add_nodes_from(
            (i, {"z": complex(zi), "ring": int(ri)}) for i, (zi, ri) in enumerate(zip(self.z, self.ring))
        )
        g.add_edges_from(map(tuple, self.edges.tolist()))
        return g

    def save(self, path) -> Path:
        """Write ``.dat`` (the paper's coordinates.dat: Re z and Im z, one site per line)
        or ``.npz`` (z, ring, edges, p, q, rings, kind), chosen by the file extension."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".dat":
            np.savetxt(path, np.column_stack([self.z.real, self.z.imag]), fmt="%.17g")
        elif suffix == ".npz":
            extra = {} if self.parent_edges is None else {"parent_edges": self.parent_edges}
            np.savez_compressed(path, z=self.z, ring=self.ring, edges=self.edges, p=self.p, q=self.q,
                                rings=self.rings, kind=self.kind, rotation=self.rotation, **extra)
        else:
            raise ValueError(f"unknown output format {path.suffix!r}: use .dat or .npz.")
        return path


def _csr_sorted(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Group ``cols`` by ``rows`` (a counting sort, O(N + E)) with sorted columns per row."""
    import scipy.sparse as sp

    m = sp.csr_matrix((np.ones(rows.shape[0], dtype=np.int8), (rows, cols)), shape=(n, n))
    m.sort_indices()  # rows hold at most a few entries: cheap, unlike a global comparison sort
    return m.indptr.astype(np.int64), m.indices.astype(np.int32)


def load_lattice(path) -> Lattice:
    """Read a lattice written by :meth:`Lattice.save` in ``.npz`` format."""
    with np.load(path, allow_pickle=False) as f:
        parent = f["parent_edges"] if "parent_edges" in f.files else None
        return Lattice(p=int(f["p"]), q=int(f["q"]), rings=int(f["rings"]), z=f["z"], ring=f["ring"],
                       edges=f["edges"], rotation=f["rotation"], kind=str(f["kind"]), parent_edges=parent)


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
    poly_count = np.bincount(spoke_slot, minlength=n_new).astype(np.int8)
    poly_count += np.bincount(nxt_slot[distinct], minlength=n_new).astype(np.int8)
    poly_count += np.bincount(mid_slot, minlength=n_new).astype(np.int8)
    return owner, k, n_new, spoke_slot, mid_poly, mid_t, mid_slot, poly_count


def _ring_counts(p: int, q: int, rings: int, stop_above: int | None = None) -> list[int]:
    """Exact sites per ring from the combinatorics alone (no coordinates)."""
    counts = [p]
    spokes = np.full(p, q - 2, dtype=np.int64)
    total = p
    for _ in range(rings - 1):
        topology = _layer_topology(spokes, p, q)
        n_new, poly_count = topology[2], topology[7]
        counts.append(n_new)
        total += n_new
        spokes = q - poly_count - 1
        if stop_above is not None and total > stop_above:
            break
    return counts


def ring_sizes(p: int, q: int, rings: int) -> np.ndarray:
    """Number of sites on each ring 1..rings (e.g. 7, 28, 77, 203, ... for {7,3}).

    Exact and O(rings) for p >= 4: the new ring's vertices are of two types (in one or in
    two new polygons) whose counts obey a linear recursion, validated against the explicit
    layer construction for the first six rings. For p = 3 (merging spoke ends) the rings are
    counted explicitly, extrapolated by the growth ratio beyond 1e9 sites (a size only ever
    used to refuse the request).
    """
    p, q = _validate.pq(p, q)
    rings = _check_rings(rings)
    return np.array(_type_recursion(p, q, rings), dtype=np.int64)


def _type_recursion(p: int, q: int, rings: int) -> list[int]:
    """Sites per ring via a recursion on vertex types (exact, O(rings)).

    A new-ring vertex lies in 1 or 2 new polygons (spoke ends in 2, middles in 1) except
    for p = 3, where spoke ends merge; the explicit construction handles the general case
    and is used whenever the recursion's assumptions fail.
    """
    # Explicit construction for the first rings calibrates/validates the linear model.
    explicit = _ring_counts(p, q, min(rings, 6))
    if rings <= 6:
        return explicit
    if p == 3:
        # spoke ends merge for triangles: count explicitly while that is cheap, then
        # extrapolate with the (converged) growth ratio; only used to refuse huge sizes.
        counts = _ring_counts(p, q, rings, stop_above=10**9)
        while len(counts) < rings:
            counts.append(int(counts[-1] * counts[-1] / counts[-2]))
        return counts
    if q >= 4:
        # every boundary vertex has >= 1 spoke; polygons have n_old in {1, 2}.
        # type a: vertex in 1 polygon (s = q-2 spokes), type b: in 2 polygons (s = q-3).
        # Each vertex with s spokes yields (s-1) polygons touching it alone (p-1 new-ring
        # entries each: 1 spoke end + p-2 middles) and one polygon spanning it and the next
        # vertex (p-3 entries: 1 spoke end + p-4 middles ... for p = 4: just the spoke end).
        def step(a, b):
            new_a = new_b = 0
            for count, s in ((a, q - 2), (b, q - 3)):
                # spoke ends (type b) : one per spoke; middles (type a): per polygon
                new_b += count * s
                new_a += count * ((s - 1) * (p - 3) + (p - 4))
            return new_a, new_b
    else:
        # q = 3, p >= 7: type a (1 polygon, 1 spoke), type b (2 polygons, no spoke);
        # b vertices are isolated, so a polygon spans 2 (a,a) or 3 (a,b,a) old vertices.
        # Polygons = number of a vertices; those spanning a b vertex: one per b vertex.
        def step(a, b):
            n_poly = a
            n3 = b
            n2 = n_poly - n3
            new_b = n_poly                       # one spoke end per polygon
            new_a = n2 * (p - 4) + n3 * (p - 5)  # middles
            return new_a, new_b
    # initial types after ring 1: all p vertices in one polygon
    a, b = p, 0
    counts = [p]
    for _ in range(rings - 1):
        a, b = step(a, b)
        counts.append(a + b)
    if counts[: len(explicit)] != explicit:  # pragma: no cover - guards the derivation
        return _ring_counts(p, q, rings)
    return counts


def site_count(p: int, q: int, rings: int) -> int:
    """Total number of sites N of the ``rings``-ring {p,q} lattice (exact)."""
    return int(ring_sizes(p, q, rings).sum())


def _check_rings(rings) -> int:
    if isinstance(rings, bool) or not isinstance(rings, (int, np.integer)):
        if isinstance(rings, float) and rings.is_integer():
            rings = int(rings)
        else:
            raise ValueError(f"rings must be a positive integer, got {rings!r}.")
    rings = int(rings)
    if rings < 1:
        raise ValueError(f"rings must be at least 1, got {rings}.")
    return rings


def _check_size(p: int, q: int, rings: int, max_sites: int | None) -> int:
    n = site_count(p, q, rings)
    if max_sites is None:
        max_sites = _available_memory() // _BYTES_PER_SITE
    if n > max_sites:
        need = n * _BYTES_PER_SITE / 1024**3
        raise ValueError(
            f"the {{{p},{q}}} lattice with {rings} rings has {n:,} sites and needs about "
            f"{need:.1f} GB, more than this machine can hold (limit {max_sites:,} sites)."
        )
    return n


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
    ends = geometry.rotate_about(zb[own - 1], zb[own], k[js] * theta)
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
        toward_b = geometry.geodesic_point(second_end, b_pt, centre_fraction)
        centre = geometry.rotate_about(toward_b, second_end, 0.5 * theta)
        sub_z[mid_slot[sel]] = geometry.rotate_about(second_end, centre, -2.0 * math.pi * mt / p)
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
        Refuse (``ValueError``) lattices with more sites; default: what fits in memory.

    Returns
    -------
    Lattice
        Sites ordered ring by ring, each ring counterclockwise starting from the site with
        the smallest polar angle :math:`\ge 0`; site 0 is :math:`z = r_0` on the positive
        real axis. Every edge has hyperbolic length :math:`d_0`.

    Examples
    --------
    >>> lat = ring_lattice(7, 3, 3)
    >>> lat.sites, lat.sites_per_ring.tolist()
    (112, [7, 28, 77])
    """
    p, q = _validate.pq(p, q)
    rings = _check_rings(rings)
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

def line_graph(lattice: Lattice) -> Lattice:
    r"""The line graph of a lattice: the layout of circuit-QED resonator arrays.

    Each edge of ``lattice`` becomes a site placed at the hyperbolic midpoint of the edge;
    two such sites are neighbours when their edges share a site. For q = 3 the adjacency
    is :math:`B^T B - 2I` with :math:`B` the site-edge incidence matrix.

    Line-graph sites are ordered by ring (the larger ring index of the two endpoints),
    then counterclockwise: by the position of the outer endpoint within its ring, spokes
    (edges from the previous ring) before ring edges, and ring edges keyed by their first
    endpoint in counterclockwise order. ``rotation`` is the induced permutation.
    """
    if lattice.kind != "sites":
        raise ValueError("line_graph() takes a site lattice, not a line graph.")
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
    z_mid = geometry.midpoint(lattice.z[e_sorted[:, 0]], lattice.z[e_sorted[:, 1]])
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
    key = e_sorted[:, 0] * lattice.sites + e_sorted[:, 1]
    rot = lattice.rotation
    a, b = rot[e_sorted[:, 0]], rot[e_sorted[:, 1]]
    img = np.minimum(a, b) * lattice.sites + np.maximum(a, b)
    srt = np.argsort(key)
    rotation = srt[np.searchsorted(key[srt], img)]
    return Lattice(p=lattice.p, q=lattice.q, rings=lattice.rings, z=z_mid, ring=ring_lg,
                   edges=lg_edges, rotation=rotation, kind="line_graph", parent_edges=e_sorted.astype(np.int32))
