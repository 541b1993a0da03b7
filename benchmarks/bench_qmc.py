"""Quantum Monte Carlo of the Bose–Hubbard model: hyperlattice's SSE against ALPS.

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

Thermalisation is counted in the CPU seconds, and each code gets the thermalisation it needs, by
one rule for both (``--therm-scan``): K chains per code started afresh, each code's energy series
after its shortest thermalisation (hyperlattice sweep by sweep; dirloop_sse from its stored bins)
in blocks of 20 sweeps; the plateau is the seeds' mean over the second half, and a chain counts
as thermalised after the last first-half block whose seed mean lies more than 3 errors from the
plateau. dirloop_sse's shortest thermalisation is the fewest sweeps with which it runs at all
(fewer stop it with "nnonzero reached the maximum value": its cutoff grows only while it
thermalises; 150 on the 847- and 2,240-site flakes, 60 is too few even on 112 sites). With
``--repeat`` K > 1 the table also applies the rule to dirloop_sse's own series of its runs.
``--json PATH`` stores the table's numbers per seed (benchmarks/bench_qmc.json holds the runs
quoted in docs/qmc.md).

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
    python benchmarks/bench_qmc.py --phases 6 --therm 60 --sweeps 20   # CPU s sweep by sweep, 2,240 sites
    python benchmarks/bench_qmc.py --points 6 --repeat 4 --no-worm   # one point, 4 seeds per code, ratio +- error
    python benchmarks/bench_qmc.py --points 9,10 --repeat 4 --sweeps 300 --therm 100 --no-worm
                                                    # 847 and 2,240 sites; efficiency also from the seeds' scatter
    python benchmarks/bench_qmc.py --therm-scan --points 9 --repeat 4 --sweeps 400 --therm 10 --alps-therm 150
                                                    # the thermalisation each code needs (the rule above)

Numbers measured on the project's shared 2-core machine are quoted in docs/qmc.md.
"""

from __future__ import annotations

import argparse
import math
import os
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
    # the sizes docs/qmc.md advertises: the l = 5 flake (847 sites) and the l = 6 flake (2,240 sites)
    ("l=5 SF b=8", ("flake", 5), 6.0, 3.0, 8.0, 3),
    ("l=6 SF b=8", ("flake", 6), 6.0, 3.0, 8.0, 3),
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


def _load() -> str:
    """The machine's load averages (1, 5, 15 min), printed with every row."""
    try:
        return "load " + " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "load unknown"


def _scatter_eff(c: dict) -> tuple[float, float]:
    """Efficiency 1/(s^2 x CPU s) of one run from the K seeds' scatter: s^2 the sample variance of the
    K energies (each run's own error bar unused), CPU s the mean per run (thermalisation included);
    its relative error sqrt(2/(K-1)) (the chi^2 of s^2, Gaussian means) with the CPU spread added."""
    runs = c["runs"]
    k = len(runs)
    if k < 2:
        return math.nan, math.nan
    e = np.array([r["energy"] for r in runs])
    cpu = np.array([r["cpu_seconds"] for r in runs])
    eff = 1.0 / (float(np.var(e, ddof=1)) * float(cpu.mean()))
    rel2 = 2.0 / (k - 1) + float(np.var(cpu, ddof=1)) / (k * float(cpu.mean()) ** 2)
    return eff, eff * math.sqrt(rel2)


def _calibration(c: dict) -> float:
    """Root mean square of the runs' own energy errors over the seeds' scatter (1 when calibrated)."""
    runs = c["runs"]
    if len(runs) < 2:
        return math.nan
    e = np.array([r["energy"] for r in runs])
    return float(np.sqrt(np.mean([r["energy_err"] ** 2 for r in runs])) / np.std(e, ddof=1))


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
          seed: int, repeat: int = 1, therm: int | None = None, alps_therm: int | None = None) -> list[dict]:
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
                           thermalization=therm if therm is not None else max(200, sweeps // 5), seed=sd))
            dls.append(run_alps("dirloop_sse", system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=alps_sweeps,
                                thermalization=(alps_therm if alps_therm is not None else therm if therm is not None
                                                else max(200, alps_sweeps // 5)), seed=sd,
                                workdir=work / f"{tag}-dirloop{sfx}"))
            if worm:
                wms.append(run_alps("worm", system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=worm_sweeps,
                                    thermalization=max(200, worm_sweeps // 5), seed=sd,
                                    workdir=work / f"{tag}-worm{sfx}"))
        hl_r = _pool(hls)
        if len(dls) > 1 and all(r.get("energy_bins") for r in dls):
            # the thermalisation rule on dirloop_sse's own measured series of this table's runs
            ser = [np.repeat(np.asarray(r["energy_bins"]), int(r["energy_bin_size"])) for r in dls]
            n = min(len(x) for x in ser)
            add, z = _thermalised_after(np.array([x[:n] for x in ser]), 20)
            print(f"  {label}: dirloop_sse's own series after its thermalisation, blocks of 20 sweeps, z against "
                  "the plateau " + " ".join(f"{v:+.1f}" for v in z) + f" (rule: {add} sweeps more)")
        row = {"label": label, "sites": hls[0]["result"].sites, "U": U, "mu": mu, "beta": beta, "hl": hl_r,
               "dl": _pool(dls), "worm": _pool(wms) if worm else None, "repeat": repeat,
               "therm": (therm if therm is not None else max(200, sweeps // 5),
                         alps_therm if alps_therm is not None else therm if therm is not None
                         else max(200, alps_sweeps // 5)),
               "sweeps": (sweeps, alps_sweeps), "load": _load()}
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
    th = [r["tau"] for r in h["runs"]]
    td = [r.get("energy_tau", math.nan) for r in d["runs"]]
    ew = _eff(w) if w is not None else math.nan
    cpu = f"{h['cpu_seconds']:.0f} / {d['cpu_seconds']:.0f} / " + (f"{w['cpu_seconds']:.0f}" if w else "-")
    zn = _z(h, d, "density")
    rw = _fmt_ratio(*_ratio(h, w)) if w is not None else "nan"
    print(f"| {row['label']} | {row['sites']} | {h['energy']:.3f} ± {h['energy_err']:.3f} | "
          f"{d['energy']:.3f} ± {d['energy_err']:.3f} | {_z(h, d, 'energy'):+.1f} | {zn:+.1f} | {cpu} | "
          f"{eh:.3g} | {ed:.3g} | {ew:.3g} | {_fmt_ratio(*_ratio(h, d))} | {rw} |", flush=True)
    print(f"  tau_int(E) per seed, sweeps: hl " + " ".join(f"{t:.1f}" for t in th) + "; dl "
          + " ".join(f"{t:.1f}" for t in td) + f"; thermalisation sweeps hl {row['therm'][0]}, dl {row['therm'][1]}"
          f" (counted in the CPU s)  ({_load()})")
    if row["repeat"] > 1:
        sh, sd_ = _scatter_eff(h), _scatter_eff(d)
        rs = sh[0] / sd_[0]
        rse = rs * math.hypot(sh[1] / sh[0], sd_[1] / sd_[0])
        print(f"  from the seeds' scatter (K = {row['repeat']}, mean CPU s per run): eff hl {sh[0]:.3g} ± {sh[1]:.2g}, "
              f"dl {sd_[0]:.3g} ± {sd_[1]:.2g}, hl/dl {rs:.2f} ± {rse:.2f}; own error / scatter: hl "
              f"{_calibration(h):.2f}, dl {_calibration(d):.2f}")
        row["scatter_ratio"] = (rs, rse)
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


def _kernel_setup(system, *, beta, U, mu, nmax, green):
    """What ``qmc`` prepares before its chain, for driving the kernels sweep by sweep: the bonded
    model, the numba kernels, the string bound and the argument tuple of ``_Chain.advance``."""
    from types import SimpleNamespace

    from hyperlattice.bosons import sse

    model = sse._bonded_model(system, 1.0)
    wind, _ = sse._bond_windings(system, model, None)
    eps, esite, cb = sse._weights(model, U, mu, nmax)
    K = sse._load_kernels()
    bound = sse._check_memory(model, beta, cb, nmax, U, mu, green)
    sq = np.sqrt(np.arange(nmax + 2, dtype=float))
    g = sse._green_setup(model, green)
    tables = sse._exit_tables(model, esite, cb, nmax, sq)
    args = (beta, model, model.tb, cb, esite, sq, nmax, g, tables, eps, wind)
    return SimpleNamespace(model=model, K=K, bound=bound, cb=cb, esite=esite, sq=sq, g=g, tables=tables,
                           args=args, chain=lambda seed: sse._Chain(model, seed, g, length=min(bound / 4, 1e8),
                                                                    windings=wind.shape[1]))


def phases(rings: int, beta: float, therm: int, sweeps: int, seed: int, green: bool) -> None:
    """Where hyperlattice's CPU time goes, sweep by sweep, on the {7,3} flake of ``rings`` rings (U = 6,
    mu = 3, nmax = 3): the string (operators n, length M), the loops per sweep and their mean length,
    and the CPU seconds of each thermalisation and measurement sweep (the chain's own kernel calls,
    one sweep each, so that the first sweeps of a short string show)."""
    import hyperlattice as hl

    U, mu, nmax = 6.0, 3.0, 3
    lat = hl.ring_lattice(7, 3, rings)
    st = _kernel_setup(lat, beta=beta, U=U, mu=mu, nmax=nmax, green=green)
    K, args, bound = st.K, st.args, st.bound
    warm = st.chain(seed + 1)
    warm.advance(K, 2, True, *args)          # compile
    warm.advance(K, 2, False, *args)
    ch = st.chain(seed)
    print(f"\nphases: {{7,3}} flake l = {rings}, {lat.sites:,} sites, beta = {beta:g}, U = {U:g}, mu = {mu:g}, "
          f"nmax = {nmax}, G {'measured' if green else 'not measured'}; string bound {bound:,.0f}, first length "
          f"{ch.ops.size:,}; {_load()}")
    tot = {True: 0.0, False: 0.0}
    for s in range(therm + sweeps):
        th = s < therm
        c0 = time.process_time()
        ch.advance(K, 1, th, *args)
        dt = time.process_time() - c0
        tot[th] += dt
        if s < 12 or s % 50 == 0 or s == therm:
            n = int(ch.counters[0])
            print(f"  {'therm' if th else 'meas '} {s:4d}: n {n:8,d}  M {ch.ops.size:8,d}  loops {int(ch.counters[1]):6d}  "
                  f"mean loop {ch.loopstat[0] / max(ch.loopstat[1], 1.0):9.0f} legs  {dt:6.3f} CPU s  "
                  f"{dt / max(n, 1) * 1e6:5.2f} us/operator  total {tot[True] + tot[False]:6.1f} s", flush=True)
    print(f"  thermalisation {therm} sweeps {tot[True]:.1f} CPU s; measurement {sweeps} sweeps {tot[False]:.1f} CPU s "
          f"({tot[False] / max(sweeps, 1):.3f} s per sweep, "
          f"{tot[False] / max(sweeps, 1) / max(int(ch.counters[0]), 1) * 1e6:.2f} us per operator); {_load()}")


def _hl_series(system, *, U, mu, beta, nmax, therm, sweeps, seed) -> tuple[np.ndarray, float]:
    """hyperlattice's energy sweep by sweep: ``therm`` thermalisation sweeps (string growth, loop count,
    leg cap: what ``qmc`` does), then ``sweeps`` measured sweeps, one kernel call each; the chain's
    CPU seconds (thermalisation included)."""
    st = _kernel_setup(system, beta=beta, U=U, mu=mu, nmax=nmax, green=False)
    K, args = st.K, st.args
    c0 = time.process_time()
    ch = st.chain(seed)
    ch.advance(K, therm, True, *args)
    out = np.empty(sweeps)
    for s in range(sweeps):
        ch.advance(K, 1, False, *args)
        out[s] = ch.sbins[int(ch.sinfo[0]) - 1, 5]        # a bin of one sweep: that sweep's energy
        ch.sinfo[0] = 0
    return out, time.process_time() - c0


def _thermalised_after(series: np.ndarray, block: int) -> tuple[int, list[float]]:
    """The thermalisation rule, the same for both codes: ``series`` (seeds x sweeps, energies after each
    code's shortest thermalisation) in blocks of ``block`` sweeps; the plateau is the seeds' mean over the
    second half, the error of a block's seed mean sigma_w / sqrt(K) with sigma_w the scatter of all
    second-half blocks (seeds x blocks: many degrees of freedom). The chain counts as thermalised after
    the last block of the first half whose seed mean lies more than 3 errors from the plateau (0 when none
    does). Returns (sweeps to add, the z of each first-half block)."""
    k, n = series.shape
    nb = n // block
    b = series[:, :nb * block].reshape(k, nb, block).mean(axis=2)
    half = nb // 2
    late = b[:, half:]
    plateau = float(late.mean())
    sw = float(late.std(ddof=1))
    err = math.hypot(sw / math.sqrt(k), sw / math.sqrt(late.size))
    z = [(float(b[:, j].mean()) - plateau) / err for j in range(half)]
    bad = [j for j in range(half) if abs(z[j]) > 3.0]
    return (bad[-1] + 1) * block if bad else 0, z


def therm_scan(points, work: Path, *, seeds: int, seed: int, therm: int, alps_therm: int, sweeps: int,
               alps_sweeps: int, block: int, peer: bool = True) -> dict:
    """How many thermalisation sweeps each code needs, by :func:`_thermalised_after` on the energy time
    series of ``seeds`` chains per code started afresh (hyperlattice after ``therm`` thermalisation
    sweeps, sweep by sweep; dirloop_sse after ``alps_therm``, the fewest with which it runs here, from its
    stored bins; skipped when not ``peer``). Prints the blocks' z and each code's need: the shortest
    thermalisation plus the rule's sweeps."""
    out = {}
    for label, spec, U, mu, beta, nmax in points:
        system = _system(spec)
        tag = label.replace(" ", "_").replace("=", "")
        hs, ds, hc, dc = [], [], [], []
        for rep in range(seeds):
            sd = seed + rep
            e, cpu = _hl_series(system, U=U, mu=mu, beta=beta, nmax=nmax, therm=therm, sweeps=sweeps, seed=sd)
            hs.append(e)
            hc.append(cpu)
            if not peer:
                print(f"  {label} seed {sd}: hyperlattice {cpu:.1f} CPU s; {_load()}", flush=True)
                continue
            r = run_alps("dirloop_sse", system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=alps_sweeps,
                         thermalization=alps_therm, seed=sd, workdir=work / f"{tag}-scan-s{sd}")
            size = int(r["energy_bin_size"])
            ds.append(np.repeat(np.asarray(r["energy_bins"]), size))      # bins of `size` sweeps
            dc.append(r["cpu_seconds"])
            print(f"  {label} seed {sd}: hyperlattice {cpu:.1f} CPU s, dirloop_sse {r['cpu_seconds']:.1f} CPU s "
                  f"(bins of {size}); {_load()}", flush=True)
        codes = [("hyperlattice", np.array(hs), therm)]
        if peer:
            n = min(len(x) for x in ds)
            codes.append(("dirloop_sse", np.array([x[:n] for x in ds]), alps_therm))
        res = {}
        for code, ser, t0 in codes:
            add, z = _thermalised_after(ser, block)
            res[code] = {"shortest": t0, "added": add, "needed": t0 + add, "z": z}
            print(f"  {label} {code}: after {t0} thermalisation sweeps, blocks of {block} sweeps, z against the "
                  f"plateau " + " ".join(f"{v:+.1f}" for v in z) + f" -> needs {t0} + {add} = {t0 + add} sweeps")
        out[label] = res
    return out


def steps(rings_list, seed: int) -> None:
    """The cost of one loop step (a vertex passage) on {7,3} flakes at U = 6, mu = 3, beta = 8, nmax = 3:
    a chain thermalised for 60 sweeps, then 30 loop updates with its loop count against 30 that only
    build the vertex list; (difference) / (vertex passages) is the time of a step."""
    import hyperlattice as hl

    beta, U, mu, nmax = 8.0, 6.0, 3.0, 3
    for rings in rings_list:
        st = _kernel_setup(hl.ring_lattice(7, 3, rings), beta=beta, U=U, mu=mu, nmax=nmax, green=False)
        model, K, args, cb, esite, sq, g, tables = st.model, st.K, st.args, st.cb, st.esite, st.sq, st.g, st.tables
        ch = st.chain(seed)
        ch.advance(K, 60, True, *args)
        ch.advance(K, 10, False, *args)
        ops, state = ch.ops, ch.state
        m, nops, nl = ops.size, int(ch.counters[0]), int(ch.counters[1])
        vb, rec = np.empty(m, np.int32), np.empty(8 * m, np.int32)
        first, last = np.empty(model.sites, np.int64), np.empty(model.sites, np.int64)
        started = np.zeros(1, np.int64)
        vis, t, t0 = 0, 0.0, 0.0
        for _ in range(30):
            for loops in (nl, 0):
                c0 = time.process_time()
                v = K._loop_update(ops, state, nops, loops, model.bi, model.bj, model.tb, cb, esite, sq, nmax, ch.rng,
                                   vb, rec, first, last, 0, False, ch.gcur, g.gclass, g.zr, g.zi, g.omz, g.hbin,
                                   ch.vcur, 0, 1, model.gauge, tables[0], tables[1], tables[0].shape[0], 0, started)
                dt = time.process_time() - c0
                if loops:
                    t, vis = t + dt, vis + v
                else:
                    t0 += dt
        print(f"steps: {{7,3}} l = {rings}, {model.sites:,} sites, n {nops:,}, {nl} loops: {vis / 30 / nops:.2f} n steps "
              f"per sweep, loop update {t / 30 * 1e3:.1f} ms (vertex list alone {t0 / 30 * 1e3:.1f} ms), "
              f"{(t - t0) / max(vis, 1) * 1e9:.0f} ns per step; {_load()}", flush=True)


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
    ap.add_argument("--therm", type=int, default=None,
                    help="thermalisation sweeps of both SSE codes (default max(200, sweeps/5) each)")
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
                    help="thermalisation sweeps of the scale run (the string starts at a quarter of its bound "
                         "and grows by 4/3 per sweep, 2 when full: a few sweeps to reach the ~10^6 of this point)")
    ap.add_argument("--profile", action="store_true", help="only profile hyperlattice on one point")
    ap.add_argument("--phases", type=int, default=None, metavar="RINGS",
                    help="only hyperlattice's CPU seconds sweep by sweep on the {7,3} flake of RINGS rings at U = 6, "
                         "mu = 3, nmax = 3, beta = --phases-beta (--therm and --sweeps sweeps)")
    ap.add_argument("--phases-beta", type=float, default=8.0)
    ap.add_argument("--steps", default=None, metavar="RINGS,...",
                    help="only the CPU time of one loop step on the {7,3} flakes of these rings (e.g. 3,4,5,6)")
    ap.add_argument("--alps-therm", type=int, default=None,
                    help="thermalisation sweeps of dirloop_sse when it needs other than --therm (its string grows "
                         "slower: at 847 sites 100 sweeps stop it with 'nnonzero reached the maximum value')")
    ap.add_argument("--green", action="store_true", help="with --phases: measure the Green function too")
    ap.add_argument("--therm-scan", action="store_true",
                    help="only measure the thermalisation each code needs (--repeat seeds per code; hyperlattice after "
                         "--therm sweeps, dirloop_sse after --alps-therm, then --sweeps / --alps-sweeps measured)")
    ap.add_argument("--scan-block", type=int, default=20, help="block of sweeps of the thermalisation rule (default 20)")
    ap.add_argument("--scan-no-peer", action="store_true", help="with --therm-scan: hyperlattice's chains only")
    ap.add_argument("--json", default=None, metavar="PATH",
                    help="also write the table's numbers (per seed and pooled) to PATH, e.g. benchmarks/bench_qmc.json")
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
    if args.steps:
        steps([int(x) for x in args.steps.split(",")], args.seed)
        return 0
    if args.phases is not None:
        phases(args.phases, args.phases_beta, 200 if args.therm is None else args.therm, args.sweeps, args.seed,
               args.green)
        return 0
    if args.therm_scan:
        points = [POINTS[int(i) - 1] for i in (args.points or "9,10").split(",")]
        with tempfile.TemporaryDirectory() as tmp:
            therm_scan(points, Path(args.workdir or tmp), seeds=args.repeat, seed=args.seed,
                       therm=20 if args.therm is None else args.therm,
                       alps_therm=150 if args.alps_therm is None else args.alps_therm, sweeps=args.sweeps,
                       alps_sweeps=args.alps_sweeps or args.sweeps, block=args.scan_block, peer=not args.scan_no_peer)
        print(_load())
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
                     worm_sweeps=args.worm_sweeps or args.alps_sweeps or sweeps, worm=worm, seed=args.seed, repeat=args.repeat,
                     therm=args.therm, alps_therm=args.alps_therm)
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
    sr = [(r["label"], r["scatter_ratio"]) for r in rows if "scatter_ratio" in r]
    if sr:
        print("efficiency ratio from the seeds' scatter: " + ", ".join(f"{lab} {v:.2f} ± {e:.2f}" for lab, (v, e) in sr))
    print(_load())
    if args.json:
        _write_json(Path(args.json), rows, " ".join(sys.argv[1:]) if argv is None else " ".join(argv))
    return 0 if ok else 1


def _write_json(path: Path, rows: list[dict], command: str) -> None:
    """The table's numbers, per seed and pooled, merged into ``path`` under the point's label (other
    points already stored there are kept)."""
    import json

    keys = ("energy", "energy_err", "density", "density_err", "cpu_seconds", "converged")
    old = json.loads(path.read_text()) if path.exists() else {}
    for r in rows:
        ratio, err = _ratio(r["hl"], r["dl"])
        old[r["label"]] = {
            "command": "python benchmarks/bench_qmc.py " + command, "machine": machine(), "load": r["load"],
            "sites": r["sites"], "U": r["U"], "mu": r["mu"], "beta": r["beta"], "seeds": r["repeat"],
            "sweeps": {"hyperlattice": r["sweeps"][0], "dirloop_sse": r["sweeps"][1]},
            "thermalization": {"hyperlattice": r["therm"][0], "dirloop_sse": r["therm"][1]},
            "hyperlattice": [{**{k: run[k] for k in keys}, "tau": run["tau"]} for run in r["hl"]["runs"]],
            "dirloop_sse": [{**{k: run[k] for k in keys}, "tau": run.get("energy_tau"),
                             "energy_bins": run.get("energy_bins"), "energy_bin_size": run.get("energy_bin_size")}
                            for run in r["dl"]["runs"]],
            "efficiency": {"hyperlattice": _eff(r["hl"]), "dirloop_sse": _eff(r["dl"])},
            "ratio": ratio, "ratio_err": err,
        }
    path.write_text(json.dumps(old, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
