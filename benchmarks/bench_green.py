"""Green functions: continuum G (hyperlattice) vs mpmath point by point; one graph column.

1. Continuum G(z_i, z_j, lambda, L) from one source (site 10, ring 2) to all sites of the
   {7,3} lattice with ``--rings`` (default 6: 2,240 sites) to tol = 1e-10, at omega = -2.95 and
   omega = -2.5+0.1i (eq21 lambda). The peer evaluates the same green34 - green36 values with
   mpmath (``legenq``/``legenp``, type 3, 20 digits) point by point, with the source- and
   boundary-dependent factors computed once and shared; it runs on ``--sample`` sites and is
   extrapolated per site. Also prints the largest deviation between the two on the sample.
2. One graph column G_.j(omega) (sparse LU) at ``--graph-rings`` (default 10: 105,875 sites).

Usage: ``python benchmarks/bench_green.py [--rings 6] [--sample 12] [--graph-rings 10]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import best_of, machine, peak_rss_mb  # noqa: E402



def mpmath_green(z, zp, lam, L, M):
    """green34 - green36 with mpmath, same truncation order M, source/boundary factors shared."""
    import mpmath as mp

    from hyperlattice.continuum.green import green_nu

    mp.mp.dps = 20
    nu = mp.mpc(green_nu(lam))
    rho = lambda r: (1 + r * r) / (1 - r * r)  # noqa: E731
    xL, xp = rho(mp.mpf(L)), rho(mp.mpf(abs(zp)))
    shared = []
    for m in range(M):
        cm = (-1) ** m * mp.gamma(nu - m + 1) / mp.gamma(nu + m + 1)
        shared.append(cm * mp.legenp(nu, m, xp, type=3) * mp.legenq(nu, m, xL, type=3)
                      / mp.legenp(nu, m, xL, type=3))
    out = []
    for zi in z:
        zi_m, zp_m = mp.mpc(zi), mp.mpc(zp)
        y = 1 + 2 * abs(zi_m - zp_m) ** 2 / ((1 - abs(zi_m) ** 2) * (1 - abs(zp_m) ** 2))
        g0 = mp.legenq(nu, 0, y, type=3) / (2 * mp.pi)
        x = rho(abs(zi_m))
        dphi = mp.arg(zi_m) - mp.arg(zp_m)
        dg = 0
        for m in range(M):
            dg += (1 if m == 0 else 2) * shared[m] * mp.legenp(nu, m, x, type=3) * mp.cos(m * dphi)
        out.append(complex(g0 - dg / (2 * mp.pi)))
    return np.array(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", type=int, default=6)
    ap.add_argument("--sample", type=int, default=12)
    ap.add_argument("--graph-rings", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)

    from hyperlattice.continuum.green import continuum_green
    from hyperlattice.dictionary import dictionary_parameters
    from hyperlattice.graph.green import GraphResolvent
    from hyperlattice.graph.lattice import ring_lattice

    print(machine())
    lat = ring_lattice(7, 3, args.rings)
    src = 10
    L = lat.radius
    rng = np.random.default_rng(0)
    sample = np.sort(rng.choice(np.delete(np.arange(lat.sites), src), args.sample, replace=False))
    print(f"continuum G, {{7,3}} l={args.rings} ({lat.sites} sites), source {src}, tol 1e-10")
    for omega in (-2.95, -2.5 + 0.1j):
        lam, _ = dictionary_parameters(omega)
        t_ours, (vals, info) = best_of(lambda: continuum_green(lat.z, lat.z[src], lam, L, tol=1e-10,
                                                               extend=True, return_info=True), args.repeat)
        t0 = time.perf_counter()
        ref = mpmath_green(lat.z[sample], lat.z[src], lam, L, info.terms)
        t_mp = (time.perf_counter() - t0) / sample.size * lat.sites
        dev = np.max(np.abs(vals[sample] - ref) / np.abs(ref))
        print(f"  omega={omega!s:>12}: hyperlattice {1e3 * t_ours:8.1f} ms ({info.terms} orders, tail "
              f"{info.tail_estimate:.1e}); mpmath {t_mp:8.1f} s (extrapolated from {sample.size} sites); "
              f"ratio {t_mp / t_ours:,.0f}x; max rel. deviation {dev:.1e}")
    big = ring_lattice(7, 3, args.graph_rings)
    for omega in (-2.95, -2.5 + 0.1j):
        t_col, _ = best_of(lambda: GraphResolvent(big).column(omega, src), 2)
        print(f"graph column l={args.graph_rings} ({big.sites} sites), omega={omega}: {t_col:.2f} s")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
