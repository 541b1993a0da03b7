"""``hyperlattice bosons <what>``: the Bose–Hubbard model (exact diagonalisation, mean field,
Gross–Pitaevskii, quantum Monte Carlo).

Each ``<what>`` lives in its own module ``hyperlattice.cli._bosons_<what>`` that defines ``NAME``,
``HELP``, ``ORDER``, ``add_arguments(parser)`` and ``run(args) -> int`` (the layout of the
top-level commands), so adding one touches no shared file.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil

NAME = "bosons"
ORDER = 90
HELP = "interacting bosons (Bose-Hubbard): exact diagonalisation, mean field, Gross-Pitaevskii, quantum Monte Carlo"


def _subcommands() -> list:
    from . import __path__ as cli_path

    mods = [importlib.import_module(f"{__package__}.{info.name}")
            for info in pkgutil.iter_modules(cli_path) if info.name.startswith("_bosons_")]
    return sorted(mods, key=lambda m: (getattr(m, "ORDER", 100), m.NAME))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="bosons_command", metavar="WHAT", parser_class=type(parser))
    sub.required = True
    for mod in _subcommands():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
        mod.add_arguments(p)
        p.set_defaults(_bosons_run=mod.run)


def run(args: argparse.Namespace) -> int:
    return int(args._bosons_run(args) or 0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
