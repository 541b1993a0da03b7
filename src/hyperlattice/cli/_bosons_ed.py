"""``hyperlattice bosons ed``: exact diagonalisation of the Bose–Hubbard model on a flake or a cluster.

Contract: ``--json`` prints one object with the keys ``sites, particles, nmax, U, t,
dim, energies`` (the lowest eigenvalues of H at mu = 0, ascending) and the extras ``m, residuals,
method, p, q, rings, cluster`` (and ``condensate_fraction`` with ``--observables``, ``note`` when the
result has one, e.g. more levels asked than the basis has states).
"""

from __future__ import annotations

import argparse

from ._common import add_pq, cluster_pq, finite_float, integer, positive_int, print_json

NAME = "ed"
ORDER = 10
HELP = "exact diagonalisation: lowest Bose-Hubbard levels with rotation-sector labels"
DESCRIPTION = ("Lowest levels of H = -t sum<ij>(a_i^+ a_j + h.c.) + (U/2) sum n_i(n_i-1) at mu = 0 for N "
               "bosons with at most NMAX per site (NMAX = 1: hard-core), on a {p,q} flake (--rings) or a "
               "periodic cluster (--cluster, names from 'hyperlattice cluster --list').")


def _particles(text: str) -> int:
    v = integer(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a number of bosons >= 0, got {v}")
    return v


def add_arguments(parser: argparse.ArgumentParser) -> None:
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a flake of this many rings (1 = one p-gon)")
    where.add_argument("--cluster", metavar="NAME", help="a periodic cluster, e.g. bolza or klein (its p and q unless -p/-q are given)")
    add_pq(parser)
    parser.add_argument("--particles", type=_particles, required=True, help="number of bosons N")
    parser.add_argument("--nmax", type=positive_int, required=True,
                        help="occupation cutoff per site (1 = hard-core bosons)")
    parser.add_argument("--U", type=finite_float, required=True, help="on-site interaction U")
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--levels", type=positive_int, default=4, help="number of lowest levels (default 4)")
    parser.add_argument("--method", choices=["auto", "sectors", "csr", "matrix-free", "dense"], default="auto",
                        help="route (default auto: angular-momentum sectors when the lattice has a rotation)")
    parser.add_argument("--observables", action="store_true",
                        help="also compute the ground-state density matrix and condensate fraction")
    parser.add_argument("--json", action="store_true", help="print JSON")


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..bosons.ed import bose_hubbard

    p, q = _validate.pq(args.p, args.q) if args.cluster is None else cluster_pq(args, args.cluster)
    if args.rings is not None:
        from ..graph.lattice import ring_lattice

        lattice = ring_lattice(p, q, args.rings)
    else:
        from ..graph.clusters import pbc_cluster

        lattice = pbc_cluster(p, q, args.cluster)
    res = bose_hubbard(lattice, args.particles, args.nmax, args.U, t=args.t, levels=args.levels,
                       method=args.method, observables=args.observables)
    if args.json:
        print_json(res.summary())
        return 0
    where = f"cluster {res.cluster}" if res.cluster is not None else f"flake, {res.rings} ring(s)"
    trunc = "hard-core" if res.nmax == 1 else ("exact" if res.nmax >= res.particles else "truncated")
    print(f"Bose-Hubbard ED on the {{{res.p},{res.q}}} {where}: {res.sites} sites, N = {res.particles}, "
          f"nmax = {res.nmax} ({trunc}), U = {res.U:g}, t = {res.t:g}, mu = 0")
    print(f"  dimension {res.dim:,}, method {res.method}, {res.seconds:.2f} s")
    print(f"  {'level':>5} {'E':>20} {'m':>4} {'residual':>10}")
    for i, e in enumerate(res.energies):
        m = "-" if res.m is None else str(int(res.m[i]))
        print(f"  {i:>5} {e:>20.12f} {m:>4} {res.residuals[i]:>10.1e}")
    if res.density is not None:
        print(f"  condensate fraction {res.condensate_fraction:.6f}")
    if res.note:
        print(f"  note: {res.note}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
