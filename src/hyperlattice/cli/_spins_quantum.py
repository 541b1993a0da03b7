"""``hyperlattice spins quantum``: the spin-1/2 XXZ model by quantum Monte Carlo (SSE with directed
loops on the bosons' engine) on a flake, a periodic cluster or a graph of your own.

Contract: ``--json`` prints one object whose first keys are ``sites, e, e_err, c, c_err, chi_u,
chi_u_err, s_pi, s_pi_err`` (per site; ``s_pi`` null on a graph that is not bipartite), then
``mz, binder, rho_s`` (spin stiffness on a periodic cluster, null otherwise) with errors,
``tau_int``, ``update``, the parameters, ``seed``, ``bins``, ``converged``, ``ring_stag``
(the staggered correlation by ring on a flake) and ``notes`` (:meth:`XXZResult.summary`).

The command module ``cmd_spins`` adds this subcommand through :func:`add_parser`.
"""

from __future__ import annotations

import argparse

from ._common import add_pq, finite_float, positive_int, print_json

NAME = "quantum"
ORDER = 20
HELP = "quantum spin-1/2 XXZ model by SSE: energy, specific heat, susceptibility, staggered structure factor"
DESCRIPTION = ("Thermal averages of H = J sum<ij> (Sx Sx + Sy Sy + Delta Sz Sz) - h sum Sz (spin 1/2) at inverse "
               "temperature BETA by stochastic series expansion with directed loops, on a {p,q} flake (--rings), "
               "a periodic cluster (--cluster) or an adjacency matrix (--adjacency, couplings J*A_ij). J < 0 "
               "(ferromagnet) runs on any graph, J > 0 (antiferromagnet) on bipartite graphs only (a graph with "
               "an odd cycle is frustrated: sign problem, refused). Per-site e, c, chi_u and the staggered "
               "structure factor s_pi with binning errors and tau_int; the spin stiffness on periodic clusters.")

#: the contract's keys, first in the JSON object, in this order
KEYS = ("sites", "e", "e_err", "c", "c_err", "chi_u", "chi_u_err", "s_pi", "s_pi_err")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from ._bosons_qmc import _beta, _seed, _sweeps

    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a flake of this many rings (1 = one p-gon)")
    where.add_argument("--cluster", metavar="NAME", help="a periodic cluster, e.g. bolza (its p and q unless -p/-q are given)")
    where.add_argument("--adjacency", metavar="FILE",
                       help="a graph of your own: a symmetric adjacency matrix A (.npz of scipy.sparse.save_npz or "
                            "a dense .npy), couplings J*A_ij")
    add_pq(parser)
    parser.add_argument("--J", type=finite_float, required=True, help="exchange J (> 0 antiferromagnet, < 0 ferromagnet)")
    parser.add_argument("--Delta", type=finite_float, default=1.0, help="anisotropy Delta (default 1: Heisenberg)")
    parser.add_argument("--h", type=finite_float, default=0.0, help="field h along z (default 0)")
    parser.add_argument("--beta", type=_beta, required=True, help="inverse temperature beta")
    parser.add_argument("--sweeps", type=positive_int, default=20000, help="measurement sweeps (default 20000)")
    parser.add_argument("--thermalization", type=_sweeps, default=None, metavar="N",
                        help="thermalisation sweeps (default max(200, sweeps/5))")
    parser.add_argument("--seed", type=_seed, default=None, help="seed of the Markov chain (default: drawn, printed)")
    parser.add_argument("--checkpoint", default=None, metavar="DIR",
                        help="save the chain in DIR (created) every minute and at the end; the same command "
                             "(more --sweeps allowed, with --thermalization given) resumes it, bit-identically")
    parser.add_argument("--no-windings", action="store_true",
                        help="do not measure the spin stiffness (a periodic cluster measures it by default)")
    parser.add_argument("--json", action="store_true",
                        help="print JSON: sites, e, c, chi_u, s_pi with _err first, then mz, binder, rho_s, "
                             "tau_int, update, the parameters, seed, ring_stag and notes")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``quantum`` subcommand to the ``spins`` command's subparsers; returns its parser."""
    p = subparsers.add_parser(NAME, help=HELP, description=DESCRIPTION)
    add_arguments(p)
    p.set_defaults(_spins_run=run)
    return p


def run(args: argparse.Namespace) -> int:
    from ..spins.quantum import xxz_qmc
    from ._bosons_qmc import _system

    from .. import _validate

    checkpoint = None if args.checkpoint is None else _validate.directory("--checkpoint", args.checkpoint)
    system = _system(args)
    res = xxz_qmc(system, J=args.J, Delta=args.Delta, h=args.h, beta=args.beta, sweeps=args.sweeps,
                  thermalization=args.thermalization, seed=args.seed, checkpoint=checkpoint,
                  windings=False if args.no_windings else None)
    if args.json:
        summary = res.summary()
        out = {k: summary[k] for k in KEYS}
        out.update((k, v) for k, v in summary.items() if k not in out)
        print_json(out)
        return 0
    print(str(res))
    print(f"  seed {res.seed}, {res.bins} bins of {res.bin_size} sweeps, {res.seconds:.1f} s")
    if res.ring_stag is not None:
        for row in res.by_ring():
            print(f"  ring {row['ring']:>2} ({row['sites']:>5} sites): stag {row['stag']:.6f} +- {row['stag_err']:.6f}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
