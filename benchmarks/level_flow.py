"""A level request followed as data: how often it enters graph/sectors.py and graph/symmetry.py (issue 28, item 9).

:func:`trace_modules` runs a call under :func:`sys.setprofile` and counts, for every module of the
package, how often the running code *enters* it: a call whose callee lies in the module and whose
nearest calling frame of the package lies outside it (a maximal run of frames of one module on the
stack counts once). The ``_validate`` guard wrapper of every public function is transparent, and
frames without a caller (the profiler's view of numba-compiled kernels) are skipped. Each request
runs once untraced first (numba compilation, imports), then traced.

Prints a Markdown table: the request, the route that ran, and the entries into sectors.py and
symmetry.py. ``tests/test_level_flow.py`` uses the same tracer; docs/architecture.md quotes the table.

Usage: ``python benchmarks/level_flow.py``.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys

import hyperlattice

PACKAGE = os.path.dirname(hyperlattice.__file__) + os.sep
#: the guard wrapper of every public function (and the checks it runs): not a step of the flow
TRANSPARENT = {"hyperlattice._validate"}
SECTORS = "hyperlattice.graph.sectors"
SYMMETRY = "hyperlattice.graph.symmetry"


def _module(code) -> str | None:
    path = code.co_filename
    if not path.startswith(PACKAGE):
        return None
    name = "hyperlattice." + path[len(PACKAGE):].removesuffix(".py").replace(os.sep, ".")
    name = name.removesuffix(".__init__")
    return None if name in TRANSPARENT else name


def trace_modules(func, *args, **kwargs):
    """(result, entries, runs, arrows): calls into each module from outside it, the executing module over
    time, and the (caller, callee) module pairs of those calls.

    ``runs`` is the sequence of modules whose code runs, one entry per maximal run (calls and
    returns both move it), for reading the flow; ``entries`` counts only the calls.
    """
    entries: dict[str, int] = {}
    runs: list[str] = []
    arrows: set[tuple[str | None, str]] = set()

    def nearest(frame):
        while frame is not None:
            name = _module(frame.f_code)
            if name is not None:
                return name
            frame = frame.f_back
        return None

    def profile(frame, event, arg):
        if event not in ("call", "return"):
            return
        name = _module(frame.f_code)
        if name is None or frame.f_back is None:
            return
        if event == "call":
            caller = nearest(frame.f_back)
            if caller != name:
                entries[name] = entries.get(name, 0) + 1
                arrows.add((caller, name))
            now = name
        else:
            now = nearest(frame.f_back)
        if now is not None and (not runs or runs[-1] != now):
            runs.append(now)

    old = sys.getprofile()
    sys.setprofile(profile)
    try:
        out = func(*args, **kwargs)
    finally:
        sys.setprofile(old)
    return out, entries, runs, arrows


def requests():
    """(name, call) of the level requests the table follows."""
    import hyperlattice as hl
    from hyperlattice.cli import main
    from hyperlattice.compare.bosons import mott_gap_comparison

    def quiet_cli(argv):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            main(argv)
        return out.getvalue()

    return [
        ("lowest_levels, {8,3} flake, 8 rings, 10 levels", lambda: hl.lowest_levels(hl.ring_lattice(8, 3, 8), 10)),
        ("hyperlattice spectrum -p 8 --rings 8 --levels 10",
         lambda: quiet_cli(["spectrum", "-p", "8", "--rings", "8", "--levels", "10"])),
        ("lowest_levels, {7,3} flake, 4 rings, 6 levels", lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 4), 6)),
        ("the same with V = 0.25", lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 4), 6, onsite=0.25)),
        ("{7,3}, 3 rings, 4 levels, flux 0.1, eigenvectors",
         lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 3), 4, flux=0.1, eigenvectors=True)),
        ("mott_gap_comparison, {7,3}, 1 ring", lambda: mott_gap_comparison(hl.ring_lattice(7, 3, 1), [0.0, 0.05])),
    ]


def main() -> None:
    print("| request | route | enters sectors.py | enters symmetry.py |")
    print("|---|---|---|---|")
    for name, call in requests():
        call()
        out, entries, _, _ = trace_modules(call)
        if isinstance(out, str):   # the command line prints its route as method=...
            route = out.split("method=", 1)[1].split()[0]
        else:
            route = getattr(out, "method", None) or "exact diagonalisation (lowest_levels for lambda_max)"
        print(f"| {name} | {route} | {entries.get(SECTORS, 0)} | {entries.get(SYMMETRY, 0)} |")


if __name__ == "__main__":
    main()
