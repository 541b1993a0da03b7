"""QMC scan of the n = 1 Mott-lobe boundaries (issue 27, item 4): writes src/hyperlattice/report/qmc_lobe_scan.json.

Each point is one boundary mu_+ or mu_- of one graph at one t/U, located by Newton steps on
<N> - (M +- 1/2) (hyperlattice.compare.qmc_lobe.qmc_boundary). The file is rewritten after every
point and points already in it are skipped, so an interrupted scan resumes. Heavy: it is not run by
the tests (they read the stored file and check the table/figure code on a tiny scan).

    PYTHONPATH=src python benchmarks/qmc_lobe_scan.py            # the stored scan (about 30 min on 1 core)
    PYTHONPATH=src python benchmarks/qmc_lobe_scan.py --points flake:1@0.04 --beta 5 --sweeps 200 --out /tmp/x.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

#: (system, t/U) of the stored scan, cheapest first
DEFAULT_POINTS = [
    ("flake:1", 0.04), ("flake:1", 0.08), ("flake:1", 0.12), ("flake:1", 0.16),
    ("flake:2", 0.06), ("flake:2", 0.10),
    ("square:6", 0.04), ("square:6", 0.06),
    ("cluster:klein", 0.06), ("cluster:klein", 0.10),
    ("flake:3", 0.08),
    ("flake:2", 0.08), ("cluster:klein", 0.08), ("flake:3", 0.06),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", nargs="*", help="system@t_over_U items (default: the stored scan)")
    ap.add_argument("--beta", type=float, default=5.0, help="beta t (default 5)")
    ap.add_argument("--sweeps", type=int, default=400, help="sweeps per Newton step (default 400)")
    ap.add_argument("--iterations", type=int, default=3)
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "src", "hyperlattice", "report",
                                                  "qmc_lobe_scan.json"))
    args = ap.parse_args(argv)
    from hyperlattice.compare.qmc_lobe import _system, qmc_boundary

    points = DEFAULT_POINTS if not args.points else [(s.split("@")[0], float(s.split("@")[1])) for s in args.points]
    data = {"meta": {}, "boundaries": []}
    if os.path.exists(args.out):
        with open(args.out, encoding="utf-8") as fh:
            data = json.load(fh)
    data["meta"] = {"command": "PYTHONPATH=src python benchmarks/qmc_lobe_scan.py", "beta_t": args.beta,
                    "sweeps_per_step": args.sweeps, "iterations": args.iterations, "nmax": args.nmax,
                    "machine": platform.machine(), "python": platform.python_version()}
    done = {(b["system"], b["t_over_U"], b["side"], b["beta_t"]) for b in data["boundaries"]}
    for spec, x in points:
        g = _system(spec)
        for side in ("plus", "minus"):
            if (spec, x, side, args.beta) in done:
                continue
            t0 = time.time()
            b = qmc_boundary(g, x, side, beta_t=args.beta, sweeps=args.sweeps, nmax=args.nmax,
                             iterations=args.iterations, seed=1000 + len(data["boundaries"]) * 10)
            b["system"] = spec
            b["seconds"] = time.time() - t0
            data["boundaries"].append(b)
            with open(args.out + ".tmp", "w", encoding="utf-8") as fh:
                json.dump(data, fh, indent=1)
            os.replace(args.out + ".tmp", args.out)
            print(f"{spec} t/U={x} {side}: mu/U = {b['mu']:.4f} +- {b['mu_err']:.4f} ({b['seconds']:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
