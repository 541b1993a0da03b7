"""hyperlattice: quantum physics on hyperbolic {p,q} lattices and their continuum limit.

Implements the computational system of Boettcher, Bienias, Belyansky, Kollár and Gorshkov,
"Quantum simulation of hyperbolic space with circuit QED: from graphs to geometry",
Phys. Rev. A 102, 032208 (2020).

Conventions: metric ds^2 = (dx^2+dy^2)/(1-|z|^2)^2 (curvature -4); h = tanh(d0);
Delta_g = (1-|z|^2)^2 (d_x^2 + d_y^2); H = -t A (t = 1 unless given); sites are indexed
0-based, ring by ring, each ring counterclockwise from the smallest polar angle >= 0.

Public names are imported lazily so that ``import hyperlattice`` stays cheap.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

# public name -> module that defines it
_EXPORTS = {
    # geometry
    "distance": "geometry",
    "tiling_constants": "geometry",
    "effective_radius": "geometry",
    "lattice_h": "geometry",
    # lattice
    "Lattice": "lattice",
    "ring_lattice": "lattice",
    "line_graph": "lattice",
    "ring_sizes": "lattice",
    "load_lattice": "lattice",
    # operators
    "adjacency": "operators",
    "hamiltonian": "operators",
    "incidence": "operators",
    # symmetry / spectra
    "sector_hamiltonian": "symmetry",
    "lowest_levels": "spectrum",
    "partition_function": "spectrum",
    # continuum
    "legendre_p": "special",
    "legendre_q": "special",
    "dirichlet_levels": "continuum.spectrum",
    "continuum_levels": "continuum.spectrum",
    "continuum_green": "continuum.green",
    # green functions on the graph
    "graph_green": "green",
    # A_h and scaling
    "frame_angles": "scaling",
}

__all__ = sorted(_EXPORTS) + ["__version__"]


def __getattr__(name: str):
    try:
        module = _EXPORTS[name]
    except KeyError:
        raise AttributeError(f"module 'hyperlattice' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return __all__
