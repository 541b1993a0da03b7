"""hyperlattice: quantum physics on hyperbolic {p,q} lattices and their continuum limit.

Implements the computational system of Boettcher, Bienias, Belyansky, Kollár and Gorshkov,
"Quantum simulation of hyperbolic space with circuit QED: from graphs to geometry",
Phys. Rev. A 102, 032208 (2020).

Conventions: metric ``ds^2 = (dx^2+dy^2)/(1-|z|^2)^2`` (curvature -4); h = tanh(d0);
``Delta_g = (1-|z|^2)^2 (d_x^2 + d_y^2)``; H = -t A (t = 1 unless given); sites are indexed
0-based, ring by ring, each ring counterclockwise from the smallest polar angle >= 0.

Public names are imported lazily so that ``import hyperlattice`` stays cheap.
"""

from __future__ import annotations

import importlib

__version__ = "0.3.0"

# public name -> module that defines it
_EXPORTS = {
    # geometry
    "distance": "geometry",
    "tiling_constants": "geometry",
    "effective_radius": "geometry",
    "lattice_h": "geometry",
    # results
    "Result": "results",
    "Levels": "results",
    "load_result": "results",
    # graph side
    "Lattice": "graph.lattice",
    "ring_lattice": "graph.lattice",
    "line_graph": "graph.lattice",
    "ring_sizes": "graph.lattice",
    "site_count": "graph.lattice",
    "edge_count": "graph.lattice",
    "load_lattice": "graph.lattice",
    "adjacency": "graph.operators",
    "hamiltonian": "graph.operators",
    "incidence": "graph.operators",
    "sector_hamiltonian": "graph.symmetry",
    "Spectrum": "graph.spectrum",
    "MatrixSpectrum": "graph.spectrum",
    "lowest_levels": "graph.spectrum",
    "full_spectrum": "graph.spectrum",
    "full_spectrum_tolerance": "graph.spectrum",
    "lattice_from_networkx": "graph.lattice",
    "partition_function": "graph.spectrum",
    "log_partition_function": "graph.spectrum",
    "graph_green": "graph.green",
    "butterfly": "graph.butterfly",
    "Butterfly": "graph.butterfly",
    "check_face_fluxes": "graph.flux",
    # continuum side
    "legendre_p": "continuum.special",
    "legendre_q": "continuum.special",
    "dirichlet_levels": "continuum.spectrum",
    "continuum_levels": "continuum.spectrum",
    "ContinuumSpectrum": "continuum.spectrum",
    "continuum_green": "continuum.green",
    "magnetic_levels": "continuum.magnetic",
    "MagneticSpectrum": "continuum.magnetic",
    "landau_levels": "continuum.magnetic",
    # the dictionary (the bridge)
    "lambda_from_energy": "dictionary",
    "energy_from_lambda": "dictionary",
    "continuum_parameters": "dictionary",
    "lattice_parameters": "dictionary",
    "field_from_flux": "dictionary",
    "flux_from_field": "dictionary",
    # comparisons
    "compare_green": "compare.green",
    "frame_angles": "compare.scaling",
    "fit_counting": "compare.sums",
    "sum_check": "compare.sums",
    "magnetic_comparison": "compare.magnetic",
    # the infinite lattice: big flakes, periodic clusters, band theory, densities of states
    "lowest_pair": "graph.sectors",
    "sector_lattice": "graph.sectors",
    "Cluster": "graph.clusters",
    "pbc_cluster": "graph.clusters",
    "list_clusters": "graph.clusters",
    "bloch_hamiltonian": "graph.bands",
    "band_structure": "graph.bands",
    "abelian_dos": "graph.bands",
    "abelian_cover": "graph.bands",
    "kpm_dos": "graph.kpm",
    "bulk_dos": "graph.kpm",
    "local_dos": "graph.kpm",
    "closed_walks": "graph.walks",
    "spectral_radius": "graph.walks",
    "dos_comparison": "compare.dos",
    "band_bottom": "compare.limits",
    "plateau_analysis": "compare.limits",
    "compare_dictionaries": "compare.limits",
    # below the band: holography and circuit-QED qubits
    "delta_from_omega": "continuum.massive",
    "bf_bound": "continuum.massive",
    "boundary_correlator": "compare.boundary",
    "delta_curve": "compare.boundary",
    "bound_state": "graph.qubits",
    "spin_model": "graph.qubits",
    "exchange_comparison": "compare.qubits",
    # disorder and sweeps
    "disordered_hamiltonian": "graph.disorder",
    "disorder_ensemble": "compare.disorder",
    "r_scan": "compare.disorder",
    "compare_scba": "compare.disorder",
    "scba": "continuum.scba",
    "run_sweep": "sweep",
    "read_table": "sweep",
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
