"""Boundary correlators below the band: hyperlattice vs full-matrix CHOLMOD and plain spsolve, same process.

1. All outer-ring correlators G_ij(omega) of the {7,3} flake with ``--rings`` (default 10:
   105,875 sites, 65,443 on the outer ring) for one source, omega = -3.2: ``boundary_correlator``
   (one factorization with the exact below-band check, one solve, the Delta fit and the continuum
   column) against ``spsolve(H - omega, e_j)``.
2. A fitted Delta(m^2) curve with ``--masses`` (default 20) frequencies in [-3.8, -2.95]:
   ``delta_curve`` against spsolve per source and frequency, and against a factorise-once CHOLMOD
   (scikit-sparse, benchmark only) per frequency when it is installed.
Prints the times (best of ``--repeat`` runs on every side, the machine being shared), the ratios
peer / ours and the largest difference of the columns. The source (the first outer-ring site) lies
on a mirror axis for l = 4 and 10, so hyperlattice solves its mirror-even block (half of H); the
CHOLMOD peer factorises the full H + 3.2 (symbolic analysis + numeric factorisation + one solve),
and for the curve analyses once and refactorises per mass (``cholesky_inplace``), solves only.

Usage: ``python benchmarks/bench_boundary.py [--rings 10] [--masses 20] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rings", type=int, default=10)
    ap.add_argument("--masses", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3, help="runs of every side; the best is reported")
    args = ap.parse_args()

    def best(fn):
        times, out = [], None
        for _ in range(args.repeat):
            t = time.perf_counter()
            out = fn()
            times.append(time.perf_counter() - t)
        return min(times), out

    from hyperlattice.compare.boundary import boundary_correlator, delta_curve, outer_ring
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import hamiltonian

    print(machine())
    lat = ring_lattice(7, 3, args.rings)
    ring = outer_ring(lat)
    src = int(ring[0])
    H = hamiltonian(lat).tocsc()
    I = sp.identity(lat.sites, format="csc")
    print(f"{{7,3}} l = {args.rings}: {lat.sites} sites, {ring.size} on the outer ring")

    try:
        from sksparse.cholmod import cholesky
    except ImportError:
        cholesky = None
        print("   CHOLMOD (scikit-sparse) not installed: peer skipped")
    from hyperlattice.graph.qubits import BelowBandResolvent

    BelowBandResolvent(ring_lattice(7, 3, 3)).column(-3.5, 0)     # numba kernels loaded (compiled once, cached)
    t_col, col = best(lambda: BelowBandResolvent(lat).column(-3.2, src))
    mirrored = bool(BelowBandResolvent(lat)._mirror(src))
    t_ours, bc = best(lambda: boundary_correlator(lat, -3.2, src, continuum=False))
    b = np.zeros(lat.sites)
    b[src] = 1.0
    t_sp, ref = best(lambda: spla.spsolve((H + 3.2 * I).tocsc(), b))
    line = (f"1. one source, all outer-ring correlators: hyperlattice column {t_col:.3f} s ("
            f"{'mirror-even block' if mirrored else 'full H'}: analysis + factor + solve; boundary_correlator incl. "
            f"the Delta fit {t_ours:.3f} s), spsolve {t_sp:.3f} s: ratio spsolve/ours {t_sp / t_col:.2f}")
    if cholesky is not None:
        t_c1, xc = best(lambda: cholesky((H + 3.2 * I).tocsc())(b))
        line += (f"; full-matrix CHOLMOD {t_c1:.3f} s: ratio CHOLMOD/ours {t_c1 / t_col:.2f} (column), "
                 f"{t_c1 / t_ours:.2f} (with the fit) (max rel diff {np.max(np.abs(xc[ring] / ref[ring] - 1)):.1e})")
    print(line)
    print(f"   max rel diff ours vs spsolve {np.max(np.abs(col[ring] / ref[ring] - 1)):.1e}; Delta = "
          f"{bc.delta_lattice:.4f} +- {bc.delta_lattice_err:.4f} (continuum {bc.delta_continuum:.4f})")

    omegas = np.linspace(-3.8, -2.95, args.masses)
    t_curve, curve = best(lambda: delta_curve(lat, omegas, source=src))

    def sp20():
        for w in omegas:
            spla.spsolve((H - w * I).tocsc(), b)
    t_sp20, _ = best(sp20)
    print(f"2. Delta(m^2) with {args.masses} masses: hyperlattice {t_curve:.2f} s (analysis once, LDL^T with inertia "
          f"check per mass, solve, fit), spsolve per mass {t_sp20:.2f} s (solves only): ratio spsolve/ours "
          f"{t_sp20 / t_curve:.2f}")
    if cholesky is not None:
        def ch20():
            f = cholesky((H - omegas[0] * I).tocsc())
            for w in omegas:
                f.cholesky_inplace((H - w * I).tocsc())
                f(b)
        t_ch, _ = best(ch20)
        print(f"   CHOLMOD factorise-once (symbolic once, numeric per mass, solves only) {t_ch:.2f} s: ratio "
              f"CHOLMOD/ours {t_ch / t_curve:.2f}")
    for w, m2, dl, de, dc in zip(curve.omegas, curve.mass2, curve.delta_lattice, curve.delta_lattice_err,
                                 curve.delta_continuum):
        print(f"   omega {w:+.4f}  m^2 {m2:+8.4f}  Delta_lattice {dl:.4f} +- {de:.4f}  Delta_continuum {dc:.4f}")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
