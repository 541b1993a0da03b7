"""Kernel polynomial method: against exact diagonalisation, error-bar scaling, exact moments."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from hyperlattice.graph import kpm
from hyperlattice.graph.kpm import KPMDos, bulk_dos, graph_operator, jackson_kernel, kpm_dos, local_dos, spectral_bound
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency
from hyperlattice.graph.walks import chebyshev_from_walks, closed_walks
from hyperlattice.results import Result


def _prism(n: int) -> np.ndarray:
    """Neighbour table of the prism C_n x K_2: a small 3-regular graph."""
    i = np.arange(n)
    top = np.column_stack([(i - 1) % n, (i + 1) % n, i + n])
    bot = np.column_stack([n + (i - 1) % n, n + (i + 1) % n, i])
    return np.vstack([top, bot]).astype(np.int32)


def _table_matrix(t: np.ndarray) -> sp.csr_matrix:
    n, w = t.shape
    return sp.csr_matrix((np.ones(n * w), (np.repeat(np.arange(n), w), t.ravel())), shape=(n, n))


def _exact_moments(energies: np.ndarray, scale: float, m: int) -> np.ndarray:
    return np.cos(np.outer(np.arange(m), np.arccos(energies / scale))).mean(axis=1)


@pytest.fixture(scope="module")
def flake():
    return ring_lattice(7, 3, 4)


def test_bounds_are_exact(flake):
    assert spectral_bound(flake) == 3.0  # the largest degree; boundary sites have 2
    assert spectral_bound(_prism(5)) == 3.0
    ev = np.linalg.eigvalsh(-adjacency(flake).toarray())
    assert np.abs(ev).max() <= 3.0
    # a periodic (regular) graph attains -q with the uniform state: the bound is sharp
    ev = np.linalg.eigvalsh(-_table_matrix(_prism(5)).toarray())
    assert ev[0] == pytest.approx(-3.0, abs=1e-12)


def test_kpm_histogram_agrees_with_exact_diagonalisation(flake):
    """Counts per energy bin agree with the exact eigenvalue histogram within the kernel
    resolution: the difference is bounded by the eigenvalues within 3 kernel widths of a bin edge
    (the Jackson kernel moves weight only that far) plus 4 standard errors."""
    ev = np.linalg.eigvalsh(-adjacency(flake).toarray())
    res = kpm_dos(flake, 256, vectors=32, seed=3)
    edges = np.linspace(-2.9, 2.9, 12)
    _, cum, err = res.integrated(edges)
    kpm_counts = np.diff(cum)
    exact_counts = np.diff(np.searchsorted(ev, edges)) / ev.size
    for b in range(len(edges) - 1):
        leak = 0.0
        for e in (edges[b], edges[b + 1]):
            w = 3.0 * res.kernel_width(e)
            leak += np.count_nonzero(np.abs(ev - e) < w) / ev.size
        tol = leak + 4.0 * math.hypot(err[b], err[b + 1])
        assert abs(kpm_counts[b] - exact_counts[b]) <= tol, (b, kpm_counts[b], exact_counts[b], tol)


def test_stochastic_moments_agree_with_exact_trace(flake):
    ev = np.linalg.eigvalsh(-adjacency(flake).toarray())
    for kind in ("rademacher", "phase"):
        res = kpm_dos(flake, 64, vectors=24, seed=5, kind=kind)
        ref = _exact_moments(ev, res.scale, 64)
        z = (res.mu[1:] - ref[1:]) / res.mu_err[1:]
        assert np.sqrt(np.mean(z**2)) < 2.0  # errors are honest (about 1 on average)
        assert np.abs(z).max() < 5.0
        assert res.mu[0] == pytest.approx(1.0, abs=1e-12 if kind == "rademacher" else 1e-12)


def test_error_bars_shrink_like_inverse_sqrt_samples():
    lat = ring_lattice(7, 3, 5)
    errs = {}
    for r in (16, 64, 256):
        res = kpm_dos(lat, 32, vectors=r, seed=11)
        errs[r] = float(np.mean(res.mu_err[1:]))
    # the fitted exponent of err ~ R**-a
    slope = np.polyfit(np.log(list(errs)), np.log(list(errs.values())), 1)[0]
    assert -0.62 < slope < -0.38, errs
    # and runs with more vectors extend runs with fewer (vector r from default_rng([seed, r]))
    a = kpm_dos(lat, 16, vectors=4, seed=2)
    b = kpm_dos(lat, 16, vectors=8, seed=2)
    assert np.array_equal(a.mu_vectors, b.mu_vectors[:4])


def test_local_moments_equal_exact_walks():
    lat = ring_lattice(7, 3, 6)
    res = local_dos(lat, 0, 40)
    assert res.exact_moments == 2 * 10 + 2  # 2 d_b + 2 with d_b = 10 for site 0 of 6 rings
    walks = closed_walks(7, 3, res.exact_moments - 1)
    ref = chebyshev_from_walks(walks, res.scale)
    assert np.abs(res.mu[: res.exact_moments] - ref).max() < 1e-12
    # beyond the proven depth the flake's moments differ (its boundary is seen)
    more = chebyshev_from_walks(closed_walks(7, 3, 39), res.scale)
    assert np.abs(res.mu - more).max() > 1e-6


def test_bulk_moments_agree_with_walks_within_errors():
    lat = ring_lattice(7, 3, 8)
    res = bulk_dos(lat, vectors=32, seed=1)
    assert res.excluded_rings == 4 and res.moments == res.exact_moments >= 2 * 4 + 2
    assert res.traced_sites == int(np.count_nonzero(np.asarray(lat.ring) <= 4))
    ref = chebyshev_from_walks(closed_walks(7, 3, res.moments - 1), res.scale)
    z = (res.mu[1:] - ref[1:]) / res.mu_err[1:]
    assert np.abs(z).max() < 5.0


@pytest.mark.slow
def test_table_and_csr_kernels_agree_and_parallel_equals_serial():
    t = _prism(40)
    a = kpm_dos(t, 40, vectors=3, seed=0)
    b = kpm_dos(_table_matrix(t), 40, vectors=3, seed=0)
    assert np.abs(a.mu - b.mu).max() < 1e-12
    c = kpm_dos(t, 40, vectors=3, seed=0, parallel=True)
    assert np.abs(a.mu - c.mu).max() < 1e-12
    # a duck-typed periodic cluster (anything with a neighbours table)
    class Cell:
        neighbours = t
        p, q, name = 4, 3, "prism"

    d = kpm_dos(Cell(), 40, vectors=3, seed=0)
    assert np.array_equal(d.mu, a.mu) and "prism" in d.label


def test_local_moments_do_not_depend_on_the_thread_count():
    """local_dos(parallel=True) sums its dot products over fixed chunks of rows, as kpm_dos does.

    A numba ``prange`` reduction adds the threads' partial sums in an order set by the number of
    threads, i.e. by the machine's core count: the moments moved by up to 4e-13 between the serial
    run, two threads and one thread. Several chunks of CHUNK rows, table and CSR kernels."""
    import numba

    t = _prism(3 * kpm.CHUNK // 2 + 7)                     # 6,158 sites: 4 chunks, the last partial
    for graph in (t, _table_matrix(t)):
        serial = local_dos(graph, 5, 40)
        assert np.array_equal(local_dos(graph, 5, 40, parallel=True).mu, serial.mu)
        threads = numba.get_num_threads()
        try:
            numba.set_num_threads(1)
            assert np.array_equal(local_dos(graph, 5, 40, parallel=True).mu, serial.mu)
        finally:
            numba.set_num_threads(threads)


def test_density_normalised_and_error_free_for_exact_moments(flake):
    res = local_dos(flake, 3, 128)
    e, rho, err = res.density()
    assert np.trapezoid(rho, e) == pytest.approx(1.0, abs=1e-3)
    assert np.all(err == 0) and np.all(rho > -1e-12)  # Jackson: positive
    one = kpm_dos(flake, 16, vectors=1)
    assert np.all(np.isnan(one.mu_err[1:]))
    g = jackson_kernel(10)
    assert g[0] == pytest.approx(1.0) and np.all(np.diff(g) < 0)


def test_result_round_trip(tmp_path, flake):
    res = kpm_dos(flake, 16, vectors=2, seed=1)
    again = Result.from_dict(res.as_dict())
    assert isinstance(again, KPMDos) and np.array_equal(again.mu, res.mu)
    path = res.save(tmp_path / "k.npz")
    assert np.array_equal(KPMDos.load(path).mu_vectors, res.mu_vectors)
    assert res.summary()["moments"] == 16


def test_refuses_before_allocating(monkeypatch, flake):
    monkeypatch.setattr(kpm, "_available_memory", lambda: 1000)
    with pytest.raises(ValueError, match="GB"):
        kpm_dos(flake, 16)


def test_bad_graphs():
    with pytest.raises(ValueError):
        graph_operator(np.array([[0, 5]]))
    with pytest.raises(ValueError):
        graph_operator(sp.csr_matrix(np.array([[0.0, 1.0], [2.0, 0.0]])))
    with pytest.raises(ValueError):
        graph_operator("graph")
    with pytest.raises(ValueError):
        bulk_dos(ring_lattice(7, 3, 1))


def test_deflation_removes_the_states_at_plus_minus_q():
    t = _prism(6)  # bipartite (even cycles): states at -3 and +3
    ev = np.linalg.eigvalsh(-_table_matrix(t).toarray())
    res = kpm_dos(t, 48, vectors=200, seed=4, deflate=True)
    assert res.deflated == 2
    inner = ev[1:-1]
    ref = np.cos(np.outer(np.arange(48), np.arccos(inner / res.scale))).sum(axis=1) / ev.size
    z = (res.mu - ref) / np.where(res.mu_err > 0, res.mu_err, 1.0)
    assert np.abs(z).max() < 5.0
    assert kpm_dos(_prism(5), 8, vectors=2, deflate=True).deflated == 1  # odd cycles: only the uniform state
    assert kpm_dos(ring_lattice(7, 3, 3), 8, vectors=2, deflate=True).deflated == 0  # a flake has none


def test_relabelled_table_keeps_site_numbers():
    # the table is renumbered breadth-first for speed; site indices and results are the user's
    rng = np.random.default_rng(0)
    t = _prism(30)
    shuffle = rng.permutation(t.shape[0])
    inv = np.argsort(shuffle)
    ts = inv[t[shuffle]].astype(np.int32)  # the same graph with scrambled labels
    m = _table_matrix(ts)
    for site in (0, 17, 44):
        a = local_dos(ts, site, 30)
        b = local_dos(m, site, 30)
        assert np.abs(a.mu - b.mu).max() < 1e-13
    assert np.abs(kpm_dos(ts, 20, vectors=2).mu - kpm_dos(m, 20, vectors=2).mu).max() < 1e-12


def test_cluster_moments_equal_lattice_walks_below_the_systole():
    clusters = pytest.importorskip("hyperlattice.graph.clusters")
    c = clusters.pbc_cluster(7, 3, "PSL(2,29)")  # 4,060 sites, systole 26
    res = kpm_dos(c, c.systole, vectors=16, seed=7)
    ref = chebyshev_from_walks(closed_walks(7, 3, c.systole - 1), res.scale)
    z = (res.mu[1:] - ref[1:]) / res.mu_err[1:]
    assert np.abs(z).max() < 5.0 and np.sqrt(np.mean(z**2)) < 2.0
    # the exact local moments at any site of the cluster are the lattice's (vertex-transitive quotient)
    loc = local_dos(c, 123, c.systole)
    assert np.abs(loc.mu - ref).max() < 1e-12


@pytest.mark.parametrize("kind", ["rademacher", "phase"])
def test_block_kernel_equals_single_vector_kernel(kind, flake):
    # kpm_dos runs its vectors in blocks of 8 columns; each column must give the single-vector moments
    clusters = pytest.importorskip("hyperlattice.graph.clusters")
    for graph in (flake, clusters.pbc_cluster(7, 3, min_sites=1000), _table_matrix(_prism(25))):
        op = graph_operator(graph)
        res = kpm_dos(graph, 61, vectors=11, seed=3, kind=kind)  # one full block of 8, one of 3
        ref = []
        for r in range(11):
            v = kpm._random_vector(kind, op.sites, 3, r, None)
            if op.perm is not None:
                w = np.empty_like(v)
                w[op.perm] = v
                v = w
            ref.append(kpm._chebyshev_moments(op, v, 61, res.scale) / op.sites)
        assert np.abs(res.mu_vectors - np.array(ref)).max() < 1e-12
    # serial and parallel block kernels reduce in the same fixed chunks: identical moments
    t = _prism(3000)
    a = kpm_dos(t, 30, vectors=8, seed=1)
    b = kpm_dos(t, 30, vectors=8, seed=1, parallel=True)
    assert np.array_equal(a.mu_vectors, b.mu_vectors)
