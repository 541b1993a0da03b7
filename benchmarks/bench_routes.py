"""The default routes against their strongest peers, same process, interleaved rounds (medians).

Measures, on the {7,3} flake (H = -A), each line with its peer and the ratio peer / ours:

(b) E0/E1 at ``--rings-big`` (default 14) by the *default* call, as a new user makes it:
    ``lowest_levels(ring_lattice(7, 3, 14), 2)`` (the lattice build counted) and the CLI
    ``hyperlattice spectrum --rings 14 --json`` (a subprocess: interpreter start-up and imports
    counted), against full-matrix CHOLMOD shift-invert ``eigsh(A, k=2, sigma=2.935)`` (the adjacency
    handed over ready-made: the build is *not* counted for the peer).
(c) the 10 lowest levels at the same size, ``lowest_levels(lattice, 10)``, against the same peer
    with k = 10.
(d) the default CLI run at ``--rings-cli`` (default 12), start-up included, against plain
    ``eigsh(A, k=2, which="LA")`` in this process (again without the build).
(e) ``method="auto"`` against every explicit method that finishes in reasonable time on these
    requests (``shift-invert``; the CLI's ``pair``; ``sector``, the Chebyshev-Lanczos per sector,
    with ``--slow``): auto / best explicit must stay below 1.2.

The backend that ran is printed. ``HYPERLATTICE_FACTOR_BACKEND=superlu`` hides CHOLMOD from the
package (the SuperLU-only configuration); the CHOLMOD peer still runs when scikit-sparse is
installed, so the printed ratio is then "SuperLU-only hyperlattice vs full-matrix CHOLMOD".

(b) and (c) run interleaved in one process, round by round (ours, the peer, the CLI), ``--repeat``
rounds (default 5), and print the median and the spread of the wall times, the median CPU times
(``time.process_time``; the CLI's from its rusage) and the ratio of the medians, both in wall and
in CPU time: on a machine shared with other jobs the CPU ratio is the steadier one. Each also prints
the **phase table** of both sides (``_phases.py``: graph build, block assembly, matrix copies,
ordering, factorisation, Lanczos bound, ARPACK, solves, post-processing; CPU s and wall s, medians
over the rounds) and the load average before and after. ``--rings-ten`` (default 12 and 14) are the
flakes of (c).

Usage: ``python benchmarks/bench_routes.py [--rings-big 14] [--rings-ten 12 14] [--rings-cli 12] [--repeat 5]
[--only b c d e] [--slow]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine, peak_rss_mb  # noqa: E402
from _phases import PHASES, PhaseClock  # noqa: E402

SIGMA = 2.935   # just above the top of the spectrum of A for rings >= 10 (NUMERICS-NOTES)


def best(fn, repeat: int):
    """(best wall time, last result) over ``repeat`` runs."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def cli(args: list[str], repeat: int) -> tuple[float, dict]:
    """Best wall time of ``python -m hyperlattice <args>`` in a fresh interpreter, and its JSON."""
    cmd = [sys.executable, "-m", "hyperlattice", *args]
    out = None

    def run():
        nonlocal out
        proc = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ))
        if proc.returncode:
            raise SystemExit(f"{' '.join(args)} failed: {proc.stderr.strip()}")
        out = json.loads(proc.stdout)
        return out

    t, _ = best(run, repeat)
    return t, out


def cholmod_shift_invert(a, k: int, clock: PhaseClock | None = None):
    """Full-matrix CHOLMOD shift-invert for the k largest eigenvalues of A (None without scikit-sparse).

    With ``clock``, the factorisation (CHOLMOD's ordering included) and the solves are timed as phases
    (ARPACK is timed by the clock's own wrapper of ``eigsh``)."""
    import contextlib

    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    try:
        from sksparse.cholmod import cholesky
    except ImportError:
        return None
    n = a.shape[0]

    def phase(name):
        return clock.phase(name) if clock is not None else contextlib.nullcontext()

    def run():
        with phase("factorisation"):
            factor = cholesky((SIGMA * sp.identity(n, format="csc") - a).tocsc())

        def solve(x):
            with phase("solves"):
                return -factor(x)
        op = spla.LinearOperator((n, n), matvec=solve, dtype=float)
        w, _ = spla.eigsh(a, k=k, sigma=SIGMA, which="LM", OPinv=op, tol=1e-12)
        return -w[::-1]
    return run


def load() -> str:
    """The load averages (1, 5, 15 min) as text."""
    return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg())


def cli_cpu(args: list[str]) -> tuple[float, float, dict]:
    """(wall s, CPU s, JSON) of one ``python -m hyperlattice <args>`` in a fresh interpreter."""
    import resource

    cmd = [sys.executable, "-m", "hyperlattice", *args]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ))
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode:
        raise SystemExit(f"{' '.join(args)} failed: {proc.stderr.strip()}")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, cpu, json.loads(proc.stdout)


def timed(clock: PhaseClock, fn):
    """(wall s, CPU s, phase row, result) of one call of ``fn`` with every phase timed."""
    clock.reset()
    c0, t0 = time.process_time(), time.perf_counter()
    with clock.total():
        out = fn()
    return time.perf_counter() - t0, time.process_time() - c0, clock.row(), out


def median(xs):
    import numpy as np

    return float(np.median(np.asarray(xs, dtype=float)))


def phase_table(rows: dict) -> str:
    """Median CPU s (wall s) per phase over the rounds, one column per side (``rows``: label -> list of rows)."""
    labels = list(rows)
    out = ["    | phase | " + " | ".join(f"{lab}: CPU s (wall s)" for lab in labels) + " |",
           "    |---|" + "---:|" * len(labels)]
    for k in PHASES:
        cells = [(median([r[k][0] for r in rows[lab]]), median([r[k][1] for r in rows[lab]])) for lab in labels]
        if all(c == 0.0 and w == 0.0 for c, w in cells):
            continue
        out.append(f"    | {k} | " + " | ".join(f"{c:.2f} ({w:.2f})" for c, w in cells) + " |")
    tot = [(median([sum(v[0] for v in r.values()) for r in rows[lab]]),
            median([sum(v[1] for v in r.values()) for r in rows[lab]])) for lab in labels]
    out.append("    | total | " + " | ".join(f"{c:.2f} ({w:.2f})" for c, w in tot) + " |")
    return "\n".join(out)


def interleaved_ratio(label: str, what: str, ours, peer, repeat: int, clock: PhaseClock, cli_args=None) -> list:
    """Round by round: ``ours()`` (phases timed), ``peer()`` (phases timed), the CLI ``cli_args``; medians,
    spreads, ratios and the phase tables printed. Returns summary rows (label, text, wall ratio, CPU ratio)."""
    from hyperlattice.graph.solvers import _single_threaded_blas

    ours_t, peer_t, cli_t = [], [], []
    ours_rows, peer_rows = [], []
    spec = e_peer = out = None
    print(f"  [{what}] {repeat} interleaved rounds, {load()}")
    for _ in range(repeat):
        w, c, row, spec = timed(clock, ours)
        ours_t.append((w, c))
        ours_rows.append(row)
        with _single_threaded_blas():
            w, c, row, e_peer = timed(clock, peer)
        peer_t.append((w, c))
        peer_rows.append(row)
        if cli_args is not None:
            w, c, out = cli_cpu(cli_args)
            cli_t.append((w, c))
    k = len(e_peer)
    diff = float(max(abs(a - b) for a, b in zip(e_peer, list(spec.energies)[:k])))
    sides = [("hyperlattice", ours_t), ("peer (full-matrix CHOLMOD shift-invert)", peer_t)]
    if cli_args is not None:
        sides.append((f"hyperlattice {' '.join(cli_args)} [subprocess]", cli_t))
    for name, ts in sides:
        walls = [w for w, _ in ts]
        print(f"    {name}: wall median {median(walls):.2f} s (min {min(walls):.2f}, max {max(walls):.2f}), "
              f"CPU median {median([c for _, c in ts]):.2f} s")
    print(f"    method {spec.method}, E0 = {spec.energies[0]:.13f}, max residual {spec.errors.max():.1e}, "
          f"max |dE| to the peer {diff:.1e}; {load()}")
    print(phase_table({"hyperlattice": ours_rows, "peer": peer_rows}))
    rows = []
    pw, pc = median([w for w, _ in peer_t]), median([c for _, c in peer_t])
    for name, ts in sides[:1] + sides[2:]:
        ow, oc = median([w for w, _ in ts]), median([c for _, c in ts])
        print(f"    ratio peer / {name}: wall {pw / ow:.2f}x, CPU {pc / oc:.2f}x")
        rows.append((label, f"{name} vs CHOLMOD shift-invert k={k} ({what})", pw / ow, pc / oc))
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings-big", type=int, default=14, help="flake of (b) and (e)")
    ap.add_argument("--rings-ten", type=int, nargs="+", default=[12, 14], help="flakes of (c)")
    ap.add_argument("--rings-cli", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=5, help="interleaved rounds of (b) and (c) (medians taken)")
    ap.add_argument("--peer-repeat", type=int, default=2, help="runs of the peer of (d) (best taken)")
    ap.add_argument("--only", nargs="*", default=["b", "c", "d", "e"])
    ap.add_argument("--slow", action="store_true", help="(e): also the Chebyshev-Lanczos 'sector' method")
    args = ap.parse_args(argv)

    import numpy as np  # noqa: F401
    import scipy.sparse.linalg as spla

    from hyperlattice.graph.factor import resolve_backend
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import adjacency
    from hyperlattice.graph.solvers import _single_threaded_blas
    from hyperlattice.graph.spectrum import lowest_levels

    print(f"machine: {machine()}")
    print(f"hyperlattice factorisation backend: {resolve_backend('auto')}"
          f"  ({os.environ.get('HYPERLATTICE_FACTOR_BACKEND', 'HYPERLATTICE_FACTOR_BACKEND unset')})")
    lowest_levels(ring_lattice(7, 3, 9), 2)          # numba kernels loaded outside every timing
    lowest_levels(ring_lattice(7, 3, 9), 10)
    big = args.rings_big
    rows = []
    clock = PhaseClock().install()

    def api(rings, k):
        def run():
            with clock.phase("build"):
                lat = ring_lattice(7, 3, rings)
            return lowest_levels(lat, k)
        return run

    for label, rings, k in ([("b", big, 2)] if "b" in args.only else []) + \
            [("c", r, 10) for r in (args.rings_ten if "c" in args.only else [])]:
        a = adjacency(ring_lattice(7, 3, rings)).tocsc()
        print(f"{{7,3}} rings = {rings}: N = {a.shape[0]:,}")
        peer = cholmod_shift_invert(a, k, clock)
        if peer is None:
            print("  (scikit-sparse not installed: no CHOLMOD peer)")
            continue
        cli_args = ["spectrum", "--rings", str(rings), "--levels", str(k), "--json"]
        rows += interleaved_ratio(label, f"lowest_levels(ring_lattice(7, 3, {rings}), {k}), build counted",
                                  api(rings, k), peer, args.repeat, clock, cli_args)
        del a
    clock.uninstall()

    if "e" in args.only:
        lat = ring_lattice(7, 3, big)
        for k in (2, 10):
            t_api, spec = best(lambda: lowest_levels(ring_lattice(7, 3, big), k), args.repeat)
            explicit = {"shift-invert": lambda: lowest_levels(ring_lattice(7, 3, big), k, method="shift-invert")}
            if args.slow:
                explicit["sector"] = lambda: lowest_levels(ring_lattice(7, 3, big), k, method="sector")
            times = {m: best(fn, args.repeat)[0] for m, fn in explicit.items()}
            print(f"  l = {big}, {k} levels: auto {t_api:7.2f} s, " + ", ".join(f"method={m}: {t:7.2f} s"
                                                                            for m, t in times.items()))
            best_m = min(times, key=times.get)
            rows.append(("e", f"auto / best explicit ({best_m}), l={big}, {k} levels", t_api / times[best_m], None))
            if k == 2:
                t_pair, _ = cli(["spectrum", "--rings", str(big), "--method", "pair", "--json"], args.repeat)
                t_cauto, _ = cli(["spectrum", "--rings", str(big), "--json"], args.repeat)
                print(f"  CLI --method pair {t_pair:7.2f} s, default {t_cauto:7.2f} s")
                rows.append(("e", f"CLI auto / --method pair, l={big}", t_cauto / t_pair, None))
        del lat

    if "d" in args.only:
        r = args.rings_cli
        t_cli, out = cli(["spectrum", "--rings", str(r), "--json"], args.repeat)
        lat = ring_lattice(7, 3, r)
        a = adjacency(lat).tocsc()
        with _single_threaded_blas():
            t_plain, (w, _) = best(lambda: spla.eigsh(a, k=2, which="LA", tol=1e-12), args.peer_repeat)
        diff = abs(-w.max() - out["energies"][0])
        print(f"{{7,3}} rings = {r}: hyperlattice spectrum --rings {r} --json [subprocess, start-up counted] "
              f"{t_cli:.2f} s (method {out['method']}); plain eigsh(A, k=2, 'LA') {t_plain:.2f} s; "
              f"|dE0| = {diff:.1e}; ratio {t_plain / t_cli:.2f}x")
        rows.append(("d", f"hyperlattice spectrum --rings {r} --json vs plain eigsh", t_plain / t_cli, None))

    print(f"process peak RSS {peak_rss_mb():.0f} MB; {load()}")
    print("summary (ratio = peer time / hyperlattice time, medians, wall and CPU; for (e) auto time / best "
          "explicit time; a [subprocess] line times a fresh interpreter, start-up and imports counted, against "
          "the peer in this process, its imports and the adjacency build not counted):")
    for label, what, ratio, cpu in rows:
        print(f"  ({label}) {what}: {ratio:.2f}" + (f" (CPU {cpu:.2f})" if cpu is not None else ""))


if __name__ == "__main__":
    main()
