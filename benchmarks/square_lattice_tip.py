"""Engine check (issue 27): the n = 1 Mott tip of the square lattice from rho_s * L crossings.

At the tip the transition is 3D XY with z = 1, so rho_s * L is scale invariant at U_c when
beta * t is proportional to L; here beta * t = L (stated choice). rho_s = <W_x^2 + W_y^2>/(2 beta)
from the winding numbers (bosons.qmc with square_lattice_windings). mu is held on the line of
commensurate density n = 1 through the tip: each point starts from --mu-over-U (default 0.37, near
the tip; mean field gives sqrt 2 - 1 = 0.414 at its own tip) and takes Newton steps
mu <- mu - (n - 1)/kappa on short runs until |n - 1| < 2 sigma, then the production run.
Exact: (U/t)_c = 16.7424(54), Capogrosso-Sansone, Prokof'ev, Svistunov, PRA 77, 015602 (2008).

Crossings of each pair of consecutive sizes: a weighted least-squares polynomial in U (--degree, a
parabola and a line by default, one line of output each) through the difference of the two rho_s L
curves over the whole U grid, its root, and the error of the root
from a parametric bootstrap (every point redrawn from a normal distribution with its QMC error
bar, --boots redraws), scaled by sqrt(chi2/dof) when chi2/dof > 1 (the polynomial then does not describe
the difference within the error bars: the usual scale factor, a convention). The linear
interpolation between the two bracketing U is printed too (the error propagated from the four
bracketing points). --sweeps takes one number or one per size; --rows reads the table rows a
previous run printed (files), so sizes run one at a time can be combined without rerunning.

    nice -n 10 python benchmarks/square_lattice_tip.py --sizes 4,6 --U 15,16.7,18.5 --sweeps 4000
    nice -n 10 python benchmarks/square_lattice_tip.py --sizes 8 --U 16,16.5,17,17.5 --sweeps 2000 > L8.txt
    python benchmarks/square_lattice_tip.py --rows L4.txt L6.txt L8.txt
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


def crossing_fit(Us, y1, e1, y2, e2, *, degree=1, boots=2000, seed=0):
    """Root of a weighted polynomial fit of y1 - y2 in U inside the grid, with a bootstrap error.

    Returns (U_c, error, chi2 per degree of freedom, fraction of redraws with a root in the grid);
    the error is the bootstrap spread times max(1, sqrt(chi2/dof)).
    """
    Us = np.asarray(Us, float)
    d = np.asarray(y1, float) - np.asarray(y2, float)
    e = np.hypot(np.asarray(e1, float), np.asarray(e2, float))
    if len(Us) < degree + 2:
        raise ValueError(f"a fit of degree {degree} needs at least {degree + 2} values of U, got {len(Us)}.")
    lo, hi = Us.min(), Us.max()

    def root(dd):
        c = np.polyfit(Us, dd, degree, w=1 / e)
        r = [z.real for z in np.roots(c) if abs(z.imag) < 1e-12 and lo <= z.real <= hi]
        return (min(r, key=lambda z: abs(z - 0.5 * (lo + hi))) if r else np.nan), c

    uc, c = root(d)
    chi2 = float(np.sum(((np.polyval(c, Us) - d) / e) ** 2) / (len(Us) - degree - 1))
    rng = np.random.default_rng(seed)
    rs = np.array([root(d + e * rng.standard_normal(len(Us)))[0] for _ in range(boots)])
    ok = np.isfinite(rs)
    err = float(np.std(rs[ok], ddof=1)) * max(1.0, np.sqrt(chi2)) if ok.sum() > 1 else float("nan")
    return float(uc), err, chi2, float(ok.mean())


def read_rows(paths):
    """{(L, U): (mu/U, n, n_err, rho_s L, error, tau_int)} from the table rows of earlier runs."""
    out = {}
    for path in paths:
        with open(path, encoding="utf-8") as fh:
            for line in fh:
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                if len(cells) != 6 or not cells[0].isdigit():
                    continue
                n, n_err = (float(x) for x in cells[3].split("±"))
                rho, rho_err = (float(x) for x in cells[4].split("±"))
                out[int(cells[0]), float(cells[1])] = (float(cells[2]), n, n_err, rho, rho_err, float(cells[5]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="4,6,8")
    ap.add_argument("--U", default="15,16,16.7,17.5,18.5")
    ap.add_argument("--sweeps", default="8000", help="one number, or one per size (comma-separated)")
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--mu-over-U", type=float, default=0.37)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--degree", default="2,1",
                    help="degrees of the fits of the rho_s L difference in U (comma-separated: one line each)")
    ap.add_argument("--boots", type=int, default=2000, help="bootstrap redraws for the crossing's error")
    ap.add_argument("--rows", nargs="+", metavar="FILE",
                    help="read the points from the table rows earlier runs printed instead of running them")
    a = ap.parse_args(argv)
    try:
        degrees = [int(x) for x in a.degree.split(",")]
    except ValueError:
        ap.error(f"--degree takes comma-separated integers, got {a.degree!r}.")
    if any(d < 1 for d in degrees):
        ap.error(f"--degree takes degrees of at least 1, got {a.degree!r}.")
    if a.rows:
        table = read_rows(a.rows)
        sizes = sorted({L for L, _ in table})
        Us = sorted({U for _, U in table})
        missing = [(L, U) for L in sizes for U in Us if (L, U) not in table]
        if missing:
            ap.error(f"the rows lack the points (L, U) = {missing}: every size needs the same U grid.")
        print("| L | U/t | mu/U | n | rho_s L | tau_int |")
        print("|---|---|---|---|---|---|")
        for L in sizes:
            for U in Us:
                m, n, ne, y, ye, tau = table[L, U]
                print(f"| {L} | {U:g} | {m:.4f} | {n:.4f} ± {ne:.4f} | {y:.4f} ± {ye:.4f} | {tau:.2f} |")
        table = {k: (v[3], v[4]) for k, v in table.items()}
    else:
        sizes = [int(x) for x in a.sizes.split(",")]
        Us = [float(x) for x in a.U.split(",")]
        sweeps = [int(x) for x in a.sweeps.split(",")]
        if len(sweeps) == 1:
            sweeps = sweeps * len(sizes)
        if len(sweeps) != len(sizes):
            ap.error(f"--sweeps takes one number or one per size ({len(sizes)}), got {len(sweeps)}.")
        table = {}
        print("| L | U/t | mu/U | n | rho_s L | tau_int |")
        print("|---|---|---|---|---|---|")
        for L, nsw in zip(sizes, sweeps):
            for U in Us:
                mu, r = point(L, U, nsw, a.nmax, a.mu_over_U, a.seed)
                table[L, U] = (r.rho_s * L, r.rho_s_err * L)
                print(f"| {L} | {U:g} | {mu / U:.4f} | {r.density:.4f} ± {r.density_err:.4f} | "
                      f"{r.rho_s * L:.4f} ± {r.rho_s_err * L:.4f} | {r.tau_int['stiffness']:.2f} |", flush=True)
    for L1, L2 in zip(sizes, sizes[1:]):
        c1, c2 = zip(*[table[L1, U] for U in Us]), zip(*[table[L2, U] for U in Us])
        y1, e1 = c1
        y2, e2 = c2
        for deg in degrees:
            if len(Us) < deg + 2:
                continue
            uc, err, chi2, frac = crossing_fit(Us, y1, e1, y2, e2, degree=deg, boots=a.boots)
            print(f"crossing L = {L1}, {L2}: (U/t)_c = {uc:.3f} ± {err:.3f}, (t/U)_c = {1 / uc:.5f}; "
                  f"exact 16.7424 (0.05973), deviation {(uc - EXACT_U) / err:.1f} sigma "
                  f"(fit of degree {deg}, chi2/dof = {chi2:.2f}{', error scaled by its root' if chi2 > 1 else ''}, "
                  f"{a.boots} redraws, {frac:.3f} with a root)")
        ui, ei = crossing(Us, y1, e1, y2, e2)
        print(f"interpolated L = {L1}, {L2}: (U/t)_c = {ui:.3f} ± {ei:.3f}")


if __name__ == "__main__":
    main()
