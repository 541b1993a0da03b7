"""Bose–Hubbard exact diagonalisation: a Lanczos run on >= 10^7 Fock states, and the time per
Hamiltonian application against QuSpin on the same problem (issue 22, item 1).

The problem: the {8,3} Dyck cluster (32 sites, periodic), N = 7 bosons, at most 2 per site,
U = 4, t = 1, mu = 0: 10,960,608 states.

1. ``bose_hubbard(..., method="matrix-free", levels=1)``: ARPACK Lanczos with hyperlattice's
   numba matrix-free product (no matrix stored); dimension, wall time, products, peak memory,
   E0 and its residual.
2. One product H x: hyperlattice's matrix-free kernel against QuSpin's
   ``quantum_LinearOperator`` (also matrix-free) on ``boson_basis_general`` of the same states,
   after checking that both give the same vector (QuSpin's states mapped to our ranks).
3. A mid-size problem (Dyck, N = 5, nmax = 2, 360,096 states) where both CSR matrices fit:
   build time and CSR product, hyperlattice (numba two-pass CSR) against QuSpin ``hamiltonian``.

QuSpin is optional (``pip install quspin``, in its own environment if it would change numpy):
without it, parts 2 and 3 compare against a plain scipy CSR build of the same matrix instead
(COO triplets from vectorised numpy, ranks by ``np.searchsorted`` on the state codes).

Usage: ``python benchmarks/bench_bosons.py [--skip-lanczos] [--repeat 3] [--small]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import best_of, machine, peak_rss_mb  # noqa: E402

U = 4.0


def _rss_mb() -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def _quspin():
    try:
        from quspin.basis import boson_basis_general  # noqa: F401
        from quspin.operators import hamiltonian, quantum_LinearOperator  # noqa: F401
    except ImportError:
        return None
    import quspin

    return quspin


def _static(edges, m):
    hop = [[-1.0, int(i), int(j)] for i, j in edges] + [[-1.0, int(j), int(i)] for i, j in edges]
    # (U/2) n (n - 1) = (U/2) n n - (U/2) n
    return [["+-", hop], ["nn", [[U / 2, i, i] for i in range(m)]], ["n", [[-U / 2, i] for i in range(m)]]]


def _quspin_perm(qb, b, sps):
    """Our rank of each QuSpin state (QuSpin: site 0 is the most significant base-sps digit)."""
    from hyperlattice.bosons.basis import rank_states

    states = np.asarray(qb.states)
    m = b.sites
    perm = np.empty(states.shape[0], dtype=np.int64)
    step = 1_000_000
    for a in range(0, states.shape[0], step):
        s = states[a:a + step].astype(np.uint64)
        occ = np.empty((s.shape[0], m), dtype=np.int64)
        for i in range(m - 1, -1, -1):
            occ[:, i] = (s % np.uint64(sps)).astype(np.int64)
            s = s // np.uint64(sps)
        perm[a:a + step] = rank_states(b, occ)
    return perm


def _scipy_csr(b, edges):
    """The peer without QuSpin: the same matrix from vectorised numpy + scipy (COO -> CSR)."""
    import scipy.sparse as sp

    st = np.asarray(b.states, dtype=np.int64)
    c = b.nmax
    base = (c + 1) ** np.arange(b.sites - 1, -1, -1, dtype=np.int64)
    code = st @ base                         # increasing with our rank (lexicographic order)
    rows, cols, vals = [np.arange(b.dim)], [np.arange(b.dim)], [0.5 * U * (st * (st - 1)).sum(axis=1)]
    for i, j in np.concatenate([edges, edges[:, ::-1]]):
        ok = (st[:, j] > 0) & (st[:, i] < c)
        src = np.flatnonzero(ok)
        tgt = np.searchsorted(code, code[src] + base[i] - base[j])
        rows.append(tgt)
        cols.append(src)
        vals.append(-np.sqrt(st[src, j] * (st[src, i] + 1.0)))
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(b.dim, b.dim))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-lanczos", action="store_true", help="only the product comparisons")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--small", action="store_true",
                    help="a quick check of the script (N = 5 and 3 instead of 7 and 5), not the benchmark")
    args = ap.parse_args(argv)

    import numba

    from hyperlattice.bosons import ed
    from hyperlattice.bosons.basis import boson_basis
    from hyperlattice.graph.clusters import pbc_cluster

    print(machine())
    print(f"numba threads: {numba.get_num_threads()}")
    q = _quspin()
    print(f"peer: {'QuSpin ' + q.__version__ if q else 'scipy CSR (QuSpin not installed)'}")
    dyck = pbc_cluster(8, 3, "dyck")
    edges = np.asarray(dyck.edges)
    m = dyck.sites

    # --- 1. Lanczos on >= 1e7 states ---------------------------------------------------
    n, c = (5, 2) if args.small else (7, 2)
    if not args.skip_lanczos:
        rss0 = _rss_mb()
        t0 = time.perf_counter()
        res = ed.bose_hubbard(dyck, n, c, U, levels=1, method="matrix-free", observables=False)
        dt = time.perf_counter() - t0
        print(f"\n[1] Lanczos, Dyck cluster {m} sites, N={n}, nmax={c}, U={U:g}: dim {res.dim:,}")
        print(f"    E0 = {res.energies[0]:.10f}, residual {res.residuals[0]:.1e}, {dt:.1f} s "
              f"(basis + Lanczos), peak RSS {peak_rss_mb():.0f} MB (start {rss0:.0f} MB)")

    # --- 2. one product on the same 1.1e7 states ------------------------------------------
    b = boson_basis(m, n, c)
    op = ed.hamiltonian_operator(b, dyck, U)
    x = np.random.default_rng(0).standard_normal(b.dim)
    op @ x                                              # compile / warm up
    t_ours, _ = best_of(lambda: op @ x, args.repeat)
    print(f"\n[2] H x on {b.dim:,} states: hyperlattice matrix-free {t_ours:.3f} s")
    if q:
        from quspin.basis import boson_basis_general
        from quspin.operators import quantum_LinearOperator

        t0 = time.perf_counter()
        qb = boson_basis_general(m, Nb=n, sps=c + 1)
        t_qb = time.perf_counter() - t0
        qop = quantum_LinearOperator(_static(edges, m), basis=qb, dtype=np.float64,
                                     check_symm=False, check_herm=False, check_pcon=False)
        perm = _quspin_perm(qb, b, c + 1)
        xq = x[perm]
        yq = qop.dot(xq)
        err = np.abs(yq - (op @ x)[perm]).max()
        t_q, _ = best_of(lambda: qop.dot(xq), args.repeat)
        print(f"    QuSpin quantum_LinearOperator {t_q:.3f} s (basis {t_qb:.1f} s); same vector to {err:.1e}")
        print(f"    ratio QuSpin / hyperlattice = {t_q / t_ours:.2f}")
        del qb, qop, perm, xq, yq
    del op, x, b

    # --- 3. CSR build and product, mid-size -----------------------------------------------
    n3 = 3 if args.small else 5
    b = boson_basis(m, n3, c)
    t0 = time.perf_counter()
    h = ed.hamiltonian(b, dyck, U)
    t_build = time.perf_counter() - t0
    x = np.random.default_rng(1).standard_normal(b.dim)
    t_mv, _ = best_of(lambda: h @ x, args.repeat)
    opf = ed.hamiltonian_operator(b, dyck, U)
    opf @ x
    t_mf, _ = best_of(lambda: opf @ x, args.repeat)
    print(f"\n[3] Dyck N={n3}, nmax={c}: {b.dim:,} states, {h.nnz:,} entries")
    print(f"    hyperlattice: CSR build {t_build:.2f} s, CSR product {t_mv * 1e3:.1f} ms, "
          f"matrix-free product {t_mf * 1e3:.1f} ms")
    if q:
        from quspin.basis import boson_basis_general
        from quspin.operators import hamiltonian

        t0 = time.perf_counter()
        qb = boson_basis_general(m, Nb=n3, sps=c + 1)
        qh = hamiltonian(_static(edges, m), [], basis=qb, dtype=np.float64,
                         check_symm=False, check_herm=False, check_pcon=False)
        t_qbuild = time.perf_counter() - t0
        qcsr = qh.tocsr()
        perm = _quspin_perm(qb, b, c + 1)
        err = abs(qcsr - h[perm][:, perm]).max()
        xq = x[perm]
        t_qmv, _ = best_of(lambda: qh.dot(xq), args.repeat)
        print(f"    QuSpin: basis + hamiltonian {t_qbuild:.2f} s, product {t_qmv * 1e3:.1f} ms; "
              f"same matrix to {err:.1e}")
        print(f"    ratio QuSpin / hyperlattice: build {t_qbuild / t_build:.2f}, product {t_qmv / t_mv:.2f}")
    else:
        t0 = time.perf_counter()
        hs = _scipy_csr(b, edges)
        t_sb = time.perf_counter() - t0
        err = abs(hs - h).max()
        t_smv, _ = best_of(lambda: hs @ x, args.repeat)
        print(f"    scipy CSR: build {t_sb:.2f} s, product {t_smv * 1e3:.1f} ms; same matrix to {err:.1e}")
        print(f"    ratio scipy / hyperlattice: build {t_sb / t_build:.2f}, product {t_smv / t_mv:.2f}")
    print(f"\npeak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
