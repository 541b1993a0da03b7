"""Command-line interface: ``hyperlattice <command> ...``.

Each subcommand lives in its own module ``hyperlattice.cli.cmd_<name>`` that defines

* ``NAME`` (the subcommand), ``HELP`` (one line), ``ORDER`` (position in ``--help``),
* ``add_arguments(parser)`` and ``run(args) -> int``.

Modules are discovered automatically, so adding a command touches no shared file.
Errors raised as :class:`ValueError` (bad input) or :class:`hyperlattice.errors.HyperlatticeError`
become a one-line message on stderr and exit code 2; there is never a traceback for bad input.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
import warnings

from .. import __version__
from ..errors import HyperlatticeError

EXIT_USAGE = 2


class _OneLineParser(argparse.ArgumentParser):
    """argparse prints usage plus an error; our contract is one line and exit 2."""

    def error(self, message):  # noqa: D102 - argparse API
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        raise SystemExit(EXIT_USAGE)


def _commands():
    mods = []
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("cmd_"):
            mods.append(importlib.import_module(f"{__name__}.{info.name}"))
    mods.sort(key=lambda m: (getattr(m, "ORDER", 100), m.NAME))
    return mods


def build_parser() -> argparse.ArgumentParser:
    parser = _OneLineParser(
        prog="hyperlattice",
        description="Quantum physics on hyperbolic {p,q} lattices and their continuum limit "
        "(Boettcher et al., PRA 102, 032208).",
    )
    parser.add_argument("--version", action="version", version=f"hyperlattice {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_OneLineParser)
    sub.required = True
    for mod in _commands():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("default")
            return int(args._run(args) or 0)
    except (ValueError, HyperlatticeError) as exc:
        msg = " ".join(str(exc).split()) or exc.__class__.__name__
        sys.stderr.write(f"hyperlattice {args.command}: error: {msg}\n")
        return EXIT_USAGE
    except MemoryError:
        sys.stderr.write(f"hyperlattice {args.command}: error: out of memory for this size.\n")
        return EXIT_USAGE
    except KeyboardInterrupt:
        sys.stderr.write("hyperlattice: interrupted\n")
        return 130
    except BrokenPipeError:
        # output piped into e.g. `head`, which closed early: not an error of ours
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
