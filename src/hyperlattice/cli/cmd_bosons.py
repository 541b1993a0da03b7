"""``hyperlattice bosons <what>``: the Bose–Hubbard model (exact diagonalisation, mean field,
Gross–Pitaevskii, quantum Monte Carlo).

Each ``<what>`` lives in its own module ``hyperlattice.cli._bosons_<what>`` that defines ``NAME``,
``HELP``, ``ORDER``, ``add_arguments(parser)`` and ``run(args) -> int`` (the layout of the
top-level commands), so adding one touches no shared file.
"""

from __future__ import annotations

import argparse

NAME = "bosons"
ORDER = 90
HELP = "interacting bosons (Bose-Hubbard): exact diagonalisation, mean field, Gross-Pitaevskii, quantum Monte Carlo"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from ._chain_args import subcommands

    subcommands(parser, "_bosons_", "bosons_command", "_bosons_run")


def run(args: argparse.Namespace) -> int:
    return int(args._bosons_run(args) or 0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
