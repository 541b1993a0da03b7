"""``hyperlattice bosons qmc``: grand-canonical quantum Monte Carlo (SSE, directed loops) of the
Bose–Hubbard model on a flake or a periodic cluster at inverse temperature beta.

Contract: ``--json`` prints one object with at least the keys ``sites, energy,
energy_err, density, density_err, compressibility, compressibility_err, tau_int`` (energy: the
total <H>, the -mu N term included; density and compressibility per site; ``tau_int`` the
integrated autocorrelation times in sweeps by observable), then the rest of
:meth:`hyperlattice.bosons.QMCResult.summary` (the parameters, ``seed``, ``bins``,
``converged``, ``notes``...), among them the superfluid stiffness from the winding numbers:
``rho_s, rho_s_err, stiffness_geometric, stiffness_geometric_err, stiffness, stiffness_err``
(the D x D tensor) and ``tau_int["stiffness"]`` when the graph has windings (a periodic cluster,
or ``--windings FILE.npy``), null otherwise, and ``stiffness_note`` saying why.

The graph: a flake (``--rings``), a periodic cluster (``--cluster``) or a user's adjacency matrix
(``--adjacency FILE``). Its edges, in the order a ``--windings`` file follows, are the pairs
(i, j) with i < j and A_ij != 0 sorted by i, then j (:func:`edges`).
"""

from __future__ import annotations

import argparse

import numpy as np

from ._chain_args import add_chain, add_graph, show
from ._chain_args import beta as _beta
from ._chain_args import graph as _system
from ._common import Interrupted, check_work, finite_float, positive_int

NAME = "qmc"
ORDER = 40
HELP = "quantum Monte Carlo (SSE): thermal energy, density and compressibility with error bars"
DESCRIPTION = ("Thermal averages of H = -t sum<ij>(a_i^+ a_j + h.c.) + (U/2) sum n_i(n_i-1) - mu sum n_i at "
               "inverse temperature BETA with at most NMAX bosons per site (NMAX = 1: hard-core), by "
               "stochastic series expansion with directed loops, on a {p,q} flake (--rings), a periodic "
               "cluster (--cluster, names from 'hyperlattice cluster --list') or a graph of your own "
               "(--adjacency). Errors from a binning analysis; "
               "the energy is the total <H> (the -mu N term included), density and compressibility per site. "
               "On a periodic cluster (or with --windings) the superfluid stiffness from the winding numbers "
               "is measured too: JSON keys rho_s, rho_s_err, stiffness_geometric, stiffness_geometric_err, "
               "stiffness and stiffness_err (D x D), tau_int.stiffness; null without windings, "
               "stiffness_note says why.")

#: default of ``--max-seconds`` for a chain (a day: QMC runs are long by nature, and checkpointed)
MAX_SECONDS = 86400.0

#: the contract's keys, first in the JSON object, in this order
KEYS = ("sites", "energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err",
        "tau_int")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_graph(parser, "a periodic cluster, e.g. bolza or klein (its p and q unless -p/-q are given)",
              "a graph of your own: a symmetric adjacency matrix, .npz written by scipy.sparse.save_npz or a "
              "dense .npy (couplings t*A_ij >= 0; -p/-q unused)")
    parser.add_argument("--nmax", type=positive_int, required=True,
                        help="occupation cutoff per site (1 = hard-core bosons)")
    parser.add_argument("--U", type=finite_float, required=True, help="on-site interaction U")
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--mu", type=finite_float, required=True, help="chemical potential mu")
    parser.add_argument("--beta", type=_beta, required=True, help="inverse temperature beta (units of 1/t)")
    add_chain(parser, sweeps_default=20000,
              thermalization="max(200, sweeps/5); 0 is refused unless resuming a thermalised --checkpoint; a "
                             "resumed chain that has begun measuring keeps its own",
              saved=", at the end and on Ctrl-C/SIGTERM", resume="more --sweeps allowed, --seed not needed")
    parser.add_argument("--max-seconds", type=finite_float, default=MAX_SECONDS, metavar="S",
                        help=f"refuse a chain estimated to take longer than S seconds (default {MAX_SECONDS:g}, a "
                             "day; runs estimated above 30 s are announced on stderr)")
    wind = parser.add_mutually_exclusive_group()
    wind.add_argument("--windings", metavar="FILE.npy",
                      help="winding numbers of the edges for the superfluid stiffness: an integer array of "
                           "shape (edges, D), row k the windings around the D cycles of the k-th edge (i, j), "
                           "i < j, A_ij != 0, sorted by i then j, counted from i to j (on a cluster it replaces "
                           "the automatic tree-cotree windings)")
    wind.add_argument("--no-windings", action="store_true",
                      help="do not measure the stiffness (a periodic cluster measures it by default)")
    parser.add_argument("--json", action="store_true",
                        help="print JSON: sites, energy(_err), density(_err), compressibility(_err), tau_int "
                             "first, then the parameters, seed, bins, converged, notes and the stiffness keys")


def edges(system) -> np.ndarray:
    """The edges (i, j), i < j, of a flake, cluster or matrix, sorted by i then j: the rows of a windings file."""
    import scipy.sparse as sp

    if sp.issparse(system):
        mat = system
    elif hasattr(system, "genus"):
        mat = system.adjacency()
    else:
        from ..graph.operators import adjacency

        mat = adjacency(system)
    up = sp.coo_matrix(sp.triu(sp.csr_matrix(mat), k=1))
    keep = up.data != 0
    pairs = np.column_stack([up.row[keep], up.col[keep]]).astype(np.int64)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def _windings(value, system):
    """``--windings FILE.npy`` as the (edges, windings) pair :func:`hyperlattice.bosons.qmc` takes."""
    from .. import _validate

    path = _validate.input_path("--windings", value, suffixes=(".npy",))
    try:
        w = np.load(path, allow_pickle=False)
    except Exception as exc:
        raise ValueError(f"--windings {str(path)!r} is not an array written by numpy.save: "
                         f"{_validate.file_problem(exc)}.") from None
    pairs = edges(system)
    if not isinstance(w, np.ndarray) or w.dtype.kind not in "iu":
        raise ValueError(f"--windings {str(path)!r} must hold integers (the winding of each edge around each "
                         f"cycle), got {getattr(w, 'dtype', type(w).__name__)}.")
    if w.ndim != 2 or w.shape[0] != len(pairs) or not 1 <= w.shape[1] <= 64:
        raise ValueError(f"--windings {str(path)!r} must be an array of shape (edges, D) with one row per edge "
                         f"(i, j), i < j, sorted by i then j ({len(pairs)} edges) and 1 <= D <= 64, got shape "
                         f"{w.shape}.")
    return pairs, w.astype(np.int64)


def _estimate(system, args) -> None:
    """Refuse (or announce) a long chain before it starts: :func:`hyperlattice.bosons.qmc_seconds`."""
    from .. import _validate
    from ..bosons.sse import SECONDS_PER_OPERATOR, qmc_memory, qmc_seconds

    need = qmc_memory(system, U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax, t=args.t)
    if need + 2**28 > _validate.available_memory():
        return      # the chain will not fit: qmc refuses it with its own sentence (the memory, not the time)
    therm = args.thermalization if args.thermalization else None
    seconds = qmc_seconds(system, U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax, t=args.t,
                          sweeps=args.sweeps, thermalization=therm)
    total = args.sweeps + (therm if therm is not None else max(200, args.sweeps // 5))
    ops = seconds / (total * SECONDS_PER_OPERATOR)
    check_work("bosons qmc", seconds, args.max_seconds,
               f"{total:,} sweeps of about {ops:,.0f} operators at about {SECONDS_PER_OPERATOR * 1e6:g} us each",
               "fewer --sweeps, a smaller --beta, --nmax or graph")


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..bosons import qmc

    checkpoint = None if args.checkpoint is None else _validate.directory("--checkpoint", args.checkpoint)
    system = _system(args)
    windings = False if args.no_windings else None if args.windings is None else _windings(args.windings, system)
    _estimate(system, args)
    try:
        res = qmc(system, U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax, t=args.t, sweeps=args.sweeps,
                  thermalization=args.thermalization, seed=args.seed, checkpoint=checkpoint, windings=windings)
    except KeyboardInterrupt as exc:
        # the chain stopped between kernel calls (saved when --checkpoint is given): say so in the line
        raise Interrupted(str(exc) or ("the chain is in " + str(checkpoint) if checkpoint else "nothing kept")) from None
    return show(res, KEYS, args.json)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
