r"""Interacting bosons on hyperbolic lattices: the Bose–Hubbard model and its continuum field theory.

.. math::

    H = -t \sum_{\langle ij\rangle} (a_i^\dagger a_j + \mathrm{h.c.})
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i

(the form of Boettcher et al., PRA 102, 032208, Sec. on the Bose–Hubbard model), mapped to the
continuum through the paper's dictionary :math:`t' = (3/4) h^2 t`, :math:`\mu' = \mu + 3t`,
:math:`U' = (\pi/28) U` for the {7,3} lattice (general {p,q}: :mod:`hyperlattice.dictionary`).

Submodules, one job each (data flows one way: basis -> ed; meanfield and gp use graph/ and
continuum/ only):

* ``basis``, ``ed`` -- exact diagonalisation in a number-conserving basis with an occupation cutoff;
* ``meanfield`` -- site-decoupled (Gutzwiller) mean field and the Mott lobes;
* ``gp`` -- discrete and continuum Gross–Pitaevskii ground states and Bogoliubov spectra;
* ``sse`` (kernels in ``_sse_kernels``) -- stochastic series expansion quantum Monte Carlo at finite
  temperature, and ``thermal`` -- its exact reference, full diagonalisation over all particle numbers;
* ``strong_coupling`` -- the third-order t/U expansion of the Mott-lobe boundaries on any graph.
"""

from __future__ import annotations

from .basis import BosonBasis, basis_dimension, boson_basis
from .ed import BoseHubbardLevels, ChargeGap, bose_hubbard, charge_gap
from .gp import BogoliubovSpectrum, GPState, bogoliubov, gp_ground_state
from .sse import QMCResult, QMCWarning, merge_chains, qmc, qmc_memory, qmc_seconds
from .thermal import ThermalAverages, exact_thermal
from .meanfield import (GutzwillerState, MottLobe, MottLobeTable, gutzwiller, largest_adjacency_eigenvalue,
                        lobe_boundary, lobe_tip, mott_lobe, mott_lobes)
from .strong_coupling import (StrongCouplingLobe, excitation_energies, hypercubic_boundaries, strong_coupling_lobe,
                              strong_coupling_tip)

__all__: list[str] = [
    # exact diagonalisation
    "BosonBasis", "basis_dimension", "boson_basis", "BoseHubbardLevels", "ChargeGap", "bose_hubbard", "charge_gap",
    # Gross-Pitaevskii and Bogoliubov
    "BogoliubovSpectrum", "GPState", "bogoliubov", "gp_ground_state",
    # mean field (item 2)
    "GutzwillerState", "MottLobe", "MottLobeTable", "gutzwiller", "largest_adjacency_eigenvalue", "lobe_boundary",
    "lobe_tip", "mott_lobe", "mott_lobes",
    # quantum Monte Carlo and its exact reference
    "QMCResult", "QMCWarning", "qmc", "qmc_memory", "qmc_seconds", "merge_chains", "exact_thermal", "ThermalAverages",
    # strong-coupling expansion
    "StrongCouplingLobe", "excitation_energies", "hypercubic_boundaries", "strong_coupling_lobe", "strong_coupling_tip",
]
