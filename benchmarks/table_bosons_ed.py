"""The table of docs/bosons-ed.md: Bose–Hubbard ED on the required systems (issue 22, item 1).

For each system: Fock dimension, E0 and E1 with their angular-momentum labels m, the charge gap
E0(N+1) + E0(N-1) - 2 E0(N) at mu = 0, the condensate fraction of the ground state, and the wall
time of the N-boson run (sectors route, 2 cores). Prints a Markdown table.

Usage: ``python benchmarks/table_bosons_ed.py [--quick]`` (``--quick`` leaves out the
charge gaps of the 5-million-state rows, Bolza at unit filling and Klein, which take minutes).
"""

from __future__ import annotations

import argparse
import time


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rows", type=int, nargs="*", help="only these rows (0-based)")
    args = ap.parse_args(argv)

    from hyperlattice import ring_lattice
    from hyperlattice.bosons.ed import bose_hubbard, charge_gap
    from hyperlattice.graph.clusters import pbc_cluster

    rows = [
        ("{7,3} heptagon", lambda: ring_lattice(7, 3, 1), 7, 7, 4.0, True),
        ("{7,3} heptagon", lambda: ring_lattice(7, 3, 1), 7, 7, 20.0, True),
        ("{7,3} heptagon, hard-core", lambda: ring_lattice(7, 3, 1), 3, 1, 0.0, True),
        ("{7,3} flake l=2", lambda: ring_lattice(7, 3, 2), 4, 4, 4.0, True),
        ("{7,3} flake l=2, hard-core", lambda: ring_lattice(7, 3, 2), 5, 1, 0.0, True),
        ("{8,3} Bolza", lambda: pbc_cluster(8, 3, "bolza"), 16, 2, 4.0, not args.quick),
        ("{8,3} Bolza", lambda: pbc_cluster(8, 3, "bolza"), 16, 2, 10.0, not args.quick),
        ("{7,3} Klein quartic", lambda: pbc_cluster(7, 3, "klein"), 4, 4, 4.0, not args.quick),
    ]
    print("| system | sites | N | nmax | U | dim | E0 (m) | E1 (m) | charge gap | f_c | time (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for k, (name, make, n, c, u, gap) in enumerate(rows):
        if args.rows and k not in args.rows:
            continue
        lat = make()
        t0 = time.perf_counter()
        r = bose_hubbard(lat, n, c, u, levels=2)
        dt = time.perf_counter() - t0
        g = "-"
        if gap:
            g = f"{charge_gap(lat, n, c, u).gap:.6f}"
        trunc = "" if c == 1 or c >= n else " (trunc.)"
        m0 = "" if r.m is None else f" ({int(r.m[0])})"
        m1 = "" if r.m is None else f" ({int(r.m[1])})"
        print(f"| {name} | {r.sites} | {n} | {c}{trunc} | {u:g} | {r.dim:,} | {r.energies[0]:.8f}{m0} | "
              f"{r.energies[1]:.8f}{m1} | {g} | {r.condensate_fraction:.5f} | {dt:.1f} |", flush=True)


if __name__ == "__main__":
    main()
