"""graph_green below the band against CHOLMOD, same process: one column, and a scan over many omega.

The {7,3} flake with ``--rings`` (default 12: 725,760 sites), source site 10. Timings are
best-of-``--repeat``, ours and the peer's interleaved, and printed as ratios (peer time / ours:
above 1 means graph_green is faster); the machine is shared, so absolute times mean little.

1. One column G_.j(omega) at omega = -2.95 and -3.5 (E0 = -2.9273 at l = 12): graph_green from
   the lattice (a fresh call: building H, every analysis and factorisation included) against the
   peer ``sksparse.cholmod.cholesky(H, beta=-omega).solve_A(e_j)`` on a prebuilt H, and against
   the peer with the build of H (``hamiltonian(lattice)``) counted too.
2. A scan over S omegas in [-3.5, -2.935] (``--scan``, default 16,32,64), one column each:
   graph_green(lattice, omegas, j) against the peer's analyse-once (``cholmod.analyze``, its time
   counted) + refactorise-per-omega (``cholesky_inplace(H, beta)``) + solve, and against the same
   peer with its analysis done before the clock starts (an analysis kept across calls).

Also printed: the largest deviation between the two answers relative to the column's largest
entry, the largest normwise backward error of ours, and what graph_green reports itself
(``GraphResolvent.report``): the routes taken and the largest proved relative error bound.

Usage: ``python benchmarks/bench_green_scan.py [--rings 12] [--repeat 3] [--scan 16,32,64]``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import interleaved, machine, peak_rss_mb  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scan", default="16,32,64")
    args = ap.parse_args(argv)

    from sksparse import cholmod

    from hyperlattice.graph.green import GraphResolvent, graph_green
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import hamiltonian

    print(machine())
    lat = ring_lattice(7, 3, args.rings)
    H = hamiltonian(lat).tocsc()
    n, src = lat.sites, 10
    e = np.zeros(n)
    e[src] = 1.0
    norm = float(abs(H).sum(axis=0).max())

    def backward(oms, cols):
        cols = np.atleast_2d(cols.real)
        oms = np.atleast_1d(oms)
        r = np.linalg.norm(e[None, :] - ((H @ cols.T).T - oms[:, None] * cols), axis=1)
        return float(np.max(r / ((norm + np.abs(oms)) * np.linalg.norm(cols, axis=1) + 1.0)))

    last = {}

    def ours(omega):
        # graph_green from the lattice, as a user calls it (the resolvent kept only to read its report)
        last["res"] = res = GraphResolvent(lat)
        return graph_green(res, omega, src)

    def reported() -> str:
        rep = last["res"].report
        routes = {r: rep["route"].count(r) for r in dict.fromkeys(rep["route"])}
        bound = np.max(rep["error_bound"])
        return (f"route {', '.join(f'{k} x{v}' for k, v in routes.items())}, "
                f"proved relative error <= {bound:.1e}")

    print(f"{{7,3}} l={args.rings}: {n:,} sites, source {src}; ratio = peer time / graph_green time")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # CHOLMOD's own warnings are not ours
        for omega in (-2.95, -3.5):
            best, out = interleaved({
                "ours": lambda: ours(omega),
                "peer": lambda: cholmod.cholesky(H, beta=-omega).solve_A(e),
                "peer+H": lambda: cholmod.cholesky(hamiltonian(lat).tocsc(), beta=-omega).solve_A(e),
            }, args.repeat)
            dev = np.max(np.abs(out["ours"] - out["peer"])) / np.max(np.abs(out["peer"]))
            print(f"one column, omega={omega}: ratio {best['peer'] / best['ours']:.2f} (peer on a prebuilt H), "
                  f"{best['peer+H'] / best['ours']:.2f} (peer building H too); deviation {dev:.1e}, "
                  f"backward error {backward(omega, out['ours']):.1e}; {reported()}")
        for S in (int(x) for x in args.scan.split(",")):
            oms = np.linspace(-3.5, -2.935, S)
            kept = cholmod.analyze(H)

            def peer(analysis=None):
                an = analysis if analysis is not None else cholmod.analyze(H)
                cols = np.empty((S, n))
                f = None
                for i, w in enumerate(oms):
                    if f is None:
                        f = an.cholesky(H, beta=-w)
                    else:
                        f.cholesky_inplace(H, beta=-w)
                    cols[i] = f.solve_A(e)
                return cols

            best, out = interleaved({
                "ours": lambda: ours(oms),
                "peer": peer,
                "peer kept": lambda: peer(kept),
            }, args.repeat)
            dev = np.max(np.abs(out["ours"] - out["peer"])) / np.max(np.abs(out["peer"]))
            print(f"scan of {S} omegas: ratio {best['peer'] / best['ours']:.2f} (peer analyses once per scan), "
                  f"{best['peer kept'] / best['ours']:.2f} (peer's analysis kept across calls); "
                  f"deviation {dev:.1e}, backward error {backward(oms, out['ours']):.1e}; {reported()}")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
