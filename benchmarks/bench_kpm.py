"""KPM moments on a large periodic cluster: hyperlattice's fused numba kernel vs scipy.sparse CSR,
and both against the memory-bandwidth limit of the matrix-vector product.

What is timed: M Chebyshev moments for one random vector (M/2 products by the doubling identities),
the graph given as a neighbour table (hyperlattice, relabelled breadth-first) or as a CSR matrix
(peer: ``y_next = c * (A @ y) - y_prev`` and two ``numpy.dot`` per step, the plain scipy way).

The bandwidth limit: a product streams at least the table (4q bytes per site), y, y_prev and out
(8 bytes each; the gathers y[nb[i, k]] hit the cache when the numbering is local): 4q + 24 bytes
per site. A STREAM-like triad ``a = b + s * c`` in numba over arrays of the same total bytes
measures what this machine moves per second (best of 5); the limit of one product is bytes / triad
bandwidth, and the script prints the measured time per product, the limit and their ratio.

The machine is shared: the load average is printed before and after. The cluster is the smallest
PSL(2, r) {7,3} cluster with at least ``--sites`` sites (``--flake R``: a ring_lattice flake instead).

Usage: ``python benchmarks/bench_kpm.py [--sites 10000000] [--moments 1000] [--threads 2] [--flake 15]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def _triad_kernel(parallel: bool):
    import numba

    rng = numba.prange if parallel else range

    @numba.njit(parallel=parallel, cache=True)
    def triad(a, b, c, s):
        for i in rng(a.shape[0]):
            a[i] = b[i] + s * c[i]

    return triad


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sites", type=int, default=10_000_000)
    ap.add_argument("--moments", type=int, default=1000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--flake", type=int, default=None, help="use a ring_lattice flake of this many rings")
    ap.add_argument("--skip-peer", action="store_true")
    args = ap.parse_args(argv)

    import numba
    import numpy as np
    import scipy.sparse as sp

    from hyperlattice.graph import kpm

    print(f"machine: {machine()}; numba threads available {numba.config.NUMBA_NUM_THREADS}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    t0 = time.perf_counter()
    if args.flake:
        from hyperlattice.graph.lattice import ring_lattice

        graph = ring_lattice(7, 3, args.flake)
        what = f"{{7,3}} flake, {args.flake} rings"
    else:
        from hyperlattice.graph.clusters import pbc_cluster

        graph = pbc_cluster(7, 3, min_sites=args.sites)
        what = f"{{7,3}} cluster {graph.name}"
    t_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    op = kpm.graph_operator(graph)
    t_op = time.perf_counter() - t0
    n = op.sites
    print(f"{what}: N = {n:,} sites; built in {t_build:.1f} s, operator (BFS relabelling) {t_op:.1f} s; "
          f"peak RSS {peak_rss_mb():.0f} MB")

    m = args.moments
    products = m // 2
    rng = np.random.default_rng(0)
    r = rng.integers(0, 2, n).astype(np.float64) * 2 - 1
    scale = op.bound / (1 - kpm.EPS)

    # warm up (compile) on a small copy
    small = kpm.graph_operator(np.ascontiguousarray(op.table[:1000] % 1000)) if op.table is not None else op
    for par in (False, True):
        kpm._chebyshev_moments(small, r[: small.sites].copy(), 8, scale, par)

    results = {}
    cpu_times = {}
    for par in (False, True):
        label = "parallel" if par else "serial"
        if par:
            numba.set_num_threads(max(1, min(args.threads, numba.config.NUMBA_NUM_THREADS)))
        t0, c0 = time.perf_counter(), time.process_time()
        mu = kpm._chebyshev_moments(op, r, m, scale, par)
        t, cpu = time.perf_counter() - t0, time.process_time() - c0
        results[label] = (t, mu)
        cpu_times[label] = cpu
        print(f"  hyperlattice ({label}{', %d threads' % numba.get_num_threads() if par else ''}): "
              f"{m} moments = {products} products in {t:.2f} s wall ({1e3 * t / products:.2f} ms per product), "
              f"{cpu:.2f} s CPU")
    t_best = min(t for t, _ in results.values())
    mu_ref = results["serial"][1]
    rel = np.abs(results["parallel"][1] - mu_ref).max() / abs(mu_ref[0])
    print(f"    serial vs parallel moments: max difference {rel:.1e} relative to mu_0 = N")

    # memory-bandwidth limit: a triad over arrays of the same total bytes as one product streams
    q = op.table.shape[1] if op.table is not None else 3
    bytes_per_product = n * (4 * q + 24) if op.table is not None else (
        op.indices.nbytes + op.indptr.nbytes + 24 * n)
    words = bytes_per_product // 24  # three float64 arrays a, b, c
    a, b, c = np.zeros(words), np.ones(words), np.ones(words)
    best_bw = 0.0
    for par in (False, True):
        triad = _triad_kernel(par)
        triad(a[:10], b[:10], c[:10], 0.5)
        for _ in range(5):
            t0 = time.perf_counter()
            triad(a, b, c, 0.5)
            dt = time.perf_counter() - t0
            best_bw = max(best_bw, 24 * words / dt)
    del a, b, c
    t_limit = products * bytes_per_product / best_bw
    print(f"  memory bandwidth (STREAM-like numba triad, best of serial/parallel x 5): {best_bw / 1e9:.2f} GB/s; "
          f"one product streams {bytes_per_product / 1e6:.0f} MB -> limit {1e3 * t_limit / products:.2f} ms per "
          f"product, {t_limit:.2f} s for {m} moments")
    print(f"  ratio hyperlattice / bandwidth limit: {t_best / t_limit:.2f}x (wall); serial CPU time / limit: "
          f"{cpu_times['serial'] / t_limit:.2f}x (a loaded machine time-slices the wall clock)")

    if not args.skip_peer:
        a_csr = graph.adjacency().tocsr().astype(np.float64) if hasattr(graph, "adjacency") else None
        if a_csr is None:
            from hyperlattice.graph.operators import adjacency

            a_csr = adjacency(graph).tocsr().astype(np.float64)
        if op.perm is not None:  # same (local) numbering for the peer: a fair comparison
            order = np.argsort(op.perm)
            a_csr = a_csr[order][:, order].tocsr()
        a_csr = sp.csr_matrix(a_csr)
        cc = -2.0 / scale

        def peer():
            mu = np.empty(m)
            t0v = r.copy()
            t1v = (cc / 2) * (a_csr @ t0v)
            mu0, mu1 = float(t0v @ t0v), float(t0v @ t1v)
            mu[0], mu[1], mu[2] = mu0, mu1, 2 * float(t1v @ t1v) - mu0
            prev, cur = t0v, t1v
            k = 1
            while 2 * k + 1 < m:
                nxt = cc * (a_csr @ cur) - prev
                mu[2 * k + 1] = 2 * float(nxt @ cur) - mu1
                if 2 * k + 2 < m:
                    mu[2 * k + 2] = 2 * float(nxt @ nxt) - mu0
                prev, cur = cur, nxt
                k += 1
            return mu

        t0, c0 = time.perf_counter(), time.process_time()
        mu_peer = peer()
        t_peer, cpu_peer = time.perf_counter() - t0, time.process_time() - c0
        print(f"  peer scipy.sparse CSR matvec Chebyshev: {t_peer:.2f} s wall, {cpu_peer:.2f} s CPU "
              f"({1e3 * t_peer / products:.2f} ms per "
              f"product); moments agree to {np.abs(mu_peer - mu_ref).max() / abs(mu_ref[0]):.1e} (relative to mu_0); "
              f"ratio peer / hyperlattice: {t_peer / t_best:.2f}x wall, {cpu_peer / cpu_times['serial']:.2f}x CPU (serial)")
    print(f"peak RSS {peak_rss_mb():.0f} MB; load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
