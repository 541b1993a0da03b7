"""What the Monte Carlo subcommands share (``bosons qmc``, ``spins classical``, ``spins quantum``):
the argument types of a chain (seed, sweeps, inverse temperature), the graph flags (a flake, a
periodic cluster or an adjacency file) and the graph they name, the contract-first JSON and the
text output, and the discovery of a command group's subcommand modules."""

from __future__ import annotations

import argparse
import importlib
import pkgutil

import numpy as np

from ._common import add_pq, cluster_pq, finite_float, integer, positive_int, print_json

#: largest number of sites of an --adjacency file (the same bound as a flake's)
MAX_ADJACENCY_SITES = 10_000_000


def subcommands(parser: argparse.ArgumentParser, prefix: str, dest: str, run_key: str) -> None:
    """Add the subcommands of a command group to ``parser``: the modules ``hyperlattice.cli.<prefix>*``
    in the order of their ``ORDER`` (then ``NAME``), each defining either ``NAME``, ``HELP``,
    ``add_arguments(parser)`` and ``run(args)`` or ``add_parser(subparsers)`` and ``run(args)``;
    the chosen module's ``run`` is stored under ``run_key``."""
    from . import __path__ as cli_path

    mods = [importlib.import_module(f"{__package__}.{info.name}")
            for info in pkgutil.iter_modules(cli_path) if info.name.startswith(prefix)]
    sub = parser.add_subparsers(dest=dest, metavar="WHAT", parser_class=type(parser))
    sub.required = True
    for mod in sorted(mods, key=lambda m: (getattr(m, "ORDER", 100), getattr(m, "NAME", m.__name__))):
        if hasattr(mod, "add_arguments"):
            p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
            mod.add_arguments(p)
        else:
            before = set(sub.choices)
            p = mod.add_parser(sub)
            if not isinstance(p, argparse.ArgumentParser):
                new = [name for name in sub.choices if name not in before]
                p = sub.choices[new[0]]
        p.set_defaults(**{run_key: mod.run})


def seed(text: str) -> int:
    """A seed, an integer >= 0 (argparse type)."""
    v = integer(text, what="a seed (an integer >= 0)")
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a seed >= 0, got {v}")
    return v


def sweeps(text: str) -> int:
    """A number of sweeps >= 0 (argparse type)."""
    v = integer(text, what="a number of sweeps")
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a number of sweeps >= 0, got {v}")
    return v


def beta(text: str) -> float:
    """An inverse temperature > 0 (argparse type)."""
    v = finite_float(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected an inverse temperature > 0, got {text!r}")
    return v


def add_graph(parser: argparse.ArgumentParser, cluster_help: str, adjacency_help: str) -> None:
    """The required choice --rings / --cluster / --adjacency, then -p/-q."""
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a flake of this many rings (1 = one p-gon)")
    where.add_argument("--cluster", metavar="NAME", help=cluster_help)
    where.add_argument("--adjacency", metavar="FILE", help=adjacency_help)
    add_pq(parser)


def add_chain(parser: argparse.ArgumentParser, *, sweeps_default: int, thermalization: str, saved: str,
              resume: str) -> None:
    """--sweeps, --thermalization, --seed and --checkpoint of a chain: ``thermalization`` the default's
    text, ``saved`` when the chain is written besides every minute, ``resume`` what a rerun may change."""
    parser.add_argument("--sweeps", type=positive_int, default=sweeps_default,
                        help=f"measurement sweeps (default {sweeps_default})")
    parser.add_argument("--thermalization", type=sweeps, default=None, metavar="N",
                        help=f"thermalisation sweeps (default {thermalization})")
    parser.add_argument("--seed", type=seed, default=None,
                        help="seed of the Markov chain (default: drawn, and printed in the output)")
    parser.add_argument("--checkpoint", default=None, metavar="DIR",
                        help=f"save the chain in DIR (created) every minute{saved}; the same command ({resume}) "
                             "resumes it, bit-identically")


def adjacency(value):
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


def graph(args: argparse.Namespace, line: bool = False):
    """The graph the flags name: the matrix of --adjacency, the flake of --rings (its line graph when
    ``line``, the ``--line-graph`` flag) or the periodic cluster of --cluster."""
    from .. import _validate

    if args.adjacency is not None:
        return adjacency(args.adjacency)
    if line and args.rings is None:
        raise ValueError("--line-graph needs a flake (--rings).")
    p, q = _validate.pq(args.p, args.q) if args.cluster is None else cluster_pq(args, args.cluster)
    if args.rings is not None:
        from ..graph.lattice import line_graph, ring_lattice

        lat = ring_lattice(p, q, args.rings)
        return line_graph(lat) if line else lat
    from ..graph.clusters import pbc_cluster

    return pbc_cluster(p, q, args.cluster)


def show(res, keys: tuple, as_json: bool, before: tuple = (), after: tuple = ()) -> int:
    """Print a chain's result: JSON with the contract's ``keys`` first; or its text, the lines
    ``before``, the seed and bins, the lines ``after``. Returns 0 (the exit code)."""
    if as_json:
        summary = res.summary()
        out = {k: summary[k] for k in keys}
        out.update((k, v) for k, v in summary.items() if k not in out)
        print_json(out)
        return 0
    print(str(res))
    for line in before:
        print(line)
    print(f"  seed {res.seed}, {res.bins} bins of {res.bin_size} sweeps, {res.seconds:.1f} s")
    for line in after:
        print(line)
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
