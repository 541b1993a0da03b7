"""Benchmark: continuum Dirichlet levels and Legendre functions against plain mpmath, one process.

Run:  .venv/bin/python benchmarks/bench_continuum.py [--radius 0.9]

1. All Dirichlet roots k_nm, n <= 3, m <= 6 at one radius: hyperlattice (dirichlet_roots) versus
   the straightforward mpmath route (mpmath.legenp + findroot, started from a sign-change scan
   at 53-bit precision, mp.dps = 15). Both find the same 21 roots; the script checks they agree.
2. One vectorized P_nu^m evaluation over 10^4 points versus mpmath.legenp point by point (timed
   on a subsample of points and scaled).
Prints absolute times, ratios and the machine.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import mpmath as mp
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _machine import best_of, machine  # noqa: E402

from hyperlattice.continuum.spectrum import dirichlet_roots  # noqa: E402
from hyperlattice.continuum.special import legendre_p  # noqa: E402


def mpmath_roots(radius, m_max=6, n_max=3):
    mp.mp.dps = 15
    x = (1 + mp.mpf(radius) ** 2) / (1 - mp.mpf(radius) ** 2)
    out = np.empty((m_max + 1, n_max))
    t = float(mp.acosh(x))
    dk = 2 * np.pi / (t + np.log(8)) / 6
    for m in range(m_max + 1):
        f = lambda k: mp.re(mp.legenp(mp.mpc(-0.5, k / 2), m, x, type=3))  # noqa: E731
        found, k, fk = [], 0.0, f(0.0)
        while len(found) < n_max:
            k2 = k + dk
            fk2 = f(k2)
            if fk * fk2 <= 0:
                found.append(float(mp.findroot(f, (k, k2), solver="anderson")))
            k, fk = k2, fk2
        out[m] = found
    return out



def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radius", type=float, default=0.9)
    args = ap.parse_args()
    print("machine:", machine())
    print(f"radius L = {args.radius}")

    dirichlet_roots(np.arange(7), args.radius, 3)          # warm-up (imports, caches)
    t_pkg, k_pkg = best_of(lambda: dirichlet_roots(np.arange(7), args.radius, 3), 5)
    t_mp, k_mp = best_of(lambda: mpmath_roots(args.radius), 1)
    agree = np.max(np.abs(k_pkg - k_mp) / k_mp)
    print(f"[levels n<=3, m<=6] hyperlattice {t_pkg * 1e3:8.2f} ms   mpmath legenp+findroot "
          f"{t_mp * 1e3:9.1f} ms   ratio {t_mp / t_pkg:7.0f}x   max rel. difference {agree:.1e}")

    x = np.geomspace(1.0 + 1e-6, 1e10, 10_000)
    nu, m = -0.5 + 1.5j, 3
    legendre_p(nu, m, x)
    t_vec, vals = best_of(lambda: legendre_p(nu, m, x), 5)
    sub = x[::100]
    mp.mp.dps = 15
    t0 = time.perf_counter()
    ref = [complex(mp.legenp(mp.mpc(nu.real, nu.imag), m, xv, type=3)) for xv in sub]
    t_mp_pt = (time.perf_counter() - t0) / sub.size
    err = np.max(np.abs(vals[::100] - ref) / np.maximum(np.abs(ref), 1e-300))
    print(f"[P_nu^m, 10^4 points] hyperlattice {t_vec * 1e3:7.2f} ms total = {t_vec / x.size * 1e6:6.2f} us/point   "
          f"mpmath {t_mp_pt * 1e6:8.1f} us/point   ratio {t_mp_pt / (t_vec / x.size):7.0f}x   "
          f"max rel. difference {err:.1e}")


if __name__ == "__main__":
    main()
