"""Sector-only flakes (graph/sectors.py): the same orbits, blocks and levels as the full lattice."""

import numpy as np
import pytest
import scipy.linalg as sla

from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.sectors import flake_memory, lowest_pair, sector_block, sector_lattice
from hyperlattice.graph.spectrum import lowest_levels
from hyperlattice.graph.symmetry import rotation_orbits, sector_hamiltonian

CASES = [(7, 3, 4), (7, 3, 5), (8, 3, 4), (3, 7, 4), (4, 5, 4), (5, 4, 4), (3, 8, 4), (6, 4, 3), (4, 6, 3),
         (12, 3, 3), (7, 3, 1), (5, 4, 1)]


@pytest.mark.parametrize("p,q,rings", CASES)
def test_orbits_coordinates_and_mirror_match_the_full_lattice(p, q, rings):
    lat = ring_lattice(p, q, rings)
    slat = sector_lattice(p, q, rings, coordinates=True)
    orb = rotation_orbits(lat)
    assert slat.sites == lat.sites and slat.size == orb.size
    assert np.array_equal(slat.ring_sizes, lat.sites_per_ring)
    assert np.allclose(slat.z, lat.z[orb.representatives], rtol=0, atol=1e-13)
    # the mirror maps representative o onto R^t (representative of mu(o)): z -> conj(z)
    image = np.exp(2j * np.pi * slat.mirror_shift / p) * slat.z[slat.mirror_orbit]
    assert np.allclose(image, np.conj(slat.z), rtol=0, atol=1e-12)


@pytest.mark.parametrize("p,q,rings", CASES)
def test_blocks_equal_the_full_lattice_blocks_and_mirror_forms_keep_the_spectrum(p, q, rings):
    lat = ring_lattice(p, q, rings)
    slat = sector_lattice(p, q, rings)
    for m in range(-((p - 1) // 2), p // 2 + 1):
        full = sector_hamiltonian(lat, m)
        ours = sector_block(slat, m)
        assert ours.nnz == full.nnz and abs(ours - full).max() < 1e-14
        ev = sla.eigvalsh(full.toarray())
        if m == 0:
            halves = [sla.eigvalsh(sector_block(slat, 0, mirror=h).toarray()) if sector_block(slat, 0, mirror=h).shape[0]
                      else np.zeros(0) for h in ("even", "odd")]
            for h in ("even", "odd"):
                # symmetric by construction: the factorisation layer is told so and skips its check
                half = sector_block(slat, 0, mirror=h)
                assert half.dtype == np.float64 and (half.nnz == 0 or abs(half - half.T).max() < 1e-14)
            other = np.sort(np.concatenate(halves))
        else:
            real = sector_block(slat, m, mirror="real")
            assert real.dtype == np.float64 and abs(real - real.T).max() < 1e-14
            other = sla.eigvalsh(real.toarray())
        assert np.allclose(ev, other, rtol=0, atol=1e-12)


def test_real_blocks_share_one_sparsity_pattern():
    slat = sector_lattice(7, 3, 5)
    pats = [sector_block(slat, m, mirror="real") for m in (1, 2, 3)]
    for b in pats[1:]:
        assert np.array_equal(b.indptr, pats[0].indptr) and np.array_equal(b.indices, pats[0].indices)


@pytest.mark.parametrize("p,q,rings,backend", [(7, 3, 6, "auto"), (7, 3, 8, "auto"), (8, 3, 5, "auto"),
                                               (4, 5, 4, "auto"), (3, 7, 5, "auto"), (7, 3, 7, "splu"),
                                               (5, 4, 4, "splu")])
def test_lowest_pair_equals_lowest_levels(p, q, rings, backend):
    ref = lowest_levels(ring_lattice(p, q, rings), 2)
    got = lowest_pair(p, q, rings, backend=backend)
    assert np.allclose(got.energies, ref.energies, rtol=0, atol=1e-12)
    assert got.m.tolist() == ref.m.tolist() and got.n.tolist() == ref.n.tolist()
    assert np.all(got.residuals <= 1e-10)
    assert got.method == "sector-shift-invert" and "inertia" in got.description
    assert got.sites == ref.sites


def test_refuses_a_flake_that_does_not_fit_before_allocating():
    with pytest.raises(ValueError, match="GB"):
        sector_lattice(7, 3, 30)
    with pytest.raises(ValueError, match="max_bytes"):
        lowest_pair(7, 3, 12, max_bytes=10**6)
    assert flake_memory(7, 3, 16) > flake_memory(7, 3, 15)


def test_unmet_tolerance_raises():
    # residuals are ~1e-15: a tolerance far below them cannot be met; refused before work (issue 28)
    with pytest.raises(ValueError, match="below what float64 arithmetic can reach"):
        lowest_pair(7, 3, 6, tol=1e-20)


def test_prebuilt_sector_lattice_is_used_and_labels_are_the_paper_ones():
    slat = sector_lattice(7, 3, 7)
    spec = lowest_pair(sectors=slat)
    assert spec.rings == 7 and spec.sites == slat.sites
    assert list(zip(spec.n.tolist(), spec.m.tolist())) == [(1, 0), (1, 1)]
    assert spec.summary()["method"] == "sector-shift-invert"


def test_without_scikit_sparse_the_pure_fallback_runs(monkeypatch):
    import hyperlattice.graph.factor as factor

    monkeypatch.setattr(factor, "_cholmod", lambda: None)
    spec = lowest_pair(7, 3, 7)  # backend="auto" falls back to SuperLU, silently
    assert "SuperLU" in spec.description and "inertia" in spec.description and spec.backend == "superlu"
    ref = lowest_levels(ring_lattice(7, 3, 7), 2)
    assert np.allclose(spec.energies, ref.energies, rtol=0, atol=1e-12)
    with pytest.warns(factor.SolverFallbackWarning, match="SuperLU"):
        spec = lowest_pair(7, 3, 3, backend="cholmod")
    assert spec.backend == "superlu"


@pytest.mark.parametrize("backend", ["superlu", pytest.param("cholmod", marks=pytest.mark.skipif(
    not __import__("hyperlattice.graph.factor", fromlist=["x"]).cholmod_available(), reason="no scikit-sparse"))])
@pytest.mark.parametrize("p,q,rings,levels", [(7, 3, 8, 10), (8, 3, 6, 7), (7, 3, 9, 25)])
def test_k_lowest_sector_levels_equal_lowest_levels(p, q, rings, levels, backend):
    # reference: the sector eigensolver of lowest_levels on the full lattice (dense/Chebyshev blocks)
    from hyperlattice.graph.sectors import lowest_sector_levels

    ref = lowest_levels(ring_lattice(p, q, rings), levels, method="sector")
    got = lowest_sector_levels(p, q, rings, levels, backend=backend)
    assert got.backend == backend and "inertia" in got.description
    np.testing.assert_allclose(got.energies, ref.energies, rtol=0, atol=1e-12)
    assert got.m.tolist() == ref.m.tolist() and got.n.tolist() == ref.n.tolist()


def test_rotation_orbits_refuses_a_rotation_that_is_not_of_order_p_or_fixes_sites():
    import dataclasses

    lat = ring_lattice(7, 3, 2)
    n = lat.sites
    cycle3 = np.arange(n)
    cycle3[[7, 8, 9]] = [8, 9, 7]                             # a 3-cycle; the rest fixed
    with pytest.raises(ValueError, match="after 1 of 7 steps"):
        rotation_orbits(dataclasses.replace(lat, rotation=cycle3))
    ring1 = np.arange(n)
    ring1[:7] = np.roll(np.arange(7), -1)
    ring1[7:] = np.roll(np.arange(7, n), -1)                 # a 28-cycle: not of order 7
    with pytest.raises(ValueError, match="not of order p = 7"):
        rotation_orbits(dataclasses.replace(lat, rotation=ring1))


def test_neighbour_lists_are_sorted_without_repeats_as_scipy_builds_them():
    import scipy.sparse as sp

    from hyperlattice.graph.lattice import _csr_sorted

    rng = np.random.default_rng(4)
    for n in (1, 6, 40):
        rows = rng.integers(0, n, 300).astype(np.int32)
        cols = rng.integers(0, n, 300).astype(np.int32)
        ref = sp.csr_matrix((np.ones(300, dtype=np.int8), (rows, cols)), shape=(n, n))
        ref.sort_indices()
        indptr, indices = _csr_sorted(rows, cols, n)
        assert np.array_equal(indptr, ref.indptr) and np.array_equal(indices, ref.indices)
        assert indptr.dtype == np.int64 and indices.dtype == np.int32


@pytest.mark.skipif(not __import__("hyperlattice.graph.factor", fromlist=["x"]).cholmod_available(),
                    reason="no scikit-sparse")
@pytest.mark.parametrize("p,q,rings", [(7, 3, 7), (8, 3, 5), (4, 5, 4)])
def test_the_m0_halves_numbered_after_the_real_ordering_are_the_same_blocks_with_as_little_fill(p, q, rings):
    # the m = 0 halves take their row order from CHOLMOD's ordering of the real blocks: the same
    # matrices up to that renumbering, and a factor about as sparse as their own AMD ordering gives
    from hyperlattice.graph import factor as fct
    from hyperlattice.graph.sectors import _BlockFactory

    slat = sector_lattice(p, q, rings)
    plain, ordered = _BlockFactory(slat, diagonal=True), _BlockFactory(slat, diagonal=True)
    real = fct.analyze(plain.block(1, "real", 1.0, csc=True), backend="cholmod")
    assert ordered.order_halves(real.permutation)
    for half in ("even", "odd"):
        a, b = plain.block(0, half, 1.0, csc=True), ordered.block(0, half, 1.0, csc=True)
        label = ordered._labels[half]
        moved = a.tocoo()
        assert abs(b - b.T).max() < 1e-14
        assert abs(b - type(a)((moved.data, (label[moved.row], label[moved.col])), shape=a.shape)).max() == 0.0
        own = fct.analyze(a, backend="cholmod").factor_entries
        assert fct.analyze(b, backend="cholmod", ordered=True).factor_entries <= 1.1 * own
    assert not ordered.order_halves(real.permutation)      # once built, the numbering stays
