"""Table: the spin-1/2 Heisenberg antiferromagnet on {8,3} flakes and clusters by SSE (docs/spins-quantum.md).

For each graph (flakes l = 2, 3, 4; the bipartite {8,3} clusters bolza and dyck) and
beta = 2, 4, 8, 16: the energy per site e, the squared staggered moment
m_s^2 = 3 s_pi / N = 3 <(M_s^z / N)^2> (SU(2): three components), on flakes the staggered
correlation by ring mu_r (mean of eps_i <S^z_i M_s> / N over ring r; their site-weighted sum is
<(M_s^z/N)^2>) and the bond energy <S_i . S_j> of the bonds inside ring 1 (bulk) and of the bonds
between boundary sites (outermost ring); on clusters the spin stiffness rho_s.

Usage::

    python benchmarks/table_spins_quantum.py [--sweeps 20000] [--betas 2 4 8 16] [--rings 2 3 4] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import time
import warnings

import numpy as np


def _bond_rings(res, ring):
    ri = ring[res.bonds[:, 0]]
    rj = ring[res.bonds[:, 1]]
    return ri, rj


def point(system, beta: float, sweeps: int, seed: int) -> dict:
    from hyperlattice.spins.quantum import xxz_qmc

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c0 = time.process_time()
        r = xxz_qmc(system, J=1.0, Delta=1.0, beta=beta, sweeps=sweeps, seed=seed, progress=False)
        cpu = time.process_time() - c0
    n = r.sites
    out = {"system": r.system, "sites": n, "beta": beta, "e": r.e, "e_err": r.e_err,
           "ms2": 3 * r.s_pi / n, "ms2_err": 3 * r.s_pi_err / n, "chi_u": r.chi_u, "chi_u_err": r.chi_u_err,
           "rho_s": r.rho_s, "rho_s_err": r.rho_s_err, "tau_e": r.tau_int["energy"], "cpu": cpu,
           "converged": bool(r.converged and not caught)}
    sdotb = r.bond_zz + r.bond_xy
    sdotb_err = np.hypot(r.bond_zz_err, r.bond_xy_err)
    if r.ring is not None:
        out["ring_stag"] = r.ring_stag.tolist()
        out["ring_stag_err"] = r.ring_stag_err.tolist()
        out["ring_sites"] = [int(np.sum(r.ring == k + 1)) for k in range(len(r.ring_stag))]
        ri, rj = _bond_rings(r, r.ring)
        last = int(r.ring.max())
        for name, sel in (("bond_bulk", (ri == 1) & (rj == 1)), ("bond_boundary", (ri == last) & (rj == last))):
            out[name] = float(sdotb[sel].mean())
            out[name + "_err"] = float(np.sqrt(np.sum(sdotb_err[sel] ** 2)) / sel.sum())
    return out


def main(argv=None) -> int:
    import hyperlattice as hl
    from hyperlattice.graph.clusters import pbc_cluster

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweeps", type=int, default=20000)
    ap.add_argument("--betas", type=float, nargs="+", default=[2.0, 4.0, 8.0, 16.0])
    ap.add_argument("--rings", type=int, nargs="+", default=[2, 3, 4])
    ap.add_argument("--clusters", nargs="*", default=["bolza", "dyck"])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f}")
    systems = [hl.ring_lattice(8, 3, ell) for ell in args.rings] + [pbc_cluster(8, 3, c) for c in args.clusters]
    rows = []
    for system in systems:
        for beta in args.betas:
            row = point(system, beta, args.sweeps, args.seed)
            rows.append(row)
            extra = ""
            if "ring_stag" in row:
                extra = (f" | mu_1 {row['ring_stag'][0]:.5f}, mu_last {row['ring_stag'][-1]:.5f}"
                         f" | <S.S> bulk {row['bond_bulk']:.4f} boundary {row['bond_boundary']:.4f}")
            elif np.isfinite(row["rho_s"]):
                extra = f" | rho_s {row['rho_s']:.4f} +- {row['rho_s_err']:.4f}"
            print(f"{row['system']:<22} N = {row['sites']:>4} beta = {beta:>4g}: e = {row['e']:.5f} +- {row['e_err']:.5f}"
                  f", m_s^2 = {row['ms2']:.5f} +- {row['ms2_err']:.5f}{extra} ({row['cpu']:.1f} CPU s"
                  f"{'' if row['converged'] else ', NOT converged'})", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
