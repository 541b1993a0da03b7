"""Slow checks of the SSE QMC: honest error bars over many seeds, and the low-temperature limit."""

from __future__ import annotations

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.bosons import exact_thermal, qmc

HEPTAGON = hl.ring_lattice(7, 3, 1)


@pytest.mark.slow
def test_error_bars_cover_the_exact_value():
    """Over 40 independent chains the exact value lies within 1 sigma about 68 % of the time and
    within 2 sigma about 95 % (binomial bounds at about 3 standard deviations of the count)."""
    kw = dict(U=4.0, mu=1.0, beta=2.0, nmax=2)
    ex = exact_thermal(HEPTAGON, **kw)
    hits1 = hits2 = total = 0
    for seed in range(40):
        r = qmc(HEPTAGON, sweeps=3000, thermalization=500, seed=100 + seed, progress=False, **kw)
        for name in ("energy", "density", "compressibility"):
            z = abs(getattr(r, name) - getattr(ex, name)) / getattr(r, name + "_err")
            hits1 += z < 1
            hits2 += z < 2
            total += 1
    assert 0.50 * total <= hits1 <= 0.85 * total, (hits1, total)
    assert 0.85 * total <= hits2, (hits2, total)


@pytest.mark.slow
def test_large_beta_reaches_the_ground_state_sector():
    """At beta = 30 the QMC energy is the ED ground-state energy of the particle number it picks."""
    U, mu = 8.0, 3.0
    levels = {n: hl.bosons.bose_hubbard(HEPTAGON, n, 2, U, mu=mu, levels=1).energies[0] for n in range(5, 10)}
    r = qmc(HEPTAGON, U=U, mu=mu, beta=30.0, nmax=2, sweeps=4000, thermalization=1000, seed=7, progress=False)
    n = int(round(r.density * 7))
    assert n == min(levels, key=levels.get)
    assert abs(r.energy - levels[n]) < 4 * r.energy_err + 1e-3


@pytest.mark.slow
def test_soft_core_nmax3_and_bolza_like_cluster():
    kw = dict(U=2.0, mu=0.5, beta=1.0, nmax=3, t=0.7)
    ex = exact_thermal(HEPTAGON, **kw)
    r = qmc(HEPTAGON, sweeps=20000, thermalization=2000, seed=3, progress=False, **kw)
    for name in ("energy", "density", "compressibility"):
        assert abs(getattr(r, name) - getattr(ex, name)) < 4 * getattr(r, name + "_err")
    c = hl.graph.clusters.pbc_cluster(5, 5, "PSL(2,5)")
    kw = dict(U=0.0, mu=-0.5, beta=2.0, nmax=1)
    ex = exact_thermal(c, **kw)
    r = qmc(c, sweeps=10000, thermalization=1000, seed=4, progress=False, **kw)
    for name in ("energy", "density", "compressibility"):
        assert abs(getattr(r, name) - getattr(ex, name)) < 4 * getattr(r, name + "_err")
    assert np.all(np.abs(r.green_matrix - ex.green)[~np.eye(12, dtype=bool)] < 0.05)
