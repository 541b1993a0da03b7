"""KPM moments on a large periodic cluster: hyperlattice's fused block kernel vs scipy.sparse CSR SpMM,
and both against the streaming and the random-gather limits of the product.

What is timed: M Chebyshev moments of a block of R random vectors (default 8; M/2 block products by
the doubling identities), stored row-major as an (N, R) array, the graph given as a neighbour table
(hyperlattice's fused numba kernel, relabelled breadth-first) or as a CSR matrix (peer:
``Y_next = c * (A @ Y) - Y_prev`` with ``A @ Y`` a CSR times dense (N, R) block, which scipy runs as
one sparse-times-dense product, and per-column dots by ``numpy.einsum``).

Two limits, measured in the same run:

(a) streaming: a block product must stream the table (4q bytes per site), Y and Y_prev (read, then
    overwritten in place): 4q + 24 R bytes per site. A STREAM-like numba triad ``a = b + s * c`` over
    arrays of the same total bytes gives the machine's bandwidth (best of serial/parallel x 3).
(b) random gather: the time to only read ``Y[nb[i, k], :]`` (one 64-byte line per gather for R = 8)
    for the same table: the real floor on an expander graph, where no numbering makes these reads
    local.

``--peer-moments K`` times the peer on K moments and scales its time linearly to M (it is a fixed
cost per product); the output says so.

The machine is shared: the load average is printed before and after. The cluster is the smallest
PSL(2, r) {7,3} cluster with at least ``--sites`` sites (``--flake R``: a ring_lattice flake instead).

Usage: ``python benchmarks/bench_kpm.py [--sites 10000000] [--moments 1000] [--vectors 8] [--threads 2]
[--peer-moments 200] [--flake 15]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
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


def _gather_kernel(parallel: bool):
    import numba

    rng = numba.prange if parallel else range

    @numba.njit(parallel=parallel, cache=True)
    def gather(nb, y, chunk):
        n, w = nb.shape
        nch = -(-n // chunk)
        part = np.zeros((nch, y.shape[1]))
        for b in rng(nch):
            for i in range(b * chunk, min(n, (b + 1) * chunk)):
                for k in range(w):
                    j = nb[i, k]
                    for r in range(y.shape[1]):
                        part[b, r] += y[j, r]
        return part.sum()

    return gather


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sites", type=int, default=10_000_000)
    ap.add_argument("--moments", type=int, default=1000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--flake", type=int, default=None, help="use a ring_lattice flake of this many rings")
    ap.add_argument("--vectors", type=int, default=8, help="block width R (random vectors per pass)")
    ap.add_argument("--skip-peer", action="store_true")
    ap.add_argument("--peer-moments", type=int, default=None, help="time the peer on fewer moments and scale")
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
    nv = args.vectors
    rng = np.random.default_rng(0)
    x0 = rng.integers(0, 2, (n, nv)).astype(np.float64) * 2 - 1  # row-major (N, R): R numbers per site
    scale = op.bound / (1 - kpm.EPS)
    par = args.threads > 1
    if par:
        numba.set_num_threads(max(1, min(args.threads, numba.config.NUMBA_NUM_THREADS)))
    mode = f"parallel, {numba.get_num_threads()} threads" if par else "serial"

    # warm up (compile) on a small graph
    small = kpm.graph_operator(np.ascontiguousarray(op.table[:1000] % 1000)) if op.table is not None else op
    kpm._chebyshev_moments_block(small, x0[: small.sites].copy(), 8, scale, par)

    # (c) the project: M moments of R vectors, one block
    x = x0.copy()
    t0, c0 = time.perf_counter(), time.process_time()
    mu = kpm._chebyshev_moments_block(op, x, m, scale, par)
    t_proj, cpu_proj = time.perf_counter() - t0, time.process_time() - c0
    del x
    print(f"  hyperlattice block kernel ({mode}): {m} moments x {nv} vectors = {products} block products in "
          f"{t_proj:.2f} s wall, {cpu_proj:.2f} s CPU; {1e3 * t_proj / products:.1f} ms per block product = "
          f"{1e3 * t_proj / products / nv:.2f} ms per vector-product; {t_proj / nv:.2f} s per vector for {m} moments")

    # (a) streaming limit: a STREAM-like triad over arrays of the bytes one block product must stream:
    # the table (4q bytes per site), Y (read), Yprev (read, then overwritten in place): 4q + 24 R bytes
    q = op.table.shape[1] if op.table is not None else 3
    bytes_block = n * (4 * q + 24 * nv) if op.table is not None else (op.indices.nbytes + op.indptr.nbytes
                                                                       + 24 * nv * n)
    words = bytes_block // 24
    a, b, c = np.zeros(words), np.ones(words), np.ones(words)
    best_bw = 0.0
    for p_ in (False, True):
        triad = _triad_kernel(p_)
        triad(a[:10], b[:10], c[:10], 0.5)
        for _ in range(3):
            t0 = time.perf_counter()
            triad(a, b, c, 0.5)
            best_bw = max(best_bw, 24 * words / (time.perf_counter() - t0))
    del a, b, c
    t_stream = products * bytes_block / best_bw
    print(f"  (a) streaming limit (numba triad, best of serial/parallel x 3): {best_bw / 1e9:.2f} GB/s; one block "
          f"product streams {bytes_block / 1e6:.0f} MB -> {1e3 * t_stream / products:.1f} ms per block product "
          f"({1e3 * t_stream / products / nv:.2f} ms per vector), {t_stream:.2f} s for {m} moments x {nv} vectors")

    # (b) random-gather limit: only read Y[nb[i, k], :] (R numbers = one cache line per gather) for
    # the same table, plus the table itself; nothing written. The floor for a graph with no locality.
    t_gather = float("inf")
    if op.table is not None:
        for p_ in (False, True):
            g = _gather_kernel(p_)
            g(small.table, x0[: small.sites], 256)
            for _ in range(3):
                t0 = time.perf_counter()
                g(op.table, x0, 2048)
                t_gather = min(t_gather, time.perf_counter() - t0)
        t_gather *= products
        print(f"  (b) random-gather limit (read Y[nb] only, best of serial/parallel x 3): "
              f"{1e3 * t_gather / products:.1f} ms per block product ({1e3 * t_gather / products / nv:.2f} ms per "
              f"vector), {t_gather:.2f} s for {m} moments x {nv} vectors")
    print(f"  ratio hyperlattice / streaming limit: {t_proj / t_stream:.2f}x; / random-gather limit: "
          f"{t_proj / t_gather:.2f}x (wall); CPU / streaming limit {cpu_proj / t_stream:.2f}x")

    if not args.skip_peer:
        a_csr = graph.adjacency().tocsr().astype(np.float64) if hasattr(graph, "adjacency") else None
        if a_csr is None:
            from hyperlattice.graph.operators import adjacency

            a_csr = adjacency(graph).tocsr().astype(np.float64)
        if op.perm is not None:  # same (breadth-first) numbering for the peer: a fair comparison
            order = np.argsort(op.perm)
            a_csr = a_csr[order][:, order].tocsr()
        a_csr = sp.csr_matrix(a_csr)
        cc = -2.0 / scale
        mp = min(m, args.peer_moments or m)

        def dots(u, w):
            return np.einsum("ij,ij->j", u, w)

        def peer():
            # CSR @ dense (N, R) block: scipy runs this as one sparse-times-dense product (SpMM)
            mu = np.empty((nv, mp))
            t0v = x0.copy()
            t1v = (cc / 2) * (a_csr @ t0v)
            mu0, mu1 = dots(t0v, t0v), dots(t0v, t1v)
            mu[:, 0], mu[:, 1], mu[:, 2] = mu0, mu1, 2 * dots(t1v, t1v) - mu0
            prev, cur = t0v, t1v
            k = 1
            while 2 * k + 1 < mp:
                nxt = cc * (a_csr @ cur) - prev
                mu[:, 2 * k + 1] = 2 * dots(nxt, cur) - mu1
                if 2 * k + 2 < mp:
                    mu[:, 2 * k + 2] = 2 * dots(nxt, nxt) - mu0
                prev, cur = cur, nxt
                k += 1
            return mu

        t0, c0 = time.perf_counter(), time.process_time()
        mu_peer = peer()
        t_peer, cpu_peer = time.perf_counter() - t0, time.process_time() - c0
        scale_up = products / (mp // 2)
        t_peer_full = t_peer * scale_up
        print(f"  peer scipy CSR @ (N, {nv}) block (SpMM), {mp} moments{' (time scaled to %d)' % m if mp < m else ''}: "
              f"{t_peer_full:.2f} s wall, {cpu_peer * scale_up:.2f} s CPU ({1e3 * t_peer / (mp // 2):.1f} ms per block "
              f"product); moments agree to {np.abs(mu_peer - mu[:, :mp]).max() / abs(mu[0, 0]):.1e} (relative to mu_0); "
              f"ratio peer / hyperlattice: {t_peer_full / t_proj:.2f}x wall")
    print(f"peak RSS {peak_rss_mb():.0f} MB; load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
