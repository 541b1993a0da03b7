"""``hyperlattice bosons lobe``: the n = 1 Mott-lobe boundaries mu+/U and mu-/U of a {p,q} flake or
periodic cluster from quantum Monte Carlo (Newton steps on <N>, :func:`hyperlattice.compare.qmc_lobe.qmc_boundary`),
next to strong coupling and mean field on the same graph.

The scan goes to ``--out DIR`` as ``DIR/qmc_lobe_scan.json`` (the format of the package's stored
scan, which :func:`hyperlattice.compare.qmc_lobe.load_scan` and ``qmc_lobe`` read), rewritten
atomically after every boundary; boundaries already in the file are skipped, so a rerun of the
same command resumes an interrupted scan. The package's own stored scan is never the target.
Every boundary carries ``converged``: False when a chain behind it has a binning error off its
plateau (or another warning of :func:`hyperlattice.bosons.qmc`), marked ``*`` in the table.
"""

from __future__ import annotations

import argparse
import json
import math
import os
from pathlib import Path

from ._common import Interrupted, add_pq, check_work, cluster_pq, finite_float, positive_int, print_json

NAME = "lobe"
ORDER = 45
HELP = "Mott-lobe boundaries mu+/U, mu-/U of a {p,q} flake or cluster from QMC (a scan written to --out DIR)"
DESCRIPTION = ("The n = 1 Mott-lobe boundaries of the Bose-Hubbard model on a {p,q} flake (--rings) or periodic "
               "cluster (--cluster) at the given t/U values: for each, mu+/U (one particle added, <N> = M + 1/2) "
               "and mu-/U (one removed, <N> = M - 1/2) from grand-canonical QMC by Newton steps on <N>(mu) with "
               "the slope beta M kappa of the same run, next to third-order strong coupling and mean field on the "
               "same graph. Written to DIR/qmc_lobe_scan.json after every boundary (a rerun resumes); a boundary "
               "whose chains did not converge is flagged (converged: false, '*' in the table).")

#: the scan's file name in --out DIR (that of the package's stored scan)
SCAN_FILE = "qmc_lobe_scan.json"
#: default of ``--max-seconds``: a lobe scan is long by nature (one day)
MAX_SECONDS = 86400.0


def _positive(text: str) -> float:
    v = finite_float(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}")
    return v


def add_arguments(parser: argparse.ArgumentParser) -> None:
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a flake of this many rings (1 = one p-gon)")
    where.add_argument("--cluster", metavar="NAME", help="a periodic cluster, e.g. klein or bolza (its p and q "
                                                         "unless -p/-q are given)")
    add_pq(parser)
    parser.add_argument("--t-over-U", dest="t_over_U", type=_positive, nargs="+", required=True, metavar="X",
                        help="values of t/U (one or more)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help=f"directory of the scan (created): DIR/{SCAN_FILE}, rewritten after every boundary; "
                             "a rerun skips the boundaries already there")
    parser.add_argument("--beta", type=_positive, default=8.0, help="inverse temperature beta t (default 8)")
    parser.add_argument("--nmax", type=positive_int, default=3,
                        help="occupation cutoff (default 3, exact to O((t/U)^4) for the n = 1 lobe)")
    parser.add_argument("--sweeps", type=positive_int, default=400, help="QMC sweeps per Newton step (default 400)")
    parser.add_argument("--thermalization", type=positive_int, default=150,
                        help="thermalisation sweeps per Newton step (default 150)")
    parser.add_argument("--iterations", type=positive_int, default=3, help="Newton steps per boundary (1-10, default 3)")
    parser.add_argument("--seed", type=positive_int, default=1000,
                        help="base seed: the k-th run of the b-th boundary in the file uses seed + 10 b + k "
                             "(default 1000)")
    parser.add_argument("--max-seconds", type=finite_float, default=MAX_SECONDS, metavar="S",
                        help=f"refuse a scan estimated to take longer than S seconds (default {MAX_SECONDS:g})")
    parser.add_argument("--json", action="store_true", help="print the boundaries as JSON")


def _stored_scan() -> Path:
    from .. import report

    return (Path(report.__file__).parent / SCAN_FILE).resolve()


def _target(out) -> Path:
    from .. import _validate

    path = _validate.directory("--out", out) / SCAN_FILE
    if path.resolve() == _stored_scan():
        raise ValueError(f"--out {str(out)!r} is the package's own report directory, whose {SCAN_FILE} is the "
                         "stored scan the report reads; choose another directory.")
    return path


def _read(path: Path) -> dict:
    if not path.exists():
        return {"meta": {}, "boundaries": []}
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"{str(path)!r} is not a lobe scan (JSON): {exc}; move it away or choose another "
                         "--out.") from None
    if (not isinstance(data, dict) or not isinstance(data.get("boundaries"), list)
            or not all(isinstance(b, dict) for b in data["boundaries"])):
        raise ValueError(f"{str(path)!r} is not a lobe scan (no list of boundaries); move it away or choose "
                         "another --out.")
    data.setdefault("meta", {})
    return data


def _write(path: Path, data: dict) -> None:
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1, allow_nan=True)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def _estimate(system, args) -> None:
    """The scan's time before it starts: every Newton run at the strong-coupling boundary."""
    from ..bosons import qmc_seconds
    from ..bosons.strong_coupling import excitation_energies

    plus, minus = excitation_energies(system, list(args.t_over_U))
    seconds = 0.0
    for x, mp, mm in zip(args.t_over_U, plus, minus):
        for mu in (mp, mm):
            mu = float(mu) if math.isfinite(mu) else 0.5
            seconds += args.iterations * qmc_seconds(system, U=1.0 / x, mu=mu / x, beta=args.beta, nmax=args.nmax,
                                                     sweeps=args.sweeps, thermalization=args.thermalization)
    check_work("bosons lobe", seconds, args.max_seconds,
               f"{2 * len(args.t_over_U)} boundaries x {args.iterations} runs of {args.sweeps + args.thermalization:,} "
               "sweeps", "fewer --t-over-U values, --sweeps or --iterations, a smaller --beta or graph")


def run(args: argparse.Namespace) -> int:
    import warnings

    from .. import _validate
    from ..bosons.meanfield import largest_adjacency_eigenvalue
    from ..bosons.strong_coupling import excitation_energies
    from ..compare.qmc_lobe import mean_field_boundaries, qmc_boundary, system_spec

    if args.iterations > 10:
        raise ValueError(f"--iterations must be 1 to 10, got {args.iterations}.")
    path = _target(args.out)
    p, q = _validate.pq(args.p, args.q) if args.cluster is None else cluster_pq(args, args.cluster)
    if args.rings is not None:
        from ..graph.lattice import ring_lattice

        system = ring_lattice(p, q, args.rings)
    else:
        from ..graph.clusters import pbc_cluster

        system = pbc_cluster(p, q, args.cluster)
    spec = system_spec(p, q, rings=args.rings, cluster=args.cluster)
    _estimate(system, args)
    from filelock import FileLock, Timeout

    lock = FileLock(str(path.parent / ".qmc_lobe_scan.lock"), timeout=0)
    try:
        lock.acquire()
    except Timeout:
        raise ValueError(f"--out {str(path.parent)!r} is in use by another lobe scan; wait for it or choose "
                         "another directory.") from None
    try:
        data = _read(path)
        data["meta"].setdefault("command", "hyperlattice bosons lobe")
        key = (spec, args.beta, args.nmax)
        done = {(b.get("system"), b.get("beta_t"), b.get("nmax", 3), b.get("t_over_U"), b.get("side")): b
                for b in data["boundaries"]}
        mine = []
        try:
            for x in args.t_over_U:
                for side in ("plus", "minus"):
                    b = done.get((*key, x, side))
                    if b is None:
                        with warnings.catch_warnings():
                            # the boundary keeps its chains' notes and its flag; no line per run
                            warnings.simplefilter("ignore")
                            b = qmc_boundary(system, x, side, beta_t=args.beta, sweeps=args.sweeps, nmax=args.nmax,
                                             iterations=args.iterations,
                                             seed=args.seed + 10 * len(data["boundaries"]),
                                             thermalization=args.thermalization)
                        b.update(system=spec, thermalization=args.thermalization)
                        data["boundaries"].append(b)
                        _write(path, data)
                    mine.append(b)
        except KeyboardInterrupt:
            raise Interrupted(f"{len(mine)} of {2 * len(args.t_over_U)} boundaries kept in {str(path)!r}; rerun the "
                              "same command to resume") from None
    finally:
        lock.release()
    lam = float(largest_adjacency_eigenvalue(system))
    xs = [b["t_over_U"] for b in mine]
    sc_p, sc_m = excitation_energies(system, xs)
    mf_p, mf_m = mean_field_boundaries(lam, xs)
    rows = []
    for k, b in enumerate(mine):
        plus = b["side"] == "plus"
        rows.append({"system": spec, "sites": b["sites"], "t_over_U": b["t_over_U"], "side": b["side"],
                     "beta_t": b["beta_t"], "nmax": b["nmax"], "mu": b["mu"], "mu_err": b["mu_err"],
                     "converged": bool(b.get("converged", True)),
                     "mu_strong_coupling": float(sc_p[k] if plus else sc_m[k]),
                     "mu_mean_field": float(mf_p[k] if plus else mf_m[k])})
    if args.json:
        print_json({"scan": str(path), "boundaries": rows})
        return 0
    print(f"{spec} ({rows[0]['sites']} sites), beta t = {args.beta:g}, nmax = {args.nmax}: n = 1 lobe, mu/U")
    print(f"  {'t/U':>8} {'side':>5} {'QMC':>18} {'strong coupl.':>14} {'mean field':>11}")
    def num(v, width):
        return f"{v:>{width}.4f}" if math.isfinite(v) else f"{'-':>{width}}"

    for r in rows:
        flag = "" if r["converged"] else " *"
        print(f"  {r['t_over_U']:>8.4g} {r['side']:>5} {r['mu']:>9.4f} +- {r['mu_err']:<6.4f}{flag:2}"
              f"{num(r['mu_strong_coupling'], 12)} {num(r['mu_mean_field'], 11)}")
    if not all(math.isfinite(r["mu_mean_field"]) for r in rows):
        print("  - beyond the mean-field tip (no lobe there)")
    if not all(r["converged"] for r in rows):
        print("  * a chain behind this boundary did not converge (binning plateau or thermalisation): "
              "run with more --sweeps")
    print(f"  written to {path}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
