"""``hyperlattice spins <what>``: magnetism on the package's graphs.

Each ``<what>`` lives in its own module ``hyperlattice.cli._spins_<what>`` with
``add_parser(subparsers)`` and ``run(args) -> int``.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil

NAME = "spins"
ORDER = 95
HELP = "magnetism: quantum spin-1/2 XXZ by SSE"


def _subcommands() -> list:
    from . import __path__ as cli_path

    mods = [importlib.import_module(f"{__package__}.{info.name}")
            for info in pkgutil.iter_modules(cli_path) if info.name.startswith("_spins_")]
    return sorted(mods, key=lambda m: (getattr(m, "ORDER", 100), m.NAME))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="spins_command", metavar="WHAT", parser_class=type(parser))
    sub.required = True
    for mod in _subcommands():
        mod.add_parser(sub)


def run(args: argparse.Namespace) -> int:
    return int(args._spins_run(args) or 0)


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
