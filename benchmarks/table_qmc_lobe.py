"""The tables and figures of docs/qmc-lobe.md from the stored QMC lobe scan.

Reads the stored scan (src/hyperlattice/report/qmc_lobe_scan.json, written by benchmarks/qmc_lobe_scan.py), adds Gutzwiller mean
field and the third-order strong-coupling expansion on the same graphs, fits the pseudo-tips and
their size extrapolation, prints three Markdown tables (the boundaries; the tips per graph and
temperature; the extrapolation) and the reference numbers (with three or more cluster sizes also
the test of the extrapolation's form: chi^2 and each middle size against the line through the
smallest and the largest), and writes docs/img/qmc_lobe.png and
docs/img/qmc_tip.png.

Usage: ``python benchmarks/table_qmc_lobe.py [--scan FILE] [--figure FILE] [--tip-figure FILE]`` (about a minute).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path


def _f(x, d=4):
    return "—" if not math.isfinite(x) else f"{x:.{d}f}"


def _table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print()


def _form_check(lobe, f) -> None:
    """Print the test of x_c(M) = x_inf + c/M with three or more cluster sizes: chi^2 of both forms, and
    each middle cluster against the line through the smallest and the largest (a prediction it did
    not enter), in units of the combined error."""
    from hyperlattice.compare.qmc_lobe import size_extrapolation

    print(f"cluster sizes {' + '.join(str(m) for m in f['sites'])} (beta t = {f['beta_t']:g}): chi2 = "
          f"{f['chi2']:.2f} for {f['dof']} dof with c/M, {f['chi2_sqrt_form']:.2f} with c/sqrt(M)")
    pts = sorted((s["sites"], d["tip"], d["tip_err"]) for s in lobe.systems if s["system"].startswith("cluster:")
                 for d in s["tips"] if d["beta_t"] == f["beta_t"] and d["nmax"] == 3 and math.isfinite(d["tip"]))
    (m0, v0, e0), (m1, v1, e1) = pts[0], pts[-1]
    for m, v, e in pts[1:-1]:
        for power, form in ((1.0, "c/M"), (0.5, "c/sqrt(M)")):
            line = size_extrapolation([m0, m1], [v0, v1], [e0, e1], power=power)
            # the two-point line at M and its propagated error (the fit's covariance, exact here)
            u, u0, u1 = m ** -power, m0 ** -power, m1 ** -power
            a0, a1 = (u - u1) / (u0 - u1), (u0 - u) / (u0 - u1)
            pred, pred_err = a0 * v0 + a1 * v1, math.hypot(a0 * e0, a1 * e1)
            assert abs(pred - (line["tip"] + line["slope"] * u)) < 1e-12
            print(f"  {m} sites: pseudo-tip {v:.4f} +- {e:.4f}; the {form} line through {m0} and {m1} sites "
                  f"predicts {pred:.4f} +- {pred_err:.4f}: residual {(v - pred) / math.hypot(e, pred_err):+.1f} sigma")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scan", default=None, help="a scan file (default: the one stored in the package)")
    ap.add_argument("--figure", default="docs/img/qmc_lobe.png")
    ap.add_argument("--tip-figure", default="docs/img/qmc_tip.png")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    from hyperlattice.compare.qmc_lobe import load_scan, qmc_lobe
    from hyperlattice.plots.qmc_lobe import qmc_lobe_figure, qmc_tip_figure
    from hyperlattice.report.qmc_lobe import (EXTRAPOLATION_HEADER, TIP_HEADER, extrapolation_rows, headline,
                                              stored_scan, system_label, tip_rows)

    lobe = qmc_lobe(load_scan(args.scan) if args.scan else stored_scan())
    _table(["graph", "sites", "t/U", "βt", "nmax", "side", "μ/U QMC", "μ/U mean field", "μ/U strong coupling"],
           [[system_label(r["system"]), str(r["sites"]), f"{r['t_over_U']:.2f}", f"{r['beta_t']:g}", str(r["nmax"]), r["side"],
             f"{r['mu']:.4f} ± {_f(r['mu_err'])}", _f(r["mu_mean_field"]), _f(r["mu_strong_coupling"])]
            for r in lobe.rows])
    _table(TIP_HEADER, tip_rows(lobe))
    _table(EXTRAPOLATION_HEADER, extrapolation_rows(lobe))
    sq = lobe.square
    h = headline(lobe)
    print(f"infinite {{7,3}}: rho = {lobe.rho:.5f}, mean-field tip {lobe.infinite_tip_mean_field:.6f}; "
          f"3-regular graph: mean-field tip {h['mf_cluster']:.4f}; "
          f"continuum lambda = {lobe.continuum['lambda_max']:.6f}, tip {lobe.continuum['tip_mean_field']:.6f}")
    print(f"square lattice: exact tip {sq['exact']:.5f}({round(sq['exact_err'] * 1e5)}), mean field "
          f"{sq['mean_field']:.5f} ({h['off_square']:.0%} low), strong coupling {sq['strong_coupling']:.5f}")
    print(f"simple cubic lattice: exact tip {sq['cubic_exact']:.5f}({round(sq['cubic_exact_err'] * 1e5)}), "
          f"mean field {sq['cubic_mean_field']:.5f} ({h['off_cubic']:.0%} low)")
    if h["cluster"]:
        c = h["cluster"]
        print(f"largest cluster {c['system'].partition(':')[2]} ({c['sites']} sites, beta t = {c['beta_t']:g}): pseudo-tip "
              f"{c['tip']:.4f} +- {c['tip_err']:.4f}; mean field on it {c['mean_field']:.4f} ({h['off_cluster']:.0%} low)")
    if h["infinite"]:
        f = h["infinite"]
        print(f"clusters extrapolated (beta t = {f['beta_t']:g}): {f['tip']:.4f} +- {f['tip_err']:.4f}; mean field "
              f"{h['off_infinite_cluster']:.0%} low (z = 3), {h['off_infinite_rho']:.0%} low (rho)")
        if f["dof"] >= 1:
            _form_check(lobe, f)
    Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
    qmc_lobe_figure(lobe, args.figure)
    Path(args.tip_figure).parent.mkdir(parents=True, exist_ok=True)
    qmc_tip_figure(lobe, args.tip_figure)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
