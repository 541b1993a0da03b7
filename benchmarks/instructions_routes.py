"""Instruction counts (and simulated last-level-cache misses) of the default sector route and its peer.

Wall-clock ratios on a shared machine move with the load; the number of instructions a run executes
does not. This script runs one side at a time under valgrind's callgrind, with the count switched
on only around the measured call (a tiny C helper with callgrind's client requests, compiled here
with ``cc``; needs ``valgrind`` and its headers), and prints the totals:

* ``ours``: ``lowest_sector_levels(7, 3, rings, k)`` (what ``hyperlattice spectrum --rings R`` and
  ``lowest_levels`` of a plain flake run; the sector lattice build counted, imports not);
* ``peer``: full-matrix CHOLMOD shift-invert ``eigsh(A, k, sigma=2.935)`` as in ``bench_routes.py``
  (the adjacency handed over ready-made).

``--cache LLBYTES`` adds callgrind's cache simulation with a last-level cache of that size (e.g.
33554432 for 32 MB, 4194304 for 4 MB): the LL misses stand for the traffic to main memory, the
part of a run that a machine with less memory bandwidth pays for. BLAS and numba run one thread.

Usage: ``python benchmarks/instructions_routes.py [--rings 11] [--levels 2] [--cache 33554432]
[--sides ours peer]``. A run at 11 rings takes a few minutes (valgrind is 50-100x slower).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HELPER = r"""
#include <valgrind/callgrind.h>
void cg_start(void) { CALLGRIND_ZERO_STATS; CALLGRIND_START_INSTRUMENTATION; }
void cg_stop(void) { CALLGRIND_STOP_INSTRUMENTATION; CALLGRIND_DUMP_STATS_AT("work"); }
"""

CHILD = r"""
import ctypes, sys
import scipy.sparse as sp, scipy.sparse.linalg as spla
from hyperlattice.graph.sectors import lowest_sector_levels
cg = ctypes.CDLL(sys.argv[1])
side, rings, k = sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
lowest_sector_levels(7, 3, 4, k)                       # kernels loaded outside the count
if side == "peer":
    from sksparse.cholmod import cholesky
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import adjacency
    a = adjacency(ring_lattice(7, 3, rings)).tocsc()
    n = a.shape[0]
cg.cg_start()
if side == "ours":
    lowest_sector_levels(7, 3, rings, k)
else:
    factor = cholesky((2.935 * sp.identity(n, format="csc") - a).tocsc())
    op = spla.LinearOperator((n, n), matvec=lambda x: -factor(x), dtype=float)
    spla.eigsh(a, k=k, sigma=2.935, which="LM", OPinv=op, tol=1e-12)
cg.cg_stop()
"""


def run_side(side: str, rings: int, k: int, cache: int | None, tmp: Path, lib: Path) -> dict:
    out = tmp / f"cg.{side}"
    child = tmp / "child.py"
    child.write_text(CHILD)
    cmd = ["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out}"]
    if cache:
        cmd += ["--cache-sim=yes", f"--LL={cache},16,64"]
    env = dict(os.environ, PYTHONHASHSEED="0", OPENBLAS_NUM_THREADS="1", NUMBA_NUM_THREADS="1")
    proc = subprocess.run(cmd + [sys.executable, str(child), str(lib), side, str(rings), str(k)],
                          capture_output=True, text=True, env=env)
    if proc.returncode:
        raise SystemExit(f"{side}: valgrind failed: {proc.stderr.strip()[-400:]}")
    # the dump at cg_stop is <out>.1 (the file <out> itself holds the empty rest of the run)
    text = out.with_name(out.name + ".1").read_text()
    events = re.search(r"^events: (.*)$", text, re.M).group(1).split()
    totals = [int(x) for x in re.findall(r"^totals: (.*)$", text, re.M)[-1].split()]
    for p in tmp.glob(f"cg.{side}*"):
        p.unlink()
    return dict(zip(events, totals))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", type=int, default=11)
    ap.add_argument("--levels", type=int, default=2)
    ap.add_argument("--cache", type=int, default=None, help="simulate a last-level cache of this many bytes")
    ap.add_argument("--sides", nargs="+", default=["ours", "peer"], choices=["ours", "peer"])
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        (tmp / "cgctl.c").write_text(HELPER)
        lib = tmp / "libcgctl.so"
        subprocess.run(["cc", "-O2", "-shared", "-fPIC", "-o", str(lib), str(tmp / "cgctl.c")], check=True)
        res = {side: run_side(side, args.rings, args.levels, args.cache, tmp, lib) for side in args.sides}
    print(f"{{7,3}} rings = {args.rings}, {args.levels} levels"
          + (f", simulated last-level cache {args.cache / 2**20:g} MB" if args.cache else ""))
    for side, ev in res.items():
        line = f"  {side}: {ev['Ir'] / 1e9:.3f} G instructions"
        if "DLmr" in ev:
            line += f", LL misses: {ev['DLmr'] / 1e6:.2f} M reads, {ev['DLmw'] / 1e6:.2f} M writes"
        print(line)
    if len(res) == 2:
        print(f"  instruction ratio peer / ours: {res['peer']['Ir'] / res['ours']['Ir']:.2f}")


if __name__ == "__main__":
    main()
