"""Two-terminal conductance of a {8,3} QWZ flake: the project's sparse Caroli route against a dense peer.

Peer: the same Caroli trace with the retarded Green function from a dense LU solve
(``scipy.linalg.solve`` of E − H − Σ for the right contact's columns), the route a user without a
sparse solver takes (Kwant, the strongest transport package, needs leads that are semi-infinite
translation-invariant systems: a hyperbolic flake has none, so it is not the peer here). Both at the
same energies in one process, interleaved; the two conductances agree to rounding.

Usage: ``python benchmarks/bench_topology_transport.py [--rings 4 5] [--energies 5]``.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from _machine import interleaved, machine, peak_rss_mb


def dense_peer(lat, energies, gamma=2.0):
    import scipy.linalg as sla

    from hyperlattice.topology.markers import _rows
    from hyperlattice.topology.models import model_hamiltonian, model_terms
    from hyperlattice.topology.transport import edge_contacts

    left, right = edge_contacts(lat)
    H = model_hamiltonian(model_terms(lat, "qwz", M=1.0)).toarray()
    rl, rr = _rows(left, 2), _rows(right, 2)
    sig = np.zeros(len(H))
    sig[rl] = sig[rr] = gamma
    out = []
    for E in energies:
        A = E * np.eye(len(H)) - H + 0.5j * np.diag(sig)
        rhs = np.zeros((len(H), len(rr)), complex)
        rhs[rr, np.arange(len(rr))] = 1
        X = sla.solve(A, rhs)
        out.append(gamma * gamma * float(np.sum(np.abs(X[rl]) ** 2)))
    return np.array(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, nargs="+", default=[4, 5])
    ap.add_argument("--energies", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    import hyperlattice as hl
    from hyperlattice.graph.solvers import single_threaded_blas
    from hyperlattice.topology.transport import conductance

    print(machine(), "| load average", os.getloadavg())
    es = np.linspace(-0.3, 0.3, args.energies)
    for rings in args.rings:
        lat = hl.ring_lattice(8, 3, rings)
        with single_threaded_blas():
            best, out = interleaved({"project": lambda: conductance(lat, "qwz", M=1.0, energies=es).conductance,
                                     "peer": lambda: dense_peer(lat, es)}, args.repeat)
        diff = float(np.max(np.abs(out["project"] - out["peer"])))
        print(f"{{8,3}} l = {rings}: {len(lat.z)} sites, {args.energies} energies: project {best['project']:.3f} s, "
              f"dense peer {best['peer']:.3f} s, ratio {best['peer'] / best['project']:.1f}x, "
              f"max |G - G_peer| = {diff:.1e} e^2/h, G = {out['project'].round(4).tolist()}")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
