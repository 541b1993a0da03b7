"""The topological Anderson insulator of QWZ on {8,3}: the two-terminal conductance against disorder.

QWZ on the l-ring {8,3} flake at a mass M on the trivial side of the transition (M_c ≈ 1.48), box
disorder W, leads on two quarter arcs of the edge (coupling 2 t), E = 0. For each W the mean
conductance over the seeds with its standard error, the median and the fraction of realizations
within 0.05 of one e²/h. Prints a Markdown table (the one of docs/topology.md).

Usage: ``python benchmarks/topology_tai.py [--rings 4] [--M 1.52] [--seeds 16]``.
"""

from __future__ import annotations

import argparse

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, default=4)
    ap.add_argument("--M", type=float, default=1.52)
    ap.add_argument("--seeds", type=int, default=16)
    ap.add_argument("--W", default="0,1,1.5,2,2.5,3,3.5,4,5,6")
    args = ap.parse_args()
    import hyperlattice as hl
    from hyperlattice.topology.transport import conductance

    lat = hl.ring_lattice(8, 3, args.rings)
    print("| W | mean G (e²/h) | standard error | median | within 0.05 of 1 | realizations |")
    print("|---|---|---|---|---|---|")
    for W in (float(x) for x in args.W.split(",")):
        g = np.array([conductance(lat, "qwz", M=args.M, disorder=W, seed=s).conductance[0]
                      for s in range(args.seeds)])
        print(f"| {W:g} | {g.mean():.3f} | {g.std(ddof=1) / np.sqrt(g.size):.3f} | {np.median(g):.3f} | "
              f"{np.mean(np.abs(g - 1) < 0.05):.2f} | {g.size} |", flush=True)


if __name__ == "__main__":
    main()
