"""Shared helpers for the subcommands: argument types, output paths, JSON output, progress and interruption."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from .. import _validate


def _shown(text: str) -> str:
    return repr(text) if len(text) <= 40 else repr(text[:37] + "...")


def integer(text: str, *, maximum: int = _validate.INT64_MAX, what: str = "an integer") -> int:
    """An integer that fits the API (argparse type, registered for every ``type=int`` flag).

    A 140-digit value used to pass argparse and end as an OverflowError inside the computation;
    here it is one sentence, and so is a number of more than 4300 digits (Python's int limit).
    """
    try:
        v = int(text.strip())
    except (ValueError, OverflowError):
        raise argparse.ArgumentTypeError(f"expected {what}, got {_shown(text)}") from None
    if abs(v) > maximum:
        raise argparse.ArgumentTypeError(f"expected {what} of magnitude at most {maximum:,}, got {_shown(text)}")
    return v


def pq_int(text: str) -> int:
    """p or q of a {p,q} tiling: an integer up to :data:`hyperlattice._validate.PQ_MAX` (argparse type)."""
    return integer(text, maximum=_validate.PQ_MAX)


def p_value(text: str) -> int | float:
    """A polygon size p: an integer, or 'inf' (only where a limit makes sense)."""
    t = text.strip().lower()
    if t in ("inf", "infinity", "oo"):
        return math.inf
    try:
        return integer(t, maximum=_validate.PQ_MAX)
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"p must be an integer or 'inf': {exc}") from None


def positive_int(text: str) -> int:
    """An integer >= 1 (argparse type)."""
    v = integer(text)
    if v < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {v}")
    return v


def tolerance(text: str) -> float:
    """A relative tolerance: a number with 0 < tol < 1 (argparse type)."""
    v = finite_float(text)
    if not 0 < v < 1:
        raise argparse.ArgumentTypeError(f"expected a tolerance between 0 and 1, got {text!r}")
    return v


def finite_float(text: str) -> float:
    """A finite real number (argparse type)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def complex_value(text: str) -> complex:
    """Parse a (possibly complex) number such as ``-2.95`` or ``-2.5+0.1j`` without eval."""
    t = text.strip().replace(" ", "").replace("i", "j")
    try:
        v = complex(t)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a real or complex number like -2.5+0.1j, got {text!r}") from None
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return v


def output_file(flag: str, value) -> Path:
    """``value`` as a file the command may write, checked before any work is done.

    Refuses directories, missing folders and read-only places with one sentence naming ``flag``.
    """
    return _validate.output_path(flag, value)


#: suffixes matplotlib writes without extra packages; a figure path must end in one of them
PLOT_SUFFIXES = (".png", ".pdf", ".svg", ".eps", ".ps", ".jpg", ".jpeg", ".tif", ".tiff", ".webp")


def plot_file(flag: str, value) -> Path:
    """A figure file: as :func:`output_file`, and its suffix names the format.

    matplotlib appends ``.png`` to a name without a known suffix (``--plot DIR`` wrote
    ``DIR.png``), so such a name is refused rather than silently changed.
    """
    path = _validate._as_path(flag, value)
    if path.is_dir():
        raise ValueError(f"{flag} {str(path)!r} is a directory; give a file name such as "
                         f"{str(path / 'figure.png')!r}.")
    if path.suffix.lower() not in PLOT_SUFFIXES:
        raise ValueError(f"{flag} {str(path)!r} must end in one of {', '.join(PLOT_SUFFIXES)} "
                         "(the suffix chooses the format).")
    return output_file(flag, path)


class DefaultInt(int):
    """An integer default of a flag: equal to the int, but distinguishable from one the user typed
    (``-p`` and ``-q`` yield to a named cluster's own p and q unless given)."""


def add_pq(parser: argparse.ArgumentParser, *, default_p: int = 7) -> None:
    parser.add_argument("-p", type=pq_int, default=DefaultInt(default_p), help=f"polygon size p (default {default_p}, "
                        "or the named cluster's)")
    parser.add_argument("-q", type=pq_int, default=DefaultInt(3), help="coordination number q (default 3, or the "
                        "named cluster's)")


def cluster_pq(args: argparse.Namespace, name: str) -> tuple[int, int]:
    """p and q for the cluster ``name``: the ones typed (``-p``/``-q``), else the named cluster's own
    (``--cluster bolza`` is {8,3} without ``-p 8``), else the defaults."""
    from ..graph.clusters import named_schlafli

    own = named_schlafli(name)
    p, q = args.p, args.q
    if own is not None:
        p = own[0] if isinstance(p, DefaultInt) else p
        q = own[1] if isinstance(q, DefaultInt) else q
    return _validate.pq(int(p), int(q))


def to_jsonable(obj) -> object:
    """The package's one JSON display encoder (:func:`hyperlattice.results.to_jsonable`: NaN is null,
    an infinity the string "inf"/"-inf")."""
    from ..results import to_jsonable as _encode

    return _encode(obj)


def print_json(obj) -> None:
    """Write ``obj`` as indented JSON (numpy values converted) to stdout."""
    json.dump(to_jsonable(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


class Interrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM stopped a run; the message says what was kept and how to resume.

    ``main`` prints it as ``hyperlattice CMD: interrupted: MESSAGE`` (one line, exit code 130).
    """


def progress_bar(total: int | None, desc: str, *, unit: str = "it"):
    """The command's own bar (``--progress`` / ``--no-progress`` decide, else whether stderr is a
    terminal): :func:`hyperlattice._progress.progress_bar` with the auto setting."""
    from .._progress import progress_bar as bar

    return bar(total, f"hyperlattice {desc}", unit=unit)


def add_checkpoint(parser: argparse.ArgumentParser, what: str) -> None:
    """The ``--checkpoint DIR`` flag of a multi-point command."""
    parser.add_argument("--checkpoint", default=None, metavar="DIR",
                        help=f"keep every finished {what} in DIR (created); a rerun of the same command "
                             "reads them back and computes only the missing ones")


def open_checkpoint(args):
    """The :class:`~hyperlattice.cache.Cache` of ``--checkpoint DIR`` (the directory checked and
    created), or None without the flag; the command passes it as ``checkpoint=`` and counts from it."""
    if args.checkpoint is None:
        return None
    from ..cache import Cache

    return Cache(_validate.directory("--checkpoint", args.checkpoint))


def interrupted(cache, total: int, what: str, where) -> Interrupted:
    """The one-line report of an interrupted multi-point run (raise it from the KeyboardInterrupt):
    the points ``cache`` (from :func:`open_checkpoint`) holds, or that nothing was kept."""
    if cache is None:
        return Interrupted(f"nothing kept of {total} {what} (--checkpoint DIR keeps the finished ones for a rerun)")
    return Interrupted(f"{cache.hits + cache.misses} of {total} {what} kept in {where}; "
                       "rerun the same command to resume")


# ----------------------------------------------------------------------------
# work estimates: refuse (or announce) long runs before they start
# ----------------------------------------------------------------------------

#: default of ``--max-seconds``: the CLI refuses a run estimated to take longer (raise the flag
#: or use the Python API for longer runs)
MAX_SECONDS = 600.0
#: runs estimated above this many seconds get one line on stderr saying so before they start
ANNOUNCE_SECONDS = 30.0
#: seconds per n^3 of a dense Hermitian eigensolver (LAPACK eigh/eigvalsh). Measured 0.17-0.22 ns
#: single-threaded for n = 800-1521 on the project's 2-core machine (2026-11-24), 3.8 s for a
#: complex 1521 block under load: 1 ns covers complex blocks, eigenvectors and a busy machine.
DENSE_SECONDS_PER_N3 = 1e-9


def add_max_seconds(parser: argparse.ArgumentParser) -> None:
    """The ``--max-seconds`` flag of commands whose work is estimated before it starts."""
    parser.add_argument("--max-seconds", type=finite_float, default=MAX_SECONDS, metavar="S",
                        help=f"refuse a run estimated to take longer than S seconds (default {MAX_SECONDS:g})")


def estimate_sites(p: int, q: int, rings: int, *, line_graph: bool = False) -> int:
    """Sites of the ``rings``-ring {p,q} flake (or of its line graph: its edges) from the ring-count
    recursion, before anything is built; ValueError with a sentence when even the count is too big."""
    from ..graph.lattice import edge_count, site_count

    p, q = _validate.pq(p, q)
    return int(edge_count(p, q, rings) if line_graph else site_count(p, q, rings))


def check_work(command: str, seconds: float, max_seconds, detail: str,
               smaller: str = "fewer rings, a smaller q or fewer values", *, upper: bool = False) -> None:
    """Refuse a run estimated above ``max_seconds`` (ValueError, one sentence, advising ``smaller``);
    announce one above :data:`ANNOUNCE_SECONDS` on stderr (one line) so that a long run is never silent.
    ``upper``: the estimate is an upper bound (the slowest case measured), and is called one."""
    limit = _validate.real("--max-seconds", max_seconds, minimum=0.0, open_min=True)
    about = "up to about" if upper else "about"
    if seconds > limit:
        raise ValueError(f"this run could take {about} {_duration(seconds)} ({detail}), more than --max-seconds "
                         f"{limit:g}; raise --max-seconds or choose {smaller}." if upper else
                         f"this run would take about {_duration(seconds)} ({detail}), more than --max-seconds "
                         f"{limit:g}; raise --max-seconds or choose {smaller}.")
    if seconds > ANNOUNCE_SECONDS:
        sys.stderr.write(f"hyperlattice {command}: note: {about} {_duration(seconds)} of work ({detail}).\n")


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.3g} days"
