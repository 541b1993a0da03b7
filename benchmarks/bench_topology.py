"""The hyperbolic local marker at the centre of a {8,3} QWZ flake: Chebyshev projector vs dense eigh.

What is timed (one process, project and peer on the same work):

* project: :func:`hyperlattice.topology.kpm_marker.centre_marker`, the Chebyshev expansion of
  P = theta(E_F - H) applied to the unit vectors of the disks around the evaluated ring-1 sites
  and the centre, then the site-centred Kitaev sums on those blocks;
* peer: dense ``numpy.linalg.eigh`` of the same Hamiltonian (one BLAS thread, as the project),
  P on the same disks from the occupied eigenvectors, the same Kitaev sums.

Both at E_F = 0, radius 4 bond lengths, QWZ at M = 1. Accuracy: the difference of the two
markers, next to the project's own error estimate (N vs N/2 moments).

Then the centre marker of the ``--big`` flake (l = 7: 40,328 sites, 80,656 rows; a dense complex
eigh would need 2 x 104 GB), with the peak memory of this process.

The machine is shared: the load average is printed before and after each part.

Usage: ``python benchmarks/bench_topology.py [--rings 5] [--moments 512] [--big 7] [--no-peer]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def dense_centre(lat, evaluated, radius, M=1.0):
    from hyperlattice.graph.solvers import single_threaded_blas
    from hyperlattice.topology.markers import _geometry, _local_kitaev, occupied_states

    with single_threaded_blas():
        occ = occupied_states(lat, "qwz", M=M, fermi=0.0)
        geo = _geometry(lat)
        vals = [_local_kitaev(geo, occ.vectors, occ.orbitals, geo.z[i], radius) for i in evaluated]
    return float(np.mean(vals))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rings", type=int, default=5)
    ap.add_argument("--moments", type=int, default=512)
    ap.add_argument("--big", type=int, default=7)
    ap.add_argument("--no-peer", action="store_true")
    args = ap.parse_args()

    import hyperlattice as hl
    from hyperlattice.topology.kpm_marker import centre_marker

    print(machine())
    lat = hl.ring_lattice(8, 3, args.rings)
    print(f"{{8,3}} flake, {args.rings} rings: {lat.sites:,} sites, {2 * lat.sites:,} rows; load {load()}")
    t0 = time.perf_counter()
    res = centre_marker(lat, "qwz", M=1.0, moments=args.moments)
    t_kpm = time.perf_counter() - t0
    print(f"  project (Chebyshev, N = {args.moments}, {res.vectors} vectors): marker {res.marker:+.6f} "
          f"(estimate +- {res.marker_error:.1e}), {t_kpm:.2f} s; load {load()}")
    if not args.no_peer:
        t0 = time.perf_counter()
        ref = dense_centre(lat, res.evaluated_sites, res.parameters["radius"])
        t_dense = time.perf_counter() - t0
        print(f"  peer (dense eigh + same marker): marker {ref:+.6f}, {t_dense:.2f} s; load {load()}")
        print(f"  ratio peer / project: {t_dense / t_kpm:.1f}x; |difference| {abs(ref - res.marker):.1e}")
    if args.big:
        big = hl.ring_lattice(8, 3, args.big)
        print(f"{{8,3}} flake, {args.big} rings: {big.sites:,} sites, {2 * big.sites:,} rows "
              f"(dense complex eigenvectors alone: {16 * (2 * big.sites) ** 2 / 1e9:.0f} GB); load {load()}")
        t0 = time.perf_counter()
        r = centre_marker(big, "qwz", M=1.0, moments=args.moments)
        print(f"  project: marker {r.marker:+.6f} (estimate +- {r.marker_error:.1e}), Kitaev {r.kitaev:+.6f}, "
              f"{time.perf_counter() - t0:.1f} s, expansion memory {r.memory_bytes / 1e6:.0f} MB, "
              f"peak RSS {peak_rss_mb():.0f} MB; load {load()}")


if __name__ == "__main__":
    main()
