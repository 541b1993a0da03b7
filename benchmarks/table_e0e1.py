"""E0 and E1 of H = -A on the {7,3} ring lattices, computed by hyperlattice.

Two modes:

* ``python benchmarks/table_e0e1.py [--max-rings 14]``: the markdown table of ``docs/spectra.md``
  for rings = 1..max (``lowest_levels`` on the full lattice; method, time and residual per row).
  Times include building the lattice.
* ``python benchmarks/table_e0e1.py --flakes 15 16 [--json PATH] [--p 7 --q 3]``: the sector-only
  path (``lowest_pair``: no full lattice) for big flakes, each ring in a fresh subprocess so that
  its peak resident memory is its own; prints one row per ring and, with ``--json``, writes
  rings, sites, E0, E1, residuals, (n, m) labels, seconds, peak_GB and the command to PATH.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def _one_flake(p: int, q: int, rings: int, backend: str) -> dict:
    from hyperlattice.graph.sectors import lowest_pair

    lowest_pair(p, q, 6, backend=backend)  # compile the numba kernels outside the timing
    t0 = time.perf_counter()
    spec = lowest_pair(p, q, rings, backend=backend)
    seconds = time.perf_counter() - t0
    return {
        "p": p, "q": q, "rings": rings, "sites": spec.sites,
        "E0": float(spec.energies[0]), "E1": float(spec.energies[1]),
        "residual0": float(spec.residuals[0]), "residual1": float(spec.residuals[1]),
        "labels": [[int(n), int(m)] for n, m in zip(spec.n, spec.m)],
        "seconds": round(seconds, 2), "peak_GB": round(peak_rss_mb() / 1024.0, 3),
        "method": spec.method, "backend": backend, "description": spec.description,
        "timings": {k: round(v, 3) for k, v in spec.timings.items()},
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--max-rings", type=int, default=14)
    ap.add_argument("--flakes", type=int, nargs="+", help="rings for the sector-only path (lowest_pair)")
    ap.add_argument("--p", type=int, default=7)
    ap.add_argument("--q", type=int, default=3)
    ap.add_argument("--backend", default="auto", choices=["auto", "cholmod", "splu"])
    ap.add_argument("--json", type=Path, help="write the --flakes rows to this JSON file")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)  # internal: one ring, JSON on stdout
    args = ap.parse_args(argv)

    if args.one is not None:
        print(json.dumps(_one_flake(args.p, args.q, args.one, args.backend)))
        return
    if args.flakes:
        command = "python benchmarks/table_e0e1.py " + " ".join(sys.argv[1:] if argv is None else argv)
        print(f"machine: {machine()}")
        rows = []
        for rings in args.flakes:
            out = subprocess.run([sys.executable, __file__, "--one", str(rings), "--p", str(args.p), "--q",
                                  str(args.q), "--backend", args.backend], capture_output=True, text=True)
            if out.returncode != 0:
                print(f"rings = {rings}: failed: {out.stderr.strip().splitlines()[-1] if out.stderr else '?'}")
                break
            row = json.loads(out.stdout.strip().splitlines()[-1])
            rows.append(row)
            print(f"rings = {rings}: N = {row['sites']:,}  E0 = {row['E0']:.13f}  E1 = {row['E1']:.13f}  "
                  f"(n,m) = {row['labels']}  residuals {row['residual0']:.1e}, {row['residual1']:.1e}  "
                  f"{row['seconds']:.1f} s  peak {row['peak_GB']:.2f} GB", flush=True)
            if args.json:
                args.json.write_text(json.dumps({"command": command, "machine": machine(), "levels": rows},
                                                indent=1) + "\n")
        return

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
