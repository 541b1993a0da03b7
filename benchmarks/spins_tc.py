"""Ising T_c on closed {7,3}, {8,3} and {5,4} surfaces from Binder-cumulant crossings (docs/spins.md).

For each tiling, three (four for {7,3}) periodic clusters of growing size (graph/clusters.py), a grid of
temperatures, one Wolff chain per point (hyperlattice.spins.classical_mc). The crossing of the
U4(T) curves of two sizes comes from monotone cubic (PCHIP) interpolants of each curve, with a
parametric bootstrap (U4 resampled within its errors, 400 times) for the error. Printed
next to it: the Bethe-lattice value 1/artanh(1/(q-1)), the mean-field value q, the cumulant at the
crossing against the mean-field value 1 - Gamma(1/4)^2 / (12 Gamma(3/4)^2) = 0.2705, and the slope
of log chi against log N at the crossing (1/2 in mean field: chi ~ N^(1/2) at T_c).

Run: ``python benchmarks/spins_tc.py`` (about 30 minutes on one core; ``--only 7,3`` for one
tiling; ``--analyse`` re-reads benchmarks/spins_tc_P_Q.json and redraws docs/img/spins_binder.png).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE / "spins_tc_{p}_{q}.json"
FIG = HERE.parent / "docs" / "img" / "spins_binder.png"

#: (p, q): [(cluster name, measured sweeps, temperatures)]; the largest cluster of each tiling only
#: near the crossing of the smaller two (CPU time)
_G73 = np.arange(1.62, 1.8401, 0.02)
_G83 = np.arange(1.66, 1.8801, 0.02)
_G54 = np.arange(2.60, 2.9201, 0.04)
PLAN = {
    (7, 3): [("macbeath", 20000, _G73), ("hurwitz14a", 20000, _G73), ("PSL(2,29)", 8000, _G73),
             ("PSL(2,41)", 2000, np.arange(1.70, 1.7801, 0.02))],
    (8, 3): [("PSL(2,17)", 20000, _G83), ("PSL(2,31)", 8000, _G83), ("PSL(2,47)", 2000, np.arange(1.74, 1.8201, 0.02))],
    (5, 4): [("PSL(2,31)", 6000, _G54), ("PSL(2,41)", 4000, _G54), ("PSL(2,71)", 1500, None)],
}
U4_MEAN_FIELD = 1.0 - math.gamma(0.25) ** 2 / (12.0 * math.gamma(0.75) ** 2)


def measure(only=None) -> dict:
    from hyperlattice.graph.clusters import pbc_cluster
    from hyperlattice.spins import classical_mc
    from hyperlattice.spins.classical import SpinWarning

    data = {}
    for (p, q), clusters in PLAN.items():
        if only and (p, q) != only:
            continue
        out = Path(str(OUT).format(p=p, q=q))
        part = json.loads(out.read_text()) if out.exists() else {}
        data.update(part)
        for name, sweeps, temps in clusters:
            if temps is None:       # near the crossing of the two smaller clusters
                keys = [f"{p},{q},{n}" for n, _, _ in clusters[:2]]
                if not all(k in data for k in keys):
                    continue
                tc = _crossing(data[keys[0]], data[keys[1]], np.random.default_rng(1), boot=0)[0]
                if not math.isfinite(tc):
                    continue
                temps = np.round(tc + np.arange(-0.06, 0.061, 0.03), 3)
            c = pbc_cluster(p, q, name)
            key = f"{p},{q},{name}"
            rows = data.get(key, {}).get("rows", [])
            done = {round(r["T"], 6) for r in rows}
            for T in temps:
                if round(float(T), 6) in done:
                    continue
                t0 = time.process_time()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", SpinWarning)
                    r = classical_mc(c, model="ising", T=float(T), sweeps=sweeps, seed=1000 + len(rows),
                                     measure_correlation=False, progress=False)
                rows.append({k: float(getattr(r, k)) for k in ("e", "e_err", "c", "c_err", "m2", "m2_err", "U4",
                                                              "U4_err", "chi", "chi_err")}
                            | {"T": float(T), "tau_m2": float(r.tau_int["m2"]), "converged": bool(r.converged),
                               "cpu": time.process_time() - t0})
                data[key] = part[key] = {"p": p, "q": q, "name": name, "sites": int(r.sites), "sweeps": sweeps,
                                         "rows": rows}
                out.write_text(json.dumps(part, indent=1))
                print(f"{key} ({r.sites} sites) T = {T:.3f}: U4 = {r.U4:.4f} +- {r.U4_err:.4f}, chi = {r.chi:.1f}, "
                      f"{time.process_time() - t0:.1f} s", flush=True)
    return data


def _curve(entry):
    rows = sorted(entry["rows"], key=lambda r: r["T"])
    return (np.array([r[k] for r in rows]) for k in ("T", "U4", "U4_err"))


def _rough(Ta, ya, Tb, yb):
    """Where the piecewise-linear curves cross (the sign change with the largest slope difference)."""
    grid = np.union1d(Ta[(Ta >= Tb.min()) & (Ta <= Tb.max())], Tb[(Tb >= Ta.min()) & (Tb <= Ta.max())])
    if grid.size < 2:
        return math.nan
    d = np.interp(grid, Ta, ya) - np.interp(grid, Tb, yb)
    s = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))
    if s.size == 0:
        return math.nan
    k = s[np.argmax(np.abs(d[s + 1] - d[s]))]
    return float(grid[k] - d[k] * (grid[k + 1] - grid[k]) / (d[k + 1] - d[k]))


def _crossing(a, b, rng, boot=400):
    """T where the U4(T) curves of two sizes cross: the crossing of their monotone cubic (PCHIP)
    interpolants next to the crossing of the piecewise-linear curves, with a parametric bootstrap
    error (U4 resampled within its binning errors); and the cumulant there. A quadratic or cubic
    fit cannot follow the sigmoid of the larger clusters (their U4 falls from 0.54 to 0.15 within
    0.03 in T), and its crossing can land outside the bracketing grid interval."""
    from scipy.interpolate import PchipInterpolator

    Ta, ya, ea = _curve(a)
    Tb, yb, eb = _curve(b)
    t_r = _rough(Ta, ya, Tb, yb)
    if not math.isfinite(t_r):
        return math.nan, math.nan, math.nan, math.nan
    lo, hi = max(Ta.min(), Tb.min()), min(Ta.max(), Tb.max())
    grid = np.linspace(lo, hi, 4001)

    def one(y1, y2):
        d = PchipInterpolator(Ta, y1)(grid) - PchipInterpolator(Tb, y2)(grid)
        s = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))
        if s.size == 0:
            return math.nan, math.nan
        k = s[np.argmin(np.abs(grid[s] - t_r))]
        t = grid[k] - d[k] * (grid[k + 1] - grid[k]) / (d[k + 1] - d[k])
        return float(t), float(PchipInterpolator(Ta, y1)(t))

    t0, u0 = one(ya, yb)
    if boot == 0:
        return t0, math.nan, u0, math.nan
    samples = [one(ya + ea * rng.standard_normal(ya.size), yb + eb * rng.standard_normal(yb.size)) for _ in range(boot)]
    ts = np.array([x[0] for x in samples])
    us = np.array([x[1] for x in samples])
    ok = np.isfinite(ts)
    if ok.sum() <= 10:
        return t0, math.nan, u0, math.nan
    return t0, float(np.std(ts[ok])), u0, float(np.std(us[ok]))


def _chi_at(entry, T):
    rows = sorted(entry["rows"], key=lambda r: r["T"])
    Ts = np.array([r["T"] for r in rows])
    lc = np.log([r["chi"] for r in rows])
    return float(np.exp(np.interp(T, Ts, lc)))


def analyse(data: dict) -> None:
    rng = np.random.default_rng(7)
    print(f"\n{'tiling':<8} {'sizes':<22} {'crossing T (pairs)':<40} {'T_c':<16} {'Bethe':>7} {'MF':>4} "
          f"{'U4 at T_c':<14} {'chi ~ N^b':<10}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, (p, q) in zip(axes, PLAN):  # noqa: B007
        entries = sorted([v for v in data.values() if v["p"] == p and v["q"] == q], key=lambda v: v["sites"])
        if len(entries) < 2:
            continue
        pairs = [(entries[i], entries[i + 1]) for i in range(len(entries) - 1)]
        cross = [_crossing(a, b, rng) for a, b in pairs]
        tc, tce, u, ue = cross[-1]
        bethe = 1.0 / math.atanh(1.0 / (q - 1))
        Ns = np.array([e["sites"] for e in entries], dtype=float)
        chis = np.array([_chi_at(e, tc) for e in entries])
        b = float(np.polyfit(np.log(Ns), np.log(chis), 1)[0]) if math.isfinite(tc) else math.nan
        ptxt = ", ".join(f"{t:.3f}({1000 * e:.0f})" for t, e, _, _ in cross)
        print(f"{{{p},{q}}}".ljust(8), ",".join(str(e["sites"]) for e in entries).ljust(22), ptxt.ljust(40),
              f"{tc:.3f} +- {tce:.3f}".ljust(16), f"{bethe:7.3f} {q:4d}", f"{u:.3f} +- {ue:.3f}".ljust(14),
              f"{b:.2f}")
        for e in entries:
            rows = sorted(e["rows"], key=lambda r: r["T"])
            ax.errorbar([r["T"] for r in rows], [r["U4"] for r in rows], [r["U4_err"] for r in rows], marker="o",
                        ms=3, capsize=2, label=f"{e['name']} ({e['sites']} sites)")
        ax.axvline(bethe, color="k", ls="--", lw=0.8, label=f"Bethe {bethe:.3f}")
        if math.isfinite(tc):
            ax.axvspan(tc - tce, tc + tce, color="C3", alpha=0.25, label=f"crossing {tc:.3f}")
        ax.axhline(U4_MEAN_FIELD, color="gray", ls=":", lw=0.8)
        ax.set_title(f"Ising on closed {{{p},{q}}} surfaces")
        ax.set_xlabel("T / J")
        ax.set_ylabel("U4")
        ax.legend(fontsize=7)
    fig.tight_layout()
    FIG.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIG, dpi=110)
    print(f"\nmean-field cumulant at T_c: {U4_MEAN_FIELD:.4f}; figure {FIG.relative_to(HERE.parent)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default=None, help="one tiling, e.g. 7,3")
    ap.add_argument("--analyse", action="store_true", help="only re-read the stored runs and redraw")
    args = ap.parse_args()
    only = tuple(int(x) for x in args.only.split(",")) if args.only else None
    if args.analyse:
        data = {}
        for p, q in PLAN:
            out = Path(str(OUT).format(p=p, q=q))
            if out.exists():
                data.update(json.loads(out.read_text()))
    else:
        data = measure(only)
    analyse(data)


if __name__ == "__main__":
    sys.exit(main())
