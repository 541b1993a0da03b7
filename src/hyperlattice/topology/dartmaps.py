r"""Maps given by a group presentation (loops and multiple edges allowed) and the {8,8} Dirac model.

The package's clusters (:class:`~hyperlattice.graph.clusters.Cluster`) are simple graphs with a
neighbour table; the {8,8} lattice with one site per unit cell is not one: its unit cell is a
single octagon whose opposite sides are glued (genus 2), one vertex where all eight corners meet,
and four edges, each a loop. Its translation group is the surface group
:math:`\Gamma = \langle \gamma_1,\dots,\gamma_4 \mid \ldots\rangle`, whose Abelianisation is
:math:`\mathbb Z^4`: the Abelian Bloch Hamiltonian of a one-site model has four momenta, one per
generator, and a hop along :math:`\gamma_j` carries :math:`e^{ik_j}`. This module builds such maps
from the dart permutations of a finite quotient :math:`G = \Delta(2, q, p)/N`
(:func:`hyperlattice.graph.groups.coset_table`, the regular representation; darts are the
elements of G, ``X`` the reverse dart, ``Y`` the next dart counterclockwise at the same vertex)
without a neighbour table, so that loops and multiple edges are kept.

Windings (a basis of :math:`H^1(\Sigma; \mathbb Z)`) by the tree–cotree decomposition (Eppstein,
SODA 2003, "Dynamic generators of topologically embedded graphs"): a spanning tree T of the
vertices, a spanning tree of the faces through the edges not in T, and the 2g edges left over;
each left-over edge gets a unit winding, tree edges zero, and the dual-tree edges the value that
makes every face's sum vanish (peeled from the leaves). The left-over edges' fundamental cycles
form a basis of :math:`H_1`, dual to these cocycles, so the basis is unimodular.

The Dirac model (the four-dimensional quantum Hall insulator of Qi, Hughes and Zhang, PRB 78,
195424 (2008), eq. 39, as put on the {8,8} lattice and measured in electric circuits by Zhang,
Di, Zheng, Sun and Zhang, Nat. Commun. 14, 1083 (2023), "Hyperbolic band topology with non-trivial
second Chern numbers"; the circuit realisation of Abelian momenta on {8,8}: Chen et al., Nat.
Commun. 14, 622 (2023)): four orbitals per site, on-site
:math:`m\Gamma_5`, and the hop along generator j (the pair of opposite octagon sides the edge
crosses) :math:`\tfrac12(\Gamma_5 - i\Gamma_j)`. Which pair an edge crosses is a homomorphism
:math:`s: G \to \mathbb Z_8` with :math:`s(x) = 4`, :math:`s(y) = 1` (the dart's slot at the one
vertex of the one-site map); a map covers the one-site map exactly when s exists (checked), and
dart d then carries :math:`\Gamma_{s(d) \bmod 4}`, forward when :math:`s(d) < 4`. On the one-site
map the Abelian Bloch Hamiltonian is
:math:`H(k) = \sum_j \sin k_j\Gamma_j + (m + \sum_j\cos k_j)\Gamma_5`, the lattice Dirac model of
:func:`~hyperlattice.topology.closed.dirac4_torus` on the 4-torus of the surface's momenta.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..results import Result
from .models import ModelTerms

__all__ = ["DartMap", "dart_map", "named_dart_map", "dirac4_terms", "DART_MAPS"]

#: name -> (p, q, extra relators, description): {8,8} maps that cover the one-site map
DART_MAPS: dict[str, tuple] = {
    "one-site": (8, 8, ("x Y^4",), "the {8,8} map with one site (one octagon, opposite sides glued, genus 2): "
                 "G = Z8, x = y^4"),
    "two-site": (8, 8, ("x y X Y",), "a two-sheeted cover of the one-site {8,8} map (genus 3): G = Z8 x Z2, "
                 "x = (4, 1), y = (1, 0)"),
}


@dataclass(frozen=True, eq=False, kw_only=True)
class DartMap(Result):
    r"""A {p,q} map on a closed orientable surface as dart permutations, with windings.

    Attributes
    ----------
    name : str
        The map.
    p, q : int
        Faces are p-gons, q darts at every vertex.
    genus : int
        From :math:`V - E + F = 2 - 2g`.
    reverse : ndarray of int64, shape (D,)
        The reverse of each dart (the permutation x).
    rotate : ndarray of int64, shape (D,)
        The next dart counterclockwise at the same vertex (the permutation y).
    vertex : ndarray of int64, shape (D,)
        The vertex each dart leaves.
    windings : ndarray of int64, shape (D, 2g)
        Each dart's winding (reverse darts carry minus it); the face sums vanish.

    Examples
    --------
    >>> from hyperlattice.topology.dartmaps import named_dart_map
    >>> m = named_dart_map("one-site")
    >>> m.sites, m.genus, m.windings.shape
    (1, 2, (8, 4))
    """

    NOT_TABULAR = "a map as permutations of darts"

    name: str
    p: int
    q: int
    genus: int
    reverse: np.ndarray
    rotate: np.ndarray
    vertex: np.ndarray
    windings: np.ndarray

    @property
    def sites(self) -> int:
        """Number of vertices."""
        return int(self.vertex.max()) + 1

    def summary(self) -> dict:
        """Sizes and genus."""
        return {"name": self.name, "p": self.p, "q": self.q, "sites": self.sites, "genus": self.genus,
                "darts": int(len(self.reverse))}


def _orbits(perm: np.ndarray) -> np.ndarray:
    """Label of the cycle of ``perm`` each element lies on (cycles numbered by first element)."""
    lab = np.full(len(perm), -1, dtype=np.int64)
    k = 0
    for s in range(len(perm)):
        if lab[s] >= 0:
            continue
        d = s
        while lab[d] < 0:
            lab[d] = k
            d = perm[d]
        k += 1
    return lab


def _windings(X: np.ndarray, Y: np.ndarray, vertex: np.ndarray, g2: int) -> np.ndarray:
    """Dart windings by the tree-cotree decomposition (module docstring)."""
    D = len(X)
    face_perm = Y[X]                                  # d -> d x y: along the face
    face = _orbits(face_perm)
    nv, nf = int(vertex.max()) + 1, int(face.max()) + 1
    fwd = np.arange(D) < X                            # one dart per edge represents it
    # spanning tree of the vertices (breadth-first over darts)
    seen_v = np.zeros(nv, dtype=bool)
    tree = np.zeros(D, dtype=bool)
    out_darts = [np.flatnonzero(vertex == v) for v in range(nv)]
    seen_v[0] = True
    queue = [0]
    while queue:
        v = queue.pop(0)
        for d in out_darts[v]:
            u = vertex[X[d]]
            if not seen_v[u]:
                seen_v[u] = True
                tree[d] = tree[X[d]] = True
                queue.append(u)
    # spanning tree of the faces through the edges not in T; dart d borders face[d], its reverse face[X[d]]
    face_darts = [np.flatnonzero(face == f) for f in range(nf)]
    seen_f = np.zeros(nf, dtype=bool)
    cotree = np.zeros(D, dtype=bool)
    parent_dart = np.full(nf, -1, dtype=np.int64)     # the dart of face f whose edge joins f to its parent
    order = [0]
    seen_f[0] = True
    i = 0
    while i < len(order):
        f = order[i]
        i += 1
        for d in face_darts[f]:
            if tree[d]:
                continue
            h = face[X[d]]
            if not seen_f[h]:
                seen_f[h] = True
                cotree[d] = cotree[X[d]] = True
                parent_dart[h] = X[d]
                order.append(h)
    left = np.flatnonzero(~tree & ~cotree & fwd)
    if len(left) != g2:
        raise ValueError(f"the tree-cotree decomposition left {len(left)} edges, expected 2g = {g2}: "
                         "the permutations do not form a closed orientable map.")
    w = np.zeros((D, g2), dtype=np.int64)
    w[left, np.arange(g2)] = 1
    w[X[left], np.arange(g2)] = -1
    for f in reversed(order[1:]):                     # leaves first: the parent edge is the one unknown
        d = parent_dart[f]
        rest = face_darts[f][face_darts[f] != d]
        w[d] = -w[rest].sum(axis=0)
        w[X[d]] = -w[d]
    if np.any(np.array([w[face_darts[f]].sum(axis=0) for f in range(nf)])):
        raise ValueError("the windings do not close around every face (not a closed orientable map).")
    return w


def dart_map(p: int, q: int, relators, *, name: str = "custom", max_cosets: int = 100_000) -> DartMap:
    r"""The {p,q} map of :math:`\Delta(2,q,p)` with extra relators, kept as darts (loops allowed).

    Parameters
    ----------
    p, q : int
        Schläfli symbol.
    relators : sequence of str
        Extra relators in x, y (``"x Y^4"``; capitals are inverses).
    name : str, optional
        Label (default ``"custom"``).
    max_cosets : int, optional
        Limit of the Todd–Coxeter enumeration (default 100,000).

    Returns
    -------
    DartMap

    Raises
    ------
    ValueError
        Bad input, an enumeration above ``max_cosets``, a quotient that is not torsion-free
        (orders of x, y, xy not 2, q, p on every dart) or of genus below 2.

    Examples
    --------
    >>> from hyperlattice.topology.dartmaps import dart_map
    >>> dart_map(8, 8, ["x y X Y"]).summary()
    {'name': 'custom', 'p': 8, 'q': 8, 'sites': 2, 'genus': 3, 'darts': 16}
    """
    from ..errors import HyperlatticeError
    from ..graph import groups

    p, q = _validate.pq(p, q)
    relators = groups._sequence("relators", relators)
    words = [groups._checked_word("relator", w, 4) for w in relators]
    max_cosets = _validate.integer("max_cosets", max_cosets, minimum=1, maximum=10_000_000)
    try:
        table = groups.coset_table(2, groups.triangle_relators(p, q) + words, max_cosets=max_cosets)
    except HyperlatticeError as exc:
        raise ValueError(str(exc)) from None
    X = table[:, 0].astype(np.int64)
    Y = table[:, 2].astype(np.int64)
    D = len(X)
    ar = np.arange(D)

    def power(perm, n):
        out = ar.copy()
        for _ in range(n):
            out = perm[out]
        return out

    XY = Y[X]
    checks = ((X, 2, "x"), (Y, q, "y"), (XY, p, "xy"))
    for perm, order, label in checks:
        if np.any(power(perm, order) != ar) or any(np.any(power(perm, k) == ar) for k in range(1, order)
                                                   if order % k == 0):
            raise ValueError(f"the quotient is not torsion-free: {label} does not have order {order} on every dart.")
    chi2pq = D * (2 * p + 2 * q - p * q)          # 2pq (V - E + F)
    genus = 1 - chi2pq // (4 * p * q)
    if genus < 2:
        raise ValueError(f"the quotient has genus {genus}; a hyperbolic map has genus >= 2.")
    vertex = _orbits(Y)
    w = _windings(X, Y, vertex, 2 * genus)
    return DartMap(name=str(name), p=p, q=q, genus=int(genus), reverse=X, rotate=Y, vertex=vertex, windings=w)


def named_dart_map(name: str) -> DartMap:
    """One of the maps of :data:`DART_MAPS` by name.

    Parameters
    ----------
    name : str
        ``"one-site"`` or ``"two-site"``.

    Returns
    -------
    DartMap

    Examples
    --------
    >>> from hyperlattice.topology.dartmaps import named_dart_map
    >>> named_dart_map("two-site").genus
    3
    """
    name = _validate.choice("cluster", name, tuple(DART_MAPS))
    p, q, rels, _ = DART_MAPS[name]
    return dart_map(p, q, rels, name=name)


def _octagon_slots(m: DartMap) -> np.ndarray:
    """The homomorphism s: G -> Z8 with s(x) = 4, s(y) = 1, or a ValueError when none exists."""
    D = len(m.reverse)
    s = np.full(D, -1, dtype=np.int64)
    s[0] = 0
    stack = [0]
    while stack:
        d = stack.pop()
        for nxt, step in ((m.rotate[d], 1), (m.reverse[d], 4)):
            want = (s[d] + step) % 8
            if s[nxt] < 0:
                s[nxt] = want
                stack.append(nxt)
            elif s[nxt] != want:
                raise ValueError(f"the map {m.name!r} does not cover the one-site {{8,8}} map (no consistent "
                                 "labelling of the darts by the four generator pairs).")
    return s


def dirac4_terms(m_map, m: float = -3.0) -> ModelTerms:
    r"""The four-band Dirac model on a {8,8} map that covers the one-site map (module docstring).

    Parameters
    ----------
    m_map : DartMap or str
        The map, or a name in :data:`DART_MAPS`.
    m : float, optional
        The mass of :math:`m\Gamma_5` (default -3: second Chern number -1 on the one-site map).

    Returns
    -------
    ModelTerms
        Model ``"dirac4"``, four orbitals per site, one hop per dart with the dart's winding.

    Raises
    ------
    ValueError
        For a map that is not {8,8} or does not cover the one-site map, or a non-finite mass.

    Examples
    --------
    >>> from hyperlattice.topology.dartmaps import dirac4_terms
    >>> t = dirac4_terms("one-site", -3.0)
    >>> t.sites, t.orbitals, t.windings.shape
    (1, 4, (8, 4))
    """
    from .closed import GAMMA

    if isinstance(m_map, str):
        m_map = named_dart_map(m_map)
    if not isinstance(m_map, DartMap):
        raise ValueError(f"expected a DartMap or a map name, got {type(m_map).__name__}.")
    if (m_map.p, m_map.q) != (8, 8):
        raise ValueError(f"the Dirac model's generator labels need a {{8,8}} map, got {{{m_map.p},{m_map.q}}}.")
    m = _validate.real("m", m, minimum=-1e6, maximum=1e6)
    s = _octagon_slots(m_map)
    hop = np.array([0.5 * (GAMMA[4] - 1j * GAMMA[j]) for j in range(4)])
    blocks = np.where((s < 4)[:, None, None], hop[s % 4], np.conj(np.swapaxes(hop[s % 4], 1, 2)))
    n = m_map.sites
    return ModelTerms(model="dirac4", orbitals=4, onsite=np.repeat((m * GAMMA[4])[None], n, axis=0),
                      tail=m_map.vertex.copy(), head=m_map.vertex[m_map.reverse].copy(),
                      blocks=blocks.astype(np.complex128), windings=m_map.windings.copy(), parameters={"m": m})


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
