"""``hyperlattice spins <what>``: magnetism on the package's graphs (classical spins by Monte Carlo,
quantum spins where their module is installed).

Each ``<what>`` lives in its own module ``hyperlattice.cli._spins_<what>``, found by name, so adding
one touches no shared file. A module defines either ``NAME``, ``HELP``, ``add_arguments(parser)``
and ``run(args)`` (the layout of the top-level commands), or ``add_parser(subparsers)`` (which adds
its own subparser) and ``run(args)``.
"""

from __future__ import annotations

import argparse

NAME = "spins"
ORDER = 95
HELP = "magnetism: classical Ising, XY and Heisenberg models by Monte Carlo (and quantum spins)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from ._chain_args import subcommands

    subcommands(parser, "_spins_", "spins_command", "_spins_run")


def run(args: argparse.Namespace) -> int:
    return int(args._spins_run(args) or 0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
