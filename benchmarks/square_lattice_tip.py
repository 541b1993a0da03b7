"""Engine check (issue 27): the n = 1 Mott tip of the square lattice from rho_s * L crossings.

At the tip the transition is 3D XY with z = 1, so rho_s * L is scale invariant at U_c when
beta * t is proportional to L; here beta * t = L (stated choice). rho_s = <W_x^2 + W_y^2>/(2 beta)
from the winding numbers (bosons.qmc with square_lattice_windings). mu is held on the line of
commensurate density n = 1 through the tip: each point starts from --mu-over-U (default 0.37, near
the tip; mean field gives sqrt 2 - 1 = 0.414 at its own tip) and takes Newton steps
mu <- mu - (n - 1)/kappa on short runs until |n - 1| < 2 sigma, then the production run.
Exact: (U/t)_c = 16.7424(54), Capogrosso-Sansone, Prokof'ev, Svistunov, PRA 77, 015602 (2008).

    nice -n 10 python benchmarks/square_lattice_tip.py --sizes 4,6 --U 15,16.7,18.5 --sweeps 4000
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from hyperlattice.bosons import qmc
from hyperlattice.compare.qmc_lobe import square_lattice, square_lattice_windings

EXACT_U = 16.7424


def point(L, U, sweeps, nmax, mu_over_U, seed):
    A, win = square_lattice(L), square_lattice_windings(L)
    mu = mu_over_U * U
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(3):
            r = qmc(A, U=U, mu=mu, beta=float(L), nmax=nmax, sweeps=max(sweeps // 4, 200), seed=seed,
                    progress=False, windings=win)
            if abs(r.density - 1) < 2 * r.density_err + 1e-12 or r.compressibility <= 0:
                break
            mu -= (r.density - 1) / max(r.compressibility, 1e-3)
        r = qmc(A, U=U, mu=mu, beta=float(L), nmax=nmax, sweeps=sweeps, seed=seed + 1, progress=False, windings=win)
    return mu, r


def crossing(Us, y1, e1, y2, e2):
    """U where the linear interpolations of two curves cross (error from the bracketing points)."""
    d = np.asarray(y1) - np.asarray(y2)
    for k in range(len(Us) - 1):
        if d[k] * d[k + 1] <= 0 and d[k] != d[k + 1]:
            f = d[k] / (d[k] - d[k + 1])
            uc = Us[k] + f * (Us[k + 1] - Us[k])
            slope = abs(d[k + 1] - d[k]) / (Us[k + 1] - Us[k])
            err = np.hypot(np.hypot(e1[k], e2[k]), np.hypot(e1[k + 1], e2[k + 1])) / max(slope, 1e-12)
            return uc, err
    return float("nan"), float("nan")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="4,6,8")
    ap.add_argument("--U", default="15,16,16.7,17.5,18.5")
    ap.add_argument("--sweeps", type=int, default=8000)
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--mu-over-U", type=float, default=0.37)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(argv)
    sizes = [int(x) for x in a.sizes.split(",")]
    Us = [float(x) for x in a.U.split(",")]
    table = {}
    print("| L | U/t | mu/U | n | rho_s L | tau_int |")
    print("|---|---|---|---|---|---|")
    for L in sizes:
        for U in Us:
            mu, r = point(L, U, a.sweeps, a.nmax, a.mu_over_U, a.seed)
            table[L, U] = (r.rho_s * L, r.rho_s_err * L)
            print(f"| {L} | {U:g} | {mu / U:.4f} | {r.density:.4f} ± {r.density_err:.4f} | "
                  f"{r.rho_s * L:.4f} ± {r.rho_s_err * L:.4f} | {r.tau_int['stiffness']:.2f} |", flush=True)
    for L1, L2 in zip(sizes, sizes[1:]):
        uc, err = crossing(Us, *zip(*[table[L1, U] for U in Us]), *zip(*[table[L2, U] for U in Us]))
        print(f"crossing L = {L1}, {L2}: (U/t)_c = {uc:.3f} ± {err:.3f}, (t/U)_c = {1 / uc:.5f}; "
              f"exact 16.7424 (0.05973), deviation {(uc - EXACT_U) / err:.1f} sigma")


if __name__ == "__main__":
    main()
