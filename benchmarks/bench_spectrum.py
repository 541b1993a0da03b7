"""E0 and E1 of H = -A: hyperlattice.lowest_levels vs plain eigsh on the full adjacency.

Both sides run in one process on the same {7,3} lattice and the same accuracy (residual
||A psi - lambda psi|| <= 1e-10 for both levels); the script prints absolute times, the speed
ratio, the residuals and the peak resident memory after each side, plus the machine.

The peer is ``scipy.sparse.linalg.eigsh(A, k=2, which="LA", ncv=40, tol=1e-12)`` (the two
largest eigenvalues of A are minus the two lowest of H). ARPACK is run with single-threaded
OpenBLAS on both sides: on a shared 2-core machine multi-threaded BLAS makes ARPACK many times
slower, and the comparison should not rest on that. The time of building the lattice is
printed separately and is not included in either side.

Usage: ``python benchmarks/bench_spectrum.py [--rings 12] [--skip-eigsh]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", type=int, default=12)
    ap.add_argument("--skip-eigsh", action="store_true", help="only time hyperlattice")
    args = ap.parse_args(argv)

    import numpy as np
    import scipy.sparse.linalg as spla

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import adjacency
    from hyperlattice.graph.solvers import _single_threaded_blas
    from hyperlattice.graph.spectrum import lowest_levels

    print(f"machine: {machine()}")
    t0 = time.perf_counter()
    lat = ring_lattice(7, 3, args.rings)
    print(f"{{7,3}} rings = {args.rings}, N = {lat.sites:,}; lattice built in {time.perf_counter() - t0:.2f} s")

    # warm the numba cache (compilation is a one-off, not part of the solve)
    lowest_levels(ring_lattice(7, 3, 9), 2)
    t0 = time.perf_counter()
    spec = lowest_levels(lat, 2, tol=1e-10)
    t_ours = time.perf_counter() - t0
    mem_ours = peak_rss_mb()
    print(f"  hyperlattice lowest_levels ({spec.method}): {t_ours:8.2f} s   E0 = {spec.energies[0]:.13f}  "
          f"E1 = {spec.energies[1]:.13f}  (n,m) = {list(zip(spec.n.tolist(), spec.m.tolist()))}  "
          f"max residual {spec.residuals.max():.1e}  peak RSS {mem_ours:.0f} MB")
    print("    per sector: " + ", ".join(f"{k} {v:.2f} s" for k, v in spec.timings.items() if k.startswith("sector")))
    if args.skip_eigsh:
        return

    a = adjacency(lat)
    with _single_threaded_blas():
        t0 = time.perf_counter()
        w, v = spla.eigsh(a, k=2, which="LA", ncv=40, tol=1e-12)
        t_eigsh = time.perf_counter() - t0
    order = np.argsort(-w)
    e = -w[order]
    v = v[:, order]
    res = np.linalg.norm(a @ v - v * w[order], axis=0)
    mem_eigsh = peak_rss_mb()
    print(f"  plain eigsh(A, k=2, which='LA'):         {t_eigsh:8.2f} s   E0 = {e[0]:.13f}  E1 = {e[1]:.13f}  "
          f"max residual {res.max():.1e}  process peak RSS {mem_eigsh:.0f} MB")
    print(f"  |dE0| = {abs(e[0] - spec.energies[0]):.1e}, |dE1| = {abs(e[1] - spec.energies[1]):.1e}")
    print(f"ratio (eigsh time / hyperlattice time): {t_eigsh / t_ours:.1f}x")


if __name__ == "__main__":
    main()
