"""The strong-coupling expansion of the Mott lobes (bosons/strong_coupling.py) against brute force.

A perturbation series is right when its error vanishes faster than its last term: the lobe
boundaries of the third-order expansion must agree with exact diagonalisation to O((t/U)^4) on any
graph, so err/t^3 -> 0 linearly in t. The brute-force ED here is a plain dense Fock-space matrix
(independent of bosons/ed.py), on weighted graphs with and without triangles, filling 1 and 2.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice.bosons import strong_coupling as sc


def _fock(M, N, nmax):
    out = []

    def rec(i, left, cur):
        if i == M - 1:
            if left <= nmax:
                out.append(tuple(cur + [left]))
            return
        for k in range(min(left, nmax) + 1):
            rec(i + 1, left - k, cur + [k])

    rec(0, N, [])
    return out


def _ground(A, N, t, nmax):
    """Lowest eigenvalue of the Bose-Hubbard model (U = 1, mu = 0) with N bosons, cutoff nmax."""
    M = A.shape[0]
    S = _fock(M, N, nmax)
    idx = {s: i for i, s in enumerate(S)}
    H = np.zeros((len(S), len(S)))
    for a, s in enumerate(S):
        H[a, a] = 0.5 * sum(k * (k - 1) for k in s)
        for i in range(M):
            if s[i] == 0:
                continue
            for j in range(M):
                if A[i, j] == 0 or s[j] == nmax:
                    continue
                s2 = list(s)
                s2[i] -= 1
                s2[j] += 1
                H[idx[tuple(s2)], a] -= t * A[i, j] * np.sqrt(s[i] * (s[j] + 1))
    return np.linalg.eigvalsh(H)[0]


def _exact_mu(A, n, t):
    M = A.shape[0]
    # a site reaches n + 3 only at sixth order in t: the cutoff n + 3 is exact to O(t^5)
    e0, ep, eh = (_ground(A, n * M + k, t, n + 3) for k in (0, 1, -1))
    return ep - e0, e0 - eh


def _graph(edges, m, weights=None):
    A = np.zeros((m, m))
    for k, (i, j) in enumerate(edges):
        A[i, j] = A[j, i] = 1.0 if weights is None else weights[k]
    return A


_PENDANT = _graph([(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (0, 5)], 6)                  # odd cycle, no triangle
_TRIANGLES = _graph([(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (4, 1), (0, 3)], 5,
                    weights=[0.9, 1.3, 0.7, 1.1, 0.6, 1.4, 0.8])                           # weighted, triangles


@pytest.mark.parametrize("A, n", [(_PENDANT, 1), (_TRIANGLES, 1), (_TRIANGLES[:4, :4], 2)],
                         ids=["pentagon+pendant", "weighted-triangles", "filling-2"])
def test_third_order_error_is_fourth_order(A, n):
    # err(t)/t^3 must shrink linearly with t: the ratio between t = 0.004 and 0.002 is 2 for an
    # O(t^4) error (it would be 1 for a wrong third-order coefficient)
    errs = {}
    for t in (0.002, 0.004):
        mp, mm = _exact_mu(A, n, t)
        sp_, sm_ = sc.excitation_energies(sp.csr_matrix(A), [t], filling=n)
        errs[t] = (mp - sp_[0], mm - sm_[0])
        assert abs(errs[t][0]) < 50 * t**3 and abs(errs[t][1]) < 50 * t**3
    for k in (0, 1):
        a, b = errs[0.002][k], errs[0.004][k]
        if abs(b) > 0.05 * 0.004**3:   # a fourth-order term large enough to dominate at these t
            assert 1.6 < (b / 0.004**3) / (a / 0.002**3) < 2.4


def test_lower_orders_fail_the_same_check():
    # the check above has teeth: dropping the third order leaves an O(t^3) error
    A = _TRIANGLES
    t = 0.004
    mp, _ = _exact_mu(A, 1, t)
    p2, _ = sc.excitation_energies(sp.csr_matrix(A), [t], order=2)
    p3, _ = sc.excitation_energies(sp.csr_matrix(A), [t], order=3)
    assert abs(mp - p2[0]) > 10 * abs(mp - p3[0])


@pytest.mark.slow          # the ED kernels compile (~20 s)
def test_heptagon_against_package_ed():
    # the {7,3} heptagon through bosons.charge_gap (the package's ED): the gap to O(t^4)
    lat = hl.ring_lattice(7, 3, 1)
    t = 0.01
    gap = hl.bosons.charge_gap(lat, 7, 8, 1.0, t=t).gap
    mp, mm = sc.excitation_energies(lat, [t])
    assert abs(gap - (mp[0] - mm[0])) < 30 * t**4


def _square(L):
    idx = np.arange(L * L).reshape(L, L)
    rows = np.concatenate([idx.ravel(), idx.ravel()])
    cols = np.concatenate([np.roll(idx, 1, 0).ravel(), np.roll(idx, 1, 1).ravel()])
    A = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(L * L, L * L))
    return (A + A.T).tocsr()


def test_hypercubic_closed_form_is_the_square_lattice_graph():
    # on a periodic square lattice the uniform vector is the lowest eigenvector: the graph
    # expansion reduces to the coordination-z closed form (Freericks-Monien's hypercubic lattice)
    A = _square(6)
    ts = [0.01, 0.03, 0.05]
    mp, mm = sc.excitation_energies(A, ts)
    hp, hm = sc.hypercubic_boundaries(2, ts)
    assert np.allclose(mp, hp, atol=1e-12) and np.allclose(mm, hm, atol=1e-12)


@pytest.mark.parametrize("d, tip", [(1, 0.215250437), (2, 0.067960429), (3, 0.041951131)])
def test_hypercubic_tips(d, tip):
    # 1D: the gap 1 - 6x + 5x^2 + 6x^3 closes at the real root 0.21525; 2D, 3D from the same forms
    from scipy.optimize import brentq

    x = brentq(lambda v: float(np.subtract(*sc.hypercubic_boundaries(d, [v]))[0]), 1e-6, 0.4 / d)
    assert x == pytest.approx(tip, abs=1e-8)


def test_ring_tip_and_first_order():
    ring = sp.csr_matrix(np.roll(np.eye(10), 1, 1) + np.roll(np.eye(10), -1, 1))
    assert sc.strong_coupling_tip(ring)[0] == pytest.approx(0.215250437, abs=1e-7)
    # first order: gap 1 - 3 z x for a z-regular graph
    assert sc.strong_coupling_tip(ring, order=1)[0] == pytest.approx(1 / 6, abs=1e-9)
    assert sc.strong_coupling_tip(_square(4), order=1)[0] == pytest.approx(1 / 12, abs=1e-9)


def test_sparse_and_dense_paths_agree(monkeypatch):
    lat = hl.ring_lattice(7, 3, 2)
    dense = sc.excitation_energies(lat, [0.03, 0.08])
    monkeypatch.setattr(sc, "_DENSE_SITES", 10)
    sparse = sc.excitation_energies(lat, [0.03, 0.08])
    assert np.allclose(dense, sparse, atol=1e-9)
    # t = 0 on the sparse route: the atomic limit, not an ARPACK error on the zero matrix
    mp, mm = sc.excitation_energies(lat, [0.0])
    assert mp[0] == 1.0 and mm[0] == 0.0


def test_lobe_result_round_trip():
    lobe = sc.strong_coupling_lobe(hl.ring_lattice(7, 3, 2))
    assert lobe.t_over_U.size == 41 and lobe.t_over_U[-1] == pytest.approx(lobe.tip_t_over_U)
    assert lobe.mu_plus[0] == 1.0 and lobe.mu_minus[0] == 0.0
    assert np.all(np.diff(lobe.mu_plus) < 0) and np.all(np.diff(lobe.mu_minus) > 0)
    back = type(lobe).from_dict(lobe.as_dict())
    assert np.array_equal(back.mu_plus, lobe.mu_plus) and back.tip_t_over_U == lobe.tip_t_over_U


@pytest.mark.parametrize("kwargs, match", [
    ({"filling": 0}, "filling"), ({"order": 4}, "order"), ({"t_over_U": [-0.1]}, "t_over_U"),
])
def test_bad_input(kwargs, match):
    ring = sp.csr_matrix(np.roll(np.eye(5), 1, 1) + np.roll(np.eye(5), -1, 1))
    with pytest.raises(ValueError, match=match):
        sc.strong_coupling_lobe(ring, **kwargs)


def test_bad_graph():
    with pytest.raises(ValueError, match="symmetric"):
        sc.strong_coupling_tip(sp.csr_matrix(np.triu(np.ones((4, 4)), 1)))
    with pytest.raises(ValueError, match="diagonal"):
        sc.strong_coupling_tip(sp.csr_matrix(np.ones((4, 4))))
