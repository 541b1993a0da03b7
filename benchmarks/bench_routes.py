"""The default routes of issue 20 against their strongest peers, same process, best of several runs.

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

Usage: ``python benchmarks/bench_routes.py [--rings-big 14] [--rings-cli 12] [--repeat 3] [--only b c d e] [--slow]``.
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


def cholmod_shift_invert(a, k: int):
    """Full-matrix CHOLMOD shift-invert for the k largest eigenvalues of A (None without scikit-sparse)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    try:
        from sksparse.cholmod import cholesky
    except ImportError:
        return None
    n = a.shape[0]

    def run():
        factor = cholesky((SIGMA * sp.identity(n, format="csc") - a).tocsc())
        op = spla.LinearOperator((n, n), matvec=lambda x: -factor(x), dtype=float)
        w, _ = spla.eigsh(a, k=k, sigma=SIGMA, which="LM", OPinv=op, tol=1e-12)
        return -w[::-1]
    return run


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings-big", type=int, default=14)
    ap.add_argument("--rings-cli", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=3, help="runs of every hyperlattice side (best taken)")
    ap.add_argument("--peer-repeat", type=int, default=2, help="runs of every peer (best taken)")
    ap.add_argument("--only", nargs="*", default=["b", "c", "d", "e"])
    ap.add_argument("--slow", action="store_true", help="(e): also the Chebyshev-Lanczos 'sector' method")
    args = ap.parse_args(argv)

    import numpy as np
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

    if {"b", "c", "e"} & set(args.only):
        lat = ring_lattice(7, 3, big)
        a = adjacency(lat).tocsc()
        print(f"{{7,3}} rings = {big}: N = {lat.sites:,}")
        for k in (2, 10):
            if k == 2 and not {"b", "e"} & set(args.only) or k == 10 and not {"c", "e"} & set(args.only):
                continue
            t_api, spec = best(lambda: lowest_levels(ring_lattice(7, 3, big), k), args.repeat)
            print(f"  lowest_levels(ring_lattice(7, 3, {big}), {k}) [default, build counted]: {t_api:7.2f} s  "
                  f"method {spec.method}  E0 = {spec.energies[0]:.13f}  max residual {spec.errors.max():.1e}")
            label = "b" if k == 2 else "c"
            peer = cholmod_shift_invert(a, k)
            if peer is not None:
                with _single_threaded_blas():
                    t_peer, e_peer = best(peer, args.peer_repeat)
                diff = float(np.max(np.abs(e_peer - np.asarray(spec.energies)[:k])))
                print(f"  full-matrix CHOLMOD shift-invert k = {k} (no build): {t_peer:7.2f} s   "
                      f"max |dE| = {diff:.1e}   ratio {t_peer / t_api:.2f}x")
                rows.append((label, f"lowest_levels(ring_lattice(7,3,{big}),{k}) vs CHOLMOD shift-invert k={k}",
                             t_peer / t_api))
            if k == 2 and "b" in args.only:
                t_cli, out = cli(["spectrum", "--rings", str(big), "--json"], args.repeat)
                print(f"  hyperlattice spectrum --rings {big} --json [subprocess]: {t_cli:7.2f} s  "
                      f"method {out['method']}")
                if peer is not None:
                    rows.append(("b", f"hyperlattice spectrum --rings {big} --json vs CHOLMOD shift-invert k=2",
                                 t_peer / t_cli))
            if "e" in args.only:
                explicit = {"shift-invert": lambda: lowest_levels(ring_lattice(7, 3, big), k, method="shift-invert")}
                if args.slow:
                    explicit["sector"] = lambda: lowest_levels(ring_lattice(7, 3, big), k, method="sector")
                times = {m: best(fn, args.repeat)[0] for m, fn in explicit.items()}
                for m, t in times.items():
                    print(f"  method={m}: {t:7.2f} s")
                best_m = min(times, key=times.get)
                rows.append(("e", f"auto / best explicit ({best_m}), l={big}, {k} levels",
                             t_api / times[best_m]))
                if k == 2:
                    t_pair, _ = cli(["spectrum", "--rings", str(big), "--method", "pair", "--json"], args.repeat)
                    t_cauto, _ = cli(["spectrum", "--rings", str(big), "--json"], args.repeat)
                    print(f"  CLI --method pair {t_pair:7.2f} s, default {t_cauto:7.2f} s")
                    rows.append(("e", f"CLI auto / --method pair, l={big}", t_cauto / t_pair))
        del a, lat

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
        rows.append(("d", f"hyperlattice spectrum --rings {r} --json vs plain eigsh", t_plain / t_cli))

    print(f"process peak RSS {peak_rss_mb():.0f} MB")
    print("summary (ratio = peer time / hyperlattice time; for (e) auto time / best explicit time):")
    for label, what, ratio in rows:
        print(f"  ({label}) {what}: {ratio:.2f}")


if __name__ == "__main__":
    main()
