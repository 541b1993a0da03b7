"""Periodic {p,q} clusters: the invariants of the issue, two routes, and the systole."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from hyperlattice.errors import HyperlatticeError
from hyperlattice.graph import clusters as C
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.results import load_result

# (p, q, name, sites, genus): genus from the literature (Klein 3, Bolza 2, Dyck 3) or from
# |G| = r (r^2 - 1)/2 and 2 - 2g = |G| (1/q - 1/2 + 1/p) for the PSL(2, r) family
TABLE = [
    (7, 3, "klein", 56, 3),
    (8, 3, "bolza", 16, 2),
    (8, 3, "dyck", 32, 3),
    (3, 7, "klein-dual", 24, 3),
    (3, 8, "dyck-dual", 12, 3),
    (7, 3, "PSL(2,7)", 56, 3),
    (7, 3, "macbeath", 168, 7),
    (7, 3, "hurwitz14a", 364, 14),
    (7, 3, "hurwitz14b", 364, 14),
    (7, 3, "PSL(2,13)", 364, 14),
    (7, 3, "PSL(2,29)", 4060, 146),
    (8, 3, "PSL(2,17)", 816, 52),
    (8, 3, "PSL(2,31)", 4960, 311),
    (3, 7, "PSL(2,13)", 156, 14),
    (4, 5, "PSL(2,31)", 2976, 373),
    (5, 4, "PSL(2,31)", 3720, 373),
]
IDS = [f"{p}-{q}-{n}" for p, q, n, _, _ in TABLE]


@pytest.mark.parametrize("p,q,name,sites,genus", TABLE, ids=IDS)
def test_invariants(p, q, name, sites, genus):
    c = C.pbc_cluster(p, q, name)
    assert (c.p, c.q, c.sites, c.genus) == (p, q, sites, genus)
    A = c.adjacency()
    assert (A != A.T).nnz == 0 and A.max() == 1 and A.diagonal().sum() == 0
    assert np.all(np.asarray(A.sum(axis=1)).ravel() == q)              # q-regular
    assert c.faces.shape == (c.sites * q // p, p)                       # p-gons
    assert c.edges.shape == (c.sites * q // 2, 2)
    assert c.sites - len(c.edges) + len(c.faces) == 2 - 2 * genus       # Euler
    # every face is a closed walk along edges, counterclockwise: at faces[f, k] the
    # neighbour after faces[f, k+1] (ccw) is faces[f, k-1]
    nb = c.neighbours
    f = c.faces
    for k in range(p):
        v, nxt, prv = f[:, k], f[:, (k + 1) % p], f[:, k - 1]
        slot = np.argmax(nb[v] == nxt[:, None], axis=1)
        assert np.all(nb[v, slot] == nxt)
        assert np.all(nb[v, (slot + 1) % q] == prv)
    # every directed edge borders exactly one face
    darts = np.stack([f.ravel(), np.roll(f, -1, axis=1).ravel()], axis=1)
    assert len(np.unique(darts, axis=0)) == c.sites * q


def _walks(A, start: int, kmax: int) -> np.ndarray:
    """Closed-walk counts (A^k)_{start,start}, k = 0..kmax, exact in int64."""
    A = A.astype(np.int64)
    v = np.zeros(A.shape[0], dtype=np.int64)
    v[start] = 1
    out = []
    for _ in range(kmax + 1):
        out.append(int(v[start]))
        v = A @ v
    return np.array(out)


def _lattice_walks(p, q, kmax):
    """Closed-walk counts of the infinite lattice from site 0 of a flake with enough rings that
    walks of length kmax (which stay within kmax/2 steps) never come near the rim."""
    from scipy.sparse.csgraph import shortest_path

    rings = 2
    while True:
        lat = ring_lattice(p, q, rings)
        e = np.asarray(lat.edges)
        A = sp.coo_matrix((np.ones(len(e), dtype=np.int64), (e[:, 0], e[:, 1])), shape=(lat.sites,) * 2).tocsr()
        A = A + A.T
        d = shortest_path(A, indices=0, unweighted=True)
        if kmax // 2 < d[np.asarray(lat.ring) == lat.rings].min() - 1:
            return _walks(A, 0, kmax)
        rings += 1


@pytest.mark.parametrize("p,q,name", [
    (7, 3, "klein"), (7, 3, "macbeath"), (7, 3, "PSL(2,13)"), (7, 3, "hurwitz14b"), (8, 3, "bolza"), (8, 3, "dyck"), (8, 3, "PSL(2,17)"),
    (3, 7, "PSL(2,13)"), (3, 8, "dyck-dual"), (4, 5, "PSL(2,31)"),
], ids=lambda v: str(v))
def test_locally_the_lattice(p, q, name):
    # closed walks shorter than the systole are contractible, so they are the lattice's; at the
    # systole the non-contractible cycles add walks (an independent check of the systole)
    c = C.pbc_cluster(p, q, name)
    ell = c.systole
    lattice = _lattice_walks(p, q, ell)
    cluster = _walks(c.adjacency(), 0, ell)
    assert np.array_equal(cluster[:ell], lattice[:ell])
    assert cluster[ell] > lattice[ell]


@pytest.mark.slow
def test_locally_the_lattice_large():
    c = C.pbc_cluster(7, 3, "PSL(2,29)")
    ell = c.systole  # 26
    lattice = _lattice_walks(7, 3, ell)
    cluster = _walks(c.adjacency(), 0, ell)
    assert np.array_equal(cluster[:ell], lattice[:ell]) and cluster[ell] > lattice[ell]


@pytest.mark.slow
def test_walks_from_every_site_agree():
    # vertex-transitivity, which the one-vertex systole relies on: same counts from all sites
    c = C.pbc_cluster(7, 3, "PSL(2,13)")
    A = c.adjacency().toarray().astype(np.int64)
    M = np.eye(len(A), dtype=np.int64)
    for _ in range(c.systole + 2):
        M = M @ A
        assert np.all(np.diag(M) == M[0, 0])


def test_two_routes_give_the_same_map():
    # Todd-Coxeter from the presentation (2,3,7;4) and the PSL(2,7) matrices
    a = C.pbc_cluster(7, 3, "klein")
    b = C.pbc_cluster(7, 3, "PSL(2,7)")
    assert C.same_map(a, b)
    ea = np.linalg.eigvalsh(a.adjacency().toarray())
    eb = np.linalg.eigvalsh(b.adjacency().toarray())
    assert np.allclose(ea, eb, atol=1e-10)
    # a second overlap: the Hurwitz surface of genus 14 from (2,3,7;7) is the PSL(2,13) member
    assert C.same_map(C.pbc_cluster(7, 3, "hurwitz14a"), C.pbc_cluster(7, 3, "PSL(2,13)"))
    assert not C.same_map(C.pbc_cluster(7, 3, "hurwitz14b"), C.pbc_cluster(7, 3, "PSL(2,13)"))
    # and differently built non-isomorphic maps are told apart
    assert not C.same_map(C.pbc_cluster(8, 3, "bolza"), C.pbc_cluster(8, 3, "dyck"))


def _psl28_hurwitz_pair():
    """x, y of orders 2 and 3 with xy of order 7 generating PSL(2,8), as permutations of the
    projective line over GF(8) = F2[a]/(a^3 + a + 1) (points 0..7 and 8 = infinity)."""
    def mul(a, b):
        r = 0
        for i in range(3):
            if b >> i & 1:
                r ^= a << i
        for i in (4, 3):
            if r >> i & 1:
                r ^= 0b1011 << (i - 3)
        return r

    inv = {a: next(b for b in range(1, 8) if mul(a, b) == 1) for a in range(1, 8)}

    def mobius(a, b, c, d):
        def f(z):
            if z == 8:
                return 8 if c == 0 else mul(a, inv[c])
            num, den = mul(a, z) ^ b, mul(c, z) ^ d
            return 8 if den == 0 else mul(num, inv[den])
        return tuple(f(z) for z in range(9))

    group = sorted({mobius(a, b, c, d) for a in range(8) for b in range(8) for c in range(8) for d in range(8)
                    if mul(a, d) ^ mul(b, c) == 1})
    assert len(group) == 504
    e = tuple(range(9))

    def compose(p, q):          # p first, then q
        return tuple(q[i] for i in p)

    def order(p):
        k, r = 1, p
        while r != e:
            r, k = compose(r, p), k + 1
        return k

    def generated(gens):
        seen, front = {e}, [e]
        while front:
            front = [t for t in {compose(s, g) for s in front for g in gens} if t not in seen]
            seen.update(front)
        return len(seen)

    x = next(g for g in group if order(g) == 2)
    y = next(g for g in group if order(g) == 3 and order(compose(x, g)) == 7 and generated([x, g]) == 504)
    return x, y, compose, e


def test_macbeath_surface():
    # Macbeath (1965): the Hurwitz surface of genus 7, group PSL(2,8) of order 504, 168 sites
    c = C.pbc_cluster(7, 3, "macbeath")
    assert (c.sites, len(c.edges), len(c.faces), c.genus) == (168, 252, 72, 7)
    assert c.sites * c.q == 504 and "PSL(2,8)" in c.group and "order 504" in c.group
    assert c.systole == 14 and c.systole_exact
    assert c.faces.shape[1] == 7
    # the table's relator holds in PSL(2,8) for a (2,3,7) generating pair, so PSL(2,8) is a
    # quotient of the enumerated group; equal orders make them isomorphic
    x, y, compose, e = _psl28_hurwitz_pair()
    y_inv = tuple(sorted(range(9), key=lambda i: y[i]))
    letters = {"x": x, "y": y, "Y": y_inv}
    (relator,) = C.KNOWN["macbeath"][2]
    word, power = relator.split(")^")
    w = e
    for ch in word.strip("(").split():
        w = compose(w, letters[ch])
    r = e
    for _ in range(int(power)):
        r = compose(r, w)
    assert r == e and w != e
    # homology: 2g = 14 independent cycles
    from hyperlattice.graph.bands import edge_windings
    wnd = edge_windings(c)
    assert wnd.genus == 7 and wnd.windings.shape == (252, 14)
    assert np.linalg.matrix_rank(wnd.windings.astype(float)) == 14
    # and it is a new map: not the Klein quartic's or a genus-14 one, spectrum top 3 once
    ev = np.linalg.eigvalsh(c.adjacency().toarray())
    assert abs(ev[-1] - 3) < 1e-12 and np.sum(np.abs(ev - 3) < 1e-9) == 1


def test_same_map_full_search_matches_regular_shortcut():
    a = C.pbc_cluster(8, 3, "bolza")
    assert C.same_map(a, a, regular=False)


def test_klein_spectrum():
    # the adjacency spectrum of the Klein quartic graph: 3 (once) ... the uniform state at -q
    e = np.linalg.eigvalsh(C.pbc_cluster(7, 3, "klein").adjacency().toarray())
    assert abs(e[-1] - 3) < 1e-12 and np.sum(np.abs(e - 3) < 1e-9) == 1


def test_systoles_of_known_maps():
    # Klein quartic map: Petrie-like closed geodesics of 8 edges; Bolza and Dyck: 6
    assert C.pbc_cluster(7, 3, "klein").systole == 8
    assert C.pbc_cluster(8, 3, "bolza").systole == 6
    assert C.pbc_cluster(8, 3, "dyck").systole == 6


def test_min_sites_picks_smallest_family_member():
    c = C.pbc_cluster(7, 3, min_sites=1000)
    assert c.name == "PSL(2,29)" and c.sites == 4060
    assert C.pbc_cluster(8, 3, min_sites=800).name == "PSL(2,17)"
    assert C.pbc_cluster(7, 3).name == "klein"   # a cited table entry before an equal family member
    assert C.pbc_cluster(8, 3).name == "bolza"


def test_list_clusters_keys_and_order():
    entries = C.list_clusters(8, 3, max_sites=5000)
    assert [e["name"] for e in entries] == ["bolza", "dyck", "PSL(2,17)", "PSL(2,31)"]
    for e in entries:
        assert list(e) == ["name", "p", "q", "sites", "edges", "faces", "genus", "systole"]
        assert e["sites"] - e["edges"] + e["faces"] == 2 - 2 * e["genus"]


def test_family_reaches_1e5_sites():
    for p in (7, 8):
        c = C.pbc_cluster(p, 3, min_sites=100_000)
        assert c.sites >= 100_000 and c.genus >= 2 and c.systole > 20
        assert c.neighbours.dtype == np.int32 and c.neighbours.shape == (c.sites, 3)


def test_refuses_before_allocating(monkeypatch):
    monkeypatch.setattr(C, "_available_memory", lambda: 10**6)
    with pytest.raises(ValueError, match="GiB"):
        C.pbc_cluster(7, 3, "PSL(2,419)")
    with pytest.raises(ValueError, match="GiB"):
        C.pbc_cluster(7, 3, min_sites=10**7)


def test_systole_lower_bound_when_reference_too_large(monkeypatch):
    monkeypatch.setattr(C, "_REFERENCE_MAX_SITES", 3000)
    C._cached.cache_clear()
    try:
        c = C.pbc_cluster(7, 3, "PSL(2,29)")
        assert not c.systole_exact and 3 <= c.systole < 26
    finally:
        C._cached.cache_clear()


def test_bad_names_and_wrong_pq():
    with pytest.raises(ValueError, match="unknown cluster"):
        C.pbc_cluster(7, 3, "nope")
    with pytest.raises(ValueError, match="not"):
        C.pbc_cluster(8, 3, "klein")
    with pytest.raises(ValueError, match="not a torsion-free"):
        C.pbc_cluster(7, 3, "PSL(2,11)")
    with pytest.raises(ValueError, match="prime"):
        C.pbc_cluster(7, 3, "PSL(2,15)")
    with pytest.raises(ValueError, match="systole 2"):
        C.pbc_cluster(3, 8, "bolza-dual")   # K6 with doubled edges: not a simple graph
    with pytest.raises(ValueError):
        C.cluster_from_relators(7, 3, ["(x Y x y)^2"])  # collapses: not torsion-free
    with pytest.raises(ValueError, match="either"):
        C.pbc_cluster(7, 3, "klein", min_sites=10)


def test_result_round_trip(tmp_path):
    c = C.pbc_cluster(7, 3, "klein")
    for suffix in (".json", ".npz"):
        d = load_result(c.save(tmp_path / f"k{suffix}"))
        assert isinstance(d, C.Cluster) and np.array_equal(d.neighbours, c.neighbours)
        assert (d.systole, d.genus, d.name, d.systole_exact) == (c.systole, c.genus, c.name, True)
    assert c.summary()["sites"] == 56
    with pytest.raises(ValueError):
        c.neighbours[0, 0] = 1


def test_broken_map_refused_at_birth():
    c = C.pbc_cluster(7, 3, "klein")
    nb = np.array(c.neighbours)
    nb[0, [0, 1]] = nb[0, [1, 0]]   # swap two neighbours: the rotation no longer closes faces
    with pytest.raises((ValueError, HyperlatticeError)):
        C.Cluster(name="x", p=7, q=3, neighbours=nb, genus=3, systole=8)
    with pytest.raises(ValueError, match="genus"):
        C.Cluster(name="x", p=7, q=3, neighbours=c.neighbours, genus=2, systole=8)
