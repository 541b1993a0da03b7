"""Decisions on values that can be exactly degenerate or at a threshold (issue: same answers on
every machine).

The {7,3} flakes with l >= 2 have exact zero modes of H = -A. Their computed energies are
+-1e-16-ish, with a sign that depends on the BLAS kernel and the thread count; counting them as
"negative" or not made the Fig2 inset's partition function machine dependent (146 vs 148 states
at l = 4). These tests fix the count by an independent exact computation and show that the count
does not move when the rounding noise flips sign.
"""

import numpy as np
import pytest

from hyperlattice import _ties
from hyperlattice.compare.levels import graph_levels_below, partition_functions, continuum_levels_below
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency, hamiltonian
from hyperlattice.graph import spectrum as gspec

pytestmark = pytest.mark.machine_independence

#: a prime below 2**31, so that products of two residues fit in int64
_PRIME = 2_147_483_629


def _rank_mod_p(a: np.ndarray, p: int = _PRIME) -> int:
    """Rank of an integer matrix over GF(p) by Gaussian elimination (exact integer arithmetic).

    rank_p(A) <= rank_Q(A) for every prime, with equality for all but finitely many primes
    (those dividing some nonzero minor); two large primes agreeing is the test's check.
    """
    m = np.array(a, dtype=np.int64) % p
    rows, cols = m.shape
    rank = 0
    for c in range(cols):
        piv = np.flatnonzero(m[rank:, c])
        if piv.size == 0:
            continue
        r = rank + int(piv[0])
        m[[rank, r]] = m[[r, rank]]
        inv = pow(int(m[rank, c]), p - 2, p)
        m[rank] = (m[rank] * inv) % p
        others = np.flatnonzero(m[:, c])
        others = others[others != rank]
        if others.size:
            f = m[others, c][:, None]
            m[others] = (m[others] - f * m[rank][None, :]) % p
        rank += 1
        if rank == rows:
            break
    return rank


@pytest.mark.parametrize("rings, zero_modes", [(1, 0), (2, 1), (3, 1), (4, 2), (5, 3)])
def test_zero_modes_counted_match_exact_nullity(rings, zero_modes):
    """The count of levels at E = 0 equals the exact nullity of the integer matrix A.

    The nullity is computed over GF(p) for two large primes (exact integer arithmetic, no
    rounding at all); the expected numbers are that nullity, independent of any eigensolver.
    """
    lat = ring_lattice(7, 3, rings)
    a = adjacency(lat).toarray().astype(np.int64)
    nullity = {lat.sites - _rank_mod_p(a, p) for p in (_PRIME, 2_147_483_587)}
    assert nullity == {zero_modes}
    g = graph_levels_below(lat, 0.0)
    assert g.at_cutoff == zero_modes
    # and the levels below plus the zero modes plus those above add up to N
    e, tol = gspec.full_spectrum_tolerance(lat)
    assert g.states + g.at_cutoff + int(np.count_nonzero(e > tol)) == lat.sites


def test_count_does_not_depend_on_the_sign_of_rounding(monkeypatch):
    """Flip the sign of the computed zero modes (as another BLAS kernel may): nothing changes."""
    lat = ring_lattice(7, 3, 4)
    ref = graph_levels_below(lat)
    real = gspec._full_spectrum

    def noisy(*args, sign, **kwargs):
        e, tol = real(*args, **kwargs)
        e = e.copy()
        zero = np.abs(e) <= tol
        e[zero] = sign * 0.5 * tol   # still within the bound, but of a chosen sign
        return e, tol

    for sign in (-1.0, 1.0):
        monkeypatch.setattr(gspec, "_full_spectrum", lambda *a, sign=sign, **k: noisy(*a, sign=sign, **k))
        g = graph_levels_below(lat)
        assert (g.states, g.at_cutoff) == (ref.states, ref.at_cutoff) == (146, 2)
        np.testing.assert_allclose(gspec.partition_function(lat, [0.5, 2.0]),
                                   ref.partition_function(np.array([0.5, 2.0])), rtol=1e-13)


@pytest.mark.slow
def test_partition_comparison_reports_the_zero_modes():
    z = partition_functions(graph_levels_below(ring_lattice(7, 3, 4)), continuum_levels_below(7, 3, rings=4),
                            np.array([1.0]))
    assert (z.graph_states, z.graph_zero_modes, z.continuum_states) == (146, 2, 108)
    # the bound is tiny against the smallest nonzero |E| of this flake (6.85e-3)
    assert 0 < z.graph_tolerance < 1e-11


def test_eigenvalue_tolerance_scales_with_norm_and_size():
    assert _ties.eigenvalue_tolerance(3.0, 100) == pytest.approx(_ties.SAFETY * 100 * _ties.EPS * 3.0)
    # t = 1e20: the tolerance scales with ||H||, so decisions are scale invariant
    assert _ties.eigenvalue_tolerance(3e20, 100) == pytest.approx(1e20 * _ties.eigenvalue_tolerance(3.0, 100))
    assert _ties.eigenvalue_tolerance(3.0, 10, residual=1e-6) == 1e-6
    with pytest.raises(ValueError):
        _ties.eigenvalue_tolerance(float("nan"), 10)


def test_classify_and_degenerate_groups():
    below, at, above = _ties.classify([-1.0, -1e-16, 0.0, 2e-16, 1e-3], 0.0, 1e-13)
    assert below.tolist() == [True, False, False, False, False]
    assert at.tolist() == [False, True, True, True, False]
    assert above.tolist() == [False, False, False, False, True]
    g = _ties.degenerate_groups([0.0, 1e-15, 2e-15, 1.0, 1.0 + 1e-15], 1e-14)
    assert g.tolist() == [0, 0, 0, 1, 1]


def test_stable_order_breaks_ties_by_labels_not_rounding():
    # two degenerate pairs whose computed values come in either order
    labels = np.array([3, 1, 2, 0])
    for noise in (1e-16, -1e-16):
        vals = np.array([1.0, 1.0 + noise, -2.0 - noise, -2.0])
        order = _ties.stable_order(vals, 1e-14, labels)
        assert labels[order].tolist() == [0, 2, 1, 3]


def test_default_distance_bins_are_centred_on_the_lattice_distances():
    """Nearest neighbours lie at exactly d0: the default bins put it at a centre, not an edge."""
    from hyperlattice.compare.correlation import bin_by_distance
    from hyperlattice.geometry import d0, distance

    lat = ring_lattice(7, 3, 4)
    d = distance(lat.z, lat.z[0])
    b = bin_by_distance(d, np.ones_like(d))
    assert b.edge_ties == 0
    # a neighbour distance computed a few ulps above or below d0 lands in the same bin
    w = 0.5 * d0(7, 3)
    for eps in (-4e-16, 4e-16):
        bb = bin_by_distance(np.array([0.0, d0(7, 3) * (1 + eps), 3.0]), np.ones(3))
        assert bb.count.tolist() == [1, 1, 1]
        np.testing.assert_allclose(bb.centre, [0.0, 2 * w, np.round(3.0 / w) * w])
    # explicit edges through an exact distance are reported as ties
    tied = bin_by_distance(np.array([0.2, 0.5, 0.7]), np.ones(3), edges=[0.0, 0.5, 1.0])
    assert tied.edge_ties == 1


def test_sector_levels_cut_through_degenerate_pairs_consistently():
    """k lowest states from sector blocks: every prefix of the k = 12 list equals the k-level
    answer, +-m pairs keep (+m, -m) with one radial index, whatever the rounding of the pair."""
    from hyperlattice.graph.sectors import lowest_sector_levels

    ref = lowest_sector_levels(7, 3, 5, levels=12)
    for k in (2, 3, 4, 7, 11):
        s = lowest_sector_levels(7, 3, 5, levels=k)
        assert s.m.tolist() == ref.m[:k].tolist() and s.n.tolist() == ref.n[:k].tolist()
        np.testing.assert_allclose(s.energies, ref.energies[:k], rtol=0, atol=1e-12)
    m, n = ref.m, ref.n
    for i in np.flatnonzero(m > 0):
        if i + 1 < m.size:
            assert m[i + 1] == -m[i] and n[i + 1] == n[i]


def test_simulated_rounding_moves_levels_within_the_bound_the_package_uses():
    """tests/rounding_noise.py (``pytest --rounding-noise SEED``) stands in for another machine: each
    eigenvalue moves by at most 8 ulps of the norm, the same input gives the same output, another
    seed another one, and the moves stay far inside eigenvalue_tolerance; the zero modes of the
    l = 4 flake come out with either sign, and the package's count does not change."""
    import rounding_noise

    from hyperlattice._ties import eigenvalue_tolerance

    h = hamiltonian(ring_lattice(7, 3, 4)).toarray()
    exact = np.linalg.eigvalsh(h)
    signs = set()
    for seed in range(6):
        undo = rounding_noise.install(seed)
        try:
            w = np.linalg.eigvalsh(h)
            assert np.array_equal(w, np.linalg.eigvalsh(h)) and np.all(np.diff(w) >= 0)
            moved = np.abs(w - exact).max()
            assert moved <= 9 * np.finfo(float).eps * np.abs(exact).max()     # 8 ulps + the rounding of the sum
            assert moved < eigenvalue_tolerance(3.0, h.shape[0]) / 100
            zero = np.abs(w) < 1e-12
            signs |= {tuple(np.sign(w[zero]))}
            g = graph_levels_below(ring_lattice(7, 3, 4))
            assert (g.states, g.at_cutoff) == (146, 2)
        finally:
            undo()
    assert len(signs) > 1                          # the zero modes' signs did change
