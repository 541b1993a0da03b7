"""Circuit-QED qubits below the band: exact bound state vs leading order, spin model, graph vs continuum."""

import math

import numpy as np
import pytest

from hyperlattice.compare.qubits import bound_state_sizes, exchange_comparison
from hyperlattice.graph.lattice import line_graph, ring_lattice
from hyperlattice.graph.qubits import bound_state, qubit_hamiltonian, spin_model


@pytest.fixture(scope="module")
def lat4():
    return ring_lattice(7, 3, 3)   # 112 sites: dense reference eigensolves stay fast


def test_bound_state_is_the_exact_eigenstate(lat4):
    bs = bound_state(lat4, 3, -3.2, 0.3)
    w, V = np.linalg.eigh(qubit_hamiltonian(lat4, [3], -3.2, 0.3).toarray())
    assert bs.energy == pytest.approx(w[0], abs=1e-13)
    v = np.abs(V[:-1, 0]) / np.linalg.norm(V[:-1, 0])
    assert np.allclose(bs.photon, v, atol=1e-12)
    assert bs.qubit_weight == pytest.approx(V[-1, 0] ** 2, abs=1e-12)
    assert bs.residual < 1e-12 and bs.energy < bs.omega_q


def test_leading_order_profile_difference_scales_as_g2(lat4):
    errs = [bound_state(lat4, 0, -3.1, g).profile_error for g in (0.2, 0.1, 0.05)]
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    assert ratios == pytest.approx([4.0, 4.0], rel=0.1)        # measured 3.74, 3.93
    # energy: E_b - (omega_q - g^2 G_jj(omega_q)) = O(g^4)
    de = [abs(b.energy - b.energy_leading) for b in (bound_state(lat4, 0, -3.1, g) for g in (0.1, 0.05))]
    assert de[0] / de[1] == pytest.approx(16.0, rel=0.1)


def test_spin_model_spectrum_to_order_g2(lat4):
    sites = [0, 9, 40, 100]
    errs = []
    for g in (0.04, 0.02):
        sm = spin_model(lat4, sites, -3.3, g)
        h = sm.matrix().toarray()
        w = np.linalg.eigvalsh(qubit_hamiltonian(lat4, sites, -3.3, g).toarray())[:4]
        errs.append(np.max(np.abs(np.linalg.eigvalsh(h) - w)))
    assert errs[0] / errs[1] > 10       # O(g^4): 16 for halving g
    J = sm.couplings
    assert np.allclose(J, J.T) and np.all(J[~np.eye(4, dtype=bool)] > 0) and np.all(np.diag(J) == 0)
    assert np.all(sm.lamb_shift < 0)
    edges = sm.edges()
    assert len(edges) == 6 and all(a < b and J[a, b] == v for a, b, v in edges)
    assert sm.matrix(threshold=1.0).nnz == 4 + 2         # only the largest coupling and the diagonal
    with pytest.raises(ValueError, match="repeats"):
        spin_model(lat4, [0, 0], -3.3, 0.1)


def test_exchange_graph_vs_continuum():
    ex = exchange_comparison(ring_lattice(7, 3, 6), -3.1, 0.05, 0)
    assert ex.rel_l2 < 0.08                              # measured 0.057
    assert ex.decay_length_graph == pytest.approx(ex.decay_length_continuum, rel=0.02)
    assert np.all(ex.graph > 0)


def test_line_graph_resonators():
    lg = line_graph(ring_lattice(7, 3, 5))
    bs = bound_state(lg, 0, -4.1, 0.05)
    assert bs.residual < 1e-12 and bs.kind == "line_graph"
    ex = exchange_comparison(lg, -4.1, 0.05, 0)
    assert ex.rel_l2 < 0.1                               # measured 0.052 (push-through identity + eq21)
    nn = np.isnan(ex.continuum)
    assert nn.sum() == 4                                 # the resonators sharing an endpoint with site 0


def test_bound_state_size_against_detuning():
    lat = ring_lattice(7, 3, 6)
    res = bound_state_sizes(lat, [-3.5, -3.2, -3.0, -2.95], 0.05)
    assert np.all(np.diff(res.size_graph) > 0) and np.all(res.detuning > 0)
    assert np.allclose(res.size_continuum, res.size_graph, rtol=0.05)
    # the continuum decay length 1/(2 Delta) stays below 2R = 1 down to the BF bound
    assert np.all(res.decay_length_asymptotic < 1.0)


def test_above_band_refused(lat4):
    with pytest.raises(ValueError, match="not below the band"):
        bound_state(lat4, 0, -2.0, 0.1)
    with pytest.raises(ValueError, match="nonzero"):
        bound_state(lat4, 0, -3.2, 0.0)
    assert math.isfinite(bound_state(lat4, 0, -3.2, -0.1).energy)    # the sign of g does not matter
