"""Sweep engine throughput: 200 disorder realizations at l = 6 on 1 and 2 local Dask workers, and the
engine's overhead per task against a plain Python loop.

Issue 15 asks for the throughput of a sweep of 200 disorder realizations of the l = 6 {7,3} flake
(2,240 sites; one realization = one dense eigvalsh of the full matrix, about 1.3 s on one core) with
1 and 2 local workers in the same run (the ratio should approach 2 on 2 cores), and the engine's
overhead per task against a plain loop. Everything runs in this process, one after the other:

1. the plain loop: ``execute("disorder", params)`` for ``--loop`` realizations (the peer: no engine);
2. the same grid of ``--realizations`` tasks through :func:`hyperlattice.sweep.run_sweep` on a local
   cluster of 1 and then 2 worker processes (cluster start-up timed separately and excluded from the
   throughput, since a long sweep pays it once);
3. the overhead: ``--probes`` no-op tasks (``probe``, x -> x^2) through the serial engine and the
   2-worker cluster, against a plain loop of the same function; (engine - loop) / tasks.

The machine is shared: the load average before and after is printed, and the ratio is only as good
as the second core is free.

Usage: ``python benchmarks/bench_sweep.py [--rings 6] [--realizations 200] [--loop 10] [--probes 400]
[--order 1 2]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine  # noqa: E402

from hyperlattice.sweep import run_sweep  # noqa: E402
from hyperlattice.sweep.tasks import TASKS, _probe, execute  # noqa: E402


def _cluster_sweep(grid: dict, task: str, workers: int, root: Path, run: int = 0) -> tuple[float, float, int]:
    """(start-up s, sweep s, rows) on a fresh local cluster of ``workers`` processes."""
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        # warm the workers (imports, numba) so the sweep time is the work, as in a long sweep
        client.run(lambda: __import__("hyperlattice.compare.disorder"))
        start = time.perf_counter() - t0
        t1 = time.perf_counter()
        # a fresh directory per run: the same grid in the same directory would be skipped (resumed)
        rep = run_sweep(task, grid, root / f"{task}-{workers}-{run}", scheduler=client, progress=False)
        sweep = time.perf_counter() - t1
    assert rep.ok, rep.failed
    return start, sweep, rep.completed


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, default=6)
    ap.add_argument("--W", type=float, default=1.0)
    ap.add_argument("--realizations", type=int, default=200)
    ap.add_argument("--loop", type=int, default=10, help="realizations of the plain loop (time per task)")
    ap.add_argument("--probes", type=int, default=400, help="no-op tasks for the overhead")
    ap.add_argument("--order", type=int, nargs="+", default=[1, 2],
                    help="worker counts in the order run (e.g. 2 1 2 1 to average out a changing load)")
    args = ap.parse_args(argv)

    print(f"machine: {machine()}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    params = dict(TASKS["disorder"].defaults)
    params.update(rings=args.rings, W=args.W)
    execute("disorder", {**params, "realization": 10**6})        # warm-up: lattice cache, imports
    t0 = time.perf_counter()
    for k in range(args.loop):
        execute("disorder", {**params, "realization": k})
    per_task = (time.perf_counter() - t0) / args.loop
    print(f"plain loop: {per_task:.3f} s per realization (l = {args.rings}, W = {args.W}, {args.loop} realizations, "
          f"1 BLAS thread)")

    grid = {"rings": [args.rings], "W": [args.W], "realization": list(range(args.realizations))}
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        rates: dict = {}
        for run, workers in enumerate(args.order):
            start, sweep, rows = _cluster_sweep(grid, "disorder", workers, root, run)
            rates.setdefault(workers, []).append(rows / sweep)
            print(f"{workers} worker(s): {rows} realizations in {sweep:.1f} s = {rows / sweep:.3f} per s "
                  f"({sweep / rows:.3f} s per realization; cluster start-up {start:.1f} s; "
                  f"1-min load average at the end {os.getloadavg()[0]:.2f})")
        rate = {w: sum(r) / len(r) for w, r in rates.items()}
        if 1 in rate and 2 in rate:
            print(f"speed-up 2 workers / 1 worker: {rate[2] / rate[1]:.2f} (ideal 2)")
        if 1 in rate:
            print(f"1 worker against the plain loop: {(1 / rate[1]) / per_task:.3f} x the time per realization")

        # the engine's own cost per task
        n = args.probes
        t0 = time.perf_counter()
        for i in range(n):
            _probe(float(i))
        loop = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_sweep("probe", {"x": [float(i) for i in range(n)]}, root / "probe-serial", scheduler="serial",
                  progress=False)
        serial = time.perf_counter() - t0
        _, dask2, _ = _cluster_sweep({"x": [float(i) for i in range(n)]}, "probe", 2, root)
        print(f"overhead per task ({n} no-op tasks): serial engine {1e3 * (serial - loop) / n:.2f} ms, "
              f"2-worker Dask {1e3 * (dask2 - loop) / n:.2f} ms (plain loop {1e6 * loop / n:.2f} us per call); "
              f"relative to one l = {args.rings} realization: {100 * (dask2 - loop) / n / per_task:.2f} %")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
