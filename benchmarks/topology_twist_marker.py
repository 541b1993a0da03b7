"""The twist-derivative Chern marker of {8,3} clusters: sum rule against the Chern matrix, and locality.

For the covariant QWZ model (M = 1, half filling; its Chern matrix is -Q, minus the intersection
form, docs/topology-surfaces.md) on Bolza (16 sites), Dyck (32) and PSL(2,17) (816 sites, genus 52,
systole 15), and for Haldane (t2 = 0.2, E_F = -1.3, the C = +1 gap; Chern matrix +Q) on Bolza and
Dyck: one diagonalisation at zero twist gives ``total`` = sum_x c_ab(x) for every pair (a, b);
printed: the largest deviation from the Chern matrix over all pairs, and for the first pair with
Q != 0 the share of its marker within r bonds of both cuts (r = 0..5).

Usage::

    python benchmarks/topology_twist_marker.py            # all three clusters (~4 min, 1 GB)
    python benchmarks/topology_twist_marker.py --small    # Bolza and Dyck only (seconds)
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main() -> None:
    import hyperlattice as hl
    from hyperlattice.topology.frames import qwz_frame_terms
    from hyperlattice.topology.landau import intersection_form
    from hyperlattice.topology.twist_marker import twist_marker

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="Bolza and Dyck only")
    args = ap.parse_args()
    names = ("bolza", "dyck") if args.small else ("bolza", "dyck", "PSL(2,17)")
    print("| cluster | sites | genus | model | gap at k = 0 | max over pairs abs(total - C) | "
          "share within r = 0..5 bonds of both cuts | seconds |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        cl = hl.pbc_cluster(8, 3, name)
        Q = intersection_form(cl)
        iu = np.triu_indices(len(Q), 1)
        first = next((int(a), int(b)) for a, b in zip(*iu) if Q[a, b] != 0)
        runs = [("qwz covariant M=1", qwz_frame_terms(cl, M=1.0), {}, -Q)]
        if name in ("bolza", "dyck"):
            runs.append(("haldane t2=0.2 E_F=-1.3", cl, dict(model="haldane", M=0.0, t2=0.2, fermi_level=-1.3), Q))
        for label, system, kw, chern in runs:
            t0 = time.process_time()
            r = twist_marker(system, pairs=[first], **kw)
            dt = time.process_time() - t0
            share = " ".join(f"{r.within(x)[0]:.3f}" for x in range(6))
            print(f"| {name} | {cl.sites} | {cl.genus} | {label} | {r.gap:.3f} | "
                  f"{np.abs(r.total - chern).max():.1e} | {share} | {dt:.0f} |", flush=True)


if __name__ == "__main__":
    main()
