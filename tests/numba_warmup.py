"""Compile the package's numba kernels into their on-disk cache before the test workers start.

``make test`` runs two pytest-xdist workers; on a fresh clone the numba cache is empty, and each
worker compiled every kernel it met itself (the SSE, XXZ and classical spin kernels alone are
about 45 s of CPU per process), so most kernels were compiled twice. The controller now runs this
module once, in two processes side by side (``python numba_warmup.py GROUP``), and the workers
load the compiled kernels from the cache (``cache=True``). Each call is small and only triggers a
compilation; a call that fails is skipped (the tests themselves report any real failure).
"""

from __future__ import annotations

import sys
import warnings


def _bosons():
    import scipy.sparse as sp  # noqa: F401

    import hyperlattice as hl
    from hyperlattice.bosons import exact_thermal, qmc
    from hyperlattice.graph.clusters import pbc_cluster

    yield lambda: qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=20, seed=1, progress=False)
    yield lambda: qmc(pbc_cluster(8, 3, "bolza"), U=0.0, mu=0.3, beta=1.0, nmax=1, sweeps=20, seed=1, progress=False)
    yield lambda: exact_thermal(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, method="sectors")
    yield lambda: exact_thermal(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, method="dense")

    from hyperlattice.bosons.ed import bose_hubbard

    yield lambda: bose_hubbard(hl.ring_lattice(7, 3, 1), particles=2, nmax=2, U=2.0, levels=2)


def _spins():
    import hyperlattice as hl
    from hyperlattice.spins.quantum import xxz_qmc

    yield lambda: xxz_qmc(hl.ring_lattice(8, 3, 1), J=1.0, Delta=1.0, beta=1.0, sweeps=20, seed=1, progress=False)
    from hyperlattice.spins.classical import classical_mc

    for model, update in (("ising", "wolff"), ("ising", "swendsen-wang"), ("ising", "local"),
                          ("heisenberg", "auto"), ("xy", "auto")):
        yield lambda m=model, u=update: classical_mc(hl.ring_lattice(7, 3, 2), model=m, T=2.0, sweeps=20,
                                                     update=u, progress=False)


def _graph():
    import hyperlattice as hl
    from hyperlattice.graph.clusters import pbc_cluster
    from hyperlattice.graph.kpm import kpm_dos
    from hyperlattice.graph.spectrum import lowest_levels

    yield lambda: hl.ring_lattice(7, 3, 3)
    yield lambda: pbc_cluster(7, 3, "klein")
    yield lambda: pbc_cluster(7, 3, min_sites=1000)
    yield lambda: lowest_levels(hl.ring_lattice(7, 3, 7), 2)
    yield lambda: kpm_dos(pbc_cluster(7, 3, "klein"), moments=32, vectors=2)
    yield lambda: hl.graph_green(hl.ring_lattice(7, 3, 3), omega=-2.95, source=1)

    from hyperlattice.continuum.magnetic import magnetic_levels

    yield lambda: magnetic_levels(7, 3, rings=3, levels=2, flux=0.1)


GROUPS = {"qmc": (_bosons,), "rest": (_spins, _graph)}


def main(group: str) -> None:
    warnings.simplefilter("ignore")
    for make in GROUPS[group]:
        try:
            for call in make():
                try:
                    call()
                except Exception:         # noqa: BLE001 - a warm-up only; the tests report real failures
                    pass
        except Exception:                 # noqa: BLE001
            pass


if __name__ == "__main__":
    main(sys.argv[1])
