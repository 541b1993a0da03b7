"""Statistical efficiency of hyperlattice's SSE against its loop budget (legs visited per sweep).

The directed-loop update visits about ``target_legs`` x n vertex legs per sweep (n the number of
operators in the string), fixed in thermalisation (``hyperlattice.bosons.sse._TARGET_LEGS``).
A larger budget decorrelates more per sweep and costs more per sweep; what counts is the
efficiency 1 / (sigma_E^2 x CPU seconds) (benchmarks/bench_qmc.py). For each budget and each
point of bench_qmc's table this script runs K seeds and prints the mean efficiency with its
standard error over the seeds, the CPU time per sweep and tau_int of the energy.

Usage::

    python benchmarks/qmc_legs_scan.py --points 3,4,6,8 --legs 2,3,4,6 --seeds 4 --sweeps 5000
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_qmc import POINTS, _system  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--points", default="3,4,6,8")
    ap.add_argument("--legs", default="2,3,4,6")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--sweeps", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=17)
    args = ap.parse_args(argv)
    import warnings

    from hyperlattice.bosons import QMCWarning, qmc, sse

    warnings.simplefilter("ignore", QMCWarning)
    legs = [float(x) for x in args.legs.split(",")]
    pts = [POINTS[int(i) - 1] for i in args.points.split(",")]
    # compile outside the timings
    qmc(_system(("flake", 1)), U=6.0, mu=3.0, beta=1.0, nmax=3, sweeps=50, thermalization=10, seed=1,
        measure_green=False, progress=False)
    print(f"{'point':16s} {'legs':>5s} {'eff':>10s} {'+-':>8s} {'ms/sweep':>9s} {'tau_E':>6s} {'n':>8s} {'loops':>6s}")
    for label, spec, U, mu, beta, nmax in pts:
        system = _system(spec)
        for tl in legs:
            sse._TARGET_LEGS = tl
            effs, per, taus = [], [], []
            for k in range(args.seeds):
                c0 = time.process_time()
                r = qmc(system, U=U, mu=mu, beta=beta, nmax=nmax, sweeps=args.sweeps,
                        thermalization=max(200, args.sweeps // 5), seed=args.seed + k, measure_green=False,
                        progress=False)
                cpu = time.process_time() - c0
                effs.append(1.0 / (r.energy_err ** 2 * cpu))
                per.append(1e3 * cpu / (args.sweeps + max(200, args.sweeps // 5)))
                taus.append(r.tau_int["energy"])
            e = np.array(effs)
            sem = e.std(ddof=1) / math.sqrt(e.size) if e.size > 1 else math.nan
            print(f"{label:16s} {tl:5.1f} {e.mean():10.4g} {sem:8.2g} {np.mean(per):9.3f} {np.mean(taus):6.2f} "
                  f"{r.mean_operators:8.0f} {r.loops_per_sweep:6d}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
