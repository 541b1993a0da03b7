"""Periodic cluster construction: the PSL(2, r) family (sites per second) against the generic route.

For {7,3} and {8,3} and a few primes r, times

* ``psl2_map`` (hyperlattice's direct construction: numba, matrix arithmetic, one scattered
  look-up per neighbour) — the issue's target is >= 10^6 sites per second;
* the generic permutation route on the same group (dart tables of right multiplication, then the
  map from the two permutations), the way a coset table from Todd–Coxeter is turned into a map;
* the complete ``pbc_cluster`` call (construction plus the systole from the lattice reference);

and prints the ratio of the generic route to the direct one. No other Python package builds
these clusters (HyperCells/HyperBloch are GAP + Mathematica), so the peer is the generic route.
Usage: ``python benchmarks/bench_clusters.py [--big] [--repeat 3]``; ``--big`` adds the
10^7-site {7,3} cluster PSL(2,419).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import best_of, machine, peak_rss_mb  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--big", action="store_true", help="also build PSL(2,419) for {7,3} (1.2e7 sites)")
    args = ap.parse_args(argv)

    from hyperlattice.graph import clusters as C
    from hyperlattice.graph import groups as G

    print(f"machine: {machine()}")
    # compile (or load from the on-disk cache) the numba kernels outside the timings
    x, y = G.psl2_triple(7, 3, 13)
    G.psl2_map(x, y, 13, 3)
    C._map_from_darts(*G.psl2_dart_tables(x, y, 13), 7, 3)
    cases = [(7, 3, 71), (7, 3, 197), (8, 3, 97), (8, 3, 193)]
    if args.big:
        cases.append((7, 3, 419))
    print(f"{'{p,q}':>6} {'r':>4} {'sites':>10} {'direct s':>9} {'sites/s':>11} {'generic s':>10} "
          f"{'ratio':>6} {'pbc_cluster s':>13} {'systole':>8}")
    for p, q, r in cases:
        x, y = G.psl2_triple(p, q, r)
        t_direct, nb = best_of(lambda: G.psl2_map(x, y, r, q), args.repeat if r < 400 else 1)
        sites = nb.shape[0]
        if r < 400:
            t_generic, nb2 = best_of(lambda: C._map_from_darts(*G.psl2_dart_tables(x, y, r), p, q), args.repeat)
            assert (nb2 == nb).all()
            generic, ratio = f"{t_generic:10.3f}", f"{t_generic / t_direct:6.1f}"
        else:
            generic, ratio = f"{'-':>10}", f"{'-':>6}"
        C._cached.cache_clear()
        t0 = time.perf_counter()
        c = C.pbc_cluster(p, q, f"PSL(2,{r})")
        t_full = time.perf_counter() - t0
        bound = "" if c.systole_exact else ">="
        print(f"{{{p},{q}}} {r:>4} {sites:>10} {t_direct:9.3f} {sites / t_direct:11.3e} {generic} {ratio} "
              f"{t_full:13.3f} {bound + str(c.systole):>8}")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
