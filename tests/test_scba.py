"""The self-consistent Born approximation: continuum local Green function, convergence, and the
graph ensemble average in the weak-disorder limit (the leading W^2 correction)."""

from __future__ import annotations

import numpy as np
import pytest

from hyperlattice import ring_lattice
from hyperlattice.compare.disorder import compare_scba, graph_scba
from hyperlattice.continuum.scba import band_cutoff, continuum_local_green, scba
from hyperlattice.errors import ConvergenceError
from hyperlattice.graph.green import graph_green


def test_local_green_is_a_resolvent_of_one_state_per_site():
    lam_c, e_c = band_cutoff(7, 3)
    assert lam_c == pytest.approx(1 + 112 + 1 / 3) and 3.0 < e_c < 3.5
    for om in (-2.9 + 0.1j, 0.5j, 2.0 + 0.01j):
        g = continuum_local_green(om)
        assert g.imag > 0                                   # retarded: Im G > 0 for Im omega > 0
        assert continuum_local_green(np.conj(om)) == pytest.approx(np.conj(g), rel=1e-12)
    assert continuum_local_green(-3.5).imag == 0 and continuum_local_green(-3.5).real > 0
    # far from the band G_loc -> -1/omega - <E>/omega^2: the states per site integrate to 1
    om = 1e4j
    assert continuum_local_green(om) == pytest.approx(-1 / om, rel=1e-3)
    with pytest.raises(ValueError, match="inside the continuum band"):
        continuum_local_green(0.0)


def test_scba_converges_and_starts_at_the_born_term():
    om = -2.9 + 0.1j
    assert scba(om, 0.0).self_energy == 0
    gaps = []
    for w2 in (0.02, 0.01):
        res = scba(om, w2, tol=1e-12)
        assert res.residual <= 1e-12 * max(1, abs(res.omega_shifted))
        assert res.self_energy.imag > 0
        # Sigma = w^2 G_loc(omega + Sigma): the self-consistency correction is O(w^4)
        gaps.append(abs(res.self_energy - res.born) / abs(res.born))
    assert gaps[1] == pytest.approx(gaps[0] / 2, rel=0.1)
    with pytest.raises(ConvergenceError):
        scba(om, 0.5, max_iter=1)


def test_graph_scba_first_order_is_second_order_perturbation_theory():
    lat = ring_lattice(7, 3, 3)
    om = -2.9 + 0.2j
    g0 = graph_green(lat, om)
    w2 = 1e-6
    sig, it = graph_scba(lat, om, w2)
    assert np.allclose(sig, w2 * np.diag(g0), rtol=1e-5, atol=0)


def test_scba_against_the_graph_ensemble_at_weak_disorder():
    lat = ring_lattice(7, 3, 4)
    cmp = compare_scba(lat, -2.9 + 0.2j, [0.5, 1.0], realizations=16, seed=0, source=0)
    for i in range(2):
        # the W^2 correction is resolved by the average ...
        assert cmp.rel_clean[i] > 3 * cmp.rel_noise[i]
        # ... and the graph SCBA predicts it to within the statistical error
        assert cmp.rel_graph_scba[i] < 2 * cmp.rel_noise[i] + 0.005
        # the projection on the exact second-order term w^2 G0 diag(G0) G0 is 1 in the limit
        assert cmp.born_ratio[i] == pytest.approx(1.0, abs=0.25)
    # the continuum self-energy matches the graph's interior average to ~15 %
    assert np.all(np.abs(cmp.sigma_continuum - cmp.sigma_graph) < 0.2 * np.abs(cmp.sigma_graph))
    # and the continuum SCBA explains most of the change: better than the clean column at W = 1
    assert cmp.rel_continuum_scba[1] < 0.6 * cmp.rel_clean[1]
    assert cmp.continuum_floor < cmp.rel_continuum_scba[1]
