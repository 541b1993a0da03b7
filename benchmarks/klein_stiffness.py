"""Superfluid stiffness on the periodic {7,3} Klein quartic (56 sites, genus 3) on both sides of the n = 1 transition."""

import warnings, time
import hyperlattice as hl
from hyperlattice.bosons import qmc
cell = hl.pbc_cluster(7, 3, "klein")
for tU in (0.15, 0.04):
    U = 1 / tU
    t0 = time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = qmc(cell, U=U, mu=0.4 * U, beta=8.0, nmax=3, sweeps=1000, seed=1, progress=False)
    print(f"t/U = {tU}: n = {r.density:.4f} ± {r.density_err:.4f}, rho_s = {r.rho_s:.4f} ± {r.rho_s_err:.4f}, "
          f"det^(1/6) = {r.stiffness_geometric:.4f} ± {r.stiffness_geometric_err:.4f}, tau = {r.tau_int['stiffness']:.2f}, {time.time()-t0:.0f} s")
