"""Lattice construction: hyperlattice.ring_lattice (+ adjacency) and the sector-only build
(``sector_lattice``: one site per rotation orbit, what the E0/E1 solver needs) vs hypertiling, same run.

Prints sites per second of each (sites of the full lattice for the sector-only build too) and the
ratios. hypertiling builds the paper's {7,3} ring
lattice as cells of {3,7} with ``kernel="SRS", center="vertex"`` (with neighbours), and its
fastest kernel ``GRC`` (cell-centred tiling, coordinates only) is timed at the same number of
layers. Usage: ``python benchmarks/bench_lattice.py [--rings 12] [--repeat 3]``.
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
    ap.add_argument("--rings", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-srs", action="store_true", help="skip hypertiling SRS (slow at large rings)")
    ap.add_argument("--srs-neighbours", action="store_true",
                    help="also time hypertiling's neighbour lists (minutes at 12 rings)")
    args = ap.parse_args(argv)

    from hypertiling import HyperbolicTiling

    from hyperlattice import adjacency, ring_lattice

    print(f"machine: {machine()}")
    print(f"{{7,3}} ring lattice, rings = {args.rings}")

    def ours():
        lat = ring_lattice(7, 3, args.rings)
        adjacency(lat)
        return lat

    t_ours, lat = best_of(ours, args.repeat)
    n = lat.sites
    print(f"  hyperlattice ring_lattice + adjacency : {t_ours:8.3f} s  {n / t_ours:12.0f} sites/s  (N = {n})"
          f"  peak RSS so far {peak_rss_mb():.0f} MB")

    from hyperlattice.graph.sectors import sector_lattice

    t_sec, slat = best_of(lambda: sector_lattice(7, 3, args.rings), args.repeat)
    print(f"  hyperlattice sector_lattice (orbits)   : {t_sec:8.3f} s  {n / t_sec:12.0f} sites/s  (N = {slat.sites},"
          f" {slat.size} orbits)  peak RSS so far {peak_rss_mb():.0f} MB")
    t_secz, _ = best_of(lambda: sector_lattice(7, 3, args.rings, coordinates=True), args.repeat)
    print(f"  ... with orbit coordinates kept        : {t_secz:8.3f} s  {n / t_secz:12.0f} sites/s")

    rates = {}
    # GRC counts layers differently: take the smallest n whose tiling has at least N cells
    # (exponential then binary search: each probe builds a tiling)
    def grc_size(k):
        return len(HyperbolicTiling(3, 7, k, kernel="GRC"))

    hi = 2
    while grc_size(hi) < n:
        hi *= 2
    lo = hi // 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if grc_size(mid) < n else (lo, mid)
    n_grc = hi
    t_grc, til = best_of(lambda: HyperbolicTiling(3, 7, n_grc, kernel="GRC"), args.repeat)
    rates[f"hypertiling GRC n={n_grc} (coords only)"] = (t_grc, len(til))
    if not args.skip_srs:
        t0 = time.perf_counter()
        til = HyperbolicTiling(3, 7, args.rings, kernel="SRS", center="vertex")
        t_srs = time.perf_counter() - t0
        rates["hypertiling SRS vertex (coords only)"] = (t_srs, len(til))
        if args.srs_neighbours:
            t0 = time.perf_counter()
            til.get_nbrs_list()
            rates["hypertiling SRS vertex + neighbours"] = (t_srs + time.perf_counter() - t0, len(til))
    for name, (t, cells) in rates.items():
        print(f"  {name:38s}: {t:8.3f} s  {cells / t:12.0f} sites/s  (N = {cells})")
    fastest = max(c / t for t, c in rates.values())
    print(f"ratio (hyperlattice sites/s over the fastest hypertiling kernel): {n / t_ours / fastest:.1f}x")
    print(f"ratio (sector-only build sites/s over the fastest hypertiling kernel): {n / t_sec / fastest:.1f}x")
    print(f"peak RSS: {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
