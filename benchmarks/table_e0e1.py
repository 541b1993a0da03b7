"""E0 and E1 of H = -A on the {7,3} ring lattices, rings = 1..14, computed by hyperlattice.

Prints the markdown table of ``docs/spectra.md`` (method, time and residual per row):
``python benchmarks/table_e0e1.py [--max-rings 14]``. Times include building the lattice.
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
    ap.add_argument("--max-rings", type=int, default=14)
    args = ap.parse_args(argv)

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.spectrum import lowest_levels

    print(f"<!-- machine: {machine()} -->")
    print("| ℓ | N | E0 (n,m)=(1,0) | E1 (n,m)=(1,±1) | E1 − E0 | method | time [s] | max residual |")
    print("|---:|---:|---:|---:|---:|---|---:|---:|")
    for rings in range(1, args.max_rings + 1):
        t0 = time.perf_counter()
        lat = ring_lattice(7, 3, rings)
        spec = lowest_levels(lat, 2)
        dt = time.perf_counter() - t0
        e0, e1 = spec.energies
        labels = list(zip(spec.n.tolist(), spec.m.tolist()))
        assert labels == [(1, 0), (1, 1)], labels
        print(f"| {rings} | {lat.sites:,} | {e0:.13f} | {e1:.13f} | {e1 - e0:.13f} | {spec.method} | "
              f"{dt:.2f} | {spec.residuals.max():.1e} |", flush=True)
    print(f"<!-- peak RSS {peak_rss_mb():.0f} MB -->")


if __name__ == "__main__":
    main()
