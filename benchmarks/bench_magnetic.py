"""Benchmark: Dirichlet levels of the magnetic Laplacian (continuum side of the flux issue), one process.

Run:  .venv/bin/python benchmarks/bench_magnetic.py

For each disk (rings l of the {7,3} flake) and flux f: hyperlattice's ``magnetic_levels`` (the K
lowest levels, every order searched) against the plain mpmath route for the SAME levels, told
their (n, m) labels in advance (so the peer does no order search): the radial function
r^|m| (1-r^2)^beta 2F1(a, b'; c; r^2) with mpmath.hyp2f1 at mp.dps = 15, bracketed on the same
k = sqrt(kappa - 1) grid cell and refined with mpmath.findroot. Both must agree to 1e-9; prints
ms per level, the ratio and, for reference, the zero-field continuum_levels time per level.
"""

from __future__ import annotations

import os
import sys

import mpmath as mp
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _machine import best_of, machine  # noqa: E402

from hyperlattice.continuum.magnetic import magnetic_levels  # noqa: E402
from hyperlattice.continuum.spectrum import continuum_levels  # noqa: E402


def mpmath_level(m, B, radius, kappa_guess):
    """The Dirichlet root in kappa of the regular radial solution near ``kappa_guess`` (mpmath)."""
    mp.mp.dps = 15
    u = mp.mpf(radius) ** 2
    am = abs(m)

    def radial(kappa):
        delta = mp.sqrt(mp.mpc(1 - kappa + B * B / 4))
        beta = (1 - delta) / 2
        a = beta + (am + m + B / 2) / 2
        b = beta + (am - m - B / 2) / 2
        return mp.re((1 - u) ** (-1j * mp.im(delta) / 2) * mp.hyp2f1(a, b, 1 + am, u))

    lo, hi = kappa_guess * (1 - 1e-6), kappa_guess * (1 + 1e-6)
    return float(mp.findroot(radial, (lo, hi), solver="anderson"))


def main():
    print(machine())
    K = 2
    for rings, flux in ((5, 0.1), (8, 0.2), (12, 0.05), (12, 0.3)):
        t_pkg, res = best_of(lambda: magnetic_levels(7, 3, rings=rings, levels=K, flux=flux), 2)
        t_zero, _ = best_of(lambda: continuum_levels(7, 3, rings=rings, levels=K), 2)

        def peer():
            return [mpmath_level(int(m), res.field, res.radius, k) for m, k in zip(res.m, res.kappa)]

        t_mp, kap = best_of(peer, 1)
        assert np.allclose(kap, res.kappa, rtol=1e-9), (kap, res.kappa)
        print(f"[l={rings:2d} f={flux:4.2f} B={res.field:5.2f}] hyperlattice {t_pkg / K * 1e3:7.1f} ms/level "
              f"(order search included)   mpmath hyp2f1+findroot, labels given, started 1e-6 from the root "
              f"{t_mp / K * 1e3:8.1f} ms/level   ratio {t_mp / t_pkg:6.1f}x   zero-field continuum_levels "
              f"{t_zero / K * 1e3:6.1f} ms/level")


if __name__ == "__main__":
    main()
