"""Every solver path through graph/factor gives the numbers of an independent reference (issue 20).

The references never touch graph/factor: LAPACK ``eigvalsh`` of the dense H, or plain ARPACK
``eigsh`` on the full sparse adjacency (no shift, no factorisation). Tolerance 1e-12 on energies
of size ~3: both sides are converged to residuals ~1e-13 and eigenvalue errors go as residual^2/gap.
"""

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from hyperlattice.graph.factor import resolve_backend
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency, hamiltonian
from hyperlattice.graph.spectrum import lowest_levels


def _plain_eigsh(lat, k):
    """The k lowest levels of H = -A by ARPACK on A itself (which='LA'), no factorisation."""
    a = adjacency(lat).astype(float).tocsr()
    w = spla.eigsh(a, k=k, which="LA", tol=1e-14, ncv=max(4 * k, 40), v0=np.ones(a.shape[0]))[0]
    return np.sort(-w)


@pytest.mark.parametrize("rings", [4, 6, 8, pytest.param(10, marks=pytest.mark.slow)])
def test_default_e0_e1_equal_plain_eigsh_and_dense(rings):
    lat = ring_lattice(7, 3, rings)
    spec = lowest_levels(lat, 2)                    # the default route, as a user calls it
    if rings >= 8:
        assert spec.method == "sector-shift-invert" and spec.backend == resolve_backend("auto")
    ref = (sla.eigvalsh(hamiltonian(lat).toarray(), subset_by_index=[0, 1]) if rings <= 4
           else _plain_eigsh(lat, 2))
    np.testing.assert_allclose(spec.energies, ref, rtol=0, atol=1e-12)


@pytest.mark.parametrize("rings", [4, 7])
def test_ten_lowest_levels_of_the_sector_route_with_multiplicity(rings):
    # the sector-only shift-invert route (forced at l = 4, the default at l = 7) for 10 levels, each
    # +-m pair counted twice, against LAPACK (l = 4, 315 sites) or plain eigsh (l = 7, 5,887 sites)
    lat = ring_lattice(7, 3, rings)
    spec = lowest_levels(lat, 10, method="shift-invert" if rings == 4 else "auto")
    assert spec.method == "sector-shift-invert"
    ref = (sla.eigvalsh(hamiltonian(lat).toarray(), subset_by_index=[0, 9]) if rings == 4
           else _plain_eigsh(lat, 10))
    np.testing.assert_allclose(spec.energies, ref, rtol=0, atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("flux", [0.05, 0.31])
def test_shift_invert_with_flux_on_complex_hermitian_blocks(flux):
    # l = 8 (15,435 sites): blocks of 2,205 > DENSE_MAX, complex Hermitian with flux, so every
    # sector runs shift-invert through graph/factor; reference: plain eigsh of the full complex H
    lat = ring_lattice(7, 3, 8)
    spec = lowest_levels(lat, 3, flux=flux)
    assert spec.method == "sector-shift-invert" and spec.backend == resolve_backend("auto")
    h = hamiltonian(lat, flux=flux).tocsr()
    w = spla.eigsh(-h, k=3, which="LA", tol=1e-14, ncv=40, v0=np.ones(h.shape[0], complex))[0]
    np.testing.assert_allclose(spec.energies, np.sort(-w), rtol=0, atol=1e-12)
