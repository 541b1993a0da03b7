"""The continuum side: the Poincaré disk with the paper's metric. Legendre functions of complex
degree (:mod:`.special`), the Dirichlet spectrum of :math:`-\\Delta_g` (:mod:`.spectrum`), the
Green functions of the Helmholtz operator (:mod:`.green`) and the Dirichlet spectrum of the
magnetic Laplacian with hyperbolic Landau levels (:mod:`.magnetic`). Nothing here knows about lattices;
energies are mapped to the lattice's units through :mod:`hyperlattice.dictionary`.

Import the submodules directly, or the public names from :mod:`hyperlattice`.
"""
