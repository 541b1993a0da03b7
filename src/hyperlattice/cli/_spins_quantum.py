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

from ._chain_args import add_chain, add_graph, beta, graph, show
from ._common import Interrupted, finite_float

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
    add_graph(parser, "a periodic cluster, e.g. bolza (its p and q unless -p/-q are given)",
              "a graph of your own: a symmetric adjacency matrix A (.npz of scipy.sparse.save_npz or a dense "
              ".npy), couplings J*A_ij")
    parser.add_argument("--J", type=finite_float, required=True, help="exchange J (> 0 antiferromagnet, < 0 ferromagnet)")
    parser.add_argument("--Delta", type=finite_float, default=1.0, help="anisotropy Delta (default 1: Heisenberg)")
    parser.add_argument("--h", type=finite_float, default=0.0, help="field h along z (default 0)")
    parser.add_argument("--beta", type=beta, required=True, help="inverse temperature beta")
    add_chain(parser, sweeps_default=20000, thermalization="max(200, sweeps/5)",
              saved=", at the end and on Ctrl-C/SIGTERM", resume="more --sweeps allowed, with --thermalization given")
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
    from .. import _validate
    from ..spins.quantum import xxz_qmc

    checkpoint = None if args.checkpoint is None else _validate.directory("--checkpoint", args.checkpoint)
    try:
        res = xxz_qmc(graph(args), J=args.J, Delta=args.Delta, h=args.h, beta=args.beta, sweeps=args.sweeps,
                      thermalization=args.thermalization, seed=args.seed, checkpoint=checkpoint,
                      windings=False if args.no_windings else None)
    except KeyboardInterrupt as exc:
        # the chain stopped between kernel calls (saved when --checkpoint is given): say so in the line
        raise Interrupted(str(exc) or ("the chain is in " + str(checkpoint) if checkpoint else "nothing kept")) from None
    rings = [] if args.json or res.ring_stag is None else [
        f"  ring {row['ring']:>2} ({row['sites']:>5} sites): stag {row['stag']:.6f} +- {row['stag_err']:.6f}"
        for row in res.by_ring()]
    return show(res, KEYS, args.json, after=rings)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
