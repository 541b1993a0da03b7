"""Error bars of the QMC against the scatter of independent seeds.

K chains with seeds 2000, 2001, ... of one point; per observable (E, n, kappa): the seeds' scatter
(sample standard deviation of the K means), the root mean square of the chains' own error bars,
their ratio (1 when the bars are true; its statistical error about 1/sqrt(2(K-1))) and
chi^2 = sum_k (x_k - xbar)^2 / sigma_k^2 for K - 1 degrees of freedom with its two-sided p-value.

Usage::

    python benchmarks/qmc_errorbars.py                       # {5,4} two rings, U = 6, mu = 3, beta = 8
    python benchmarks/qmc_errorbars.py --seeds 120 --sweeps 500 --therm 200
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np
from scipy import stats


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pq", default="5,4", help="p,q of the flake (default 5,4)")
    ap.add_argument("--rings", type=int, default=2)
    ap.add_argument("--U", type=float, default=6.0)
    ap.add_argument("--mu", type=float, default=3.0)
    ap.add_argument("--beta", type=float, default=8.0)
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--sweeps", type=int, default=500)
    ap.add_argument("--therm", type=int, default=200)
    ap.add_argument("--seeds", type=int, default=120)
    args = ap.parse_args(argv)
    import hyperlattice as hl
    from hyperlattice.bosons import QMCWarning, qmc

    p, q = (int(x) for x in args.pq.split(","))
    lat = hl.ring_lattice(p, q, args.rings)
    rows = []
    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", QMCWarning)
        for s in range(args.seeds):
            r = qmc(lat, U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax, sweeps=args.sweeps,
                    thermalization=args.therm, seed=2000 + s, measure_green=False, progress=False)
            rows.append((r.energy, r.energy_err, r.density, r.density_err, r.compressibility, r.compressibility_err))
    a = np.array(rows)
    k = args.seeds
    print(f"{{{p},{q}}} l = {args.rings} ({lat.sites} sites), U = {args.U:g}, mu = {args.mu:g}, beta = {args.beta:g}, "
          f"nmax = {args.nmax}; {k} seeds of {args.sweeps} sweeps after {args.therm}; {time.process_time() - c0:.0f} CPU s, "
          f"load {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    print("| observable | scatter | rms own error | own / scatter | chi^2 | dof | p (two-sided) |")
    print("|---|---|---|---|---|---|---|")
    for col, name in ((0, "E"), (2, "n"), (4, "kappa")):
        x, e = a[:, col], a[:, col + 1]
        sd = float(np.std(x, ddof=1))
        rms = float(np.sqrt(np.mean(e ** 2)))
        w = 1.0 / e ** 2
        chi2 = float(np.sum((x - np.sum(w * x) / np.sum(w)) ** 2 * w))
        cdf = float(stats.chi2.cdf(chi2, k - 1))
        print(f"| {name} | {sd:.4g} | {rms:.4g} | {rms / sd:.3f} ± {1 / np.sqrt(2 * (k - 1)):.3f} | {chi2:.1f} | "
              f"{k - 1} | {2 * min(cdf, 1 - cdf):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
