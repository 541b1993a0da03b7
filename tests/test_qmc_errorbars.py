"""The QMC's error bars against the scatter of independent seeds (a superfluid point, short chains)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import stats

import hyperlattice as hl
from hyperlattice.bosons import QMCWarning, qmc


@pytest.mark.slow
def test_error_bars_agree_with_the_scatter_of_independent_seeds():
    """24 seeds of the {5,4} two-ring flake (30 sites) in the superfluid (U = 6, mu = 3, beta = 8), 500
    sweeps each: chi^2 = sum_k (x_k - xbar)^2 / sigma_k^2 of the seeds' means with their own error
    bars follows chi^2 with 23 degrees of freedom when the bars are true; it must lie in the central
    99.9 % interval for the energy, the density and the compressibility. (The plateau error of the
    binning alone was about 12 % low here: chi^2 of 162, 143 and 179 for 120 seeds, 119 dof.)"""
    lat = hl.ring_lattice(5, 4, 2)
    k = 24
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", QMCWarning)     # 500 sweeps: a plateau may be flagged
        for seed in range(k):
            r = qmc(lat, U=6.0, mu=3.0, beta=8.0, nmax=3, sweeps=500, thermalization=200, seed=4000 + seed,
                    measure_green=False, progress=False)
            rows.append([r.energy, r.energy_err, r.density, r.density_err, r.compressibility,
                         r.compressibility_err])
    a = np.array(rows)
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], k - 1)
    for col, name in ((0, "energy"), (2, "density"), (4, "compressibility")):
        x, e = a[:, col], a[:, col + 1]
        w = 1.0 / e ** 2
        mean = float(np.sum(w * x) / np.sum(w))
        chi2 = float(np.sum((x - mean) ** 2 * w))
        assert lo < chi2 < hi, f"{name}: chi^2 = {chi2:.1f} for {k - 1} dof, outside [{lo:.1f}, {hi:.1f}]"
