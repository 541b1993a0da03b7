"""The phase boundary of the topological Anderson insulator of QWZ on {8,3}: conductance ensembles and the SCBA.

QWZ on the l-ring {8,3} flake (chord frame), box disorder W, E = 0. Three parts, stored in one JSON
(``benchmarks/topology_tai_boundary.json``):

* the clean critical mass M_c: the ring-1 density of states at E = 0 with an absorbing outer ring
  (its peak in M, l = 5, 6, 7) and the clean two-terminal conductance against M (l = 4, 5, 6: the
  curves of growing l cross at M_c);
* the disorder ensembles: the two-terminal conductance (leads on two quarter arcs, coupling 2 t) of
  every (l, M, W, seed), run as Dask sweeps (task ``conductance``, one local worker); for each (l, M)
  the mean over seeds with its standard error, the median, the fraction within 0.05 of one e²/h,
  and the two boundaries of the plateau: where the mean conductance crosses 1/2 (lower: rising,
  upper: falling), linear between grid points, with errors by a bootstrap over the seeds (whole
  curves resampled: one seed's disorder pattern is the same at every W, scaled), and the same
  crossings of the median; their drift from l = 4 to 5 to 6 is the finite-size check;
* the self-consistent Born approximation on the graph (:mod:`hyperlattice.topology.anderson`):
  W_c(M) where the renormalised mass reaches M_c, on the l = 4, 5, 6 flakes, with M_c moved by its
  error.

Usage::

    python benchmarks/topology_tai_boundary.py --run /tmp/tai > benchmarks/topology_tai_boundary.json
    python benchmarks/topology_tai_boundary.py --from-json benchmarks/topology_tai_boundary.json --out fig.png

``--run DIR`` runs (or resumes) the sweeps in DIR and prints the JSON; ``--from-json`` prints the
Markdown tables of docs/topology.md and, with ``--out``, draws the figure.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
STORED = HERE / "topology_tai_boundary.json"

MASSES = (1.3, 1.5, 1.6, 1.7, 1.8)
DISORDER = (0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5, 5, 5.5, 6, 6.5, 7)
#: l = 5 and 6 only near the boundaries (0.4 and 5.6 CPU s per realization against 0.1 s at l = 4)
L5_DISORDER = (1.5, 2, 2.5, 3, 3.5, 4.5, 5, 5.5, 6)
L6_DISORDER = (2, 2.5, 5, 5.5)
#: the sweeps: (directory, rings, masses, W, seeds); each is one resumable Dask sweep
SWEEPS = (("l4", 4, MASSES, DISORDER, 48), ("l5a", 5, (1.5, 1.6), L5_DISORDER, 12),
          ("l5b", 5, (1.8,), L5_DISORDER, 8), ("l6a", 6, (1.6,), L6_DISORDER, 6))
#: the clean critical mass: fine grid of the E = 0 density of states and the clean conductance's grid
MC_DOS_MASSES = tuple(np.round(np.arange(1.39, 1.4401, 0.005), 4))
MC_G_MASSES = tuple(np.round(np.arange(1.36, 1.5001, 0.02), 3))
SCBA_MASSES = (1.45, 1.5, 1.6, 1.7, 1.8, 1.9, 2.0)
BOOTSTRAP = 1000


# ------------------------------------------------------------------------------------------------
# analysis (pure functions of the stored per-seed conductances)
# ------------------------------------------------------------------------------------------------

def _crossings(W: np.ndarray, y: np.ndarray, level: float = 0.5) -> tuple[float, float]:
    """(first rising, last falling) W where y crosses ``level``, linear between grid points; nan if none."""
    up = down = np.nan
    s = y - level
    for i in range(len(W) - 1):
        if s[i] < 0 <= s[i + 1] and np.isnan(up):
            up = W[i] + (W[i + 1] - W[i]) * (-s[i]) / (s[i + 1] - s[i])
        if s[i] >= 0 > s[i + 1]:
            down = W[i] + (W[i + 1] - W[i]) * s[i] / (s[i] - s[i + 1])
    return float(up), float(down)


def _boot(fn, curves: list, rng) -> tuple:
    """(fn of the mean curves, its bootstrap standard deviation, the fraction of resamples without a value)."""
    best = np.asarray(fn(*[c.mean(axis=0) for c in curves]), float)
    samples = []
    for _ in range(BOOTSTRAP):
        samples.append(fn(*[c[rng.integers(0, c.shape[0], c.shape[0])].mean(axis=0) for c in curves]))
    samples = np.asarray(samples, float)
    import warnings

    with warnings.catch_warnings():       # a boundary no resample has (nan) gives an empty nanstd
        warnings.simplefilter("ignore", RuntimeWarning)
        err = np.nanstd(samples, axis=0, ddof=1)
    missing = np.mean(np.isnan(samples), axis=0)
    return best, err, missing


def analyse(data: dict) -> dict:
    """Per (l, M): the W table and the two boundaries (mean conductance 1/2), with bootstrap errors."""
    rng = np.random.default_rng(20261128)
    out = {"points": []}
    for block in data["ensembles"]:
        W = np.array(block["W"])
        G = np.array(block["G"])                       # seeds x W
        (lo, hi), (elo, ehi), (mlo, mhi) = _boot(lambda g: _crossings(W, g), [G], rng)
        med_lo, med_hi = _crossings(W, np.median(G, axis=0))
        out["points"].append({
            "rings": block["rings"], "M": block["M"], "W": W.tolist(), "seeds": int(G.shape[0]),
            "mean": G.mean(axis=0).tolist(), "sem": (G.std(axis=0, ddof=1) / np.sqrt(G.shape[0])).tolist(),
            "median": np.median(G, axis=0).tolist(), "within": np.mean(np.abs(G - 1) < 0.05, axis=0).tolist(),
            "lower": float(lo), "lower_err": float(elo), "upper": float(hi), "upper_err": float(ehi),
            "lower_median": med_lo, "upper_median": med_hi})
    return out


# ------------------------------------------------------------------------------------------------
# the runs
# ------------------------------------------------------------------------------------------------

def critical_mass() -> dict:
    """The clean M_c: the peak of the ring-1 DOS at E = 0 (absorbing outer ring) and the clean conductance."""
    import hyperlattice as hl
    from hyperlattice.topology.anderson import _LocalGreen, _parts
    from hyperlattice.topology.transport import conductance

    dos = {}
    for rings in (5, 6, 7):
        green = _LocalGreen(hl.ring_lattice(8, 3, rings), 2.0)
        dos[rings] = [float(-_parts(green.blocks(0.0, M, 0j))[0].imag / np.pi) for M in MC_DOS_MASSES]
    peaks = {}
    for rings, d in dos.items():
        i = int(np.argmax(d))
        i = min(max(i, 1), len(d) - 2)
        x, y = np.array(MC_DOS_MASSES[i - 1:i + 2]), np.array(d[i - 1:i + 2])
        a, b, _ = np.polyfit(x, y, 2)
        peaks[rings] = float(-b / (2 * a))
    clean = {rings: [float(conductance(hl.ring_lattice(8, 3, rings), "qwz", M=M).conductance[0])
                     for M in MC_G_MASSES] for rings in (4, 5, 6)}
    cross = {}
    for l1, l2 in ((4, 5), (5, 6), (4, 6)):
        lo, hi = _crossings(np.array(MC_G_MASSES), np.array(clean[l2]) - np.array(clean[l1]), 0.0)
        cross[f"{l1}-{l2}"] = hi                        # larger flake conducts more below M_c, less above
    return {"dos_masses": list(MC_DOS_MASSES), "dos": {str(k): v for k, v in dos.items()},
            "dos_peak": {str(k): v for k, v in peaks.items()}, "clean_masses": list(MC_G_MASSES),
            "clean_conductance": {str(k): v for k, v in clean.items()},
            "clean_crossing": cross}


def _sweep(where: Path, rings: int, masses, disorder, seeds: int) -> list:
    """Run (or resume) the conductance sweep and return one block per mass (seeds x W)."""
    from hyperlattice.sweep import read_table, run_sweep

    # W as listed (1 and 1.0 are different task keys): the same keys as the command line's --grid W=0.5,1,...
    rep = run_sweep("conductance", {"rings": [rings], "M": list(masses), "W": list(disorder),
                                    "seed": list(range(seeds))}, where, scheduler="local", workers=1,
                    progress=False)
    if not rep.ok:
        raise SystemExit(f"{len(rep.failed)} tasks failed in {where}; rerun to retry them.")
    cols = read_table(where).columns
    blocks = []
    for M in masses:
        G = np.full((seeds, len(disorder)), np.nan)
        for m, w, s, g in zip(cols["M"], cols["W"], cols["seed"], cols["conductance"]):
            if m == M and s < seeds and float(w) in disorder:
                G[int(s), [float(x) for x in disorder].index(float(w))] = g
        blocks.append({"rings": rings, "M": M, "W": [float(w) for w in disorder], "G": np.round(G, 6).tolist()})
    return blocks


def scba_part(mc: float, dmc: float) -> dict:
    """The SCBA boundary on l = 4, 5, 6 at M_c (l = 5 also at M_c -+ its error) and the renormalised mass."""
    import hyperlattice as hl
    from hyperlattice.topology.anderson import scba, scba_boundary

    out = {"critical_mass": mc, "critical_mass_err": dmc, "masses": list(SCBA_MASSES), "boundary": {}}
    for rings in (4, 5, 6):
        lat = hl.ring_lattice(8, 3, rings)
        row = {}
        for tag, m in (("mid", mc), ("low", mc - dmc), ("high", mc + dmc)):
            if rings != 5 and tag != "mid":
                continue
            b = scba_boundary(lat, masses=SCBA_MASSES, critical_mass=m)
            row[tag] = b.critical_disorder.round(6).tolist()
            if tag == "mid":
                row["broadening"] = b.broadening.round(6).tolist()
        out["boundary"][str(rings)] = row
    lat = hl.ring_lattice(8, 3, 5)
    Ws = [0.0, 1, 2, 3, 4, 5, 6, 7]
    out["mass_vs_W"] = {"W": Ws}
    for M in (1.6, 1.8):
        s = scba(lat, M=M, disorder=Ws)
        out["mass_vs_W"][str(M)] = {"mass": s.mass.round(6).tolist(), "broadening": s.broadening.round(6).tolist()}
    return out


def _cached(where: Path, name: str, compute):
    """compute() stored as DIR/name.json (a rerun reads it: the parts run in separate processes)."""
    path = where / f"{name}.json"
    if path.exists():
        return json.loads(path.read_text())
    value = compute()
    where.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(value))
    return value


def run(where: Path, parts=("critical", "scba", "ensembles")) -> dict:
    import platform

    mc = _cached(where, "critical", critical_mass)
    est = list(mc["dos_peak"].values()) + [v for v in mc["clean_crossing"].values() if np.isfinite(v)]
    m_c = round(float(np.mean([min(est), max(est)])), 3)
    dm = round(float(max(est) - min(est)) / 2 + 0.005, 3)
    sc = _cached(where, "scba", lambda: scba_part(m_c, dm)) if "scba" in parts else None
    ensembles = []
    if "ensembles" in parts:
        for name, rings, masses, disorder, seeds in SWEEPS:
            ensembles += _sweep(where / name, rings, masses, disorder, seeds)
    return {"model": "qwz", "p": 8, "q": 3, "energy": 0.0, "coupling": 2.0, "arc": 0.25,
            "critical": mc, "ensembles": ensembles, "scba": sc,
            "command": "python benchmarks/topology_tai_boundary.py --run DIR", "machine": platform.machine()}


# ------------------------------------------------------------------------------------------------
# tables and figure
# ------------------------------------------------------------------------------------------------

def _pm(x, e, digits=2):
    if not np.isfinite(x):
        return "—"
    return f"{x:.{digits}f} ± {e:.{digits}f}" if np.isfinite(e) else f"{x:.{digits}f}"


def tables(data: dict) -> str:
    res = analyse(data)
    sc = data["scba"]
    mc = data["critical"]
    lines = ["| estimate of M_c | ℓ | M_c |", "|---|---|---|"]
    for rings, v in mc["dos_peak"].items():
        lines.append(f"| peak of the ring-1 DOS at E = 0 | {rings} | {v:.3f} |")
    for pair, v in mc["clean_crossing"].items():
        lines.append(f"| clean G of two flakes equal | {pair.replace('-', ', ')} | {v:.3f} |")
    lines.append(f"| taken | | {sc['critical_mass']:.3f} ± {sc['critical_mass_err']:.3f} |")
    lines += ["", "| M | ℓ | seeds | lower W_c (⟨G⟩ = ½) | upper W_c (⟨G⟩ = ½) | lower (median) | upper (median) |",
             "|---|---|---|---|---|---|---|"]
    for p in sorted(res["points"], key=lambda p: (p["M"], p["rings"])):
        lines.append(f"| {p['M']:g} | {p['rings']} | {p['seeds']} | {_pm(p['lower'], p['lower_err'])} | "
                     f"{_pm(p['upper'], p['upper_err'])} | {_pm(p['lower_median'], np.nan)} | "
                     f"{_pm(p['upper_median'], np.nan)} |")
    b = sc["boundary"]
    lines += ["", f"| M | SCBA W_c, ℓ = 4 | ℓ = 5 | ℓ = 6 | ℓ = 5, M_c ∓ {sc['critical_mass_err']:g} | Γ at W_c (ℓ = 6) |",
              "|---|---|---|---|---|---|"]
    for i, M in enumerate(sc["masses"]):
        lines.append(f"| {M:g} | {b['4']['mid'][i]:.2f} | {b['5']['mid'][i]:.2f} | {b['6']['mid'][i]:.2f} | "
                     f"{b['5']['low'][i]:.2f} – {b['5']['high'][i]:.2f} | {b['6']['broadening'][i]:.3f} |")
    return "\n".join(lines)


def figure(data: dict, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = analyse(data)
    sc = data["scba"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    colours = {1.3: "C0", 1.5: "C1", 1.6: "C2", 1.7: "C3", 1.8: "C4"}
    styles = {4: ":", 5: "--", 6: "-"}
    for p in res["points"]:
        # l = 6 has two W pairs only: points, no line across the gap between them
        ax.errorbar(p["W"], p["mean"], yerr=p["sem"], ls="none" if p["rings"] == 6 else styles[p["rings"]],
                    color=colours.get(p["M"], "k"), marker="s" if p["rings"] == 6 else "o",
                    ms=5 if p["rings"] == 6 else 2.5, lw=1, label=f"M = {p['M']:g}, ℓ = {p['rings']}")
    ax.axhline(1, color="0.6", lw=0.6)
    ax.set_xlabel("box disorder W (t)")
    ax.set_ylabel("mean conductance ⟨G⟩ (e²/h)")
    ax.legend(fontsize=6, ncol=2)
    ax = axes[1]
    for rings, mk, dy in ((4, "v", -0.012), (5, "s", 0.0), (6, "o", 0.012)):     # sizes apart in M
        pts = [p for p in res["points"] if p["rings"] == rings]
        ax.errorbar([p["lower"] for p in pts], [p["M"] + dy for p in pts], xerr=[p["lower_err"] for p in pts],
                    fmt=mk, color="C0", ms=4, label=f"⟨G⟩ = ½, ℓ = {rings} (blue: lower, red: upper)")
        ax.errorbar([p["upper"] for p in pts], [p["M"] + dy for p in pts], xerr=[p["upper_err"] for p in pts],
                    fmt=mk, color="C3", ms=4)
    b = sc["boundary"]
    M = np.array(sc["masses"])
    ax.plot(b["6"]["mid"], M, "-", color="C2", label=f"SCBA (ℓ = 6), M_c = {sc['critical_mass']:g}")
    ax.fill_betweenx(M, b["5"]["low"], b["5"]["high"], color="C2", alpha=0.2, lw=0)
    ax.axhline(sc["critical_mass"], color="0.5", lw=0.6, ls="--")
    ax.set_xlabel("box disorder W (t)")
    ax.set_ylabel("mass M (t)")
    ax.set_title("QWZ on {8,3}: the topological Anderson insulator", fontsize=9)
    ax.legend(fontsize=6, loc="lower center")
    fig.tight_layout()
    fig.savefig(out, dpi=130)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", metavar="DIR", help="run (or resume) the sweeps in DIR and print the JSON")
    ap.add_argument("--from-json", metavar="FILE", help="print the tables of a stored JSON")
    ap.add_argument("--out", metavar="PNG", help="with --from-json: draw the figure")
    ap.add_argument("--parts", default="critical,scba,ensembles",
                    help="with --run: the parts to run (critical, scba, ensembles; each cached in DIR)")
    args = ap.parse_args(argv)
    if args.run:
        print(json.dumps(run(Path(args.run), tuple(args.parts.split(",")))))
        return
    if not args.from_json:
        ap.error("give --run DIR or --from-json FILE")
    data = json.loads(Path(args.from_json).read_text())
    print(tables(data))
    if args.out:
        figure(data, Path(args.out))


if __name__ == "__main__":
    sys.exit(main())
