"""The SSE quantum Monte Carlo (bosons.qmc) against exact thermal averages, and its contracts.

Reference: exact_thermal (full diagonalisation over every particle-number block). Each QMC number
must lie within 4 of its own error bars of the exact value; the error bars themselves are checked
in test_qmc_errors.py (coverage over many seeds).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice import mcstats
from hyperlattice.bosons import QMCResult, exact_thermal, merge_chains, qmc
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.results import Result


def _ring(n: int, weights=None) -> sp.csr_matrix:
    w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
    i = np.arange(n)
    a = sp.coo_matrix((w, (i, (i + 1) % n)), shape=(n, n))
    return (a + a.T).tocsr()


def _check(r, ex, names=("energy", "density", "compressibility"), k=4.0):
    for name in names:
        v, e = getattr(r, name), getattr(r, name + "_err")
        assert abs(v - getattr(ex, name)) < k * e + 1e-9, (name, v, e, getattr(ex, name))


HEPTAGON = hl.ring_lattice(7, 3, 1)

# (system, parameters, sweeps): superfluid, Mott, hard-core, weak hopping, large nmax
CASES = [
    (HEPTAGON, dict(U=4.0, mu=1.0, beta=2.0, nmax=2), 6000),
    (HEPTAGON, dict(U=12.0, mu=6.0, beta=3.0, nmax=2), 6000),                 # deep Mott, n = 1
    (HEPTAGON, dict(U=0.0, mu=-0.3, beta=3.0, nmax=1), 6000),                 # hard-core (XY)
    (HEPTAGON, dict(U=2.0, mu=0.5, beta=1.0, nmax=2, t=0.7), 6000),
    (pbc_cluster(3, 8, "dyck-dual"), dict(U=0.0, mu=0.5, beta=1.0, nmax=1), 4000),   # 12 sites, q = 8
]


@pytest.mark.parametrize("system, kw, sweeps", CASES)
def test_qmc_matches_exact_thermal(system, kw, sweeps):
    ex = exact_thermal(system, **kw)
    r = qmc(system, sweeps=sweeps, thermalization=1000, seed=11, progress=False, **kw)
    _check(r, ex)
    # site densities and the nearest-neighbour one-body density matrix (operator counts)
    assert np.all(np.abs(r.site_density - ex.site_density) < 4.5 * r.site_density_err + 1e-9)
    assert np.all(np.abs(r.bond_kinetic - ex.bond_kinetic) < 4.5 * r.bond_kinetic_err + 1e-9)


def test_green_function_and_condensate_fraction():
    kw = dict(U=4.0, mu=1.0, beta=2.0, nmax=2)
    ex = exact_thermal(HEPTAGON, **kw)
    r = qmc(HEPTAGON, sweeps=8000, thermalization=1000, seed=5, progress=False, **kw)
    g = ex.green
    d = hl.geometry.distance(HEPTAGON.z[:, None], HEPTAGON.z[None, :], check=False)
    assert r.distance_kind == "hyperbolic"
    cls = np.rint(d / (hl.geometry.d0(7, 3) / 2))          # the classes: bins of d0 / 2
    off = ~np.eye(7, dtype=bool)
    for c, dist, val, err, npairs in zip(np.unique(cls[off]), r.green_distance, r.green, r.green_err, r.green_pairs):
        sel = (cls == c) & off
        assert npairs == sel.sum() and dist == pytest.approx(d[sel].mean())
        assert abs(val - g[sel].mean()) < 4 * err, (dist, val, err, g[sel].mean())
    # the worm estimator at distance d0 agrees with the operator-count estimator of the bonds
    assert abs(2 * r.green[0] - r.bond_kinetic.mean()) < 4 * math.hypot(2 * r.green_err[0], r.bond_kinetic_err.mean())
    assert abs(r.condensate_fraction - ex.condensate_fraction) < 4 * r.condensate_fraction_err
    assert r.green_matrix.shape == (7, 7)


def test_gauge_for_negative_hopping_on_a_bipartite_graph():
    """t < 0 on an even ring: same thermodynamics, G(i, j) picks up the gauge signs."""
    a = _ring(6)
    kw = dict(U=3.0, mu=1.0, beta=1.5, nmax=2)
    ex = exact_thermal(a, t=-1.0, **kw)
    r = qmc(a, t=-1.0, sweeps=6000, thermalization=1000, seed=2, progress=False, **kw)
    _check(r, ex)
    assert np.all(r.bond_kinetic < 0)
    assert np.all(np.abs(r.bond_kinetic - ex.bond_kinetic) < 4.5 * r.bond_kinetic_err)
    assert np.all(np.abs(r.green_matrix - ex.green) < 0.05)


def test_weighted_adjacency():
    a = _ring(5, [1.0, 0.5, 2.0, 1.0, 0.3])
    kw = dict(U=2.0, mu=0.7, beta=1.2, nmax=2)
    ex = exact_thermal(a, **kw)
    r = qmc(a, sweeps=6000, thermalization=1000, seed=3, progress=False, **kw)
    _check(r, ex)
    assert r.distance_kind == "graph (hops)"
    # a self-loop is refused in one sentence, not dropped
    loop = sp.lil_matrix(a)
    loop[2, 2] = 1.0
    with pytest.raises(ValueError, match="self-loop") as exc:
        qmc(loop.tocsr(), **kw)
    assert "\n" not in str(exc.value)


def test_sites_without_bonds_are_added_exactly(tmp_path):
    """Fuzz case: "an isolated site is refused although docs/qmc.md says isolated sites are added exactly".

    A site without bonds is an independent single-site problem: the chain runs on the bonded sites and
    the site's exact thermal averages are added. Against exact_thermal of the whole graph (a weighted
    5-ring with a site without bonds numbered 2), and bit for bit against the chain of the ring alone
    (same seed: the same chain) plus one exact site.
    """
    ring = _ring(5, [1.0, 0.5, 2.0, 1.0, 0.3])
    grown = sp.lil_matrix(ring)
    grown.resize((6, 6))
    order = np.array([0, 1, 5, 2, 3, 4])            # the bondless site 5 becomes site 2
    a = grown.tocsr()[order][:, order]
    kw = dict(U=2.0, mu=0.7, beta=1.2, nmax=2)
    ex = exact_thermal(a, **kw)
    r = qmc(a, sweeps=6000, thermalization=1000, seed=3, progress=False, **kw)
    _check(r, ex, names=("energy", "density", "compressibility", "condensate_fraction"))
    assert r.sites == 6 and r.site_density.shape == (6,) and r.site_density_err[2] == 0
    assert np.all(np.abs(r.site_density - ex.site_density) < 4 * r.site_density_err + 1e-12)
    assert np.all(np.abs(r.green_matrix - ex.green) < 0.05)
    assert r.green_matrix[2, 2] == r.site_density[2] and not np.any(np.delete(r.green_matrix[2], 2))
    assert sorted(map(tuple, r.bonds.tolist())) == [(0, 1), (0, 5), (1, 3), (3, 4), (4, 5)]
    assert r.green_distance[-1] == np.inf and r.green[-1] == 0 and r.green_pairs.sum() == 6 * 5
    assert any("without bonds" in n for n in r.notes)
    # the same chain as the ring's: only the exact site differs
    alone = qmc(ring, sweeps=6000, thermalization=1000, seed=3, progress=False, **kw)
    n = np.arange(3.0)
    eps = 0.5 * kw["U"] * n * (n - 1) - kw["mu"] * n
    w = np.exp(-kw["beta"] * (eps - eps.min()))
    w /= w.sum()
    e1, n1, v1 = w @ eps, w @ n, w @ n ** 2 - (w @ n) ** 2
    assert r.energy == pytest.approx(alone.energy + e1, rel=1e-13) and r.energy_err == alone.energy_err
    assert r.density == pytest.approx((5 * alone.density + n1) / 6, rel=1e-13)
    assert r.compressibility == pytest.approx((5 * alone.compressibility + kw["beta"] * v1) / 6, rel=1e-13)
    assert r.site_density[2] == pytest.approx(n1, rel=1e-13)
    # the bondless site enters the chain's identity: a checkpoint of the ring alone is not resumed
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hl.bosons.QMCWarning)        # short chains
        qmc(ring, sweeps=20, thermalization=10, seed=3, progress=False, checkpoint=tmp_path, **kw)
        with pytest.raises(ValueError, match="other parameters"):
            qmc(a, sweeps=20, thermalization=10, seed=3, progress=False, checkpoint=tmp_path, **kw)
        # merging chains of the graph keeps the exact part
        m = merge_chains([r, qmc(a, sweeps=1000, thermalization=200, seed=4, progress=False, **kw)])
    assert m.sites == 6 and m.site_density_err[2] == 0
    _check(m, ex)
    # a graph without any bond is still refused in one sentence
    with pytest.raises(ValueError, match="no bonds") as exc:
        qmc(sp.csr_matrix((3, 3)), **kw)
    assert "\n" not in str(exc.value)


def test_sign_problems_are_refused():
    with pytest.raises(ValueError, match="sign problem"):
        qmc(HEPTAGON, U=1.0, mu=0.0, beta=1.0, nmax=1, t=-1.0)          # odd ring, t < 0
    with pytest.raises(ValueError, match="flux"):
        qmc(_ring(4) * (1 + 0.5j), U=1.0, mu=0.0, beta=1.0, nmax=1)
    frustrated = _ring(3, [1.0, 1.0, -1.0])
    with pytest.raises(ValueError, match="sign problem"):
        qmc(frustrated, U=1.0, mu=0.0, beta=1.0, nmax=1)
    with pytest.raises(ValueError, match="flux"):
        qmc(HEPTAGON, U=1.0, mu=0.0, beta=1.0, nmax=1, t=1j)


@pytest.mark.parametrize("kw, match", [
    (dict(beta=0.0), "beta"), (dict(beta=-1.0), "beta"), (dict(nmax=0), "nmax"), (dict(U=math.nan), "U"),
    (dict(mu=math.inf), "mu"), (dict(sweeps=0), "sweeps"), (dict(thermalization=-1), "thermalization"),
    (dict(seed=-3), "seed"), (dict(beta=math.nan), "beta"),
])
def test_bad_input_one_sentence(kw, match):
    args = dict(U=1.0, mu=0.0, beta=1.0, nmax=1, sweeps=10)
    args.update(kw)
    with pytest.raises(ValueError, match=match) as exc:
        qmc(HEPTAGON, **args)
    assert "\n" not in str(exc.value)


def test_bad_systems():
    with pytest.raises(ValueError, match="system"):
        qmc("heptagon", U=1.0, mu=0.0, beta=1.0, nmax=1)
    with pytest.raises(ValueError, match="no bonds"):
        qmc(sp.csr_matrix((3, 3)), U=1.0, mu=0.0, beta=1.0, nmax=1)
    with pytest.raises(ValueError, match="exact_thermal diagonalises at most"):
        exact_thermal(hl.ring_lattice(7, 3, 2), U=1.0, mu=0.0, beta=1.0, nmax=1)


def test_memory_refused_before_work():
    with pytest.raises(MemoryError, match="operator string"):
        qmc(HEPTAGON, U=1.0, mu=0.0, beta=1e15, nmax=1)


def test_resume_is_bit_identical(tmp_path):
    kw = dict(U=3.0, mu=1.0, beta=2.0, nmax=2, thermalization=300, seed=9, progress=False)
    full = qmc(HEPTAGON, sweeps=1200, **kw)
    first = qmc(HEPTAGON, sweeps=600, checkpoint=tmp_path, **kw)
    resumed = qmc(HEPTAGON, sweeps=1200, checkpoint=tmp_path, **kw)
    assert first.sweeps == 600
    a, b = full.as_dict(), resumed.as_dict()
    a.pop("seconds"), b.pop("seconds")
    assert a == b
    with pytest.raises(ValueError, match="other parameters"):
        qmc(HEPTAGON, sweeps=1200, checkpoint=tmp_path, **{**kw, "seed": 10})


@pytest.mark.filterwarnings("ignore::hyperlattice.bosons.sse.QMCWarning")   # short chains: reproducibility only
def test_reproducible_and_seeds_differ():
    kw = dict(U=3.0, mu=1.0, beta=2.0, nmax=2, sweeps=500, thermalization=100, progress=False)
    a, b, c = qmc(HEPTAGON, seed=1, **kw), qmc(HEPTAGON, seed=1, **kw), qmc(HEPTAGON, seed=2, **kw)
    assert a.energy == b.energy and a.density == b.density
    assert a.energy != c.energy


def test_merge_chains():
    kw = dict(U=4.0, mu=1.0, beta=2.0, nmax=2, sweeps=3000, thermalization=500, progress=False)
    runs = [qmc(HEPTAGON, seed=s, **kw) for s in (1, 2, 3, 4)]
    m = merge_chains(runs)
    assert m.chains == 4 and m.sweeps == 12000 and m.seed is None and m.seeds == (1, 2, 3, 4)
    assert m.energy == pytest.approx(np.mean([r.energy for r in runs]))
    assert m.energy_err == pytest.approx(math.sqrt(sum(r.energy_err ** 2 for r in runs)) / 4)
    _check(m, exact_thermal(HEPTAGON, U=4.0, mu=1.0, beta=2.0, nmax=2))
    with pytest.raises(ValueError, match="seed occurs twice"):
        merge_chains([runs[0], runs[0]])
    other = qmc(HEPTAGON, seed=9, **{**kw, "U": 5.0})
    with pytest.raises(ValueError, match="U differs"):
        merge_chains([runs[0], other])
    with pytest.raises(ValueError, match="non-empty"):
        merge_chains([])


@pytest.mark.filterwarnings("ignore::hyperlattice.bosons.sse.QMCWarning")   # a short chain: the round trip only
def test_result_round_trip_and_summary():
    r = qmc(HEPTAGON, U=3.0, mu=1.0, beta=1.0, nmax=2, sweeps=500, thermalization=100, seed=4, progress=False)
    back = Result.from_dict(json.loads(r.to_json()))
    assert isinstance(back, QMCResult) and back.energy == r.energy
    assert np.array_equal(back.green_matrix, r.green_matrix)
    s = r.summary()
    for key in ("sites", "energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err",
                "tau_int"):
        assert key in s
    json.dumps(s)
    assert [row["observable"] for row in r.table()] == ["energy", "density", "compressibility"]
    assert "energy" in str(r)


def test_exact_thermal_low_temperature_is_the_ground_state():
    """At large beta the grand-canonical energy is E0 of the sector that minimises E0(N) (ED)."""
    kw = dict(U=6.0, mu=2.0, nmax=2)
    levels = [hl.bosons.bose_hubbard(HEPTAGON, n, 2, 6.0, mu=2.0, levels=1).energies[0] for n in range(0, 15)]
    ex = exact_thermal(HEPTAGON, beta=60.0, **kw)
    assert ex.energy == pytest.approx(min(levels), abs=1e-6)
    assert ex.density * 7 == pytest.approx(int(np.argmin(levels)), abs=1e-6)


def test_mcstats():
    rng = np.random.default_rng(0)
    white = rng.normal(size=8192)
    b = mcstats.binning(white, variance=1.0)
    assert b.converged and 0.4 < b.tau_int < 0.6
    # AR(1) with rho = 0.8: tau_int = (1 + rho) / (2 (1 - rho)) = 4.5
    x = np.empty(2 ** 16)
    x[0] = 0.0
    e = rng.normal(size=x.size)
    for k in range(1, x.size):
        x[k] = 0.8 * x[k - 1] + e[k]
    b = mcstats.binning(x, variance=float(np.var(x)))
    assert 3.5 < b.tau_int < 5.5
    v, err = mcstats.jackknife(lambda m: m * m, white[:100] + 3.0)
    assert abs(v - 9.0) < 5 * err
    assert mcstats.combine_independent([1.0, 3.0], [1.0, 1.0], [1, 1]) == (2.0, math.sqrt(2) / 2)


def test_a_string_still_filling_up_is_flagged_not_silently_measured():
    """One thermalisation sweep at beta = 20 leaves the operator string full: the result says so."""
    import hyperlattice as hl
    from hyperlattice.bosons import QMCWarning, qmc

    with pytest.warns(QMCWarning) as rec:
        r = qmc(hl.ring_lattice(7, 3, 2), U=6.0, mu=3.0, beta=20.0, nmax=3, sweeps=4, thermalization=1, seed=1,
                progress=False)
    assert not r.converged
    assert any("operator string" in str(w.message) and "nearly full" in str(w.message) for w in rec)


def test_empty_system_at_large_beta_mu_returns_a_result():
    """Hard-core bosons at beta |mu| = 269 (an empty lattice, all-to-all weak couplings).

    Found by the lobe helper through compare.qmc_lobe.xy_qubit_check: almost every loop start is
    refused there (n_i - 1 < 0), the mean loop length is ~0, and the loops per sweep were set to
    ~10^9, so the kernel ran for hours and an interrupt surfaced as numba's "SystemError ...
    returned a result with an exception set". The loops per sweep are now capped at 4 per operator.
    """
    n = 7
    a = sp.csr_matrix(0.0372 * (np.ones((n, n)) - np.eye(n)))
    kw = dict(U=0.0, mu=-1.0, beta=268.6, nmax=1)
    r = qmc(a, sweeps=300, thermalization=200, seed=1, progress=False, measure_green=False, **kw)
    ex = exact_thermal(a, **kw)
    assert r.loops_per_sweep <= 4 * (r.string_length + 16)
    assert abs(r.density) < 1e-6 and abs(r.energy - ex.energy) < 1e-6
