"""E0 and E1 of H = -A: hyperlattice.lowest_levels vs the strongest peers on the full adjacency.

All sides run in one process on the same {7,3} lattice and the same accuracy (residual
||A psi - lambda psi|| <= 1e-10 for both levels); the script prints absolute times, the speed
ratios, the residuals and the peak resident memory after each side, plus the machine.

Peers (the two largest eigenvalues of A are minus the two lowest of H):

* plain Lanczos, ``scipy.sparse.linalg.eigsh(A, k=2, which="LA", ncv=40, tol=1e-12)``;
* shift-invert Lanczos with a sparse direct solver, the stronger method: ``eigsh`` with
  ``sigma = 3`` (above the spectrum of A, whose largest degree is 3) and ``(A - 3)^-1`` applied by
  ``scipy.sparse.linalg.splu`` (SuperLU, COLAMD ordering; the fill-in on these graphs is tiny);
* the same with CHOLMOD (``scikit-sparse``) when it is installed: the fastest peer measured on this
  kind of machine (``shared/NUMERICS-NOTES.md``). It needs ``apt-get install libsuitesparse-dev``
  and ``pip install "scikit-sparse<0.5"``, so it is optional and skipped when absent.

ARPACK is run with single-threaded
OpenBLAS on both sides: on a shared 2-core machine multi-threaded BLAS makes ARPACK many times
slower, and the comparison should not rest on that. The time of building the lattice is
printed separately and is not included in either side.

Usage: ``python benchmarks/bench_spectrum.py [--rings 12] [--skip-eigsh] [--skip-plain]``.
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
    ap.add_argument("--skip-plain", action="store_true", help="skip plain eigsh (the slowest peer)")
    args = ap.parse_args(argv)

    import numpy as np
    import scipy.sparse as sp
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

    a = adjacency(lat).tocsc()
    n = a.shape[0]
    sigma = 3.0

    def plain():
        return spla.eigsh(a, k=2, which="LA", ncv=40, tol=1e-12)

    def shift_invert_splu():
        lu = spla.splu((a - sigma * sp.identity(n, format="csc")).tocsc(), permc_spec="COLAMD")
        op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
        return spla.eigsh(a, k=2, sigma=sigma, which="LM", OPinv=op, tol=1e-12)

    peers = [] if args.skip_plain else [("plain eigsh(A, k=2, which='LA')", plain)]
    peers.append(("eigsh shift-invert, splu (COLAMD), sigma=3", shift_invert_splu))
    try:
        from sksparse.cholmod import cholesky  # optional, see the module docstring

        def shift_invert_cholmod():
            factor = cholesky((sigma * sp.identity(n, format="csc") - a).tocsc())
            op = spla.LinearOperator((n, n), matvec=lambda x: -factor(x), dtype=float)
            return spla.eigsh(a, k=2, sigma=sigma, which="LM", OPinv=op, tol=1e-12)

        peers.append(("eigsh shift-invert, CHOLMOD, sigma=3", shift_invert_cholmod))
    except ImportError:
        print("  (scikit-sparse not installed: the CHOLMOD peer is skipped)")
    for label, run in peers:
        with _single_threaded_blas():
            t0 = time.perf_counter()
            w, v = run()
            t_peer = time.perf_counter() - t0
        order = np.argsort(-w)
        e = -w[order]
        v = v[:, order]
        res = np.linalg.norm(a @ v - v * w[order], axis=0)
        print(f"  {label}: {t_peer:8.2f} s   E0 = {e[0]:.13f}  E1 = {e[1]:.13f}  "
              f"max residual {res.max():.1e}  process peak RSS {peak_rss_mb():.0f} MB")
        print(f"    |dE0| = {abs(e[0] - spec.energies[0]):.1e}, |dE1| = {abs(e[1] - spec.energies[1]):.1e}; "
              f"ratio (peer time / hyperlattice time): {t_peer / t_ours:.2f}x")


if __name__ == "__main__":
    main()
