"""Ising on open {7,3} flakes (docs/spins.md): bulk against boundary, and the continuum propagator.

Part 1 (``--part bulk``): flakes of l = 4..8 rings over a grid of temperatures (Wolff): the
specific heat and susceptibility per site, and by ring the alignment <s_i . M/|M|> of the first
(bulk) and last (boundary) ring. Two transitions would show as two peaks of c(T) that sharpen
with l, or a window where the bulk aligns and the boundary does not.

Part 2 (``--part continuum``): above T_c, the correlation <s_c . s_j> from the first-ring sites c
of the l = 5 flake against the massive propagator of the disk,
G(d) = Q_nu(cosh 2d) / (2 pi) (hyperlattice.continuum.green.green_infinite_disk, lambda = -m^2),
with the amplitude and m^2 fitted to the correlation from d = 3 d0 to the edge of the flake; the
fit's chi^2 per degree of freedom there, and the deviation at shorter distances (the lattice scale);
then the same fit with the Dirichlet disk of the flake's area-matched radius (continuum_green).

Run: ``python benchmarks/spins_flakes.py`` (about 10 minutes); results in
benchmarks/spins_flakes.json, figures docs/img/spins_flakes.png and docs/img/spins_correlation.png.
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE / "spins_flakes.json"
IMG = HERE.parent / "docs" / "img"
#: the fit window starts here (in units of d0): below it the lattice's graph distance, not the
#: hyperbolic distance, orders the correlations (pairs at one hyperbolic distance but one or two
#: bonds apart differ by 20 standard errors at d = 2 d0)
FIT_FROM = 3.0


def bulk(data: dict) -> None:
    import hyperlattice as hl
    from hyperlattice.spins import classical_mc
    from hyperlattice.spins.classical import SpinWarning

    temps = np.round(np.arange(0.8, 2.41, 0.1), 3)
    for rings, sweeps in ((4, 10000), (5, 10000), (6, 6000), (7, 4000), (8, 2500)):
        lat = hl.ring_lattice(7, 3, rings)
        key = f"l{rings}"
        rows = data.setdefault("bulk", {}).setdefault(key, [])
        done = {r["T"] for r in rows}
        for T in temps:
            if float(T) in done:
                continue
            t0 = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", SpinWarning)
                r = classical_mc(lat, model="ising", T=float(T), sweeps=sweeps, seed=int(100 * T) + rings,
                                 measure_correlation=False, progress=False)
            rows.append({"T": float(T), "sites": r.sites, "c": r.c, "c_err": r.c_err, "chi": r.chi,
                         "chi_err": r.chi_err, "m2": r.m2, "m2_err": r.m2_err, "U4": r.U4, "U4_err": r.U4_err,
                         "bulk": float(r.ring_alignment[0]), "bulk_err": float(r.ring_alignment_err[0]),
                         "boundary": float(r.ring_alignment[-1]), "boundary_err": float(r.ring_alignment_err[-1]),
                         "e_bulk": float(r.ring_energy[0]), "e_boundary": float(r.ring_energy[-1])})
            OUT.write_text(json.dumps(data, indent=1))
            print(f"l = {rings} ({r.sites} sites) T = {T:.2f}: c = {r.c:.3f} +- {r.c_err:.3f}, chi/N = "
                  f"{r.chi / r.sites:.3f}, bulk {r.ring_alignment[0]:.3f}, boundary {r.ring_alignment[-1]:.3f} "
                  f"({time.process_time() - t0:.1f} s)", flush=True)


def continuum(data: dict) -> None:
    import hyperlattice as hl
    from hyperlattice import geometry
    from hyperlattice.spins import classical_mc
    from hyperlattice.spins.classical import SpinWarning

    lat = hl.ring_lattice(7, 3, 5)
    rows = data.setdefault("continuum", {})
    for T in (2.0, 2.4, 3.0):
        if f"{T:g}" in rows:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SpinWarning)
            r = classical_mc(lat, model="ising", T=T, sweeps=60000, seed=int(10 * T), correlation_from="centre",
                             progress=False)
        rows[f"{T:g}"] = {"d": r.corr_distance.tolist(), "C": r.corr.tolist(), "err": r.corr_err.tolist(),
                          "pairs": r.corr_pairs.tolist(), "d0": float(geometry.d0(7, 3)), "sites": r.sites}
        OUT.write_text(json.dumps(data, indent=1))
        print(f"correlation at T = {T}: {len(r.corr)} classes", flush=True)


def _propagator(d, lam):
    from hyperlattice.continuum.green import green_infinite_disk

    return np.real(green_infinite_disk(0.0, np.tanh(np.asarray(d, dtype=float)), lam))


def fit_continuum(entry: dict) -> dict:
    from scipy.optimize import minimize_scalar

    d, C, err, d0 = np.array(entry["d"]), np.array(entry["C"]), np.array(entry["err"]), entry["d0"]
    inner = (d >= FIT_FROM * d0) & np.isfinite(d) & (err > 0)
    w = 1.0 / err[inner] ** 2

    def chi2(m2):
        g = _propagator(d[inner], -m2)
        a = float(np.sum(w * g * C[inner]) / np.sum(w * g * g))
        return float(np.sum(w * (C[inner] - a * g) ** 2)), a

    res = minimize_scalar(lambda m2: chi2(m2)[0], bounds=(-0.99, 200.0), method="bounded")
    m2 = float(res.x)
    c2, a = chi2(m2)
    dof = int(inner.sum()) - 2
    # the error of m^2: where chi^2 rises by 1, scaled by chi^2/dof when the fit is worse than the
    # errors allow (the error bars then also carry the model's misfit)
    rise = max(1.0, c2 / max(dof, 1))
    lo = minimize_scalar(lambda x: abs(chi2(x)[0] - c2 - rise), bounds=(-0.99, m2), method="bounded").x
    hi = minimize_scalar(lambda x: abs(chi2(x)[0] - c2 - rise), bounds=(m2, 400.0), method="bounded").x
    nu = -0.5 + 0.5 * math.sqrt(1.0 + m2)            # lambda/4 = -nu(nu+1), lambda = -m^2
    outer = (d < FIT_FROM * d0) & (err > 0)
    dev = (C[outer] - a * _propagator(d[outer], -m2)) / err[outer]
    return {"m2": m2, "m2_lo": float(lo), "m2_hi": float(hi), "amplitude": a, "chi2_dof": c2 / max(dof, 1), "dof": dof,
            "xi_over_d0": 1.0 / (2.0 * (nu + 1.0)) / d0, "outer_max_sigma": float(np.max(np.abs(dev))) if dev.size else math.nan,
            "outer_mean_sigma": float(np.mean(dev)) if dev.size else math.nan}


def _centre_pairs(entry: dict):
    """The flake's centre pairs (i < j, one of them in ring 1) grouped as the measured classes."""
    import hyperlattice as hl
    from hyperlattice import geometry

    lat = hl.ring_lattice(7, 3, 5)
    z = np.asarray(lat.z)
    n = z.size
    c = np.flatnonzero(np.asarray(lat.ring) == 1)
    i, j = np.triu_indices(n, 1)
    use = np.isin(i, c) | np.isin(j, c)
    i, j = i[use], j[use]
    d = np.asarray(geometry.distance(z[i], z[j], check=False), dtype=float)
    cls = np.rint(d / (entry["d0"] / 4)).astype(int)
    labels = np.unique(cls)                 # the measured classes, in order
    return z[i], z[j], np.searchsorted(labels, cls), labels.size


def fit_dirichlet(entry: dict) -> dict:
    """As :func:`fit_continuum`, with the Dirichlet disk of the flake's area-matched radius
    (hyperlattice.dictionary.disk_radius) in place of the infinite disk: each class's prediction
    is the mean of continuum_green over its pairs."""
    from scipy.optimize import minimize_scalar

    from hyperlattice.continuum.green import continuum_green
    from hyperlattice.dictionary import disk_radius

    zi, zj, k, ncls = _centre_pairs(entry)
    L = float(disk_radius(entry["sites"], 7, 3))
    d, C, err, d0 = np.array(entry["d"]), np.array(entry["C"]), np.array(entry["err"]), entry["d0"]
    if ncls != d.size:
        return {}
    inner = (d >= FIT_FROM * d0) & np.isfinite(d) & (err > 0)
    w = 1.0 / err[inner] ** 2

    def pred(m2):
        g = np.real(continuum_green(zi, zj, -m2, L, extend=True))
        return np.bincount(k, weights=g, minlength=ncls) / np.bincount(k, minlength=ncls)

    def chi2(m2):
        g = pred(m2)[inner]
        a = float(np.sum(w * g * C[inner]) / np.sum(w * g * g))
        return float(np.sum(w * (C[inner] - a * g) ** 2)), a

    res = minimize_scalar(lambda m2: chi2(m2)[0], bounds=(-0.99, 60.0), method="bounded",
                          options={"xatol": 1e-3})
    c2, a = chi2(float(res.x))
    far = (d > 7.0 * d0) & np.isfinite(d) & (err > 0)
    dev = (C[far] - a * pred(float(res.x))[far]) / err[far]
    return {"m2": float(res.x), "chi2_dof": c2 / max(int(inner.sum()) - 2, 1), "radius": L,
            "far_mean_sigma": float(np.mean(dev)) if dev.size else math.nan}


def report(data: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if "bulk" in data:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        print("\nflakes: peak of c(T) and the bulk/boundary alignment at T = 1.2 and 1.6")
        for key, rows in sorted(data["bulk"].items()):
            rows = sorted(rows, key=lambda r: r["T"])
            T = np.array([r["T"] for r in rows])
            c = np.array([r["c"] for r in rows])
            axes[0].errorbar(T, c, [r["c_err"] for r in rows], marker="o", ms=3, label=f"{key} ({rows[0]['sites']} sites)")
            axes[1].errorbar(T, [r["bulk"] for r in rows], [r["bulk_err"] for r in rows], marker="o", ms=3,
                             label=f"{key} ring 1")
            axes[1].errorbar(T, [r["boundary"] for r in rows], [r["boundary_err"] for r in rows], marker="s", ms=3,
                             ls="--", label=f"{key} outer ring")
            at = {r["T"]: r for r in rows}
            print(f"  {key} ({rows[0]['sites']} sites): c peaks at T = {T[np.argmax(c)]:.1f} (c = {c.max():.3f}); "
                  + "; ".join(f"T = {t}: bulk {at[t]['bulk']:.3f}, boundary {at[t]['boundary']:.3f}"
                              for t in (1.2, 1.6) if t in at))
        axes[0].axvline(1.0 / math.atanh(0.5), color="k", ls=":", lw=0.8)
        axes[0].set_xlabel("T / J")
        axes[0].set_ylabel("c per site")
        axes[0].legend(fontsize=7)
        axes[1].set_xlabel("T / J")
        axes[1].set_ylabel("<s_i . M/|M|> by ring")
        axes[1].legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(IMG / "spins_flakes.png", dpi=110)
    if "continuum" in data:
        fig, ax = plt.subplots(figsize=(6, 4))
        print("\ncontinuum: <s_c . s_j> from the centre of the l = 5 flake against A Q_nu(cosh 2d)/(2 pi), "
              "fitted from d = 3 d0 to the edge")
        for k, (Tk, entry) in enumerate(sorted(data["continuum"].items(), key=lambda kv: float(kv[0]))):
            f = fit_continuum(entry)
            d, C, err = np.array(entry["d"]), np.array(entry["C"]), np.array(entry["err"])
            ok = np.isfinite(d)
            ax.errorbar(d[ok] / entry["d0"], C[ok], err[ok], ls="none", marker="o", ms=3, color=f"C{k}", label=f"T = {Tk}")
            x = np.linspace(0.9 * entry["d0"], d[ok].max(), 200)
            ax.plot(x / entry["d0"], f["amplitude"] * _propagator(x, -f["m2"]), color=f"C{k}", lw=1)
            g = fit_dirichlet(entry)
            if g:
                print(f"  T = {Tk}: Dirichlet disk of radius L = {g['radius']:.4f}: m^2 = {g['m2']:.2f}, chi^2/dof = "
                      f"{g['chi2_dof']:.2f}; beyond 7 d0 the data sit {g['far_mean_sigma']:+.1f} sigma from it on average")
            print(f"  T = {Tk}: m^2 = {f['m2']:.2f} (+{f['m2_hi'] - f['m2']:.2f} / -{f['m2'] - f['m2_lo']:.2f}), "
                  f"xi = {f['xi_over_d0']:.2f} d0, chi^2/dof = {f['chi2_dof']:.2f} ({f['dof']} dof); below 3 d0 the "
                  f"data sit {f['outer_mean_sigma']:+.1f} sigma from the fit on average (at most "
                  f"{f['outer_max_sigma']:.1f})")
        ax.set_yscale("log")
        ax.set_ylim(1e-4, 1)
        ax.set_xlabel("d / d0")
        ax.set_ylabel("<s_c . s_j>")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(IMG / "spins_correlation.png", dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=("bulk", "continuum", "both"), default="both")
    ap.add_argument("--analyse", action="store_true", help="only redraw from benchmarks/spins_flakes.json")
    args = ap.parse_args()
    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    if not args.analyse:
        if args.part in ("continuum", "both"):
            continuum(data)
        if args.part in ("bulk", "both"):
            bulk(data)
    report(data)


if __name__ == "__main__":
    main()
