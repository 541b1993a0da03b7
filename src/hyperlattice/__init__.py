"""hyperlattice: quantum physics on hyperbolic {p,q} lattices and their continuum limit.

The computational system of Boettcher, Bienias, Belyansky, Kollár and Gorshkov, "Quantum
simulation of hyperbolic space with circuit QED: from graphs to geometry", PRA 102, 032208 (2020).
Start: ``hl.ring_lattice(7, 3, 4)``, ``hl.lowest_levels(lat, 2)``, ``hl.continuum_levels(7, 3,
rings=4)``; each name below has its own ``help()``. The command line: ``hyperlattice --help``.

Index by topic (every name is ``hyperlattice.<name>``)::

    Lattices, geometry  ring_lattice Lattice line_graph ring_sizes site_count edge_count
                        load_lattice lattice_from_networkx distance tiling_constants
                        effective_radius lattice_h
    Graph spectra       lowest_levels full_spectrum full_spectrum_tolerance Spectrum
                        MatrixSpectrum adjacency hamiltonian incidence sector_hamiltonian
                        lowest_pair sector_lattice partition_function log_partition_function
    Continuum           continuum_levels dirichlet_levels ContinuumSpectrum legendre_p legendre_q
    Dictionary          lambda_from_energy energy_from_lambda continuum_parameters
                        lattice_parameters field_from_flux flux_from_field
    Green functions     graph_green continuum_green compare_green
    Magnetic flux       butterfly Butterfly check_face_fluxes magnetic_levels MagneticSpectrum
                        landau_levels magnetic_comparison
    Sums, scaling       frame_angles fit_counting sum_check
    Infinite lattice    band_bottom plateau_analysis compare_dictionaries Cluster pbc_cluster
                        list_clusters bloch_hamiltonian band_structure abelian_dos abelian_cover
                        kpm_dos bulk_dos local_dos closed_walks spectral_radius dos_comparison
    Below the band      delta_from_omega bf_bound boundary_correlator delta_curve bound_state
                        spin_model exchange_comparison
    Disorder            disordered_hamiltonian disorder_ensemble r_scan compare_scba scba
    Bosons              bose_hubbard charge_gap boson_basis basis_dimension BosonBasis
                        BoseHubbardLevels ChargeGap gutzwiller mott_lobe mott_lobes lobe_tip
                        lobe_boundary largest_adjacency_eigenvalue GutzwillerState MottLobe
                        MottLobeTable gp_ground_state bogoliubov GPState BogoliubovSpectrum
                        gp_comparison mott_gap_comparison
    Bosons, QMC         qmc qmc_memory qmc_seconds merge_chains exact_thermal ThermalAverages QMCResult QMCWarning
                        strong_coupling_lobe
                        strong_coupling_tip excitation_energies hypercubic_boundaries StrongCouplingLobe
                        qmc_lobe qmc_boundary
    Devices             resonator_device transmission impedance node_voltages
                        circuit_resonances fit_transmission read_trace
                        continuum_transmission ensemble_statistics flat_band_degeneracy
    Topology            flake_topology local_markers edge_chirality cluster_chern
                        centre_marker model_hamiltonian conductance
    Spins               classical_mc classical_mc_memory merge_classical xxz_qmc xxz_exact
                        merge_xxz
    Sweeps, results     run_sweep read_table Result Levels load_result

Conventions: metric ``ds² = (dx² + dy²)/(1 − |z|²)²`` (curvature −4); h = tanh(d0); H = −tA (t = 1
unless given); sites 0-based, ring by ring, each counterclockwise from the smallest polar angle
≥ 0. Names are imported lazily (``import hyperlattice`` is cheap), so ``help(hyperlattice)``
shows this index, not every class.
"""

from __future__ import annotations

import importlib

__version__ = "0.5.0"

# public name -> module that defines it
_EXPORTS = {
    # devices
    "resonator_device": "device.resonators",
    "transmission": "device.transmission",
    "impedance": "device.circuit",
    "node_voltages": "device.circuit",
    "circuit_resonances": "device.circuit",
    "fit_transmission": "device.fit",
    "read_trace": "device.fit",
    "continuum_transmission": "device.continuum",
    "ensemble_statistics": "device.ensemble",
    "flat_band_degeneracy": "device.resonators",
    # topology
    "flake_topology": "topology.markers",
    "local_markers": "topology.markers",
    "edge_chirality": "topology.markers",
    "cluster_chern": "topology.surfaces",
    "centre_marker": "topology.kpm_marker",
    "model_hamiltonian": "topology.models",
    "conductance": "topology.transport",
    # spins
    "classical_mc": "spins.classical",
    "classical_mc_memory": "spins.classical",
    "merge_classical": "spins.classical",
    "xxz_qmc": "spins.quantum",
    "xxz_exact": "spins.quantum",
    "merge_xxz": "spins.quantum",
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
    "Spectrum": "graph.levels",
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
    # interacting bosons (hyperlattice.bosons, and their comparisons with the continuum)
    "BosonBasis": "bosons.basis",
    "basis_dimension": "bosons.basis",
    "boson_basis": "bosons.basis",
    "BoseHubbardLevels": "bosons.ed",
    "ChargeGap": "bosons.ed",
    "bose_hubbard": "bosons.ed",
    "charge_gap": "bosons.ed",
    "BogoliubovSpectrum": "bosons.gp",
    "GPState": "bosons.gp",
    "bogoliubov": "bosons.gp",
    "gp_ground_state": "bosons.gp",
    "GutzwillerState": "bosons.meanfield",
    "MottLobe": "bosons.meanfield",
    "MottLobeTable": "bosons.meanfield",
    "gutzwiller": "bosons.meanfield",
    "largest_adjacency_eigenvalue": "bosons.meanfield",
    "lobe_boundary": "bosons.meanfield",
    "lobe_tip": "bosons.meanfield",
    "mott_lobe": "bosons.meanfield",
    "mott_lobes": "bosons.meanfield",
    "gp_comparison": "compare.bosons",
    "mott_gap_comparison": "compare.bosons",
    # quantum Monte Carlo and the strong-coupling expansion
    "qmc": "bosons.sse",
    "merge_chains": "bosons.sse",
    "QMCResult": "bosons.sse",
    "QMCWarning": "bosons.sse",
    "exact_thermal": "bosons.thermal",
    "ThermalAverages": "bosons.thermal",
    "qmc_memory": "bosons.sse",
    "qmc_seconds": "bosons.sse",
    "StrongCouplingLobe": "bosons.strong_coupling",
    "excitation_energies": "bosons.strong_coupling",
    "hypercubic_boundaries": "bosons.strong_coupling",
    "strong_coupling_lobe": "bosons.strong_coupling",
    "strong_coupling_tip": "bosons.strong_coupling",
    "qmc_lobe": "compare.qmc_lobe",
    "qmc_boundary": "compare.qmc_lobe",
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
    # ``help(hyperlattice)`` (pydoc) documents every class and function that ``dir`` lists, which
    # for the whole API is ~6,000 lines; it gets the module's own names and the docstring's index
    # instead. Everything else (tab completion, ``dir(hyperlattice)``) sees the whole API.
    import sys

    frame = sys._getframe(1)
    for _ in range(6):
        if frame is None:
            break
        if frame.f_globals.get("__name__") == "pydoc":
            # the exports already imported are in globals() too: leave them out, loaded or not
            return sorted(n for n in globals()
                          if n not in _EXPORTS and (not n.startswith("_") or n in ("__version__", "__all__")))
        frame = frame.f_back
    return __all__
