"""The worm estimator of the one-body density matrix G(i, j) = <a_i^dagger a_j> against exact G.

The estimator's factor 2 is derived in the docstring of bosons.qmc (Notes): it holds for every
pair of sites and every cutoff. These cases check it where a mistake in the derivation would
show: pairs beyond nearest neighbours (up to four hops), hard-core bosons (nmax = 1) and a
cutoff of three bosons per site.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice.bosons import exact_thermal, qmc

HEPTAGON = hl.ring_lattice(7, 3, 1)


def _ring(n: int) -> sp.csr_matrix:
    i = np.arange(n)
    a = sp.coo_matrix((np.ones(n), (i, (i + 1) % n)), shape=(n, n))
    return (a + a.T).tocsr()


def _classes(system, r):
    """The distance class of every ordered pair, as the estimator bins them."""
    if r.distance_kind == "hyperbolic":
        d = hl.geometry.distance(system.z[:, None], system.z[None, :], check=False)
        return np.rint(d / (hl.geometry.d0(system.p, system.q) / 2)).astype(int)
    from scipy.sparse.csgraph import shortest_path

    return shortest_path(system, unweighted=True).astype(int)


@pytest.mark.parametrize("system, kw, seed", [
    (HEPTAGON, dict(U=0.0, mu=0.3, beta=2.0, nmax=1), 4),               # hard-core; hyperbolic classes
    (_ring(6), dict(U=3.0, mu=2.5, beta=1.5, nmax=3), 6),               # three bosons per site: 1 to 3 hops
    (_ring(8), dict(U=2.0, mu=0.8, beta=1.5, nmax=2), 8),               # a graph: 1 to 4 hops
])
def test_green_at_every_distance_against_exact(system, kw, seed):
    ex = exact_thermal(system, **kw)
    r = qmc(system, sweeps=8000, thermalization=1000, seed=seed, progress=False, **kw)
    cls = _classes(system, r)
    off = ~np.eye(r.sites, dtype=bool)
    labels = np.unique(cls[off])
    assert len(labels) == len(r.green) >= 2
    far = 0
    for c, val, err, npairs in zip(labels, r.green, r.green_err, r.green_pairs):
        sel = (cls == c) & off
        exact = ex.green[sel].mean()
        assert npairs == sel.sum()
        assert abs(val - exact) < 4 * err, (c, val, err, exact)
        # a wrong factor would show: the value is many error bars away from zero and from half/twice exact
        assert abs(exact) > 8 * err and abs(val - exact) < min(abs(val - exact / 2), abs(val - 2 * exact))
        far += c != labels[0]
    assert far >= 1                                           # beyond nearest neighbours
