"""Classical spins: hyperlattice.spins.classical_mc against ALPS ``spinmc`` on the same graph.

The Ising model on the {7,3} flake of 6 rings (2,240 sites) near the Bethe-lattice T_c of q = 3,
T = 1/artanh(1/2) = 1.820, and deeper at T = 1.5: the package's automatic update (Wolff) against
both of spinmc's updates, UPDATE "cluster" (one Wolff cluster and one measurement per ALPS sweep)
and "local"; the ratio is taken against the better of the two. Efficiency = 1 / (sigma_e^2 x CPU seconds) of the energy per site, thermalisation
counted on both sides (the package: process time of the whole call, compiled kernels warmed up
first; ALPS: the application's user + system time). The peers take turns, several seeds each, in
one process; the scatter of the seeds' energies is printed next to the mean stated error, so both
codes' error bars are checked.

Scale: Wolff sweeps on a {7,3} flake of 13 rings (1.9 million sites) at T = 1.820, with the
memory the package counts before the run and the peak resident memory after.

Run: ``python benchmarks/bench_spins.py`` (``--validate``: both codes against exact enumeration
on the heptagon first; ``--quick``: fewer seeds and sweeps; ``--no-scale``: skip the big flake).
ALPS lives in its own virtualenv (benchmarks/_alps.py).
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

from _alps import run_spinmc  # noqa: E402
from _machine import machine, peak_rss_mb  # noqa: E402

import hyperlattice as hl  # noqa: E402
from hyperlattice.spins import classical_mc, classical_mc_memory  # noqa: E402
from hyperlattice.spins.classical import SpinWarning  # noqa: E402

T_BETHE = 1.0 / math.atanh(0.5)


def _ours(system, beta, sweeps, therm, seed):
    t0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        r = classical_mc(system, model="ising", beta=beta, sweeps=sweeps, thermalization=therm, seed=seed,
                         measure_correlation=False, progress=False)
    return {"energy": r.e, "energy_err": r.e_err, "m2": r.m2, "m2_err": r.m2_err, "cpu_seconds": time.process_time() - t0,
            "tau": r.tau_int["e"], "update": r.update}


def _exact_heptagon(beta, J):
    lat = hl.ring_lattice(7, 3, 1)
    a = hl.adjacency(lat).toarray()
    s = 1 - 2 * ((np.arange(128)[:, None] >> np.arange(7)[None, :]) & 1)
    E = -0.5 * J * np.einsum("si,ij,sj->s", s, a, s)
    w = np.exp(-beta * (E - E.min()))
    w /= w.sum()
    return float(w @ E) / 7, float(w @ (s.mean(axis=1) ** 2))


def validate(work: Path) -> None:
    lat = hl.ring_lattice(7, 3, 1)
    print("validation on the heptagon (7 sites), beta = 0.6, exact enumeration:")
    for J in (1.0, -1.0):
        e, m2 = _exact_heptagon(0.6, J)
        a = run_spinmc(lat, J=J, beta=0.6, sweeps=100000, thermalization=1000, seed=1, workdir=work / f"val{J:+g}")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SpinWarning)
            o = classical_mc(lat, model="ising", J=J, beta=0.6, sweeps=100000, seed=1, progress=False)
        print(f"  J = {J:+g}: exact e = {e:.5f}, m2 = {m2:.5f} | ALPS e = {a['energy']:.5f} +- {a['energy_err']:.5f} "
              f"({(a['energy'] - e) / a['energy_err']:+.1f} sigma), m2 = {a['m2']:.5f} +- {a['m2_err']:.5f} | "
              f"package e = {o.e:.5f} +- {o.e_err:.5f} ({(o.e - e) / o.e_err:+.1f} sigma), m2 = {o.m2:.5f} +- "
              f"{o.m2_err:.5f} [{o.update}]")


def compare(lat, T, seeds, ours_sweeps, alps_sweeps, work: Path) -> float:
    """alps_sweeps: (cluster, local); ALPS's cluster "sweep" is one Wolff cluster and one measurement."""
    beta = 1.0 / T
    runs = {"package": [], "ALPS cluster": [], "ALPS local": []}
    for s in seeds:
        runs["package"].append(_ours(lat, beta, ours_sweeps, max(100, ours_sweeps // 10), s))
        for (name, upd), sw in zip((("ALPS cluster", "cluster"), ("ALPS local", "local")), alps_sweeps):
            runs[name].append(run_spinmc(lat, J=1.0, beta=beta, sweeps=sw, thermalization=max(100, sw // 10), seed=s,
                                         update=upd, workdir=work / f"T{T:.3f}-{upd}-{s}"))
    eff = {}
    print(f"\nIsing, {{7,3}} flake l = {lat.rings} ({lat.sites} sites), T = {T:.3f}, Wolff clusters, "
          f"{len(seeds)} seeds each")
    for name, rs in runs.items():
        e = np.array([r["energy"] for r in rs])
        err = np.array([r["energy_err"] for r in rs])
        cpu = np.array([r["cpu_seconds"] for r in rs])
        per = 1.0 / (err ** 2 * cpu)
        eff[name] = float(np.mean(per))
        scatter = float(e.std(ddof=1)) if e.size > 1 else math.nan
        print(f"  {name:<12} e = {e.mean():.6f}, stated error {err.mean():.2e} (seed scatter {scatter:.2e}), "
              f"CPU {cpu.mean():.2f} s per run, efficiency 1/(sigma^2 s) = {eff[name]:.3g}"
              + (f", tau_int(e) = {np.mean([r['tau'] for r in rs]):.2f} sweeps" if name == "package" else ""))
    for peer in ("ALPS cluster", "ALPS local"):
        d = np.mean([r["energy"] for r in runs["package"]]) - np.mean([r["energy"] for r in runs[peer]])
        sd = math.hypot(np.mean([r["energy_err"] for r in runs["package"]]) / math.sqrt(len(seeds)),
                        np.mean([r["energy_err"] for r in runs[peer]]) / math.sqrt(len(seeds)))
        print(f"  package - {peer}: energies differ by {d:+.2e} ({d / sd:+.1f} sigma); efficiency ratio "
              f"{eff['package'] / eff[peer]:.2f}")
    ratio = eff["package"] / max(eff["ALPS cluster"], eff["ALPS local"])
    print(f"  efficiency ratio package / best spinmc update = {ratio:.2f}")
    return ratio


def updates(lat, temps=(T_BETHE, 1.5, 1.2), sweeps: int = 20000) -> None:
    """The evidence behind update="auto": the package's own Wolff and heat-bath chains, same work."""
    print(f"\nthe package's updates on the {{7,3}} flake l = {lat.rings} ({lat.sites} sites), Ising, {sweeps} sweeps: "
          "efficiency 1/(sigma^2 x CPU s) of e and of m2")
    for T in temps:
        for upd in ("wolff", "swendsen-wang", "local"):
            t0 = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", SpinWarning)
                r = classical_mc(lat, model="ising", T=T, sweeps=sweeps, seed=1, update=upd, measure_correlation=False,
                                 progress=False)
            cpu = time.process_time() - t0
            print(f"  T = {T:.3f} {r.update:<14} e = {r.e:.5f} +- {r.e_err:.5f}  tau_int(e) = {r.tau_int['e']:6.2f}  "
                  f"tau_int(m2) = {r.tau_int['m2']:7.2f}  CPU {cpu:5.2f} s  efficiency(e) {1 / (r.e_err ** 2 * cpu):.2e}  "
                  f"efficiency(m2) {1 / (r.m2_err ** 2 * cpu):.2e}")


def scale(rings: int, sweeps: int) -> None:
    t0 = time.perf_counter()
    lat = hl.ring_lattice(7, 3, rings)
    build = time.perf_counter() - t0
    need = classical_mc_memory(lat, model="ising", measure_correlation=False)
    t0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        r = classical_mc(lat, model="ising", T=T_BETHE, sweeps=sweeps, thermalization=20, seed=1,
                         measure_correlation=False, progress=False)
    cpu = time.process_time() - t0
    total = sweeps + 20
    print(f"\nscale: {{7,3}} flake l = {rings}, {lat.sites:,} sites (built in {build:.1f} s), Ising at T = {T_BETHE:.3f}, "
          f"{total} Wolff sweeps ({r.clusters_per_sweep:.0f} clusters each) in {cpu:.1f} s CPU: "
          f"{cpu / total:.2f} s per sweep, {1e9 * cpu / total / lat.sites:.0f} ns per site and sweep; "
          f"memory counted before the run {need / 2**20:.0f} MiB, peak RSS of this process {peak_rss_mb():.0f} MB; "
          f"e = {r.e:.5f} +- {r.e_err:.5f}, bulk (ring 1) alignment {r.ring_alignment[0]:.3f}, "
          f"boundary (ring {rings}) {r.ring_alignment[-1]:.3f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--validate", action="store_true")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-scale", action="store_true")
    ap.add_argument("--updates", action="store_true", help="only the package's Wolff against heat-bath table")
    ap.add_argument("--rings", type=int, default=6)
    ap.add_argument("--scale-rings", type=int, default=13)
    args = ap.parse_args()
    print(machine())
    print("load:", os.getloadavg())
    work = Path(tempfile.mkdtemp(prefix="bench_spins_"))
    # warm the compiled kernels (their compile time is not a run's work)
    _ours(hl.ring_lattice(7, 3, 2), 0.5, 200, 10, 0)
    lat = hl.ring_lattice(7, 3, args.rings)
    if args.updates:
        updates(lat)
        return
    if args.validate:
        validate(work)
    seeds = (1, 2) if args.quick else (1, 2, 3, 4)
    ours_sweeps = 20000 if args.quick else 50000
    alps_sweeps = (40000, 10000) if args.quick else (200000, 50000)
    for T in (T_BETHE, 1.5):
        compare(lat, T, seeds, ours_sweeps, alps_sweeps, work)
    print("load:", os.getloadavg())
    if not args.no_scale:
        scale(args.scale_rings, 20 if args.quick else 50)


if __name__ == "__main__":
    main()
