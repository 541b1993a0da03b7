"""Exact thermal averages (bosons.exact_thermal): the symmetry-sector route against the plain one,
the result's contract, refusals before work, and the QMC against it on the Bolza cluster."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.bosons import ThermalAverages, exact_thermal, qmc
from hyperlattice.bosons import thermal as TH
from hyperlattice.bosons.basis import boson_basis
from hyperlattice.bosons.ed import bose_hubbard_graph, fock_sectors
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.results import Result

HEPTAGON = hl.ring_lattice(7, 3, 1)
SCALARS = ("energy", "density", "compressibility", "free_energy")


@pytest.mark.parametrize("system, kw", [
    (HEPTAGON, dict(U=4.0, mu=1.0, beta=2.0, nmax=2)),                      # p = 7, soft-core
    pytest.param(HEPTAGON, dict(U=3.0, mu=1.5, beta=1.3, nmax=3, t=0.7),     # 16,384 states: 30 s dense
                 marks=pytest.mark.slow),
    (pbc_cluster(3, 8, "dyck-dual"), dict(U=0.0, mu=0.5, beta=1.0, nmax=1)),          # p = 3, 12 sites
    (pbc_cluster(3, 8, "dyck-dual"), dict(U=0.0, mu=-0.4, beta=2.0, nmax=1, t=-0.8)),  # t < 0, not bipartite
])
def test_sector_route_equals_the_plain_route(system, kw):
    a = exact_thermal(system, method="dense", **kw)
    b = exact_thermal(system, method="sectors", **kw)
    assert (a.method, b.method) == ("dense", "sectors") and a.sectors == 1 and b.sectors > 1
    assert b.largest_block < a.largest_block
    for k in SCALARS + ("condensate_fraction",):
        assert getattr(b, k) == pytest.approx(getattr(a, k), rel=1e-10, abs=1e-10), k
    for k in ("site_density", "green", "bond_kinetic"):
        assert np.max(np.abs(getattr(b, k) - getattr(a, k))) < 1e-10, k
    assert np.array_equal(a.bonds, b.bonds)
    # eigenvalues only: the same scalars, no one-body data
    c = exact_thermal(system, method="sectors", one_body=False, **kw)
    for k in SCALARS:
        assert getattr(c, k) == pytest.approx(getattr(a, k), rel=1e-10, abs=1e-10), k
    assert c.green is None and c.site_density is None and c.bond_kinetic is None and math.isnan(c.condensate_fraction)


def test_sector_dimensions_count_the_orbits_without_building_them():
    g = bose_hubbard_graph(HEPTAGON)
    dims = TH.sector_dimensions(g.rotation, 3)
    assert dims.shape == (22, 7)
    for n in (0, 1, 4, 11, 21):
        assert dims[n].tolist() == fock_sectors(boson_basis(7, n, 3), HEPTAGON).dims.tolist(), n
    bolza = pbc_cluster(8, 3, "bolza")
    d8 = TH.sector_dimensions(bose_hubbard_graph(bolza).rotation, 1)
    assert d8[8].tolist() == [1620, 1600, 1616, 1600, 1618, 1600, 1616, 1600]
    assert d8.sum() == 2 ** 16
    with pytest.raises(ValueError, match="permutation"):
        TH.sector_dimensions([0, 0, 1], 1)


def test_result_contract():
    ex = exact_thermal(HEPTAGON, U=4.0, mu=1.0, beta=2.0, nmax=2)
    assert isinstance(ex, ThermalAverages) and isinstance(ex, Result)
    assert round(ex.density, 6) == 0.97273 and ex.states == 3 ** 7 and ex.sites == 7
    assert ex.energy == pytest.approx(-12.716475603480262, abs=1e-9)
    rows = ex.table()
    assert [r["observable"] for r in rows] == ["energy", "density", "compressibility", "free_energy",
                                               "condensate_fraction"]
    assert {r["observable"]: r["unit"] for r in rows}["energy"] == "t"
    back = Result.from_dict(json.loads(ex.to_json()))
    assert isinstance(back, ThermalAverages)
    for k in SCALARS:
        assert getattr(back, k) == getattr(ex, k)
    assert np.array_equal(back.green, ex.green) and np.array_equal(back.site_density, ex.site_density)
    assert ex.table_columns()["site_density"].shape == (7,)
    with pytest.raises(TypeError):
        ex["energy"]                                   # a Result, not a dict: no item access
    with pytest.raises(ValueError):
        ex.green[0, 0] = 1.0                           # read-only arrays
    # G: symmetric, diagonal = site densities, nearest-neighbour part = bond kinetic / 2
    assert np.allclose(ex.green, ex.green.T, atol=1e-14)
    assert np.allclose(np.diag(ex.green), ex.site_density)
    assert np.allclose([2 * ex.green[i, j] for i, j in ex.bonds], ex.bond_kinetic)


def test_eigenvalues_are_reused_across_mu_beta_and_t_for_hard_core_bosons():
    c = pbc_cluster(3, 8, "dyck-dual")
    TH._CACHE.clear()
    first = exact_thermal(c, U=0.0, mu=0.2, beta=1.0, nmax=1, one_body=False)
    assert len(TH._CACHE) == 1
    for kw in (dict(mu=-0.7, beta=3.0), dict(mu=0.4, beta=0.5, t=0.6), dict(mu=0.1, beta=2.0, t=-1.3)):
        args = dict(U=0.0, nmax=1, **kw)
        reused = exact_thermal(c, one_body=False, **args)
        fresh = exact_thermal(c, **args)               # one_body=True: diagonalised again
        assert len(TH._CACHE) == 1
        for k in SCALARS:
            assert getattr(reused, k) == pytest.approx(getattr(fresh, k), rel=1e-11, abs=1e-11), (kw, k)
    assert first.energy != reused.energy


def test_refused_before_work_in_one_sentence():
    with pytest.raises(ValueError, match="exact_thermal diagonalises at most") as exc:
        exact_thermal(hl.ring_lattice(7, 3, 2), U=1.0, mu=0.0, beta=1.0, nmax=1)      # 28 sites
    assert "\n" not in str(exc.value)
    with pytest.raises(ValueError, match="exact_thermal diagonalises at most"):
        exact_thermal(pbc_cluster(8, 3, "bolza"), U=0.0, mu=0.0, beta=1.0, nmax=1, method="dense")
    with pytest.raises(ValueError, match="sectors of at least"):
        exact_thermal(pbc_cluster(7, 3, "klein"), U=0.0, mu=0.0, beta=1.0, nmax=1)    # 56 sites
    import scipy.sparse as sp

    ring = sp.csr_matrix(np.roll(np.eye(5), 1, axis=1) + np.roll(np.eye(5), -1, axis=1))
    with pytest.raises(ValueError, match="no rotation symmetry"):
        exact_thermal(ring, U=1.0, mu=0.0, beta=1.0, nmax=1, method="sectors")
    with pytest.raises(ValueError, match="method"):
        exact_thermal(HEPTAGON, U=1.0, mu=0.0, beta=1.0, nmax=1, method="lanczos")
    with pytest.raises(ValueError, match="beta"):
        exact_thermal(HEPTAGON, U=1.0, mu=0.0, beta=0.0, nmax=1)
    old = TH.WORK_MAX
    try:
        TH.WORK_MAX = 1e6
        with pytest.raises(ValueError, match="units of dense-diagonalisation work"):
            exact_thermal(HEPTAGON, U=1.0, mu=0.0, beta=1.0, nmax=3, method="sectors")
    finally:
        TH.WORK_MAX = old


@pytest.mark.slow
def test_qmc_against_exact_thermal_on_the_bolza_cluster():
    """The issue's check: hard-core bosons on the 16-site Bolza cluster (65,536 states; N blocks up
    to 12,870 split into the 8 sectors of its face rotation), several (t, mu, beta), within 4 sigma;
    at the first point also G(i, j) by graph distance and the condensate fraction. One
    diagonalisation serves every point (hard-core spectra are reused across t, mu and beta)."""
    from scipy.sparse.csgraph import shortest_path

    bolza = pbc_cluster(8, 3, "bolza")
    hops = shortest_path(bolza.adjacency(), unweighted=True).astype(int)
    off = ~np.eye(16, dtype=bool)
    TH._CACHE.clear()
    for t, mu, beta, seed, green in ((1.0, 0.3, 2.0, 1, True), (0.7, -0.5, 1.0, 2, False), (1.0, 1.2, 3.0, 3, False)):
        ex = exact_thermal(bolza, U=0.0, mu=mu, beta=beta, nmax=1, t=t, one_body=green)
        assert ex.method == "sectors" and ex.largest_block == 1620
        r = qmc(bolza, U=0.0, mu=mu, beta=beta, nmax=1, t=t, sweeps=20000, thermalization=2000, seed=seed,
                progress=False, measure_green=green)
        for k in ("energy", "density", "compressibility"):
            v, e = getattr(r, k), getattr(r, k + "_err")
            assert abs(v - getattr(ex, k)) < 4 * e, (t, mu, beta, k, v, e, getattr(ex, k))
        if green:
            assert r.distance_kind == "graph x d0" and len(r.green) == hops.max()
            for d, val, err in zip(range(1, hops.max() + 1), r.green, r.green_err):
                exact = ex.green[(hops == d) & off].mean()
                assert abs(val - exact) < 4 * err, (d, val, err, exact)
            assert abs(r.condensate_fraction - ex.condensate_fraction) < 4 * r.condensate_fraction_err
            assert np.allclose(ex.site_density, ex.density)                # vertex-transitive
