"""QMC scan of the n = 1 Mott-lobe boundaries of the {7,3} graphs behind the stored scan src/hyperlattice/report/qmc_lobe_scan.json.

Each point is one boundary mu_+ or mu_- of one graph at one t/U and one beta t, located by Newton
steps on <N> - (M +- 1/2) (hyperlattice.compare.qmc_lobe.qmc_boundary). The file is rewritten after
every point and points already in it are skipped, so an interrupted scan resumes. Each Newton
search starts from the boundaries already found on the same graph (the same t/U at another
temperature, else a straight line through the two nearest t/U, else the strong-coupling value),
which saves one or two Newton steps near the tip where the strong-coupling series is poor. Heavy:
it is not run by the tests (they read the stored file and check the analysis on synthetic data).

    PYTHONPATH=src python benchmarks/qmc_lobe_scan.py --stage tip --out src/hyperlattice/report/qmc_lobe_scan.json
    PYTHONPATH=src python benchmarks/qmc_lobe_scan.py --points cluster:klein@0.07 --beta 8 --sweeps 400
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

#: (system, t/U) of the early scan at beta t = 5 (heptagon, l = 2 flake, Klein quartic)
EARLY_POINTS = [
    ("flake:1", 0.04), ("flake:1", 0.08), ("flake:1", 0.12), ("flake:1", 0.16),
    ("flake:2", 0.06), ("flake:2", 0.10),
    ("cluster:klein", 0.06), ("cluster:klein", 0.10),
    ("flake:2", 0.08), ("cluster:klein", 0.08),
]

#: the tip scan, cheapest first: (system, beta t, t/U values)
TIP_STAGES = [
    ("cluster:klein", 8.0, (0.06, 0.07, 0.08, 0.09)),
    ("flake:3", 8.0, (0.06, 0.07, 0.08, 0.09)),
    ("cluster:klein", 4.0, (0.06, 0.07, 0.08, 0.09)),
    ("flake:3", 4.0, (0.06, 0.07, 0.08, 0.09)),
    ("cluster:PSL(2,13)", 8.0, (0.06, 0.07, 0.08)),
    ("flake:4", 8.0, (0.07, 0.08, 0.09)),
    ("cluster:PSL(2,13)", 4.0, (0.06, 0.07, 0.08)),
    ("flake:4", 4.0, (0.07, 0.08, 0.09)),
    ("cluster:macbeath", 8.0, (0.06, 0.07, 0.08, 0.09)),
    ("cluster:macbeath", 4.0, (0.06, 0.07, 0.08, 0.09)),
]


def _start(data, spec, x, side, beta, nmax):
    """A starting mu/U from the boundaries already in the scan (None: the strong-coupling value)."""
    same = [b for b in data["boundaries"] if b["system"] == spec and b["side"] == side and b.get("nmax", 3) == nmax
            and b["mu"] == b["mu"]]
    at_x = [b for b in same if abs(b["t_over_U"] - x) < 1e-12]
    if at_x:
        return min(at_x, key=lambda b: abs(b["beta_t"] - beta))["mu"]
    pts = sorted({b["t_over_U"]: b["mu"] for b in same if b["beta_t"] == beta}.items(), key=lambda p: abs(p[0] - x))
    if len(pts) >= 2:
        (x1, m1), (x2, m2) = pts[:2]
        return m1 + (m2 - m1) / (x2 - x1) * (x - x1)
    return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", nargs="*", help="system@t_over_U items (with --beta)")
    ap.add_argument("--stage", choices=("early", "tip"), default="tip", help="the stored point list to run")
    ap.add_argument("--beta", type=float, default=8.0, help="beta t of --points (default 8)")
    ap.add_argument("--sweeps", type=int, default=400, help="sweeps per Newton step (default 400)")
    ap.add_argument("--thermalization", type=int, default=150, help="thermalisation sweeps per step (default 150)")
    ap.add_argument("--iterations", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1000,
                    help="base seed: a boundary's runs use seed + 10 x (boundaries already in the file) + k "
                         "(give concurrent scans into separate files different bases)")
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--max-seconds", type=float, default=float("inf"), help="stop starting new points after this")
    ap.add_argument("--out", default="qmc_lobe_scan.json",
                    help="the scan's JSON file (default qmc_lobe_scan.json here; the stored scan is "
                         "src/hyperlattice/report/qmc_lobe_scan.json, regenerated only when named); any {p,q}: "
                         "hyperlattice bosons lobe")
    args = ap.parse_args(argv)
    from hyperlattice.compare.qmc_lobe import _system, qmc_boundary

    if args.points:
        todo = [(s.split("@")[0], args.beta, float(s.split("@")[1])) for s in args.points]
    elif args.stage == "early":
        todo = [(s, 5.0, x) for s, x in EARLY_POINTS]
    else:
        todo = [(s, b, x) for s, b, xs in TIP_STAGES for x in xs]
    data = {"meta": {}, "boundaries": []}
    if os.path.exists(args.out):
        with open(args.out, encoding="utf-8") as fh:
            data = json.load(fh)
    data["meta"]["command"] = ("PYTHONPATH=src python benchmarks/qmc_lobe_scan.py --stage tip "
                               "--out src/hyperlattice/report/qmc_lobe_scan.json")
    data["meta"]["machine"] = f"{platform.machine()}, python {platform.python_version()}"
    done = {(b["system"], b["t_over_U"], b["side"], b["beta_t"], b.get("nmax", 3)) for b in data["boundaries"]}
    t_start = time.time()
    graphs = {}
    for spec, beta, x in todo:
        if spec not in graphs:
            graphs[spec] = _system(spec)
        for side in ("plus", "minus"):
            if (spec, x, side, beta, args.nmax) in done:
                continue
            if time.time() - t_start > args.max_seconds:
                print("time budget reached", flush=True)
                return 0
            t0 = time.time()
            b = qmc_boundary(graphs[spec], x, side, beta_t=beta, sweeps=args.sweeps, nmax=args.nmax,
                             iterations=args.iterations, seed=args.seed + len(data["boundaries"]) * 10,
                             mu_start=_start(data, spec, x, side, beta, args.nmax),
                             thermalization=args.thermalization)
            b["system"] = spec
            b["thermalization"] = args.thermalization
            b["seconds"] = time.time() - t0
            data["boundaries"].append(b)
            with open(args.out + ".tmp", "w", encoding="utf-8") as fh:
                json.dump(data, fh, indent=1)
            os.replace(args.out + ".tmp", args.out)
            print(f"{spec} bt={beta:g} t/U={x} {side}: mu/U = {b['mu']:.4f} +- {b['mu_err']:.4f} "
                  f"({b['seconds']:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
