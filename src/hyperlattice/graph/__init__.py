"""The graph side: finite {p,q} lattices, operators on them, symmetry sectors, solvers, spectra
and Green functions. Nothing here knows about the continuum.

Import the submodules (``hyperlattice.graph.lattice``, ``.operators``, ``.symmetry``,
``.solvers``, ``.spectrum``, ``.green``) or the public names from :mod:`hyperlattice`.
"""
