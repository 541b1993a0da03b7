"""Exact closed walks of the infinite {p,q} lattice: depth limit, integers, bounds on rho."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency
from hyperlattice.graph.walks import (boundary_distance, chebyshev_from_walks, closed_walks, exact_depth,
                                      exact_depths, isoperimetric_upper_bound, rings_for_walks, spectral_radius,
                                      spectral_radius_bounds)


def _tree_walks(q: int, n_max: int) -> list[int]:
    """Closed walks of the q-regular tree, by the distance chain (exact integers)."""
    v = [1] + [0] * (n_max + 1)
    out = [1]
    for _ in range(n_max):
        w = [0] * len(v)
        w[1] += q * v[0]
        for d in range(1, len(v) - 1):
            w[d - 1] += v[d]
            w[d + 1] += (q - 1) * v[d]
        v = w
        out.append(v[0])
    return out


def test_small_counts_by_hand():
    # below the shortest cycle (the 7-gon) the {7,3} lattice looks like the 3-regular tree;
    # W_7 = 2 directions x 3 heptagons through a site
    w = closed_walks(7, 3, 8)
    assert w.dtype == np.int64
    assert w.tolist() == [1, 0, 3, 0, 15, 0, 87, 6, 543]
    assert closed_walks(13, 3, 10).tolist() == _tree_walks(3, 10)  # no cycle shorter than 13


def test_depth_limit_is_sharp_and_proven():
    # on a flake of R rings the counts from a ring-1 site agree up to 2(R-1)+1
    w = closed_walks(7, 3, 13)
    for rings in (2, 3):
        lat = ring_lattice(7, 3, rings)
        a = adjacency(lat).astype(np.int64).tocsr()
        v = np.zeros(lat.sites, dtype=np.int64)
        v[0] = 1
        counts = [1]
        x = v
        for _ in range(13):
            x = a @ x
            counts.append(int(x[0]))
        d = exact_depth(rings, 1)
        assert d == 2 * rings - 1
        assert counts[: d + 1] == w[: d + 1].tolist()
        # a sufficient condition, not a sharp one; a little further the flake misses walks
        assert any(c < x for c, x in zip(counts, w.tolist()))
        # the sharper proven limit 2 d_b + 1 (distance to a deficient site) is attained exactly here
        sharp = int(exact_depths(lat)[0])
        assert sharp == 2 * boundary_distance(lat, site=0) + 1 >= d
        assert counts[: sharp + 1] == w[: sharp + 1].tolist() and counts[sharp + 1] < w[sharp + 1]
    assert rings_for_walks(7, 3, 25) == 7


def test_python_ints_beyond_int64(monkeypatch):
    # when q**n_max could pass the int64 range the counts are Python ints (same values); the
    # switch is exercised by lowering the threshold (real cases need flakes of > 10**8 sites)
    from hyperlattice.graph import walks

    ref = closed_walks(7, 3, 15)
    monkeypatch.setattr(walks, "_INT64_MAX", 1000)
    walks._walks_cached.cache_clear()
    try:
        w = closed_walks(7, 3, 15)
    finally:
        walks._walks_cached.cache_clear()
    assert w.dtype == object
    assert [int(x) for x in w] == ref.tolist()


def test_lower_bounds_increase_and_stay_below_upper():
    for p, q, n in ((7, 3, 20), (8, 3, 16), (4, 5, 12), (3, 7, 10)):
        s = spectral_radius(p, q, n)
        assert np.all(np.diff(s.ratios) >= -1e-15)  # Cauchy-Schwarz: W_2n^2 <= W_2n-2 W_2n+2
        assert 2 * math.sqrt(q - 1) - 1e-12 <= s.upper < q
        assert s.lower < s.upper
        assert s.ratios[-1] <= s.upper
        lo, hi = s.band_bottom_interval()
        assert lo < hi < 0


def test_isoperimetric_bound_is_sharp_for_trees():
    assert isoperimetric_upper_bound(math.inf, 3) == pytest.approx(2 * math.sqrt(2), rel=1e-15)
    # tree counts: the ratio bound tends to 2 sqrt(q - 1) from below
    root, ratio = spectral_radius_bounds(_tree_walks(4, 60))
    assert root < ratio < 2 * math.sqrt(3)
    assert ratio > 2 * math.sqrt(3) * 0.97


def test_chebyshev_from_walks_matches_spectrum():
    # exact walks of a small matrix's site 0 against its eigen-decomposition
    lat = ring_lattice(7, 3, 2)
    a = adjacency(lat).toarray()
    ev, vec = np.linalg.eigh(-a)
    weights = vec[0] ** 2
    walks = [int(round(np.linalg.matrix_power(a, n)[0, 0])) for n in range(20)]
    scale = 3.0 / 0.99
    mu = chebyshev_from_walks(walks, scale)
    ref = np.array([np.sum(weights * np.cos(n * np.arccos(ev / scale))) for n in range(20)])
    assert np.abs(mu - ref).max() < 1e-12


def test_bad_walks():
    with pytest.raises(ValueError):
        chebyshev_from_walks([], 3.0)
    with pytest.raises(ValueError):
        chebyshev_from_walks([1, "x"], 3.0)
    with pytest.raises(ValueError):
        closed_walks(7, 3, 201)
    with pytest.raises(ValueError):
        exact_depth(3, 4)
