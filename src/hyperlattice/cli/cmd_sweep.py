"""``hyperlattice sweep``: run a parameter grid of tasks on Dask (or serially) into a resumable table."""

from __future__ import annotations

import json
import sys

from .. import _validate
from ._common import Interrupted, finite_float, positive_int, print_json

NAME = "sweep"
ORDER = 45
HELP = ("run a grid of tasks (disorder realizations, levels over flux, rings and {p,q}, Bose–Hubbard QMC) on Dask "
        "into a resumable Parquet table")
DESCRIPTION = (
    "Run every point of a parameter grid for one task (disorder, levels, qmc, spins, spins_quantum, device, "
    "topology, conductance, probe) and stream one row per task "
    "into OUT/table.parquet (pandas.read_parquet reads it; the parameters and the package version are in its "
    "metadata). A rerun skips finished tasks. CONFIG is a JSON file {\"task\": ..., \"grid\": {name: [values]}, "
    "\"out\": DIR, \"scheduler\": ..., \"workers\": N, \"retries\": N}; flags override it. --grid NAME=V1,V2,... "
    "or NAME=START:STOP (integers, STOP excluded) may be repeated. By default a local Dask cluster with one "
    "worker per core is started; --scheduler ADDRESS uses a running one (e.g. from dask-jobqueue), "
    "--scheduler serial runs in this process. Exit 3 if some tasks failed (they are listed, and retried by the "
    "next run)."
)

EXIT_FAILED = 3
_JSON_NAMES = {list: "array", str: "string", int: "number", float: "number", bool: "boolean"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("config", nargs="?", default=None, metavar="CONFIG", help="JSON file with the sweep")
    parser.add_argument("--task", default=None, help="task name: disorder, levels, qmc, spins, spins_quantum, device, topology, "
                        "conductance or probe")
    parser.add_argument("--grid", action="append", default=[], metavar="NAME=VALUES",
                        help="a grid axis: NAME=1,2,3 or NAME=0:100 (repeatable)")
    parser.add_argument("--out", default=None, metavar="DIR", help="sweep directory (created; resumed if present)")
    parser.add_argument("--scheduler", default=None,
                        help="local, threads, serial, or the address of a running Dask scheduler (default: a local "
                             "cluster when the grid is worth its ~5 s start-up, else this process)")
    parser.add_argument("--workers", type=positive_int, default=None, help="workers of the local cluster")
    parser.add_argument("--retries", type=int, default=None, help="extra attempts of a failing task (default 2)")
    parser.add_argument("--timeout", type=finite_float, default=None, help="seconds before unfinished tasks fail")
    parser.add_argument("--progress", dest="progress", action="store_true", default=None,
                        help="progress bar (default: when stderr is a terminal)")
    parser.add_argument("--no-progress", dest="progress", action="store_false")
    parser.add_argument("--json", action="store_true", help="print the run's summary as one JSON object")


def _value(text: str):
    t = text.strip()
    low = t.lower()
    if low in ("true", "false"):
        return low == "true"
    if low in ("null", "none"):
        return None
    try:
        return int(t)
    except ValueError:
        pass
    try:
        v = float(t)
    except ValueError:
        return t
    _validate.real("a grid value", v)      # nan, inf and 1e400 are refused
    return v


def _axis(spec: str) -> tuple[str, list]:
    if "=" not in spec:
        raise ValueError(f"--grid takes NAME=VALUES, got {spec!r}.")
    name, _, values = spec.partition("=")
    name = name.strip()
    if not name or not values.strip():
        raise ValueError(f"--grid takes NAME=VALUES, got {spec!r}.")
    if ":" in values and "," not in values:
        lo, _, hi = values.partition(":")
        try:
            a, b = int(lo), int(hi)
        except ValueError:
            raise ValueError(f"--grid {name}=START:STOP takes integers, got {values!r}.") from None
        if b <= a:
            raise ValueError(f"--grid {name}={values}: STOP must exceed START.")
        from ..sweep.engine import check_grid_size

        check_grid_size(b - a)      # before the list is built: ten million points is refused, not allocated
        return name, list(range(a, b))
    return name, [_value(v) for v in values.split(",")]


class _DuplicateKey(ValueError):
    pass


def _no_duplicates(pairs: list) -> dict:
    """json's object hook: a key given twice in one object is refused (json keeps the last value,
    so ``"grid": {"x": [1], "x": [2]}`` silently dropped x = 1)."""
    out: dict = {}
    for k, v in pairs:
        if k in out:
            raise _DuplicateKey(k)
        out[k] = v
    return out


def _config(path) -> dict:
    p = _validate.input_path("CONFIG", path, suffixes=(".json",))
    try:
        data = json.loads(p.read_text(), object_pairs_hook=_no_duplicates)
    except _DuplicateKey as exc:
        raise ValueError(f"CONFIG {str(p)!r} gives the key {str(exc)!r} twice in one object; "
                         "give it once (with all its values).") from None
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"CONFIG {str(p)!r} is not valid JSON ({exc}).") from None
    except RecursionError:
        # json's decoder recurses once per level: a file nested 100,000 deep exhausts the stack
        raise ValueError(f"CONFIG {str(p)!r} is nested too deeply to be a sweep configuration.") from None
    except OSError as exc:
        raise ValueError(f"cannot read CONFIG {str(p)!r}: {exc.strerror or exc}.") from None
    if not isinstance(data, dict):
        raise ValueError(f"CONFIG {str(p)!r} must hold a JSON object.")
    unknown = set(data) - {"task", "grid", "out", "scheduler", "workers", "retries", "timeout"}
    if unknown:
        raise ValueError(f"CONFIG has unknown keys: {', '.join(sorted(unknown))}.")
    return data


def run(args: argparse.Namespace) -> int:
    """Run the sweep and print a summary; exit 3 when some tasks failed."""
    from ..sweep import run_sweep

    cfg = _config(args.config) if args.config is not None else {}
    task = args.task or cfg.get("task")
    if task is None:
        raise ValueError("give the task (--task NAME or \"task\" in CONFIG).")
    grid = cfg.get("grid")
    if grid is None:
        grid = {}
    if not isinstance(grid, dict):
        raise ValueError(f"the grid in CONFIG must be an object of NAME: [values], got a JSON "
                         f"{_JSON_NAMES.get(type(grid), type(grid).__name__)}.")
    grid = dict(grid)
    given: set[str] = set()
    for spec in args.grid:
        name, values = _axis(spec)
        if name in given:
            # the second --grid would silently replace the first one's values
            raise ValueError(f"--grid {name}=... is given twice; list all its values in one --grid "
                             f"{name}=V1,V2,... .")
        given.add(name)
        grid[name] = values         # a flag overrides the CONFIG's axis of that name
    out = args.out or cfg.get("out")
    if out is None:
        raise ValueError("give the sweep directory (--out DIR or \"out\" in CONFIG).")
    retries = args.retries if args.retries is not None else cfg.get("retries", 2)
    timeout = args.timeout if args.timeout is not None else cfg.get("timeout")
    progress = args.progress  # None: bars when stderr is a terminal (hyperlattice._progress)
    scheduler = args.scheduler if args.scheduler is not None else cfg.get("scheduler")
    try:
        rep = run_sweep(task, grid, out, scheduler=scheduler,
                        workers=args.workers or cfg.get("workers"), retries=retries, progress=progress,
                        timeout=timeout)
    except KeyboardInterrupt:
        # the engine writes the finished rows before the interrupt leaves it
        raise Interrupted(f"the finished tasks are kept in {out}; rerun the same command to resume") from None
    summary = rep.summary()
    if args.json:
        print_json(summary)
    else:
        print(f"sweep {rep.task}: {rep.total} tasks, {rep.skipped} already done, {rep.completed} computed, "
              f"{len(rep.failed)} failed on {rep.scheduler} in {rep.seconds:.1f} s")
        print(f"table: {rep.table}")
    if rep.failed:
        first = rep.failed[0]
        sys.stderr.write(f"hyperlattice sweep: {len(rep.failed)} task(s) failed (listed in {rep.path}/_failures.json; "
                         f"a rerun retries them); first: {first['key']}: {first['error']}\n")
        return EXIT_FAILED
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
