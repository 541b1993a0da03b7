"""``hyperlattice bosons qmc``: grand-canonical quantum Monte Carlo (SSE, directed loops) of the
Bose–Hubbard model on a flake or a periodic cluster at inverse temperature beta.

Contract (issue 27, item 5): ``--json`` prints one object with at least the keys ``sites, energy,
energy_err, density, density_err, compressibility, compressibility_err, tau_int`` (energy: the
total <H>, the -mu N term included; density and compressibility per site; ``tau_int`` the
integrated autocorrelation times in sweeps by observable), then the rest of
:meth:`hyperlattice.bosons.QMCResult.summary` (the parameters, ``seed``, ``bins``,
``converged``, ``notes``...).
"""

from __future__ import annotations

import argparse

from ._common import add_pq, cluster_pq, finite_float, integer, positive_int, print_json

NAME = "qmc"
ORDER = 40
HELP = "quantum Monte Carlo (SSE): thermal energy, density and compressibility with error bars"
DESCRIPTION = ("Thermal averages of H = -t sum<ij>(a_i^+ a_j + h.c.) + (U/2) sum n_i(n_i-1) - mu sum n_i at "
               "inverse temperature BETA with at most NMAX bosons per site (NMAX = 1: hard-core), by "
               "stochastic series expansion with directed loops, on a {p,q} flake (--rings) or a periodic "
               "cluster (--cluster, names from 'hyperlattice cluster --list'). Errors from a binning analysis; "
               "the energy is the total <H> (the -mu N term included), density and compressibility per site.")

#: the contract's keys, first in the JSON object, in this order
KEYS = ("sites", "energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err",
        "tau_int")


def _seed(text: str) -> int:
    v = integer(text, what="a seed (an integer >= 0)")
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a seed >= 0, got {v}")
    return v


def _sweeps(text: str) -> int:
    v = integer(text, what="a number of sweeps")
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a number of sweeps >= 0, got {v}")
    return v


def _beta(text: str) -> float:
    v = finite_float(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected an inverse temperature > 0, got {text!r}")
    return v


def add_arguments(parser: argparse.ArgumentParser) -> None:
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a flake of this many rings (1 = one p-gon)")
    where.add_argument("--cluster", metavar="NAME", help="a periodic cluster, e.g. bolza or klein (its p and q unless -p/-q are given)")
    add_pq(parser)
    parser.add_argument("--nmax", type=positive_int, required=True,
                        help="occupation cutoff per site (1 = hard-core bosons)")
    parser.add_argument("--U", type=finite_float, required=True, help="on-site interaction U")
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--mu", type=finite_float, required=True, help="chemical potential mu")
    parser.add_argument("--beta", type=_beta, required=True, help="inverse temperature beta (units of 1/t)")
    parser.add_argument("--sweeps", type=positive_int, default=20000, help="measurement sweeps (default 20000)")
    parser.add_argument("--thermalization", type=_sweeps, default=None, metavar="N",
                        help="thermalisation sweeps (default max(200, sweeps/5))")
    parser.add_argument("--seed", type=_seed, default=None,
                        help="seed of the Markov chain (default: drawn, and printed in the output)")
    parser.add_argument("--checkpoint", default=None, metavar="DIR",
                        help="save the chain in DIR (created) every minute and at the end; the same command "
                             "(more --sweeps allowed) resumes it, bit-identically")
    parser.add_argument("--json", action="store_true", help="print JSON")


def _system(args: argparse.Namespace):
    from .. import _validate

    p, q = _validate.pq(args.p, args.q) if args.cluster is None else cluster_pq(args, args.cluster)
    if args.rings is not None:
        from ..graph.lattice import ring_lattice

        return ring_lattice(p, q, args.rings)
    from ..graph.clusters import pbc_cluster

    return pbc_cluster(p, q, args.cluster)


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..bosons import qmc

    checkpoint = None if args.checkpoint is None else _validate.directory("--checkpoint", args.checkpoint)
    system = _system(args)
    res = qmc(system, U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax, t=args.t, sweeps=args.sweeps,
              thermalization=args.thermalization, seed=args.seed, checkpoint=checkpoint)
    if args.json:
        summary = res.summary()
        out = {k: summary[k] for k in KEYS}
        out.update((k, v) for k, v in summary.items() if k not in out)
        print_json(out)
        return 0
    print(str(res))
    print(f"  seed {res.seed}, {res.bins} bins of {res.bin_size} sweeps, {res.seconds:.1f} s")
    return 0


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
