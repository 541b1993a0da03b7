"""Continuum theory on the Poincaré disk: Dirichlet spectrum (``spectrum``), and — in sibling
modules — Green functions and the lattice/continuum dictionary.

Only the spectrum names are re-exported here; import submodules directly for the rest so that
importing this package stays cheap.
"""

from .spectrum import (  # noqa: F401
    ContinuumSpectrum,
    DirichletTable,
    asymptotic_energies,
    asymptotic_k0,
    asymptotic_k1,
    continuum_levels,
    dirichlet_levels,
    dirichlet_roots,
    disk_argument,
    energy_infinity,
    level_energy,
    psi_K,
    radial_g,
)
