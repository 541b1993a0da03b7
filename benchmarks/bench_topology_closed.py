"""Second Chern number of the 4D lattice Dirac model on an n^4 grid: batched projector curvature vs a per-point loop.

What is timed (one process, project and peer on the same work, taking turns):

* project: the curvature engine of :mod:`hyperlattice.topology.closed` on one n^4 grid (the
  Bloch Hamiltonians and their derivatives from one sparse scatter, batched ``eigh``, the
  curvature ``F = i(X^dagger X - ...)`` for all six pairs at once, chunks of 4,096 points);
* peer: what one writes without it, the same formula point by point (``numpy.linalg.eigh`` of
  H(k) built from the hop list, the four derivatives, the six curvatures, the trace products).

Both give the same number (same formula, same grid); printed with the difference. One BLAS thread.
The machine is shared: the load average is printed.

Usage: ``python benchmarks/bench_topology_closed.py [--grid 12] [--m -3] [--repeat 2]``.
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import interleaved, machine  # noqa: E402


def peer(terms, n: int, occ: int) -> float:
    d = terms.orbitals
    w = terms.windings.astype(float)
    ks = 2 * np.pi * np.arange(n) / n
    total = 0.0
    for k in itertools.product(ks, repeat=4):
        ph = np.exp(1j * (w @ np.array(k)))
        H = terms.onsite[0].copy()
        dH = [np.zeros((d, d), dtype=complex) for _ in range(4)]
        for h in range(len(ph)):
            H += ph[h] * terms.blocks[h]
            for mu in range(4):
                dH[mu] += 1j * w[h, mu] * ph[h] * terms.blocks[h]
        e, v = np.linalg.eigh(H)
        vo, vu = v[:, :occ], v[:, occ:]
        den = e[None, :occ] - e[occ:, None]
        X = [(vu.conj().T @ x @ vo) / den for x in dH]
        F = {}
        for i, j in itertools.combinations(range(4), 2):
            xy = X[i].conj().T @ X[j]
            F[i, j] = 1j * (xy - xy.conj().T)
        total += float(np.trace(F[0, 1] @ F[2, 3] - F[0, 2] @ F[1, 3] + F[0, 3] @ F[1, 2]).real)
    return total * (2 * np.pi / n) ** 4 / (4 * np.pi ** 2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, default=12)
    ap.add_argument("--m", type=float, default=-3.0)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    from hyperlattice.graph.solvers import single_threaded_blas
    from hyperlattice.topology.closed import _Bloch, _second_chern_subtorus, dirac4_torus

    print(machine())
    print(f"load before: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    terms = dirac4_torus(args.m)
    bloch = _Bloch(terms)
    with single_threaded_blas():
        best, out = interleaved({
            "project": lambda: _second_chern_subtorus(bloch, 4, (0, 1, 2, 3), 2, args.grid)[0],
            "peer": lambda: peer(terms, args.grid, 2),
        }, args.repeat)
    print(f"4D Dirac m = {args.m}, grid {args.grid}^4 = {args.grid ** 4:,} points")
    print(f"  project {best['project']:.3f} s  C2 = {out['project']:.6f}")
    print(f"  peer    {best['peer']:.3f} s  C2 = {out['peer']:.6f}  (difference {abs(out['project'] - out['peer']):.1e})")
    print(f"  ratio peer / project = {best['peer'] / best['project']:.1f}")
    print(f"load after: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
