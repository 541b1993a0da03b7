"""``hyperlattice spins <what>``: magnetism on the package's graphs (classical spins by Monte Carlo,
quantum spins where their module is installed).

Each ``<what>`` lives in its own module ``hyperlattice.cli._spins_<what>``, found by name, so adding
one touches no shared file. A module defines either ``NAME``, ``HELP``, ``add_arguments(parser)``
and ``run(args)`` (the layout of the top-level commands), or ``add_parser(subparsers)`` (which adds
its own subparser) and ``run(args)``.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil

NAME = "spins"
ORDER = 95
HELP = "magnetism: classical Ising, XY and Heisenberg models by Monte Carlo (and quantum spins)"


def _subcommands() -> list:
    from . import __path__ as cli_path

    mods = [importlib.import_module(f"{__package__}.{info.name}")
            for info in pkgutil.iter_modules(cli_path) if info.name.startswith("_spins_")]
    return sorted(mods, key=lambda m: (getattr(m, "ORDER", 100), getattr(m, "NAME", m.__name__)))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="spins_command", metavar="WHAT", parser_class=type(parser))
    sub.required = True
    for mod in _subcommands():
        if hasattr(mod, "add_arguments"):
            p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
            mod.add_arguments(p)
        else:
            before = set(sub.choices)
            p = mod.add_parser(sub)
            if not isinstance(p, argparse.ArgumentParser):
                new = [name for name in sub.choices if name not in before]
                p = sub.choices[new[0]]
        p.set_defaults(_spins_run=mod.run)


def run(args: argparse.Namespace) -> int:
    return int(args._spins_run(args) or 0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
