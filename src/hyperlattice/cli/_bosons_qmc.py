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

from ._common import Interrupted, add_pq, check_work, cluster_pq, finite_float, integer, positive_int, print_json

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

#: largest number of sites of an --adjacency file (the same bound as a flake's)
MAX_ADJACENCY_SITES = 10_000_000

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
    where.add_argument("--adjacency", metavar="FILE",
                       help="a graph of your own: a symmetric adjacency matrix, .npz written by "
                            "scipy.sparse.save_npz or a dense .npy (couplings t*A_ij >= 0; -p/-q unused)")
    add_pq(parser)
    parser.add_argument("--nmax", type=positive_int, required=True,
                        help="occupation cutoff per site (1 = hard-core bosons)")
    parser.add_argument("--U", type=finite_float, required=True, help="on-site interaction U")
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--mu", type=finite_float, required=True, help="chemical potential mu")
    parser.add_argument("--beta", type=_beta, required=True, help="inverse temperature beta (units of 1/t)")
    parser.add_argument("--sweeps", type=positive_int, default=20000, help="measurement sweeps (default 20000)")
    parser.add_argument("--thermalization", type=_sweeps, default=None, metavar="N",
                        help="thermalisation sweeps (default max(200, sweeps/5); 0 is refused unless resuming a "
                             "thermalised --checkpoint; a resumed chain that has begun measuring keeps its own)")
    parser.add_argument("--seed", type=_seed, default=None,
                        help="seed of the Markov chain (default: drawn, and printed in the output)")
    parser.add_argument("--checkpoint", default=None, metavar="DIR",
                        help="save the chain in DIR (created) every minute, at the end and on Ctrl-C/SIGTERM; "
                             "the same command (more --sweeps allowed, --seed not needed) resumes it, "
                             "bit-identically")
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


def _adjacency(value):
    """The matrix of ``--adjacency FILE`` (.npz of scipy.sparse.save_npz or a dense .npy)."""
    import scipy.sparse as sp

    from .. import _validate

    path = _validate.input_path("--adjacency", value, suffixes=(".npz", ".npy"))
    try:
        if path.suffix == ".npz":
            mat = sp.load_npz(path)
        else:
            mat = np.load(path, allow_pickle=False)
    except Exception as exc:  # numpy's and zipfile's many ways of saying "not this kind of file"
        what = ("a sparse matrix written by scipy.sparse.save_npz" if path.suffix == ".npz"
                else "a dense array written by numpy.save")
        raise ValueError(f"--adjacency {str(path)!r} is not {what}: {_validate.file_problem(exc)}.") from None
    if not (sp.issparse(mat) or isinstance(mat, np.ndarray)) or mat.ndim != 2 or mat.shape[0] != mat.shape[1]:
        raise ValueError(f"--adjacency {str(path)!r} must hold a square matrix, got shape "
                         f"{getattr(mat, 'shape', None)}.")
    if mat.shape[0] == 0 or mat.shape[0] > MAX_ADJACENCY_SITES:
        raise ValueError(f"--adjacency {str(path)!r} must have 1 to {MAX_ADJACENCY_SITES:,} sites, got "
                         f"{mat.shape[0]:,}.")
    if mat.dtype.kind not in "biufc":
        raise ValueError(f"--adjacency {str(path)!r} must hold numbers, got {mat.dtype}.")
    return sp.csr_matrix(mat)


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


def _system(args: argparse.Namespace):
    from .. import _validate

    if args.adjacency is not None:
        return _adjacency(args.adjacency)
    p, q = _validate.pq(args.p, args.q) if args.cluster is None else cluster_pq(args, args.cluster)
    if args.rings is not None:
        from ..graph.lattice import ring_lattice

        return ring_lattice(p, q, args.rings)
    from ..graph.clusters import pbc_cluster

    return pbc_cluster(p, q, args.cluster)


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
    if args.json:
        summary = res.summary()
        out = {k: summary[k] for k in KEYS}
        out.update((k, v) for k, v in summary.items() if k not in out)
        print_json(out)
        return 0
    print(str(res))
    print(f"  seed {res.seed}, {res.bins} bins of {res.bin_size} sweeps, {res.seconds:.1f} s")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
