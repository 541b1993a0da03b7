"""Benchmark: the spin-1/2 Heisenberg antiferromagnet by SSE, hyperlattice against ALPS ``dirloop_sse``.

The work: H = J sum_<ij> S_i . S_j (J = 1) on the {8,3} flake with l = 3 rings (200 sites) at
beta = 4, both codes on the same graph (ALPS reads it as a lattice-library file written by
``benchmarks/_alps.py``; its MODEL "spin" with ``local_S = 0.5``). Efficiency = 1/(sigma_e^2 x CPU s)
of the energy per site, thermalisation counted on both sides (hyperlattice: ``time.process_time``
around the whole call, after a warm-up that compiles the kernels; ALPS: the application's own
user + system time from ``RUSAGE_CHILDREN``). ALPS's ``loop`` application segfaults on every
custom graph (/work/shared/NUMERICS-NOTES.md, "ALPS spin peers"), so ``dirloop_sse`` is the only
quantum peer. Several seeds per code; the ratio of the pooled efficiencies is printed with the
spread of the per-seed ratios, and each code's error bars are checked against the other's value
and against the scatter of its own seeds.

Usage::

    python benchmarks/bench_spins_quantum.py [--seeds 4] [--sweeps 20000] [--alps-sweeps 20000]
        [--rings 3] [--beta 4] [--validate]

``--validate`` runs both codes on the 8-site ring (l = 1) at beta = 2 and compares them with
exact diagonalisation first (conventions).

ALPS lives in its own virtualenv (``.venv-alps``, created on first use: see ``_alps.py``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def run_alps_spin(system, *, J: float, beta: float, sweeps: int, thermalization: int, seed: int, workdir) -> dict:
    """ALPS ``dirloop_sse`` on the Heisenberg model of ``system``: energy per site with its error,
    the staggered structure factor per site, and the application's CPU seconds."""
    from _alps import adjacency_of, alps_python, lattice_xml

    adj = adjacency_of(system)
    text, weights = lattice_xml(adj)
    if len(weights) != 1 or abs(next(iter(weights.values())) - 1.0) > 0:
        raise ValueError("the spin benchmark takes unweighted graphs only.")
    work = Path(workdir)
    work.mkdir(parents=True, exist_ok=True)
    (work / "lattice.xml").write_text(text)
    parms = {"LATTICE_LIBRARY": "lattice.xml", "LATTICE": "graph", "MODEL": "spin", "local_S": 0.5,
             "J": float(J), "T": 1.0 / float(beta), "THERMALIZATION": int(thermalization), "SWEEPS": int(sweeps),
             "SEED": int(seed)}
    spec = {"parms": parms, "sites": int(adj.shape[0])}
    (work / "job.json").write_text(json.dumps(spec))
    proc = subprocess.run([str(alps_python()), str(Path(__file__).resolve()), "--worker", str(work / "job.json")],
                          cwd=work, capture_output=True, text=True)
    (work / "alps.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        tail = " | ".join((proc.stdout + proc.stderr).strip().splitlines()[-5:])
        raise RuntimeError(f"ALPS dirloop_sse failed (exit {proc.returncode}): {tail}")
    return json.loads([ln for ln in proc.stdout.splitlines() if ln.startswith("{")][-1])


def _worker(job: str) -> None:
    """The ALPS side (numpy and pyalps only)."""
    import resource

    import pyalps
    import pyalps.hdf5 as h5

    spec = json.loads(Path(job).read_text())
    parms, sites = spec["parms"], spec["sites"]
    infile = pyalps.writeInputFiles("dirloop_sse", [parms])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    code, _ = pyalps.runApplication("dirloop_sse", infile, Tmin=1)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if code != 0:
        sys.exit(f"dirloop_sse exited with status {code}")
    ar = h5.archive("dirloop_sse.task1.out.h5", "r")
    base = "/simulation/results/"

    def mean(name):
        m = ar[base + name + "/mean"]
        return float(m["value"]), float(m["error"]), int(m.get("error_convergence", 0))

    e, de, conv = mean("Energy")
    s, ds, _ = mean("Staggered Magnetization^2")
    chi, dchi, _ = mean("Susceptibility")
    print(json.dumps({"e": e / sites, "e_err": de / sites, "s_pi": s / sites, "s_pi_err": ds / sites,
                      "chi_u": chi, "chi_u_err": dchi, "cpu_seconds": cpu, "converged": conv == 0}))


def _hl(system, *, J, beta, sweeps, thermalization, seed) -> dict:
    from hyperlattice.spins.quantum import xxz_qmc

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c0 = time.process_time()
        r = xxz_qmc(system, J=J, Delta=1.0, beta=beta, sweeps=sweeps, thermalization=thermalization, seed=seed,
                    progress=False)
        cpu = time.process_time() - c0
    return {"e": r.e, "e_err": r.e_err, "s_pi": r.s_pi, "s_pi_err": r.s_pi_err, "chi_u": r.chi_u,
            "chi_u_err": r.chi_u_err, "cpu_seconds": cpu, "converged": r.converged and not caught,
            "tau": r.tau_int["energy"], "estimator": r.energy_estimator}


def _eff(r: dict) -> float:
    return 1.0 / (r["e_err"] ** 2 * r["cpu_seconds"])


def _pool(runs: list[dict]) -> dict:
    """Sweep-equal chains pooled: mean, error sqrt(sum err^2)/n, CPU summed."""
    n = len(runs)
    out = {"cpu_seconds": sum(r["cpu_seconds"] for r in runs), "converged": all(r["converged"] for r in runs)}
    for k in ("e", "s_pi", "chi_u"):
        out[k] = float(np.mean([r[k] for r in runs]))
        out[k + "_err"] = float(math.sqrt(sum(r[k + "_err"] ** 2 for r in runs)) / n)
        vals = np.array([r[k] for r in runs])
        out[k + "_scatter"] = float(vals.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    return out


def _system(rings: int):
    import hyperlattice as hl

    return hl.ring_lattice(8, 3, rings)


def validate(work: Path, seed: int = 1) -> bool:
    from hyperlattice.spins.quantum import xxz_exact

    ring = _system(1)
    ex = xxz_exact(ring, J=1.0, Delta=1.0, beta=2.0)
    h = _hl(ring, J=1.0, beta=2.0, sweeps=20000, thermalization=2000, seed=seed)
    a = run_alps_spin(ring, J=1.0, beta=2.0, sweeps=20000, thermalization=2000, seed=seed, workdir=work / "validate")
    ok = True
    print(f"validate: 8-site Heisenberg ring, beta = 2; exact e = {ex.e:.5f}, s_pi = {ex.s_pi:.5f}, "
          f"chi_u = {ex.chi_u:.5f}")
    for name, r in (("hyperlattice", h), ("dirloop_sse", a)):
        zs = {k: (r[k] - getattr(ex, k)) / r[k + "_err"] for k in ("e", "s_pi", "chi_u")}
        print(f"  {name:<13} e = {r['e']:.5f} ± {r['e_err']:.5f}, s_pi = {r['s_pi']:.5f} ± {r['s_pi_err']:.5f}, "
              f"chi_u = {r['chi_u']:.5f} ± {r['chi_u_err']:.5f}; z = "
              + ", ".join(f"{k} {v:+.1f}" for k, v in zs.items()))
        ok &= all(abs(v) < 4 for v in zs.values())
    return ok


def main(argv=None) -> int:
    from _machine import machine, peak_rss_mb

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--sweeps", type=int, default=20000, help="hyperlattice measurement sweeps per seed")
    ap.add_argument("--alps-sweeps", type=int, default=20000, help="dirloop_sse measurement sweeps per seed")
    ap.add_argument("--rings", type=int, default=3)
    ap.add_argument("--beta", type=float, default=4.0)
    ap.add_argument("--validate", action="store_true")
    args = ap.parse_args(argv)
    print(machine())
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    work = Path(tempfile.mkdtemp(prefix="bench_spins_quantum_"))
    _hl(_system(1), J=1.0, beta=1.0, sweeps=200, thermalization=50, seed=0)     # compile the kernels
    if args.validate and not validate(work):
        print("validation FAILED")
        return 1
    system = _system(args.rings)
    n = system.z.size
    therm_h = max(200, args.sweeps // 5)
    therm_a = max(200, args.alps_sweeps // 5)
    print(f"Heisenberg AFM on the {{8,3}} flake, l = {args.rings} ({n} sites), beta = {args.beta:g}; "
          f"hyperlattice {args.sweeps} + {therm_h} sweeps, dirloop_sse {args.alps_sweeps} + {therm_a} sweeps per seed")
    hs, als, ratios = [], [], []
    for s in range(args.seeds):
        seed = 1000 + s
        h = _hl(system, J=1.0, beta=args.beta, sweeps=args.sweeps, thermalization=therm_h, seed=seed)
        a = run_alps_spin(system, J=1.0, beta=args.beta, sweeps=args.alps_sweeps, thermalization=therm_a, seed=seed,
                          workdir=work / f"seed{seed}")
        hs.append(h)
        als.append(a)
        ratios.append(_eff(h) / _eff(a))
        print(f"  seed {seed}: hyperlattice e = {h['e']:.5f} ± {h['e_err']:.5f} ({h['cpu_seconds']:.2f} CPU s, "
              f"tau_int {h['tau']:.2f}), dirloop_sse e = {a['e']:.5f} ± {a['e_err']:.5f} ({a['cpu_seconds']:.2f} "
              f"CPU s); efficiency ratio {ratios[-1]:.2f}")
    ph, pa = _pool(hs), _pool(als)
    ratio = _eff(ph) / _eff(pa)
    z = (ph["e"] - pa["e"]) / math.hypot(ph["e_err"], pa["e_err"])
    zs = (ph["s_pi"] - pa["s_pi"]) / math.hypot(ph["s_pi_err"], pa["s_pi_err"])
    print(f"pooled: hyperlattice e = {ph['e']:.6f} ± {ph['e_err']:.6f} (seed scatter {ph['e_scatter']:.6f}), "
          f"s_pi = {ph['s_pi']:.4f} ± {ph['s_pi_err']:.4f}, {ph['cpu_seconds']:.1f} CPU s")
    print(f"        dirloop_sse  e = {pa['e']:.6f} ± {pa['e_err']:.6f} (seed scatter {pa['e_scatter']:.6f}), "
          f"s_pi = {pa['s_pi']:.4f} ± {pa['s_pi_err']:.4f}, {pa['cpu_seconds']:.1f} CPU s")
    print(f"        agreement: e {z:+.1f} sigma, s_pi {zs:+.1f} sigma; converged {ph['converged']} / {pa['converged']}")
    print(f"hyperlattice's energy estimator: {hs[0]['estimator']} (spins.quantum module notes)")
    print(f"efficiency 1/(sigma_e^2 CPU s): hyperlattice {_eff(ph):.4g}, dirloop_sse {_eff(pa):.4g}, "
          f"ratio {ratio:.2f} (per seed {min(ratios):.2f} - {max(ratios):.2f}); target >= 2")
    print(f"peak RSS {peak_rss_mb():.0f} MB; load average now {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--worker":
        _worker(sys.argv[2])
    else:
        sys.exit(main())
