"""E0 and E1 of H = -A: hyperlattice vs the strongest peers on the full adjacency, same run.

All sides run in one process on the same {7,3} flake and report the residual
||A psi - lambda psi|| of both levels; the script prints absolute times, the speed ratios, the
level differences and the peak resident memory, plus the machine.

hyperlattice sides:

* ``lowest_pair(7, 3, rings)`` (the headline): the sector-only path. The timing *includes*
  building the flake (sector by sector, never the full lattice), the mirror-real sector blocks,
  shift-invert Lanczos for E0 (m = 0 even) and E1 (m = 1), and the Sylvester-inertia proof that
  no other block has a level below E1. CHOLMOD when scikit-sparse is importable, else SuperLU.
* ``lowest_levels(lattice, 2, method="sector")`` (the sector blocks of the full lattice, each by
  shift-invert through graph/factor; the Chebyshev-accelerated Lanczos of 0.2 before issue 20),
  for reference (``--skip-old`` to skip). The *default* call is benchmarked by ``bench_routes.py``.

Peers (the two largest eigenvalues of A are minus the two lowest of H), timed *without* building
the lattice or the adjacency (a handicap for hyperlattice):

* shift-invert Lanczos with CHOLMOD (``scikit-sparse``, optional, skipped when absent):
  ``eigsh(A, k=2, sigma, OPinv = (sigma - A)^-1)`` with ``sigma = 2.935``, just above the top of
  the spectrum of A for rings >= 10 (the setting of ``shared/NUMERICS-NOTES.md``), the fastest
  peer measured on this kind of machine;
* the same with ``scipy.sparse.linalg.splu`` (COLAMD) and ``sigma = 3``;
* plain ``eigsh(A, k=2, which="LA")`` with ``--plain`` (slow).

ARPACK runs with single-threaded OpenBLAS on every side. ``--flake 16`` additionally runs
``lowest_pair`` for 16 rings in a fresh process and prints its time and peak memory.

Usage: ``python benchmarks/bench_spectrum.py [--rings 12 14] [--skip-old] [--plain] [--flake 16]``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def one_size(rings: int, args) -> None:
    import numpy as np
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import adjacency
    from hyperlattice.graph.sectors import lowest_pair
    from hyperlattice.graph.solvers import _single_threaded_blas
    from hyperlattice.graph.spectrum import lowest_levels

    t0 = time.perf_counter()
    ours = lowest_pair(7, 3, rings, tol=1e-10)
    t_ours = time.perf_counter() - t0
    e_ours = ours.energies
    print(f"{{7,3}} rings = {rings}, N = {ours.sites:,}")
    print(f"  hyperlattice lowest_pair (sector-only, build included): {t_ours:8.2f} s   E0 = {e_ours[0]:.13f}  "
          f"E1 = {e_ours[1]:.13f}  (n,m) = {list(zip(ours.n.tolist(), ours.m.tolist()))}  "
          f"max residual {ours.residuals.max():.1e}  peak RSS so far {peak_rss_mb():.0f} MB")
    print("    stages: " + ", ".join(f"{k} {v:.2f}" for k, v in ours.timings.items()))
    results = []
    t0 = time.perf_counter()
    lat = ring_lattice(7, 3, rings)
    a = adjacency(lat).tocsc()
    n = a.shape[0]
    print(f"  (full lattice + adjacency for the peers built in {time.perf_counter() - t0:.2f} s, not counted)")

    if not args.skip_old:
        t0 = time.perf_counter()
        old = lowest_levels(lat, 2, tol=1e-10, method="sector")
        results.append(("hyperlattice lowest_levels(method='sector', full-lattice blocks)", time.perf_counter() - t0,
                        np.asarray(old.energies), float(old.residuals.max())))

    def shift_invert(solve_factory, sigma):
        def run():
            op = spla.LinearOperator((n, n), matvec=solve_factory(sigma), dtype=float)
            return spla.eigsh(a, k=2, sigma=sigma, which="LM", OPinv=op, tol=1e-12)
        return run

    peers = []
    try:
        from sksparse.cholmod import cholesky  # optional, see the module docstring

        def cholmod_factory(sigma):
            factor = cholesky((sigma * sp.identity(n, format="csc") - a).tocsc())
            return lambda x: -factor(x)

        peers.append(("full-matrix CHOLMOD shift-invert, sigma=2.935", shift_invert(cholmod_factory, 2.935)))
    except ImportError:
        print("  (scikit-sparse not installed: the CHOLMOD peer is skipped)")

    def splu_factory(sigma):
        lu = spla.splu((a - sigma * sp.identity(n, format="csc")).tocsc(), permc_spec="COLAMD")
        return lu.solve

    if not args.skip_splu:
        peers.append(("full-matrix splu (COLAMD) shift-invert, sigma=3", shift_invert(splu_factory, 3.0)))
    if args.plain:
        peers.append(("plain eigsh(A, k=2, which='LA')", lambda: spla.eigsh(a, k=2, which="LA", ncv=40, tol=1e-12)))
    for label, run in peers:
        with _single_threaded_blas():
            t0 = time.perf_counter()
            w, v = run()
            t_peer = time.perf_counter() - t0
        order = np.argsort(-w)
        res = np.linalg.norm(a @ v[:, order] - v[:, order] * w[order], axis=0)
        results.append((label, t_peer, -w[order], float(res.max())))
    for label, t_peer, e, res in results:
        print(f"  {label}: {t_peer:8.2f} s   E0 = {e[0]:.13f}  E1 = {e[1]:.13f}  max residual {res:.1e}")
        print(f"    |dE0| = {abs(e[0] - e_ours[0]):.1e}, |dE1| = {abs(e[1] - e_ours[1]):.1e}; "
              f"ratio (its time / lowest_pair time): {t_peer / t_ours:.2f}x")
    print(f"  process peak RSS {peak_rss_mb():.0f} MB")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", type=int, nargs="+", default=[12, 14])
    ap.add_argument("--skip-old", action="store_true", help="skip lowest_levels(method='sector')")
    ap.add_argument("--skip-splu", action="store_true", help="skip the splu peer")
    ap.add_argument("--plain", action="store_true", help="also time plain eigsh (the slowest peer)")
    ap.add_argument("--flake", type=int, nargs="*", default=[], help="sector-only lowest_pair in a fresh process")
    args = ap.parse_args(argv)

    from hyperlattice.graph.sectors import lowest_pair
    from hyperlattice.graph.spectrum import lowest_levels
    from hyperlattice.graph.lattice import ring_lattice

    print(f"machine: {machine()}")
    # compile the numba kernels once, outside every timing
    lowest_pair(7, 3, 6)
    lowest_levels(ring_lattice(7, 3, 9), 2)
    for rings in args.rings:
        one_size(rings, args)
    for rings in args.flake:
        table = Path(__file__).resolve().parent / "table_e0e1.py"
        out = subprocess.run([sys.executable, str(table), "--one", str(rings)], capture_output=True, text=True)
        if out.returncode:
            print(f"rings = {rings}: failed: {out.stderr.strip()[-300:]}")
            continue
        row = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{{7,3}} rings = {rings}, N = {row['sites']:,}: lowest_pair {row['seconds']:.1f} s, peak RSS "
              f"{row['peak_GB']:.2f} GB, E0 = {row['E0']:.13f}, E1 = {row['E1']:.13f}, residuals "
              f"{row['residual0']:.1e}, {row['residual1']:.1e}")


if __name__ == "__main__":
    main()
