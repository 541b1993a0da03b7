"""``hyperlattice reproduce``: regenerate every table and figure of the paper into one report."""

from __future__ import annotations

from ..cache import Cache
from ._common import progress_bar

NAME = "reproduce"
ORDER = 5
HELP = "recompute every table and figure of the paper (report.html/.md, CSV/JSON, PNG/SVG)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", default="reproduction", metavar="DIR", help="output directory (default reproduction/)")
    parser.add_argument("--max-rings", type=int, default=10,
                        help="largest l in the spectrum tables, 2..14 (default 10, the paper's range)")
    parser.add_argument("--cache-dir", metavar="DIR", help="cache directory (default $HYPERLATTICE_CACHE or ~/.cache/hyperlattice)")
    parser.add_argument("--no-cache", action="store_true", help="recompute everything, store nothing")
    parser.add_argument("--clear-cache", action="store_true", help="delete the cache entries hyperlattice wrote before running (other files stay)")


def run(args: argparse.Namespace) -> int:
    from ..report import _out_directory, reproduce

    if not 2 <= args.max_rings <= 14:
        raise ValueError(f"--max-rings must be between 2 and 14, got {args.max_rings}.")
    # every path is checked before the first computation, so a run never fails at its end
    # new, empty or an earlier report's: a directory of the user's is refused, never written into
    _out_directory("--out", args.out)
    cache = Cache(args.cache_dir, enabled=not args.no_cache)
    if args.clear_cache:
        cache.clear()       # only the package's own entries: the directory may hold the user's files
    with progress_bar(None, "reproduce", unit="stage") as bar:
        started = [False]

        def stage(message: str) -> None:
            # the report announces each stage as it starts: the one before it has finished
            if started[0]:
                bar.update()
            started[0] = True
            bar.note(message)

        summary = reproduce(args.out, args.max_rings, cache=cache, progress=stage)
        bar.update()
    print(f"wrote {summary['out_dir']}/report.html and report.md ({len(summary['sections'])} sections) in "
          f"{summary['seconds']:.1f} s (cache: {summary['cache_hits']} read from earlier runs, "
          f"{summary['cache_misses']} computed, {summary['cache_reused']} reused within this run)")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
