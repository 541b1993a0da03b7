"""Boundary correlators below the band: hyperlattice vs plain scipy.sparse.linalg.spsolve (and CHOLMOD).

1. All outer-ring correlators G_ij(omega) of the {7,3} flake with ``--rings`` (default 10:
   105,875 sites, 65,443 on the outer ring) for one source, omega = -3.2: ``boundary_correlator``
   (one factorization with the exact below-band check, one solve, the Delta fit and the continuum
   column) against ``spsolve(H - omega, e_j)``.
2. A fitted Delta(m^2) curve with ``--masses`` (default 20) frequencies in [-3.8, -2.95]:
   ``delta_curve`` against spsolve per source and frequency, and against a factorise-once CHOLMOD
   (scikit-sparse, benchmark only) per frequency when it is installed.
Prints the times, the ratios and the largest difference of the columns.

Usage: ``python benchmarks/bench_boundary.py [--rings 10] [--masses 20]``.
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
    args = ap.parse_args()

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
    t = time.perf_counter()
    res = BelowBandResolvent(lat)
    col = res.column(-3.2, src)
    t_col = time.perf_counter() - t
    t = time.perf_counter()
    bc = boundary_correlator(lat, -3.2, src)
    t_ours = time.perf_counter() - t
    b = np.zeros(lat.sites)
    b[src] = 1.0
    t = time.perf_counter()
    ref = spla.spsolve((H + 3.2 * I).tocsc(), b)
    t_sp = time.perf_counter() - t
    line = (f"1. one source, all outer-ring correlators: hyperlattice column {t_col:.3f} s (order + factor + solve; "
            f"boundary_correlator incl. fit + continuum {t_ours:.2f} s), spsolve {t_sp:.3f} s: ratio spsolve/ours "
            f"{t_sp / t_col:.2f}")
    if cholesky is not None:
        t = time.perf_counter()
        xc = cholesky((H + 3.2 * I).tocsc())(b)
        t_c1 = time.perf_counter() - t
        line += f"; CHOLMOD {t_c1:.3f} s: ratio CHOLMOD/ours {t_c1 / t_col:.2f} (max rel diff {np.max(np.abs(xc[ring] / ref[ring] - 1)):.1e})"
    print(line)
    print(f"   max rel diff ours vs spsolve {np.max(np.abs(col[ring] / ref[ring] - 1)):.1e}; Delta = "
          f"{bc.delta_lattice:.4f} +- {bc.delta_lattice_err:.4f} (continuum {bc.delta_continuum:.4f})")

    omegas = np.linspace(-3.8, -2.95, args.masses)
    t = time.perf_counter()
    curve = delta_curve(lat, omegas, source=src)
    t_curve = time.perf_counter() - t
    t = time.perf_counter()
    for w in omegas:
        spla.spsolve((H - w * I).tocsc(), b)
    t_sp20 = time.perf_counter() - t
    print(f"2. Delta(m^2) with {args.masses} masses: hyperlattice {t_curve:.2f} s (order once, LDL^T with inertia "
          f"check per mass, solve, fit), spsolve per mass {t_sp20:.2f} s (solves only): ratio spsolve/ours "
          f"{t_sp20 / t_curve:.2f}")
    if cholesky is not None:
        t = time.perf_counter()
        f = cholesky((H - omegas[0] * I).tocsc())
        for w in omegas:
            f.cholesky_inplace((H - w * I).tocsc())
            x = f(b)
        t_ch = time.perf_counter() - t
        print(f"   CHOLMOD factorise-once (symbolic once, numeric per mass, solves only) {t_ch:.2f} s: ratio "
              f"CHOLMOD/ours {t_ch / t_curve:.2f}")
    for w, m2, dl, de, dc in zip(curve.omegas, curve.mass2, curve.delta_lattice, curve.delta_lattice_err,
                                 curve.delta_continuum):
        print(f"   omega {w:+.4f}  m^2 {m2:+8.4f}  Delta_lattice {dl:.4f} +- {de:.4f}  Delta_continuum {dc:.4f}")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
