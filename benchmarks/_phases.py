"""Phase breakdown of the sparse eigenvalue routes: CPU and wall time per phase, exclusive of nested phases.

Used by ``bench_routes.py`` and ``bench_spectrum.py``. ``PhaseClock.install()`` wraps the package's
and SciPy's functions of each phase (graph build, block assembly, ordering, factorisation, the
Lanczos bound, ARPACK, solves with the factor, the Rayleigh-quotient / residual post-processing,
matrix copies and format conversions); ``clock.phase(name)`` times a peer's own calls. The time of a
phase excludes the phases nested in it (ARPACK's time excludes the solves it asks for), so the
phases add up to the total. CPU time (``time.process_time``) is far less sensitive than wall time to
the load of other jobs on a shared machine; both are printed.
"""

from __future__ import annotations

import contextlib
import functools
import time

#: the phases in print order
PHASES = ("build", "blocks", "copies", "ordering", "factorisation", "bound", "arpack", "solves", "post", "other")


class PhaseClock:
    """Exclusive CPU and wall time per phase while installed (see the module docstring)."""

    def __init__(self):
        self.cpu = dict.fromkeys(PHASES, 0.0)
        self.wall = dict.fromkeys(PHASES, 0.0)
        self.calls = dict.fromkeys(PHASES, 0)
        self._stack = []
        self._undo = []

    # -- timing --
    def _enter(self, name):
        self._stack.append([name, time.process_time(), time.perf_counter(), 0.0, 0.0])

    def _exit(self):
        name, c0, w0, cc, cw = self._stack.pop()
        dc, dw = time.process_time() - c0, time.perf_counter() - w0
        self.cpu[name] += dc - cc
        self.wall[name] += dw - cw
        self.calls[name] += 1
        if self._stack:
            self._stack[-1][3] += dc
            self._stack[-1][4] += dw

    @contextlib.contextmanager
    def phase(self, name: str):
        """Time the block as phase ``name`` (exclusive of nested phases)."""
        self._enter(name)
        try:
            yield
        finally:
            self._exit()

    def reset(self):
        for d in (self.cpu, self.wall):
            for k in d:
                d[k] = 0.0
        for k in self.calls:
            self.calls[k] = 0

    # -- patching --
    def _wrap(self, owner, attr: str, name: str):
        orig = getattr(owner, attr)
        clock = self

        @functools.wraps(orig)
        def wrapper(*args, **kwargs):
            clock._enter(name)
            try:
                return orig(*args, **kwargs)
            finally:
                clock._exit()

        setattr(owner, attr, wrapper)
        self._undo.append((owner, attr, orig))

    def install(self):
        """Wrap the functions of every phase; ``uninstall()`` restores them."""
        import scipy.sparse.linalg as spla

        from hyperlattice.graph import factor as fct
        from hyperlattice.graph import sectors, solvers

        self._wrap(sectors, "sector_lattice", "build")
        self._wrap(sectors._BlockFactory, "block", "blocks")
        self._wrap(sectors._BlockFactory, "_pattern", "blocks")
        for attr in ("_with_diagonal", "_as_square"):
            if hasattr(fct, attr):
                self._wrap(fct, attr, "copies")
        self._wrap(fct.SymbolicAnalysis, "__init__", "ordering")
        self._wrap(fct.Factor, "__init__", "factorisation")
        self._wrap(sectors, "_lanczos_ritz", "bound")
        self._wrap(solvers, "_lanczos_ritz", "bound")
        self._wrap(spla, "eigsh", "arpack")
        self._wrap(fct.Factor, "solve", "solves")
        self._wrap(fct, "shift_invert_lowest", "post")
        return self

    def uninstall(self):
        while self._undo:
            owner, attr, orig = self._undo.pop()
            setattr(owner, attr, orig)

    @contextlib.contextmanager
    def total(self):
        """The whole call: time not in a named phase is ``other``."""
        with self.phase("other"):
            yield

    # -- output --
    def row(self) -> dict:
        return {k: (self.cpu[k], self.wall[k]) for k in PHASES}


def table(rows: dict, title: str) -> str:
    """Markdown table: one column per route (``rows``: label -> PhaseClock.row()), CPU s (wall s)."""
    labels = list(rows)
    out = [f"{title}", "| phase | " + " | ".join(labels) + " |", "|---|" + "---:|" * len(labels)]
    for k in PHASES:
        if all(rows[lab][k][0] == 0.0 and rows[lab][k][1] == 0.0 for lab in labels):
            continue
        out.append(f"| {k} | " + " | ".join(f"{rows[lab][k][0]:.2f} ({rows[lab][k][1]:.2f})" for lab in labels) + " |")
    out.append("| total | " + " | ".join(f"{sum(v[0] for v in rows[lab].values()):.2f} "
                                         f"({sum(v[1] for v in rows[lab].values()):.2f})" for lab in labels) + " |")
    return "\n".join(out)
