"""Abelian hyperbolic band theory: windings, Bloch Hamiltonians and the exact cover check."""

from __future__ import annotations

import numpy as np
import pytest

from hyperlattice.graph import bands as B
from hyperlattice.graph import clusters as C


def _grid(two_g: int, n: int) -> np.ndarray:
    """All k in (2 pi / n) Z^{2g} modulo 2 pi."""
    m = np.array(np.meshgrid(*[np.arange(n)] * two_g, indexing="ij")).reshape(two_g, -1).T
    return 2 * np.pi * m / n


@pytest.mark.parametrize("p,name", [(8, "bolza"), (8, "dyck"), (7, "klein"), (7, "PSL(2,13)")])
def test_windings_are_homology(p, name):
    c = C.pbc_cluster(p, 3, name)
    w = B.edge_windings(c)
    assert w.windings.shape == (c.n_edges, 2 * c.genus)
    # the basis edges carry the unit vectors (their fundamental cycles are the homology basis)
    assert np.array_equal(w.windings[w.basis_edges], np.eye(2 * c.genus, dtype=np.int64))
    # every face boundary is null-homologous
    dw = w.dart_windings(c)
    f = c.faces
    for face in f:
        total = np.zeros(2 * c.genus, dtype=np.int64)
        for k in range(p):
            v, u = face[k], face[(k + 1) % p]
            total += dw[v, list(c.neighbours[v]).index(u)]
        assert not total.any()


def test_shortest_cycles_are_homologically_nontrivial_on_bolza():
    # a systolic cycle of the Bolza map (length 6) winds around a handle: its homology class is
    # not zero (found here as a closed walk of length 6 with non-zero total winding)
    c = C.pbc_cluster(8, 3, "bolza")
    dw = B.edge_windings(c).dart_windings(c)
    nb = c.neighbours
    best = None
    stack = [(0, (0,), np.zeros(4, dtype=np.int64))]
    while stack:
        v, path, tot = stack.pop()
        if len(path) == 7:
            if path[-1] == 0 and tot.any():
                best = path
                break
            continue
        for j, u in enumerate(nb[v]):
            if len(path) >= 2 and u == path[-2]:
                continue
            stack.append((int(u), path + (int(u),), tot + dw[v, j]))
    assert best is not None and c.systole == 6


def test_bloch_hamiltonian_basic():
    c = C.pbc_cluster(7, 3, "klein")
    H0 = B.bloch_hamiltonian(c, np.zeros(6))
    assert np.allclose(H0, -c.adjacency().toarray())
    rng = np.random.default_rng(1)
    H = B.bloch_hamiltonian(c, rng.uniform(-np.pi, np.pi, 6))
    assert np.allclose(H, H.conj().T)
    e = np.linalg.eigvalsh(H0)
    assert abs(e[0] + 3) < 1e-12   # the uniform state at E = -q lives at k = 0 only
    assert np.linalg.eigvalsh(H)[0] > -3 + 1e-6


@pytest.mark.parametrize("name,n", [
    ("bolza", 2),
    pytest.param("bolza", 3, marks=pytest.mark.slow),
    pytest.param("dyck", 2, marks=pytest.mark.slow),
])
def test_cover_spectrum_is_union_of_bloch_spectra(name, n):
    c = C.pbc_cluster(8, 3, name)
    cover = B.abelian_cover(c, n)
    g2 = 2 * c.genus
    assert cover.sites == c.sites * n**g2
    assert cover.genus == 1 + (c.genus - 1) * n**g2
    assert (cover.p, cover.q) == (8, 3) and cover.systole >= c.systole
    w = B.edge_windings(c)
    bloch = np.sort(np.concatenate([np.linalg.eigvalsh(B.bloch_hamiltonian(c, k, windings=w))
                                    for k in _grid(g2, n)]))
    exact = np.linalg.eigvalsh(-cover.adjacency().toarray())
    assert np.abs(exact - bloch).max() < 1e-10


def test_cover_moments_klein():
    # the Klein cell (odd p, not bipartite): the Z_2^6 cover (3584 sites) against the Bloch
    # spectra through the moments tr(H^m), m <= 20 (the cover is vertex-transitive, so its trace
    # is N times the closed walks from one site, an exact integer)
    c = C.pbc_cluster(7, 3, "klein")
    cover = B.abelian_cover(c, 2)
    A = cover.adjacency().astype(np.int64)
    v = np.zeros(cover.sites, dtype=np.int64)
    v[0] = 1
    w = B.edge_windings(c)
    evs = np.concatenate([np.linalg.eigvalsh(B.bloch_hamiltonian(c, k, windings=w)) for k in _grid(6, 2)])
    for m in range(1, 21):
        v = A @ v
        bloch = np.sum(evs**m)
        exact = (-1) ** m * cover.sites * v[0]
        assert abs(bloch - exact) <= 1e-9 * max(1.0, abs(exact))


def test_cover_is_a_regular_cluster():
    c = C.pbc_cluster(8, 3, "bolza")
    cover = B.abelian_cover(c, 2)
    # vertex-transitive (the one-vertex systole relies on it): closed-walk counts from all sites
    A = cover.adjacency().toarray().astype(np.int64)
    M = np.eye(len(A), dtype=np.int64)
    for _ in range(cover.systole + 1):
        M = M @ A
        assert np.all(np.diag(M) == M[0, 0])


def test_band_structure_and_path():
    c = C.pbc_cluster(8, 3, "bolza")
    bands = B.band_structure(c, points=6)
    k, ticks, labels = B.k_path(2, points=6)
    assert bands.energies.shape == (len(k), 16) and labels[0] == "Γ"
    assert np.all(np.diff(bands.distance) >= 0)
    assert abs(bands.energies[0, 0] + 3) < 1e-12      # E = -q at Γ
    assert np.all(np.abs(bands.energies) <= 3 + 1e-12)
    custom = B.band_structure(c, k=np.zeros((3, 4)), labels=["a", "b"], ticks=[0, 2])
    assert custom.tick_labels == ["a", "b"]


def test_abelian_dos_normalised():
    c = C.pbc_cluster(8, 3, "bolza")
    dos = B.abelian_dos(c, samples=64, bins=60, seed=3)
    width = np.diff(dos.bin_edges)
    assert abs(np.sum(dos.density * width) - 1) < 1e-12
    assert np.all(dos.errors >= 0) and dos.samples == 64
    again = B.abelian_dos(c, samples=64, bins=60, seed=3)
    assert np.array_equal(dos.density, again.density)


def test_bad_input():
    c = C.pbc_cluster(8, 3, "bolza")
    with pytest.raises(ValueError):
        B.bloch_hamiltonian(c, np.zeros(3))
    with pytest.raises(ValueError):
        B.bloch_hamiltonian("bolza", np.zeros(4))
    with pytest.raises(ValueError):
        B.abelian_cover(c, 1)
    with pytest.raises(ValueError, match="2,000,000"):
        B.abelian_cover(C.pbc_cluster(7, 3, "klein"), 20)
    with pytest.raises(ValueError):
        B.k_path(2, [("a", np.zeros(4))])


def test_figure(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hyperlattice.plots.bands import bands_and_dos

    c = C.pbc_cluster(8, 3, "bolza")
    fig = bands_and_dos(B.band_structure(c, points=4), B.abelian_dos(c, samples=16, bins=20, batches=2),
                        path=tmp_path / "b.png")
    assert (tmp_path / "b.png").stat().st_size > 0 and len(fig.axes) == 2
    plt.close(fig)
    with pytest.raises(ValueError):
        bands_and_dos("bands")
