"""Quantum Monte Carlo of the Bose–Hubbard model: hyperlattice's SSE against ALPS (issue 27, Performance).

For each point (graph, U, mu, beta, nmax) the same model is run by

* ``hyperlattice.bosons.qmc`` (SSE with directed loops, numba; one chain, in this process),
* ALPS ``dirloop_sse`` (SSE with directed loops) and ALPS ``worm`` (continuous-time worm), each in
  a subprocess of its own virtualenv (:mod:`_alps`, created on first use),

with the same seed (``--sweeps``, ``--alps-sweeps`` and ``--worm-sweeps`` set each code's run
length: a "sweep" is a different amount of work in each code). The figure of merit is the
statistical efficiency

    efficiency = 1 / (sigma_E^2 x CPU seconds),

sigma_E the error bar of the total energy <H> each code reports (hyperlattice: binning analysis;
ALPS: its own binning analysis), CPU seconds the user + system time of the chain (hyperlattice:
``time.process_time`` around the call, after a warm-up that compiles the kernels; ALPS: the
application's own seconds from ``RUSAGE_CHILDREN``; both include thermalisation). The efficiency
does not depend on how long a code runs (sigma^2 falls as 1/time), so codes whose "sweeps" do
different amounts of work are compared fairly. The table gives both efficiencies, their ratio
(target: >= 2 against dirloop_sse on every point) and the agreement z = (E_hl - E_alps) /
sqrt(sigma_hl^2 + sigma_alps^2) for the energy and the density (|z| < 3 expected).

``--validate`` first checks both codes against exact thermal averages (full diagonalisation,
:func:`hyperlattice.bosons.exact_thermal`) on the heptagon: the conventions (total energy with
-mu N, density per site, compressibility per site) are the same.

``--scale`` runs hyperlattice alone on the {7,3} flake of l = 8 rings (15,435 sites, the first
flake above 10^4 sites) at beta t = 20, and reports time, peak memory and the string length.

Usage::

    python benchmarks/bench_qmc.py                  # the table (minutes: ALPS worm is slow at low T)
    python benchmarks/bench_qmc.py --validate       # the exact-thermal check of both codes first
    python benchmarks/bench_qmc.py --quick          # fewer sweeps, no worm (a smoke run)
    python benchmarks/bench_qmc.py --scale          # the 10^4-site run only
    python benchmarks/bench_qmc.py --profile        # where hyperlattice's time goes on one point
    python benchmarks/bench_qmc.py --points 6 --repeat 4 --no-worm   # one point, 4 seeds per code, ratio +- error

Numbers measured on the project's shared 2-core machine are quoted in docs/qmc.md.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _alps import run_alps  # noqa: E402
from _machine import machine, peak_rss_mb  # noqa: E402

#: (label, system, U, mu, beta, nmax): Mott points deep in the n = 1 lobe (t/U = 1/30, mu/U = 1/2,
#: mean-field tip of {7,3} at t/U = 0.058), superfluid points at t/U = 1/6 with n about 1.3
POINTS = (
    ("l=3 Mott b=2", ("flake", 3), 30.0, 15.0, 2.0, 3),
    ("l=3 Mott b=8", ("flake", 3), 30.0, 15.0, 8.0, 3),
    ("l=3 SF b=2", ("flake", 3), 6.0, 3.0, 2.0, 3),
    ("l=3 SF b=8", ("flake", 3), 6.0, 3.0, 8.0, 3),
    ("l=4 Mott b=4", ("flake", 4), 30.0, 15.0, 4.0, 3),
    ("l=4 SF b=4", ("flake", 4), 6.0, 3.0, 4.0, 3),
    ("klein Mott b=4", ("cluster", "klein"), 30.0, 15.0, 4.0, 3),
    ("klein SF b=4", ("cluster", "klein"), 6.0, 3.0, 4.0, 3),
)


def _system(spec):
    import hyperlattice as hl

    kind, what = spec
    if kind == "flake":
        return hl.ring_lattice(7, 3, what)
    from hyperlattice.graph.clusters import pbc_cluster

    return pbc_cluster(7, 3, what)


def _hl(system, *, U, mu, beta, nmax, sweeps, thermalization, seed) -> dict:
    from hyperlattice.bosons import QMCWarning, qmc

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", QMCWarning)
        c0 = time.process_time()
        # measure_green=False: the ALPS runs measure no Green function either (their default)
        r = qmc(system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=sweeps, thermalization=thermalization,
                seed=seed, measure_green=False, progress=False)
        cpu = time.process_time() - c0
    return {"energy": r.energy, "energy_err": r.energy_err, "density": r.density, "density_err": r.density_err,
            "compressibility": r.compressibility, "compressibility_err": r.compressibility_err,
            "cpu_seconds": cpu, "converged": r.converged and not caught, "tau": r.tau_int.get("energy", math.nan),
            "result": r}


def _eff(r: dict) -> float:
    return 1.0 / (r["energy_err"] ** 2 * r["cpu_seconds"])


def _z(a: dict, b: dict, key: str) -> float:
    s = math.hypot(a[key + "_err"], b[key + "_err"])
    return (a[key] - b[key]) / s if s > 0 else (0.0 if a[key] == b[key] else math.inf)


def _warm_up() -> None:
    import hyperlattice as hl
    from hyperlattice.bosons import qmc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=3, sweeps=200, seed=0, progress=False)


def validate(work: Path, sweeps: int) -> bool:
    """Both codes against exact thermal averages on the heptagon (z-scores of E, n, kappa)."""
    import hyperlattice as hl
    from hyperlattice.bosons import exact_thermal

    lat = hl.ring_lattice(7, 3, 1)
    ok = True
    print("\nvalidation against exact thermal averages, {7,3} heptagon (7 sites)")
    print(f"{'U':>5} {'mu':>5} {'beta':>5} {'nmax':>4}  {'code':<12} {'E':>10} {'z_E':>6} {'n':>8} {'z_n':>6} "
          f"{'kappa':>8} {'z_k':>6}")
    for U, mu, beta, nmax in ((4.0, 1.5, 2.0, 3), (10.0, 4.0, 4.0, 2), (2.0, 0.5, 1.0, 2)):
        ex = exact_thermal(lat, U=U, mu=mu, beta=beta, nmax=nmax)
        print(f"{U:5g} {mu:5g} {beta:5g} {nmax:4d}  {'exact':<12} {ex.energy:10.4f} {'':>6} "
              f"{ex.density:8.5f} {'':>6} {ex.compressibility:8.5f}")
        runs = {"hyperlattice": _hl(lat, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=sweeps,
                                    thermalization=sweeps // 5, seed=3)}
        for app in ("dirloop_sse", "worm"):
            runs[app] = run_alps(app, lat, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=sweeps,
                                 thermalization=sweeps // 5, seed=3, workdir=work / f"val-{app}-{U:g}-{nmax}")
        for code, r in runs.items():
            zs = []
            for k in ("energy", "density", "compressibility"):
                err = r[k + "_err"]
                zs.append((r[k] - getattr(ex, k)) / err if err > 0 else (0.0 if abs(r[k] - getattr(ex, k)) < 1e-3 else math.inf))
            print(f"{'':22}  {code:<12} {r['energy']:10.4f} {zs[0]:6.2f} {r['density']:8.5f} {zs[1]:6.2f} "
                  f"{r['compressibility']:8.5f} {zs[2]:6.2f}")
            # ALPS worm reports no fluctuation of N deep in a Mott phase (error 0): its z is skipped
            ok &= all(abs(z) < 4 or not math.isfinite(z) and code == "worm" for z in zs)
    print("validation:", "all within 4 sigma" if ok else "SOME VALUE IS MORE THAN 4 SIGMA OFF")
    return ok


def _pool(runs: list[dict]) -> dict:
    """K independent runs of one code on one point as one: merged means (equal weights, the runs have the
    same length; :func:`hyperlattice.mcstats.combine_independent`), total CPU seconds, and the per-seed
    efficiencies (their spread gives the error of the efficiency)."""
    from hyperlattice.mcstats import combine_independent

    if len(runs) == 1:
        out = dict(runs[0])
    else:
        out = {"cpu_seconds": sum(r["cpu_seconds"] for r in runs), "converged": all(r["converged"] for r in runs),
               "result": runs[0].get("result")}
        ones = [1.0] * len(runs)
        for k in ("energy", "density", "compressibility"):
            out[k], out[k + "_err"] = combine_independent([r[k] for r in runs], [r[k + "_err"] for r in runs], ones)
    out["effs"] = [_eff(r) for r in runs]
    out["runs"] = runs
    return out


def _ratio(a: dict, b: dict) -> tuple[float, float]:
    """Efficiency ratio of two pooled codes and its error: the delta method on the standard errors of the
    mean of each code's K per-seed efficiencies (NaN for K = 1: one run has no spread)."""
    ratio = _eff(a) / _eff(b)
    k = len(a["effs"])
    if k < 2 or len(b["effs"]) < 2:
        return ratio, math.nan
    rel2 = 0.0
    for c in (a, b):
        e = np.asarray(c["effs"])
        rel2 += float(np.var(e, ddof=1)) / (e.size * float(np.mean(e)) ** 2)
    return ratio, ratio * math.sqrt(rel2)


def table(points, work: Path, *, sweeps: int, alps_sweeps: int, worm_sweeps: int, worm: bool,
          seed: int, repeat: int = 1) -> list[dict]:
    """The benchmark table; with ``repeat`` K > 1, K independent seeds (seed, seed + 1, ...) per code and
    point, pooled by :func:`_pool` (one efficiency per code from the merged error and the total CPU s)."""
    rows = []
    for label, spec, U, mu, beta, nmax in points:
        system = _system(spec)
        tag = label.replace(" ", "_").replace("=", "")
        hls, dls, wms = [], [], []
        for rep in range(repeat):
            sd = seed + rep
            sfx = f"-s{sd}" if repeat > 1 else ""
            hls.append(_hl(system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=sweeps,
                           thermalization=max(200, sweeps // 5), seed=sd))
            dls.append(run_alps("dirloop_sse", system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=alps_sweeps,
                                thermalization=max(200, alps_sweeps // 5), seed=sd,
                                workdir=work / f"{tag}-dirloop{sfx}"))
            if worm:
                wms.append(run_alps("worm", system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=worm_sweeps,
                                    thermalization=max(200, worm_sweeps // 5), seed=sd,
                                    workdir=work / f"{tag}-worm{sfx}"))
        hl_r = _pool(hls)
        row = {"label": label, "sites": hls[0]["result"].sites, "U": U, "mu": mu, "beta": beta, "hl": hl_r,
               "dl": _pool(dls), "worm": _pool(wms) if worm else None, "repeat": repeat}
        rows.append(row)
        _print_row(row, header=len(rows) == 1)
    return rows


def _fmt_ratio(r: float, e: float) -> str:
    return f"{r:.2f}" if not math.isfinite(e) else f"{r:.2f} ± {e:.2f}"


def _print_row(row, header: bool) -> None:
    if header:
        if row["repeat"] > 1:
            print(f"\n{row['repeat']} seeds per code and point, pooled: merged E, total CPU s; "
                  "ratio error from the spread of the per-seed efficiencies")
        print("\n| point | sites | E (hyperlattice) | E (dirloop_sse) | z_E | z_n | CPU s hl / dl / worm | "
              "eff hl | eff dl | eff worm | hl/dl | hl/worm |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    h, d, w = row["hl"], row["dl"], row["worm"]
    eh, ed = _eff(h), _eff(d)
    ew = _eff(w) if w is not None else math.nan
    cpu = f"{h['cpu_seconds']:.0f} / {d['cpu_seconds']:.0f} / " + (f"{w['cpu_seconds']:.0f}" if w else "-")
    zn = _z(h, d, "density")
    rw = _fmt_ratio(*_ratio(h, w)) if w is not None else "nan"
    print(f"| {row['label']} | {row['sites']} | {h['energy']:.3f} ± {h['energy_err']:.3f} | "
          f"{d['energy']:.3f} ± {d['energy_err']:.3f} | {_z(h, d, 'energy'):+.1f} | {zn:+.1f} | {cpu} | "
          f"{eh:.3g} | {ed:.3g} | {ew:.3g} | {_fmt_ratio(*_ratio(h, d))} | {rw} |", flush=True)
    if row["repeat"] > 1:
        print("  per-seed efficiencies: hl " + " ".join(f"{e:.3g}" for e in h["effs"]) + "; dl "
              + " ".join(f"{e:.3g}" for e in d["effs"])
              + ("; worm " + " ".join(f"{e:.3g}" for e in w["effs"]) if w is not None else ""))
    if w is not None:
        zw = _z(h, w, "energy")
        if abs(zw) > 3:
            print(f"  note: worm energy {w['energy']:.3f} ± {w['energy_err']:.3f} (z = {zw:+.1f} against hyperlattice)")
    for r in h["runs"]:
        if not r["converged"]:
            print("  note: hyperlattice's binning flagged a chain as not converged: " + " ".join(r["result"].notes))


def scale(sweeps: int, therm: int, seed: int, checkpoint: str | None = None) -> None:
    import hyperlattice as hl
    from hyperlattice.bosons import QMCWarning, qmc

    lat = hl.ring_lattice(7, 3, 8)
    U, mu, beta, nmax = 6.0, 3.0, 20.0, 3
    print(f"\nscale: {{7,3}} flake l = 8, {lat.sites:,} sites, U = {U:g}, mu = {mu:g}, beta t = {beta:g}, "
          f"nmax = {nmax}, {sweeps} sweeps after {therm} thermalisation sweeps")
    rss0 = peak_rss_mb()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", QMCWarning)
        c0, w0 = time.process_time(), time.perf_counter()
        r = qmc(lat, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=sweeps, thermalization=therm, seed=seed,
                progress=True, checkpoint=checkpoint)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    print(f"  E = {r.energy:.2f} ± {r.energy_err:.2f}, n = {r.density:.5f} ± {r.density_err:.5f}, "
          f"kappa = {r.compressibility:.4f} ± {r.compressibility_err:.4f}, tau_E = {r.tau_int.get('energy'):.1f}")
    print(f"  mean string {r.mean_operators:,.0f} operators (length {r.string_length:,}), "
          f"{r.loops_per_sweep} loops per sweep")
    print(f"  {cpu:.0f} CPU s ({cpu / (sweeps + therm):.2f} s per sweep), {wall:.0f} s wall, peak RSS "
          f"{peak_rss_mb():.0f} MB (before: {rss0:.0f} MB)")
    for w in caught:
        print(f"  warning: {w.message}")


def profile(sweeps: int, seed: int) -> None:
    """Split hyperlattice's time on the l = 3 superfluid point: kernels against the Python around them."""
    import cProfile
    import pstats

    system = _system(("flake", 3))
    pr = cProfile.Profile()
    pr.enable()
    _hl(system, U=6.0, mu=3.0, beta=8.0, nmax=3, sweeps=sweeps, thermalization=sweeps // 5, seed=seed)
    pr.disable()
    pstats.Stats(pr).sort_stats("tottime").print_stats(12)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sweeps", type=int, default=5000, help="measurement sweeps of hyperlattice (default 5000)")
    ap.add_argument("--alps-sweeps", type=int, default=None, help="sweeps of ALPS dirloop_sse (default: --sweeps)")
    ap.add_argument("--worm-sweeps", type=int, default=None, help="sweeps of ALPS worm (default: --sweeps)")
    ap.add_argument("--seed", type=int, default=17)
    ap.add_argument("--repeat", type=int, default=1,
                    help="independent seeds per code and point (seed, seed + 1, ...), pooled; K > 1 gives the "
                         "efficiency ratio an error bar from the spread of the per-seed efficiencies")
    ap.add_argument("--quick", action="store_true", help="2000 sweeps, no worm, the l = 3 points only")
    ap.add_argument("--no-worm", action="store_true", help="skip ALPS worm")
    ap.add_argument("--points", default=None, help="comma-separated point numbers (1-based) of the table")
    ap.add_argument("--validate", action="store_true", help="check both codes against exact thermal averages first")
    ap.add_argument("--scale", action="store_true", help="only the 10^4-site run")
    ap.add_argument("--scale-sweeps", type=int, default=20, help="measurement sweeps of the scale run")
    ap.add_argument("--scale-checkpoint", default=None, metavar="DIR",
                    help="checkpoint directory of the scale run: a rerun resumes there (--scale-sweeps may grow); "
                         "the CPU and wall times printed are this process's only")
    ap.add_argument("--scale-therm", type=int, default=60,
                    help="thermalisation sweeps of the scale run (the string grows by 4/3 per sweep from 100 "
                         "operators: about 40 sweeps to reach the ~10^6 of this point)")
    ap.add_argument("--profile", action="store_true", help="only profile hyperlattice on one point")
    ap.add_argument("--workdir", default=None, help="keep ALPS's files here (default: a temporary directory)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    print(machine())
    _warm_up()
    if args.scale:
        scale(args.scale_sweeps, args.scale_therm, args.seed, args.scale_checkpoint)
        return 0
    if args.profile:
        profile(args.sweeps, args.seed)
        return 0
    points = POINTS
    sweeps, worm = args.sweeps, not args.no_worm
    if args.quick:
        points, sweeps, worm = POINTS[:4], 2000, False
    if args.points:
        points = [POINTS[int(i) - 1] for i in args.points.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(args.workdir or tmp)
        ok = True
        if args.validate:
            ok = validate(work, 20000 if not args.quick else 4000)
        rows = table(points, work, sweeps=sweeps, alps_sweeps=args.alps_sweeps or sweeps,
                     worm_sweeps=args.worm_sweeps or args.alps_sweeps or sweeps, worm=worm, seed=args.seed, repeat=args.repeat)
    ratios = [_ratio(r["hl"], r["dl"]) for r in rows]
    worst = min(ratios)
    print(f"\nefficiency ratio against dirloop_sse: min {_fmt_ratio(*worst)}, max {_fmt_ratio(*max(ratios))} "
          f"(target >= 2 on every point: {'met' if worst[0] >= 2 else 'NOT met'}"
          + (f"; {sum(r - e < 2 for r, e in ratios)} point(s) within one error of 2 or below)" if args.repeat > 1
             else ")"))
    if worm:
        rw = [_ratio(r["hl"], r["worm"]) for r in rows]
        print(f"efficiency ratio against worm: min {_fmt_ratio(*min(rw))}, max {_fmt_ratio(*max(rw))}")
    zmax = max(max(abs(_z(r["hl"], r["dl"], "energy")), abs(_z(r["hl"], r["dl"], "density"))) for r in rows)
    print(f"largest |z| against dirloop_sse (energy, density): {zmax:.1f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
