"""Disorder models and ensembles: reproducibility, the clean limit, GOE and Poisson level statistics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hyperlattice import full_spectrum, hamiltonian, line_graph, ring_lattice
from hyperlattice.compare.disorder import (GOE_R, POISSON_R, disorder_ensemble, green_ensemble,
                                           realization_observables, r_scan, spacing_ratios)
from hyperlattice.graph.disorder import disorder, disordered_hamiltonian, onsite_variance, realization_rng
from hyperlattice.graph.green import graph_green


@pytest.fixture(scope="module")
def lat4():
    return ring_lattice(7, 3, 4)


def test_realizations_are_reproducible_and_independent(lat4):
    a = disorder(lat4, "box", 2.0, seed=3, realization=5)
    b = disorder(lat4, "box", 2.0, seed=3, realization=5)
    assert np.array_equal(a.onsite, b.onsite)
    # realization k is the k-th child of SeedSequence(seed), whatever else was drawn before
    child = np.random.SeedSequence(3).spawn(6)[5]
    assert np.array_equal(a.onsite, 2.0 * (np.random.default_rng(child).random(lat4.sites) - 0.5))
    assert not np.array_equal(a.onsite, disorder(lat4, "box", 2.0, seed=3, realization=4).onsite)
    assert not np.array_equal(a.onsite, disorder(lat4, "box", 2.0, seed=4, realization=5).onsite)
    assert realization_rng(3, 5).random() == realization_rng(3, 5).random()
    assert np.all(np.abs(a.onsite) <= 1.0)


def test_model_variances(lat4):
    big = ring_lattice(7, 3, 6)
    w = 3.0
    for model in ("box", "gaussian"):
        v = np.concatenate([disorder(big, model, w, realization=k).onsite for k in range(3)])
        # same variance W^2/12 by construction; 6720 samples: 3 % is about 2.5 sigma
        assert np.var(v) == pytest.approx(onsite_variance(model, w), rel=0.06)
    hop = disorder(lat4, "hopping", 0.4).hopping
    assert hop.shape == (lat4.edges.shape[0],) and np.all(np.abs(hop - 1) <= 0.2)
    lg = line_graph(lat4)
    res = disorder(lg, "resonator", 1e-3, omega0=100.0)
    assert np.std(res.onsite) == pytest.approx(0.1, rel=0.1)
    assert onsite_variance("resonator", 1e-3, omega0=100.0) == pytest.approx(0.01)
    with pytest.raises(ValueError, match="line graph"):
        disorder(lat4, "resonator", 1e-3, omega0=100.0)
    with pytest.raises(ValueError, match="omega0"):
        disorder(lg, "resonator", 1e-3)


@pytest.mark.parametrize("model", ["box", "gaussian", "hopping"])
def test_zero_disorder_is_the_clean_lattice(lat4, model):
    h0 = hamiltonian(lat4)
    h = disordered_hamiltonian(lat4, disorder(lat4, model, 0.0, seed=1))
    assert (h != h0).nnz == 0 and np.array_equal(h.indices, h0.indices)


def test_weak_disorder_approaches_the_clean_spectrum(lat4):
    clean = full_spectrum(lat4)
    for w in (1e-3, 1e-6):
        h = disordered_hamiltonian(lat4, disorder(lat4, "box", w, seed=2)).toarray()
        e = np.linalg.eigvalsh(h)
        # Weyl: |E_n(W) - E_n(0)| <= ||V|| <= W/2
        assert np.max(np.abs(e - clean)) <= w / 2 + 1e-12
    g0 = graph_green(lat4, -2.9 + 0.2j, source=0)
    ens = green_ensemble(lat4, -2.9 + 0.2j, 1e-6, realizations=2)
    assert np.max(np.abs(ens.mean - g0)) < 1e-9 and np.max(np.abs(ens.clean - g0)) < 1e-12


def test_spacing_ratios_known_cases():
    r, mid = spacing_ratios([0.0, 1.0, 3.0, 4.0])
    assert np.allclose(r, [0.5, 0.5]) and np.allclose(mid, [1.0, 3.0])
    # exact degeneracies (0/0) are left out
    r, _ = spacing_ratios([0.0, 1.0, 1.0, 1.0, 2.0])
    assert np.allclose(r, [0.0, 0.0])
    rng = np.random.default_rng(0)
    r, _ = spacing_ratios(np.cumsum(rng.exponential(size=200_000)))
    assert r.mean() == pytest.approx(POISSON_R, abs=3e-3)


def test_weak_disorder_gives_goe():
    # {7,3} with 5 rings (847 sites), W = 1, band centre |E| < 2.5: the flake's large boundary keeps
    # <r> about 0.01 below the bulk GOE value (0.519 at l = 5, 0.526 at l = 6 in |E| < 1.5)
    scan = r_scan(ring_lattice(7, 3, 5), [1.0], realizations=4, window=(-2.5, 2.5))
    assert abs(scan.r_mean[0] - GOE_R) < 0.02
    assert scan.r_mean[0] - POISSON_R > 0.1


def test_strong_disorder_gives_poisson(lat4):
    ens = disorder_ensemble(lat4, 200.0, 10, ipr=False)
    assert abs(ens.r_mean - POISSON_R) < 0.02
    assert abs(ens.r_mean - POISSON_R) < 4 * ens.r_err + 0.005


def test_ensemble_observables(lat4):
    weak = disorder_ensemble(lat4, 0.5, 2)
    strong = disorder_ensemble(lat4, 50.0, 2)
    for ens in (weak, strong):
        assert np.sum(ens.dos * np.diff(ens.dos_edges)) == pytest.approx(1.0)
    # localized states: participation ratio of a few sites
    assert np.nanmin(strong.ipr_window) > 5 * np.nanmax(weak.ipr_window)
    s = weak.summary()
    assert {"W", "realizations", "seed", "r_mean", "r_err"} <= set(s)
    row = realization_observables(lat4, "box", 0.5, seed=0, realization=1)
    assert row["r_count"] == lat4.sites - 2 and math.isfinite(row["r_mean"])


def test_resonator_model_on_the_line_graph(lat4):
    lg = line_graph(ring_lattice(7, 3, 3))
    ens = disorder_ensemble(lg, 1e-3, 2, model="resonator", omega0=100.0, ipr=False)
    assert ens.kind == "line_graph" and math.isfinite(ens.r_mean)


def test_periodic_cluster_without_boundary_reaches_goe():
    from hyperlattice.graph.clusters import psl2_cluster

    # {7,3} cluster of PSL(2,13) (364 sites, no boundary): the models apply unchanged, and W = 2 mixes
    # its large symmetry multiplets; the 4060-site PSL(2,29) cluster gives 0.529 +- 0.002 at W = 1
    c = psl2_cluster(7, 3, 13)
    assert np.array_equal(disordered_hamiltonian(c, disorder(c, "box", 0.0)).toarray(), -c.adjacency().toarray())
    ens = disorder_ensemble(c, 2.0, 10, ipr=False)
    assert ens.kind == "cluster" and abs(ens.r_mean - GOE_R) < 0.02
    assert abs(disorder_ensemble(c, 200.0, 10, ipr=False).r_mean - POISSON_R) < 0.02


def test_summary_windows_hold_numbers_and_nulls_only():
    """Window edges are [low, high] pairs, null for an open end: no mix of strings and numbers."""
    import json

    from hyperlattice.compare.disorder import disorder_ensemble
    from hyperlattice.graph.lattice import ring_lattice

    s = disorder_ensemble(ring_lattice(7, 3, 2), 1.0, realizations=2, seed=1).summary()
    w = s["windows"]
    assert w[0][0] is None and w[-1][1] is None and all(len(pair) == 2 for pair in w)
    assert all(v is None or isinstance(v, float) for pair in w for v in pair)
    json.dumps(s["windows"], allow_nan=False)


def test_r_scan_window_uses_the_same_convention():
    """An open window end is null in JSON, never the string "inf" (issue 21 item 5c)."""
    import json

    from hyperlattice.compare.disorder import r_scan
    from hyperlattice.graph.lattice import ring_lattice

    lat = ring_lattice(7, 3, 2)
    whole = r_scan(lat, [1.0], realizations=2, window=None).summary()
    assert whole["window"] == [None, None]
    assert r_scan(lat, [1.0], realizations=2).summary()["window"] == [-1.0, 1.0]
    json.dumps(whole, allow_nan=False)
