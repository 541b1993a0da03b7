"""The hyperbolic Hofstadter butterfly by sectors against dense ``eigvalsh`` of the Peierls matrix.

Issue 11 asks: the butterfly of the l = 6 {7,3} flake (2,240 sites) at 200 flux values, by
sectors, at least 20x faster than dense ``scipy.linalg.eigvalsh`` of the full N x N Peierls
matrix at the same flux values, measured side by side in one run.

Both sides run in this process on the same lattice. The sector side is
:func:`hyperlattice.graph.butterfly.butterfly` at all ``--fluxes`` values in [0, 1] (building the
p blocks included). The dense side builds ``hamiltonian(lattice, flux=f).toarray()`` and calls
``eigvalsh`` at ``--dense-fluxes`` of those values spread over [0, 1] (default 10: one dense solve
takes seconds); its time per flux value is multiplied by ``--fluxes`` to give the dense time
of the whole butterfly (an extrapolation, printed as such: the dense cost does not depend on f).
The levels of both sides are compared at the dense flux values.

Usage: ``python benchmarks/bench_butterfly.py [--rings 6] [--fluxes 200] [--dense-fluxes 10]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg as sla

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine  # noqa: E402

from hyperlattice.graph.butterfly import butterfly  # noqa: E402
from hyperlattice.graph.lattice import ring_lattice  # noqa: E402
from hyperlattice.graph.operators import hamiltonian  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-p", type=int, default=7)
    ap.add_argument("-q", type=int, default=3)
    ap.add_argument("--rings", type=int, default=6)
    ap.add_argument("--fluxes", type=int, default=200)
    ap.add_argument("--dense-fluxes", type=int, default=10)
    args = ap.parse_args(argv)
    print(machine())
    t0 = time.perf_counter()
    lattice = ring_lattice(args.p, args.q, args.rings)
    print(f"{{{args.p},{args.q}}} rings={args.rings}: {lattice.sites:,} sites "
          f"(lattice built in {time.perf_counter() - t0:.2f} s, not counted)")
    fluxes = np.linspace(0.0, 1.0, args.fluxes)

    t0 = time.perf_counter()
    result = butterfly(lattice, fluxes)
    t_sector = time.perf_counter() - t0
    print(f"sectors: {args.fluxes} flux values in {t_sector:.2f} s ({t_sector / args.fluxes * 1e3:.1f} ms per flux)")

    pick = np.unique(np.linspace(0, args.fluxes - 1, min(args.dense_fluxes, args.fluxes)).round().astype(int))
    worst = 0.0
    t0 = time.perf_counter()
    for k in pick.tolist():
        e = sla.eigvalsh(hamiltonian(lattice, flux=float(fluxes[k])).toarray())
        worst = max(worst, float(np.max(np.abs(e - result.energies[k]))))
    t_dense = time.perf_counter() - t0
    per = t_dense / pick.size
    full = per * args.fluxes
    print(f"dense eigvalsh: {pick.size} flux values in {t_dense:.2f} s ({per:.2f} s per flux, matrix built "
          f"included); extrapolated to {args.fluxes} flux values: {full:.1f} s")
    print(f"ratio dense / sectors: {full / t_sector:.1f}x (the issue asks for >= 20x)")
    print(f"largest level difference between the two sides: {worst:.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
