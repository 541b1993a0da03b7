"""The tables and figure of docs/qmc-lobe.md from the stored QMC lobe scan (issue 27, item 4).

Reads the stored scan (src/hyperlattice/report/qmc_lobe_scan.json, written by benchmarks/qmc_lobe_scan.py), adds Gutzwiller mean
field and the third-order strong-coupling expansion on the same graphs, prints two Markdown tables
(the boundaries; the tips per graph) and the reference numbers, and writes docs/img/qmc_lobe.png.

Usage: ``python benchmarks/table_qmc_lobe.py [--scan FILE] [--figure FILE]`` (about 30 s).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path


def _f(x, d=4):
    return "—" if not math.isfinite(x) else f"{x:.{d}f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scan", default=None, help="a scan file (default: the one stored in the package)")
    ap.add_argument("--figure", default="docs/img/qmc_lobe.png")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    from hyperlattice.compare.qmc_lobe import load_scan, qmc_lobe
    from hyperlattice.plots.qmc_lobe import qmc_lobe_figure
    from hyperlattice.report.qmc_lobe import stored_scan

    lobe = qmc_lobe(load_scan(args.scan) if args.scan else stored_scan())
    print("| graph | sites | t/U | βt | side | μ/U QMC | μ/U mean field | μ/U strong coupling |")
    print("|---|---|---|---|---|---|---|---|")
    for r in lobe.rows:
        err = _f(r["mu_err"])
        print(f"| {r['system']} | {r['sites']} | {r['t_over_U']:.2f} | {r['beta_t']:g} | {r['side']} | "
              f"{r['mu']:.4f} ± {err} | {_f(r['mu_mean_field'])} | {_f(r['mu_strong_coupling'])} |")
    print()
    print("| graph | sites | λ_max | tip mean field | tip strong coupling | QMC pseudo-tip | βδ |")
    print("|---|---|---|---|---|---|---|")
    for s in lobe.systems:
        tq = s["tip_qmc_extrapolated"]
        tq = f"{tq:.3f} ± {s['tip_qmc_extrapolated_err']:.3f}" if math.isfinite(tq) else "—"
        print(f"| {s['system']} | {s['sites']} | {s['lambda_max']:.4f} | {s['tip_mean_field']:.4f} | "
              f"{s['tip_strong_coupling']:.4f} | {tq} | {s['beta_splitting']:.1f} |")
    print()
    sq = lobe.square
    print(f"infinite {{7,3}}: rho = {lobe.rho:.5f}, mean-field tip {lobe.infinite_tip_mean_field:.6f}; "
          f"continuum lambda = {lobe.continuum['lambda_max']:.6f}, tip {lobe.continuum['tip_mean_field']:.6f}")
    print(f"square lattice: exact tip {sq['exact']:.5f}({round(sq['exact_err'] * 1e5)}), mean field "
          f"{sq['mean_field']:.5f}, strong coupling {sq['strong_coupling']:.5f}")
    Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
    qmc_lobe_figure(lobe, args.figure)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
