"""Command-line interface: ``hyperlattice <command> ...``.

Each subcommand lives in its own module ``hyperlattice.cli.cmd_<name>`` that defines

* ``NAME`` (the subcommand), ``HELP`` (one line), ``ORDER`` (position in ``--help``),
* ``add_arguments(parser)`` and ``run(args) -> int``.

Modules are discovered automatically, so adding a command touches no shared file.
Errors raised as :class:`ValueError` (bad input), :class:`hyperlattice.errors.HyperlatticeError`,
:class:`MemoryError` or :class:`OSError` (a file that cannot be written) become a one-line message
on stderr and exit code 2. Warnings are printed as one line each. Ctrl-C (SIGINT) and SIGTERM stop a
run with one line (what was kept, for commands that checkpoint) and exit code 130 (143 for SIGTERM).
Every command takes ``--progress`` / ``--no-progress``: bars on stderr, by default only when stderr
is a terminal (:mod:`hyperlattice._progress`). Anything else is a bug of
hyperlattice: one line asking for a report and exit code 1 (``HYPERLATTICE_TRACEBACK=1`` shows
the traceback instead). There is never a traceback for bad input.
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import signal
import sys
import threading
import warnings

from .. import __version__
from ..errors import HyperlatticeError
from ._common import Interrupted

EXIT_USAGE = 2
EXIT_BUG = 1
EXIT_INTERRUPT = 130
EXIT_TERMINATED = 143


class _NegativeNumber:
    """argparse's test of whether a word after a flag is a (negative) number rather than a flag.

    Its own pattern knows only ``-1`` and ``-0.5``: ``--U -1e-3``, ``--omega -2.5+0.1j`` and
    ``--mu -inf`` were read as unknown flags ("expected one argument"). Here any word that starts
    with ``-`` and parses as a real or complex number, or a comma-separated list of them, is one
    (then checked by the flag's type).
    """

    @staticmethod
    def match(text: str) -> bool:
        if not text.startswith("-") or text.startswith("--") or len(text) < 2:
            return False
        word = text.strip().replace(" ", "")
        # a comma-separated list of numbers (--energies -0.5,0,0.5) is a value too
        return all(_NegativeNumber._number(part) for part in word.split(","))

    @staticmethod
    def _number(word: str) -> bool:
        for candidate in (word, word.replace("i", "j")):     # -inf, and -1.5i for -1.5j
            try:
                complex(candidate)
            except ValueError:
                continue
            return True
        return False


class _OneLineParser(argparse.ArgumentParser):
    """argparse prints usage plus an error; our contract is one line and exit 2."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        from ._common import integer

        self._negative_number_matcher = _NegativeNumber()   # --U -1e-3, --omega -2.5+0.1j

        # every ``type=int`` flag of every command: bounded to what the API takes, one sentence
        self.register("type", int, integer)

    def error(self, message) -> None:  # noqa: D102 - argparse API
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        raise SystemExit(EXIT_USAGE)


def _commands(only: str | None = None) -> list:
    """The command modules; with ``only``, just the module of that command when it exists (start-up:
    importing every command costs ~0.5 s of imports a single run does not need)."""
    names = [info.name for info in pkgutil.iter_modules(__path__) if info.name.startswith("cmd_")]
    if only is not None and f"cmd_{only}" in names:
        mod = importlib.import_module(f"{__name__}.cmd_{only}")
        if getattr(mod, "NAME", None) == only:
            return [mod]
    mods = [importlib.import_module(f"{__name__}.{name}") for name in names]
    mods.sort(key=lambda m: (getattr(m, "ORDER", 100), m.NAME))
    return mods


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command, or (``only``) of that one command alone (same parser for it)."""
    parser = _OneLineParser(
        prog="hyperlattice",
        description="Quantum physics on hyperbolic {p,q} lattices and their continuum limit "
        "(Boettcher et al., PRA 102, 032208).",
    )
    parser.add_argument("--version", action="version", version=f"hyperlattice {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_OneLineParser)
    sub.required = True
    for mod in _commands(only):
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP))
        mod.add_arguments(p)
        _add_progress(p, None)
        p.set_defaults(_run=mod.run)
    return parser


def _add_progress(parser: argparse.ArgumentParser, default) -> None:
    """``--progress`` / ``--no-progress`` on a command and on its own subcommands (``bosons ed``), so
    the flags work after any word; a subcommand leaves the value alone unless the flag is given there."""
    if "--no-progress" not in parser._option_string_actions:
        parser.add_argument("--progress", dest="progress", action="store_true", default=default,
                            help="progress bars on stderr (default: only when stderr is a terminal)")
        parser.add_argument("--no-progress", dest="progress", action="store_false", default=default,
                            help="no progress bars")
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                _add_progress(sub, argparse.SUPPRESS)


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``hyperlattice ...`` (``argv`` without the program name); return the exit code."""
    if argv is not None and (not isinstance(argv, (list, tuple)) or not all(isinstance(w, str) for w in argv)):
        raise ValueError("argv must be a list of strings (the command line words).")
    words = list(sys.argv[1:] if argv is None else argv)
    # a command named first: build its parser alone (the others' imports are not paid for)
    only = words[0] if words and not words[0].startswith("-") and words[0].isidentifier() else None
    parser = build_parser(only)
    args = parser.parse_args(words)
    prefix = f"hyperlattice {args.command}"

    def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
        # one line per warning, like the errors; the source line of the warn() call means nothing here
        sys.stderr.write(f"{prefix}: warning: {_one_line(message)} ({category.__name__})\n")

    from .._progress import default as progress_default

    terminated = []

    def on_sigterm(signum, frame) -> None:
        # SIGTERM ends a run like Ctrl-C: finished points stay on disk, one line, no traceback
        terminated.append(signum)
        raise KeyboardInterrupt

    installed, old_term = False, None
    if threading.current_thread() is threading.main_thread():
        old_term, installed = signal.signal(signal.SIGTERM, on_sigterm), True
    try:
        from .._validate import factor_backend_env

        factor_backend_env()        # a misspelt HYPERLATTICE_FACTOR_BACKEND: one line, before any work
        with warnings.catch_warnings(), progress_default(getattr(args, "progress", None)):
            warnings.simplefilter("default")
            warnings.showwarning = show_warning
            return int(args._run(args) or 0)
    except (ValueError, HyperlatticeError) as exc:
        msg = _one_line(exc) or exc.__class__.__name__
        sys.stderr.write(f"{prefix}: error: {msg}\n")
        return EXIT_USAGE
    except MemoryError as exc:
        # a refusal of the package says what it needs and what is available (numpy's says the size)
        sys.stderr.write(f"{prefix}: error: {_one_line(exc) or 'out of memory for this size.'}\n")
        return EXIT_USAGE
    except BrokenPipeError:
        # output piped into e.g. `head`, which closed early: not an error of ours
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OSError as exc:
        # a file failed after the up-front checks (disk full, folder removed meanwhile, ...)
        where = f"{exc.filename!s}: " if getattr(exc, "filename", None) else ""
        sys.stderr.write(f"{prefix}: error: {where}{_one_line(exc.strerror or exc)}.\n")
        return EXIT_USAGE
    except KeyboardInterrupt as exc:
        # a command that keeps finished work says where (cli._common.Interrupted), in the same line
        detail = _one_line(exc) if isinstance(exc, Interrupted) else ""
        sys.stderr.write(f"{prefix}: interrupted{': ' + detail if detail else ''}\n")
        return EXIT_TERMINATED if terminated else EXIT_INTERRUPT
    except Exception as exc:  # a bug of ours: say so in one line, keep the traceback on request
        if os.environ.get("HYPERLATTICE_TRACEBACK"):
            raise
        sys.stderr.write(f"{prefix}: internal error ({type(exc).__name__}: {_one_line(exc)[:200]}); "
                         "please report it (HYPERLATTICE_TRACEBACK=1 shows the traceback).\n")
        return EXIT_BUG
    finally:
        if installed:
            signal.signal(signal.SIGTERM, signal.SIG_DFL if old_term is None else old_term)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
